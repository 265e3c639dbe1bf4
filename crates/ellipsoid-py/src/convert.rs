//! Python values → TOML text, so that scenarios built in Python go through the same
//! parser (and the same validation and messages) as scenario files.
//!
//! - [`document`]: `Scenario(body={...}, ...)` → a TOML document, one `[table]` per
//!   keyword, keys in the order given; `None` leaves a key out.
//! - [`overrides`]: `replace(contact={"friction": 0.2})` or `replace(**{"contact.friction":
//!   0.2})` → `contact.friction=0.2`, the command line's `--set` overrides. Nested dicts
//!   merge into the tables they name (only the keys given change).
//! - [`to_python`]: the other way, a document's value for `Scenario.get`.
//!
//! Accepted values: bool, int, float, str, dicts (tables), lists and tuples (arrays), and
//! anything with `tolist()` (numpy arrays and scalars) or `__index__` / `__float__`.
//! Every value that cannot be converted raises `ScenarioError` (`ScenarioTypeError` for a
//! wrong Python type) naming the key: nesting deeper than [`MAX_DEPTH`] (the conversion
//! recurses, and a list nested 16,000 deep used to overflow the stack), an integer beyond
//! the range of a float, a string that is not valid Unicode, an exception raised by the
//! value's own `tolist`/`__index__`/`__float__`.

use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyMapping, PyString, PyTuple};

use crate::errors;

/// Deepest nesting of lists and dicts a scenario value may have (the format's deepest
/// value, an inertia matrix inside a table, needs 3; the TOML parser's own limit is
/// higher, so a file and a Python value are refused alike only far beyond any real use).
pub const MAX_DEPTH: usize = 32;

/// Converts values for the scenario named `source` (for messages).
pub struct Conv<'a> {
    pub source: &'a str,
}

