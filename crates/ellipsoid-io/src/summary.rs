//! The run summary: why the run stopped, what happened, what it cost, how well the
//! invariants held. Serialised as JSON by the CLI (`--summary`) and stored in HDF5 files.

use std::collections::BTreeMap;
use std::sync::Arc;

use ellipsoid_core::body::{Body, Surface};
use ellipsoid_core::error::number;
use ellipsoid_core::integrate::Stats;
use ellipsoid_core::invariants::Invariants;
use ellipsoid_core::scenario::Scenario;
use ellipsoid_core::simulate::{
    Chatter, ContactModel, Drift, EventKind, EventRecord, Outcome, RunWarning, Sample, Scene,
    Status,
};
use serde::Serialize;
use serde::ser::SerializeStruct;
use serde_json::{Map, Value};

use crate::columns;

/// Everything a run reports besides its trajectory. The status, events and final state
/// are the core's typed values; they become JSON only in [`Summary::to_json`] (whose
/// field order and spelling the serialisation below fixes).
#[derive(Debug, Clone)]
pub struct Summary {
    /// Why the run ended (its name is one of `Status::NAMES`).
    pub status: Status,
    /// Why, in a sentence.
    pub message: String,
    /// The located events; serialised each as `{kind, t, …}` ([`event_json`]).
    pub events: Vec<EventRecord>,
    /// Solver work: accepted and rejected steps, right-hand-side calls, events.
    pub stats: Stats,
    /// Wall-clock time of the simulation \[s\].
    pub wall_time_s: f64,
    /// Trajectory rows written.
    pub samples: u64,
    /// The output row where the run ended (serialised as `final`, by column name).
    pub final_sample: Sample,
    /// Largest relative deviation of each invariant; null where it is not conserved.
    pub drift: Drift,
    pub initial_invariants: Invariants,
    pub final_invariants: Invariants,
    pub warnings: Vec<String>,
    /// The scenario's `[check]` expectations and whether the run met them.
    pub checks: BTreeMap<String, CheckResult>,
    /// The scenario file.
    pub scenario: String,
    /// `--set` overrides applied to it.
    pub overrides: Vec<String>,
    /// The trajectory file, if one was written.
    pub output: Option<String>,
    /// Version of the program that ran.
    pub version: String,
    /// The columns of the run (serialised as `units`, and naming the `final` state's).
    pub layout: columns::Layout,
    /// What the events are named by: the body's surfaces and the scene's observables.
    pub(crate) names: Names,
}

/// The names an event's JSON uses: the body's surfaces (by name, for a body with contact
/// spheres) and the scene's observables.
#[derive(Debug, Clone)]
pub(crate) struct Names {
    pub(crate) body: Arc<Body>,
    pub(crate) observables: Vec<String>,
}

impl Names {
    pub(crate) fn of(scene: &Scene) -> Names {
        Names {
            body: Arc::new(scene.body.clone()),
            observables: scene.observe.iter().map(|o| o.name.clone()).collect(),
        }
    }
}

/// One `[check]` expectation against what the run did.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CheckResult {
    /// The tolerance (or the expected status).
    pub expected: Value,
    /// The drift (or status) observed; null if the invariant was not tracked.
    pub actual: Value,
    pub passed: bool,
}

