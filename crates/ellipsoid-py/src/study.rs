//! `ellipsoid.precision` (the work–precision study, `PrecisionTable`) and
//! `ellipsoid.check` (a scenario's derived quantities), both from `ellipsoid-study`, the
//! code behind `ellipsoid precision` and `ellipsoid check`.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use ellipsoid_core::scenario::Scenario;
use ellipsoid_io::{OutputError, Summary, atomic};
use ellipsoid_study::precision as study;
use ellipsoid_study::precision::{
    Column, Hooks, Report, Spelling, StudyError, StudyOptions, WriteError,
};
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{IntoPyDict, PyDict, PyList};

use crate::convert;
use crate::errors::{self, Class};
use crate::run::{self, Run, VERSION};
use crate::scenario::resolve;
use crate::trajectory::Trajectory;

/// The work–precision study of `ellipsoid precision SCENARIO.toml`: every method over a
/// grid of settings (RK4 at h = 1e-2 … 1e-6 s, DOPRI5 and DOP853 at rtol = 1e-3 … 1e-13),
/// each run's error against a reference (the exact nutation period for a frictionless
/// body of revolution, else a DOP853 run at rtol = 1e-14), its invariant drift, median
/// wall time, right-hand-side evaluations and steps. Returns a PrecisionTable.
///
/// `scenario` is an `ellipsoid.Scenario` or the path of a scenario file; `changes` are
/// applied first, as for `simulate`. The options mirror the command line's:
/// `t_end` [s] (`--t-end`; default the scenario's end time, at most 10 s), `quick`
/// (`--quick`: three settings per method, one timed run each), `repeats` (`--repeats`:
/// fewest timed runs per setting, 1 to 1000; default 3, 1 with `quick`), `out`
/// (`-o DIR`: write precision.csv, error_vs_time.svg and error_vs_evaluations.svg there,
/// each atomically, the directory created as needed; default: write nothing).
///
/// The GIL is released while the study runs; Ctrl-C stops it at the next integration
/// step and raises KeyboardInterrupt. Raises ScenarioError for a bad scenario or option
/// (`err.key` is "t_end" or "repeats" for an option), SimulationError when the
/// reference run does not finish cleanly (`.trajectory` holds its summary, no samples),
/// OutputError when `out` cannot be written.
#[pyfunction]
#[pyo3(signature = (scenario, /, *, t_end = None, quick = None, repeats = None, out = None, **changes))]
#[pyo3(
    text_signature = "(scenario, /, *, t_end=None, quick=False, repeats=None, out=None, **changes)"
)]
pub fn precision(
    py: Python<'_>,
    scenario: &Bound<'_, PyAny>,
    t_end: Option<&Bound<'_, PyAny>>,
    quick: Option<&Bound<'_, PyAny>>,
    repeats: Option<&Bound<'_, PyAny>>,
    out: Option<&Bound<'_, PyAny>>,
    changes: Option<&Bound<'_, PyDict>>,
) -> PyResult<PrecisionTable> {
    let scenario = resolve(py, scenario, convert::changes_for(scenario, changes)?)?.inner;
    crate::plausible::warn(py, &scenario)?;
    // Read by hand: pyo3's extraction would raise a plain TypeError.
    let quick = match quick.map(|q| q.cast::<pyo3::types::PyBool>()) {
        None => false,
        Some(Ok(b)) => b.is_true(),
        Some(Err(_)) => {
            let quick = quick.expect("given");
            return Err(crate::errors::type_error(
                py,
                &scenario.source,
                Some("quick"),
                None,
                format!(
                    "expected True or False, found {}",
                    crate::args::type_name(quick)
                ),
            ));
        }
    };
    let out = crate::args::opt_path(py, &scenario.source, "out", out)?;
    let not_bool = |v: &Bound<'_, PyAny>| !v.is_instance_of::<pyo3::types::PyBool>();
    let t_end = match t_end {
        None => None,
        Some(t) => match t.extract::<f64>() {
            Ok(x) if not_bool(t) => Some(x),
            _ => {
                return Err(option_error(
                    py,
                    &scenario,
                    "t_end",
                    &t.repr()?.to_string(),
                    "expected a number, the simulated time per run (s), or None",
                    None,
                ));
            }
        },
    };
    let repeats = match repeats {
        None => None,
        Some(r) => Some(repeats_value(py, &scenario, r)?),
    };
    let options = StudyOptions {
        t_end,
        quick,
        repeats,
    };
    let work_scenario = scenario.clone();
    let (result, interrupt) = run::detached(py, move |cancel| {
        let hooks = Hooks {
            cancel: Some(Arc::clone(cancel)),
            ..Hooks::SILENT
        };
        let report = study::measure(&work_scenario, &options, &Spelling::PYTHON, &hooks)
            .map_err(Failure::Study)?;
        if let Some(dir) = &out {
            study::write(&report, dir).map_err(Failure::Write)?;
        }
        Ok(report)
    })?;
    if let Some(e) = interrupt {
        return Err(e);
    }
    match result {
        Ok(report) => Ok(PrecisionTable::new(report)),
        Err(Failure::Study(e)) => Err(study_error(py, &scenario, e)),
        Err(Failure::Write(WriteError::Output(e))) => Err(errors::output_error(py, &e)),
        Err(Failure::Write(e @ WriteError::Plot(_))) => {
            Err(Class::Output.error(py, &e.to_string(), &[("errno", py.None())]))
        }
    }
}

