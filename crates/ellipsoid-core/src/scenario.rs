//! Scenario files: a TOML document (SI units, radians) → a validated [`Scene`].
//!
//! The format is documented in `docs/scenarios.md`; the bundled examples are in
//! `scenarios/`. Shared by the command-line tool and the Python package.
//!
//! ```text
//!   text ──DeTable::parse──▶ spanned tree ──--set key=value──▶ tree ──walk──▶ Scene
//!                                                                 └──▶ Body::new, Scene::validate
//! ```
//! The document is read into a tree that remembers where every key and value came
//! from (a byte span in the file, or a `--set` override), so that every error — a
//! syntax error, an unknown key, a wrong type, a missing key, or a physical rule broken
//! in `Body::new` or `simulate` (via [`Scenario::locate`]) — names the file, the line
//! and column, the key, the value and the rule:
//!
//! ```text
//!   scenarios/x.toml:4:1: body.mass = -0.05: the mass must be positive and finite (kg)
//! ```
#![allow(clippy::result_large_err)] // one error per failed parse, off the hot path; its fields are public API

use std::collections::BTreeMap;
use std::fmt;
use std::ops::Range;
use std::path::Path;

use nalgebra::{Matrix3, UnitQuaternion, Vector2, Vector3};
use serde::Serialize;
use toml::de::{DeTable, DeValue};

use crate::body::{uniform_inertia, Body};
use crate::effects::{AirDrag, RollingResistance, SpinFriction};
use crate::error::ModelError;
use crate::integrate::Method;
use crate::simulate::{ContactModel, EffectSet, InitialState, Scene, SolverSettings};
use crate::state::EulerAngles;

/// g when `effects.gravity` is absent [m/s²] (standard gravity rounded as in the paper).
pub const DEFAULT_GRAVITY: f64 = 9.81;
/// `solver.method` when absent.
pub const DEFAULT_METHOD: &str = "dop853";
/// `solver.rtol` when absent.
pub const DEFAULT_RTOL: f64 = 1e-10;
/// `solver.atol` when absent (in each state component's SI unit).
pub const DEFAULT_ATOL: f64 = 1e-12;
/// `solver.max_steps` when absent (accepted + rejected steps per mode segment).
pub const DEFAULT_MAX_STEPS: u64 = 10_000_000;
/// `regularisation` of rolling resistance and spin friction when absent [rad/s].
pub const DEFAULT_REGULARISATION: f64 = 1e-3;
/// Most output samples a scenario may ask for (10⁷ rows of CSV is already ~3 GB).
pub const MAX_SAMPLES: usize = 10_000_000;
/// The invariants a `[check]` table may bound (the fields of `simulate::Drift`).
pub const DRIFT_NAMES: [&str; 6] = ["energy", "energy_plus_work", "momentum", "angular_momentum_z", "axial_spin", "jellett"];
/// The run statuses a `[check]` table may expect (the `status` names of `simulate::Status`).
pub const STATUS_NAMES: [&str; 7] = ["completed", "lost_contact", "slip_stopped", "painleve", "solver_failure", "chattering", "cancelled"];

const TOP_KEYS: [&str; 7] = ["body", "initial", "contact", "effects", "solver", "output", "check"];
const BODY_KEYS: [&str; 7] = ["a", "b", "c", "mass", "com_offset", "com_offset_vector", "inertia"];
const INITIAL_KEYS: [&str; 17] = [
    "theta", "theta_deg", "phi", "phi_deg", "psi", "psi_deg", "theta_dot", "theta_dot_deg", "phi_dot", "phi_dot_deg", "psi_dot", "psi_dot_deg",
    "omega_body", "omega_body_deg", "rotation", "position", "velocity",
];
const CONTACT_KEYS: [&str; 2] = ["model", "friction"];
const CONTACT_MODELS: [&str; 4] = ["frictionless", "sliding", "rolling", "coulomb"];
const EFFECT_KEYS: [&str; 4] = ["gravity", "rolling_resistance", "spin_friction", "air_drag"];
const SOLVER_KEYS: [&str; 5] = ["method", "rtol", "atol", "step", "max_steps"];
const METHODS: [&str; 3] = ["rk4", "dopri5", "dop853"];
const OUTPUT_KEYS: [&str; 3] = ["t_end", "dt", "times"];

/// A parsed, validated scenario.
#[derive(Debug, Clone, PartialEq)]
pub struct Scenario {
    /// What to simulate.
    pub scene: Scene,
    /// The scenario's text as read (before `--set` overrides).
    pub text: String,
    /// Where it came from: the path as given, or a name for text given directly.
    pub source: String,
    /// The `key=value` overrides applied, in order.
    pub overrides: Vec<String>,
    /// Expectations of the optional `[check]` table.
    pub check: Check,
    /// The document after overrides, with spans (for [`Scenario::locate`]).
    tree: Node,
}

/// The optional `[check]` table: what a run of the scenario is expected to achieve.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Check {
    /// Expected `status` of the run (one of [`STATUS_NAMES`]).
    pub status: Option<String>,
    /// Largest allowed relative drift of each named invariant (names from [`DRIFT_NAMES`]).
    pub drift: BTreeMap<String, f64>,
}

/// What kind of mistake a [`ScenarioError`] reports.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ErrorKind {
    /// The file could not be read.
    Io,
    /// The text is not valid TOML.
    Syntax,
    /// A `--set key=value` override is malformed.
    Override,
    /// A key the format does not know.
    UnknownKey,
    /// A required key is absent.
    Missing,
    /// A value of the wrong type (a string for a number, …).
    Type,
    /// Two keys that exclude each other.
    Conflict,
    /// A value that breaks a rule (physical or numerical).
    Invalid,
}

/// Where an error lies.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Location {
    /// The file (path as given) or the name of the text.
    pub source: String,
    /// 1-based line and column (in characters) in the file; `None` for a `--set` value.
    pub line: Option<usize>,
    pub column: Option<usize>,
    /// The `--set key=value` override the value came from.
    pub set: Option<String>,
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.source)?;
        if let (Some(line), Some(col)) = (self.line, self.column) {
            write!(f, ":{line}:{col}")?;
        }
        if let Some(set) = &self.set {
            write!(f, ": --set {set}")?;
        }
        Ok(())
    }
}

/// A scenario that cannot be run. Displays as one line:
/// `file:line:col: key = value: rule` (or `file:line:col: key is missing: rule`, …).
#[derive(Debug, Clone, PartialEq, thiserror::Error, Serialize)]
#[error("{}", self.render())]
pub struct ScenarioError {
    pub kind: ErrorKind,
    pub location: Location,
    /// The full dotted key (`body.mass`), when the error concerns one.
    pub key: Option<String>,
    /// The offending value as written (or as the physics layer formatted it).
    pub value: Option<String>,
    /// What is wrong, and what would be right.
    pub rule: String,
}

impl ScenarioError {
    fn render(&self) -> String {
        let loc = &self.location;
        match (&self.key, &self.value, self.kind) {
            (Some(k), _, ErrorKind::Missing) => format!("{loc}: {k} is missing: {}", self.rule),
            (Some(k), Some(v), _) => format!("{loc}: {k} = {v}: {}", self.rule),
            (Some(k), None, _) => format!("{loc}: {k}: {}", self.rule),
            (None, _, _) => format!("{loc}: {}", self.rule),
        }
    }
}

type Result<T> = std::result::Result<T, ScenarioError>;

/// Reads and parses the scenario file at `path`, applying `overrides` (`key=value`).
pub fn load(path: &Path, overrides: &[impl AsRef<str>]) -> Result<Scenario> {
    let source = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| ScenarioError {
        kind: ErrorKind::Io,
        location: Location { source: source.clone(), line: None, column: None, set: None },
        key: None,
        value: None,
        rule: format!("cannot read the scenario file: {e}"),
    })?;
    parse(&text, &source, overrides)
}