impl Summary {
    /// The summary of `outcome`, a run of `scenario`.
    pub fn new(
        scenario: &Scenario,
        outcome: &Outcome,
        wall_time_s: f64,
        samples: u64,
        output: Option<String>,
        version: &str,
    ) -> Summary {
        let status = outcome.status.name();
        let s = &outcome.final_sample;
        let mut checks = BTreeMap::new();
        if let Some(expected) = &scenario.check.status {
            checks.insert(
                "status".to_owned(),
                CheckResult {
                    expected: Value::from(expected.as_str()),
                    actual: Value::from(status),
                    passed: expected == status,
                },
            );
        }
        for (name, tol) in &scenario.check.drift {
            let actual = outcome
                .drift
                .iter()
                .find(|(which, _)| which.name() == name)
                .and_then(|(_, d)| d);
            checks.insert(
                name.clone(),
                CheckResult {
                    expected: Value::from(*tol),
                    actual: actual.map_or(Value::Null, finite_or_null),
                    passed: actual.is_some_and(|d| d <= *tol),
                },
            );
        }
        Summary {
            status: outcome.status.clone(),
            message: status_message(&scenario.scene, &outcome.status, s.t),
            events: outcome.events.clone(),
            stats: outcome.stats,
            wall_time_s,
            samples,
            final_sample: *s,
            drift: outcome.drift,
            initial_invariants: outcome.initial_invariants,
            final_invariants: outcome.final_invariants,
            warnings: warning_messages(&outcome.warnings),
            checks,
            scenario: scenario.source.clone(),
            overrides: scenario.overrides.clone(),
            output,
            version: version.to_owned(),
            layout: columns::Layout::of(&scenario.scene.body),
            names: Names::of(&scenario.scene),
        }
    }

    /// Pretty-printed JSON with a final newline.
    pub fn to_json(&self) -> String {
        let mut s = serde_json::to_string_pretty(self)
            .expect("a summary holds only JSON-representable values");
        s.push('\n');
        s
    }

    /// The events as their JSON list (`events` of [`Summary::to_json`]).
    pub fn events_json(&self) -> Vec<Value> {
        self.events
            .iter()
            .map(|e| event_json(&self.names, &self.layout, e))
            .collect()
    }

    /// The checks that failed, as `name (expected …, got …)`.
    pub fn failed_checks(&self) -> Vec<String> {
        self.checks
            .iter()
            .filter(|(_, c)| !c.passed)
            .map(|(n, c)| format!("{n} (expected {}, got {})", c.expected, c.actual))
            .collect()
    }
}

/// The JSON of `ellipsoid run --summary`: the typed values serialised here, once.
impl Serialize for Summary {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let units: Map<String, Value> = self
            .layout
            .units()
            .into_iter()
            .map(|(c, u)| (c.into_owned(), Value::from(u)))
            .collect();
        let mut m = serializer.serialize_struct("Summary", 17)?;
        m.serialize_field("status", self.status.name())?;
        m.serialize_field("message", &self.message)?;
        m.serialize_field("events", &self.events_json())?;
        m.serialize_field("stats", &self.stats)?;
        m.serialize_field("wall_time_s", &self.wall_time_s)?;
        m.serialize_field("samples", &self.samples)?;
        m.serialize_field("final", &state_map(&self.layout, &self.final_sample))?;
        m.serialize_field("drift", &self.drift)?;
        m.serialize_field("initial_invariants", &self.initial_invariants)?;
        m.serialize_field("final_invariants", &self.final_invariants)?;
        m.serialize_field("warnings", &self.warnings)?;
        m.serialize_field("checks", &self.checks)?;
        m.serialize_field("units", &units)?;
        m.serialize_field("scenario", &self.scenario)?;
        m.serialize_field("overrides", &self.overrides)?;
        m.serialize_field("output", &self.output)?;
        m.serialize_field("version", &self.version)?;
        m.end()
    }
}

fn finite_or_null(v: f64) -> Value {
    serde_json::Number::from_f64(v).map_or(Value::Null, Value::Number)
}

/// A sample as a map from column name to value (null where not finite), with the
/// columns of `layout`.
pub fn state_map(layout: &columns::Layout, s: &Sample) -> Map<String, Value> {
    let mut values = columns::values(s).to_vec();
    layout.surface_values(s, &mut values);
    let mut state = Map::new();
    for ((name, _), v) in layout.numeric_columns().into_iter().zip(values) {
        state.insert(name.into_owned(), finite_or_null(v));
    }
    state.insert(columns::MODE.to_owned(), Value::from(layout.mode(s)));
    state
}

/// Adds the `surface` an event happened at, by name, for a body with contact spheres (a
/// one-surface body's events have none).
fn surface_name(body: &Body, m: &mut Map<String, Value>, surface: Surface) {
    if !body.plain() {
        m.insert("surface".into(), Value::from(body.surface_name(surface)));
    }
}

