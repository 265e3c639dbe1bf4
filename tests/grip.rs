//! Sticking at two contacts (docs/physics.md, "Several contacts"): a top lying on its rim and
//! its peg rolls about the line joining them — about a fixed point on the plane, at a
//! constant rate, with no slip and no dissipation — and a top sliding on both stops
//! slipping at each, sticks, and rolls on so.

mod common;

use std::path::Path;

use common::run;
use ellipsoid_core::body::Surface;
use ellipsoid_core::invariants::Invariant;
use ellipsoid_core::simulate::{EventKind, Mode, Outcome, Sample};

/// The top of scenarios/top-on-peg.toml lying on its rim and peg (θ where both touch).
const LYING: &str = "tests/data/spheres/top-lying.toml";
const THETA: f64 = 0.9437659548618835;

fn load(set: &[String]) -> (Outcome, Vec<Sample>) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let sc = ellipsoid_core::scenario::load(&root.join(LYING), set).unwrap();
    run(&sc.scene)
}

/// Each sample's slip speed at each surface (the per-surface columns).
fn slips(samples: &[Sample]) -> Vec<[f64; 2]> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let sc = ellipsoid_core::scenario::load(&root.join(LYING), &[] as &[&str]).unwrap();
    let layout = ellipsoid_core::columns::Layout::of(&sc.scene.body);
    let names = layout.numeric_columns();
    let at = |name: &str| {
        (names.iter().position(|c| c.0 == name)).unwrap_or_else(|| panic!("no column {name}"))
    };
    let (rim, peg) = (at("slip_speed_ellipsoid"), at("slip_speed_peg"));
    let mut row = Vec::new();
    samples
        .iter()
        .map(|s| {
            row.clear();
            row.extend(ellipsoid_core::columns::values(s));
            layout.surface_values(s, &mut row);
            [row[rim], row[peg]]
        })
        .collect()
}

/// The largest departures of `samples` from the steady roll about a fixed point: |θ − θ*|,
/// |φ̇ − Ω|/|Ω| with Ω the first sample's φ̇, the distance O moved, and |φ̇ + ψ̇ cos θ|/|Ω|
/// (ω horizontal). O is the point of the axis at the plane, G − (z_G/cos θ) k.
fn departures(samples: &[Sample]) -> [f64; 4] {
    let apex = |s: &Sample| {
        let (th, ph) = (s.angles.theta, s.angles.phi);
        let k = nalgebra::Vector3::new(th.sin() * ph.sin(), -th.sin() * ph.cos(), th.cos());
        (s.position - s.position.z / th.cos() * k).xy()
    };
    let (o, rate) = (apex(&samples[0]), samples[0].angles.phi_dot);
    samples.iter().fold([0.0_f64; 4], |d, s| {
        let a = &s.angles;
        [
            d[0].max((a.theta - THETA).abs()),
            d[1].max((a.phi_dot - rate).abs() / rate.abs()),
            d[2].max((apex(s) - o).norm()),
            d[3].max((a.phi_dot + a.psi_dot * a.theta.cos()).abs() / rate.abs()),
        ]
    })
}

