//! `ellipsoid.Study` and `ellipsoid._ellipsoid.make_study`: parameter studies from
//! `ellipsoid-study` (the code behind `ellipsoid study`). The orchestration —
//! `ellipsoid.study(...)`, chunks on a `concurrent.futures` executor or a Dask client, the
//! DataFrame — is Python (`python/ellipsoid/_study.py`); a chunk is `Study.run(start, stop)`,
//! one rayon sweep without the GIL.

use std::path::PathBuf;
use std::sync::Arc;

use ellipsoid_study::study::spec::{self, Naming};
use ellipsoid_study::study::{self as st, Base, Cell, ExecError, Study, Type};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyString, PyTuple};

use crate::convert::Conv;
use crate::run;
use crate::scenario::PyScenario;
use crate::{args, errors};

/// Where Python-made studies say they come from, in messages.
const SOURCE: &str = "ellipsoid.study";

/// A parameter study ready to run: a base scenario, axes over its keys, the outcomes to
/// record (docs/studies.md). Made by `Study.load(path)` from a study file, or by
/// `ellipsoid.study(base, axes, ...)`. Picklable (it travels to Dask workers as JSON).
#[pyclass(frozen, module = "ellipsoid", name = "Study")]
pub struct PyStudy {
    pub inner: Arc<Study>,
}

fn to_py(py: Python<'_>, c: &Cell) -> PyResult<Py<PyAny>> {
    Ok(match c {
        Cell::Null => py.None(),
        Cell::Int(i) => i.into_pyobject(py)?.into_any().unbind(),
        Cell::Float(f) => f.into_pyobject(py)?.into_any().unbind(),
        Cell::Text(s) => s.into_pyobject(py)?.into_any().unbind(),
    })
}

fn rows_to_py<'py>(py: Python<'py>, rows: &[Vec<Cell>]) -> PyResult<Bound<'py, PyList>> {
    let list = PyList::empty(py);
    for r in rows {
        let cells: Vec<Py<PyAny>> = r.iter().map(|c| to_py(py, c)).collect::<PyResult<_>>()?;
        list.append(PyTuple::new(py, cells)?)?;
    }
    Ok(list)
}

fn new_study(py: Python<'_>, plan: st::Plan) -> PyResult<PyStudy> {
    let study = Study::new(plan).map_err(|e| errors::scenario_errors(py, &e))?;
    Ok(PyStudy {
        inner: Arc::new(study),
    })
}

/// The base scenario from an `ellipsoid.Scenario` or a path.
fn base_of(py: Python<'_>, base: &Bound<'_, PyAny>) -> PyResult<Base> {
    if let Ok(s) = base.cast::<PyScenario>() {
        let s = &s.get().inner;
        return Ok(Base {
            text: s.text.clone(),
            source: s.source.clone(),
            overrides: s.overrides.clone(),
        });
    }
    let path: PathBuf = base.extract().map_err(|_| {
        let ty = base
            .get_type()
            .name()
            .map(|n| n.to_string())
            .unwrap_or_default();
        errors::type_error(
            py,
            SOURCE,
            Some("base"),
            None,
            format!("expected an ellipsoid.Scenario or the path of a scenario file, found {ty}"),
        )
    })?;
    // Read (and validated) exactly as `ellipsoid.load` reads it.
    let s = PyScenario::load(py, &path, &[])?.inner;
    Ok(Base {
        text: s.text,
        source: s.source,
        overrides: Vec::new(),
    })
}

