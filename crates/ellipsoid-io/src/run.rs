//! One scenario run as the command-line tool and the Python package both perform it:
//! every sample goes to a sink; the run stops at the first non-finite sample (never
//! passed on: no NaN is reported as a result), when the sink fails, or at the next
//! integration step after `cancel` is set; the summary is built from the outcome.

use std::ops::ControlFlow;
use std::sync::Arc;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

use ellipsoid_core::scenario::{Scenario, ScenarioError};
use ellipsoid_core::simulate::{self, Outcome, Sample};

use crate::{Summary, columns};

/// A run that produced a result (possibly stopped early).
pub struct Finished {
    pub outcome: Outcome,
    /// The summary; its message says why a non-finite sample stopped the run.
    pub summary: Summary,
    /// Why the run was stopped at a non-finite sample, if it was.
    pub non_finite: Option<String>,
}

/// Why a run produced no result.
pub enum Failure<E> {
    /// The physics layer rejected the scene (an input error found at t = 0), placed in
    /// the scenario file.
    Scenario(Box<ScenarioError>),
    /// The sink failed (e.g. a write error).
    Sink(E),
}

/// Why a sample must stop the run: it holds NaN or infinity (named by column).
pub fn non_finite_note(s: &Sample) -> Option<String> {
    columns::non_finite(s).map(|(column, value)| {
        format!("stopped at t = {} s: the state became non-finite ({column} = {value}); the samples before it are kept", s.t)
    })
}

/// Simulates `scenario`, handing each finite sample to `sink`. `output` is recorded in
/// the summary (where the trajectory went, if anywhere); `version` is the caller's.
pub fn run<E>(
    scenario: &Scenario,
    output: Option<String>,
    version: &str,
    cancel: Option<Arc<AtomicBool>>,
    mut sink: impl FnMut(&Sample) -> Result<(), E>,
) -> Result<Finished, Failure<E>> {
    let mut rows = 0u64;
    let mut non_finite = None;
    let mut sink_error = None;
    let start = Instant::now();
    let result = simulate::simulate_cancellable(
        &scenario.scene,
        &mut |s| {
            if let Some(note) = non_finite_note(s) {
                non_finite = Some(note);
                return ControlFlow::Break(());
            }
            if let Err(e) = sink(s) {
                sink_error = Some(e);
                return ControlFlow::Break(());
            }
            rows += 1;
            ControlFlow::Continue(())
        },
        cancel,
    );
    let wall_time_s = start.elapsed().as_secs_f64();
    let outcome = result.map_err(|e| Failure::Scenario(Box::new(scenario.locate(&e))))?;
    if let Some(e) = sink_error {
        return Err(Failure::Sink(e));
    }
    let mut summary = Summary::new(scenario, &outcome, wall_time_s, rows, output, version);
    if let Some(n) = &non_finite {
        summary.message = n.clone();
    }
    Ok(Finished {
        outcome,
        summary,
        non_finite,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use ellipsoid_core::simulate::Mode;
    use ellipsoid_core::state::EulerAngles;
    use nalgebra::Vector3;

    #[test]
    fn a_non_finite_sample_is_named_and_stops_the_run() {
        let mut s = Sample {
            t: 0.1,
            position: Vector3::zeros(),
            angles: EulerAngles::default(),
            omega: Vector3::new(0.0, 0.0, 1.0),
            velocity: Vector3::zeros(),
            energy: 1.0,
            work: 0.0,
            normal_force: 1.0,
            slip_speed: 0.0,
            mode: Mode::Rolling,
        };
        assert_eq!(non_finite_note(&s), None);
        s.omega.y = f64::NAN;
        let note = non_finite_note(&s).expect("NaN stops the run");
        assert!(
            note.starts_with("stopped at t = 0.1 s") && note.contains("omega_y = NaN"),
            "{note}"
        );
    }
}