/// An event as the summary lists it: `{kind, t}` (a touchdown and an impact of a body with
/// contact spheres name their `surface`), with `from` and `to` for a mode switch
/// (and, by name, for a change of the surface in contact),
/// `name` and the full `state` (the columns of `layout`) for an observable, the approach
/// `speed` (m/s) for a touchdown, the rim's `surface`, its far side's `speed` (m/s) and the
/// `energy_loss` (J) for a flat landing, and for an impact its `impulse` (N s, world axes),
/// `energy_loss` (J), whether the contact `stuck`, the `rebound` speed (m/s) and whether
/// contact became `persistent`.
fn event_json(names: &Names, layout: &columns::Layout, e: &EventRecord) -> Value {
    let body = &names.body;
    let mut m = Map::new();
    m.insert("kind".into(), Value::from(e.kind.name()));
    m.insert("t".into(), finite_or_null(e.t));
    match &e.kind {
        EventKind::ModeSwitch { from, to } => {
            m.insert("from".into(), Value::from(from.name()));
            m.insert("to".into(), Value::from(to.name()));
        }
        EventKind::Observed { index, sample } => {
            m.insert(
                "name".into(),
                Value::from(names.observables[*index].as_str()),
            );
            m.insert("state".into(), Value::Object(state_map(layout, sample)));
        }
        EventKind::Touchdown { speed, surface } => {
            m.insert("speed".into(), finite_or_null(*speed));
            surface_name(body, &mut m, *surface);
        }
        EventKind::Impact(hit) => {
            let p = &hit.impulse;
            m.insert(
                "impulse".into(),
                Value::Array(vec![
                    finite_or_null(p.x),
                    finite_or_null(p.y),
                    finite_or_null(p.z),
                ]),
            );
            m.insert("energy_loss".into(), finite_or_null(hit.energy_loss));
            m.insert("stuck".into(), Value::from(hit.stuck));
            m.insert("rebound".into(), finite_or_null(hit.rebound));
            m.insert("persistent".into(), Value::from(hit.persistent));
            surface_name(body, &mut m, hit.surface);
        }
        EventKind::ContactSurface { from, to } => {
            m.insert("from".into(), Value::from(body.surface_name(*from)));
            m.insert("to".into(), Value::from(body.surface_name(*to)));
        }
        EventKind::Grip { surface, sticks } => {
            m.insert("surface".into(), Value::from(body.surface_name(*surface)));
            m.insert("sticks".into(), Value::from(*sticks));
        }
        EventKind::Flat {
            surface,
            speed,
            energy_loss,
        } => {
            m.insert("surface".into(), Value::from(body.surface_name(*surface)));
            m.insert("speed".into(), finite_or_null(*speed));
            m.insert("energy_loss".into(), finite_or_null(*energy_loss));
        }
        EventKind::SlipStop | EventKind::LostContact | EventKind::LiftOff | EventKind::Painleve => {
        }
    }
    Value::Object(m)
}

/// The warnings as sentences; repeats of one kind are said once, with their count.
pub fn warning_messages(warnings: &[RunWarning]) -> Vec<String> {
    let stiff: Vec<f64> = warnings
        .iter()
        .map(|w| match w {
            RunWarning::Stiff { t, .. } => *t,
        })
        .collect();
    match stiff.as_slice() {
        [] => Vec::new(),
        [t] => vec![format!(
            "the problem looks stiff at t = {t} s; an explicit method will be slow here"
        )],
        [first, .., last] => vec![format!(
            "the problem looks stiff {} times, from t = {first} s to t = {last} s; an explicit method will be slow there",
            stiff.len()
        )],
    }
}