/// `axes` (dotted key, or a tuple of keys → a list of values or a dict naming a generator),
/// `outcomes` and `combine` as a study document, read by the study file parser.
fn document(
    py: Python<'_>,
    axes: &Bound<'_, PyDict>,
    outcomes: Option<&Bound<'_, PyDict>>,
    combine: Option<&str>,
) -> PyResult<String> {
    let conv = Conv { source: SOURCE };
    let mut doc = toml::Table::new();
    if let Some(c) = combine {
        doc.insert("combine".into(), toml::Value::String(c.to_owned()));
    }
    let mut list = Vec::new();
    for (k, v) in axes.iter() {
        let keys: Vec<String> = if let Ok(s) = k.cast::<PyString>() {
            vec![s.to_str()?.to_owned()]
        } else if let Ok(t) = k.cast::<PyTuple>() {
            t.iter()
                .map(|x| x.extract::<String>())
                .collect::<PyResult<_>>()
                .map_err(|_| {
                    errors::type_error(
                        py,
                        SOURCE,
                        Some("axes"),
                        None,
                        "a key of axes is a dotted key (str) or a tuple of them",
                    )
                })?
        } else {
            return Err(errors::type_error(
                py,
                SOURCE,
                Some("axes"),
                None,
                "a key of axes is a dotted key (str) or a tuple of them",
            ));
        };
        if keys.is_empty() {
            return Err(errors::value_error(
                py,
                SOURCE,
                Some("axes"),
                Some("()"),
                "a tuple of keys names at least one",
            ));
        }
        let label = format!("axes[{:?}]", keys[0]);
        let mut axis = toml::Table::new();
        match v.cast::<PyDict>() {
            Ok(generator) => {
                let spec = conv.toml_value(&label, generator.as_any())?;
                let toml::Value::Table(spec) = spec else {
                    unreachable!("a dict")
                };
                if spec.contains_key("latin_hypercube") {
                    axis.insert(
                        "keys".into(),
                        keys.iter()
                            .cloned()
                            .map(toml::Value::String)
                            .collect::<Vec<_>>()
                            .into(),
                    );
                } else {
                    axis.insert("key".into(), keys[0].clone().into());
                    if keys.len() > 1 {
                        axis.insert(
                            "also".into(),
                            keys[1..]
                                .iter()
                                .cloned()
                                .map(toml::Value::String)
                                .collect::<Vec<_>>()
                                .into(),
                        );
                    }
                }
                axis.extend(spec);
            }
            Err(_) => {
                axis.insert("key".into(), keys[0].clone().into());
                if keys.len() > 1 {
                    axis.insert(
                        "also".into(),
                        keys[1..]
                            .iter()
                            .cloned()
                            .map(toml::Value::String)
                            .collect::<Vec<_>>()
                            .into(),
                    );
                }
                let values = conv.toml_value(&label, &v)?;
                if !values.is_array() {
                    return Err(errors::type_error(
                        py,
                        SOURCE,
                        Some(&label),
                        None,
                        "expected a list of values, or a dict naming a generator: {\"linspace\": [start, stop, n]}, {\"logspace\": [...]}, {\"random\": {\"low\": ..., \"high\": ..., \"n\": ..., \"seed\": ...}}, {\"latin_hypercube\": {...}}",
                    ));
                }
                axis.insert("values".into(), values);
            }
        }
        list.push(toml::Value::Table(axis));
    }
    doc.insert("axis".into(), toml::Value::Array(list));
    if let Some(o) = outcomes {
        doc.insert("outcomes".into(), conv.toml_value("outcomes", o.as_any())?);
    }
    toml::to_string(&doc).map_err(|e| errors::internal_error(py, &e.to_string()))
}

/// Makes a study from Python arguments (used by `ellipsoid.study`): `base` a Scenario or
/// path; `axes` a dict from dotted keys (or tuples of keys set to the same value) to value
/// lists or generator dicts; `outcomes` a dict of the `[outcomes]` table; `combine` "grid"
/// (default, the last key varying fastest) or "zip".
#[pyfunction]
#[pyo3(signature = (base, axes, outcomes = None, combine = None))]
pub fn make_study(
    py: Python<'_>,
    base: &Bound<'_, PyAny>,
    axes: &Bound<'_, PyAny>,
    outcomes: Option<&Bound<'_, PyAny>>,
    combine: Option<&Bound<'_, PyAny>>,
) -> PyResult<PyStudy> {
    errors::guard(py, || {
        let base = base_of(py, base)?;
        let axes = axes.cast::<PyDict>().map_err(|_| {
            errors::type_error(
                py,
                SOURCE,
                Some("axes"),
                None,
                "expected a dict from dotted keys to value lists (or an ellipsoid.Study)",
            )
        })?;
        let outcomes = match outcomes.filter(|o| !o.is_none()) {
            None => None,
            Some(o) => Some(
                o.cast::<PyDict>()
                    .map_err(|_| {
                        errors::type_error(
                            py,
                            SOURCE,
                            Some("outcomes"),
                            None,
                            "expected a dict (the [outcomes] table of docs/studies.md) or None",
                        )
                    })?
                    .clone(),
            ),
        };
        let combine = match combine.filter(|c| !c.is_none()) {
            None => None,
            Some(c) => Some(c.extract::<String>().map_err(|_| {
                errors::type_error(
                    py,
                    SOURCE,
                    Some("combine"),
                    None,
                    "expected \"grid\" or \"zip\"",
                )
            })?),
        };
        let text = document(py, axes, outcomes.as_ref(), combine.as_deref())?;
        let plan = spec::parse(&text, SOURCE, None, Some(base), Naming::Python)
            .map_err(|e| errors::scenario_errors(py, &e))?;
        new_study(py, plan)
    })
}

