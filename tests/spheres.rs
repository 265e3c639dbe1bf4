//! Contact spheres (docs/physics.md, "Contact spheres"): exact geometry of a sphere fixed
//! in the body, a sphere that never touches changes nothing, the classic top on its peg
//! sleeps above the critical spin and falls below it, Jellett's quantity on a sphere,
//! and the tippe top's stem touching down at the angle the geometry gives.

mod common;

use std::path::Path;

use common::{G, run};
use ellipsoid_core::body::{Body, Sphere, Surface};
use ellipsoid_core::geometry::{self, Contact};
use ellipsoid_core::model::{Contacts, System};
use ellipsoid_core::simulate::{EventKind, Mode, Outcome, Sample, Status};
use nalgebra::{Matrix3, Vector3};

fn root() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn load(file: &str, set: &[&str]) -> (Outcome, Vec<Sample>) {
    let sc = ellipsoid_core::scenario::load(&root().join(file), set)
        .unwrap_or_else(|e| panic!("{file}: {e}"));
    run(&sc.scene)
}

/// Asserts that in every row of `samples` (a run of `file` with `set`) every surface's gap
/// (the output's `gap_*` columns) is above −1e-15 m, and returns how many surfaces there
/// are.
fn assert_no_gap_below_the_plane(
    file: &str,
    set: &[&str],
    samples: &[Sample],
    case: &str,
) -> usize {
    let sc = ellipsoid_core::scenario::load(&root().join(file), set).unwrap();
    let layout = ellipsoid_core::columns::Layout::of(&sc.scene.body);
    let names = layout.numeric_columns();
    let gaps: Vec<usize> = (0..names.len())
        .filter(|&k| names[k].0.starts_with("gap_"))
        .collect();
    let mut row: Vec<f64> = Vec::new();
    for s in samples {
        row.clear();
        row.extend(ellipsoid_core::columns::values(s));
        layout.surface_values(s, &mut row);
        for &k in &gaps {
            assert!(
                row[k] > -1e-15,
                "{case}, t = {}: {} = {}",
                s.t,
                names[k].0,
                row[k]
            );
        }
    }
    gaps.len()
}

/// The Leine–Glocker tippe top with its stem: ball r1 = 15 mm, G 3 mm below its centre,
/// stem sphere r2 = 5 mm centred 13 mm above the ball's centre (16 mm above G).
fn tippe_top_with_stem() -> Body {
    Body::of_revolution(0.015, 0.015, 6e-3, 8e-7, 7e-7, 0.003)
        .unwrap()
        .with_spheres(vec![Sphere {
            name: "stem".into(),
            center: Vector3::new(0.0, 0.0, 0.013),
            radius: 0.005,
        }])
        .unwrap()
}

/// ζ = Rᵀe3 of a body of revolution tilted by θ (ψ = 0).
fn zeta(theta: f64) -> Vector3<f64> {
    Vector3::new(0.0, theta.sin(), theta.cos())
}

#[test]
fn geo_the_stem_touches_where_both_gaps_vanish_and_g_stands_r2_plus_16_mm_on_it() {
    let body = tippe_top_with_stem();
    let stem = Surface::Sphere(0);
    // Ball touching: the ball's centre is r1 above the plane; the stem's lowest point is
    // then r1 + 13 mm cos θ − r2 above it, zero at cos θ* = (r2 − r1)/13 mm.
    let theta_star = ((0.005_f64 - 0.015) / 0.013).acos();
    let (hb, hs) = (
        geometry::height(&body, Surface::Ellipsoid, zeta(theta_star)),
        geometry::height(&body, stem, zeta(theta_star)),
    );
    assert!(
        (hb - hs).abs() <= 1e-12 * hb,
        "at θ* = {theta_star}: ball {hb}, stem {hs}"
    );
    // Below θ* the ball is the lowest surface, above it the stem.
    for (theta, lowest) in [
        (theta_star - 1e-6, Surface::Ellipsoid),
        (theta_star + 1e-6, stem),
    ] {
        let c = Contact::lowest(&body, zeta(theta), Vector3::zeros());
        assert_eq!(c.surface, lowest, "θ = {theta}");
    }
    // Upright on the stem (θ = π): G stands r2 + 16 mm above the plane.
    let h = geometry::height(&body, stem, zeta(std::f64::consts::PI));
    assert!((h - 0.021).abs() <= 1e-15, "{h}");
}

