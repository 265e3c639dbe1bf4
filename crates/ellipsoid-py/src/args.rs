//! Arguments read by hand instead of by pyo3's extraction, so that a value of the wrong
//! type or out of range is an `ellipsoid.ScenarioTypeError` / `ScenarioError` naming the
//! argument, the value and the rule (pyo3's own would be a plain TypeError or
//! OverflowError).

use std::path::PathBuf;

use pyo3::prelude::*;
use pyo3::types::{PyBool, PyInt};

use crate::errors;

/// The name of `v`'s type, for messages.
pub fn type_name(v: &Bound<'_, PyAny>) -> String {
    v.get_type()
        .name()
        .map(|n| n.to_string())
        .unwrap_or_default()
}

/// `v` as shown in a message: its repr on one line, cut to 60 characters.
fn shown(v: &Bound<'_, PyAny>) -> String {
    let r = v
        .repr()
        .map(|r| r.to_string_lossy().into_owned())
        .unwrap_or_default();
    errors::short(&r)
}

/// Argument `key` of `source` as a path (str or os.PathLike).
pub fn path(py: Python<'_>, source: &str, key: &str, v: &Bound<'_, PyAny>) -> PyResult<PathBuf> {
    v.extract::<PathBuf>().map_err(|_| {
        errors::type_error(
            py,
            source,
            Some(key),
            None,
            format!(
                "expected a path (str or os.PathLike), found {}",
                type_name(v)
            ),
        )
    })
}

/// Argument `key` of `source` as a path, None allowed.
pub fn opt_path(
    py: Python<'_>,
    source: &str,
    key: &str,
    v: Option<&Bound<'_, PyAny>>,
) -> PyResult<Option<PathBuf>> {
    v.filter(|v| !v.is_none())
        .map(|v| path(py, source, key, v))
        .transpose()
}

/// Argument `key` of `source` as a string, None allowed.
pub fn opt_string(
    py: Python<'_>,
    source: &str,
    key: &str,
    v: Option<&Bound<'_, PyAny>>,
) -> PyResult<Option<String>> {
    v.filter(|v| !v.is_none())
        .map(|v| {
            v.extract::<String>().map_err(|_| {
                errors::type_error(
                    py,
                    source,
                    Some(key),
                    None,
                    format!("expected a str, found {}", type_name(v)),
                )
            })
        })
        .transpose()
}

/// Argument `key` of `source` as names: a comma-separated str, or a sequence of str
/// (joined with commas), None allowed.
pub fn opt_names(
    py: Python<'_>,
    source: &str,
    key: &str,
    v: Option<&Bound<'_, PyAny>>,
) -> PyResult<Option<String>> {
    v.filter(|v| !v.is_none())
        .map(|v| {
            v.extract::<String>()
                .or_else(|_| v.extract::<Vec<String>>().map(|names| names.join(",")))
                .map_err(|_| {
                    errors::type_error(
                        py,
                        source,
                        Some(key),
                        None,
                        format!(
                            "expected a str or a sequence of str, found {}",
                            type_name(v)
                        ),
                    )
                })
        })
        .transpose()
}

/// `v` as a Python int if `operator.index` takes it (an int, a numpy integer, anything
/// with `__index__`), but not a bool (Python's or numpy's): None otherwise.
pub fn as_int<'py>(v: &Bound<'py, PyAny>) -> Option<Bound<'py, PyInt>> {
    if v.is_instance_of::<PyBool>() || type_name(v) == "bool" {
        return None;
    }
    if let Ok(i) = v.cast::<PyInt>() {
        return Some(i.clone());
    }
    if !v.hasattr("__index__").unwrap_or(false) {
        return None;
    }
    let i = v
        .py()
        .import("operator")
        .ok()?
        .getattr("index")
        .ok()?
        .call1((v,))
        .ok()?;
    i.cast_into::<PyInt>().ok()
}

/// Argument `key` of `source` as an integer from 0 to `max` (anything `operator.index`
/// takes, not a bool), None allowed.
pub fn opt_count(
    py: Python<'_>,
    source: &str,
    key: &str,
    v: Option<&Bound<'_, PyAny>>,
    max: usize,
) -> PyResult<Option<usize>> {
    let Some(v) = v.filter(|v| !v.is_none()) else {
        return Ok(None);
    };
    let Some(n) = as_int(v) else {
        return Err(errors::type_error(
            py,
            source,
            Some(key),
            None,
            format!("expected an integer, found {}", type_name(v)),
        ));
    };
    match n.extract::<u64>() {
        Ok(n) if n <= max as u64 => Ok(Some(n as usize)),
        _ => Err(errors::value_error(
            py,
            source,
            Some(key),
            Some(&shown(v)),
            format!("give an integer from 0 to {max}"),
        )),
    }
}

/// Argument `key` of `source` as a finite float (an int or a float, not a bool).
pub fn number(py: Python<'_>, source: &str, key: &str, v: &Bound<'_, PyAny>) -> PyResult<f64> {
    if v.is_instance_of::<PyBool>() {
        return Err(errors::type_error(
            py,
            source,
            Some(key),
            None,
            "expected a number, found bool",
        ));
    }
    v.extract::<f64>().map_err(|_| {
        errors::type_error(
            py,
            source,
            Some(key),
            None,
            format!("expected a number, found {}", type_name(v)),
        )
    })
}
