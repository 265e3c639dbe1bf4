//! A study as data ([`Plan`]: base scenario, common changes, axes, outcomes), and the
//! same study made ready to run ([`Study`]): the base document, the key paths, the
//! columns of its table, and each point resolved to the scenario it runs.
//!
//! A point's scenario is the base document (parsed once, with the study's `set` changes)
//! with the point's axis values set on it as typed values, each named by the `--set`
//! override that would make it (so a bad value is reported exactly as `ellipsoid run
//! --set` reports it), and its **key** is a hash of the fully resolved document written
//! out by the `toml` crate in its canonical form. Two points that run the same scenario
//! have the same key, whatever the study file looks like; a point whose scenario changed
//! gets a new one.

#![allow(clippy::result_large_err)] // errors of a whole study, made once, off the hot path

use std::fmt::Write as _;
use std::hash::Hasher;

use ellipsoid_core::columns::Layout;
use ellipsoid_core::invariants::Invariant;
pub use ellipsoid_core::scenario::KEY_RULE;
use ellipsoid_core::scenario::{
    self, Draft, ErrorKind, KeyPath, Location, Scenario, ScenarioError, ScenarioErrors, Seg,
    SetError,
};
use serde::{Deserialize, Serialize};
use siphasher::sip128::{Hasher128, SipHasher13};

/// Most points a study may have (10⁷: a table of that many rows is already gigabytes).
pub const MAX_POINTS: usize = 10_000_000;
/// Most axes (and most keys of one Latin hypercube).
pub const MAX_AXES: usize = 32;
/// Most `also` keys of one axis, and most columns named in one outcome list.
pub const MAX_KEYS: usize = 64;

/// The base scenario: its TOML text, where it came from, and overrides already applied
/// to it (a Python `Scenario` made by `replace`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Base {
    pub text: String,
    pub source: String,
    pub overrides: Vec<String>,
}

/// How the axes combine into points.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Combine {
    /// Every combination, in row-major order: the last axis varies fastest.
    Grid,
    /// Point i takes the i-th value of every axis (all axes as long as each other).
    Zip,
}

/// The values of one key along an axis.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum Values {
    /// Generated numbers (linspace, logspace, random, Latin hypercube).
    Floats(Vec<f64>),
    /// Values given one by one (`values = [...]`): numbers, strings, arrays, tables.
    Given(Vec<toml::Value>),
}

impl Values {
    pub fn len(&self) -> usize {
        match self {
            Values::Floats(v) => v.len(),
            Values::Given(v) => v.len(),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    fn get(&self, i: usize) -> toml::Value {
        match self {
            Values::Floats(v) => toml::Value::Float(v[i]),
            Values::Given(v) => v[i].clone(),
        }
    }

    /// Whether the table column is numeric (every value a number).
    fn numeric(&self) -> bool {
        match self {
            Values::Floats(_) => true,
            Values::Given(v) => v
                .iter()
                .all(|x| matches!(x, toml::Value::Float(_) | toml::Value::Integer(_))),
        }
    }
}

/// One key an axis sets (and others that take the same value, `also`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Dim {
    /// Dotted path into the scenario, with `[i]` for array elements (`body.inertia[0]`).
    pub key: String,
    pub also: Vec<String>,
    pub values: Values,
}

/// One axis: a key with its values, or several keys moving together (a Latin hypercube).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Axis {
    pub dims: Vec<Dim>,
}

impl Axis {
    pub fn len(&self) -> usize {
        self.dims.first().map_or(0, |d| d.values.len())
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// What each row records besides the axis values, status, message and end time.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Outcomes {
    /// The first crossing time of each of the scenario's observables (`t_NAME [s]`).
    pub observables: bool,
    /// Output columns whose value at the end of the run is recorded (`final.COLUMN`).
    #[serde(rename = "final")]
    pub final_columns: Vec<String>,
    /// Output columns whose smallest / largest sampled value is recorded.
    pub min: Vec<String>,
    pub max: Vec<String>,
    /// Each invariant's largest relative drift (`drift.NAME [1]`; empty where not conserved).
    pub drift: bool,
    /// The run's wall-clock time (`wall_time [s]`).
    pub wall_time: bool,
    /// Right-hand-side evaluations of the integrator (`rhs_evals`).
    pub rhs_evals: bool,
}

impl Default for Outcomes {
    fn default() -> Self {
        Outcomes {
            observables: true,
            final_columns: Vec::new(),
            min: Vec::new(),
            max: Vec::new(),
            drift: true,
            wall_time: true,
            rhs_evals: true,
        }
    }
}

/// A study: everything needed to run it anywhere (it travels to Dask workers as JSON).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Plan {
    /// The study file, or a name for a study given otherwise.
    pub source: String,
    pub base: Base,
    /// Changes applied to the base for every point (dotted key → value).
    pub set: Vec<(String, toml::Value)>,
    pub axes: Vec<Axis>,
    pub combine: Combine,
    pub outcomes: Outcomes,
    /// Where the parts were written in the study file, for messages (empty for a study
    /// made otherwise; not sent to workers).
    #[serde(skip)]
    pub places: Places,
}