/// Parses scenario `text` (named `source` in messages), applying `overrides` (`key=value`,
/// the value in TOML syntax; a bare word is taken as a string).
pub fn parse(text: &str, source: &str, overrides: &[impl AsRef<str>]) -> Result<Scenario> {
    let ctx = Ctx { source, text };
    let doc = DeTable::parse(text).map_err(|e| ctx.syntax(&e, None))?;
    let mut tree = Node::from_table(doc.into_inner(), Origin::File(0..0));
    let overrides: Vec<String> = overrides.iter().map(|s| s.as_ref().to_owned()).collect();
    for set in &overrides {
        apply_override(&ctx, &mut tree, set)?;
    }
    let (scene, check) = build(&ctx, &tree)?;
    Ok(Scenario { scene, text: text.to_owned(), source: source.to_owned(), overrides, check, tree })
}

impl Scenario {
    /// The file name without its extension (`nutation` for `scenarios/nutation.toml`).
    pub fn stem(&self) -> String {
        Path::new(&self.source).file_stem().map_or_else(|| "scenario".to_owned(), |s| s.to_string_lossy().into_owned())
    }

    /// Places an error of the physics layer (e.g. from `simulate`) at the key it names:
    /// `body.com_offset` → the `com_offset` or `com_offset_vector` key, `initial state` →
    /// the `[initial]` table, and so on.
    pub fn locate(&self, err: &ModelError) -> ScenarioError {
        Ctx { source: &self.source, text: &self.text }.model(&self.tree, err)
    }
}

// ---------------------------------------------------------------------------------
// The spanned document tree.

/// Where a key or value came from.
#[derive(Debug, Clone, PartialEq)]
enum Origin {
    /// A byte range of the file.
    File(Range<usize>),
    /// A `--set key=value` override (its text).
    Set(String),
}

#[derive(Debug, Clone, PartialEq)]
enum Value {
    Str(String),
    Int(i64),
    Float(f64),
    Bool(bool),
    Datetime(String),
    Array(Vec<Node>),
    Table(Vec<Entry>),
}

#[derive(Debug, Clone, PartialEq)]
struct Node {
    value: Value,
    origin: Origin,
}

#[derive(Debug, Clone, PartialEq)]
struct Entry {
    key: String,
    key_origin: Origin,
    node: Node,
}

impl Node {
    fn from_table(table: DeTable<'_>, origin: Origin) -> Node {
        let mut entries: Vec<Entry> = table
            .into_iter()
            .map(|(k, v)| {
                let key_origin = Origin::File(k.span());
                Entry { key: k.into_inner().into_owned(), key_origin, node: Node::from_value(v.span(), v.into_inner(), None) }
            })
            .collect();
        // In file order, so that the first error reported is the first in the file.
        entries.sort_by_key(|e| match &e.key_origin {
            Origin::File(r) => r.start,
            Origin::Set(_) => usize::MAX,
        });
        Node { value: Value::Table(entries), origin }
    }

    /// Converts a parsed value; with `set`, every node's origin is that override.
    fn from_value(span: Range<usize>, value: DeValue<'_>, set: Option<&str>) -> Node {
        let origin = match set {
            Some(s) => Origin::Set(s.to_owned()),
            None => Origin::File(span),
        };
        let value = match value {
            DeValue::String(s) => Value::Str(s.into_owned()),
            DeValue::Integer(i) => match i64::from_str_radix(i.as_str(), i.radix()) {
                Ok(v) => Value::Int(v),
                // Beyond i64: no key of the format needs it; keep it as a number that
                // fails the finiteness checks rather than a different type.
                Err(_) => Value::Float(if i.as_str().starts_with('-') { f64::NEG_INFINITY } else { f64::INFINITY }),
            },
            DeValue::Float(f) => Value::Float(f.as_str().parse().unwrap_or(f64::NAN)),
            DeValue::Boolean(b) => Value::Bool(b),
            DeValue::Datetime(d) => Value::Datetime(d.to_string()),
            DeValue::Array(a) => Value::Array(a.into_iter().map(|e| Node::from_value(e.span(), e.into_inner(), set)).collect()),
            DeValue::Table(t) => {
                let mut node = Node::from_table(t, origin.clone());
                if let (Some(s), Value::Table(entries)) = (set, &mut node.value) {
                    for e in entries.iter_mut() {
                        e.key_origin = Origin::Set(s.to_owned());
                        set_origin(&mut e.node, s);
                    }
                }
                return node;
            }
        };
        Node { value, origin }
    }

    fn entries(&self) -> &[Entry] {
        match &self.value {
            Value::Table(e) => e,
            _ => &[],
        }
    }

    /// The origin of the key at `path` (dotted segments), if present.
    fn find(&self, path: &[String]) -> Option<Origin> {
        let (first, rest) = path.split_first()?;
        let entry = self.entries().iter().find(|e| &e.key == first)?;
        if rest.is_empty() { Some(entry.key_origin.clone()) } else { entry.node.find(rest) }
    }

    fn as_f64(&self) -> Option<f64> {
        match self.value {
            Value::Int(i) => Some(i as f64),
            Value::Float(f) => Some(f),
            _ => None,
        }
    }

    fn type_name(&self) -> &'static str {
        match self.value {
            Value::Str(_) => "a string",
            Value::Int(_) => "an integer",
            Value::Float(_) => "a float",
            Value::Bool(_) => "a boolean",
            Value::Datetime(_) => "a date-time",
            Value::Array(_) => "an array",
            Value::Table(_) => "a table",
        }
    }

    /// The value in TOML syntax (for values that did not come from the file).
    fn render(&self) -> String {
        match &self.value {
            Value::Str(s) => format!("{s:?}"),
            Value::Int(i) => i.to_string(),
            Value::Float(f) => f.to_string(),
            Value::Bool(b) => b.to_string(),
            Value::Datetime(d) => d.clone(),
            Value::Array(a) => format!("[{}]", a.iter().map(Node::render).collect::<Vec<_>>().join(", ")),
            Value::Table(e) => format!("{{ {} }}", e.iter().map(|e| format!("{} = {}", e.key, e.node.render())).collect::<Vec<_>>().join(", ")),
        }
    }
}

fn set_origin(node: &mut Node, set: &str) {
    node.origin = Origin::Set(set.to_owned());
    match &mut node.value {
        Value::Array(a) => a.iter_mut().for_each(|n| set_origin(n, set)),
        Value::Table(t) => t.iter_mut().for_each(|e| {
            e.key_origin = Origin::Set(set.to_owned());
            set_origin(&mut e.node, set);
        }),
        _ => {}
    }
}