#[pymethods]
impl PyStudy {
    /// Reads a study file (docs/studies.md); its `base` path is relative to the file.
    #[staticmethod]
    fn load(py: Python<'_>, path: &Bound<'_, PyAny>) -> PyResult<PyStudy> {
        let path = args::path(py, SOURCE, "path", path)?;
        errors::guard(py, || {
            let plan = spec::load(&path).map_err(|e| errors::scenario_errors(py, &e))?;
            new_study(py, plan)
        })
    }

    /// The study as JSON (what pickling sends to workers).
    fn to_json(&self, py: Python<'_>) -> PyResult<String> {
        serde_json::to_string(&self.inner.plan)
            .map_err(|e| errors::internal_error(py, &e.to_string()))
    }

    /// A study from `to_json()`'s text.
    #[staticmethod]
    fn from_json(py: Python<'_>, text: &Bound<'_, PyAny>) -> PyResult<PyStudy> {
        let text = args::opt_string(py, SOURCE, "text", Some(text))?.unwrap_or_default();
        let plan: st::Plan = serde_json::from_str(&text).map_err(|e| {
            errors::value_error(
                py,
                SOURCE,
                Some("study"),
                None,
                format!("not a study's JSON: {e}"),
            )
        })?;
        new_study(py, plan)
    }

    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<(Bound<'py, PyAny>, (String,))> {
        let from_json = slf.get_type().getattr("from_json")?;
        Ok((from_json, (slf.get().to_json(slf.py())?,)))
    }

    /// This study with another base scenario and/or outcomes (None keeps them).
    #[pyo3(signature = (base = None, outcomes = None))]
    fn replace(
        &self,
        py: Python<'_>,
        base: Option<&Bound<'_, PyAny>>,
        outcomes: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<PyStudy> {
        let mut plan = self.inner.plan.clone();
        if let Some(b) = base.filter(|b| !b.is_none()) {
            plan.base = base_of(py, b)?;
        }
        if let Some(o) = outcomes.filter(|o| !o.is_none()) {
            let dict = o.cast::<PyDict>().map_err(|_| {
                errors::type_error(py, SOURCE, Some("outcomes"), None, "expected a dict")
            })?;
            let text = document(py, &PyDict::new(py), Some(dict), None)?;
            plan.outcomes =
                spec::parse(&text, SOURCE, None, Some(plan.base.clone()), Naming::Python)
                    .map_err(|e| errors::scenario_errors(py, &e))?
                    .outcomes;
        }
        new_study(py, plan)
    }

    fn __len__(&self) -> usize {
        self.inner.len()
    }

    fn __repr__(&self) -> String {
        format!(
            "<ellipsoid.Study {} ({} points, {} columns)>",
            self.inner.plan.source,
            self.inner.len(),
            self.inner.columns.len()
        )
    }

    /// The study file, or "ellipsoid.study".
    #[getter]
    fn source(&self) -> &str {
        &self.inner.plan.source
    }

    /// Column headers of the table, `name [unit]` (as in the files).
    #[getter]
    fn columns(&self) -> Vec<String> {
        self.inner.columns.iter().map(|c| c.header()).collect()
    }

    /// Each column's type: "int", "float" or "text".
    #[getter]
    fn types(&self) -> Vec<&'static str> {
        self.inner
            .columns
            .iter()
            .map(|c| match c.ty {
                Type::Int => "int",
                Type::Float => "float",
                Type::Text => "text",
            })
            .collect()
    }

    /// Whether each column may hold no value (None) in some rows.
    #[getter]
    fn nullable(&self) -> Vec<bool> {
        self.inner.columns.iter().map(|c| c.nullable).collect()
    }