/// A sentence explaining the status; `t` is where the run ended \[s\].
pub fn status_message(scene: &Scene, status: &Status, t: f64) -> String {
    match status {
        Status::Completed => format!("reached t_end = {t} s"),
        Status::Observed { index } => {
            let o = &scene.observe[*index];
            format!(
                "observable {:?} ({} crossed {}) at t = {t} s, where the scene asked the run to end",
                o.name,
                columns::Layout::of(&scene.body).numeric_columns()[o.column].0,
                o.crosses
            )
        }
        Status::SectionFull { index } => {
            let s = &scene.sections[*index];
            format!(
                "section {:?} reached its max_points = {} points at t = {t} s, where the scene asked the run to end",
                s.crossing.name, s.max_points
            )
        }
        Status::LostContact => format!(
            "the normal force reached zero at t = {t} s: the body leaves the plane (the run stops there: contact.on_lift_off = \"stop\")"
        ),
        Status::SlipStopped if scene.disc.is_some() => format!(
            "the slip speed and the spin about the vertical reached zero together at t = {t} s, where the \
             contact disc's friction law is set-valued; the run ends there (rolling without spin is not simulated)"
        ),
        Status::SlipStopped => {
            format!(
                "the slip speed reached zero at t = {t} s, where the pure sliding model ends (model = \"coulomb\" goes on rolling)"
            )
        }
        Status::Painleve {
            denominator,
            error: None,
        } => format!(
            "Painlevé inconsistency at t = {t} s: the sliding normal-force denominator 1 + m u·I⁻¹(r × d) fell to {denominator:.1e} \
             on its way to 0, so N grows without bound and Coulomb sliding has no consistent contact force beyond \
             (reduce contact.friction or use the rolling model)"
        ),
        Status::Painleve {
            denominator,
            error: Some(e),
        } => format!(
            "Painlevé inconsistency at t = {t} s: the sliding normal-force denominator 1 + m u·I⁻¹(r × d) fell to {denominator:.1e}, \
             so N grows without bound (a tangential impact) and Coulomb sliding has no consistent contact force ({e})"
        ),
        Status::SolverFailure { mode, error } => format!("{error} (mode {})", mode.name()),
        Status::Chattering {
            switches,
            kind: Chatter::Phases,
        } => format!(
            "more than {switches} switches between sliding and rolling by t = {t} s; the motion is chattering at the friction-cone boundary"
        ),
        Status::Chattering {
            switches,
            kind: Chatter::Impacts,
        } => format!(
            "more than {switches} impacts and mode switches by t = {t} s: the bounces did not settle into persistent contact"
        ),
        Status::InconsistentContact {
            mode,
            normal,
            gap_acceleration,
        } => format!(
            "no consistent motion at t = {t} s: the {} contact's normal force falls through zero (N = {} N), so going on \
             would need the plane to pull, while with no contact force the body falls into the plane (gap acceleration \
             {} m/s²); this is the {} model's analogue of Painlevé's paradox (model = \"coulomb\" with a finite friction \
             coefficient resolves it by sliding)",
            mode.name(),
            number(*normal),
            number(*gap_acceleration),
            mode.name()
        ),
        Status::SeveralContacts {
            touching,
            pressed,
            approach,
        } => format!(
            "several surfaces on the plane at t = {t} s, the {} and the {} (normal velocity {} m/s), in a way \
             that is not simulated: an impact at the contacts with no solution, no set of the contacts on \
             which every normal force is positive and no other surface is driven into the plane, or a fourth \
             surface touching while on three (docs/physics.md, \"Contact \
             spheres\"){}",
            scene.body.surface_name(*touching),
            scene.body.surface_name(*pressed),
            number(*approach),
            match scene.contact {
                ContactModel::Rolling => {
                    "; under the rolling model, whose friction is unbounded, this can be its analogue of \
                     Painlevé's paradox (model = \"coulomb\" with a finite friction coefficient lets a \
                     contact slide)"
                }
                _ => "",
            }
        ),
        Status::NonFinite { column, value } => {
            format!(
                "stopped at t = {t} s: the state became non-finite ({column} = {value}); the samples before it are kept"
            )
        }
        Status::BelowPlane { surface, gap } => format!(
            "stopped at t = {t} s: the {} is below the plane (gap {} m) while not in contact, a touchdown \
             the simulation did not locate; no result past this point is reported (please report the scene)",
            scene.body.surface_name(*surface),
            number(*gap)
        ),
        Status::Cancelled => format!("cancelled at t = {t} s"),
    }
}