/// (line, column) in the study file of its parts, by label: `base`, `combine` (or the
/// axis array, for the grid), `set.KEY`, `axis[I]`, `axis[I].key` (`key` or `keys`),
/// `axis[I].also`, `outcomes.NAME`.
#[derive(Debug, Clone, Default)]
pub struct Places(pub std::collections::HashMap<String, (usize, usize)>);

/// Any two compare equal: where a study was written is not part of what it runs (a plan
/// sent to a worker as JSON, without its places, is the same plan).
impl PartialEq for Places {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

impl Places {
    /// `e` placed at the part `label`, if it was written in the file: the study file's
    /// name, line and column.
    fn locate(&self, source: &str, label: &str, mut e: ScenarioError) -> ScenarioError {
        if let Some(&(line, column)) = self.0.get(label) {
            e.location = Location {
                source: source.to_owned(),
                line: Some(line),
                column: Some(column),
                set: None,
            };
        }
        e
    }
}

/// The type of a table column.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Type {
    Int,
    Float,
    Text,
}

/// Where a column's values come from.
#[derive(Debug, Clone, PartialEq)]
pub enum Role {
    Point,
    Axis {
        axis: usize,
        dim: usize,
    },
    Status,
    Message,
    TFinal,
    Observed(String),
    /// The final value of a numeric output column: its index among the base scenario's
    /// `Layout::numeric_columns` (the per-surface columns of a body with spheres after the
    /// fixed ones); a point whose body lacks the column gets no value.
    Final(usize),
    FinalMode,
    /// The smallest or largest sampled value of a numeric output column (as `Final`).
    Min(usize),
    Max(usize),
    Drift(Invariant),
    WallTime,
    RhsEvals,
    Key,
}

/// A column of the study's table.
#[derive(Debug, Clone, PartialEq)]
pub struct Column {
    /// The name without its unit (`t_inverted`, `body.com_offset`).
    pub name: String,
    /// SI unit ("1" for dimensionless numbers), `None` for names and counts.
    pub unit: Option<String>,
    pub ty: Type,
    /// Whether some rows may have no value (a run that failed, or never got there).
    pub nullable: bool,
    pub role: Role,
}

impl Column {
    /// The header: `name [unit]`, or the name alone.
    pub fn header(&self) -> String {
        match &self.unit {
            Some(u) => format!("{} [{u}]", self.name),
            None => self.name.clone(),
        }
    }
}

/// A table cell.
#[derive(Debug, Clone, PartialEq)]
pub enum Cell {
    Null,
    Int(i64),
    Float(f64),
    Text(String),
}

/// A study's key path: the scenario's grammar ([`KEY_RULE`]), at most 200 characters.
pub(crate) fn parse_path(text: &str) -> Result<KeyPath, String> {
    if text.is_empty() || text.len() > 200 {
        return Err(format!("{KEY_RULE}; at most 200 characters"));
    }
    KeyPath::parse(text).map_err(|e| e.to_string())
}