enum Failure {
    Study(StudyError),
    Write(WriteError),
}

/// `repeats` as the study takes it: an integer (anything `operator.index` takes, bool refused); a negative or huge one
/// gets the study's own range error.
fn repeats_value(py: Python<'_>, scenario: &Scenario, r: &Bound<'_, PyAny>) -> PyResult<u64> {
    let Some(r) = crate::args::as_int(r) else {
        return Err(option_error(
            py,
            scenario,
            "repeats",
            &r.repr()?.to_string(),
            "expected an int, the fewest timed runs per setting (1 to 1000)",
            None,
        ));
    };
    match r.extract::<u64>() {
        Ok(n) => Ok(n),
        Err(_) => Err(study_error(
            py,
            scenario,
            study::repeats_error(&r.str()?.to_string(), &Spelling::PYTHON),
        )),
    }
}

/// A bad study option as ScenarioError (`kind` "invalid", `key` the option's name).
fn option_error(
    py: Python<'_>,
    scenario: &Scenario,
    key: &str,
    value: &str,
    rule: &str,
    message: Option<&str>,
) -> PyErr {
    let message = message.map_or_else(|| format!("{key}={value}: {rule}"), str::to_owned);
    let obj = |v: Option<&str>| -> Py<PyAny> {
        v.into_pyobject(py)
            .map(|o| o.into_any().unbind())
            .unwrap_or_else(|_| py.None())
    };
    Class::Scenario.error(
        py,
        &message,
        &[
            ("kind", obj(Some("invalid"))),
            ("key", obj(Some(key))),
            ("value", obj(Some(value))),
            ("rule", obj(Some(rule))),
            ("source", obj(Some(&scenario.source))),
            ("line", py.None()),
            ("column", py.None()),
            ("override", py.None()),
        ],
    )
}

fn study_error(py: Python<'_>, scenario: &Scenario, e: StudyError) -> PyErr {
    match e {
        StudyError::Scenario(e) => errors::scenario_error(py, &e),
        StudyError::Option {
            option,
            ref value,
            ref rule,
            ..
        } => option_error(
            py,
            scenario,
            option.key(),
            value,
            rule,
            Some(&e.to_string()),
        ),
        StudyError::Reference { message, outcome } => {
            let summary = Summary::new(scenario, &outcome, 0.0, 0, None, VERSION);
            let status = summary.status.name();
            let trajectory = Trajectory::new(Run {
                scenario: scenario.clone(),
                samples: Vec::new(),
                summary,
                sections: outcome.sections.clone(),
            });
            let attrs = (|| -> PyResult<Vec<(&str, Py<PyAny>)>> {
                Ok(vec![
                    ("status", status.into_pyobject(py)?.into_any().unbind()),
                    (
                        "trajectory",
                        Bound::new(py, trajectory)?.into_any().unbind(),
                    ),
                ])
            })();
            match attrs {
                Ok(attrs) => {
                    Class::Simulation.error(py, &format!("no reference: {message}"), &attrs)
                }
                Err(e) => e,
            }
        }
        // Only the interrupt sets the flag, and it is raised before this.
        StudyError::Cancelled => {
            errors::internal_error(py, "the study was cancelled without an interrupt")
        }
    }
}