/// The sphere's contact geometry is the support map of the sphere: ∇h = −r (finite
/// differences of `geometry::height`), the contact point on the sphere with its outward
/// normal along −ζ, and ṙ_b = −ρ ζ̇.
#[test]
fn geo_sphere_contact_is_its_support_point_and_height_gradient() {
    let body = Body::new(
        Vector3::new(0.03, 0.02, 0.01),
        1.0,
        Matrix3::from_diagonal(&Vector3::new(1e-4, 2e-4, 2.5e-4)),
        Vector3::new(0.001, -0.002, -0.003),
    )
    .unwrap()
    .with_spheres(vec![Sphere {
        name: "knob".into(),
        center: Vector3::new(0.01, -0.02, 0.03),
        radius: 0.004,
    }])
    .unwrap();
    let s = Surface::Sphere(0);
    let z = Vector3::new(0.3, -0.5, 0.8).normalize();
    let omega = Vector3::new(3.0, -1.0, 7.0);
    let c = Contact::of(&body, s, z, omega);
    let sphere = &body.spheres()[0];
    assert!(((c.p_c - sphere.center).norm() - sphere.radius).abs() < 1e-15);
    assert!((c.p_c - sphere.center).normalize().dot(&-z) > 1.0 - 1e-14);
    let eps = 1e-6;
    for k in 0..3 {
        let mut dz = Vector3::zeros();
        dz[k] = eps;
        let grad =
            (geometry::height(&body, s, z + dz) - geometry::height(&body, s, z - dz)) / (2.0 * eps);
        assert!(
            (grad + c.r[k]).abs() < 1e-10,
            "gradient {k}: {grad} vs {}",
            -c.r[k]
        );
    }
    let zeta_dot = z.cross(&omega);
    assert!((c.r_dot_surface + sphere.radius * zeta_dot).norm() < 1e-15 * zeta_dot.norm());
}

/// A sphere inside the ball never touches: the run is bit-identical to the ball alone
/// (each phase watches the sphere's gap, which never falls through zero; nothing else
/// changes).
#[test]
fn a_sphere_that_never_touches_changes_nothing_bit_for_bit() {
    let file = "scenarios/tippe-top-disc.toml";
    let set = ["output.t_end=1.5"];
    let (plain, a) = load(file, &set);
    let text = std::fs::read_to_string(root().join(file)).unwrap()
        + "\n[[body.sphere]]\nname = \"inside\"\ncenter = [0.0, 0.0, 0.005]\nradius = 0.004\n";
    let sc = ellipsoid_core::scenario::parse(&text, "inside.toml", &set).unwrap();
    let (with, b) = run(&sc.scene);
    assert_eq!(plain.status, with.status);
    assert_eq!(a.len(), b.len());
    for (x, y) in a.iter().zip(&b) {
        assert_eq!(x, y, "at t = {}", x.t);
    }
}

/// The tippe top with its stem runs exactly as the ball alone until the stem touches;
/// the stem touches at θ* (both gaps zero, geometry above); no impact raises the energy;
/// E + W balances throughout. On its stem the top rises towards θ = π (Leine & Glocker's
/// spinning on the stem); as its spin decays it falls back, and rests on ball and stem at
/// θ* — there θ stays θ* and, G's height being fixed, the two normal forces sum to m g —
/// until the stem's normal force reaches zero and the top goes on on its ball.
#[test]
fn the_tippe_top_on_its_stem_rises_falls_back_and_rests_on_two_contacts() {
    let (ball, a) = load("scenarios/tippe-top-disc.toml", &["output.t_end=6"]);
    let (stem, b) = load("scenarios/tippe-top-stem.toml", &["output.t_end=6"]);
    assert_eq!(ball.status, Status::Completed);
    assert_eq!(stem.status, Status::Completed, "{:?}", stem.status);
    let touch = stem
        .events
        .iter()
        .find(|e| {
            matches!(
                e.kind,
                EventKind::ContactSurface {
                    to: Surface::Sphere(0),
                    ..
                }
            )
        })
        .expect("the stem touches")
        .t;
    let before: Vec<_> = b.iter().take_while(|s| s.t < touch).collect();
    assert!(before.len() > 1000);
    for (x, y) in a.iter().zip(&before) {
        assert_eq!(x, *y, "at t = {}", x.t);
    }
    // The ball-only run passes θ* (where it would go through the table) at the touch.
    let theta_star = ((0.005_f64 - 0.015) / 0.013).acos();
    let crossing = a
        .windows(2)
        .find(|w| w[0].angles.theta < theta_star && w[1].angles.theta >= theta_star)
        .expect("the ball-only run passes θ*");
    assert!(
        crossing[0].t <= touch && touch <= crossing[1].t,
        "the stem touches at t = {touch}, the ball-only run passes θ* between {} and {}",
        crossing[0].t,
        crossing[1].t
    );
    for e in &stem.events {
        if let EventKind::Impact(hit) = &e.kind {
            assert!(
                hit.energy_loss >= 0.0,
                "an impact at t = {} gained energy",
                e.t
            );
        }
    }
    let drift = stem
        .drift
        .get(ellipsoid_core::invariants::Invariant::EnergyPlusWork)
        .unwrap();
    assert!(drift.abs() < 1e-9, "E + W drift {drift:e}");
    let highest = b.iter().map(|s| s.angles.theta).fold(0.0, f64::max);
    assert!(highest > 3.1, "on its stem θ rose only to {highest}");
    let both: Vec<&Sample> = b.iter().filter(|s| s.mode == Mode::TwoContacts).collect();
    assert!(both.len() > 100, "{} samples on two contacts", both.len());
    let mg = 6e-3 * G;
    for s in &both {
        assert!(
            (s.angles.theta - theta_star).abs() < 1e-12,
            "θ = {}",
            s.angles.theta
        );
        assert!(
            (s.normal_force - mg).abs() < 1e-9 * mg,
            "N = {}",
            s.normal_force
        );
    }
    let last_on_both = both.last().unwrap().t;
    assert!(
        stem.events.iter().any(|e| e.t > last_on_both
            && e.kind
                == EventKind::ModeSwitch {
                    from: Mode::TwoContacts,
                    to: Mode::Sliding
                }),
        "the stem leaves again"
    );
}

