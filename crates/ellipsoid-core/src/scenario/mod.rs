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
use std::sync::Arc;

use nalgebra::{Matrix3, UnitQuaternion, Vector2, Vector3};
use serde::Serialize;
use toml::de::{DeTable, DeValue};

use crate::body::{Body, MAX_NAME, MAX_RIMS, MAX_SPHERES, Rim, Sphere, uniform_inertia};
use crate::columns::Layout;
use crate::effects::{
    AirBoundaryLayer, AirDrag, AirFilm, RollingFriction, RollingResistance, SpinFriction,
};
use crate::error::{ModelError, number};
use crate::geometry;
use crate::integrate::{Direction, Method};
use crate::model::{ContactDisc, contensou};
use crate::simulate::{
    ContactModel, EffectSet, InitialState, Landing, LiftOff, MAX_OBSERVE, MAX_SECTION_POINTS,
    MAX_SECTIONS, MAX_VISCOUS_FRICTION, Observe, Scene, Section, SolverSettings,
};
use crate::state::EulerAngles;

mod collect;
mod file;
mod format;
mod path;
pub mod plausibility;
mod reader;
pub mod schema;
#[cfg(test)]
mod tests;
mod tree;

pub use collect::MAX_ERRORS;
use collect::*;
pub use file::{MAX_SCENARIO_BYTES, open_regular, read_bounded};
use format::*;
pub use path::{KEY_RULE, KeyPath, MAX_INDEX, PathError, Seg};
pub use plausibility::{Warning, warnings};
use reader::*;
use schema::{DIRECTIONS, ROTATION_AXES, keys};
use tree::*;
pub use tree::{Blocked, SetError};

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
/// The invariants a `[check]` table may bound (declared in `invariants::Invariant`).
pub const DRIFT_NAMES: [&str; 6] = crate::invariants::Invariant::NAMES;
/// The run statuses a `[check]` table may expect (declared in `simulate::Status`).
pub const STATUS_NAMES: [&str; 13] = crate::simulate::Status::NAMES;
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
            write!(f, ": --set {}", cut(set))?;
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
    /// One line; keys (which may be as long as the file) cut like values, numbers short.
    fn render(&self) -> String {
        let loc = &self.location;
        let rule = crate::error::shorten_numbers(&self.rule);
        match (
            self.key.as_deref().map(cut),
            self.value.as_deref().map(crate::error::shorten_numbers),
            self.kind,
        ) {
            (Some(k), _, ErrorKind::Missing) => format!("{loc}: {k} is missing: {rule}"),
            (Some(k), Some(v), _) => format!("{loc}: {k} = {v}: {rule}"),
            (Some(k), None, _) => format!("{loc}: {k}: {rule}"),
            (None, _, _) => format!("{loc}: {rule}"),
        }
    }
}

/// `text` on one line and at most 60 characters, as messages show keys and values.
pub(crate) fn cut(text: &str) -> String {
    let mut chars = text.chars().map(|c| if c.is_control() { ' ' } else { c });
    let head: String = chars.by_ref().take(60).collect();
    if chars.next().is_some() {
        format!("{}…", head.chars().take(59).collect::<String>())
    } else {
        head
    }
}

/// Every independent error of one scenario (at least one, at most [`MAX_ERRORS`]), in
/// file order; displays as one line per error.
#[derive(Debug, Clone, PartialEq, thiserror::Error, Serialize)]
#[error("{}", self.0.iter().map(ToString::to_string).collect::<Vec<_>>().join("\n"))]
pub struct ScenarioErrors(pub Vec<ScenarioError>);

impl ScenarioErrors {
    /// The first error in the file.
    pub fn first(self) -> ScenarioError {
        self.0.into_iter().next().expect("at least one error")
    }
}

impl From<ScenarioError> for ScenarioErrors {
    fn from(e: ScenarioError) -> Self {
        ScenarioErrors(vec![e])
    }
}

type Result<T> = std::result::Result<T, ScenarioError>;