/// Applies one `key.path=value` override to the document.
fn apply_override(ctx: &Ctx<'_>, tree: &mut Node, set: &str) -> Result<()> {
    let location = Location { source: ctx.source.to_owned(), line: None, column: None, set: Some(set.to_owned()) };
    let fail = |key: Option<String>, value: Option<String>, rule: String| ScenarioError { kind: ErrorKind::Override, location: location.clone(), key, value, rule };
    let Some((key, raw)) = set.split_once('=') else {
        return Err(fail(None, None, "an override must have the form key=value, e.g. --set output.t_end=1.0".into()));
    };
    let path: Vec<&str> = key.trim().split('.').map(str::trim).collect();
    if path.iter().any(|s| s.is_empty() || !s.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')) {
        return Err(fail(Some(key.trim().to_owned()), None, "the key must be a dotted path of names such as body.mass".into()));
    }
    let raw = raw.trim();
    let node = match DeValue::parse(raw) {
        Ok(v) => Node::from_value(v.span(), v.into_inner(), Some(set)),
        // A bare word (`--set contact.model=rolling`) is a string.
        Err(_) if !raw.is_empty() && raw.chars().all(|c| c.is_ascii_alphanumeric() || "_-+.".contains(c)) => {
            Node { value: Value::Str(raw.to_owned()), origin: Origin::Set(set.to_owned()) }
        }
        Err(e) => return Err(fail(Some(key.trim().to_owned()), Some(raw.to_owned()), format!("not a TOML value: {}", e.message()))),
    };
    let mut table = tree;
    for (i, seg) in path.iter().enumerate() {
        let Value::Table(entries) = &mut table.value else {
            return Err(fail(Some(path[..i].join(".")), None, format!("is not a table, so {} cannot be set", path.join("."))));
        };
        let pos = match entries.iter().position(|e| e.key == *seg) {
            Some(p) => p,
            None => {
                let empty = Node { value: Value::Table(Vec::new()), origin: Origin::Set(set.to_owned()) };
                entries.push(Entry { key: (*seg).to_owned(), key_origin: Origin::Set(set.to_owned()), node: empty });
                entries.len() - 1
            }
        };
        let entry = &mut entries[pos];
        if i + 1 == path.len() {
            entry.key_origin = Origin::Set(set.to_owned());
            entry.node = node;
            return Ok(());
        }
        table = &mut entry.node;
    }
    unreachable!("the loop returns at the last segment of a non-empty path")
}

// ---------------------------------------------------------------------------------
// Errors with positions.

struct Ctx<'a> {
    source: &'a str,
    text: &'a str,
}

impl Ctx<'_> {
    fn locate(&self, origin: &Origin) -> Location {
        match origin {
            Origin::File(span) => {
                let offset = span.start.min(self.text.len());
                let before = &self.text[..offset];
                let line = before.matches('\n').count() + 1;
                let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
                Location { source: self.source.to_owned(), line: Some(line), column: Some(column), set: None }
            }
            Origin::Set(s) => Location { source: self.source.to_owned(), line: None, column: None, set: Some(s.clone()) },
        }
    }

    /// The value as the user wrote it, on one line and at most 60 characters.
    fn value_text(&self, node: &Node) -> String {
        let raw = match (&node.origin, &node.value) {
            // A [table] header: its span is the header, not the value.
            (Origin::File(span), Value::Table(_)) if !self.text.get(span.clone()).is_some_and(|s| s.trim_start().starts_with('{')) => "a table".to_owned(),
            (Origin::File(span), _) => self.text.get(span.clone()).map_or_else(|| node.render(), str::to_owned),
            (Origin::Set(_), _) => node.render(),
        };
        let one_line = raw.split_whitespace().collect::<Vec<_>>().join(" ");
        if one_line.chars().count() > 60 { format!("{}…", one_line.chars().take(59).collect::<String>()) } else { one_line }
    }

    fn error(&self, kind: ErrorKind, origin: &Origin, key: Option<String>, value: Option<String>, rule: impl Into<String>) -> ScenarioError {
        ScenarioError { kind, location: self.locate(origin), key, value, rule: rule.into() }
    }

    fn syntax(&self, e: &toml::de::Error, set: Option<&str>) -> ScenarioError {
        let origin = match set {
            Some(s) => Origin::Set(s.to_owned()),
            None => Origin::File(e.span().unwrap_or(0..0)),
        };
        self.error(ErrorKind::Syntax, &origin, None, None, format!("TOML syntax error: {}", e.message()))
    }

    /// A physics-layer error, placed at the key it names.
    fn model(&self, tree: &Node, err: &ModelError) -> ScenarioError {
        let scenario_like = Locator { tree };
        let ModelError::Invalid { quantity, value, rule } = err;
        self.error(ErrorKind::Invalid, &scenario_like.origin_of(quantity), Some(quantity.clone()), Some(value.clone()), rule.clone())
    }
}

/// Finds the origin of a physics quantity's key in a tree (see [`Scenario::locate`]).
struct Locator<'t> {
    tree: &'t Node,
}

impl Locator<'_> {
    /// The origin of the key a physics quantity names, or of the nearest table holding it.
    fn origin_of(&self, quantity: &str) -> Origin {
        let path: Vec<String> = quantity.split(['.', ' ']).filter(|s| !s.is_empty()).map(str::to_owned).collect();
        // A quantity may name a key's degree twin or general form, or a key left to its
        // default (body.b defaults to body.a).
        let mut candidates = vec![path.clone()];
        if let Some((last, head)) = path.split_last() {
            for alt in [format!("{last}_deg"), format!("{last}_vector")] {
                let mut p = head.to_vec();
                p.push(alt);
                candidates.push(p);
            }
        }
        if path == ["body", "b"] {
            candidates.push(vec!["body".into(), "a".into()]);
        }
        // Then the table: "initial state" → [initial]; "solver" → [solver].
        candidates.extend(path.first().map(|first| vec![first.clone()]));
        candidates.iter().find_map(|c| self.tree.find(c)).unwrap_or(Origin::File(0..0))
    }
}

// ---------------------------------------------------------------------------------
// Reading tables.

/// A table of the document being read, with its dotted path.
struct Sec<'t> {
    path: String,
    node: &'t Node,
}

/// A key found in a table.
#[derive(Clone, Copy)]
struct Got<'t> {
    key: &'t str,
    entry: &'t Entry,
}

impl<'t> Got<'t> {
    fn node(&self) -> &'t Node {
        &self.entry.node
    }
}

