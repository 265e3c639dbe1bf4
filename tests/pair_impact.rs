//! The impact at two contacts in the hybrid machine (docs/physics.md, "Contact spheres",
//! "Impact at two contacts", "Settling at a second surface"): a top falling from its peg
//! onto the rim of its disc takes the rim's impact with an impulse at the peg too and goes
//! on touching with both; the impact keeps the law at each contact and never adds energy.

mod common;

use std::path::Path;

use common::run;
use ellipsoid_core::body::Surface;
use ellipsoid_core::invariants::Invariant;
use ellipsoid_core::simulate::{EventKind, ImpactReport, Mode, Outcome, Sample};

fn load(file: &str, set: &[&str]) -> (Outcome, Vec<Sample>) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let sc = ellipsoid_core::scenario::load(&root.join(file), set)
        .unwrap_or_else(|e| panic!("{file}: {e}"));
    run(&sc.scene)
}

/// The impacts of a run grouped by time: each touchdown's one or two reports.
fn impacts(out: &Outcome) -> Vec<(f64, Vec<ImpactReport>)> {
    let mut groups: Vec<(f64, Vec<ImpactReport>)> = Vec::new();
    for e in &out.events {
        if let EventKind::Impact(r) = e.kind {
            match groups.last_mut() {
                Some((t, reports)) if *t == e.t => reports.push(r),
                _ => groups.push((e.t, vec![r])),
            }
        }
    }
    groups
}

/// The top of `scenarios/top-on-peg.toml` started at θ0 = 0.3 rad with spin `psi_dot`: it
/// falls from its peg onto the rim of its disc.
fn top_falling(psi_dot: f64) -> (Outcome, Vec<Sample>) {
    let spin = format!("initial.psi_dot={psi_dot}");
    load(
        "scenarios/top-on-peg.toml",
        &[
            "initial.theta=0.3",
            &spin,
            "output.t_end=0.6",
            "output.dt=1e-5",
        ],
    )
}

/// The rim's touchdown of a falling top: its time and its impact reports (rim, peg).
fn rim_touchdown(out: &Outcome) -> (f64, ImpactReport, ImpactReport) {
    let (t, reports) = impacts(out)
        .into_iter()
        .find(|(_, r)| r.iter().any(|r| r.surface == Surface::Ellipsoid))
        .expect("the rim touches down");
    let at = |s: Surface| *reports.iter().find(|r| r.surface == s).expect("a report");
    (t, at(Surface::Ellipsoid), at(Surface::Sphere(0)))
}

#[test]
fn a_top_falling_from_its_peg_onto_its_rim_goes_on_touching_with_both() {
    for psi_dot in [30.0, 60.0, 100.0] {
        let (out, samples) = top_falling(psi_dot);
        let (t, rim, peg) = rim_touchdown(&out);
        // The impact took impulse at both contacts and left both on the plane; the run
        // goes on in two contacts from there (where the one-surface impact stopped it).
        assert!(
            rim.impulse.z > 0.0 && peg.impulse.z > 0.0,
            "ψ̇ {psi_dot}: {rim:?} {peg:?}"
        );
        assert!(rim.persistent && peg.persistent, "ψ̇ {psi_dot}");
        let switch = out.events.iter().find(|e| {
            e.t == t
                && e.kind
                    == EventKind::ModeSwitch {
                        from: Mode::Sliding,
                        to: Mode::TwoContacts,
                    }
        });
        assert!(switch.is_some(), "ψ̇ {psi_dot}: {:?}", out.events);
        assert!(
            samples
                .iter()
                .any(|s| s.t > t && s.mode == Mode::TwoContacts),
            "ψ̇ {psi_dot}: no sample on two contacts"
        );
        assert!(
            out.final_sample.t > t + 1e-3,
            "ψ̇ {psi_dot}: ended at the touchdown"
        );
        // E + W is exact through the impact and the two-contact phase.
        let drift = out.drift.get(Invariant::EnergyPlusWork).unwrap();
        assert!(drift.abs() <= 1e-9, "ψ̇ {psi_dot}: E + W drifted {drift:e}");
        // No impact adds energy: each impact's loss is ≥ 0, and the body's energy (kinetic
        // plus potential, which only friction and impacts change here) does not rise
        // across any impact, from the sample before it to the sample after it.
        for (t, reports) in impacts(&out) {
            let loss: f64 = reports.iter().map(|r| r.energy_loss).sum();
            assert!(
                loss >= 0.0,
                "ψ̇ {psi_dot}: the impact at {t} added {loss:e} J"
            );
            let before = samples.iter().rev().find(|s| s.t < t).unwrap();
            let after = samples.iter().find(|s| s.t > t).unwrap();
            assert!(
                after.energy <= before.energy + 1e-12 * before.energy.abs(),
                "ψ̇ {psi_dot}: E rose across the impact at {t}: {} → {}",
                before.energy,
                after.energy
            );
        }
    }
}