/// Why a value cannot be set at `path` of the base scenario, in the study's words: the
/// slot named by the last name before the segment that does not fit (and its indexes).
fn blocked_rule(path: &KeyPath, e: &SetError) -> String {
    let before = &path.segs()[..e.depth];
    let start = before
        .iter()
        .rposition(|s| matches!(s, Seg::Name(_)))
        .unwrap_or(0);
    let head = path.prefix(start);
    let slot = path.prefix(e.depth);
    let at = slot[head.len()..].trim_start_matches('.');
    match e.blocked {
        scenario::Blocked::NotTable => format!("{at} is not a table in the base scenario"),
        scenario::Blocked::NotArray => format!("{at} is not an array in the base scenario"),
        scenario::Blocked::OutOfRange { len } => {
            let index = match path.segs().get(e.depth) {
                Some(Seg::Index(i)) => *i,
                _ => 0,
            };
            format!("{at} has {len} elements in the base scenario; index {index} is out of range")
        }
    }
}

/// A value as the right-hand side of a `--set` override (TOML; floats in the shortest
/// form that reads back exactly).
pub fn value_text(v: &toml::Value) -> String {
    match v {
        toml::Value::Float(f) => format!("{f:e}"),
        toml::Value::Integer(i) => i.to_string(),
        other => other.to_string(),
    }
}

/// A study ready to run: the plan, its base document, parsed keys and columns.
#[derive(Debug, Clone)]
pub struct Study {
    pub plan: Plan,
    /// The base with its overrides and the `set` changes (recorded in that order).
    base: Draft,
    /// Key paths, by axis and dim: the key and its `also` keys.
    paths: Vec<Vec<Vec<KeyPath>>>,
    /// Points per axis.
    lens: Vec<usize>,
    points: usize,
    /// The base scenario's observable names (their columns).
    pub observables: Vec<String>,
    pub columns: Vec<Column>,
    /// Index of the first outcome column (status).
    outcome_start: usize,
    /// Points resolved so far (tests count them).
    #[cfg(test)]
    pub(crate) resolves: std::sync::Arc<std::sync::atomic::AtomicUsize>,
}

/// What resolving a point gives: the scenario it runs, or the key that cannot be set
/// and why.
pub type Resolution = Result<Resolved, (String, String)>;

/// A point resolved to the scenario it runs.
#[derive(Debug, Clone)]
pub struct Resolved {
    /// The base document with every change of the point set, not yet validated; its
    /// `overrides` name the changes (`key=value`), in order.
    pub draft: Draft,
    /// Hash of the fully resolved document's canonical TOML text ([`Draft::canonical`]):
    /// 32 hexadecimal digits (SipHash-1-3, 128 bits, key 0).
    pub key: String,
}

/// An error of the study itself (not of one point), in the scenario errors' form.
pub fn study_error(
    source: &str,
    key: Option<String>,
    value: Option<String>,
    rule: String,
) -> ScenarioError {
    ScenarioError {
        kind: ErrorKind::Invalid,
        location: Location {
            source: source.to_owned(),
            line: None,
            column: None,
            set: None,
        },
        key,
        value,
        rule,
    }
}

/// Most points [`Study::warnings`] checks (each a scenario built: about 0.2 s in all).
pub const MAX_WARNING_POINTS: usize = 2_000;

/// The points of a grid over axes of `lens` values each, or the rule it breaks (more than
/// [`MAX_POINTS`]).
pub(crate) fn grid_points(lens: &[usize]) -> Result<usize, String> {
    lens.iter()
        .try_fold(1usize, |acc, &n| {
            acc.checked_mul(n).filter(|p| *p <= MAX_POINTS)
        })
        .ok_or_else(|| too_many_points(lens))
}

/// The rule broken by axes of `lens` values whose product is more than [`MAX_POINTS`].
fn too_many_points(lens: &[usize]) -> String {
    let shown: Vec<String> = lens.iter().map(|n| n.to_string()).collect();
    let total: f64 = lens.iter().map(|&n| n as f64).product();
    format!(
        "{} = {total:e} points; a study has at most {MAX_POINTS} (split it into several studies)",
        shown.join(" × ")
    )
}

