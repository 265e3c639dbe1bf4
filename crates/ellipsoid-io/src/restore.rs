//! A summary read back into its typed values (unpickling a Python `Trajectory`): the
//! events and the final state from the summary JSON ([`Summary::to_json`]), the status
//! from [`status_text`], which keeps every number it carries (the JSON keeps only its
//! name and its sentence). Read back, the summary writes the same JSON.

use ellipsoid_core::body::{Body, Surface};
use ellipsoid_core::columns::{self, Layout, NUMERIC, NUMERIC_COLUMNS};
use ellipsoid_core::integrate::{IntegrateError, Method, Stats};
use ellipsoid_core::invariants::{Drift, Invariant, Invariants};
use ellipsoid_core::model::MOST_CONTACTS;
use ellipsoid_core::scenario::Scenario;
use ellipsoid_core::simulate::{
    Chatter, EventKind, EventRecord, ImpactReport, Mode, Sample, Status,
};
use nalgebra::Vector3;
use serde_json::{Map, Value, json};

use crate::Summary;
use crate::summary::{CheckResult, Names};

/// The sample whose numeric columns (`layout`'s order) are `v`, its mode label `label`:
/// the inverse of `columns::values` and `Layout::{surface_values, mode}` (`None` for a
/// label the layout cannot write, or too few values).
pub fn sample(layout: &Layout, v: &[f64], label: &str) -> Option<Sample> {
    let (mode, surfaces) = layout.parse_mode(label)?;
    let fixed: &[f64; NUMERIC] = v.get(..NUMERIC)?.try_into().ok()?;
    let total = fixed[columns::index("normal_force")?];
    // The normal force of a surface in contact: its column (a body with contact
    // spheres), or the one contact's.
    let normal = |surface: Surface| match layout.extra() {
        0 => Some(total),
        _ => v
            .get(layout.surface_column("normal_force", surface)?)
            .copied(),
    };
    let touching = match (mode, surfaces.as_slice()) {
        (Mode::Flight, _) => [None; MOST_CONTACTS],
        (_, []) => std::array::from_fn(|i| (i == 0).then_some((Surface::Ellipsoid, total))),
        (_, on) => {
            let mut touching = [None; MOST_CONTACTS];
            for (slot, &s) in touching.iter_mut().zip(on) {
                *slot = Some((s, normal(s)?));
            }
            touching
        }
    };
    Some(columns::sample(fixed, mode, touching))
}