/// A top lying at rest on its rim and its peg (the angle where both touch; G between the
/// contacts) settles on both within nanoseconds and stays: the two normal forces of the
/// two-contact law equal the statics — N_1 + N_2 = m g and no moment about G,
/// Σ N_i (R r_i) × e3 = 0 — to 1e-12, and E is conserved. On a frictionless table both
/// contacts slide; on a Coulomb table (μ = 0.5) both stick, with no horizontal force.
#[test]
fn val_two_contacts_at_rest_carry_the_statics_normal_forces() {
    for (set, friction, sticks) in [
        (&[] as &[&str], 0.0, [false; 3]),
        (
            &["contact.model=\"coulomb\"", "contact.friction=0.5"][..],
            0.5,
            [true; 3],
        ),
    ] {
        let (out, samples) = load("tests/data/spheres/top-lying.toml", set);
        assert!(out.status.completed(), "{:?}", out.status);
        assert!(samples[1..].iter().all(|s| s.mode == Mode::TwoContacts));
        let body = out_body();
        let y = out.final_state;
        let system = System {
            body: body.touching(Surface::Ellipsoid),
            gravity: G,
            contact: Contacts {
                friction,
                disc: None,
                others: [Surface::Sphere(0); 2],
                count: 2,
                sticks,
            },
            effects: (),
        };
        let ev = system.evaluate(&y);
        let forces = system.contact.forces(&system.body, G, &ev.kin, &ev.load);
        let [n_rim, n_peg, _] = forces.normal;
        // The statics: the horizontal levers (world) of the two contacts about G.
        let rot = ev.kin.rot;
        let zeta = ev.kin.contact.zeta;
        let lever = |s: Surface| rot * Contact::of(&body, s, zeta, Vector3::zeros()).r;
        let (l1, l2) = (lever(Surface::Ellipsoid), lever(Surface::Sphere(0)));
        let along = (l2 - l1).xy().normalize();
        let (x1, x2) = (l1.xy().dot(&along), l2.xy().dot(&along));
        let mg = 0.1 * G;
        let (s1, s2) = (mg * x2 / (x2 - x1), -mg * x1 / (x2 - x1));
        let friction_force = forces.tangential[0].norm() + forces.tangential[1].norm();
        eprintln!(
            "MEASURED two contacts at rest (μ = {friction}): rim {n_rim} N (statics {s1}), \
             peg {n_peg} N (statics {s2}), horizontal forces {friction_force:e} N"
        );
        assert!(s1 > 0.0 && s2 > 0.0, "G lies between the contacts");
        assert!((n_rim - s1).abs() <= 1e-12 * mg, "rim {n_rim} vs {s1}");
        assert!((n_peg - s2).abs() <= 1e-12 * mg, "peg {n_peg} vs {s2}");
        assert!(friction_force <= 1e-12 * mg, "{friction_force:e}");
        let drift = out
            .drift
            .get(ellipsoid_core::invariants::Invariant::Energy)
            .or(out
                .drift
                .get(ellipsoid_core::invariants::Invariant::EnergyPlusWork))
            .unwrap();
        assert!(drift.abs() < 1e-12, "E drift {drift:e}");
    }
}

/// The top of tests/data/spheres/top-lying.toml.
fn out_body() -> Body {
    ellipsoid_core::scenario::load(
        &root().join("tests/data/spheres/top-lying.toml"),
        &[] as &[&str],
    )
    .unwrap()
    .scene
    .body
}

/// Jellett's J = L_G·(G − C) is conserved on a single sphere in contact with a point
/// contact and Coulomb friction (the contact force acts at C, and for a sphere G − C
/// turns with the body's axis of revolution): the tippe top spinning on its stem.
#[test]
fn inv_jellett_is_conserved_on_the_stem() {
    let (out, samples) = load(
        "scenarios/tippe-top-stem.toml",
        &[
            "initial.theta=2.8",
            "contact.contact_radius=0",
            "output.t_end=1",
        ],
    );
    assert!(out.status.completed(), "{:?}", out.status);
    let body = tippe_top_with_stem();
    let jellett = |s: &Sample| {
        let rot = s.angles.rotation();
        let l = rot * (body.inertia() * s.omega);
        let g_minus_c = s.position - Vector3::new(s.contact.x, s.contact.y, 0.0);
        l.dot(&g_minus_c)
    };
    let j0 = jellett(&samples[0]);
    let worst = samples
        .iter()
        .map(|s| ((jellett(s) - j0) / j0).abs())
        .fold(0.0, f64::max);
    eprintln!("MEASURED Jellett on the stem: {worst:e} of J(0) = {j0:e}");
    assert!(worst < 1e-9, "J drifted by {worst:e} of J(0) = {j0}");
    assert!(
        out.events
            .iter()
            .all(|e| !matches!(e.kind, EventKind::ContactSurface { .. })),
        "it stays on its stem"
    );
}

