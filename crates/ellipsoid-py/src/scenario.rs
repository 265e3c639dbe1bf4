//! `ellipsoid.Scenario` and `ellipsoid.load`: the core's scenario parser, unchanged.

use std::path::PathBuf;

use ellipsoid_core::scenario::{self, Scenario};
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};

use crate::convert;
use crate::errors;

/// A validated scenario: what to simulate (body, initial state, contact model, effects,
/// solver, output times), as read from a TOML scenario file or built from keyword
/// arguments that mirror the file's tables. SI units and radians throughout; keys ending in
/// `_deg` take degrees (see docs/scenarios.md).
///
/// Scenario(*, body, initial=None, contact, effects=None, solver=None, output, check=None, name="<scenario>")
///
/// Each keyword is a dict holding the keys of the TOML table of the same name, e.g.
/// `body=dict(a=0.025, c=0.0175, mass=0.05, com_offset=0.003, inertia=[9.3125e-6, 9.3125e-6, 1.25e-5])`
/// (semi-axes [m], mass [kg], inertia about G [kg·m²]), `initial=dict(theta_deg=10, psi_dot=60)`
/// ([rad] or [deg], [rad/s]), `contact=dict(model="coulomb", friction=0.3)`,
/// `output=dict(t_end=1.0, dt=1e-3)` ([s]). The dicts are written out as a TOML document
/// (`Scenario.text`) and parsed by the same parser as a file, so every check and every
/// message is the command-line tool's. A key whose value is None is left out. Raises
/// ScenarioError naming the key (`err.key`) and the rule.
///
/// Scenarios are immutable; `replace(...)` returns a changed copy.
#[pyclass(frozen, module = "ellipsoid", name = "Scenario")]
#[derive(Clone)]
pub struct PyScenario {
    pub inner: Scenario,
}

impl PyScenario {
    /// `scenario::parse_all` with its errors as one `ScenarioError`.
    pub fn parse(py: Python<'_>, text: &str, source: &str, overrides: &[String]) -> PyResult<Self> {
        errors::guard(py, || {
            scenario::parse_all(text, source, overrides)
                .map(|inner| PyScenario { inner })
                .map_err(|e| errors::scenario_errors(py, &e))
        })
    }

    /// `scenario::load_all` with its errors as one `ScenarioError`.
    pub fn load(py: Python<'_>, path: &std::path::Path, overrides: &[String]) -> PyResult<Self> {
        errors::guard(py, || {
            scenario::load_all(path, overrides)
                .map(|inner| PyScenario { inner })
                .map_err(|e| errors::scenario_errors(py, &e))
        })
    }

    /// This scenario with more overrides (`key=value`), applied to its document, which
    /// is then validated again (every check runs).
    #[allow(clippy::result_large_err)] // the scenario's own error, once per failed change
    pub fn with_overrides(&self, py: Python<'_>, more: Vec<String>) -> PyResult<Self> {
        self.changed(py, more.len(), |draft, i| draft.apply(&more[i]))
    }

    /// This scenario with `n` changes made to its document by `change(draft, i)`, validated
    /// again; itself when there are none.
    fn changed(
        &self,
        py: Python<'_>,
        n: usize,
        change: impl Fn(&mut scenario::Draft, usize) -> Result<(), scenario::ScenarioError>,
    ) -> PyResult<Self> {
        if n == 0 {
            return Ok(self.clone());
        }
        errors::guard(py, || {
            let mut draft = self.inner.draft();
            for i in 0..n {
                change(&mut draft, i).map_err(|e| errors::scenario_errors(py, &e.into()))?;
            }
            draft
                .build()
                .map(|inner| PyScenario { inner })
                .map_err(|e| errors::scenario_errors(py, &e))
        })
    }