impl<'a> Ctx<'a> {
    /// The table `key` of `parent`, its keys checked against `allowed`.
    fn section<'t>(&self, parent: &Sec<'t>, key: &str, allowed: &[&str], what: &str) -> Result<Option<Sec<'t>>> {
        let Some(got) = parent.get(key) else { return Ok(None) };
        self.table_of(&parent.full(key), got.node(), &got.entry.key_origin, allowed, what).map(Some)
    }

    /// `node` as a table at `path`, its keys checked against `allowed`.
    fn table_of<'t>(&self, path: &str, node: &'t Node, key_origin: &Origin, allowed: &[&str], what: &str) -> Result<Sec<'t>> {
        let Value::Table(entries) = &node.value else {
            return Err(self.error(ErrorKind::Type, key_origin, Some(path.to_owned()), Some(self.value_text(node)), format!("expected a table ({what}), found {}", node.type_name())));
        };
        for e in entries {
            if !allowed.contains(&e.key.as_str()) {
                let full = if path.is_empty() { e.key.clone() } else { format!("{path}.{}", e.key) };
                let place = if path.is_empty() { "at the top level".to_owned() } else { format!("in [{path}]") };
                let hint = match suggest(&e.key, allowed) {
                    Some(s) => format!("did you mean `{s}`?"),
                    None => format!("expected one of: {}", allowed.join(", ")),
                };
                let (value, what) = match e.node.value {
                    Value::Table(_) => (None, "unknown table"),
                    _ => (Some(self.value_text(&e.node)), "unknown key"),
                };
                return Err(self.error(ErrorKind::UnknownKey, &e.key_origin, Some(full), value, format!("{what} {place}; {hint}")));
            }
        }
        Ok(Sec { path: path.to_owned(), node })
    }

    fn missing(&self, sec: &Sec<'_>, key: &str, rule: impl Into<String>) -> ScenarioError {
        self.error(ErrorKind::Missing, &sec.node.origin, Some(sec.full(key)), None, rule)
    }

    /// An error about the value of a key that is present.
    fn bad(&self, kind: ErrorKind, sec: &Sec<'_>, got: Got<'_>, rule: impl Into<String>) -> ScenarioError {
        self.error(kind, &got.entry.key_origin, Some(sec.full(got.key)), Some(self.value_text(got.node())), rule)
    }

    fn wrong_type(&self, sec: &Sec<'_>, got: Got<'_>, expected: &str) -> ScenarioError {
        self.bad(ErrorKind::Type, sec, got, format!("expected {expected}, found {}", got.node().type_name()))
    }

    /// A number (integer or float), if present.
    fn number(&self, sec: &Sec<'_>, key: &str, what: &str) -> Result<Option<(f64, Origin)>> {
        let Some(got) = sec.get(key) else { return Ok(None) };
        match got.node().as_f64() {
            Some(v) => Ok(Some((v, got.entry.key_origin.clone()))),
            None => Err(self.wrong_type(sec, got, &format!("a number: {what}"))),
        }
    }

    fn required(&self, sec: &Sec<'_>, key: &str, what: &str) -> Result<f64> {
        self.number(sec, key, what)?.map(|(v, _)| v).ok_or_else(|| self.missing(sec, key, format!("give {what}")))
    }

    /// A number that must be finite and satisfy `ok`, if present.
    fn checked(&self, sec: &Sec<'_>, key: &str, what: &str, ok: impl Fn(f64) -> bool, rule: &str) -> Result<Option<f64>> {
        match self.number(sec, key, what)? {
            Some((v, _)) if !(v.is_finite() && ok(v)) => Err(self.bad(ErrorKind::Invalid, sec, sec.get(key).expect("just read"), rule)),
            other => Ok(other.map(|(v, _)| v)),
        }
    }

    /// An array of exactly N numbers, if present.
    fn numbers<const N: usize>(&self, sec: &Sec<'_>, key: &str, what: &str) -> Result<Option<[f64; N]>> {
        let Some(got) = sec.get(key) else { return Ok(None) };
        let expected = || format!("an array of {N} numbers: {what}");
        let Value::Array(items) = &got.node().value else { return Err(self.wrong_type(sec, got, &expected())) };
        if items.len() != N {
            return Err(self.bad(ErrorKind::Type, sec, got, format!("expected {}, found {} element(s)", expected(), items.len())));
        }
        let mut out = [0.0; N];
        for (o, item) in out.iter_mut().zip(items) {
            *o = item.as_f64().ok_or_else(|| self.bad(ErrorKind::Type, sec, got, format!("expected {}, found {} among them", expected(), item.type_name())))?;
        }
        Ok(Some(out))
    }

    /// A string that must be one of `choices`, if present.
    fn choice<'t>(&self, sec: &Sec<'t>, key: &str, choices: &[&'static str]) -> Result<Option<(&'static str, Got<'t>)>> {
        let Some(got) = sec.get(key) else { return Ok(None) };
        let Value::Str(s) = &got.node().value else {
            return Err(self.wrong_type(sec, got, &format!("a string, one of {}", quoted(choices))));
        };
        match choices.iter().find(|c| **c == s.as_str()) {
            Some(c) => Ok(Some((c, got))),
            None => {
                let hint = suggest(s, choices).map_or_else(String::new, |c| format!("; did you mean \"{c}\"?"));
                Err(self.bad(ErrorKind::Invalid, sec, got, format!("expected one of {}{hint}", quoted(choices))))
            }
        }
    }

    /// Rejects giving both `a` and `b`.
    fn exclusive(&self, sec: &Sec<'_>, a: &str, b: &str, why: &str) -> Result<()> {
        if let (Some(_), Some(got)) = (sec.get(a), sec.get(b)) {
            let (first, second) = (sec.full(a), sec.full(b));
            return Err(self.bad(ErrorKind::Conflict, sec, got, format!("give either {first} or {second}, not both ({why})")));
        }
        Ok(())
    }

    /// An angle or angular rate in radians from `key` or degrees from `key_deg`.
    fn angle(&self, sec: &Sec<'_>, key: &str, what: &str) -> Result<Option<f64>> {
        let deg = format!("{key}_deg");
        self.exclusive(sec, key, &deg, "radians or degrees")?;
        if let Some((v, _)) = self.number(sec, key, what)? {
            return Ok(Some(v));
        }
        Ok(self.number(sec, &deg, what)?.map(|(v, _)| v.to_radians()))
    }
}

impl<'t> Sec<'t> {
    fn get(&self, key: &str) -> Option<Got<'t>> {
        self.node.entries().iter().find(|e| e.key == key).map(|entry| Got { key: entry.key.as_str(), entry })
    }

    fn full(&self, key: &str) -> String {
        if self.path.is_empty() { key.to_owned() } else { format!("{}.{key}", self.path) }
    }
}

fn quoted(choices: &[&str]) -> String {
    choices.iter().map(|c| format!("\"{c}\"")).collect::<Vec<_>>().join(", ")
}

/// The allowed name closest to `key` in edit distance, if close enough to be a typo.
fn suggest<'c>(key: &str, allowed: &[&'c str]) -> Option<&'c str> {
    let limit = (key.chars().count() / 3).clamp(1, 3);
    allowed.iter().map(|c| (levenshtein(&key.to_lowercase(), c), *c)).filter(|(d, _)| *d <= limit).min_by_key(|(d, _)| *d).map(|(_, c)| c)
}

/// Edit distance (insertions, deletions, substitutions) between two strings.
fn levenshtein(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut diag = row[0];
        row[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let next = (diag + usize::from(ca != *cb)).min(row[j] + 1).min(row[j + 1] + 1);
            diag = row[j + 1];
            row[j + 1] = next;
        }
    }
    row[b.len()]
}

// ---------------------------------------------------------------------------------
// The format.

const CHECK_KEYS: [&str; 7] = ["status", "energy", "energy_plus_work", "momentum", "angular_momentum_z", "axial_spin", "jellett"];

/// An empty table standing in for an optional table that is absent.
static EMPTY: Node = Node { value: Value::Table(Vec::new()), origin: Origin::File(0..0) };

fn build(ctx: &Ctx<'_>, tree: &Node) -> Result<(Scene, Check)> {
    let root = ctx.table_of("", tree, &tree.origin, &TOP_KEYS, "the scenario")?;
    let body = read_body(ctx, tree, &root)?;
    let contact = read_contact(ctx, &root)?;
    let initial = read_initial(ctx, &root, contact)?;
    let (gravity, effects) = read_effects(ctx, &root)?;
    let solver = read_solver(ctx, &root)?;
    let (t_end, sample_times) = read_output(ctx, &root)?;
    let check = read_check(ctx, &root)?;
    let scene = Scene { body, gravity, contact, effects, initial, solver, t_end, sample_times };
    scene.validate().map_err(|e| ctx.model(tree, &e))?;
    Ok((scene, check))
}

fn read_body(ctx: &Ctx<'_>, tree: &Node, root: &Sec<'_>) -> Result<Body> {
    let sec = ctx
        .section(root, "body", &BODY_KEYS, "semi-axes, mass, centre of mass, inertia")?
        .ok_or_else(|| ctx.missing(root, "body", "a scenario needs a [body] table (semi-axes a and c, mass, inertia)"))?;
    let a = ctx.required(&sec, "a", "the semi-axis along body x (m)")?;
    let b = ctx.number(&sec, "b", "the semi-axis along body y (m)")?.map_or(a, |(v, _)| v);
    let c = ctx.required(&sec, "c", "the semi-axis along the symmetry axis, body z (m)")?;
    let mass = ctx.required(&sec, "mass", "the mass (kg)")?;
    ctx.exclusive(&sec, "com_offset", "com_offset_vector", "the distance D2 of G below the centre on the axis, or the general vector G − C0")?;
    let com = if let Some((d2, _)) = ctx.number(&sec, "com_offset", "D2, the distance of G below the geometric centre along body z (m)")? {
        Vector3::new(0.0, 0.0, -d2)
    } else if let Some(v) = ctx.numbers::<3>(&sec, "com_offset_vector", "G − C0 in body axes (m)")? {
        Vector3::from(v)
    } else {
        Vector3::zeros()
    };
    let axes = Vector3::new(a, b, c);
    let inertia = read_inertia(ctx, &sec, axes, mass, com)?;
    Body::new(axes, mass, inertia, com).map_err(|e| ctx.model(tree, &e))
}