/// A classic top on a frictionless table (peg sphere, G at height d above the peg's
/// centre, A and C about G) sleeps above n_c = √(4 A m g d)/C and falls below it
/// (docs/physics.md, "Contact spheres"): from θ0 = 1e-4 the tilt stays below 1e-3 rad
/// over 3 s at 1.01 n_c and grows past 0.1 rad at 0.99 n_c.
#[test]
fn val_classic_top_sleeps_above_the_critical_spin_and_falls_below() {
    let (a, c, m, d) = (0.03_f64, 0.005_f64, 0.1_f64, 0.04_f64);
    let big_a = m * (a * a + c * c) / 5.0;
    let big_c = 2.0 * m * a * a / 5.0;
    let n_c = (4.0 * big_a * m * G * d).sqrt() / big_c;
    for (factor, sleeps) in [(1.01, true), (0.99, false)] {
        let n = format!("initial.psi_dot={}", factor * n_c);
        let text = std::fs::read_to_string(root().join("scenarios/top-on-peg.toml"))
            .unwrap()
            .replace(
                "model = \"coulomb\"\nfriction = 0.3",
                "model = \"frictionless\"",
            );
        let sc = ellipsoid_core::scenario::parse(&text, "top.toml", &["initial.theta=1e-4", &n])
            .unwrap();
        let (out, samples) = run(&sc.scene);
        let max_tilt = samples.iter().map(|s| s.angles.theta).fold(0.0, f64::max);
        eprintln!(
            "MEASURED classic top at {factor} n_c = {}: max tilt {max_tilt:e}",
            factor * n_c
        );
        if sleeps {
            assert!(out.status.completed(), "{:?}", out.status);
            assert!(max_tilt < 1e-3, "at 1.01 n_c the tilt reached {max_tilt}");
        } else {
            assert!(
                max_tilt > 0.1,
                "at 0.99 n_c the tilt only reached {max_tilt}"
            );
        }
    }
}

/// The hopping tippe top with its stem (scenarios/tippe-top-jump-stem.toml) rocks between
/// ball and stem with ever smaller bounces. Every surface stays on or above the plane in
/// every row (a gap that starts a phase at zero by round-off is a zero the integrator never
/// reports: unless the phase takes it at once, the surface sinks through the plane unseen);
/// E + W balances through the dozens of impacts; the run ends with a clear status and
/// physical numbers.
#[test]
fn a_body_rocking_between_two_surfaces_never_passes_through_the_plane() {
    let file = "scenarios/tippe-top-jump-stem.toml";
    let (out, samples) = load(file, &[]);
    assert_eq!(assert_no_gap_below_the_plane(file, &[], &samples, file), 2);
    let impacts = out
        .events
        .iter()
        .filter(|e| matches!(e.kind, EventKind::Impact(_)))
        .count();
    assert!(impacts > 50, "{impacts} impacts");
    let drift = out
        .drift
        .get(ellipsoid_core::invariants::Invariant::EnergyPlusWork)
        .unwrap();
    assert!(drift.abs() < 1e-9, "E + W drift {drift:e}");
    // Where it stops, the status's approach speed is the motion's (a grazing touchdown
    // taken back seconds along a flight would report a meaningless one: `back_to_contact`).
    match out.status {
        Status::Completed => {}
        Status::SeveralContacts { approach, .. } => assert!(approach.abs() < 0.1, "{approach}"),
        other => panic!("{other:?}"),
    }
}

/// A sphere's name names output columns: one that is not a word of at most 24 ASCII
/// letters, digits or underscores is refused at its TOML value, with the rule.
#[test]
fn a_sphere_name_that_cannot_name_a_column_is_refused_at_its_line() {
    let stem = std::fs::read_to_string(root().join("scenarios/tippe-top-stem.toml")).unwrap();
    let line = 1 + stem.lines().position(|l| l == "name = \"stem\"").unwrap();
    for bad in ["st em", "stem,2", "\u{e9}tige", &"s".repeat(25)] {
        let text = stem.replace("name = \"stem\"", &format!("name = {bad:?}"));
        let err = ellipsoid_core::scenario::parse(&text, "s.toml", &[] as &[&str])
            .err()
            .unwrap_or_else(|| panic!("{bad:?} accepted"))
            .to_string();
        assert!(err.contains(&format!("s.toml:{line}:")), "{err}");
        assert!(err.contains("body.sphere[0].name"), "{err}");
        assert!(
            err.contains("1 to 24 ASCII letters, digits or underscores"),
            "{err}"
        );
    }
    let ok = stem.replace("name = \"stem\"", "name = \"stem_2\"");
    assert!(ellipsoid_core::scenario::parse(&ok, "s.toml", &[] as &[&str]).is_ok());
}