    /// This scenario sampled at `times` [s] instead of its `dt` or `times` (`simulate`'s
    /// `t_eval`): the `[output]` table's sampling keys and changes are dropped and
    /// `output.times` set, so that the scenario's text and changes still rebuild it.
    /// The times must be finite, strictly increasing, in [0, t_end], at most
    /// `MAX_SAMPLES`; an error names `t_eval`.
    pub fn with_output_times(&self, py: Python<'_>, times: &[f64]) -> PyResult<Self> {
        let source = &self.inner.source;
        let t_end = self.inner.scene.t_end;
        let bad = |value: String, rule: String| {
            errors::value_error(py, source, Some("t_eval"), Some(&value), rule)
        };
        if times.is_empty() {
            return Err(bad("[]".into(), "give at least one output time (s)".into()));
        }
        if times.len() > scenario::MAX_SAMPLES {
            return Err(bad(
                format!("{} times", times.len()),
                format!("at most {} output times are allowed", scenario::MAX_SAMPLES),
            ));
        }
        if let Some(x) = times.iter().find(|x| !(0.0..=t_end).contains(*x)) {
            return Err(bad(
                x.to_string(),
                format!("every time in t_eval must lie in [0, t_end] = [0, {t_end}] s"),
            ));
        }
        if let Some(w) = times.windows(2).find(|w| w[1] <= w[0]) {
            return Err(bad(
                format!("{} after {}", w[1], w[0]),
                "the times in t_eval must be strictly increasing (s)".into(),
            ));
        }
        let mut doc: toml::Table = toml::from_str(&self.inner.text)
            .map_err(|e| errors::internal_error(py, &e.to_string()))?;
        if let Some(toml::Value::Table(output)) = doc.get_mut("output") {
            output.remove("dt");
            output.remove("times");
        }
        let overrides: Vec<String> = self
            .inner
            .overrides
            .iter()
            .filter(|o| !(o.starts_with("output.dt=") || o.starts_with("output.times=")))
            .cloned()
            .collect();
        let text = toml::to_string(&doc).map_err(|e| errors::internal_error(py, &e.to_string()))?;
        // Times k·dt from 0 to t_end (`np.arange(0, t_end + dt/2, dt)`, `np.linspace(0,
        // t_end, n)`) are the scenario's own `output.dt` grid: recorded as that one change
        // when its grid is these times bit for bit, so they cost what `output.dt` costs
        // (a document holding 10 001 times costs about a sixth of a 10 s run more to
        // build, keep and free).
        if let Some(scenario) = as_grid(&text, source, &overrides, times, t_end) {
            return Ok(PyScenario { inner: scenario });
        }
        // The times are set on the parsed document as values, not as TOML text to parse
        // again (which cost about as much as the run's own sampling); the change is
        // recorded as `output.times=[...]`, as `ellipsoid run --set` would write it.
        // (Each time in the shortest form that reads back to it, `0.001`, `10.0`, `1e-300`,
        // by zmij as the CSV writer does: several times faster than `{:?}`.)
        let mut label = String::with_capacity(16 + 24 * times.len());
        label.push_str("output.times=[");
        let mut digits = zmij::Buffer::new();
        for (i, x) in times.iter().enumerate() {
            if i > 0 {
                label.push_str(", ");
            }
            label.push_str(digits.format(*x));
        }
        label.push(']');
        let list = toml::Value::Array(times.iter().map(|&x| toml::Value::Float(x)).collect());
        errors::guard(py, || {
            let mut draft = scenario::Draft::parse(&text, source, &overrides)
                .map_err(|e| errors::scenario_errors(py, &e))?;
            draft
                .change("output.times", &list, &label)
                .map_err(|e| errors::scenario_errors(py, &e.into()))?;
            draft
                .build()
                .map(|inner| PyScenario { inner })
                .map_err(|e| errors::scenario_errors(py, &e))
        })
    }
}