impl Study {
    /// Checks the plan and prepares it: the base must be a valid scenario, every key a
    /// valid path into it, the number of points at most [`MAX_POINTS`], and the first
    /// point must not name an unknown key.
    pub fn new(plan: Plan) -> Result<Study, ScenarioErrors> {
        let src = plan.source.clone();
        let places = plan.places.clone();
        // An error of the part `label` of the study, placed where it was written.
        let err_at = |label: &str, key: Option<String>, value: Option<String>, rule: String| {
            ScenarioErrors::from(places.locate(&src, label, study_error(&src, key, value, rule)))
        };
        let err = |key: Option<String>, value: Option<String>, rule: String| {
            let label = key.clone().unwrap_or_default();
            err_at(&label, key, value, rule)
        };
        if plan.axes.len() > MAX_AXES {
            return Err(err(
                Some("axis".into()),
                Some(format!("{} axes", plan.axes.len())),
                format!("a study has at most {MAX_AXES} axes"),
            ));
        }
        let set_labels: Vec<String> = plan
            .set
            .iter()
            .map(|(k, v)| format!("{k}={}", value_text(v)))
            .collect();
        // The base as the study changes it must be a valid scenario; an error of a `set`
        // change is placed at that change in the study file.
        let at_set = |errs: ScenarioErrors| {
            ScenarioErrors(
                errs.0
                    .into_iter()
                    .map(|mut e| {
                        let Some(j) = set_labels
                            .iter()
                            .position(|o| e.location.set.as_ref() == Some(o))
                        else {
                            return e;
                        };
                        let label = format!("set.{}", plan.set[j].0);
                        if places.0.contains_key(&label) {
                            e.key = e.key.map(|k| format!("set.{k}"));
                        }
                        places.locate(&src, &label, e)
                    })
                    .collect(),
            )
        };
        let mut base = Draft::parse(&plan.base.text, &plan.base.source, &plan.base.overrides)
            .map_err(at_set)?;
        for ((k, v), label) in plan.set.iter().zip(&set_labels) {
            let path = parse_path(k).map_err(|r| err(Some(format!("set.{k}")), None, r))?;
            base.set(&path, v, label)
                .map_err(|e| at_set(e.error(&plan.base.source, &path, label).into()))?;
            base.overrides.push(label.clone());
        }
        let base_scenario = base.clone().build().map_err(at_set)?;
        let mut paths = Vec::new();
        let mut lens = Vec::new();
        for (i, axis) in plan.axes.iter().enumerate() {
            let n = axis.len();
            if axis.dims.is_empty() || n == 0 {
                return Err(err_at(
                    &format!("axis[{i}]"),
                    Some("axis".into()),
                    None,
                    "every axis needs at least one key and one value".into(),
                ));
            }
            let mut dims = Vec::new();
            for d in &axis.dims {
                if d.values.len() != n {
                    return Err(err_at(
                        &format!("axis[{i}]"),
                        Some(format!("axis[{}]", d.key)),
                        None,
                        "every key of a Latin hypercube has n values".into(),
                    ));
                }
                let mut keys = Vec::new();
                let named =
                    std::iter::once((&d.key, "key")).chain(d.also.iter().map(|k| (k, "also")));
                for (k, field) in named {
                    let fail = |r| {
                        err_at(
                            &format!("axis[{i}].{field}"),
                            Some(format!("axis[{}].{field}", d.key)),
                            Some(format!("{k:?}")),
                            r,
                        )
                    };
                    let p = parse_path(k).map_err(fail)?;
                    // The path must reach into the base (indices exist, no scalar in the way).
                    let mut probe = base.clone();
                    probe
                        .set(&p, &d.values.get(0), "")
                        .map_err(|e| fail(blocked_rule(&p, &e)))?;
                    keys.push(p);
                }
                dims.push(keys);
            }
            paths.push(dims);
            lens.push(n);
        }
        let points = match plan.combine {
            Combine::Grid => grid_points(&lens).ok(),
            Combine::Zip => {
                if let Some((i, n)) = lens.iter().enumerate().find(|(_, n)| **n != lens[0]) {
                    return Err(err(
                        Some("combine".into()),
                        Some("\"zip\"".into()),
                        format!(
                            "zipped axes must all have the same number of values: axis[{}] has {}, axis[{}] has {n}",
                            plan.axes[0].dims[0].key, lens[0], plan.axes[i].dims[0].key
                        ),
                    ));
                }
                Some(lens.first().copied().unwrap_or(1)).filter(|p| *p <= MAX_POINTS)
            }
        };
        let points = points.ok_or_else(|| {
            let rule = match plan.combine {
                Combine::Grid => grid_points(&lens).unwrap_err(),
                Combine::Zip => too_many_points(&lens[..1]),
            };
            err(
                Some("combine".into()),
                Some(format!("{:?}", plan.combine).to_lowercase()),
                rule,
            )
        })?;
        let observables: Vec<String> = base_scenario
            .scene
            .observe
            .iter()
            .map(|o| o.name.clone())
            .collect();
        let layout = Layout::of(&base_scenario.scene.body);
        let columns =
            columns(&plan, &observables, &layout).map_err(|(k, v, r)| err(Some(k), Some(v), r))?;
        let outcome_start = columns
            .iter()
            .position(|c| c.role == Role::Status)
            .unwrap_or(0);
        let study = Study {
            plan,
            base,
            paths,
            lens,
            points,
            observables,
            columns,
            outcome_start,
            #[cfg(test)]
            resolves: Default::default(),
        };
        // A misspelt key fails every point the same way: say so now, at the axis.
        if study.points > 0 {
            let r = study.resolve(0).map_err(|(k, r)| err(Some(k), None, r))?;
            if let Err(e) = r.draft.clone().build()
                && let Some(e) = e.0.iter().find(|e| {
                    matches!(
                        e.kind,
                        ErrorKind::UnknownKey | ErrorKind::Override | ErrorKind::Syntax
                    )
                })
            {
                let rule = format!(
                    "{} (the first point, {})",
                    e.rule,
                    r.draft.overrides[study.base.overrides.len()..].join(", ")
                );
                // The axis (and whether its key or an `also` key) that names it.
                let named = e.key.as_deref().and_then(|k| {
                    study.plan.axes.iter().enumerate().find_map(|(i, a)| {
                        a.dims.iter().find_map(|d| {
                            let field = if d.key == k {
                                "key"
                            } else if d.also.iter().any(|x| x == k) {
                                "also"
                            } else {
                                return None;
                            };
                            Some((
                                format!("axis[{i}].{field}"),
                                format!("axis[{}].{field}", d.key),
                                k,
                            ))
                        })
                    })
                });
                return Err(match named {
                    Some((label, key, k)) => {
                        err_at(&label, Some(key), Some(format!("{k:?}")), rule)
                    }
                    None => err(
                        e.key.clone().map(|k| format!("axis key {k}")),
                        e.value.clone(),
                        rule,
                    ),
                });
            }
        }
        Ok(study)
    }

