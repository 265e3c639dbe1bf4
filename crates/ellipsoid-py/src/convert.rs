//! Python values → TOML text, so that scenarios built in Python go through the same
//! parser (and the same validation and messages) as scenario files.
//!
//! - [`document`]: `Scenario(body={...}, ...)` → a TOML document, one `[table]` per
//!   keyword, keys in the order given; `None` leaves a key out.
//! - [`overrides`]: `replace(contact={"friction": 0.2})` or `replace(**{"contact.friction":
//!   0.2})` → `contact.friction=0.2`, the command line's `--set` overrides. Nested dicts
//!   merge into the tables they name (only the keys given change).
//!
//! Accepted values: bool, int, float, str, dicts (tables), lists and tuples (arrays), and
//! anything with `tolist()` (numpy arrays and scalars) or `__index__` / `__float__`.

use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyMapping, PyString, PyTuple};

/// `value` (at dotted `key`, for messages) as a TOML value.
pub fn toml_value(key: &str, value: &Bound<'_, PyAny>) -> PyResult<toml::Value> {
    if let Ok(b) = value.cast::<PyBool>() {
        return Ok(toml::Value::Boolean(b.is_true()));
    }
    if let Ok(i) = value.cast::<PyInt>() {
        // Beyond i64, TOML has no integer: pass the nearest float (the parser checks it).
        return Ok(match i.extract::<i64>() {
            Ok(v) => toml::Value::Integer(v),
            Err(_) => toml::Value::Float(i.extract::<f64>()?),
        });
    }
    if let Ok(f) = value.cast::<PyFloat>() {
        return Ok(toml::Value::Float(f.value()));
    }
    if let Ok(s) = value.cast::<PyString>() {
        return Ok(toml::Value::String(s.to_str()?.to_owned()));
    }
    if value.is_none() {
        return Err(PyTypeError::new_err(format!(
            "{key}: None is not a scenario value (leave the key out instead)"
        )));
    }
    if let Ok(m) = value.cast::<PyMapping>() {
        let mut table = toml::Table::new();
        for item in m.items()?.iter() {
            let (k, v): (Bound<'_, PyAny>, Bound<'_, PyAny>) = item.extract()?;
            let k = key_str(key, &k)?;
            if v.is_none() {
                continue;
            }
            let full = join(key, &k);
            table.insert(k, toml_value(&full, &v)?);
        }
        return Ok(toml::Value::Table(table));
    }
    if value.is_instance_of::<PyList>() || value.is_instance_of::<PyTuple>() {
        let mut items = Vec::new();
        for (i, v) in value.try_iter()?.enumerate() {
            items.push(toml_value(&format!("{key}[{i}]"), &v?)?);
        }
        return Ok(toml::Value::Array(items));
    }
    if value.hasattr("tolist")? {
        // numpy arrays and scalars: plain Python lists and numbers.
        let plain = value.call_method0("tolist")?;
        if !plain.is(value) {
            return toml_value(key, &plain);
        }
    }
    if value.hasattr("__index__")?
        && let Ok(i) = value.call_method0("__index__")
    {
        return toml_value(key, &i);
    }
    if value.hasattr("__float__")? {
        return Ok(toml::Value::Float(value.extract::<f64>()?));
    }
    let ty = value.get_type().name()?;
    Err(PyTypeError::new_err(format!(
        "{key}: a value of type {ty} cannot be put in a scenario (use numbers, strings, booleans, lists and dicts)"
    )))
}

fn key_str(parent: &str, k: &Bound<'_, PyAny>) -> PyResult<String> {
    match k.cast::<PyString>() {
        Ok(s) => Ok(s.to_str()?.to_owned()),
        Err(_) => Err(PyTypeError::new_err(format!(
            "{}: keys must be strings, found {}",
            if parent.is_empty() {
                "scenario"
            } else {
                parent
            },
            k.repr()?
        ))),
    }
}

fn join(prefix: &str, key: &str) -> String {
    if prefix.is_empty() {
        key.to_owned()
    } else {
        format!("{prefix}.{key}")
    }
}

/// A key as TOML writes it: bare when it can be, else quoted.
fn toml_key(key: &str) -> String {
    if !key.is_empty()
        && key
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
    {
        key.to_owned()
    } else {
        toml::Value::String(key.to_owned()).to_string()
    }
}

/// A TOML document from top-level `(name, value)` pairs: a dict becomes a `[name]` table
/// (keys in the dict's order), anything else a top-level `name = value` (which the
/// parser then rejects with its usual message).
pub fn document(parts: &[(&str, Option<&Bound<'_, PyAny>>)]) -> PyResult<String> {
    let mut head = String::new();
    let mut tables = String::new();
    for (name, value) in parts {
        let Some(value) = value.filter(|v| !v.is_none()) else {
            continue;
        };
        match value.cast::<PyDict>() {
            Ok(dict) => {
                tables.push_str(&format!("\n[{}]\n", toml_key(name)));
                for (k, v) in dict.iter() {
                    let k = key_str(name, &k)?;
                    if v.is_none() {
                        continue;
                    }
                    let full = join(name, &k);
                    tables.push_str(&format!("{} = {}\n", toml_key(&k), toml_value(&full, &v)?));
                }
            }
            Err(_) => head.push_str(&format!(
                "{} = {}\n",
                toml_key(name),
                toml_value(name, value)?
            )),
        }
    }
    Ok(format!(
        "# built by ellipsoid.Scenario(...)\n{head}{tables}"
    ))
}

/// `key=value` overrides (the command line's `--set`) from keyword arguments: a dict value
/// merges into the table its key names; dotted keys address nested keys directly.
pub fn overrides(changes: Option<&Bound<'_, PyDict>>) -> PyResult<Vec<String>> {
    let mut out = Vec::new();
    if let Some(changes) = changes {
        for (k, v) in changes.iter() {
            let k = key_str("", &k)?;
            flatten(&k, &v, &mut out)?;
        }
    }
    Ok(out)
}

fn flatten(key: &str, value: &Bound<'_, PyAny>, out: &mut Vec<String>) -> PyResult<()> {
    if value.is_none() {
        return Err(PyTypeError::new_err(format!(
            "{key}: None cannot be given as a change (a key cannot be removed by replace(); build a new ellipsoid.Scenario instead)"
        )));
    }
    match value.cast::<PyDict>() {
        Ok(dict) if !dict.is_empty() => {
            for (k, v) in dict.iter() {
                let k = key_str(key, &k)?;
                flatten(&join(key, &k), &v, out)?;
            }
            Ok(())
        }
        _ => {
            out.push(format!("{key}={}", toml_value(key, value)?));
            Ok(())
        }
    }
}