/// The summary of a run of `scenario` whose JSON (`Summary::to_json`) is `json` and whose
/// status [`status_text`] wrote as `status`: every field read back.
pub fn summary(json: &str, status: &str, scenario: &Scenario) -> Result<Summary, String> {
    let v: Value = serde_json::from_str(json).map_err(|e| e.to_string())?;
    let get = |k: &str| v.get(k).ok_or_else(|| format!("the summary has no `{k}`"));
    let text = |k: &str| -> Result<String, String> {
        get(k)?
            .as_str()
            .map(str::to_owned)
            .ok_or_else(|| format!("summary `{k}` is not a string"))
    };
    let object = |k: &str| -> Result<&Map<String, Value>, String> {
        get(k)?
            .as_object()
            .ok_or_else(|| format!("summary `{k}` is not an object"))
    };
    let strings = |k: &str| -> Result<Vec<String>, String> {
        serde_json::from_value(get(k)?.clone()).map_err(|e| format!("summary `{k}`: {e}"))
    };
    let scene = &scenario.scene;
    let names = Names::of(scene);
    let layout = Layout::of(&scene.body);
    let status = self::status(status, &scene.body)?;
    if status.name() != text("status")? {
        return Err(format!(
            "the status {:?} is not the summary's {:?}",
            status.name(),
            text("status")?
        ));
    }
    let stats = object("stats")?;
    let count = |k: &str| stats.get(k).and_then(Value::as_u64).unwrap_or(0);
    let st = Stats {
        accepted: count("accepted"),
        rejected: count("rejected"),
        rhs_evals: count("rhs_evals"),
        events: count("events"),
        min_step: stats
            .get("min_step")
            .and_then(Value::as_f64)
            .unwrap_or(f64::INFINITY),
    };
    let drifts = object("drift")?;
    let drift = Drift(Invariant::ALL.map(|i| drifts.get(i.name()).and_then(Value::as_f64)));
    let checks = object("checks")?
        .iter()
        .map(|(k, c)| {
            let passed = c.get("passed").and_then(Value::as_bool).unwrap_or(false);
            let field = |f: &str| c.get(f).cloned().unwrap_or(Value::Null);
            (
                k.clone(),
                CheckResult {
                    expected: field("expected"),
                    actual: field("actual"),
                    passed,
                },
            )
        })
        .collect();
    let events = get("events")?
        .as_array()
        .ok_or("summary `events` is not a list")?
        .iter()
        .map(|e| event(e, &names, &layout))
        .collect::<Result<Vec<_>, String>>()?;
    Ok(Summary {
        status,
        message: text("message")?,
        events,
        stats: st,
        wall_time_s: get("wall_time_s")?.as_f64().unwrap_or(0.0),
        samples: get("samples")?.as_u64().unwrap_or(0),
        final_sample: state(get("final")?, &layout)?,
        drift,
        initial_invariants: invariants(get("initial_invariants")?)?,
        final_invariants: invariants(get("final_invariants")?)?,
        warnings: strings("warnings")?,
        checks,
        scenario: text("scenario")?,
        overrides: strings("overrides")?,
        output: get("output")?.as_str().map(str::to_owned),
        version: text("version")?,
        layout,
        names,
    })
}

/// A number of the JSON (null, where the value was not finite, as NaN).
fn number(v: Option<&Value>, what: &str) -> Result<f64, String> {
    match v {
        Some(Value::Null) => Ok(f64::NAN),
        Some(v) => v
            .as_f64()
            .ok_or_else(|| format!("`{what}` is not a number")),
        None => Err(format!("`{what}` is missing")),
    }
}

/// The sample a summary's state map (`final`, an observable's `state`) holds.
fn state(v: &Value, layout: &Layout) -> Result<Sample, String> {
    let m = v.as_object().ok_or("a summary state is not an object")?;
    let values = layout
        .numeric_columns()
        .iter()
        .map(|(name, _)| number(m.get(name.as_ref()), name))
        .collect::<Result<Vec<f64>, String>>()?;
    let label = m
        .get(crate::columns::MODE)
        .and_then(Value::as_str)
        .ok_or("a summary state has no `mode`")?;
    sample(layout, &values, label).ok_or_else(|| format!("unknown mode {label:?}"))
}

/// The surface of `body` called `name`.
fn surface(body: &Body, name: &str) -> Result<Surface, String> {
    body.surfaces()
        .find(|s| body.surface_name(*s) == name)
        .ok_or_else(|| format!("no surface {name:?}"))
}

/// The mode called `name`.
fn mode(name: &str) -> Result<Mode, String> {
    Mode::NAMES
        .iter()
        .position(|n| *n == name)
        .map(|k| Mode::ALL[k])
        .ok_or_else(|| format!("unknown mode {name:?}"))
}