/// Rolling at both contacts, v_C1 = v_C2 = 0, turns the body about the horizontal line
/// C_1C_2, which meets the symmetry axis at a point O on the plane: the top precesses about
/// the vertical through O. Its tilt is then fixed and its potential energy with it, so
/// energy conservation holds its rate constant: θ = θ*, φ̇ = Ω and O fixed, with
/// ψ̇ = −Ω/cos θ* (ω horizontal, along C_1C_2). Started so under the rolling model, it
/// holds to 1e-9 over 2 s, with no slip at either contact, no work done and E constant.
#[test]
fn inv_a_top_rolling_on_its_rim_and_peg_turns_about_a_fixed_point_at_a_constant_rate() {
    let rate = 3.0;
    let (out, samples) = load(&[
        "contact.model=\"rolling\"".into(),
        format!("initial.phi_dot={rate}"),
        format!("initial.psi_dot={}", -rate / THETA.cos()),
        "output.t_end=2".into(),
        "output.dt=0.01".into(),
    ]);
    assert!(out.status.completed(), "{:?}", out.status);
    assert!(samples[1..].iter().all(|s| s.mode == Mode::TwoContacts));
    let d = departures(&samples);
    let slip = slips(&samples)
        .iter()
        .flatten()
        .fold(0.0_f64, |m, &v| m.max(v));
    let drift = out.drift.get(Invariant::EnergyPlusWork).unwrap();
    let work = samples.last().unwrap().work;
    eprintln!(
        "MEASURED rolling on rim and peg: |θ − θ*| {:.1e} rad, |φ̇ − Ω|/Ω {:.1e}, O moved \
         {:.1e} m, ω off the line {:.1e}, slip {slip:.1e} m/s, W {work:.1e} J, E + W drift \
         {drift:.1e}",
        d[0], d[1], d[2], d[3]
    );
    assert!(d.iter().all(|&x| x < 1e-9), "not the steady roll: {d:?}");
    assert!(slip < 1e-9, "slip {slip:e}");
    assert!(drift.abs() < 1e-10, "E + W drift {drift:e}");
    assert!(
        work.abs() < 1e-15,
        "a rolling contact dissipates {work:e} J"
    );
}

/// A top lying on its rim and peg on a Coulomb table (μ = 0.5), spun about the vertical:
/// both contacts slide, friction stops each slip and each contact sticks where it stops
/// (`grip` events, the rim first). Sticking at both leaves the body one motion, the roll
/// about the line C_1C_2: from the last grip on it is the steady roll of the test above
/// (to 1e-9), with no slip and no more work done, and E + W balances throughout.
#[test]
fn val_a_top_sliding_on_its_rim_and_peg_sticks_and_rolls_on() {
    let (out, samples) = load(&[
        "contact.model=\"coulomb\"".into(),
        "contact.friction=0.5".into(),
        "initial.phi_dot=2".into(),
        "output.t_end=1".into(),
    ]);
    assert!(out.status.completed(), "{:?}", out.status);
    assert!(samples[1..].iter().all(|s| s.mode == Mode::TwoContacts));
    let grips: Vec<(Surface, bool, f64)> = (out.events.iter())
        .filter_map(|e| match e.kind {
            EventKind::Grip { surface, sticks } => Some((surface, sticks, e.t)),
            _ => None,
        })
        .collect();
    let stuck: Vec<Surface> = grips.iter().filter(|g| g.1).map(|g| g.0).collect();
    assert_eq!(stuck, [Surface::Ellipsoid, Surface::Sphere(0)], "{grips:?}");
    let last = grips.last().unwrap().2;
    let rolling: Vec<Sample> = samples.iter().filter(|s| s.t > last).copied().collect();
    let d = departures(&rolling);
    let slip = slips(&rolling)
        .iter()
        .flatten()
        .fold(0.0_f64, |m, &v| m.max(v));
    let work = (rolling[0].work, rolling.last().unwrap().work);
    let drift = out.drift.get(Invariant::EnergyPlusWork).unwrap();
    eprintln!(
        "MEASURED sliding on rim and peg: grips {grips:?}; then rolling at φ̇ = {:.6} rad/s: \
         departures {d:?}, slip {slip:.1e} m/s, W {:.6e} → {:.6e} J, E + W drift {drift:.1e}",
        rolling[0].angles.phi_dot, work.0, work.1
    );
    assert!(work.0 > 0.0, "sliding dissipates");
    assert!(d.iter().all(|&x| x < 1e-9), "not the steady roll: {d:?}");
    assert!(slip < 1e-12, "slip {slip:e}");
    assert!((work.1 - work.0).abs() < 1e-15, "rolling dissipates");
    assert!(drift.abs() < 1e-9, "E + W drift {drift:e}");
}
