//! Running scenarios without the GIL: one run, or many in parallel (rayon), interruptible
//! with Ctrl-C.
//!
//! The calling thread detaches from Python and hands the work to a worker thread (or a
//! rayon pool); it then wakes every [`POLL`] to attach briefly and run Python's signal
//! handlers (`Python::check_signals`). A `KeyboardInterrupt` raised there sets a flag that
//! the integrator reads before every step (`simulate_cancellable`), so the runs stop at
//! their next step, and the interrupt is raised once they have. Panics are caught on the worker
//! and become `ellipsoid.InternalError`.

use std::convert::Infallible;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::time::Duration;

use ellipsoid_core::scenario::{Scenario, ScenarioError};
use ellipsoid_core::simulate::Sample;
use ellipsoid_io::Summary;
use ellipsoid_io::run as io_run;
use pyo3::prelude::*;

/// How often the detached caller checks for signals.
const POLL: Duration = Duration::from_millis(50);

/// Most samples reserved before a run (24 MB of them); beyond, the vector grows.
const RESERVE: usize = 100_000;

/// Stack of the worker threads (the CLI runs on the main thread, which usually has 8 MiB).
pub const STACK: usize = 8 << 20;

/// Version written into summaries (the workspace's, the same as the CLI's).
pub const VERSION: &str = env!("CARGO_PKG_VERSION");

/// A finished run.
pub struct Run {
    pub scenario: Scenario,
    /// The samples, unless only the summary was asked for.
    pub samples: Vec<Sample>,
    pub summary: Summary,
    /// The points of the scene's Poincaré sections (`Outcome::sections`).
    pub sections: Vec<Vec<Sample>>,
}

/// Why a run produced no result.
pub enum Failure {
    /// The physics layer rejected the scene (an input error found at t = 0), placed in
    /// the scenario like the command-line tool does.
    Model(Box<ScenarioError>),
    /// A panic (its message).
    Panic(String),
}

/// Simulates `scenario` exactly as the command-line tool's `run` does
/// (`ellipsoid_io::run`): stops at the first non-finite sample (not kept; status
/// `non_finite`), or when `cancel` is set.
pub fn run(
    scenario: Scenario,
    keep_samples: bool,
    cancel: &Arc<AtomicBool>,
) -> Result<Run, Failure> {
    // Room for the samples asked for (up to [`RESERVE`]), so that a run with dense output
    // does not copy them as the vector grows.
    let mut samples = Vec::with_capacity(if keep_samples {
        scenario.scene.sample_times.len().min(RESERVE)
    } else {
        0
    });
    let finished =
        ellipsoid_io::run::run(&scenario, None, VERSION, Some(Arc::clone(cancel)), |s| {
            if keep_samples {
                samples.push(*s);
            }
            Ok::<(), Infallible>(())
        });
    let finished = match finished {
        Ok(f) => f,
        Err(io_run::Failure::Scenario(e)) => return Err(Failure::Model(e)),
        Err(io_run::Failure::Sink(never)) => match never {},
    };
    Ok(Run {
        scenario,
        samples,
        summary: finished.summary,
        sections: finished.outcome.sections,
    })
}

/// `run` with panics caught.
pub fn run_caught(
    scenario: Scenario,
    keep_samples: bool,
    cancel: &Arc<AtomicBool>,
) -> Result<Run, Failure> {
    catch_unwind(AssertUnwindSafe(|| run(scenario, keep_samples, cancel)))
        .unwrap_or_else(|p| Err(Failure::Panic(ellipsoid_core::error::panic_message(&*p))))
}

/// Runs `work` on a worker thread while the caller, detached from Python, checks for
/// signals every [`POLL`]. Returns the work's result and the interrupt, if any (the work
/// was told to stop through the flag it receives).
pub fn detached<T: Send>(
    py: Python<'_>,
    work: impl FnOnce(&Arc<AtomicBool>) -> T + Send,
) -> PyResult<(T, Option<PyErr>)> {
    let cancel = Arc::new(AtomicBool::new(false));
    let mut interrupt: Option<PyErr> = None;
    let outcome: Result<T, String> = py.detach(|| {
        std::thread::scope(|scope| {
            let (tx, rx) = mpsc::channel();
            let cancel = &cancel;
            let spawned = std::thread::Builder::new()
                .name("ellipsoid".into())
                .stack_size(STACK)
                .spawn_scoped(scope, move || {
                    let r = catch_unwind(AssertUnwindSafe(|| work(cancel)))
                        .map_err(|p| ellipsoid_core::error::panic_message(&*p));
                    let _ = tx.send(r);
                });
            if let Err(e) = spawned {
                return Err(format!("cannot start a worker thread: {e}"));
            }
            loop {
                match rx.recv_timeout(POLL) {
                    Ok(r) => return r,
                    Err(mpsc::RecvTimeoutError::Timeout) => {
                        if interrupt.is_none()
                            && let Err(e) = Python::attach(|py| py.check_signals())
                        {
                            interrupt = Some(e);
                            cancel.store(true, Ordering::Relaxed);
                        }
                    }
                    Err(mpsc::RecvTimeoutError::Disconnected) => {
                        return Err("the worker thread ended without a result".into());
                    }
                }
            }
        })
    });
    match outcome {
        Ok(v) => Ok((v, interrupt)),
        Err(msg) => Err(crate::errors::internal_error(py, &msg)),
    }
}
