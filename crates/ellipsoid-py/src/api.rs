//! `ellipsoid.simulate` and `ellipsoid.sweep`.

use ellipsoid_core::scenario::Scenario;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use rayon::prelude::*;

use crate::convert;
use crate::errors::{self, Class};
use crate::run::{self, Failure, Run};
use crate::scenario::{PyScenario, resolve};
use crate::trajectory::Trajectory;

/// Simulates a scenario and returns its Trajectory.
///
/// `scenario` is an `ellipsoid.Scenario` or the path of a TOML scenario file; `changes`
/// are applied first, as `Scenario.replace` does (e.g. `output={"t_end": 0.5}` or
/// `**{"output.t_end": 0.5}`, end time in s).
///
/// The GIL is released while the run lasts; Ctrl-C (SIGINT) stops it at its next
/// integration step and raises KeyboardInterrupt.
///
/// Loss of contact and the pure sliding model's slip stop are outcomes: the trajectory
/// ends there and `traj.status` / `traj.events` say so. Raises ScenarioError for bad
/// input (including a state the physics rejects at t = 0, e.g. N ≤ 0), and
/// SimulationError (with the partial trajectory as `.trajectory`) for a Painlevé
/// inconsistency, a solver failure, chattering, or a non-finite state.
#[pyfunction]
#[pyo3(signature = (scenario, /, **changes))]
pub fn simulate(
    py: Python<'_>,
    scenario: &Bound<'_, PyAny>,
    changes: Option<&Bound<'_, PyDict>>,
) -> PyResult<Py<Trajectory>> {
    let inner = resolve(py, scenario, convert::overrides(changes)?)?.inner;
    let (result, interrupt) =
        run::detached(py, move |cancel| run::run_caught(inner, true, cancel))?;
    if let Some(e) = interrupt {
        return Err(e);
    }
    finish(py, result, false)?
        .cast_into::<Trajectory>()
        .map(Bound::unbind)
        .map_err(|e| errors::internal_error(py, &e.to_string()))
}

/// A run's result as a Trajectory (or its summary dict), or its error as an exception.
fn finish(
    py: Python<'_>,
    result: Result<Run, Failure>,
    summary_only: bool,
) -> PyResult<Bound<'_, PyAny>> {
    let run = match result {
        Ok(run) => run,
        Err(Failure::Model(e)) => return Err(errors::scenario_error(py, &e)),
        Err(Failure::Panic(msg)) => return Err(errors::internal_error(py, &msg)),
    };
    let failure = errors::status_error(&run.status, &run.summary.message);
    let status = run.summary.status;
    let traj = Bound::new(py, Trajectory::new(run))?;
    match failure {
        None if summary_only => traj.getattr("summary"),
        None => Ok(traj.into_any()),
        Some(message) => Err(Class::Simulation.error(
            py,
            &message,
            &[
                ("status", status.into_pyobject(py)?.into_any().unbind()),
                ("trajectory", traj.into_any().unbind()),
            ],
        )),
    }
}

/// Runs many scenarios in parallel (a rayon pool of `workers` threads; None = one per
/// CPU), without the GIL, and returns their results in input order: Trajectory objects,
/// or with `summaries_only=True` the summary dicts (the samples are then not kept).
///
/// `scenarios` holds `ellipsoid.Scenario` objects or scenario file paths, e.g.
/// `[base.replace(contact={"friction": mu}) for mu in (0.1, 0.2, 0.3)]`.
///
/// `errors="raise"` (default) raises the first failure in input order once every run has
/// ended; `errors="return"` puts the exception object (ScenarioError, SimulationError
/// with `.trajectory`, ...) in the failed run's place instead. Ctrl-C stops every run at
/// its next integration step and raises KeyboardInterrupt.
#[pyfunction]
#[pyo3(signature = (scenarios, workers = None, *, summaries_only = false, errors = "raise"))]
pub fn sweep<'py>(
    py: Python<'py>,
    scenarios: &Bound<'py, PyAny>,
    workers: Option<usize>,
    summaries_only: bool,
    errors: &str,
) -> PyResult<Bound<'py, PyList>> {
    let return_errors = match errors {
        "raise" => false,
        "return" => true,
        other => {
            return Err(PyValueError::new_err(format!(
                "errors = {other:?}: expected \"raise\" or \"return\""
            )));
        }
    };
    if workers == Some(0) {
        return Err(PyValueError::new_err(
            "workers = 0: give at least 1 worker thread, or None for one per CPU",
        ));
    }
    let mut slots: Vec<Option<PyResult<Bound<'py, PyAny>>>> = Vec::new();
    let mut jobs: Vec<(usize, Scenario)> = Vec::new();
    for (i, item) in scenarios.try_iter()?.enumerate() {
        match resolve(py, &item?, Vec::new()) {
            Ok(PyScenario { inner }) => {
                jobs.push((i, inner));
                slots.push(None);
            }
            Err(e) if return_errors => slots.push(Some(Err(e))),
            Err(e) => return Err(e),
        }
    }
    let keep = !summaries_only;
    let (results, interrupt) = run::detached(py, move |cancel| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(workers.unwrap_or(0))
            .stack_size(run::STACK)
            .thread_name(|i| format!("ellipsoid-sweep-{i}"))
            .build()
            .map_err(|e| format!("cannot start the worker threads: {e}"))?;
        Ok::<_, String>(pool.install(|| {
            jobs.into_par_iter()
                .map(|(i, scenario)| {
                    if cancel.load(std::sync::atomic::Ordering::Relaxed) {
                        return (i, None);
                    }
                    (i, Some(run::run_caught(scenario, keep, cancel)))
                })
                .collect::<Vec<_>>()
        }))
    })?;
    if let Some(e) = interrupt {
        return Err(e);
    }
    let results = results.map_err(|msg| errors::internal_error(py, &msg))?;
    for (i, result) in results {
        let result = result
            .ok_or_else(|| errors::internal_error(py, "a run was skipped without an interrupt"))?;
        slots[i] = Some(finish(py, result, summaries_only));
    }
    let mut out = Vec::with_capacity(slots.len());
    for slot in slots {
        match slot {
            Some(Ok(v)) => out.push(v),
            Some(Err(e)) if return_errors => out.push(e.into_value(py).into_bound(py).into_any()),
            Some(Err(e)) => return Err(e),
            None => return Err(errors::internal_error(py, "a run produced no result")),
        }
    }
    PyList::new(py, out)
}