/// The event whose JSON ([`Summary::events_json`]) is `e`.
fn event(e: &Value, names: &Names, layout: &Layout) -> Result<EventRecord, String> {
    let field = |k: &str| e.get(k).ok_or_else(|| format!("an event has no `{k}`"));
    let text = |k: &str| -> Result<&str, String> {
        field(k)?
            .as_str()
            .ok_or_else(|| format!("event `{k}` is not a string"))
    };
    let flag = |k: &str| -> Result<bool, String> {
        field(k)?
            .as_bool()
            .ok_or_else(|| format!("event `{k}` is not true or false"))
    };
    let body = &names.body;
    // A one-surface body's touchdowns and impacts name no surface.
    let struck = || match e.get("surface").and_then(Value::as_str) {
        Some(name) => surface(body, name),
        None => Ok(Surface::Ellipsoid),
    };
    let kind = match text("kind")? {
        "slip_stop" => EventKind::SlipStop,
        "lost_contact" => EventKind::LostContact,
        "lift_off" => EventKind::LiftOff,
        "painleve" => EventKind::Painleve,
        "mode_switch" => EventKind::ModeSwitch {
            from: mode(text("from")?)?,
            to: mode(text("to")?)?,
        },
        "contact_surface" => EventKind::ContactSurface {
            from: surface(body, text("from")?)?,
            to: surface(body, text("to")?)?,
        },
        "grip" => EventKind::Grip {
            surface: surface(body, text("surface")?)?,
            sticks: flag("sticks")?,
        },
        "flat" => EventKind::Flat {
            surface: surface(body, text("surface")?)?,
            speed: number(e.get("speed"), "speed")?,
            energy_loss: number(e.get("energy_loss"), "energy_loss")?,
        },
        "touchdown" => EventKind::Touchdown {
            speed: number(e.get("speed"), "speed")?,
            surface: struck()?,
        },
        "impact" => {
            let p = field("impulse")?
                .as_array()
                .filter(|p| p.len() == 3)
                .ok_or("event `impulse` is not three numbers")?;
            EventKind::Impact(ImpactReport {
                impulse: Vector3::new(
                    number(p.first(), "impulse")?,
                    number(p.get(1), "impulse")?,
                    number(p.get(2), "impulse")?,
                ),
                energy_loss: number(e.get("energy_loss"), "energy_loss")?,
                stuck: flag("stuck")?,
                rebound: number(e.get("rebound"), "rebound")?,
                persistent: flag("persistent")?,
                surface: struck()?,
            })
        }
        "observed" => {
            let name = text("name")?;
            EventKind::Observed {
                index: names
                    .observables
                    .iter()
                    .position(|o| o == name)
                    .ok_or_else(|| format!("no observable {name:?}"))?,
                sample: Box::new(state(field("state")?, layout)?),
            }
        }
        other => return Err(format!("unknown event kind {other:?}")),
    };
    Ok(EventRecord {
        kind,
        t: number(e.get("t"), "t")?,
    })
}

fn invariants(v: &Value) -> Result<Invariants, String> {
    let f = |k: &str| {
        v.get(k)
            .and_then(Value::as_f64)
            .ok_or_else(|| format!("invariant `{k}` missing"))
    };
    let p = v
        .get("momentum")
        .and_then(Value::as_array)
        .filter(|a| a.len() == 2)
        .and_then(|a| Some([a[0].as_f64()?, a[1].as_f64()?]))
        .ok_or("invariant `momentum` missing")?;
    Ok(Invariants {
        energy: f("energy")?,
        energy_plus_work: f("energy_plus_work")?,
        momentum: p,
        angular_momentum_z: f("angular_momentum_z")?,
        axial_spin: f("axial_spin")?,
        jellett: f("jellett")?,
    })
}

/// A float by its bits: exact, NaN and the infinities included.
fn bits(x: f64) -> Value {
    Value::from(x.to_bits())
}

/// `status` as one line of JSON, `[name, numbers…]` (floats by their bits, surfaces of
/// `body` by name), which [`status`] reads back into the very same status.
pub fn status_text(status: &Status, body: &Body) -> String {
    let name = status.name();
    let surface = |s: &Surface| body.surface_name(*s);
    let v = match status {
        Status::Completed | Status::LostContact | Status::SlipStopped | Status::Cancelled => {
            json!([name])
        }
        Status::Observed { index } | Status::SectionFull { index } => json!([name, index]),
        Status::Painleve { denominator, error } => {
            json!([
                name,
                bits(*denominator),
                error.as_ref().map(integrate_error)
            ])
        }
        Status::SolverFailure { mode, error } => {
            json!([name, mode.name(), integrate_error(error)])
        }
        Status::Chattering { switches, kind } => {
            json!([name, switches, matches!(kind, Chatter::Impacts)])
        }
        Status::InconsistentContact {
            mode,
            normal,
            gap_acceleration,
        } => json!([name, mode.name(), bits(*normal), bits(*gap_acceleration)]),
        Status::SeveralContacts {
            touching,
            pressed,
            approach,
        } => json!([name, surface(touching), surface(pressed), bits(*approach)]),
        Status::NonFinite { column, value } => json!([name, column, bits(*value)]),
        Status::BelowPlane { surface: s, gap } => json!([name, surface(s), bits(*gap)]),
    };
    v.to_string()
}