/// The table of a work–precision study (`ellipsoid.precision`): one row per setting,
/// one read-only numpy array per column of the `precision.csv` that `ellipsoid
/// precision` writes, named and ordered alike (`columns`).
///
/// Columns: `scene`, `measure` ("period" or "final_state"), `method` ("rk4", "dopri5",
/// "dop853"), `setting` ("h=1e-4", "rtol=1e-10"), `status` (str arrays); `t_end`, `h`,
/// `rtol`, `atol`, `t_final` [s or 1], `error`, `period_error`, `state_error`,
/// `energy_drift`, `invariant_drift` [1, relative], `wall_time_median_s`,
/// `wall_time_min_s` [s] (float64, NaN where the CSV cell is empty: h of the adaptive
/// methods, rtol and atol of RK4, measures that do not apply); `repeats`, `rhs_evals`,
/// `steps`, `rejected` (int64). The values are the CSV's exactly (it prints floats in
/// the shortest form that reads back to the same number).
#[pyclass(frozen, module = "ellipsoid")]
pub struct PrecisionTable {
    report: Report,
    cached: PyOnceLock<Py<PyDict>>,
}

impl PrecisionTable {
    fn new(report: Report) -> Self {
        PrecisionTable {
            report,
            cached: PyOnceLock::new(),
        }
    }

    /// Column name → read-only numpy array, built once.
    fn arrays<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let dict = self.cached.get_or_try_init(py, || -> PyResult<_> {
            let numpy = py.import("numpy")?;
            let dict = PyDict::new(py);
            for (name, column) in study::columns(&self.report) {
                let arr = match column {
                    Column::Float(v) => PyArray1::from_vec(
                        py,
                        v.into_iter().map(|x| x.unwrap_or(f64::NAN)).collect(),
                    )
                    .into_any(),
                    Column::Count(v) => PyArray1::from_vec(
                        py,
                        v.into_iter().map(|x| x as i64).collect::<Vec<i64>>(),
                    )
                    .into_any(),
                    Column::Text(v) => numpy.getattr("array")?.call(
                        (PyList::new(py, v)?,),
                        Some(&[("dtype", "U")].into_py_dict(py)?),
                    )?,
                };
                let kwargs = [("write", false)].into_py_dict(py)?;
                arr.call_method("setflags", (), Some(&kwargs))?;
                dict.set_item(name, arr)?;
            }
            Ok(dict.unbind())
        })?;
        Ok(dict.bind(py).clone())
    }

    fn column<'py>(&self, py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyAny>> {
        self.arrays(py)?
            .get_item(name)?
            .ok_or_else(|| errors::internal_error(py, &format!("no column {name}")))
    }
}

