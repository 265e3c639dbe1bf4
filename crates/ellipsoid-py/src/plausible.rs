//! Plausibility warnings (`ellipsoid_core::scenario::plausibility`: valid values that are
//! likely unit slips) as Python warnings of the category `ellipsoid.PlausibilityWarning`,
//! a `UserWarning`, so that `warnings.filterwarnings("ignore",
//! category=ellipsoid.PlausibilityWarning)` silences them and `"error"` makes them raise.
//! The messages are the command-line tool's lines.

use std::ffi::CString;

use ellipsoid_core::scenario::{Scenario, warnings};
use pyo3::exceptions::PyUserWarning;
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyDict, PyTuple, PyType};

/// The name of the category in the `ellipsoid` module.
pub const NAME: &str = "PlausibilityWarning";

const DOC: &str = "A scenario value that is valid but likely a unit slip: an angle beyond 2π in a radian key \
(degrees?), a density outside 10 to 3e4 kg/m³ (grams? centimetres?), an initial spin energy above 100 m g L \
(rpm?). A UserWarning: silence it with warnings.filterwarnings(\"ignore\", category=ellipsoid.PlausibilityWarning). \
The message is the command-line tool's line (`file:line:col: warning: key = value: slip`); \
docs/scenarios.md, \"Plausibility warnings\".";

static CLASS: PyOnceLock<Py<PyType>> = PyOnceLock::new();

/// The category (created on first use, as `ellipsoid.PlausibilityWarning`).
pub fn class(py: Python<'_>) -> PyResult<Bound<'_, PyType>> {
    let ty = CLASS.get_or_try_init(py, || -> PyResult<Py<PyType>> {
        let ns = PyDict::new(py);
        ns.set_item("__module__", "ellipsoid")?;
        ns.set_item("__doc__", DOC)?;
        let bases = PyTuple::new(py, [py.get_type::<PyUserWarning>()])?;
        let ty = py.get_type::<PyType>().call1((NAME, bases, ns))?;
        Ok(ty.cast_into::<PyType>()?.unbind())
    })?;
    Ok(ty.bind(py).clone())
}

/// Issues each plausibility warning of `scenario`, attributed to the Python line that
/// called into the package. Errs only when a filter turns the warning into an error.
pub fn warn(py: Python<'_>, scenario: &Scenario) -> PyResult<()> {
    issue(py, warnings(scenario).iter().map(ToString::to_string), 1)
}

/// Issues each of `lines` (warnings' texts) as a [`NAME`] warning, attributed to the
/// Python frame `stacklevel` up (1: the caller of this function; 2 when that caller is
/// the package's own Python, so that the user's line is named). Errs only when a filter
/// makes it an error.
pub fn issue(
    py: Python<'_>,
    lines: impl IntoIterator<Item = String>,
    stacklevel: i32,
) -> PyResult<()> {
    let mut lines = lines.into_iter().peekable();
    if lines.peek().is_none() {
        return Ok(());
    }
    let category = class(py)?;
    for line in lines {
        let text = CString::new(line.replace('\0', " ")).expect("no NUL left");
        PyErr::warn(py, category.as_any(), &text, stacklevel)?;
    }
    Ok(())
}