#[test]
fn the_pair_impact_keeps_the_unilateral_law_at_both_contacts() {
    for psi_dot in [30.0, 60.0, 100.0] {
        let (out, _) = top_falling(psi_dot);
        let (_, rim, peg) = rim_touchdown(&out);
        for r in [rim, peg] {
            // v⁺ ≥ 0 (no contact point goes into the plane), Λ ≥ 0, Λ v⁺ = 0 (a contact
            // that takes impulse does not leave), and the friction within the cone.
            assert!(r.rebound >= -1e-12, "ψ̇ {psi_dot}: {r:?}");
            assert!(r.impulse.z >= 0.0, "ψ̇ {psi_dot}: {r:?}");
            assert!(
                r.impulse.z * r.rebound.abs() <= 1e-12 * r.impulse.z,
                "ψ̇ {psi_dot}: {r:?}"
            );
            assert!(
                r.impulse.xy().norm() <= 0.3 * r.impulse.z * (1.0 + 1e-9),
                "ψ̇ {psi_dot}: {r:?}"
            );
        }
        // The impact was needed at both: the rim's impulse alone would have driven the
        // peg into the plane, so the peg takes a share of the normal impulse.
        assert!(peg.impulse.z > 1e-3 * rim.impulse.z, "ψ̇ {psi_dot}: {peg:?}");
    }
}

#[test]
fn with_restitution_the_rim_bounces_off_and_the_peg_stays() {
    // e = 0.5: the rim rebounds above its settling speed, the peg (which does not approach)
    // takes no restitution and stays; the run goes on on the peg, E + W exact.
    let (out, _) = load(
        "scenarios/top-on-peg.toml",
        &[
            "initial.theta=0.3",
            "initial.psi_dot=60",
            "contact.restitution=0.5",
            "output.t_end=0.3",
        ],
    );
    let (_, rim, peg) = rim_touchdown(&out);
    assert!(
        rim.impulse.z > 0.0 && peg.impulse.z > 0.0,
        "{rim:?} {peg:?}"
    );
    assert!(rim.rebound > 0.0 && !rim.persistent, "{rim:?}");
    assert!(peg.rebound.abs() <= 1e-9 && peg.persistent, "{peg:?}");
    let drift = out.drift.get(Invariant::EnergyPlusWork).unwrap();
    assert!(drift.abs() <= 1e-9, "E + W drifted {drift:e}");
}

/// Row 9 of the transition table (a second touchdown where the pressed surface stays and
/// the new one rebounds), on the dumbbell of tests/data/spheres/dumbbell.toml: spheres a
/// and b at d = 30 mm either side of G, m = 0.1 kg, I1 = m d². Level, each contact is the
/// other's centre of percussion, W_ab = 1/m − d²/I1 = 0: the impulse at b leaves a's normal
/// velocity at zero, so a stays pressed, and b, frictionless with e = 0.8, rebounds at e
/// times its speed with the effective mass m_b = 1/W_bb = 1/(1/m + d²/I1) = m/2:
/// P = m_b (1 + e) v, loss ½ m_b (1 − e²) v². The run goes on touching with a alone (no
/// change of surface, no switch), and every later touchdown is b's again.
#[test]
fn a_sphere_striking_at_the_pressed_ones_centre_of_percussion_rebounds_while_it_stays() {
    let (out, samples) = load("tests/data/spheres/dumbbell.toml", &[]);
    let (m, d, i1, e) = (0.1, 0.03, 9e-5, 0.8);
    let m_b = 1.0 / (1.0 / m + d * d / i1);
    let touchdowns: Vec<(f64, f64, Surface)> = (out.events.iter())
        .filter_map(|ev| match ev.kind {
            EventKind::Touchdown { speed, surface } => Some((ev.t, speed, surface)),
            _ => None,
        })
        .collect();
    assert!(touchdowns.len() >= 3, "{:?}", out.events);
    for &(t, v, surface) in &touchdowns {
        assert_eq!(surface, Surface::Sphere(1), "at t = {t}");
        let at: Vec<&EventKind> = (out.events.iter())
            .filter(|ev| ev.t == t)
            .map(|ev| &ev.kind)
            .collect();
        let [EventKind::Touchdown { .. }, EventKind::Impact(hit)] = at[..] else {
            panic!("at t = {t}: {at:?}");
        };
        assert_eq!(hit.surface, Surface::Sphere(1));
        assert!(!hit.persistent, "at t = {t}");
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * b.abs();
        assert!(
            close(hit.rebound, e * v),
            "{} against {}",
            hit.rebound,
            e * v
        );
        assert!(
            close(hit.impulse.z, m_b * (1.0 + e) * v),
            "{}",
            hit.impulse.z
        );
        let loss = 0.5 * m_b * (1.0 - e * e) * v * v;
        assert!(
            close(hit.energy_loss, loss),
            "{} against {loss}",
            hit.energy_loss
        );
        let after = samples.iter().find(|s| s.t > t).expect("a row after");
        assert_eq!(after.mode, Mode::Frictionless, "at t = {}", after.t);
        assert!(
            matches!(after.touching[0], Some((Surface::Sphere(0), n)) if n > 0.0),
            "{:?}",
            after.touching
        );
    }
    let drift = out.drift.get(Invariant::EnergyPlusWork).expect("E + W");
    assert!(drift.abs() < 1e-9, "E + W drift {drift:e}");
}