/// An observable may watch a per-surface column: the stem's gap falling through 1 mm while
/// the ball is in contact is located where the geometry puts it, r1 + 13 mm·cos θ − r2 =
/// 1 mm (docs/physics.md, "Contact spheres"), before the stem touches.
#[test]
fn an_observable_watches_a_surface_s_own_column() {
    let stem = std::fs::read_to_string(root().join("scenarios/tippe-top-stem.toml")).unwrap();
    let text = stem.replace(
        "[check]",
        "[[observe]]\nname = \"near\"\ncolumn = \"gap_stem\"\ncrosses = 0.001\ndirection = \"down\"\n\n[check]",
    );
    let sc = ellipsoid_core::scenario::parse(&text, "near.toml", &["output.t_end=1.5"]).unwrap();
    let (out, _) = run(&sc.scene);
    let near = out
        .events
        .iter()
        .find_map(|e| match &e.kind {
            EventKind::Observed { index, sample } if sc.scene.observe[*index].name == "near" => {
                Some((e.t, sample.angles.theta))
            }
            _ => None,
        })
        .expect("the stem comes within 1 mm");
    let touch = out
        .events
        .iter()
        .find(|e| matches!(e.kind, EventKind::ContactSurface { .. }))
        .expect("the stem touches")
        .t;
    assert!(near.0 < touch, "{} {touch}", near.0);
    let theta = ((0.001_f64 - 0.015 + 0.005) / 0.013).acos();
    assert!(
        (near.1 - theta).abs() < 1e-8,
        "θ = {} against {theta}",
        near.1
    );
    // A column the body lacks is refused with the columns it has.
    let bad = text.replace("\"gap_stem\"", "\"gap_peg\"");
    let err = ellipsoid_core::scenario::parse(&bad, "near.toml", &[] as &[&str])
        .err()
        .unwrap()
        .to_string();
    assert!(err.contains("gap_peg") && err.contains("gap_stem"), "{err}");
}

/// A disc on two legs (tests/data/spheres/tripod.toml) falls from one leg onto the other,
/// tips onto its rim, rocks between rim and legs with plastic impacts — the impact at
/// the rim while both legs press is taken at all three contacts (docs/physics.md, "A third
/// surface touching down") — and comes to rest on all three (mode `three_contacts`).
/// - Coulomb (μ = 0.5): at rest, the three normal forces equal the statics — Σ N_i = m g
///   and no moment about G, a 3 × 3 system solved here from each surface's lowest point
///   (`Contact::of`) — to 1e-12 m g; the three gaps equal to 1e-12 m; E + W constant.
/// - Frictionless, spun about its axis: the plane pushes only vertically, so the
///   horizontal momentum (zero) and the vertical angular momentum L_z stay as they were
///   through every impact and on three contacts, where the disc spins on at its rate
///   about the vertical; E + W constant.
#[test]
fn val_three_contacts_at_rest_carry_the_statics_normal_forces() {
    let file = "tests/data/spheres/tripod.toml";
    let on_three = |out: &Outcome, samples: &[Sample]| {
        assert!(out.status.completed(), "{:?}", out.status);
        let entered = (out.events.iter().rev())
            .find_map(|e| match e.kind {
                EventKind::ModeSwitch {
                    to: Mode::ThreeContacts,
                    ..
                } => Some(e.t),
                _ => None,
            })
            .expect("the disc reaches three contacts");
        let after: Vec<&Sample> = samples.iter().filter(|s| s.t > entered).collect();
        assert!(after.len() > 100, "{entered}");
        assert!(after.iter().all(|s| s.mode == Mode::ThreeContacts));
        let balance = out
            .drift
            .get(ellipsoid_core::invariants::Invariant::EnergyPlusWork);
        assert!(balance.unwrap().abs() < 1e-11, "E + W {balance:?}");
        entered
    };
    let (out, samples) = load(file, &["contact.model=\"coulomb\"", "contact.friction=0.5"]);
    let entered = on_three(&out, &samples);
    let sc = ellipsoid_core::scenario::load(&root().join(file), &[] as &[&str]).unwrap();
    let body = sc.scene.body;
    let y = out.final_state;
    let rot = ellipsoid_core::state::rotation(&y);
    let zeta = rot.row(2).transpose();
    let surfaces = [Surface::Ellipsoid, Surface::Sphere(0), Surface::Sphere(1)];
    let heights = surfaces.map(|s| geometry::height(&body, s, zeta));
    assert!(
        heights.iter().all(|h| (h - heights[0]).abs() <= 1e-12),
        "{heights:?}"
    );
    let levers = surfaces.map(|s| rot * Contact::of(&body, s, zeta, Vector3::zeros()).r);
    let mg = body.mass() * G;
    let statics = Matrix3::from_fn(|row, i| match row {
        0 => 1.0,
        1 => levers[i].x,
        _ => levers[i].y,
    })
    .lu()
    .solve(&Vector3::new(mg, 0.0, 0.0))
    .unwrap();
    let last = samples.last().unwrap();
    let reported = surfaces.map(|s| {
        (last.touching.iter().flatten())
            .find(|t| t.0 == s)
            .map(|t| t.1)
            .expect("every surface in contact")
    });
    let speed = last.velocity.norm() + last.omega.norm() * 0.04;
    eprintln!(
        "MEASURED the tripod (Coulomb) rests on three contacts from {entered:.6} s: N = \
         {reported:?} N, statics {statics:?}, speed {speed:e} m/s"
    );
    assert!(statics.iter().all(|&n| n > 0.0), "G over the triangle");
    for i in 0..3 {
        assert!(
            (reported[i] - statics[i]).abs() <= 1e-12 * mg,
            "{i}: {reported:?}"
        );
    }
    assert!(speed < 1e-12, "at rest: {speed:e}");

    let (out, samples) = load(file, &["initial.psi_dot=3"]);
    let entered = on_three(&out, &samples);
    let lz = |s: &Sample| {
        let rot = s.angles.rotation().to_rotation_matrix().into_inner();
        (rot * body.inertia() * s.omega).z
    };
    let (lz0, spin) = (lz(&samples[0]), samples.last().unwrap().omega_world.z);
    let worst = samples
        .iter()
        .map(|s| {
            (lz(s) - lz0)
                .abs()
                .max(s.velocity.xy().norm() * body.mass())
        })
        .fold(0.0, f64::max);
    eprintln!(
        "MEASURED the tripod (frictionless, ψ̇0 = 3) on three contacts from {entered:.6} s, \
         spinning at {spin} rad/s; L_z {lz0:e}, worst change of L_z or m|v_G,h| {worst:e}"
    );
    assert!(worst <= 1e-8 * lz0.abs(), "{worst:e} of {lz0:e}");
    assert!(spin.abs() > 1.0, "it spins on: {spin}");
}