    /// Number of points (rows).
    pub fn len(&self) -> usize {
        self.points
    }

    pub fn is_empty(&self) -> bool {
        self.points == 0
    }

    /// The value index of each axis at point `index` (grid: row-major, last axis fastest).
    pub fn coords(&self, index: usize) -> Vec<usize> {
        match self.plan.combine {
            Combine::Zip => vec![index; self.lens.len()],
            Combine::Grid => {
                let mut rest = index;
                let mut c = vec![0; self.lens.len()];
                for (i, n) in self.lens.iter().enumerate().rev() {
                    c[i] = rest % n;
                    rest /= n;
                }
                c
            }
        }
    }

    /// Point `index` as the overrides that make its scenario, its resolved text and key.
    /// (An error names the key and why: an index out of range in the base.)
    pub fn resolve(&self, index: usize) -> Resolution {
        #[cfg(test)]
        self.resolves
            .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let coords = self.coords(index);
        let mut draft = self.base.clone();
        // Arrays with an element set, by their path as written: each is named by one
        // change, the whole array as resolved, after the others.
        let mut heads: Vec<(String, KeyPath)> = Vec::new();
        for ((axis, paths), &c) in self.plan.axes.iter().zip(&self.paths).zip(&coords) {
            for (dim, keys) in axis.dims.iter().zip(paths) {
                let v = dim.values.get(c);
                for p in keys {
                    let label = if p.is_indexed() {
                        let head = p.head();
                        heads.push((head.to_string(), head));
                        String::new()
                    } else {
                        format!("{p}={}", value_text(&v))
                    };
                    draft
                        .set(p, &v, &label)
                        .map_err(|e| (dim.key.clone(), blocked_rule(p, &e)))?;
                    if !label.is_empty() {
                        draft.overrides.push(label);
                    }
                }
            }
        }
        heads.sort_unstable_by(|a, b| a.0.cmp(&b.0));
        heads.dedup_by(|a, b| a.0 == b.0);
        for (h, path) in heads {
            if let Some(v) = draft.get(&path) {
                let label = format!("{h}={}", value_text(&v));
                draft
                    .set(&path, &v, &label)
                    .map_err(|e| (h.clone(), blocked_rule(&path, &e)))?;
                draft.overrides.push(label);
            }
        }
        let text = draft.canonical().map_err(|e| ("base".to_owned(), e))?;
        Ok(Resolved {
            key: hash_hex(&text),
            draft,
        })
    }