#[pymethods]
impl PrecisionTable {
    /// Column names in the CSV file's order.
    #[classattr]
    fn columns() -> Vec<&'static str> {
        study::CSV_HEADER.split(',').collect()
    }

    /// The scenario's name (its file name without .toml), per row.
    #[getter]
    fn scene<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.column(py, "scene")
    }
    /// Simulated time of every run [s], per row.
    #[getter]
    fn t_end<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.column(py, "t_end")
    }
    /// The error measure, "period" or "final_state", per row.
    #[getter]
    fn measure<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.column(py, "measure")
    }
    /// "rk4", "dopri5" or "dop853".
    #[getter]
    fn method<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.column(py, "method")
    }
    /// "h=1e-4" (RK4) or "rtol=1e-10".
    #[getter]
    fn setting<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.column(py, "setting")
    }
    /// RK4's fixed step [s]; NaN for the adaptive methods.
    #[getter]
    fn h<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.column(py, "h")
    }
    /// Relative tolerance [1]; NaN for RK4.
    #[getter]
    fn rtol<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.column(py, "rtol")
    }
    /// Absolute tolerance [1]; NaN for RK4.
    #[getter]
    fn atol<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.column(py, "atol")
    }
    /// How the run ended (the summary's status name).
    #[getter]
    fn status<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.column(py, "status")
    }
    /// Time at which the run ended [s].
    #[getter]
    fn t_final<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.column(py, "t_final")
    }
    /// The headline error [1] (inf where it could not be measured).
    #[getter]
    fn error<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.column(py, "error")
    }
    /// |T_run − T|/T [1] (measure "period"); NaN otherwise.
    #[getter]
    fn period_error<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.column(py, "period_error")
    }
    /// Final-state error against the reference run [1] (measure "final_state"); NaN otherwise.
    #[getter]
    fn state_error<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.column(py, "state_error")
    }
    /// Relative drift of E (conservative scenes) or E + W [1].
    #[getter]
    fn energy_drift<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.column(py, "energy_drift")
    }
    /// Largest relative drift of the invariants the scene conserves [1].
    #[getter]
    fn invariant_drift<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.column(py, "invariant_drift")
    }
    /// Median wall time of the timed runs [s].
    #[getter]
    fn wall_time_median_s<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.column(py, "wall_time_median_s")
    }
    /// Shortest wall time of the timed runs [s].
    #[getter]
    fn wall_time_min_s<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.column(py, "wall_time_min_s")
    }
    /// Timed runs made of the setting.
    #[getter]
    fn repeats<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.column(py, "repeats")
    }
    /// Right-hand-side evaluations of the integrator.
    #[getter]
    fn rhs_evals<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.column(py, "rhs_evals")
    }
    /// Accepted steps.
    #[getter]
    fn steps<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.column(py, "steps")
    }
    /// Rejected steps.
    #[getter]
    fn rejected<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.column(py, "rejected")
    }

    /// What the errors are measured against: `measure` ("period" or "final_state"),
    /// `description` (the paragraph the command line prints), `status` (how an accurate
    /// run ends); for "period" also `period` [s], `period_uncertainty` [s], `theta_min`
    /// and `theta_max` [rad]; for "final_state" `rtol` (the reference run's),
    /// `uncertainty` [1] (its distance from a tighter run: smaller errors are not
    /// resolved) and `t_final` [s].
    #[getter]
    fn reference<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let r = &self.report.reference;
        let d = PyDict::new(py);
        d.set_item("measure", r.measure())?;
        d.set_item("description", r.describe())?;
        d.set_item("status", r.status())?;
        match r {
            study::Reference::Period { nutation, .. } => {
                d.set_item("period", nutation.period)?;
                d.set_item("period_uncertainty", nutation.uncertainty)?;
                d.set_item("theta_min", nutation.theta_min)?;
                d.set_item("theta_max", nutation.theta_max)?;
            }
            study::Reference::State {
                outcome,
                rtol,
                uncertainty,
            } => {
                d.set_item("rtol", *rtol)?;
                d.set_item("uncertainty", *uncertainty)?;
                d.set_item("t_final", outcome.final_sample.t)?;
            }
        }
        Ok(d)
    }

    /// The table and the cheapest setting reaching 1e-3, 1e-6, 1e-9 and 1e-12, as
    /// `ellipsoid precision` prints them.
    #[getter]
    fn summary(&self) -> String {
        study::summary(&self.report)
    }

    /// Notes made while measuring (e.g. why no exact period reference was formed).
    #[getter]
    fn notes(&self) -> Vec<String> {
        self.report.notes.clone()
    }

    fn __len__(&self) -> usize {
        self.report.rows.len()
    }

    fn __repr__(&self) -> String {
        format!(
            "<ellipsoid.PrecisionTable {:?}: {} settings, t_end = {} s, measure {:?}>",
            self.report.scene_name,
            self.report.rows.len(),
            self.report.t_end,
            self.report.reference.measure()
        )
    }

    /// Column name → numpy array (the arrays themselves, read-only), in CSV order.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        self.arrays(py)?.copy()
    }

    /// A pandas.DataFrame of the columns, in CSV order (needs pandas).
    fn to_pandas<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let pandas = py.import("pandas").map_err(|e| {
            pyo3::exceptions::PyImportError::new_err(format!(
                "PrecisionTable.to_pandas needs pandas (`pip install pandas`): {e}"
            ))
        })?;
        pandas.getattr("DataFrame")?.call1((self.to_dict(py)?,))
    }

    /// Writes the table as CSV, byte for byte the `precision.csv` of `ellipsoid
    /// precision`; the file appears only when complete, its directory must exist.
    /// Raises OutputError.
    fn to_csv(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        let text = study::csv(&self.report);
        py.detach(|| atomic::write(&path, text.as_bytes()))
            .map_err(|e: OutputError| errors::output_error(py, &e))
    }

    /// Writes precision.csv, error_vs_time.svg and error_vs_evaluations.svg into `dir`
    /// (created as needed; each file atomically), as `ellipsoid precision -o DIR` does;
    /// returns their paths. Raises OutputError.
    fn write(&self, py: Python<'_>, dir: PathBuf) -> PyResult<Vec<PathBuf>> {
        let report = &self.report;
        errors::guard(py, || {
            py.detach(|| study::write(report, Path::new(&dir)))
                .map_err(|e| match e {
                    WriteError::Output(e) => errors::output_error(py, &e),
                    e @ WriteError::Plot(_) => {
                        Class::Output.error(py, &e.to_string(), &[("errno", py.None())])
                    }
                })
        })
    }
}