/// Reads and parses the scenario file at `path`, applying `overrides` (`key=value`).
/// The error is the first in the file; [`load_all`] returns them all.
pub fn load(path: &Path, overrides: &[impl AsRef<str>]) -> Result<Scenario> {
    load_all(path, overrides).map_err(ScenarioErrors::first)
}

/// [`load`] with every independent error of the file, in file order.
pub fn load_all(
    path: &Path,
    overrides: &[impl AsRef<str>],
) -> std::result::Result<Scenario, ScenarioErrors> {
    let source = path.display().to_string();
    let io = |rule: String, line: Option<usize>, column: Option<usize>| ScenarioError {
        kind: if line.is_some() {
            ErrorKind::Syntax
        } else {
            ErrorKind::Io
        },
        location: Location {
            source: source.clone(),
            line,
            column,
            set: None,
        },
        key: None,
        value: None,
        rule,
    };
    let bytes = read_bounded(path, MAX_SCENARIO_BYTES)
        .map_err(|e| io(format!("cannot read the scenario file: {e}"), None, None))?;
    let text = String::from_utf8(bytes).map_err(|e| {
        // Where the first bad byte is: line and column (in characters) of the valid text before it.
        let bytes = e.as_bytes();
        let good = std::str::from_utf8(&bytes[..e.utf8_error().valid_up_to()]).unwrap_or_default();
        let line = good.matches('\n').count() + 1;
        let column = good.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
        let offset = good.len();
        io(format!("the file is not UTF-8 text, as TOML must be: byte 0x{:02x} at offset {offset} does not begin a UTF-8 character (save the file as UTF-8)", bytes[offset]), Some(line), Some(column))
    })?;
    parse_all(&text, &source, overrides)
}

/// Parses scenario `text` (named `source` in messages), applying `overrides` (`key=value`,
/// the value in TOML syntax; a bare word is taken as a string). The error is the first in
/// the file; [`parse_all`] returns them all.
pub fn parse(text: &str, source: &str, overrides: &[impl AsRef<str>]) -> Result<Scenario> {
    parse_all(text, source, overrides).map_err(ScenarioErrors::first)
}

/// [`parse`] with every independent error, in file order (at most [`MAX_ERRORS`]).
pub fn parse_all(
    text: &str,
    source: &str,
    overrides: &[impl AsRef<str>],
) -> std::result::Result<Scenario, ScenarioErrors> {
    Draft::parse(text, source, overrides)?.build()
}

/// A scenario document with changes applied, not yet validated: [`parse_all`] is
/// [`Draft::parse`] then [`Draft::build`]. A study or Python sets typed values in a
/// draft ([`Draft::set`]) rather than writing them as `--set` text.
#[derive(Debug, Clone)]
pub struct Draft {
    text: String,
    source: String,
    /// The changes applied, as `key=value`, in order (they become [`Scenario::overrides`]).
    pub overrides: Vec<String>,
    /// The document after the changes, with spans.
    tree: Node,
}

impl Draft {
    /// Parses scenario `text` (named `source` in messages) and applies `overrides`
    /// (`key=value`, see [`parse`]).
    pub fn parse(
        text: &str,
        source: &str,
        overrides: &[impl AsRef<str>],
    ) -> std::result::Result<Draft, ScenarioErrors> {
        let ctx = Ctx { source, text };
        let doc = DeTable::parse(text).map_err(|e| ctx.syntax(&e, None))?;
        if let Some(span) = wide_integer_table(doc.get_ref()) {
            let literal = text.get(span.clone()).unwrap_or_default();
            return Err(ctx
                .error(
                    ErrorKind::Syntax,
                    &Origin::File(span),
                    None,
                    None,
                    format!("{}: {WIDE_INTEGER}", cut(literal)),
                )
                .into());
        }
        let mut draft = Draft {
            text: text.to_owned(),
            source: source.to_owned(),
            overrides: Vec::new(),
            tree: Node::from_table(doc.into_inner(), Origin::File(0..0)),
        };
        for set in overrides {
            draft.apply(set.as_ref())?;
        }
        Ok(draft)
    }