/// The scenario of `text` with `overrides` and `output.dt` = `times[1]`, if its sample
/// times are `times` exactly (`times` from 0 to `t_end`); None otherwise.
fn as_grid(
    text: &str,
    source: &str,
    overrides: &[String],
    times: &[f64],
    t_end: f64,
) -> Option<Scenario> {
    let (&first, &last) = (times.first()?, times.last()?);
    if times.len() < 2 || first.to_bits() != 0.0f64.to_bits() || last != t_end {
        return None;
    }
    let dt = times[1];
    let label = format!("output.dt={}", zmij::Buffer::new().format(dt));
    let mut draft = scenario::Draft::parse(text, source, overrides).ok()?;
    draft
        .change("output.dt", &toml::Value::Float(dt), &label)
        .ok()?;
    let scenario = draft.build().ok()?;
    let same = scenario.scene.sample_times.len() == times.len()
        && scenario
            .scene
            .sample_times
            .iter()
            .zip(times)
            .all(|(a, b)| a.to_bits() == b.to_bits());
    same.then_some(scenario)
}

#[pymethods]
impl PyScenario {
    #[new]
    #[pyo3(signature = (*, body = None, initial = None, contact = None, effects = None, solver = None, output = None, check = None, name = None, **unknown))]
    #[pyo3(
        text_signature = "(*, body=None, initial=None, contact=None, effects=None, solver=None, output=None, check=None, name='<scenario>', **unknown)"
    )]
    #[allow(clippy::too_many_arguments)] // one keyword per TOML table, as the issue asks
    fn new(
        py: Python<'_>,
        body: Option<Bound<'_, PyAny>>,
        initial: Option<Bound<'_, PyAny>>,
        contact: Option<Bound<'_, PyAny>>,
        effects: Option<Bound<'_, PyAny>>,
        solver: Option<Bound<'_, PyAny>>,
        output: Option<Bound<'_, PyAny>>,
        check: Option<Bound<'_, PyAny>>,
        name: Option<Bound<'_, PyAny>>,
        unknown: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        let name = name_arg(py, name.as_ref(), "<scenario>")?;
        let conv = convert::Conv { source: &name };
        let mut parts = vec![
            ("body".to_owned(), body),
            ("initial".to_owned(), initial),
            ("contact".to_owned(), contact),
            ("effects".to_owned(), effects),
            ("solver".to_owned(), solver),
            ("output".to_owned(), output),
            ("check".to_owned(), check),
        ];
        // A misspelt table keyword reaches the parser, which names it with a suggestion
        // ("unknown table at the top level; did you mean `body`?").
        if let Some(unknown) = unknown {
            for (k, v) in unknown.iter() {
                let k = k
                    .cast::<PyString>()
                    .map(|s| s.to_string_lossy().into_owned())
                    .unwrap_or_default();
                parts.push((k, Some(v)));
            }
        }
        let parts: Vec<(&str, Option<&Bound<'_, PyAny>>)> = parts
            .iter()
            .map(|(k, v)| (k.as_str(), v.as_ref()))
            .collect();
        let text = conv.document(&parts)?;
        Self::parse(py, &text, &name, &[])
    }

    /// Parses a scenario from TOML text; `name` stands for the file in messages and in
    /// the summary. Keyword arguments are changes, as for `replace`.
    #[staticmethod]
    #[pyo3(signature = (text, name = None, **changes))]
    #[pyo3(text_signature = "(text, name='<string>', **changes)")]
    fn from_toml(
        py: Python<'_>,
        text: &Bound<'_, PyAny>,
        name: Option<Bound<'_, PyAny>>,
        changes: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        let name = name_arg(py, name.as_ref(), "<string>")?;
        let text = str_arg(py, text, &name, "text")?;
        Self::parse(
            py,
            &text,
            &name,
            &convert::Conv { source: &name }.overrides(changes)?,
        )
    }

    /// A copy with some values changed, like the command line's `--set key=value`:
    /// `replace(contact={"friction": 0.2})` (a dict merges into the table: only the keys
    /// given change) or `replace(**{"contact.friction": 0.2, "output.t_end": 1.0})` (dotted
    /// keys). The changed scenario is validated again; a bad value raises ScenarioError
    /// naming the override. Keys cannot be removed.
    #[pyo3(signature = (**changes))]
    #[allow(clippy::result_large_err)] // the scenario's own error, once per failed change
    fn replace(&self, py: Python<'_>, changes: Option<&Bound<'_, PyDict>>) -> PyResult<Self> {
        let changes = convert::Conv {
            source: &self.inner.source,
        }
        .changes(changes)?;
        self.changed(py, changes.len(), |draft, i| {
            let (key, value) = &changes[i];
            draft.change(key, value, &convert::label(key, value))
        })
    }

    /// The value the scenario's document holds at `key`, a key path of `replace`'s grammar
    /// (`"contact.friction"`, `"body.inertia[0]"`, `"observe[0].crosses"`), after its
    /// changes: a float, int, str, bool, list or dict as the document has it, in the unit
    /// of its key (`initial.theta` in rad, `initial.theta_deg` in degrees; each twin only
    /// as written). `default` (None) when the document does not set the key: the format's
    /// default then applies, which this does not show. A key that is not of the grammar
    /// raises ScenarioError.
    #[pyo3(signature = (key, default = None))]
    fn get(&self, py: Python<'_>, key: &str, default: Option<Py<PyAny>>) -> PyResult<Py<PyAny>> {
        let path = scenario::KeyPath::parse(key).map_err(|e| {
            errors::value_error(
                py,
                &self.inner.source,
                Some(&errors::short(key)),
                None,
                e.to_string(),
            )
        })?;
        match self.inner.draft().get(&path) {
            Some(value) => convert::to_python(py, &value),
            None => Ok(default.unwrap_or_else(|| py.None())),
        }
    }

    /// Where the scenario came from: the file path as given, or the name of the text.
    #[getter]
    fn source(&self) -> &str {
        &self.inner.source
    }

    /// The file name without its extension (`nutation` for `scenarios/nutation.toml`).
    #[getter]
    fn stem(&self) -> String {
        self.inner.stem()
    }

    /// The TOML text as read or built (before overrides).
    #[getter]
    fn text(&self) -> &str {
        &self.inner.text
    }

    /// The `key=value` overrides applied to `text`, in order.
    #[getter]
    fn overrides(&self) -> Vec<String> {
        self.inner.overrides.clone()
    }

    /// End time of the run [s].
    #[getter]
    fn t_end(&self) -> f64 {
        self.inner.scene.t_end
    }

    /// Output times [s] (a new float64 array).
    #[getter]
    fn sample_times<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.inner.scene.sample_times)
    }

    /// The contact model: "frictionless", "sliding", "rolling" or "coulomb".
    #[getter]
    fn contact_model(&self) -> &'static str {
        self.inner.scene.contact.name()
    }

    fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
        let source = PyString::new(py, &self.inner.source).repr()?;
        let scene = &self.inner.scene;
        let ax = scene.body.semi_axes();
        let init = &scene.initial;
        let omega = init.omega_body.unwrap_or_else(|| init.angles.omega_body());
        let mut s = format!(
            "<ellipsoid.Scenario {source}: {}, a = {} m, b = {} m, c = {} m, mass = {} kg; theta = {} rad, omega_body = [{}, {}, {}] rad/s; {}, t_end = {} s, {} samples",
            self.contact_model(),
            ax.x,
            ax.y,
            ax.z,
            scene.body.mass(),
            init.angles.theta,
            omega.x,
            omega.y,
            omega.z,
            scene.solver.method.name(),
            scene.t_end,
            scene.sample_times.len(),
        );
        if !self.inner.overrides.is_empty() {
            s.push_str(&format!("; changes: {}", self.inner.overrides.join(" ")));
        }
        s.push('>');
        Ok(s)
    }

    /// Pickling (joblib, multiprocessing): the text, the name and the changes, parsed
    /// again when unpickled.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let rebuild = py.import("ellipsoid._result")?.getattr("_scenario")?;
        (
            rebuild,
            (
                self.inner.text.clone(),
                self.inner.source.clone(),
                self.inner.overrides.clone(),
            ),
        )
            .into_pyobject(py)
            .map(Bound::into_any)
    }

    /// The inverse of `__reduce__`.
    #[staticmethod]
    fn _from_parts(
        py: Python<'_>,
        text: &str,
        source: &str,
        overrides: Vec<String>,
    ) -> PyResult<Self> {
        Self::parse(py, text, source, &overrides)
    }

    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        other
            .cast::<PyScenario>()
            .is_ok_and(|o| o.get().inner == self.inner)
    }

    fn __copy__(&self) -> Self {
        self.clone()
    }

    fn __deepcopy__(&self, _memo: &Bound<'_, PyAny>) -> Self {
        self.clone()
    }
}