fn read_inertia(ctx: &Ctx<'_>, sec: &Sec<'_>, axes: Vector3<f64>, mass: f64, com: Vector3<f64>) -> Result<Matrix3<f64>> {
    const FORMS: &str = "[I1, I2, I3] (principal moments about G, kg m^2), a symmetric 3x3 array [[..], [..], [..]], or \"uniform\"";
    let got = sec.get("inertia").ok_or_else(|| ctx.missing(sec, "inertia", format!("give the central inertia in body axes: {FORMS}")))?;
    let numbers = |items: &[Node]| items.iter().map(Node::as_f64).collect::<Option<Vec<f64>>>();
    match &got.node().value {
        Value::Str(s) if s == "uniform" => {
            if com != Vector3::zeros() {
                return Err(ctx.bad(
                    ErrorKind::Invalid,
                    sec,
                    got,
                    "\"uniform\" is a homogeneous body, whose centre of mass is the geometric centre; with a centre-of-mass offset give the moments about G",
                ));
            }
            Ok(uniform_inertia(axes, mass))
        }
        Value::Array(items) if items.len() == 3 => {
            if let Some(d) = numbers(items) {
                return Ok(Matrix3::from_diagonal(&Vector3::new(d[0], d[1], d[2])));
            }
            let rows: Option<Vec<Vec<f64>>> = items
                .iter()
                .map(|row| match &row.value {
                    Value::Array(r) if r.len() == 3 => numbers(r),
                    _ => None,
                })
                .collect();
            match rows {
                Some(r) => Ok(Matrix3::from_fn(|i, j| r[i][j])),
                None => Err(ctx.bad(ErrorKind::Type, sec, got, format!("expected {FORMS}"))),
            }
        }
        _ => Err(ctx.bad(ErrorKind::Type, sec, got, format!("expected {FORMS}"))),
    }
}

fn read_contact(ctx: &Ctx<'_>, root: &Sec<'_>) -> Result<ContactModel> {
    let models = quoted(&CONTACT_MODELS);
    let sec = ctx
        .section(root, "contact", &CONTACT_KEYS, "model and friction")?
        .ok_or_else(|| ctx.missing(root, "contact", format!("a scenario needs a [contact] table with model = {models}")))?;
    let (model, _) = ctx.choice(&sec, "model", &CONTACT_MODELS)?.ok_or_else(|| ctx.missing(&sec, "model", format!("give the contact model, one of {models}")))?;
    let friction = ctx.checked(&sec, "friction", "μ, the Coulomb coefficient", |v| v >= 0.0, "the Coulomb coefficient must be finite and non-negative")?;
    let need = || ctx.missing(&sec, "friction", format!("the {model} model needs μ, the Coulomb friction coefficient (e.g. friction = 0.3)"));
    Ok(match model {
        "frictionless" | "rolling" => {
            if let Some(got) = sec.get("friction") {
                let why = if model == "rolling" { "rolling assumes unlimited friction" } else { "the plane exerts no friction" };
                return Err(ctx.bad(ErrorKind::Invalid, &sec, got, format!("the {model} model takes no friction coefficient ({why}); remove it, or use model = \"coulomb\"")));
            }
            if model == "rolling" { ContactModel::Rolling } else { ContactModel::Frictionless }
        }
        "sliding" => ContactModel::Sliding { friction: friction.ok_or_else(need)? },
        _ => ContactModel::Coulomb { friction: friction.ok_or_else(need)? },
    })
}

fn read_initial(ctx: &Ctx<'_>, root: &Sec<'_>, contact: ContactModel) -> Result<InitialState> {
    let sec = ctx.section(root, "initial", &INITIAL_KEYS, "initial angles, rates, position and velocity")?.unwrap_or(Sec { path: "initial".into(), node: &EMPTY });
    let orientation = if let Some(got) = sec.get("rotation") {
        for key in ["theta", "phi", "psi"] {
            for k in [key.to_owned(), format!("{key}_deg")] {
                if sec.get(&k).is_some() {
                    return Err(ctx.bad(ErrorKind::Conflict, &sec, got, format!("give either {} or the Euler angles (here {}), not both", sec.full("rotation"), sec.full(&k))));
                }
            }
        }
        let r = read_rotation(ctx, &sec, got)?;
        let e = EulerAngles::from_rotation(r.to_rotation_matrix().matrix(), &Vector3::zeros(), None);
        (e.theta, e.phi, e.psi)
    } else {
        (
            ctx.angle(&sec, "theta", "θ, the tilt of the symmetry axis from the vertical (rad)")?.unwrap_or(0.0),
            ctx.angle(&sec, "phi", "φ, the precession angle (rad)")?.unwrap_or(0.0),
            ctx.angle(&sec, "psi", "ψ, the spin angle (rad)")?.unwrap_or(0.0),
        )
    };
    ctx.exclusive(&sec, "omega_body", "omega_body_deg", "radians or degrees per second")?;
    let omega = match ctx.numbers::<3>(&sec, "omega_body", "the body angular velocity (rad/s)")? {
        Some(w) => Some(Vector3::from(w)),
        None => ctx.numbers::<3>(&sec, "omega_body_deg", "the body angular velocity (deg/s)")?.map(|w| Vector3::from(w).map(f64::to_radians)),
    };
    let mut rates = [0.0; 3];
    for (rate, key) in rates.iter_mut().zip(["theta_dot", "phi_dot", "psi_dot"]) {
        if let Some(got) = [key.to_owned(), format!("{key}_deg")].iter().find_map(|k| sec.get(k)).filter(|_| omega.is_some()) {
            let body_key = if sec.get("omega_body").is_some() { "omega_body" } else { "omega_body_deg" };
            return Err(ctx.bad(ErrorKind::Conflict, &sec, got, format!("give either {} or the Euler-angle rates, not both", sec.full(body_key))));
        }
        *rate = ctx.angle(&sec, key, "an Euler-angle rate (rad/s)")?.unwrap_or(0.0);
    }
    let (theta, phi, psi) = orientation;
    let angles = EulerAngles { theta, phi, psi, theta_dot: rates[0], phi_dot: rates[1], psi_dot: rates[2] };
    let position = ctx.numbers::<2>(&sec, "position", "x, y of G (m)")?.map_or_else(Vector2::zeros, Vector2::from);
    let velocity = ctx.numbers::<2>(&sec, "velocity", "the horizontal velocity of G (m/s)")?.map(Vector2::from);
    if let (Some(_), ContactModel::Rolling) = (velocity, contact) {
        let got = sec.get("velocity").expect("just read");
        return Err(ctx.bad(ErrorKind::Invalid, &sec, got, "not allowed for the rolling model, where the velocity of G is implied by ω (v_G = −ω × r); remove it"));
    }
    for (name, v) in [("position", position.as_slice()), ("velocity", velocity.as_ref().map_or(&[][..], |v| v.as_slice())), ("omega_body", omega.as_ref().map_or(&[][..], |v| v.as_slice()))] {
        if v.iter().any(|x| !x.is_finite()) {
            let got = sec.get(name).or_else(|| sec.get(&format!("{name}_deg"))).expect("a value was read");
            return Err(ctx.bad(ErrorKind::Invalid, &sec, got, "every component must be finite"));
        }
    }
    Ok(InitialState { angles, omega_body: omega, position, velocity })
}