/// The tripod of tests/data/spheres/tripod.toml spun fast (frictionless, ψ̇0 = 80 rad/s):
/// on its legs, it nutates and its rim grazes the plane again and again, each time at a
/// lower speed (5e-3, 1e-4, 4e-6, 1e-7 m/s, ...). Where the impact at the three contacts
/// leaves all three within their settling speeds but the rim would pull (N ≤ 0 on three
/// contacts), the contacts that stay are the consistent subset (docs/physics.md, "Which
/// contacts stay": for frictionless contacts the solution of the normal forces'
/// complementarity problem): the legs, the rim's gap opening. The run used to stop there
/// with `several_contacts`. Asserted: the run completes; some rim touchdown leaves the
/// legs in contact and the rim off the plane; no cascade of touchdowns (at most 10 within
/// any microsecond: the residual velocities of the contacts that stay are removed with
/// all three constraints, so the rim left out is not driven back into the plane); no
/// surface below the plane by more than 1e-8 m and no normal force < 0 in any sample;
/// E + W, the horizontal momentum (zero) and L_z kept, the plane pushing only vertically.
#[test]
fn val_a_fast_tripod_goes_on_on_its_legs_where_its_rim_grazes() {
    let file = "tests/data/spheres/tripod.toml";
    let (out, samples) = load(file, &["initial.psi_dot=80", "output.t_end=2"]);
    assert!(out.status.completed(), "{:?}", out.status);
    let sc = ellipsoid_core::scenario::load(&root().join(file), &[] as &[&str]).unwrap();
    let body = sc.scene.body;

    // A rim touchdown whose impacts leave the legs pressed and the rim off the plane.
    let legs_alone = out.events.windows(4).filter(|w| {
        let persistent = |e: &ellipsoid_core::simulate::EventRecord, s: Surface| match &e.kind {
            EventKind::Impact(r) => (r.surface == s).then_some(r.persistent),
            _ => None,
        };
        matches!(
            w[0].kind,
            EventKind::Touchdown {
                surface: Surface::Ellipsoid,
                ..
            }
        ) && w[1..]
            .iter()
            .any(|e| persistent(e, Surface::Ellipsoid) == Some(false))
            && w[1..]
                .iter()
                .any(|e| persistent(e, Surface::Sphere(0)) == Some(true))
            && w[1..]
                .iter()
                .any(|e| persistent(e, Surface::Sphere(1)) == Some(true))
    });
    let left_out = legs_alone.count();
    let touchdowns: Vec<f64> = (out.events.iter())
        .filter(|e| matches!(e.kind, EventKind::Touchdown { .. }))
        .map(|e| e.t)
        .collect();
    let crowd = (touchdowns.iter())
        .map(|&t| touchdowns.iter().filter(|&&u| (u - t).abs() < 1e-6).count())
        .max()
        .unwrap_or(0);
    let surfaces = [Surface::Ellipsoid, Surface::Sphere(0), Surface::Sphere(1)];
    let mut deepest = f64::INFINITY;
    for s in &samples {
        let zeta = s
            .angles
            .rotation()
            .to_rotation_matrix()
            .into_inner()
            .row(2)
            .transpose();
        for surface in surfaces {
            deepest = deepest.min(s.position.z - geometry::height(&body, surface, zeta));
        }
        for (_, n) in s.touching.iter().flatten() {
            assert!(*n >= 0.0, "N = {n} at t = {}", s.t);
        }
    }
    let lz = |s: &Sample| {
        let rot = s.angles.rotation().to_rotation_matrix().into_inner();
        (rot * body.inertia() * s.omega).z
    };
    let lz0 = lz(&samples[0]);
    let worst = (samples.iter())
        .map(|s| {
            (lz(s) - lz0)
                .abs()
                .max(s.velocity.xy().norm() * body.mass())
        })
        .fold(0.0, f64::max);
    let balance = (out.drift)
        .get(ellipsoid_core::invariants::Invariant::EnergyPlusWork)
        .unwrap();
    eprintln!(
        "MEASURED the fast tripod: {} touchdowns, {left_out} leaving the legs alone, at most \
         {crowd} within 1 µs; deepest gap {deepest:e} m; L_z {lz0:e}, worst change of L_z or \
         m|v_G,h| {worst:e}; E + W {balance:e}",
        touchdowns.len()
    );
    assert!(left_out >= 1, "no rim touchdown left the legs alone");
    assert!(crowd <= 10, "{crowd} touchdowns within 1 µs");
    assert!(deepest >= -1e-8, "{deepest:e} m");
    assert!(worst <= 1e-8 * lz0.abs(), "{worst:e} of {lz0:e}");
    assert!(balance.abs() < 1e-11, "E + W {balance:e}");
}