/// Reads a scenario file (TOML; SI units, see docs/scenarios.md), applying `changes` as
/// `Scenario.replace` does. Raises ScenarioError (file, line, column, key, value and
/// rule in the message) if it cannot be read or is invalid.
#[pyfunction]
#[pyo3(signature = (path, **changes))]
pub fn load(
    py: Python<'_>,
    path: &Bound<'_, PyAny>,
    changes: Option<&Bound<'_, PyDict>>,
) -> PyResult<PyScenario> {
    let path = path_arg(py, path)?;
    PyScenario::load(
        py,
        &path,
        &convert::Conv {
            source: &path.display().to_string(),
        }
        .overrides(changes)?,
    )
}

/// A path argument (`str` or `os.PathLike`), or ScenarioTypeError.
fn path_arg(py: Python<'_>, what: &Bound<'_, PyAny>) -> PyResult<PathBuf> {
    what.extract::<PathBuf>().map_err(|_| {
        let ty = what
            .get_type()
            .name()
            .map(|n| n.to_string())
            .unwrap_or_default();
        errors::type_error(
            py,
            "<arguments>",
            None,
            None,
            format!("expected an ellipsoid.Scenario or the path of a scenario file, found {ty}"),
        )
    })
}

/// A string argument (`name`, `text`) as UTF-8, or ScenarioError / ScenarioTypeError.
fn str_arg(py: Python<'_>, what: &Bound<'_, PyAny>, source: &str, arg: &str) -> PyResult<String> {
    let Ok(s) = what.cast::<PyString>() else {
        let ty = what
            .get_type()
            .name()
            .map(|n| n.to_string())
            .unwrap_or_default();
        return Err(errors::type_error(
            py,
            source,
            Some(arg),
            None,
            format!("expected a string, found {ty}"),
        ));
    };
    s.to_str().map(str::to_owned).map_err(|_| {
        errors::value_error(
            py,
            source,
            Some(arg),
            None,
            "not valid Unicode text (it holds a lone surrogate); give UTF-8 text",
        )
    })
}

/// The `name` argument, `default` when None.
fn name_arg(py: Python<'_>, name: Option<&Bound<'_, PyAny>>, default: &str) -> PyResult<String> {
    match name.filter(|n| !n.is_none()) {
        Some(n) => str_arg(py, n, default, "name"),
        None => Ok(default.to_owned()),
    }
}

/// A scenario from a `Scenario` or a path (`str` / `os.PathLike`), with `changes` applied.
pub fn resolve(
    py: Python<'_>,
    what: &Bound<'_, PyAny>,
    changes: Vec<String>,
) -> PyResult<PyScenario> {
    if let Ok(s) = what.cast::<PyScenario>() {
        return s.get().with_overrides(py, changes);
    }
    PyScenario::load(py, &path_arg(py, what)?, &changes)
}