/// `rotation = [{ axis = "x", angle = … }, …]`: R = R1 R2 … (body → world).
fn read_rotation(ctx: &Ctx<'_>, sec: &Sec<'_>, got: Got<'_>) -> Result<UnitQuaternion<f64>> {
    const FORM: &str = "an array of { axis = \"x\" | \"y\" | \"z\", angle = rad (or angle_deg) } tables, composed as R = R1 R2 …";
    let Value::Array(items) = &got.node().value else { return Err(ctx.wrong_type(sec, got, FORM)) };
    let mut q = UnitQuaternion::identity();
    for (i, item) in items.iter().enumerate() {
        let path = format!("{}[{i}]", sec.full("rotation"));
        let rot = ctx.table_of(&path, item, &item.origin, &["axis", "angle", "angle_deg"], FORM)?;
        let (axis, _) = ctx.choice(&rot, "axis", &["x", "y", "z"])?.ok_or_else(|| ctx.missing(&rot, "axis", "give the axis, \"x\", \"y\" or \"z\" (world and body axes coincide before the rotation)"))?;
        let angle = ctx.angle(&rot, "angle", "the rotation angle (rad)")?.ok_or_else(|| ctx.missing(&rot, "angle", "give the angle in radians (angle) or degrees (angle_deg)"))?;
        if !angle.is_finite() {
            return Err(ctx.bad(ErrorKind::Invalid, &rot, rot.get("angle").or_else(|| rot.get("angle_deg")).expect("just read"), "the angle must be finite"));
        }
        let axis = match axis {
            "x" => Vector3::x_axis(),
            "y" => Vector3::y_axis(),
            _ => Vector3::z_axis(),
        };
        q *= UnitQuaternion::from_axis_angle(&axis, angle);
    }
    Ok(q)
}

fn read_effects(ctx: &Ctx<'_>, root: &Sec<'_>) -> Result<(f64, EffectSet)> {
    let Some(sec) = ctx.section(root, "effects", &EFFECT_KEYS, "gravity and optional dissipation")? else {
        return Ok((DEFAULT_GRAVITY, EffectSet::default()));
    };
    let gravity = ctx.checked(&sec, "gravity", "g (m/s^2)", |v| v >= 0.0, "g must be finite and non-negative (m/s^2)")?.unwrap_or(DEFAULT_GRAVITY);
    let rolling_resistance = resistance(ctx, &sec, "rolling_resistance", "c_r, the rolling-resistance length (m)")?.map(|(coefficient, regularisation)| RollingResistance { coefficient, regularisation });
    let spin_friction = resistance(ctx, &sec, "spin_friction", "c_s, the spin-friction length (m)")?.map(|(coefficient, regularisation)| SpinFriction { coefficient, regularisation });
    let air_drag = match ctx.section(&sec, "air_drag", &["linear", "angular"], "{ linear = k (kg/s), angular = k_ω (kg m^2/s) }")? {
        Some(d) => {
            let linear = ctx.checked(&d, "linear", "k, the linear drag coefficient (kg/s)", |v| v >= 0.0, "the drag coefficient must be finite and non-negative (kg/s)")?;
            let angular = ctx.checked(&d, "angular", "k_ω, the angular drag coefficient (kg m^2/s)", |v| v >= 0.0, "the drag coefficient must be finite and non-negative (kg m^2/s)")?;
            Some(AirDrag { linear: linear.unwrap_or(0.0), angular: angular.unwrap_or(0.0) })
        }
        None => None,
    };
    Ok((gravity, EffectSet { air_drag, rolling_resistance, spin_friction }))
}

/// `key = c` or `key = { coefficient = c, regularisation = ε }` → (c, ε).
fn resistance(ctx: &Ctx<'_>, sec: &Sec<'_>, key: &str, what: &str) -> Result<Option<(f64, f64)>> {
    const RULE: &str = "the coefficient must be finite and non-negative (m)";
    let Some(got) = sec.get(key) else { return Ok(None) };
    if let Some(c) = got.node().as_f64() {
        if !(c.is_finite() && c >= 0.0) {
            return Err(ctx.bad(ErrorKind::Invalid, sec, got, RULE));
        }
        return Ok(Some((c, DEFAULT_REGULARISATION)));
    }
    let form = format!("a number {what}, or {{ coefficient = c (m), regularisation = ε (rad/s) }}");
    let sub = ctx.table_of(&sec.full(key), got.node(), &got.entry.key_origin, &["coefficient", "regularisation"], &form)?;
    let c = ctx.checked(&sub, "coefficient", what, |v| v >= 0.0, RULE)?.ok_or_else(|| ctx.missing(&sub, "coefficient", format!("give {what}")))?;
    let eps = ctx
        .checked(&sub, "regularisation", "ε, the regularisation rate (rad/s)", |v| v > 0.0, "the regularisation must be positive and finite (rad/s)")?
        .unwrap_or(DEFAULT_REGULARISATION);
    Ok(Some((c, eps)))
}

fn read_solver(ctx: &Ctx<'_>, root: &Sec<'_>) -> Result<SolverSettings> {
    let sec = ctx.section(root, "solver", &SOLVER_KEYS, "method, tolerances and step")?.unwrap_or(Sec { path: "solver".into(), node: &EMPTY });
    let method = ctx.choice(&sec, "method", &METHODS)?.map_or(DEFAULT_METHOD, |(m, _)| m);
    let rtol = ctx
        .checked(&sec, "rtol", "the relative tolerance", |v| v >= 10.0 * f64::EPSILON, "the relative tolerance must be finite and at least 10·EPS ≈ 2.2e-15")?
        .unwrap_or(DEFAULT_RTOL);
    let atol = ctx.checked(&sec, "atol", "the absolute tolerance", |v| v > 0.0, "the absolute tolerance must be positive and finite")?.unwrap_or(DEFAULT_ATOL);
    let step = ctx.checked(&sec, "step", "the step (s)", |v| v > 0.0, "the step must be positive and finite (s)")?;
    let max_steps = ctx
        .checked(&sec, "max_steps", "the most steps per run segment", |v| v >= 1.0 && v.fract() == 0.0 && v < u64::MAX as f64, "must be a whole number of at least 1")?
        .map_or(DEFAULT_MAX_STEPS, |v| v as u64);
    let (method, initial_step) = match method {
        "rk4" => {
            let h = step.ok_or_else(|| ctx.missing(&sec, "step", "the rk4 method needs its fixed step (s), e.g. step = 1e-4"))?;
            (Method::Rk4 { h }, None)
        }
        "dopri5" => (Method::Dopri5, step),
        _ => (Method::Dop853, step),
    };
    Ok(SolverSettings { method, rtol, atol, initial_step, max_steps })
}

