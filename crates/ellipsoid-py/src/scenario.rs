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
    /// `scenario::parse` with errors as `ScenarioError`.
    pub fn parse(py: Python<'_>, text: &str, source: &str, overrides: &[String]) -> PyResult<Self> {
        errors::guard(py, || {
            scenario::parse(text, source, overrides)
                .map(|inner| PyScenario { inner })
                .map_err(|e| errors::scenario_error(py, &e))
        })
    }

    /// `scenario::load` with errors as `ScenarioError`.
    pub fn load(py: Python<'_>, path: &std::path::Path, overrides: &[String]) -> PyResult<Self> {
        errors::guard(py, || {
            scenario::load(path, overrides)
                .map(|inner| PyScenario { inner })
                .map_err(|e| errors::scenario_error(py, &e))
        })
    }

    /// This scenario with more overrides (the text is parsed again, so every check runs).
    pub fn with_overrides(&self, py: Python<'_>, more: Vec<String>) -> PyResult<Self> {
        if more.is_empty() {
            return Ok(self.clone());
        }
        let mut all = self.inner.overrides.clone();
        all.extend(more);
        Self::parse(py, &self.inner.text, &self.inner.source, &all)
    }
}

#[pymethods]
impl PyScenario {
    #[new]
    #[pyo3(signature = (*, body = None, initial = None, contact = None, effects = None, solver = None, output = None, check = None, name = "<scenario>"))]
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
        name: &str,
    ) -> PyResult<Self> {
        let text = convert::document(&[
            ("body", body.as_ref()),
            ("initial", initial.as_ref()),
            ("contact", contact.as_ref()),
            ("effects", effects.as_ref()),
            ("solver", solver.as_ref()),
            ("output", output.as_ref()),
            ("check", check.as_ref()),
        ])?;
        Self::parse(py, &text, name, &[])
    }

    /// Parses a scenario from TOML text; `name` stands for the file in messages and in
    /// the summary. Keyword arguments are changes, as for `replace`.
    #[staticmethod]
    #[pyo3(signature = (text, name = "<string>", **changes))]
    fn from_toml(
        py: Python<'_>,
        text: &str,
        name: &str,
        changes: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        Self::parse(py, text, name, &convert::overrides(changes)?)
    }

    /// A copy with some values changed, like the command line's `--set key=value`:
    /// `replace(contact={"friction": 0.2})` (a dict merges into the table: only the keys
    /// given change) or `replace(**{"contact.friction": 0.2, "output.t_end": 1.0})` (dotted
    /// keys). The changed scenario is validated again; a bad value raises ScenarioError
    /// naming the override. Keys cannot be removed.
    #[pyo3(signature = (**changes))]
    fn replace(&self, py: Python<'_>, changes: Option<&Bound<'_, PyDict>>) -> PyResult<Self> {
        self.with_overrides(py, convert::overrides(changes)?)
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
        use ellipsoid_core::simulate::ContactModel;
        match self.inner.scene.contact {
            ContactModel::Frictionless => "frictionless",
            ContactModel::Sliding { .. } => "sliding",
            ContactModel::Rolling => "rolling",
            ContactModel::Coulomb { .. } => "coulomb",
        }
    }

    fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
        let source = PyString::new(py, &self.inner.source).repr()?;
        let mut s = format!("<ellipsoid.Scenario {source}");
        for o in &self.inner.overrides {
            s.push_str(&format!(" {o}"));
        }
        s.push('>');
        Ok(s)
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
    path: PathBuf,
    changes: Option<&Bound<'_, PyDict>>,
) -> PyResult<PyScenario> {
    PyScenario::load(py, &path, &convert::overrides(changes)?)
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
    match what.extract::<PathBuf>() {
        Ok(path) => PyScenario::load(py, &path, &changes),
        Err(_) => Err(pyo3::exceptions::PyTypeError::new_err(format!(
            "expected an ellipsoid.Scenario or the path of a scenario file, found {}",
            what.get_type().name()?
        ))),
    }
}
