//! `ellipsoid.simulate` and `ellipsoid.sweep`.

use ellipsoid_core::scenario::Scenario;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyList, PyString};
use rayon::prelude::*;

use crate::convert;
use crate::errors;
use crate::run::{self, Failure, Run};
use crate::scenario::{PyScenario, resolve};
use crate::trajectory::Trajectory;

/// Simulates a scenario and returns its Trajectory.
///
/// `scenario` is an `ellipsoid.Scenario` or the path of a TOML scenario file; `changes`
/// are applied first, as `Scenario.replace` does (e.g. `output={"t_end": 0.5}` or
/// `**{"output.t_end": 0.5}`, end time in s).
///
/// `t_eval`: the output times [s] (strictly increasing, in [0, t_end]) instead of the
/// scenario's `dt` or `times`, as solve_ivp's `t_eval`. `method`: the integrator, by
/// the scenario's name ("dop853", "dopri5", "rk4") or scipy's, case-insensitive:
/// "RK45" is dopri5 (Dormand–Prince 5(4), as scipy's RK45), "DOP853" dop853, "RK4" the
/// classical fixed-step RK4 (it needs `solver={"step": h}`); scipy's "RK23", "Radau",
/// "BDF" and "LSODA" have no counterpart here. `rtol`, `atol`: the relative and absolute
/// tolerances, as solve_ivp's, meaning `solver.rtol` and `solver.atol`; given, they
/// override the scenario's own (the file's, and those set by `changes`, e.g.
/// `solver={"rtol": ...}`), as any change does.
///
/// The GIL is released while the run lasts; Ctrl-C (SIGINT) stops it at its next
/// integration step and raises KeyboardInterrupt.
///
/// Every run that starts returns its Trajectory, as solve_ivp returns its result: loss of
/// contact and the pure sliding model's slip stop are outcomes (`traj.success`), and a
/// Painlevé inconsistency, a solver failure, chattering or a non-finite state end the
/// trajectory with `traj.success == False`, `traj.status` and `traj.message` saying why.
/// Only bad input raises (ScenarioError, including a state the physics rejects at
/// t = 0, e.g. N ≤ 0): there is no run to return.
#[pyfunction]
#[pyo3(signature = (scenario, /, *, t_eval = None, method = None, rtol = None, atol = None, **changes))]
pub fn simulate(
    py: Python<'_>,
    scenario: &Bound<'_, PyAny>,
    t_eval: Option<&Bound<'_, PyAny>>,
    method: Option<&Bound<'_, PyAny>>,
    rtol: Option<&Bound<'_, PyAny>>,
    atol: Option<&Bound<'_, PyAny>>,
    changes: Option<&Bound<'_, PyDict>>,
) -> PyResult<Py<Trajectory>> {
    let source = scenario
        .cast::<PyScenario>()
        .map(|s| s.get().inner.source.clone())
        .unwrap_or_else(|_| "<changes>".into());
    let mut overrides = convert::Conv { source: &source }.overrides(changes)?;
    if let Some(m) = method.filter(|m| !m.is_none()) {
        overrides.push(format!(
            "solver.method=\"{}\"",
            method_name(py, &source, m)?
        ));
    }
    // solve_ivp's tolerances: changes applied after the others, so they win.
    for (name, value) in [("rtol", rtol), ("atol", atol)] {
        if let Some(v) = value.filter(|v| !v.is_none()) {
            let x = crate::args::number(py, &source, name, v)?;
            overrides.push(format!("solver.{name}={}", toml::Value::Float(x)));
        }
    }
    let mut resolved = resolve(py, scenario, overrides)?;
    if let Some(t) = t_eval.filter(|t| !t.is_none()) {
        // One contiguous float64 array, read as a slice (no Python float per time).
        let times: Vec<f64> = py
            .import("numpy")?
            .getattr("ascontiguousarray")?
            .call1((t, "float64"))
            .and_then(|a| a.call_method0("ravel"))
            .and_then(|a| {
                let a = a.cast_into::<numpy::PyArray1<f64>>()?;
                let r = numpy::PyArrayMethods::readonly(&a);
                Ok(r.as_slice()?.to_vec())
            })
            .map_err(|_| {
                errors::type_error(
                    py,
                    &source,
                    Some("t_eval"),
                    None,
                    "expected a sequence of output times (s)",
                )
            })?;
        resolved = resolved.with_output_times(py, &times)?;
    }
    let inner = resolved.inner;
    crate::plausible::warn(py, &inner)?;
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

/// scipy's integrator names (and the scenario's own), case-insensitive, → the
/// scenario's `solver.method`.
fn method_name(py: Python<'_>, source: &str, method: &Bound<'_, PyAny>) -> PyResult<&'static str> {
    const RULE: &str = "give \"RK45\" (dopri5), \"DOP853\" (dop853), \"RK4\" (rk4, with solver.step), or the scenario names dopri5, dop853, rk4 (case-insensitive); scipy's RK23, Radau, BDF and LSODA have no counterpart here";
    let name = method.cast::<PyString>().map_err(|_| {
        errors::type_error(
            py,
            source,
            Some("method"),
            None,
            format!("expected a string; {RULE}"),
        )
    })?;
    let name = name.to_string_lossy().to_ascii_lowercase();
    match name.as_str() {
        "rk45" | "dopri5" => Ok("dopri5"),
        "dop853" => Ok("dop853"),
        "rk4" => Ok("rk4"),
        _ => Err(errors::value_error(
            py,
            source,
            Some("method"),
            Some(&format!("{name:?}")),
            RULE,
        )),
    }
}