/// The fields of a `[name, …]` list, read in order.
struct Fields<'a>(std::slice::Iter<'a, Value>);

impl<'a> Fields<'a> {
    fn next(&mut self) -> Result<&'a Value, String> {
        self.0
            .next()
            .ok_or_else(|| "a status field is missing".to_owned())
    }
    fn text(&mut self) -> Result<&'a str, String> {
        self.next()?
            .as_str()
            .ok_or_else(|| "a status field is not a string".to_owned())
    }
    fn count(&mut self) -> Result<u64, String> {
        self.next()?
            .as_u64()
            .ok_or_else(|| "a status field is not a count".to_owned())
    }
    fn index(&mut self) -> Result<usize, String> {
        usize::try_from(self.count()?).map_err(|e| e.to_string())
    }
    fn float(&mut self) -> Result<f64, String> {
        self.count().map(f64::from_bits)
    }
    fn flag(&mut self) -> Result<bool, String> {
        self.next()?
            .as_bool()
            .ok_or_else(|| "a status field is not true or false".to_owned())
    }
}

/// The status [`status_text`] wrote as `text` for a run of `body`.
pub fn status(text: &str, body: &Body) -> Result<Status, String> {
    let v: Value = serde_json::from_str(text).map_err(|e| format!("status {text:?}: {e}"))?;
    let items = v.as_array().ok_or("the status is not a list")?;
    let mut f = Fields(items.iter());
    Ok(match f.text()? {
        "completed" => Status::Completed,
        "lost_contact" => Status::LostContact,
        "slip_stopped" => Status::SlipStopped,
        "cancelled" => Status::Cancelled,
        "observed" => Status::Observed { index: f.index()? },
        "section_full" => Status::SectionFull { index: f.index()? },
        "below_plane" => Status::BelowPlane {
            surface: surface(body, f.text()?)?,
            gap: f.float()?,
        },
        "painleve" => Status::Painleve {
            denominator: f.float()?,
            error: match f.next()? {
                Value::Null => None,
                e => Some(read_integrate_error(e)?),
            },
        },
        "solver_failure" => Status::SolverFailure {
            mode: mode(f.text()?)?,
            error: read_integrate_error(f.next()?)?,
        },
        "chattering" => Status::Chattering {
            switches: f.index()?,
            kind: if f.flag()? {
                Chatter::Impacts
            } else {
                Chatter::Phases
            },
        },
        "inconsistent_contact" => Status::InconsistentContact {
            mode: mode(f.text()?)?,
            normal: f.float()?,
            gap_acceleration: f.float()?,
        },
        "several_contacts" => Status::SeveralContacts {
            touching: surface(body, f.text()?)?,
            pressed: surface(body, f.text()?)?,
            approach: f.float()?,
        },
        "non_finite" => {
            let name = f.text()?;
            Status::NonFinite {
                column: NUMERIC_COLUMNS
                    .iter()
                    .find(|(c, _)| *c == name)
                    .map(|(c, _)| *c)
                    .ok_or_else(|| format!("no column {name:?}"))?,
                value: f.float()?,
            }
        }
        other => return Err(format!("unknown status {other:?}")),
    })
}