impl Conv<'_> {
    fn type_error(
        &self,
        py: Python<'_>,
        key: &str,
        value: Option<&str>,
        rule: impl Into<String>,
    ) -> PyErr {
        errors::type_error(
            py,
            self.source,
            Some(key).filter(|k| !k.is_empty()),
            value,
            rule,
        )
    }

    fn value_error(
        &self,
        py: Python<'_>,
        key: &str,
        value: Option<&str>,
        rule: impl Into<String>,
    ) -> PyErr {
        errors::value_error(
            py,
            self.source,
            Some(key).filter(|k| !k.is_empty()),
            value,
            rule,
        )
    }

    /// An exception raised by a value's own conversion method, as a ScenarioTypeError
    /// (the original as its `__cause__`).
    fn raised(&self, py: Python<'_>, key: &str, what: &str, e: PyErr) -> PyErr {
        let err = self.type_error(
            py,
            key,
            None,
            format!("{what} raised {}", errors::short(&e.to_string())),
        );
        err.set_cause(py, Some(e));
        err
    }

    /// `value` (at dotted `key`, for messages) as a TOML value.
    pub fn toml_value(&self, key: &str, value: &Bound<'_, PyAny>) -> PyResult<toml::Value> {
        self.value_at(key, value, 0)
    }

    fn value_at(&self, key: &str, value: &Bound<'_, PyAny>, depth: usize) -> PyResult<toml::Value> {
        let py = value.py();
        if depth > MAX_DEPTH {
            return Err(self.value_error(
                py,
                key,
                None,
                format!(
                    "lists and dicts nested more than {MAX_DEPTH} deep cannot be scenario values"
                ),
            ));
        }
        if let Ok(b) = value.cast::<PyBool>() {
            return Ok(toml::Value::Boolean(b.is_true()));
        }
        if let Ok(i) = value.cast::<PyInt>() {
            if let Ok(v) = i.extract::<i64>() {
                return Ok(toml::Value::Integer(v));
            }
            // Beyond i64, TOML has no integer: pass the nearest float (the parser checks
            // its range), unless it is beyond every float.
            return match i.extract::<f64>() {
                Ok(v) => Ok(toml::Value::Float(v)),
                Err(_) => {
                    let digits = i
                        .str()
                        .map(|s| s.to_string_lossy().trim_start_matches('-').len())
                        .unwrap_or(0);
                    Err(self.value_error(py, key, Some(&format!("an integer of {digits} digits")), "beyond the range of a float (about ±1.8e308); a scenario number must be finite"))
                }
            };
        }
        if let Ok(f) = value.cast::<PyFloat>() {
            return Ok(toml::Value::Float(f.value()));
        }
        if let Ok(s) = value.cast::<PyString>() {
            return Ok(toml::Value::String(self.text(key, s)?));
        }
        if value.is_none() {
            return Err(self.type_error(
                py,
                key,
                Some("None"),
                "None is not a scenario value (leave the key out instead)",
            ));
        }
        if let Ok(m) = value.cast::<PyMapping>() {
            let mut table = toml::Table::new();
            let items = m.items().map_err(|e| self.raised(py, key, "items()", e))?;
            for item in items.iter() {
                let (k, v): (Bound<'_, PyAny>, Bound<'_, PyAny>) = item
                    .extract()
                    .map_err(|e| self.raised(py, key, "items()", e))?;
                let k = self.key_str(key, &k)?;
                if v.is_none() {
                    continue;
                }
                let full = join(key, &k);
                table.insert(k, self.value_at(&full, &v, depth + 1)?);
            }
            return Ok(toml::Value::Table(table));
        }
        if value.is_instance_of::<PyList>() || value.is_instance_of::<PyTuple>() {
            let mut items = Vec::new();
            for (i, v) in value.try_iter()?.enumerate() {
                items.push(self.value_at(&format!("{key}[{i}]"), &v?, depth + 1)?);
            }
            return Ok(toml::Value::Array(items));
        }
        if value.hasattr("tolist").unwrap_or(false) {
            // numpy arrays and scalars: plain Python lists and numbers.
            let plain = value
                .call_method0("tolist")
                .map_err(|e| self.raised(py, key, "tolist()", e))?;
            if !plain.is(value) {
                return self.value_at(key, &plain, depth + 1);
            }
        }
        if value.hasattr("__index__").unwrap_or(false)
            && let Ok(i) = value.call_method0("__index__")
            && i.is_instance_of::<PyInt>()
        {
            return self.value_at(key, &i, depth + 1);
        }
        if value.hasattr("__float__").unwrap_or(false) {
            return Ok(toml::Value::Float(
                value
                    .extract::<f64>()
                    .map_err(|e| self.raised(py, key, "__float__()", e))?,
            ));
        }
        let ty = value
            .get_type()
            .name()
            .map(|n| n.to_string())
            .unwrap_or_else(|_| "?".into());
        Err(self.type_error(py, key, None, format!("a value of type {ty} cannot be put in a scenario (use numbers, strings, booleans, lists and dicts)")))
    }

    /// A Python string as UTF-8 text (a lone surrogate is not).
    fn text(&self, key: &str, s: &Bound<'_, PyString>) -> PyResult<String> {
        match s.to_str() {
            Ok(t) => Ok(t.to_owned()),
            Err(_) => {
                let shown = s.to_string_lossy();
                Err(self.value_error(
                    s.py(),
                    key,
                    Some(&format!("{shown:?}")),
                    "not valid Unicode text (it holds a lone surrogate such as '\\udc80'); scenario strings and keys must be UTF-8",
                ))
            }
        }
    }

    fn key_str(&self, parent: &str, k: &Bound<'_, PyAny>) -> PyResult<String> {
        match k.cast::<PyString>() {
            Ok(s) => self.text(&join(parent, &s.to_string_lossy()), s),
            Err(_) => {
                let shown = k
                    .repr()
                    .map(|r| r.to_string_lossy().into_owned())
                    .unwrap_or_else(|_| "?".into());
                Err(self.type_error(
                    k.py(),
                    if parent.is_empty() {
                        "scenario"
                    } else {
                        parent
                    },
                    Some(&shown),
                    "keys must be strings",
                ))
            }
        }
    }

    /// A TOML document from top-level `(name, value)` pairs: a dict becomes a `[name]` table
    /// (keys in the dict's order), anything else a top-level `name = value` (which the
    /// parser then rejects with its usual message).
    pub fn document(&self, parts: &[(&str, Option<&Bound<'_, PyAny>>)]) -> PyResult<String> {
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
                        let k = self.key_str(name, &k)?;
                        if v.is_none() {
                            continue;
                        }
                        let full = join(name, &k);
                        tables.push_str(&format!(
                            "{} = {}\n",
                            toml_key(&k),
                            self.value_at(&full, &v, 1)?
                        ));
                    }
                }
                Err(_) => head.push_str(&format!(
                    "{} = {}\n",
                    toml_key(name),
                    self.toml_value(name, value)?
                )),
            }
        }
        Ok(format!(
            "# built by ellipsoid.Scenario(...)\n{head}{tables}"
        ))
    }

    /// `key=value` overrides (the command line's `--set`) from keyword arguments: a dict value
    /// merges into the table its key names; dotted keys address nested keys directly.
    pub fn overrides(&self, changes: Option<&Bound<'_, PyDict>>) -> PyResult<Vec<String>> {
        Ok(self
            .changes(changes)?
            .iter()
            .map(|(k, v)| label(k, v))
            .collect())
    }

    /// The changes of [`Conv::overrides`] as (key path, value) pairs, to set on a scenario's
    /// document as they are.
    pub fn changes(
        &self,
        changes: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Vec<(String, toml::Value)>> {
        let mut out = Vec::new();
        if let Some(changes) = changes {
            for (k, v) in changes.iter() {
                let k = self.key_str("", &k)?;
                self.flatten(&k, &v, &mut out, 0)?;
            }
        }
        Ok(out)
    }

    fn flatten(
        &self,
        key: &str,
        value: &Bound<'_, PyAny>,
        out: &mut Vec<(String, toml::Value)>,
        depth: usize,
    ) -> PyResult<()> {
        let py = value.py();
        if value.is_none() {
            return Err(self.type_error(
                py,
                key,
                Some("None"),
                "None cannot be given as a change (a key cannot be removed by replace(); build a new ellipsoid.Scenario instead)",
            ));
        }
        if depth > MAX_DEPTH {
            return Err(self.value_error(
                py,
                key,
                None,
                format!("dicts nested more than {MAX_DEPTH} deep cannot be scenario changes"),
            ));
        }
        match value.cast::<PyDict>() {
            Ok(dict) if !dict.is_empty() => {
                for (k, v) in dict.iter() {
                    let k = self.key_str(key, &k)?;
                    self.flatten(&join(key, &k), &v, out, depth + 1)?;
                }
                Ok(())
            }
            _ => {
                out.push((key.to_owned(), self.value_at(key, value, depth)?));
                Ok(())
            }
        }
    }
}

