//! The exception tree and the one place where Rust errors become Python exceptions.
//!
//! ```text
//! Exception
//! └── EllipsoidError                       every error this package raises
//!     ├── ScenarioError(…, ValueError)     bad input: file, TOML, key, value, physical rule,
//!     │   │                                and bad arguments (workers, errors=, …)
//!     │   ├── ScenarioTypeError(…, TypeError)  a Python value of a type a scenario
//!     │   │                                cannot hold, or an argument of the wrong type
//!     │   └── ScenarioKeyError(…, KeyError)    a name that is not there (a Trajectory
//!     │                                    column: `traj["nope"]`)
//!     ├── SimulationError(…, RuntimeError) Painlevé, solver failure, chattering, non-finite
//!     │                                    state; `.trajectory` holds the run up to the stop
//!     ├── OutputError(…, OSError)          a trajectory file could not be written
//!     └── InternalError(…, RuntimeError)   a bug (a Rust panic caught at the boundary)
//! ```
//! Messages are the command-line tool's, without its `error: ` prefix. Every mapping is an
//! exhaustive `match`, so a new error variant in the core or io crate fails to compile
//! here until it is given its class.

use ellipsoid_core::scenario::{ErrorKind, ScenarioError, ScenarioErrors};
use ellipsoid_io::OutputError;
use pyo3::exceptions::{
    PyException, PyKeyError, PyOSError, PyRuntimeError, PyTypeError, PyValueError,
};
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyDict, PyTuple, PyType};

/// How to get a wheel that writes HDF5.
pub const HDF5_HINT: &str = "this ellipsoid Python package was built without HDF5 support; \
reinstall it with the default features, which include it: `pip install ./crates/ellipsoid-py`, \
or write CSV with to_csv()";

/// The exception classes, created once at import.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Class {
    Ellipsoid,
    Scenario,
    ScenarioType,
    ScenarioKey,
    Simulation,
    Output,
    Internal,
}

static CLASSES: [PyOnceLock<Py<PyType>>; 7] = [const { PyOnceLock::new() }; 7];

impl Class {
    pub const ALL: [Class; 7] = [
        Class::Ellipsoid,
        Class::Scenario,
        Class::ScenarioType,
        Class::ScenarioKey,
        Class::Simulation,
        Class::Output,
        Class::Internal,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Class::Ellipsoid => "EllipsoidError",
            Class::Scenario => "ScenarioError",
            Class::ScenarioType => "ScenarioTypeError",
            Class::ScenarioKey => "ScenarioKeyError",
            Class::Simulation => "SimulationError",
            Class::Output => "OutputError",
            Class::Internal => "InternalError",
        }
    }

    fn doc(self) -> &'static str {
        match self {
            Class::Ellipsoid => "Base class of every error raised by the ellipsoid package.",
            Class::Scenario => {
                "A scenario that cannot be run: unreadable file, TOML syntax, unknown or missing key, wrong type, \
                 or a value that breaks a physical rule.\n\n\
                 The message is the command-line tool's (`file:line:col: key = value: rule`). Attributes: `kind` \
                 (io | syntax | override | unknown_key | missing | type | conflict | invalid), `key` (dotted, e.g. \
                 'body.mass', or None), `value` (as written, or None), `rule`, `source` (file or name), `line` and \
                 `column` (1-based, or None), `override` (the `key=value` override the value came from, or None), \
                 `errors` (every independent error of the scenario, in file order, each a ScenarioError; the message \
                 then has one line per error and the other attributes are the first's)."
            }
            Class::ScenarioType => {
                "A ScenarioError (and a TypeError) for a Python value of a type a scenario cannot hold (None, an \
                 object without a number or list form, a non-string key), or an argument of the wrong type. Same \
                 attributes as ScenarioError."
            }
            Class::ScenarioKey => {
                "A ScenarioError (and a KeyError) for a name that is not there: a column of a Trajectory \
                 (`traj[\"nope\"]`), so that `except KeyError` catches it as a mapping's would. Same attributes \
                 as ScenarioError."
            }
            Class::Simulation => {
                "A run that stopped on an error: a Painlevé inconsistency, a solver failure, chattering at the \
                 friction-cone boundary, or a non-finite state.\n\n\
                 Attributes: `status` (the summary's status name: painleve | inconsistent_contact | several_contacts | solver_failure | chattering | below_plane | cancelled), \
                 `trajectory` (the Trajectory up to the stop, with its summary)."
            }
            Class::Output => {
                "A trajectory file could not be written (file system, HDF5 library, or a format this build lacks)."
            }
            Class::Internal => {
                "A bug in ellipsoid (a Rust panic caught at the Python boundary); please report it with the message."
            }
        }
    }

    /// Base classes besides [`Class::Ellipsoid`].
    fn bases<'py>(self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        let base = |c: Class| c.get(py).map(|t| t.into_any());
        match self {
            Class::Ellipsoid => PyTuple::new(py, [py.get_type::<PyException>().into_any()]),
            Class::Scenario => PyTuple::new(
                py,
                [
                    base(Class::Ellipsoid)?,
                    py.get_type::<PyValueError>().into_any(),
                ],
            ),
            Class::ScenarioType => PyTuple::new(
                py,
                [
                    base(Class::Scenario)?,
                    py.get_type::<PyTypeError>().into_any(),
                ],
            ),
            Class::ScenarioKey => PyTuple::new(
                py,
                [
                    base(Class::Scenario)?,
                    py.get_type::<PyKeyError>().into_any(),
                ],
            ),
            Class::Simulation | Class::Internal => PyTuple::new(
                py,
                [
                    base(Class::Ellipsoid)?,
                    py.get_type::<PyRuntimeError>().into_any(),
                ],
            ),
            Class::Output => PyTuple::new(
                py,
                [
                    base(Class::Ellipsoid)?,
                    py.get_type::<PyOSError>().into_any(),
                ],
            ),
        }
    }

    /// The class object (created on first use, as `ellipsoid.<Name>`).
    pub fn get(self, py: Python<'_>) -> PyResult<Bound<'_, PyType>> {
        let cell = &CLASSES[self as usize];
        let ty = cell.get_or_try_init(py, || -> PyResult<Py<PyType>> {
            let ns = PyDict::new(py);
            ns.set_item("__module__", "ellipsoid")?;
            ns.set_item("__doc__", self.doc())?;
            let ty = py
                .get_type::<PyType>()
                .call1((self.name(), self.bases(py)?, ns))?;
            Ok(ty.cast_into::<PyType>()?.unbind())
        })?;
        Ok(ty.bind(py).clone())
    }

    /// An exception of this class with `message` and attributes.
    pub fn error(self, py: Python<'_>, message: &str, attrs: &[(&str, Py<PyAny>)]) -> PyErr {
        let build = || -> PyResult<PyErr> {
            let exc = self.get(py)?.call1((message,))?;
            for (k, v) in attrs {
                exc.setattr(*k, v)?;
            }
            Ok(PyErr::from_value(exc))
        };
        build().unwrap_or_else(|e| e)
    }
}