/// The integrator's error as `[kind, numbers…]` (floats by their bits).
fn integrate_error(e: &IntegrateError) -> Value {
    match e {
        IntegrateError::InvalidOptions { reason } => json!(["invalid_options", reason]),
        IntegrateError::StepSizeTooSmall { t, h } => {
            json!(["step_size_too_small", bits(*t), bits(*h)])
        }
        IntegrateError::MaxSteps { t, steps, method } => json!([
            "max_steps",
            bits(*t),
            steps,
            method.name(),
            bits(match method {
                Method::Rk4 { h } => *h,
                Method::Dopri5 | Method::Dop853 => 0.0,
            })
        ]),
        IntegrateError::Collapsed {
            t,
            h,
            steps,
            projected,
        } => json!(["collapsed", bits(*t), bits(*h), steps, bits(*projected)]),
        IntegrateError::OverBudget {
            t,
            steps,
            projected,
            max_steps,
        } => json!(["over_budget", bits(*t), steps, bits(*projected), max_steps]),
        IntegrateError::FastRate {
            t,
            h,
            rate,
            stiff,
            steps,
            projected,
            max_steps,
        } => json!([
            "fast_rate",
            bits(*t),
            bits(*h),
            bits(*rate),
            stiff,
            steps,
            bits(*projected),
            max_steps
        ]),
        IntegrateError::NonFinite { t } => json!(["non_finite", bits(*t)]),
    }
}

