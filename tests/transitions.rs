//! The hybrid machine's decision table (docs/physics.md, "The hybrid machine";
//! crates/ellipsoid-core/src/simulate/transition/mod.rs), tested as a table: one scene per
//! row that reaches it, the transition the row names asserted from the run's events and
//! status, and on every row the physics every state map must keep — E + W continuous
//! (impacts and stops book their losses in W), no non-finite value, and a reported normal
//! force that is a force (finite; positive wherever the body is held on the plane).
//!
//! Rows the table cannot reach with a scene of its own are named, with the test that
//! reaches them, in [`ROWS_ELSEWHERE`].

mod common;

use std::path::Path;

use common::run;
use ellipsoid_core::body::Surface;
use ellipsoid_core::invariants::Invariant;
use ellipsoid_core::simulate::{EventKind, Mode, Outcome, Sample};

/// What a row's scene must show.
#[derive(Debug)]
enum Expect {
    /// The run starts in this mode, with no event at t = 0.
    Starts(Mode),
    /// The run ends at t = 0 with this status, in this mode.
    EndsAtStart(&'static str, Mode),
    /// The run switches `from` → `to` (at its first such switch), right after an event
    /// `after`.
    Switches {
        after: &'static str,
        from: Mode,
        to: Mode,
    },
    /// The first touchdown's impact is not persistent, and the body flies on.
    Rebounds,
    /// The surface in contact changes from the ellipsoid to contact sphere 0.
    ChangesSurface,
    /// The run stops with `status` in `mode`, after an event `after` (if it records one).
    Stops {
        after: Option<&'static str>,
        status: &'static str,
        mode: Mode,
    },
}

/// A scene: a file of the repository, and `--set` changes.
struct Scene {
    file: &'static str,
    set: &'static [&'static str],
}