/// Four legs at once: the stool of tests/data/spheres/stool.toml dropped level, and
/// tilted 0.001 to 0.05 rad in three directions. Four contacts are statically
/// indeterminate, and the machine never needs them: a leg that reaches the plane at rest
/// relative to it is watched from δz below and carries no force. Every run (measured) ends
/// on the two legs of one diagonal, m g/2 each with G above their midpoint, the other two
/// at zero gap with no force: one of the splits the statics admits (complementarity
/// holds at each leg: zero gap, zero force). Asserted: every run ends `completed`, level
/// (θ < 1e-12) and at rest (|v_G| and |ω| < 1e-9) on the plane, its normal forces summing to
/// m g to 1e-12, no leg's gap below −1e-15 m in any row, E + W to 1e-9.
#[test]
fn val_a_stool_dropped_on_four_legs_comes_to_rest_level() {
    let file = "tests/data/spheres/stool.toml";
    let weight = 0.05 * 9.81;
    let mut cases = vec![(0.0, 0.0)];
    for theta in [1e-3, 1e-2, 5e-2] {
        cases.extend([0.0, 0.3, std::f64::consts::FRAC_PI_4].map(|phi| (theta, phi)));
    }
    for (theta, phi) in cases {
        let (t, p) = (
            format!("initial.theta={theta}"),
            format!("initial.phi={phi}"),
        );
        let (out, samples) = load(file, &[&t, &p]);
        let case = format!("θ0 = {theta}, φ0 = {phi}");
        assert!(
            matches!(out.status, Status::Completed),
            "{case}: {:?}",
            out.status
        );
        let surfaces = assert_no_gap_below_the_plane(file, &[&t, &p], &samples, &case);
        assert_eq!(surfaces, 5, "the disc and four legs");
        let f = &out.final_sample;
        assert!(
            f.angles.theta.abs() < 1e-12,
            "{case}: θ = {}",
            f.angles.theta
        );
        assert!(
            f.velocity.norm() < 1e-9 && f.omega.norm() < 1e-9,
            "{case}: {f:?}"
        );
        let carried: f64 = f.touching.iter().flatten().map(|(_, n)| n).sum();
        assert!(
            (carried - weight).abs() < 1e-12 * weight,
            "{case}: ΣN = {carried}"
        );
        assert!((f.normal_force - weight).abs() < 1e-12 * weight, "{case}");
        let drift = (out.drift)
            .get(ellipsoid_core::invariants::Invariant::EnergyPlusWork)
            .unwrap();
        assert!(drift.abs() < 1e-9, "{case}: E + W drift {drift:e}");
        eprintln!("MEASURED {case}: ends {:?} on {:?}", f.mode, f.touching);
    }
}