    /// The plausibility warnings of the study's points (`scenario::warnings`: valid values
    /// that are likely unit slips), each text once, in the order found. Checked at the
    /// points that give every value of every axis, the other axes at their first values —
    /// as many points as the axes have values together, not their product — so a slip in
    /// one axis's values is always found, and one that needs two axes' values together (a
    /// density from a mass and a size) where these points have them; at most
    /// [`MAX_WARNING_POINTS`] of them, the axes' values taken in turn (a zipped study: its
    /// first points). Points the scenario refuses are skipped: a run reports them.
    pub fn warnings(&self) -> Vec<String> {
        let mut points = vec![0];
        match self.plan.combine {
            Combine::Zip => points.extend(1..self.points),
            Combine::Grid => {
                // Row-major: axis k's stride is the product of the later axes' lengths.
                // The axes' values taken in turn (the second of each, then the third, …),
                // so that the cap leaves no axis unchecked.
                let mut strides = vec![1; self.lens.len()];
                for k in (0..self.lens.len().saturating_sub(1)).rev() {
                    strides[k] = strides[k + 1] * self.lens[k + 1];
                }
                let longest = self.lens.iter().copied().max().unwrap_or(0);
                for c in 1..longest.min(MAX_WARNING_POINTS) {
                    for (&n, &stride) in self.lens.iter().zip(&strides) {
                        if c < n {
                            points.push(c * stride);
                        }
                    }
                }
            }
        }
        let mut out: Vec<String> = Vec::new();
        points.truncate(MAX_WARNING_POINTS);
        for index in points.into_iter().filter(|&i| i < self.points) {
            let Ok(Ok(point)) = self.resolve(index).map(|r| self.scenario(&r)) else {
                continue;
            };
            for w in scenario::warnings(&point) {
                let text = w.to_string();
                if !out.contains(&text) {
                    out.push(text);
                }
            }
        }
        out
    }

    /// Point `index`'s scenario.
    pub fn scenario(&self, r: &Resolved) -> Result<Scenario, ScenarioErrors> {
        r.draft.clone().build()
    }

    /// The axis cells of point `index`, in column order.
    pub fn axis_cells(&self, index: usize) -> Vec<Cell> {
        let coords = self.coords(index);
        let mut cells = Vec::new();
        for (axis, &c) in self.plan.axes.iter().zip(&coords) {
            for d in &axis.dims {
                cells.push(match (&d.values, d.values.numeric()) {
                    (Values::Floats(v), _) => Cell::Float(v[c]),
                    (Values::Given(v), true) => Cell::Float(match &v[c] {
                        toml::Value::Integer(i) => *i as f64,
                        toml::Value::Float(f) => *f,
                        _ => unreachable!("numeric"),
                    }),
                    (Values::Given(v), false) => Cell::Text(match &v[c] {
                        toml::Value::String(s) => s.clone(),
                        other => value_text(other),
                    }),
                });
            }
        }
        cells
    }

    /// The outcome columns (status … rhs_evals), whose cells a run produces.
    pub fn outcome_columns(&self) -> &[Column] {
        &self.columns[self.outcome_start..self.columns.len() - 1]
    }

    /// A fingerprint of the study as data: SipHash-1-3 of its [`Plan`] as JSON (exact
    /// floats), without its source's name. A journal of another plan (an edited study
    /// file) is not trusted by point index.
    pub fn plan_fingerprint(&self) -> String {
        let plan = Plan {
            source: String::new(),
            ..self.plan.clone()
        };
        hash_hex(&serde_json::to_string(&plan).unwrap_or_default())
    }

    /// A fingerprint of the outcome columns (names and types): a journal made for other
    /// outcomes is not reused.
    pub fn outcome_fingerprint(&self) -> String {
        let mut s = String::new();
        for c in self.outcome_columns() {
            let _ = write!(s, "{}:{:?};", c.header(), c.ty);
        }
        hash_hex(&s)
    }
}