/// A case of one row of the table: (from, event, condition, to), the scene and what it
/// must show.
struct Row {
    /// The row of the table in transition/mod.rs's module docs (1 = the first below its
    /// header).
    table: usize,
    row: [&'static str; 4],
    scene: Scene,
    expect: Expect,
}

const BALL: &str = "tests/data/hybrid/ball-e075-settles.toml";

/// The rows, in the order of the table in transition/mod.rs.
const ROWS: &[Row] = &[
    Row {
        table: 1,
        row: ["start", "on the plane", "frictionless", "frictionless"],
        scene: Scene {
            file: "scenarios/nutation.toml",
            set: &[],
        },
        expect: Expect::Starts(Mode::Frictionless),
    },
    Row {
        table: 1,
        row: ["start", "on the plane", "rolling model", "rolling"],
        scene: Scene {
            file: "scenarios/paper-rolling.toml",
            set: &[],
        },
        expect: Expect::Starts(Mode::Rolling),
    },
    Row {
        table: 1,
        row: [
            "start",
            "on the plane",
            "Coulomb, no slip, cone holds",
            "rolling",
        ],
        scene: Scene {
            file: BALL,
            set: &[
                "initial.height=0",
                "contact.model=\"coulomb\"",
                "contact.friction=0.3",
                "output.t_end=0.1",
            ],
        },
        expect: Expect::Starts(Mode::Rolling),
    },
    Row {
        table: 1,
        row: [
            "start",
            "on the plane",
            "Coulomb, no slip, cone fails",
            "sliding from rest",
        ],
        scene: Scene {
            file: "tests/data/onset/prolate-onset.toml",
            set: &[
                "initial.velocity=[0, 0]",
                "initial.phi_dot=0",
                "initial.psi_dot=0",
                "initial.theta_deg=60",
                "contact.friction=0.01",
                "output.t_end=0.05",
            ],
        },
        expect: Expect::Starts(Mode::Sliding),
    },
    Row {
        table: 1,
        row: [
            "start",
            "on the plane",
            "sliding model, no slip",
            "stop slip_stopped",
        ],
        scene: Scene {
            file: BALL,
            set: &[
                "initial.height=0",
                "contact.model=\"sliding\"",
                "contact.friction=0.3",
            ],
        },
        expect: Expect::EndsAtStart("slip_stopped", Mode::Sliding),
    },
    Row {
        table: 1,
        row: [
            "start",
            "on the plane",
            "contact disc, no slip and no spin",
            "stop slip_stopped",
        ],
        scene: Scene {
            file: BALL,
            set: &[
                "initial.height=0",
                "contact.model=\"coulomb\"",
                "contact.friction=0.3",
                "contact.contact_radius=0.002",
            ],
        },
        expect: Expect::EndsAtStart("slip_stopped", Mode::Sliding),
    },
    Row {
        table: 2,
        row: ["start", "above the plane", "", "flight"],
        scene: Scene {
            file: BALL,
            set: &["output.t_end=0.05"],
        },
        expect: Expect::Starts(Mode::Flight),
    },
    Row {
        table: 3,
        row: ["flight", "touchdown", "rebound > v_settle", "flight"],
        scene: Scene {
            file: BALL,
            set: &["contact.restitution=0.5", "output.t_end=0.2"],
        },
        expect: Expect::Rebounds,
    },
    Row {
        table: 4,
        row: [
            "flight",
            "touchdown",
            "rebound ≤ v_settle, N > 0",
            "on the plane",
        ],
        scene: Scene {
            file: BALL,
            set: &["contact.restitution=0", "output.t_end=0.2"],
        },
        expect: Expect::Switches {
            after: "impact",
            from: Mode::Flight,
            to: Mode::Frictionless,
        },
    },
    Row {
        table: 7,
        row: [
            "flight",
            "touchdown",
            "another surface touches at the same instant and approaches after the impact; \
             the impact at them has no solution (rolling: the rim and the peg at once, the \
             no-slip law pulling)",
            "stop several_contacts",
        ],
        scene: Scene {
            file: "tests/data/spheres/top-on-peg-rolling.toml",
            set: &["initial.theta=0.6", "initial.theta_dot=5"],
        },
        expect: Expect::Stops {
            after: None,
            status: "several_contacts",
            mode: Mode::Flight,
        },
    },
    Row {
        table: 8,
        row: [
            "any contact",
            "another surface's gap ↓ −δz",
            "the pressed surface separates",
            "as a touchdown",
        ],
        scene: Scene {
            file: "scenarios/tippe-top-stem.toml",
            set: &["output.t_end=1.4"],
        },
        expect: Expect::ChangesSurface,
    },
    Row {
        table: 11,
        row: [
            "any contact",
            "another surface's gap ↓ −δz",
            "a further surface touches at the same instant (the tripod rocking on its rim and \
             one leg: the other leg's gap within the touchdown's time resolution, approaching)",
            "three contacts",
        ],
        scene: Scene {
            file: "tests/data/spheres/tripod.toml",
            set: &["contact.model=\"coulomb\"", "contact.friction=0.5"],
        },
        expect: Expect::Switches {
            after: "impact",
            from: Mode::Rolling,
            to: Mode::ThreeContacts,
        },
    },
    Row {
        table: 12,
        row: [
            "any contact",
            "another surface's gap ↓ −δz",
            "no pair solution, or no consistent set of the two (rolling: the peg touches \
             down while the rim rolls, both within their settling speeds, and no set of \
             them is consistent)",
            "stop several_contacts",
        ],
        scene: Scene {
            file: "tests/data/spheres/top-on-peg-rolling.toml",
            set: &["initial.theta=0.6"],
        },
        expect: Expect::Stops {
            after: None,
            status: "several_contacts",
            mode: Mode::Rolling,
        },
    },
    Row {
        table: 9,
        row: [
            "any contact",
            "another surface's gap ↓ −δz",
            "the pressed surface stays, the new one persistent",
            "two contacts",
        ],
        scene: Scene {
            file: "scenarios/tippe-top-stem.toml",
            set: &[],
        },
        expect: Expect::Switches {
            after: "impact",
            from: Mode::Sliding,
            to: Mode::TwoContacts,
        },
    },
    Row {
        table: 13,
        row: ["two contacts", "N_1 or N_2 ↓ 0", "", "the other alone"],
        scene: Scene {
            file: "scenarios/tippe-top-stem.toml",
            set: &[],
        },
        expect: Expect::Switches {
            after: "mode_switch",
            from: Mode::TwoContacts,
            to: Mode::Sliding,
        },
    },
    Row {
        table: 16,
        row: [
            "sliding",
            "slip stop, confirmed",
            "Coulomb, cone holds",
            "rolling",
        ],
        scene: Scene {
            file: BALL,
            set: &[
                "initial.height=0",
                "initial.velocity=[0.5, 0]",
                "contact.model=\"coulomb\"",
                "contact.friction=0.3",
                "output.t_end=0.2",
            ],
        },
        expect: Expect::Switches {
            after: "slip_stop",
            from: Mode::Sliding,
            to: Mode::Rolling,
        },
    },
    Row {
        table: 16,
        row: [
            "sliding",
            "slip stop, confirmed",
            "sliding model",
            "stop slip_stopped",
        ],
        scene: Scene {
            file: BALL,
            set: &[
                "initial.height=0",
                "initial.velocity=[0.5, 0]",
                "contact.model=\"sliding\"",
                "contact.friction=0.3",
                "output.t_end=0.2",
            ],
        },
        expect: Expect::Stops {
            after: Some("slip_stop"),
            status: "slip_stopped",
            mode: Mode::Sliding,
        },
    },
    Row {
        table: 14,
        row: [
            "two contacts",
            "a slip ↓ its stop",
            "sliding model",
            "stop slip_stopped",
        ],
        scene: Scene {
            file: "tests/data/spheres/top-lying.toml",
            set: &[
                "contact.model=\"sliding\"",
                "contact.friction=0.3",
                "initial.phi_dot=2",
            ],
        },
        expect: Expect::Stops {
            after: Some("slip_stop"),
            status: "slip_stopped",
            mode: Mode::TwoContacts,
        },
    },
    Row {
        table: 18,
        row: [
            "sliding",
            "Painlevé denominator ↓ 10⁻³",
            "",
            "stop painleve",
        ],
        scene: Scene {
            file: "tests/data/hybrid/painleve-needle.toml",
            set: &[],
        },
        expect: Expect::Stops {
            after: Some("painleve"),
            status: "painleve",
            mode: Mode::Sliding,
        },
    },
    Row {
        table: 19,
        row: ["rolling", "cone left", "", "sliding"],
        scene: Scene {
            file: "tests/data/onset/prolate-onset.toml",
            set: &["output.t_end=0.5"],
        },
        expect: Expect::Switches {
            after: "mode_switch",
            from: Mode::Rolling,
            to: Mode::Sliding,
        },
    },
    Row {
        table: 20,
        row: [
            "any contact",
            "N ↓ 0",
            "on_lift_off = \"stop\"",
            "stop lost_contact",
        ],
        scene: Scene {
            file: "scenarios/egg-jump.toml",
            set: &["contact.on_lift_off=\"stop\"", "output.t_end=2.5"],
        },
        expect: Expect::Stops {
            after: Some("lost_contact"),
            status: "lost_contact",
            mode: Mode::Sliding,
        },
    },
    Row {
        table: 21,
        row: ["any contact", "N ↓ 0", "flight consistent", "flight"],
        scene: Scene {
            file: "scenarios/egg-jump.toml",
            set: &["output.t_end=2.0"],
        },
        expect: Expect::Switches {
            after: "lift_off",
            from: Mode::Sliding,
            to: Mode::Flight,
        },
    },
    Row {
        table: 22,
        row: [
            "any contact",
            "N ↓ 0",
            "flight inconsistent",
            "stop inconsistent_contact",
        ],
        scene: Scene {
            file: "tests/data/hybrid/rolling-liftoff.toml",
            set: &[],
        },
        expect: Expect::Stops {
            after: None,
            status: "inconsistent_contact",
            mode: Mode::Rolling,
        },
    },
    Row {
        table: 26,
        row: [
            "two contacts",
            "a third surface's gap ↓ −δz",
            "all three stay after the impact at the three",
            "three contacts",
        ],
        scene: Scene {
            file: "tests/data/spheres/tripod.toml",
            set: &["contact.model=\"coulomb\"", "contact.friction=0.3"],
        },
        expect: Expect::Switches {
            after: "impact",
            from: Mode::TwoContacts,
            to: Mode::ThreeContacts,
        },
    },
];

/// Rows of the table no scene here reaches (by their number in the table), and the tests
/// that reach them.
const ROWS_ELSEWHERE: &[(&[usize], &str, &str)] = &[
    (
        &[11],
        "any contact | second touchdown | the pressed surface approaches | by who stays after the impact at both",
        "tests/pair_impact.rs (the top of scenarios/top-on-peg.toml falling onto its rim: impulse at \
         both contacts, both persistent, sliding → two contacts at the rim's touchdown)",
    ),
    (
        &[24],
        "two contacts | a slip ↓ the slip stop | Coulomb | two contacts, that contact sticking",
        "tests/grip.rs (a top sliding on its rim and peg: grip events, the rim then the peg, \
         and the steady roll after)",
    ),
    (
        &[25],
        "two contacts | a hold's margin ↓ 0 | | that contact sliding",
        "tests/cli.rs, the hopping tippe top with its stem (the stem's grip released at \
         1.016 s)",
    ),
    (
        &[27, 28],
        "three contacts | N_i ↓ 0 | two contacts; three contacts | a fourth surface's gap ↓ −δz | \
         stop several_contacts",
        "not reached by a scene or a campaign yet: no test covers these two rows. Row 28 \
         cannot be reached by the three-contact phase's motion: three contacts fix ζ and \
         every gap depends on ζ alone (docs/physics.md, \"Several contacts\"), so it is a \
         guard. Row 27 needs friction whose moments about G turn a normal force to zero; \
         the tripod (tests/data/spheres/tripod.toml) spun at 3 to 150 rad/s, sliding or \
         Coulomb with μ up to 3, thrown at up to 2 m/s, enters three contacts late and \
         stays there",
    ),
    (
        &[10],
        "any contact | second touchdown | the pressed surface stays, the new one rebounds | the previous phase",
        "tests/pair_impact.rs (a dumbbell whose two spheres are each other's centres of \
         percussion: at the second sphere's touchdown the first stays pressed and the second \
         rebounds at e times its speed)",
    ),
    (
        &[15],
        "two contacts | Painlevé denominator ↓ 1e-3 | stop painleve",
        "not reached by a scene or a campaign yet: no test covers this row",
    ),
    (
        &[17],
        "sliding | slip stop, not confirmed (a turn of the slip) | sliding",
        "tests/hard_cases.rs, row 2d (a loose DOPRI5 step turns the slip through 90°)",
    ),
    (
        &[5, 6],
        "flight | touchdown | rebound ≤ v_settle, N ≤ 0 on the plane | flight or stop inconsistent_contact",
        "tests/campaign.rs (random scenes; a landing whose own motion lifts it needs a state \
         tuned to N = 0, which no scene file here holds)",
    ),
    (
        &[23],
        "sliding | the integrator's pace check fails, the slip held at the cone's edge | on the plane",
        "tests/campaign.rs, random_scenes_whose_slip_was_held_at_the_cone_edge_end_physically \
         (14 random scenes; a scene file would need a state tuned to the cone's edge)",
    ),
    (
        &[29, 30, 31, 32],
        "start on a flat rim; flight | touchdown of a flat rim; a rim in contact | sin α ↓ 1e-6; \
         face | slip and spin stop",
        "tests/rims.rs (a coin started flat, a coin dropped flat, a coin tipping over: each \
         lands on its face and, with friction, rests there)",
    ),
    (
        &[33],
        "face | N ↓ 0 | as frictionless",
        "not reached by a scene yet: no effect lifts a body lying on its face",
    ),
];

fn load(scene: &Scene) -> (Outcome, Vec<Sample>) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let sc = ellipsoid_core::scenario::load(&root.join(scene.file), scene.set)
        .unwrap_or_else(|e| panic!("{}: {e}", scene.file));
    run(&sc.scene)
}