    /// Applies one `--set` override (`key=value`, the value in TOML syntax or a bare
    /// word) and records it.
    pub fn apply(&mut self, set: &str) -> Result<()> {
        let ctx = Ctx {
            source: &self.source,
            text: &self.text,
        };
        apply_override(&ctx, &mut self.tree, set)?;
        self.overrides.push(set.to_owned());
        Ok(())
    }

    /// Sets `value` at `path` (tables made as needed; an index must name an element that
    /// exists). `label`, the change as `key=value`, names it in messages; it is not
    /// recorded in [`Draft::overrides`], which the caller keeps.
    pub fn set(
        &mut self,
        path: &KeyPath,
        value: &toml::Value,
        label: &str,
    ) -> std::result::Result<(), SetError> {
        set_node(
            &mut self.tree,
            path,
            Node::from_toml(value, &Arc::from(label)),
        )
    }

    /// Sets `value` at the key path `key`, a change named `label` (`key=value`) in
    /// messages and recorded in [`Draft::overrides`]: the typed counterpart of
    /// [`Draft::apply`], with its errors.
    pub fn change(&mut self, key: &str, value: &toml::Value, label: &str) -> Result<()> {
        let path = parse_key(&self.source, label, key)?;
        self.set(&path, value, label)
            .map_err(|e| e.error(&self.source, &path, label))?;
        self.overrides.push(label.to_owned());
        Ok(())
    }

    /// The value at `path`, if the document has one.
    pub fn get(&self, path: &KeyPath) -> Option<toml::Value> {
        self.tree.get(path).map(Node::to_toml)
    }

    /// The document in the `toml` crate's canonical form: the same text for the same
    /// content, whatever the spelling, order or comments of the file and the changes.
    pub fn canonical(&self) -> std::result::Result<String, String> {
        toml::to_string(&self.tree.to_toml()).map_err(|e| e.to_string())
    }

    /// Validates the document into a scenario, or returns every independent error.
    pub fn build(self) -> std::result::Result<Scenario, ScenarioErrors> {
        let ctx = Ctx {
            source: &self.source,
            text: &self.text,
        };
        let (scene, check) = build_all(&ctx, &self.tree).map_err(ScenarioErrors)?;
        Ok(Scenario {
            scene,
            text: self.text,
            source: self.source,
            overrides: self.overrides,
            check,
            tree: self.tree,
        })
    }
}

impl Scenario {
    /// The scenario's document with its changes, to change further.
    pub fn draft(&self) -> Draft {
        Draft {
            text: self.text.clone(),
            source: self.source.clone(),
            overrides: self.overrides.clone(),
            tree: self.tree.clone(),
        }
    }

    /// The file name without its extension (`nutation` for `scenarios/nutation.toml`).
    pub fn stem(&self) -> String {
        Path::new(&self.source).file_stem().map_or_else(
            || "scenario".to_owned(),
            |s| s.to_string_lossy().into_owned(),
        )
    }

    /// Places an error of the physics layer (e.g. from `simulate`) at the key it names:
    /// `body.com_offset` → the `com_offset` or `com_offset_vector` key, `initial state` →
    /// the `[initial]` table, and so on. A quantity derived from several keys (`initial
    /// state`) has no key of its own: when the scenario was changed by `--set`, the
    /// overrides are named too, since one of them may be the cause.
    pub fn locate(&self, err: &ModelError) -> ScenarioError {
        let mut e = Ctx {
            source: &self.source,
            text: &self.text,
        }
        .model(&self.tree, err);
        if e.location.set.is_none() && !self.overrides.is_empty() {
            e.rule = format!(
                "{} (in the scenario as changed by --set {})",
                e.rule,
                self.overrides.join(", --set ")
            );
        }
        e
    }
}