/// SipHash-1-3 (128-bit output, key 0) of `text`, as 32 hexadecimal digits.
pub fn hash_hex(text: &str) -> String {
    let mut h = SipHasher13::new_with_keys(0, 0);
    h.write(text.as_bytes());
    format!("{:032x}", h.finish128().as_u128())
}

/// The table's columns: point, the axis values, then the outcomes, then the key. The
/// `final`, `min` and `max` columns are the base scenario's output columns (`layout`:
/// for a body with contact spheres, the per-surface ones too).
fn columns(
    plan: &Plan,
    observables: &[String],
    layout: &Layout,
) -> Result<Vec<Column>, (String, String, String)> {
    let named = layout.numeric_columns();
    let col = |name: String, unit: Option<&str>, ty: Type, nullable: bool, role: Role| Column {
        name,
        unit: unit.map(str::to_owned),
        ty,
        nullable,
        role,
    };
    let mut cols = vec![col("point".into(), None, Type::Int, false, Role::Point)];
    for (a, axis) in plan.axes.iter().enumerate() {
        for (d, dim) in axis.dims.iter().enumerate() {
            let numeric = dim.values.numeric();
            cols.push(col(
                dim.key.clone(),
                if numeric {
                    scenario::schema::unit(&dim.key)
                } else {
                    None
                },
                if numeric { Type::Float } else { Type::Text },
                false,
                Role::Axis { axis: a, dim: d },
            ));
        }
    }
    cols.push(col("status".into(), None, Type::Text, false, Role::Status));
    cols.push(col(
        "message".into(),
        None,
        Type::Text,
        false,
        Role::Message,
    ));
    cols.push(col(
        "t_final".into(),
        Some("s"),
        Type::Float,
        true,
        Role::TFinal,
    ));
    let o = &plan.outcomes;
    if o.observables {
        for name in observables {
            cols.push(col(
                format!("t_{name}"),
                Some("s"),
                Type::Float,
                true,
                Role::Observed(name.clone()),
            ));
        }
    }
    let numeric = |list: &str, name: &str| -> Result<usize, (String, String, String)> {
        layout.index(name).ok_or_else(|| {
            (
                format!("outcomes.{list}"),
                format!("{name:?}"),
                format!(
                    "expected the name of a numeric output column of the base scenario's body: {}",
                    named.iter().map(|c| &*c.0).collect::<Vec<_>>().join(", ")
                ),
            )
        })
    };
    for name in &o.final_columns {
        if name == "mode" {
            cols.push(col(
                "final.mode".into(),
                None,
                Type::Text,
                true,
                Role::FinalMode,
            ));
        } else {
            let i = numeric("final", name)?;
            cols.push(col(
                format!("final.{name}"),
                Some(named[i].1),
                Type::Float,
                true,
                Role::Final(i),
            ));
        }
    }
    for name in &o.min {
        let i = numeric("min", name)?;
        cols.push(col(
            format!("min.{name}"),
            Some(named[i].1),
            Type::Float,
            true,
            Role::Min(i),
        ));
    }
    for name in &o.max {
        let i = numeric("max", name)?;
        cols.push(col(
            format!("max.{name}"),
            Some(named[i].1),
            Type::Float,
            true,
            Role::Max(i),
        ));
    }
    if o.drift {
        for inv in Invariant::ALL {
            cols.push(col(
                format!("drift.{}", inv.name()),
                Some("1"),
                Type::Float,
                true,
                Role::Drift(inv),
            ));
        }
    }
    if o.wall_time {
        cols.push(col(
            "wall_time".into(),
            Some("s"),
            Type::Float,
            true,
            Role::WallTime,
        ));
    }
    if o.rhs_evals {
        cols.push(col(
            "rhs_evals".into(),
            None,
            Type::Int,
            true,
            Role::RhsEvals,
        ));
    }
    cols.push(col("key".into(), None, Type::Text, false, Role::Key));
    let mut seen = std::collections::HashSet::new();
    for c in &cols {
        if !seen.insert(c.header()) {
            return Err((
                "outcomes".into(),
                format!("{:?}", c.header()),
                "two columns of the table have this name; name each key and column once".into(),
            ));
        }
    }
    Ok(cols)
}