/// The run's first mode switch (out of mode `out_of`, if given): its index among the
/// events, from, to.
fn first_switch(out: &Outcome, out_of: Option<Mode>) -> Option<(usize, Mode, Mode)> {
    out.events
        .iter()
        .enumerate()
        .find_map(|(i, e)| match e.kind {
            EventKind::ModeSwitch { from, to } if out_of.is_none_or(|m| m == from) => {
                Some((i, from, to))
            }
            _ => None,
        })
}

/// What every row keeps: finite rows, E + W continuous through the state maps, and a
/// normal force that is a force.
fn check_physics(name: &str, out: &Outcome, samples: &[Sample]) {
    assert!(!samples.is_empty(), "{name}: no samples");
    for s in samples {
        let values = [s.t, s.energy, s.work, s.normal_force, s.slip_speed, s.gap];
        assert!(
            values.iter().all(|v| v.is_finite()),
            "{name}: a non-finite value at t = {}",
            s.t
        );
        if s.mode != Mode::Flight {
            assert!(
                s.normal_force >= 0.0,
                "{name}: N = {} N on the plane at t = {}",
                s.normal_force,
                s.t
            );
        }
    }
    let drift = out
        .drift
        .get(Invariant::EnergyPlusWork)
        .expect("E + W is always tracked");
    assert!(drift.abs() <= 1e-8, "{name}: E + W drifted by {drift:e}");
}