/// Three contact points on one line: the dumbbell of tests/data/spheres/dumbbell.toml with
/// its ball grown to the spheres' radius (10 mm), plastic impacts, spun about its axis at
/// 0 and 5 rad/s, under DOP853 and DOPRI5. Level on its end spheres, the ball touches the
/// plane midway between their contacts at rest relative to it: its normal velocity is
/// the round-off of a body at rest (−1e-41 m/s measured), which counted as approaching, so
/// it was taken as a touchdown, stepped back along a free fall that never happened
/// (+1.2e-7 m/s), and the body hopped off all three and fell back, 10 000 times at one
/// instant: `chattering`. A normal velocity now approaches only beyond its round-off
/// (`Numerics::velocity_resolution`); and at rest DOP853's error norm met subnormal sums
/// (`a_state_whose_error_norm_is_subnormal_integrates`, tests/val_integrators.rs). Each
/// run completes on the end spheres with G at rest (1e-9 m/s; the spin about the axis goes
/// on, frictionless) and the axis level (1e-12 rad), ΣN = m g to 1e-12, no gap below
/// −1e-15 m in any row, E + W to 1e-9.
#[test]
fn val_a_dumbbell_resting_on_three_contacts_in_a_line_stays_at_rest() {
    let file = "tests/data/spheres/dumbbell.toml";
    let grown = ["body.a=0.01", "body.c=0.01", "contact.restitution=0"];
    let mut set: Vec<&str> = grown.to_vec();
    let weight = 0.1 * 9.81;
    for method in ["solver.method=\"dop853\"", "solver.method=\"dopri5\""] {
        for spin in ["initial.psi_dot=0", "initial.psi_dot=5"] {
            set.truncate(grown.len());
            set.extend([method, spin]);
            let (out, samples) = load(file, &set);
            let case = format!("{method}, {spin}");
            assert!(
                matches!(out.status, Status::Completed),
                "{case}: {:?}",
                out.status
            );
            assert_eq!(
                assert_no_gap_below_the_plane(file, &set, &samples, &case),
                3
            );
            let f = &out.final_sample;
            assert_eq!(f.mode, Mode::TwoContacts, "{case}");
            let tilt = f.angles.theta - std::f64::consts::FRAC_PI_2;
            assert!(tilt.abs() < 1e-12, "{case}: θ − π/2 = {tilt:e}");
            assert!(f.velocity.norm() < 1e-9, "{case}: {:?}", f.velocity);
            let carried: f64 = f.touching.iter().flatten().map(|(_, n)| n).sum();
            assert!(
                (carried - weight).abs() < 1e-12 * weight,
                "{case}: ΣN = {carried}"
            );
            let drift = (out.drift)
                .get(ellipsoid_core::invariants::Invariant::EnergyPlusWork)
                .unwrap();
            assert!(drift.abs() < 1e-9, "{case}: E + W drift {drift:e}");
        }
    }
}

/// The sizes of a body's surfaces span at most what a run resolves (issue 48: a contact
/// sphere of radius 10⁶ m under a 15 mm top was accepted and ground 19 s to a solver
/// failure): with L the largest semi-axis, a radius from 10⁻⁶ L to 10³ L and a centre at
/// most 10³ L from C0. Each refusal names the key, its value, the rule and the place in
/// the file (file:line:col), at once; the bounds themselves are accepted.
#[test]
fn sphere_sizes_are_bounded_by_the_body_and_refused_at_their_line() {
    let file = "scenarios/tippe-top-stem.toml";
    let text = std::fs::read_to_string(root().join(file)).unwrap();
    let with = |center: &str, radius: &str| {
        text.replace("center = [0.0, 0.0, 0.013]", &format!("center = {center}"))
            .replace("radius = 0.005", &format!("radius = {radius}"))
    };
    let line_of = |t: &str, key: &str| t[..t.find(key).unwrap()].matches('\n').count() + 1;
    let start = std::time::Instant::now();
    for (center, radius, key, says) in [
        (
            "[0.0, 0.0, 0.013]",
            "1e6",
            "radius",
            "times the body's largest semi-axis",
        ),
        ("[0.0, 0.0, 0.013]", "15.01", "radius", "1.500e1 m"),
        ("[0.0, 0.0, 0.013]", "1e-8", "radius", "1.500e-8"),
        ("[0.0, 0.0, 16.0]", "0.005", "center", "at most 1e3 times"),
        (
            "[1e6, 0.0, 0.0]",
            "0.005",
            "center",
            "from the ellipsoid's centre",
        ),
    ] {
        let t = with(center, radius);
        let e = ellipsoid_core::scenario::parse(&t, "top.toml", &[] as &[&str])
            .expect_err(radius)
            .to_string();
        let line = line_of(&t, &format!("{key} = "));
        assert!(
            e.starts_with(&format!("top.toml:{line}:")),
            "{e} (line {line})"
        );
        assert!(e.contains(&format!("body.sphere[0].{key} = ")), "{e}");
        assert!(e.contains(says), "{e} does not say {says:?}");
    }
    assert!(start.elapsed() < std::time::Duration::from_secs(1));
    // The bounds are allowed: L = 0.015 m.
    for (center, radius) in [
        ("[0.0, 0.0, 14.9]", "14.9"),
        ("[0.0, 0.0, 0.013]", "1.6e-8"),
    ] {
        let t = with(center, radius);
        ellipsoid_core::scenario::parse(&t, "top.toml", &[] as &[&str])
            .unwrap_or_else(|e| panic!("{center} {radius}: {e}"));
    }
}