/// A scenario error, as `ellipsoid.ScenarioError` with its parts as attributes.
pub fn scenario_error(py: Python<'_>, e: &ScenarioError) -> PyErr {
    scenario_error_as(py, Class::Scenario, e)
}

/// Every independent error of a scenario as one `ellipsoid.ScenarioError`: the message
/// has one line per error, the attributes are the first error's, and `errors` lists each
/// as a ScenarioError of its own (a single error's list holds the error itself).
pub fn scenario_errors(py: Python<'_>, errs: &ScenarioErrors) -> PyErr {
    let each: Vec<PyErr> = errs.0.iter().map(|e| scenario_error(py, e)).collect();
    if each.len() == 1 {
        return each.into_iter().next().expect("one");
    }
    let first = &errs.0[0];
    let top = scenario_error_as(py, Class::Scenario, first);
    let build = || -> PyResult<PyErr> {
        let value = top.value(py);
        value.setattr("args", (python_words(&errs.to_string()),))?;
        let list = pyo3::types::PyList::new(py, each.iter().map(|e| e.value(py)))?;
        value.setattr("errors", list)?;
        Ok(PyErr::from_value(value.clone().into_any()))
    };
    build().unwrap_or_else(|e| e)
}

/// An input error found on the Python side (a value or argument that never reached the
/// parser), as `class` (ScenarioError or ScenarioTypeError) with the usual attributes.
/// `key` and `value` are cut to one short line, as the parser cuts values.
pub fn input_error(
    py: Python<'_>,
    class: Class,
    kind: ErrorKind,
    source: &str,
    key: Option<&str>,
    value: Option<&str>,
    rule: impl Into<String>,
) -> PyErr {
    let e = ScenarioError {
        kind,
        location: ellipsoid_core::scenario::Location {
            source: short(source),
            line: None,
            column: None,
            set: None,
        },
        key: key.map(short),
        value: value.map(short),
        rule: rule.into(),
    };
    scenario_error_as(py, class, &e)
}

/// `text` on one line, at most 60 characters (the parser's rule for values in messages).
pub fn short(text: &str) -> String {
    let one_line: String = text
        .chars()
        .take(200)
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect();
    if text.chars().nth(60).is_some() {
        format!("{}…", one_line.chars().take(59).collect::<String>())
    } else {
        one_line
    }
}

/// [`input_error`] for a wrong Python type: `ellipsoid.ScenarioTypeError` (also a TypeError).
pub fn type_error(
    py: Python<'_>,
    source: &str,
    key: Option<&str>,
    value: Option<&str>,
    rule: impl Into<String>,
) -> PyErr {
    input_error(
        py,
        Class::ScenarioType,
        ErrorKind::Type,
        source,
        key,
        value,
        rule,
    )
}