fn check_row(row: &Row) {
    let name = row.row.join(" | ");
    let (out, samples) = load(&row.scene);
    check_physics(&name, &out, &samples);
    match row.expect {
        Expect::Starts(mode) => {
            assert_eq!(samples[0].mode, mode, "{name}");
            assert!(
                out.events.iter().all(|e| e.t > 0.0),
                "{name}: an event at t = 0: {:?}",
                out.events
            );
        }
        Expect::EndsAtStart(status, mode) => {
            assert_eq!(out.status.name(), status, "{name}");
            assert_eq!(out.final_sample.t, 0.0, "{name}");
            assert_eq!(out.final_sample.mode, mode, "{name}");
        }
        Expect::Switches { after, from, to } => {
            let i = out
                .events
                .iter()
                .position(|e| e.kind == EventKind::ModeSwitch { from, to })
                .unwrap_or_else(|| panic!("{name}: no switch: {:?}", out.events));
            if after != "mode_switch" {
                assert_eq!(out.events[i - 1].kind.name(), after, "{name}");
                assert_eq!(out.events[i - 1].t, out.events[i].t, "{name}");
            }
            // The switch is where the samples change mode.
            let t_switch = out.events[i].t;
            assert!(
                samples
                    .iter()
                    .filter(|s| s.t > t_switch)
                    .take(1)
                    .all(|s| s.mode == to || s.t > t_switch + 1e-3),
                "{name}: the sample after the switch"
            );
        }
        Expect::Rebounds => {
            let impact = out
                .events
                .iter()
                .find_map(|e| match &e.kind {
                    EventKind::Impact(r) => Some(r),
                    _ => None,
                })
                .unwrap_or_else(|| panic!("{name}: no impact"));
            assert!(!impact.persistent && impact.rebound > 0.0, "{name}");
            assert!(
                first_switch(&out, None).is_none(),
                "{name}: a switch: {:?}",
                out.events
            );
        }
        Expect::ChangesSurface => {
            let change = out.events.iter().position(|e| {
                matches!(
                    e.kind,
                    EventKind::ContactSurface {
                        from: Surface::Ellipsoid,
                        to: Surface::Sphere(0)
                    }
                )
            });
            let i = change.unwrap_or_else(|| panic!("{name}: no change of surface"));
            // The impact at the new surface follows, at the same time.
            assert!(
                out.events[i + 1..]
                    .iter()
                    .take_while(|e| e.t == out.events[i].t)
                    .any(|e| matches!(e.kind, EventKind::Impact(_))),
                "{name}: no impact at the change of surface"
            );
        }
        Expect::Stops {
            after,
            status,
            mode,
        } => {
            assert_eq!(out.status.name(), status, "{name}: {:?}", out.status);
            assert_eq!(out.final_sample.mode, mode, "{name}");
            if let Some(after) = after {
                assert!(
                    out.events.iter().any(|e| e.kind.name() == after),
                    "{name}: no {after} event"
                );
            }
            assert!(out.final_sample.t > 0.0, "{name}");
        }
    }
}

