//! One scenario run as the command-line tool and the Python package both perform it:
//! every sample goes to a sink; the run stops when the sink fails, or at the next
//! integration step after `cancel` is set (a non-finite state stops it in the core, with
//! status `non_finite`: no NaN is reported as a result); the summary is built from the
//! outcome.

use std::ops::ControlFlow;
use std::sync::Arc;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

use ellipsoid_core::scenario::{Scenario, ScenarioError};
use ellipsoid_core::simulate::{self, Outcome, Sample};

use crate::Summary;

/// A run that produced a result (possibly stopped early).
pub struct Finished {
    pub outcome: Outcome,
    pub summary: Summary,
}

/// Why a run produced no result.
pub enum Failure<E> {
    /// The physics layer rejected the scene (an input error found at t = 0), placed in
    /// the scenario file.
    Scenario(Box<ScenarioError>),
    /// The sink failed (e.g. a write error).
    Sink(E),
}

/// Simulates `scenario`, handing each sample to `sink`. `output` is recorded in the
/// summary (where the trajectory went, if anywhere); `version` is the caller's.
pub fn run<E>(
    scenario: &Scenario,
    output: Option<String>,
    version: &str,
    cancel: Option<Arc<AtomicBool>>,
    mut sink: impl FnMut(&Sample) -> Result<(), E>,
) -> Result<Finished, Failure<E>> {
    let mut rows = 0u64;
    let mut sink_error = None;
    let start = Instant::now();
    let result = simulate::simulate_cancellable(
        &scenario.scene,
        &mut |s| {
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
    let summary = Summary::new(scenario, &outcome, wall_time_s, rows, output, version);
    Ok(Finished { outcome, summary })
}