fn read_output(ctx: &Ctx<'_>, root: &Sec<'_>) -> Result<(f64, Vec<f64>)> {
    let sec = ctx
        .section(root, "output", &OUTPUT_KEYS, "end time and sampling")?
        .ok_or_else(|| ctx.missing(root, "output", "a scenario needs an [output] table with t_end and dt (or times)"))?;
    let t_end = ctx
        .checked(&sec, "t_end", "the end time (s)", |v| v > 0.0, "the end time must be positive and finite (s)")?
        .ok_or_else(|| ctx.missing(&sec, "t_end", "give the end time of the run (s)"))?;
    ctx.exclusive(&sec, "dt", "times", "a sampling interval or explicit output times")?;
    if let Some(dt) = ctx.checked(&sec, "dt", "the sampling interval (s)", |v| v > 0.0, "the sampling interval must be positive and finite (s)")? {
        let times = grid(t_end, dt).map_err(|n| {
            ctx.bad(ErrorKind::Invalid, &sec, sec.get("dt").expect("just read"), format!("t_end / dt asks for {n:.3e} samples; at most {MAX_SAMPLES} are allowed (raise dt)"))
        })?;
        return Ok((t_end, times));
    }
    let got = sec.get("times").ok_or_else(|| ctx.missing(&sec, "dt", "give the sampling interval dt (s), or explicit output times = [t1, t2, …]"))?;
    const FORM: &str = "an array of output times (s)";
    let Value::Array(items) = &got.node().value else { return Err(ctx.wrong_type(&sec, got, FORM)) };
    let times = items.iter().map(Node::as_f64).collect::<Option<Vec<f64>>>().ok_or_else(|| ctx.wrong_type(&sec, got, FORM))?;
    if times.is_empty() {
        return Err(ctx.bad(ErrorKind::Invalid, &sec, got, "give at least one output time"));
    }
    if times.len() > MAX_SAMPLES {
        return Err(ctx.bad(ErrorKind::Invalid, &sec, got, format!("at most {MAX_SAMPLES} output times are allowed")));
    }
    Ok((t_end, times))
}

/// t = k·dt for k = 0, 1, … while ≤ t_end, plus t_end itself if it is not on the grid
/// (a time within 1e-9·k·dt of t_end counts as t_end). Err(count) when too many.
fn grid(t_end: f64, dt: f64) -> std::result::Result<Vec<f64>, f64> {
    let ratio = t_end / dt;
    if ratio >= MAX_SAMPLES as f64 {
        return Err(ratio);
    }
    let nearest = ratio.round();
    let on_grid = nearest >= 1.0 && (ratio - nearest).abs() <= 1e-9 * nearest;
    let n = if on_grid { nearest as usize } else { ratio.floor() as usize + 1 };
    let mut times: Vec<f64> = (0..n).map(|k| k as f64 * dt).collect();
    times.push(t_end);
    Ok(times)
}

fn read_check(ctx: &Ctx<'_>, root: &Sec<'_>) -> Result<Check> {
    let Some(sec) = ctx.section(root, "check", &CHECK_KEYS, "expected status and invariant tolerances")? else { return Ok(Check::default()) };
    let status = ctx.choice(&sec, "status", &STATUS_NAMES)?.map(|(s, _)| s.to_owned());
    let mut drift = BTreeMap::new();
    for name in DRIFT_NAMES {
        if let Some(tol) = ctx.checked(&sec, name, "the largest allowed relative drift", |v| v >= 0.0, "a tolerance must be finite and non-negative")? {
            drift.insert(name.to_owned(), tol);
        }
    }
    Ok(Check { status, drift })
}

#[cfg(test)]
mod tests {
    use super::*;

    const PAPER: &str = r#"# the brief's example
[body]
a = 0.025
c = 0.0175
mass = 0.05
com_offset = 0.003
inertia = [3.8e-6, 3.8e-6, 6.25e-6]

[initial]
theta = 0.1745
psi_dot = 60.0

[contact]
model = "frictionless"

[solver]
method = "dopri5"
rtol = 1e-10
atol = 1e-12

[output]
t_end = 10.0
dt = 1e-3
"#;

    fn ok(text: &str, sets: &[&str]) -> Scenario {
        parse(text, "x.toml", sets).unwrap_or_else(|e| panic!("{e}"))
    }

    fn err(text: &str, sets: &[&str]) -> String {
        parse(text, "x.toml", sets).expect_err("should be rejected").to_string()
    }

    /// `PAPER` with `old` replaced by `new` (which must occur).
    fn edit(old: &str, new: &str) -> String {
        assert!(PAPER.contains(old), "{old}");
        PAPER.replacen(old, new, 1)
    }

    #[test]
    fn reads_the_example_scene() {
        let s = ok(PAPER, &[]);
        let scene = &s.scene;
        assert_eq!(scene.body.semi_axes(), Vector3::new(0.025, 0.025, 0.0175));
        assert_eq!(scene.body.com_offset(), Vector3::new(0.0, 0.0, -0.003));
        assert_eq!(scene.body.inertia()[(2, 2)], 6.25e-6);
        assert_eq!(scene.gravity, DEFAULT_GRAVITY);
        assert_eq!(scene.contact, ContactModel::Frictionless);
        assert_eq!(scene.initial.angles.theta, 0.1745);
        assert_eq!(scene.initial.angles.psi_dot, 60.0);
        assert_eq!(scene.initial.velocity, None);
        assert_eq!(scene.solver.method, Method::Dopri5);
        assert_eq!(scene.sample_times.len(), 10_001);
        assert_eq!(scene.sample_times[1], 1e-3);
        assert_eq!(*scene.sample_times.last().unwrap(), 10.0);
        assert_eq!(s.stem(), "x");
        assert_eq!(s.check, Check::default());
    }

    #[test]
    fn sampling_grid_ends_at_t_end() {
        assert_eq!(grid(0.3, 0.1).unwrap(), vec![0.0, 0.1, 0.2, 0.3]);
        assert_eq!(grid(1.0, 0.3).unwrap(), vec![0.0, 0.3, 0.6, 0.8999999999999999, 1.0]);
        assert_eq!(grid(0.5, 2.0).unwrap(), vec![0.0, 0.5]);
        assert!(grid(1.0, 1e-9).is_err());
    }

    #[test]
    fn degree_twins_convert_and_exclude_each_other() {
        let s = ok(&edit("theta = 0.1745", "theta_deg = 10\nphi_dot_deg = 180"), &[]);
        assert_eq!(s.scene.initial.angles.theta, 10f64.to_radians());
        assert_eq!(s.scene.initial.angles.phi_dot, std::f64::consts::PI);
        let msg = err(&edit("theta = 0.1745", "theta = 0.1745\ntheta_deg = 10"), &[]);
        assert_eq!(msg, "x.toml:11:1: initial.theta_deg = 10: give either initial.theta or initial.theta_deg, not both (radians or degrees)");
    }