/// [`input_error`] for a bad value: `ellipsoid.ScenarioError`.
pub fn value_error(
    py: Python<'_>,
    source: &str,
    key: Option<&str>,
    value: Option<&str>,
    rule: impl Into<String>,
) -> PyErr {
    input_error(
        py,
        Class::Scenario,
        ErrorKind::Invalid,
        source,
        key,
        value,
        rule,
    )
}

fn scenario_error_as(py: Python<'_>, class: Class, e: &ScenarioError) -> PyErr {
    let err = scenario_error_bare(py, class, e);
    // `errors`: this error alone (replaced by the full list for several).
    let value = err.value(py);
    if let Ok(list) = pyo3::types::PyList::new(py, [value]) {
        let _ = value.setattr("errors", list);
    }
    err
}

fn scenario_error_bare(py: Python<'_>, class: Class, e: &ScenarioError) -> PyErr {
    let kind = match e.kind {
        ErrorKind::Io => "io",
        ErrorKind::Syntax => "syntax",
        ErrorKind::Override => "override",
        ErrorKind::UnknownKey => "unknown_key",
        ErrorKind::Missing => "missing",
        ErrorKind::Type => "type",
        ErrorKind::Conflict => "conflict",
        ErrorKind::Invalid => "invalid",
    };
    let loc = &e.location;
    let any = |v: Option<&str>| {
        v.into_pyobject(py)
            .map(|o| o.into_any().unbind())
            .unwrap_or_else(|_| py.None())
    };
    let num = |v: Option<usize>| {
        v.into_pyobject(py)
            .map(|o| o.into_any().unbind())
            .unwrap_or_else(|_| py.None())
    };
    let attrs = [
        ("kind", any(Some(kind))),
        ("key", any(e.key.as_deref())),
        ("value", any(e.value.as_deref())),
        ("rule", any(Some(&e.rule))),
        ("source", any(Some(&loc.source))),
        ("line", num(loc.line)),
        ("column", num(loc.column)),
        ("override", any(loc.set.as_deref())),
    ];
    class.error(py, &python_words(&e.to_string()), &attrs)
}

/// A scenario error's text in Python's terms: a change given as a keyword
/// (`replace(body={"mass": -1})`, `simulate(..., output={"t_end": 2})`) is named "the
/// change body.mass=-1", not by the command line's `--set`.
fn python_words(message: &str) -> String {
    message
        .replace(": --set ", ": the change ")
        .replace("as changed by --set ", "as changed by ")
}

/// A write failure, as `ellipsoid.OutputError`.
pub fn output_error(py: Python<'_>, e: &OutputError) -> PyErr {
    let message = match e {
        OutputError::Hdf5Unavailable { path } => format!("{}: {HDF5_HINT}", path.display()),
        OutputError::UnknownFormat { .. } | OutputError::Io { .. } | OutputError::Hdf5 { .. } => {
            e.to_string()
        }
    };
    // `err.errno`: the OS error number, or for errors that wrap one without it (the
    // temporary file's), the number of its kind. No `filename`, which would make OSError
    // rewrite the message.
    let errno = match e {
        OutputError::Io { source, .. } => source
            .raw_os_error()
            .or_else(|| errno_of(py, source.kind())),
        OutputError::UnknownFormat { .. }
        | OutputError::Hdf5Unavailable { .. }
        | OutputError::Hdf5 { .. } => None,
    };
    let errno = errno
        .into_pyobject(py)
        .map(|o| o.into_any().unbind())
        .unwrap_or_else(|_| py.None());
    Class::Output.error(py, &message, &[("errno", errno)])
}

/// The number of an I/O error kind from Python's `errno` module.
fn errno_of(py: Python<'_>, kind: std::io::ErrorKind) -> Option<i32> {
    use std::io::ErrorKind as K;
    let name = match kind {
        K::NotFound => "ENOENT",
        K::PermissionDenied => "EACCES",
        K::AlreadyExists => "EEXIST",
        K::NotADirectory => "ENOTDIR",
        K::IsADirectory => "EISDIR",
        K::ReadOnlyFilesystem => "EROFS",
        K::StorageFull => "ENOSPC",
        _ => return None,
    };
    py.import("errno")
        .and_then(|m| m.getattr(name))
        .and_then(|v| v.extract())
        .ok()
}

/// Runs `f`, turning a panic into `ellipsoid.InternalError` (pyo3 would raise its
/// `PanicException`, a BaseException that `except Exception` does not catch).
pub fn guard<T>(py: Python<'_>, f: impl FnOnce() -> PyResult<T>) -> PyResult<T> {
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)).unwrap_or_else(|p| {
        Err(internal_error(
            py,
            &ellipsoid_core::error::panic_message(&*p),
        ))
    })
}

/// A caught panic, as `ellipsoid.InternalError`.
pub fn internal_error(py: Python<'_>, msg: &str) -> PyErr {
    Class::Internal.error(py, &format!("internal error: {msg}; please report it"), &[])
}