/// A run's result as a Trajectory (or its summary dict), or its input error as an
/// exception. A run that stopped on an error is a Trajectory too (`success` False).
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
    let traj = Bound::new(py, Trajectory::new(run))?;
    if summary_only {
        traj.getattr("summary")
    } else {
        Ok(traj.into_any())
    }
}

/// Runs many scenarios in parallel (a rayon pool of `workers` threads; None = one per
/// CPU), without the GIL, and returns their results in input order: Trajectory objects,
/// or with `summaries_only=True` the summary dicts (the samples are then not kept).
///
/// `scenarios` holds `ellipsoid.Scenario` objects or scenario file paths, e.g.
/// `[base.replace(contact={"friction": mu}) for mu in (0.1, 0.2, 0.3)]`.
///
/// A run that stops on an error is a Trajectory with `success == False`, as in
/// `simulate`. `errors="raise"` (default) raises the first input error (ScenarioError)
/// in input order once every run has ended; `errors="return"` puts the exception object
/// in that scenario's place instead. Ctrl-C stops every run at
/// its next integration step and raises KeyboardInterrupt.
#[pyfunction]
#[pyo3(signature = (scenarios, workers = None, *, summaries_only = None, errors = None))]
#[pyo3(text_signature = "(scenarios, workers=None, *, summaries_only=False, errors='raise')")]
pub fn sweep<'py>(
    py: Python<'py>,
    scenarios: &Bound<'py, PyAny>,
    workers: Option<Bound<'py, PyAny>>,
    summaries_only: Option<Bound<'py, PyAny>>,
    errors: Option<Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyList>> {
    let return_errors = match errors.as_ref().filter(|e| !e.is_none()) {
        None => false,
        Some(e) => match e
            .cast::<PyString>()
            .ok()
            .and_then(|s| s.to_str().ok().map(str::to_owned))
            .as_deref()
        {
            Some("raise") => false,
            Some("return") => true,
            _ => {
                let shown = e
                    .repr()
                    .map(|r| r.to_string_lossy().into_owned())
                    .unwrap_or_default();
                return Err(errors::value_error(
                    py,
                    "sweep",
                    Some("errors"),
                    Some(&shown),
                    "expected \"raise\" or \"return\"",
                ));
            }
        },
    };
    let summaries_only = match summaries_only.as_ref().filter(|s| !s.is_none()) {
        None => false,
        Some(s) => s.cast::<PyBool>().map(|b| b.is_true()).map_err(|_| {
            errors::type_error(
                py,
                "sweep",
                Some("summaries_only"),
                None,
                "expected True or False",
            )
        })?,
    };
    let workers = worker_count(py, "sweep", workers.as_ref())?;
    let mut slots: Vec<Option<PyResult<Bound<'py, PyAny>>>> = Vec::new();
    let mut jobs: Vec<(usize, Scenario)> = Vec::new();
    let items = scenarios.try_iter().map_err(|_| {
        let ty = scenarios.get_type().name().map(|n| n.to_string()).unwrap_or_default();
        errors::type_error(py, "sweep", Some("scenarios"), None, format!("expected an iterable of ellipsoid.Scenario objects or scenario file paths, found {ty}"))
    })?;
    for (i, item) in items.enumerate() {
        match resolve(py, &item?, Vec::new()) {
            Ok(PyScenario { inner }) => {
                crate::plausible::warn(py, &inner)?;
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

/// Most worker threads a sweep or a study may start (4 per CPU, at least 8), as in
/// `ellipsoid study -j`.
pub use ellipsoid_study::study::max_threads as max_workers;

/// The `workers` argument of `source` (`sweep`, `study`): None (one per CPU) or an integer
/// in 1..=[`max_workers`].
pub(crate) fn worker_count(
    py: Python<'_>,
    source: &str,
    workers: Option<&Bound<'_, PyAny>>,
) -> PyResult<Option<usize>> {
    let Some(w) = workers.filter(|w| !w.is_none()) else {
        return Ok(None);
    };
    let max = max_workers();
    let rule =
        format!("give 1 to {max} worker threads (4 per CPU, at least 8), or None for one per CPU");
    let Some(w) = crate::args::as_int(w) else {
        let ty = crate::args::type_name(w);
        return Err(errors::type_error(
            py,
            source,
            Some("workers"),
            None,
            format!("expected an integer, found {ty}; {rule}"),
        ));
    };
    let digits = w
        .str()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    // An integer too long to read in a message is described, not cut.
    let shown = if digits.len() > 24 {
        format!(
            "an integer of {} digits",
            digits.trim_start_matches('-').len()
        )
    } else {
        digits
    };
    match w.extract::<i64>() {
        Ok(n) if n >= 1 && n as u64 <= max as u64 => Ok(Some(n as usize)),
        _ => Err(errors::value_error(
            py,
            source,
            Some("workers"),
            Some(&shown),
            rule,
        )),
    }
}