/// The inverse of [`integrate_error`].
fn read_integrate_error(v: &Value) -> Result<IntegrateError, String> {
    let items = v.as_array().ok_or("the integrator's error is not a list")?;
    let mut f = Fields(items.iter());
    Ok(match f.text()? {
        "invalid_options" => IntegrateError::InvalidOptions {
            reason: f.text()?.to_owned(),
        },
        "step_size_too_small" => IntegrateError::StepSizeTooSmall {
            t: f.float()?,
            h: f.float()?,
        },
        "max_steps" => {
            let (t, steps, name, h) = (f.float()?, f.count()?, f.text()?, f.float()?);
            let method = Method::ALL
                .into_iter()
                .find(|m| m.name() == name)
                .ok_or_else(|| format!("unknown method {name:?}"))?;
            IntegrateError::MaxSteps {
                t,
                steps,
                method: match method {
                    Method::Rk4 { .. } => Method::Rk4 { h },
                    other => other,
                },
            }
        }
        "collapsed" => IntegrateError::Collapsed {
            t: f.float()?,
            h: f.float()?,
            steps: f.count()?,
            projected: f.float()?,
        },
        "over_budget" => IntegrateError::OverBudget {
            t: f.float()?,
            steps: f.count()?,
            projected: f.float()?,
            max_steps: f.count()?,
        },
        "fast_rate" => IntegrateError::FastRate {
            t: f.float()?,
            h: f.float()?,
            rate: f.float()?,
            stiff: f.flag()?,
            steps: f.count()?,
            projected: f.float()?,
            max_steps: f.count()?,
        },
        "non_finite" => IntegrateError::NonFinite { t: f.float()? },
        other => return Err(format!("unknown integrator error {other:?}")),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn load(name: &str, overrides: &[&str]) -> Scenario {
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../scenarios")
            .join(name);
        ellipsoid_core::scenario::load(&path, overrides).expect("the bundled scenario loads")
    }

    /// Every status, each integrator error inside one, reads back as itself, its floats
    /// bit for bit (NaN and the infinities included) and its surfaces by name.
    #[test]
    fn every_status_reads_back_as_itself() {
        let scenario = load("tippe-top-stem.toml", &[]);
        let body = &scenario.scene.body;
        assert!(!body.spheres().is_empty(), "the scene has a contact sphere");
        let errors = [
            IntegrateError::InvalidOptions {
                reason: "rtol \"0\" too small".into(),
            },
            IntegrateError::StepSizeTooSmall { t: 0.1, h: 1e-300 },
            IntegrateError::MaxSteps {
                t: 2.5,
                steps: 7,
                method: Method::Rk4 { h: 1e-4 },
            },
            IntegrateError::MaxSteps {
                t: 2.5,
                steps: 7,
                method: Method::Dopri5,
            },
            IntegrateError::Collapsed {
                t: 1.0,
                h: 1e-17,
                steps: 9,
                projected: f64::INFINITY,
            },
            IntegrateError::OverBudget {
                t: 1.0,
                steps: 3,
                projected: 4e9,
                max_steps: 10,
            },
            IntegrateError::FastRate {
                t: 1.0,
                h: 1e-9,
                rate: 3e8,
                stiff: true,
                steps: 5,
                projected: 6e12,
                max_steps: 11,
            },
            IntegrateError::NonFinite { t: -0.0 },
        ];
        let mut all = vec![
            Status::Completed,
            Status::Observed { index: 3 },
            Status::SectionFull { index: 2 },
            Status::LostContact,
            Status::SlipStopped,
            Status::Painleve {
                denominator: 1e-3,
                error: None,
            },
            Status::Chattering {
                switches: 200,
                kind: Chatter::Phases,
            },
            Status::Chattering {
                switches: 50,
                kind: Chatter::Impacts,
            },
            Status::InconsistentContact {
                mode: Mode::Rolling,
                normal: -0.84,
                gap_acceleration: -9.81,
            },
            Status::SeveralContacts {
                touching: Surface::Sphere(0),
                pressed: Surface::Ellipsoid,
                approach: -0.5,
            },
            Status::NonFinite {
                column: "omega_z",
                value: f64::NAN,
            },
            Status::BelowPlane {
                surface: Surface::Sphere(0),
                gap: -2.5e-9,
            },
            Status::Cancelled,
        ];
        for e in errors {
            all.push(Status::SolverFailure {
                mode: Mode::TwoContacts,
                error: e.clone(),
            });
            all.push(Status::Painleve {
                denominator: 2e-4,
                error: Some(e),
            });
        }
        // Every name is met.
        for name in Status::NAMES {
            assert!(all.iter().any(|s| s.name() == name), "{name}");
        }
        for s in &all {
            let text = status_text(s, body);
            let back = status(&text, body).unwrap_or_else(|e| panic!("{text}: {e}"));
            // Debug shows NaN as NaN, so it compares the NaN case too.
            assert_eq!(format!("{back:?}"), format!("{s:?}"), "{text}");
            if !matches!(s, Status::NonFinite { .. }) {
                assert_eq!(&back, s);
            }
        }
        assert!(status("[\"gone\"]", body).is_err());
        assert!(status("[\"non_finite\", \"no_such_column\", 0]", body).is_err());
    }

    /// A summary read back from its JSON and its status text holds the run's own typed
    /// values (events, final sample, status) and writes the same JSON: a scene with a
    /// contact sphere (touchdowns, impacts, surface changes) and one with observables.
    #[test]
    fn a_summary_reads_back_into_the_runs_values() {
        for (name, overrides) in [
            ("tippe-top-stem.toml", &["output.t_end=3"][..]),
            ("egg-jump.toml", &[][..]),
            ("tippe-top-disc.toml", &["output.t_end=1"][..]),
        ] {
            let scenario = load(name, overrides);
            let finished = crate::run::run(&scenario, None, "test", None, |_| {
                Ok::<(), std::convert::Infallible>(())
            })
            .ok()
            .expect("the run finishes");
            let (outcome, summary) = (&finished.outcome, &finished.summary);
            assert!(!outcome.events.is_empty(), "{name} has events");
            let json = summary.to_json();
            let text = status_text(&summary.status, &scenario.scene.body);
            let back = self::summary(&json, &text, &scenario).unwrap_or_else(|e| panic!("{e}"));
            assert_eq!(back.to_json(), json, "{name}");
            assert_eq!(back.status, outcome.status, "{name}");
            assert_eq!(back.events, outcome.events, "{name}");
            assert_eq!(back.final_sample, outcome.final_sample, "{name}");
            // A status that is not the summary's is refused.
            let other = status_text(&Status::Cancelled, &scenario.scene.body);
            assert!(self::summary(&json, &other, &scenario).is_err());
        }
    }
}