/// [`Conv::overrides`] for the changes given with `scenario` (an `ellipsoid.Scenario`, named
/// by its source in messages, or a path).
pub fn changes_for(
    scenario: &Bound<'_, PyAny>,
    changes: Option<&Bound<'_, PyDict>>,
) -> PyResult<Vec<String>> {
    let source = match scenario.cast::<crate::scenario::PyScenario>() {
        Ok(s) => s.get().inner.source.clone(),
        Err(_) => scenario
            .str()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|_| "<changes>".into()),
    };
    Conv { source: &source }.overrides(changes)
}

/// A change as the override that names it: `key=value`, the value in TOML syntax.
pub fn label(key: &str, value: &toml::Value) -> String {
    format!("{key}={value}")
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

/// A TOML value as Python's: float, int, str, bool, list or dict (a date as its text).
/// The document it comes from was parsed with nesting bounded, so the recursion is too.
pub fn to_python(py: Python<'_>, value: &toml::Value) -> PyResult<Py<PyAny>> {
    Ok(match value {
        toml::Value::Float(f) => f.into_pyobject(py)?.into_any().unbind(),
        toml::Value::Integer(i) => i.into_pyobject(py)?.into_any().unbind(),
        toml::Value::String(s) => s.into_pyobject(py)?.into_any().unbind(),
        toml::Value::Boolean(b) => b.into_pyobject(py)?.to_owned().into_any().unbind(),
        toml::Value::Datetime(d) => d.to_string().into_pyobject(py)?.into_any().unbind(),
        toml::Value::Array(items) => {
            let items = items
                .iter()
                .map(|v| to_python(py, v))
                .collect::<PyResult<Vec<_>>>()?;
            PyList::new(py, items)?.into_any().unbind()
        }
        toml::Value::Table(table) => {
            let dict = PyDict::new(py);
            for (k, v) in table {
                dict.set_item(k, to_python(py, v)?)?;
            }
            dict.into_any().unbind()
        }
    })
}