    #[test]
    fn errors_name_file_line_column_key_value_and_rule() {
        let cases = [
            (edit("mass = 0.05", "mass = -0.05"), "x.toml:5:1: body.mass = -0.05: the mass must be positive and finite (kg)"),
            (edit("mass = 0.05", "mass = \"heavy\""), "x.toml:5:1: body.mass = \"heavy\": expected a number: the mass (kg), found a string"),
            (edit("mass = 0.05\n", ""), "x.toml:2:1: body.mass is missing: give the mass (kg)"),
            (edit("mass = 0.05", "mas = 0.05"), "x.toml:5:1: body.mas = 0.05: unknown key in [body]; did you mean `mass`?"),
            (edit("[solver]", "[solvr]"), "x.toml:16:2: solvr: unknown table at the top level; did you mean `solver`?"),
            (edit("\"frictionless\"", "\"frictionles\""), "x.toml:14:1: contact.model = \"frictionles\": expected one of \"frictionless\", \"sliding\", \"rolling\", \"coulomb\"; did you mean \"frictionless\"?"),
            (edit("\"frictionless\"", "\"sliding\""), "x.toml:13:1: contact.friction is missing: the sliding model needs μ, the Coulomb friction coefficient (e.g. friction = 0.3)"),
            (edit("t_end = 10.0", "t_end = 0"), "x.toml:22:1: output.t_end = 0: the end time must be positive and finite (s)"),
            (edit("com_offset = 0.003", "com_offset = 0.02"), "x.toml:6:1: body.com_offset = [0, 0, -0.02]: the centre of mass must lie inside the ellipsoid (g^T A^-2 g = 1.306122 must be < 1)"),
            (edit("3.8e-6, 3.8e-6", "1e-6, 1e-6"), "x.toml:7:1: body.inertia = [0.000001, 0.000001, 0.00000625]: principal moments must satisfy the triangle inequality (each at most the sum of the other two)"),
            (edit("inertia = [3.8e-6, 3.8e-6, 6.25e-6]", "inertia = \"uniform\""), "x.toml:7:1: body.inertia = \"uniform\": \"uniform\" is a homogeneous body, whose centre of mass is the geometric centre; with a centre-of-mass offset give the moments about G"),
            (edit("method = \"dopri5\"", "method = \"rk4\""), "x.toml:16:1: solver.step is missing: the rk4 method needs its fixed step (s), e.g. step = 1e-4"),
            (edit("psi_dot = 60.0", "psi_dot = 60.0\nvelocity = [1, 0]"), "x.toml:12:1: initial.velocity = [1, 0]: not allowed for the rolling model, where the velocity of G is implied by ω (v_G = −ω × r); remove it"),
            (edit("dt = 1e-3", "dt = 1e-3\ntimes = [1.0]"), "x.toml:24:1: output.times = [1.0]: give either output.dt or output.times, not both (a sampling interval or explicit output times)"),
            (edit("t_end = 10.0", "t_end = 10.0.0"), "x.toml:22:13: TOML syntax error: invalid float, expected nothing"),
        ];
        let mut failures = Vec::new();
        for (i, (text, expected)) in cases.iter().enumerate() {
            let text = if expected.contains("rolling model") { text.replace("\"frictionless\"", "\"rolling\"") } else { text.clone() };
            let got = err(&text, &[]);
            if &got != expected {
                failures.push(format!("case {i}:\n  got      {got}\n  expected {expected}"));
            }
        }
        assert!(failures.is_empty(), "{}", failures.join("\n"));
    }

    #[test]
    fn overrides_apply_before_validation() {
        let s = ok(PAPER, &["output.t_end=0.5", "contact.model=rolling", "effects.gravity = 1.62", "initial.position=[1, 2]"]);
        assert_eq!(s.scene.t_end, 0.5);
        assert_eq!(*s.scene.sample_times.last().unwrap(), 0.5);
        assert_eq!(s.scene.contact, ContactModel::Rolling);
        assert_eq!(s.scene.gravity, 1.62);
        assert_eq!(s.scene.initial.position, Vector2::new(1.0, 2.0));
        assert_eq!(s.text, PAPER);
        assert_eq!(err(PAPER, &["body.mass=-1"]), "x.toml: --set body.mass=-1: body.mass = -1: the mass must be positive and finite (kg)");
        assert_eq!(err(PAPER, &["body.mas=1"]), "x.toml: --set body.mas=1: body.mas = 1: unknown key in [body]; did you mean `mass`?");
        assert_eq!(err(PAPER, &["body.mass"]), "x.toml: --set body.mass: an override must have the form key=value, e.g. --set output.t_end=1.0");
        assert_eq!(err(PAPER, &["body.mass.x=1"]), "x.toml: --set body.mass.x=1: body.mass: is not a table, so body.mass.x cannot be set");
        assert!(err(PAPER, &["body.mass=[1,"]).starts_with("x.toml: --set body.mass=[1,: body.mass = [1,: not a TOML value"));
    }

    #[test]
    fn inertia_forms() {
        let full = ok(&edit("[3.8e-6, 3.8e-6, 6.25e-6]", "[[3.8e-6, 1e-7, 0], [1e-7, 3.8e-6, 0], [0, 0, 6.25e-6]]"), &[]);
        assert_eq!(full.scene.body.inertia()[(0, 1)], 1e-7);
        let uniform = ok(&edit("com_offset = 0.003\ninertia = [3.8e-6, 3.8e-6, 6.25e-6]", "inertia = \"uniform\""), &[]);
        assert_eq!(*uniform.scene.body.inertia(), uniform_inertia(Vector3::new(0.025, 0.025, 0.0175), 0.05));
        let vector = ok(&edit("com_offset = 0.003", "com_offset_vector = [0.001, 0, -0.003]"), &[]);
        assert_eq!(vector.scene.body.com_offset(), Vector3::new(0.001, 0.0, -0.003));
    }

    #[test]
    fn rotation_composes_left_to_right() {
        let s = ok(&edit("theta = 0.1745", "rotation = [{ axis = \"x\", angle_deg = 0.5 }, { axis = \"y\", angle = 0.01 }]"), &[]);
        let expected = UnitQuaternion::from_axis_angle(&Vector3::x_axis(), 0.5f64.to_radians()) * UnitQuaternion::from_axis_angle(&Vector3::y_axis(), 0.01);
        assert!(s.scene.initial.angles.rotation().angle_to(&expected) < 1e-14);
        let msg = err(&edit("theta = 0.1745", "theta = 0.1\nrotation = []"), &[]);
        assert!(msg.starts_with("x.toml:11:1: initial.rotation = []: give either initial.rotation or the Euler angles"), "{msg}");
        let msg = err(&edit("theta = 0.1745", "rotation = [{ axis = \"w\", angle = 1 }]"), &[]);
        assert!(msg.starts_with("x.toml:10:15: initial.rotation[0].axis = \"w\": expected one of \"x\", \"y\", \"z\""), "{msg}");
    }

    #[test]
    fn effects_and_check_tables() {
        let s = ok(
            &format!(
                "{PAPER}\n[effects]\ngravity = 9.8\nrolling_resistance = 1e-4\nspin_friction = {{ coefficient = 2e-4, regularisation = 1e-2 }}\nair_drag = {{ linear = 0.1 }}\n[check]\nstatus = \"completed\"\nenergy = 1e-9\n"
            ),
            &[],
        );
        let e = s.scene.effects;
        assert_eq!(s.scene.gravity, 9.8);
        assert_eq!(e.rolling_resistance, Some(RollingResistance { coefficient: 1e-4, regularisation: DEFAULT_REGULARISATION }));
        assert_eq!(e.spin_friction, Some(SpinFriction { coefficient: 2e-4, regularisation: 1e-2 }));
        assert_eq!(e.air_drag, Some(AirDrag { linear: 0.1, angular: 0.0 }));
        assert_eq!(s.check.status.as_deref(), Some("completed"));
        assert_eq!(s.check.drift.get("energy"), Some(&1e-9));
        let msg = err(&format!("{PAPER}\n[effects]\nspin_friction = {{ coefficent = 1 }}\n"), &[]);
        assert_eq!(msg, "x.toml:26:19: effects.spin_friction.coefficent = 1: unknown key in [effects.spin_friction]; did you mean `coefficient`?");
    }

    #[test]
    fn physics_errors_found_later_are_located() {
        let s = ok(PAPER, &[]);
        let e = s.locate(&ModelError::invalid("initial state", "N = -1 N", "the plane must push"));
        assert_eq!(e.to_string(), "x.toml:9:2: initial state = N = -1 N: the plane must push");
        let e = s.locate(&ModelError::invalid("contact.friction", 0.3, "r"));
        assert_eq!(e.location.line, Some(13), "falls back to the table");
    }

    #[test]
    fn unreadable_file_is_an_io_error() {
        let e = load(Path::new("/nonexistent/x.toml"), &[] as &[&str]).unwrap_err();
        assert_eq!(e.kind, ErrorKind::Io);
        assert!(e.to_string().starts_with("/nonexistent/x.toml: cannot read the scenario file: "), "{e}");
    }

    #[test]
    fn suggestions_need_a_small_edit_distance() {
        assert_eq!(levenshtein("kitten", "sitting"), 3);
        assert_eq!(suggest("gravty", &EFFECT_KEYS), Some("gravity"));
        assert_eq!(suggest("zzz", &EFFECT_KEYS), None);
    }
}