/// What `ellipsoid check SCENARIO.toml` prints, as a dict (SI units, radians; vectors
/// as lists, body axes unless named `_world`): `scenario`, `overrides`, `body`
/// (`semi_axes` [m], `shape`, `mass` [kg], `inertia` [kg m²] by rows,
/// `principal_moments` [kg m²], `com_offset` [m], `com_offset_radial` (gᵀA⁻²g, < 1
/// inside the body), `weight` [N], `spheres` (`name`, `center` [m], `radius` [m]), `rims`
/// (`name`, `center`, `radius`, `edge` [m]), `ellipsoid_contact`, `two_contact_tilts`:
/// the tilts θ* at which two surfaces touch at once, dicts of `surfaces` (two names),
/// `theta` [rad] and `theta_deg`; empty for one surface, None for a body of several not
/// of revolution about its c axis),
/// `gravity` [m/s²], `contact` (`model`, `friction`, `disc`: `radius` [m] and `law`, or None),
/// `effects` (`rolling_resistance`, `spin_friction`, `air_drag`, `rolling_friction`,
/// `air_film`, `air_boundary_layer`, None where absent),
/// `initial` (`theta`, `phi`, `psi` [rad], `theta_deg`, `rates` (`theta_dot`, `phi_dot`,
/// `psi_dot` [rad/s]; None when `omega_body` was given), `omega_body` [rad/s],
/// `omega_body_given`, `contact_point` [m] (from C0), `contact_point_world` [m],
/// `height` [m] (of G), `mode`, `normal_force` [N], `energy` [J], `slip_speed` [m/s]),
/// `invariants` (tracked by a run), `solver` (`method`, `step` [s], `rtol`, `atol`,
/// `initial_step` [s]), `output` (`t_end` [s], `samples`), `check` (`status`, `drift`).
///
/// `scenario` is an `ellipsoid.Scenario` or a path; `changes` are applied first. Makes
/// every check a run makes at t = 0 (raises ScenarioError as the command line reports
/// it), without simulating further.
#[pyfunction]
#[pyo3(signature = (scenario, /, **changes))]
pub fn check<'py>(
    py: Python<'py>,
    scenario: &Bound<'py, PyAny>,
    changes: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyAny>> {
    let scenario = resolve(py, scenario, convert::changes_for(scenario, changes)?)?.inner;
    crate::plausible::warn(py, &scenario)?;
    let derived = errors::guard(py, || {
        ellipsoid_study::check::derive(&scenario).map_err(|e| errors::scenario_error(py, &e))
    })?;
    let json = serde_json::to_string(&derived)
        .map_err(|e| errors::internal_error(py, &format!("check data: {e}")))?;
    py.import("json")?.getattr("loads")?.call1((json,))
}