    /// Header → SI unit (None for names and counts).
    #[getter]
    fn units<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for c in &self.inner.columns {
            d.set_item(c.header(), c.unit.as_deref())?;
        }
        Ok(d)
    }

    /// The `key=value` overrides and key of point `index` (what it runs).
    fn point<'py>(
        &self,
        py: Python<'py>,
        index: &Bound<'py, PyAny>,
    ) -> PyResult<(Vec<String>, String)> {
        let index = args::opt_count(py, SOURCE, "index", Some(index), usize::MAX)?.unwrap_or(0);
        if index >= self.inner.len() {
            return Err(errors::value_error(
                py,
                SOURCE,
                Some("index"),
                Some(&index.to_string()),
                format!("points are 0 to {}", self.inner.len().saturating_sub(1)),
            ));
        }
        let r = self
            .inner
            .resolve(index)
            .map_err(|(k, rule)| errors::value_error(py, SOURCE, Some(&k), None, rule))?;
        Ok((r.draft.overrides, r.key))
    }

    /// Issues the study's plausibility warnings (each distinct one once, as
    /// `ellipsoid study` prints them: `Study::warnings` of ellipsoid-study) as
    /// `ellipsoid.PlausibilityWarning`, attributed to the line that called
    /// `ellipsoid.study`, which calls it before running.
    fn _warn_plausibility(&self, py: Python<'_>) -> PyResult<()> {
        crate::plausible::issue(py, self.inner.warnings(), 2)
    }

    /// Runs points `start` to `stop` (exclusive) on `threads` threads (0 or None: one per
    /// CPU), without the GIL, and returns their rows (tuples in column order, None where
    /// there is no value), in point order. With `journal` (a path), rows already in it are
    /// not run again, and each finished row is appended (a killed study resumes). Ctrl-C
    /// stops the runs at their next step and raises KeyboardInterrupt.
    #[pyo3(signature = (start = None, stop = None, threads = None, journal = None))]
    #[pyo3(text_signature = "(self, /, start=0, stop=None, threads=None, journal=None)")]
    fn run<'py>(
        &self,
        py: Python<'py>,
        start: Option<&Bound<'py, PyAny>>,
        stop: Option<&Bound<'py, PyAny>>,
        threads: Option<&Bound<'py, PyAny>>,
        journal: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyList>> {
        let n = self.inner.len();
        let start = args::opt_count(py, SOURCE, "start", start, usize::MAX)?.unwrap_or(0);
        let stop = args::opt_count(py, SOURCE, "stop", stop, usize::MAX)?
            .unwrap_or(n)
            .min(n);
        let journal = args::opt_path(py, SOURCE, "journal", journal)?;
        if start > stop {
            return Err(errors::value_error(
                py,
                SOURCE,
                Some("start"),
                Some(&start.to_string()),
                format!("start must be at most stop ({stop})"),
            ));
        }
        let max = crate::api::max_workers();
        let threads = args::opt_count(py, SOURCE, "threads", threads, max)?.unwrap_or(0);
        let study = Arc::clone(&self.inner);
        let (result, interrupt) = run::detached(py, move |cancel| {
            if journal.is_none() && start == 0 && stop == n {
                st::execute(&study, None, threads, cancel, |_| {}).map(|r| study.rows(r))
            } else if let Some(j) = journal {
                // A journal covers the whole study; only [start, stop) is returned.
                let sub = st::execute(&study, Some(&j), threads, cancel, |_| {})?;
                Ok(study.rows(
                    sub.into_iter()
                        .filter(|r| (start..stop).contains(&r.index))
                        .collect(),
                ))
            } else {
                let indices: Vec<usize> = (start..stop).collect();
                let mut out = Vec::with_capacity(indices.len());
                study
                    .run_many(&indices, threads, cancel, |r| out.push(r))
                    .map_err(ExecError::Internal)?;
                if out.len() < indices.len() {
                    return Err(ExecError::Interrupted {
                        done: out.len(),
                        total: indices.len(),
                    });
                }
                Ok(study.rows(out))
            }
        })?;
        if let Some(e) = interrupt {
            return Err(e);
        }
        match result {
            Ok(rows) => rows_to_py(py, &rows),
            Err(ExecError::Journal(e)) => Err(errors::output_error(
                py,
                &ellipsoid_io::OutputError::Io {
                    path: PathBuf::from("journal"),
                    source: std::io::Error::other(e.to_string()),
                },
            )),
            Err(ExecError::Interrupted { .. }) => Err(
                pyo3::exceptions::PyKeyboardInterrupt::new_err("the study was interrupted"),
            ),
            Err(ExecError::Internal(msg)) => Err(errors::internal_error(py, &msg)),
            // Python asks for no trajectories.
            Err(e @ (ExecError::Resumed { .. } | ExecError::Trajectories(_))) => {
                Err(errors::internal_error(py, &e.to_string()))
            }
        }
    }

    /// Writes `rows` (from `run`) as the table at `path`: .csv, .parquet (if built in) or
    /// .h5, atomically — the files `ellipsoid study -o` writes.
    fn write(
        &self,
        py: Python<'_>,
        path: &Bound<'_, PyAny>,
        rows: &Bound<'_, PyAny>,
    ) -> PyResult<()> {
        let path = args::path(py, SOURCE, "path", path)?;
        let cols = &self.inner.columns;
        let not_rows = || {
            errors::type_error(
                py,
                SOURCE,
                Some("rows"),
                None,
                "expected the list of tuples that run() returns",
            )
        };
        let rows = rows.cast::<PyList>().map_err(|_| not_rows())?;
        let mut table = Vec::with_capacity(rows.len());
        for r in rows.iter() {
            let t = r.cast::<PyTuple>().map_err(|_| not_rows())?;
            if t.len() != cols.len() {
                return Err(errors::value_error(
                    py,
                    SOURCE,
                    Some("rows"),
                    None,
                    format!("each row has {} cells", cols.len()),
                ));
            }
            let mut row = Vec::with_capacity(cols.len());
            for (c, v) in cols.iter().zip(t.iter()) {
                row.push(if v.is_none() {
                    Cell::Null
                } else {
                    match c.ty {
                        Type::Int => Cell::Int(v.extract().map_err(|_| not_rows())?),
                        Type::Float => Cell::Float(v.extract().map_err(|_| not_rows())?),
                        Type::Text => Cell::Text(v.extract().map_err(|_| not_rows())?),
                    }
                });
            }
            table.push(row);
        }
        let source = self.inner.plan.source.clone();
        let cols = cols.clone();
        py.detach(|| ellipsoid_study::study::table::write(&path, &cols, &table, &source))
            .map_err(|e| errors::output_error(py, &e))
    }

    /// Writes `data`, a table another library made (pandas' Parquet), at `path` as the
    /// study's own tables are written: atomically (a temporary beside it, renamed into
    /// place), refusing a symbolic link, directory or device there.
    fn write_bytes(
        &self,
        py: Python<'_>,
        path: &Bound<'_, PyAny>,
        data: &Bound<'_, PyAny>,
    ) -> PyResult<()> {
        let path = args::path(py, SOURCE, "path", path)?;
        let data: Vec<u8> = data
            .cast::<pyo3::types::PyBytes>()
            .map_err(|_| errors::type_error(py, SOURCE, Some("data"), None, "expected bytes"))?
            .as_bytes()
            .to_vec();
        py.detach(|| ellipsoid_io::atomic::write(&path, &data))
            .map_err(|e| errors::output_error(py, &e))
    }
}

/// `ellipsoid.study`'s `workers`, checked as `sweep`'s are: None (0: one per CPU) or 1 to
/// 4 per CPU (at least 8); anything else a ScenarioError or ScenarioTypeError.
#[pyfunction]
#[pyo3(name = "_study_workers", signature = (workers = None))]
pub fn study_workers(py: Python<'_>, workers: Option<&Bound<'_, PyAny>>) -> PyResult<usize> {
    Ok(crate::api::worker_count(py, "study", workers)?.unwrap_or(0))
}

/// The exception for a bad argument checked in Python (of `ellipsoid.study`, or of the
/// function `source` names): a ScenarioError (a ScenarioTypeError if `wrong_type`) naming
/// `key`, `value` and `rule`, as every input error of the package is.
#[pyfunction]
#[pyo3(name = "_argument_error", signature = (key, value, rule, wrong_type = false, source = "study"))]
pub fn argument_error(
    py: Python<'_>,
    key: &str,
    value: Option<&str>,
    rule: &str,
    wrong_type: bool,
    source: &str,
) -> Py<PyAny> {
    let make = if wrong_type {
        errors::type_error
    } else {
        errors::value_error
    };
    make(py, source, Some(key), value, rule)
        .into_value(py)
        .into_any()
}