/// The rows of a markdown table: the lines starting with `|` from the one starting with
/// `header` on, in `text`, with `prefix` removed from each line first.
fn table_rows(text: &str, prefix: &str, header: &str) -> Vec<String> {
    (text.lines())
        .filter_map(|l| l.strip_prefix(prefix))
        .skip_while(|l| !l.starts_with(header))
        .take_while(|l| l.starts_with('|'))
        .map(str::to_owned)
        .collect()
}

/// transition/mod.rs's table and docs/physics.md's ("The hybrid machine") are one table: the
/// same rows, word for word.
#[test]
fn the_transition_table_here_is_the_one_in_docs_physics_md() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let read = |p: &str| std::fs::read_to_string(root.join(p)).unwrap();
    let module = table_rows(&read("src/simulate/transition/mod.rs"), "//! ", "| from |");
    let physics = read("../../docs/physics.md");
    let section = &physics[physics.find("## The hybrid machine").unwrap()..];
    let docs = table_rows(section, "", "| from |");
    assert!(module.len() > 20, "{} rows in the module", module.len());
    for (k, (m, d)) in module.iter().zip(&docs).enumerate() {
        assert_eq!(m, d, "row {k} (0: the header) differs");
    }
    assert_eq!(module.len(), docs.len(), "row counts differ");
}

/// Every row of transition/mod.rs's table has a case here or an entry in [`ROWS_ELSEWHERE`].
#[test]
fn every_row_of_the_table_is_tested() {
    let source = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("src/simulate/transition/mod.rs"),
    )
    .unwrap();
    let documented = source
        .lines()
        .filter(|l| l.starts_with("//! | ") && !l.starts_with("//! | from"))
        .count();
    for table in 1..=documented {
        assert!(
            ROWS.iter().any(|r| r.table == table)
                || ROWS_ELSEWHERE
                    .iter()
                    .any(|(rows, ..)| rows.contains(&table)),
            "row {table} of the table in transition/mod.rs has no case"
        );
    }
    assert!(ROWS.iter().all(|r| (1..=documented).contains(&r.table)));
}

#[test]
fn every_row_of_the_transition_table_reaches_its_phase_and_keeps_the_physics() {
    for row in ROWS {
        check_row(row);
    }
}
