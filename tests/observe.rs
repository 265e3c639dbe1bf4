//! Observables (`[[observe]]`) and the columns added with them (omega_world_*,
//! contact_*, drift), each checked against an independent path: the exact nutation
//! period by quadrature, Euler's kinematics, the geometry of a ball, the energy column.

use std::f64::consts::FRAC_PI_2;
use std::ops::ControlFlow;
use std::path::Path;

use ellipsoid_core::reference;
use ellipsoid_core::scenario::{self, Scenario};
use ellipsoid_core::simulate::{self, EventKind, Outcome, Sample, Status};

fn scenario(name: &str, sets: &[&str]) -> Scenario {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenarios")
        .join(name);
    scenario::load(&path, sets).unwrap()
}

fn run(s: &Scenario) -> (Outcome, Vec<Sample>) {
    let mut samples = Vec::new();
    let out = simulate::simulate(&s.scene, &mut |x| {
        samples.push(*x);
        ControlFlow::Continue(())
    })
    .unwrap();
    (out, samples)
}

fn observed(out: &Outcome) -> Vec<(f64, Sample)> {
    out.events
        .iter()
        .filter_map(|e| match &e.kind {
            EventKind::Observed { sample, .. } => Some((e.t, **sample)),
            _ => None,
        })
        .collect()
}

/// θ of the frictionless nutation scene crosses the middle of its well downwards once
/// per period: the intervals between the observed crossings equal the exact period of
/// the one-degree-of-freedom reduction (quadrature, `reference::nutation`) to 1e-9, and
/// θ at each event is the value crossed to 1e-12.
#[test]
fn val_observed_crossings_give_the_exact_nutation_period() {
    let base = scenario("nutation.toml", &[]);
    let (_, y0) = base.scene.initial_state().unwrap();
    let exact = reference::nutation(&base.scene.body, base.scene.gravity, &y0).unwrap();
    let mid = 0.5 * (exact.theta_min + exact.theta_max);
    let set = format!(
        "observe=[{{ name = \"mid\", column = \"theta\", crosses = {mid:e}, direction = \"down\" }}]"
    );
    let s = scenario("nutation.toml", &[set.as_str()]);
    let (out, _) = run(&s);
    assert_eq!(out.status, Status::Completed);
    let events = observed(&out);
    assert!(events.len() > 10, "{} crossings", events.len());
    for (t, sample) in &events {
        assert!(
            (sample.angles.theta - mid).abs() < 1e-12,
            "θ = {} at t = {t}",
            sample.angles.theta
        );
        assert_eq!(sample.t, *t);
    }
    let periods: Vec<f64> = events.windows(2).map(|w| w[1].0 - w[0].0).collect();
    let worst = periods
        .iter()
        .map(|p| (p - exact.period).abs() / exact.period)
        .fold(0.0, f64::max);
    assert!(
        worst < 1e-9,
        "period error {worst:e} (T = {})",
        exact.period
    );
}

/// A terminal observable ends the run exactly where the non-terminal one is reported:
/// the tippe top's axis passes the horizontal (θ = π/2) at the same time, the last row
/// is that state, and the status is `observed`.
#[test]
fn terminal_observable_ends_the_run_at_the_crossing() {
    let obs = |terminal: bool| {
        format!(
            "observe=[{{ name = \"horizontal\", column = \"theta\", crosses = {FRAC_PI_2:e}, direction = \"up\", terminal = {terminal} }}]"
        )
    };
    let (free, _) = run(&scenario("tippe-top.toml", &[obs(false).as_str()]));
    let (stop, rows) = run(&scenario("tippe-top.toml", &[obs(true).as_str()]));
    let crossings = observed(&free);
    assert_eq!(crossings.len(), 1, "{crossings:?}");
    let t = crossings[0].0;
    assert!(
        (t - 0.750628).abs() < 1e-6,
        "the top passes π/2 at {t} (0.750628 s in tests/physics.rs)"
    );
    assert_eq!(stop.status, Status::Observed { index: 0 });
    assert_eq!(stop.final_sample.t, t);
    let last = rows.last().unwrap();
    assert_eq!(last.t, t);
    assert!(
        (last.angles.theta - FRAC_PI_2).abs() < 1e-9,
        "θ = {}",
        last.angles.theta
    );
}

/// omega_world = R ω_b: its vertical component is φ̇ + ψ̇ cos θ (Euler's kinematic
/// equations), and |ω_world| = |ω_b|; checked on every sample of the tippe top.
#[test]
fn val_world_angular_velocity_follows_euler_kinematics() {
    let (_, rows) = run(&scenario("tippe-top.toml", &["output.t_end=1"]));
    for s in &rows {
        let a = &s.angles;
        if a.theta.sin() < 1e-6 {
            continue;
        }
        let scale = s.omega.norm();
        let vertical = a.phi_dot + a.psi_dot * a.theta.cos();
        assert!(
            (s.omega_world.z - vertical).abs() < 1e-9 * scale,
            "t = {}: {} vs {vertical}",
            s.t,
            s.omega_world.z
        );
        assert!((s.omega_world.norm() - s.omega.norm()).abs() < 1e-12 * scale);
    }
}

/// For the billiard ball (centred mass) the contact point lies under G; for the tilted
/// nutation body it lies, seen from above, on the line of the tilted axis.
#[test]
fn val_contact_point_geometry() {
    let (_, rows) = run(&scenario("billiard.toml", &[]));
    for s in &rows {
        assert!(
            (s.contact - s.position.xy()).norm() < 1e-15 * (1.0 + s.position.norm()),
            "t = {}",
            s.t
        );
    }
    let (_, rows) = run(&scenario("nutation.toml", &["output.t_end=1"]));
    for s in &rows {
        let axis = s.angles.rotation() * nalgebra::Vector3::z();
        let d = s.contact - s.position.xy();
        let cross = d.x * axis.y - d.y * axis.x;
        assert!(
            cross.abs() < 1e-12 * 0.03,
            "t = {}: C − G not along the axis ({cross:e})",
            s.t
        );
    }
}

/// The drift column is (E − E(0))/|E(0)| where energy is conserved and
/// (E + W − (E + W)(0))/|(E + W)(0)| otherwise, recomputed from the energy and work columns,
/// and its largest magnitude is the summary's drift of that quantity.
#[test]
fn inv_drift_column_matches_energy_and_work() {
    for (name, with_work) in [("nutation.toml", false), ("egg.toml", true)] {
        let (out, rows) = run(&scenario(name, &[]));
        let q = |s: &Sample| s.energy + if with_work { s.work } else { 0.0 };
        let q0 = q(&rows[0]);
        let mut largest: f64 = 0.0;
        for s in &rows {
            let expected = (q(s) - q0) / q0.abs();
            assert!(
                (s.drift - expected).abs() <= 1e-15 + 1e-6 * expected.abs(),
                "{name} t = {}: {} vs {expected}",
                s.t,
                s.drift
            );
            largest = largest.max(s.drift.abs());
        }
        let which = if with_work {
            ellipsoid_core::invariants::Invariant::EnergyPlusWork
        } else {
            ellipsoid_core::invariants::Invariant::Energy
        };
        let summary = out.drift.get(which).unwrap();
        assert!(
            (largest - summary).abs() <= 1e-6 * summary.max(1e-300),
            "{name}: column {largest:e} vs summary {summary:e}"
        );
    }
}

/// Bad observables are refused by name with the rule.
#[test]
fn bad_observables_are_refused() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/nutation.toml");
    for (set, expect) in [
        (
            "observe=[{ name = \"x\", column = \"thetta\", crosses = 1 }]",
            "did you mean \"theta\"",
        ),
        (
            "observe=[{ name = \"x\", column = \"theta\" }]",
            "observe[0].crosses is missing",
        ),
        (
            "observe=[{ name = \"x\", column = \"theta\", crosses = 1, direction = \"sideways\" }]",
            "expected one of",
        ),
        (
            "observe=[{ name = \"x\", column = \"theta\", crosses = 1 }, { name = \"x\", column = \"phi\", crosses = 1 }]",
            "unique",
        ),
        (
            "observe=[{ name = \"x\", column = \"theta\", crosses = 1, colour = 2 }]",
            "unknown key",
        ),
        ("observe = 3", "array of tables"),
        (
            "observe=[{ name = \"x\", column = \"theta\", crosses = nan }]",
            "finite",
        ),
    ] {
        let e = scenario::load(&path, &[set]).unwrap_err().to_string();
        assert!(e.contains(expect), "{set}: {e}");
    }
}

/// The drift column can be observed too. At rtol 1e-6 the nutation scene's energy drifts
/// by 1e-9 to 1e-8; half the final state's drift is crossed somewhere between t = 0
/// (drift 0) and t_end (the drift is continuous on the dense output), and the event's state
/// carries that drift. (Output rows between step ends add the dense output's own error,
/// larger at loose tolerances, so the rows' drift is not the measure here.)
#[test]
fn the_drift_column_is_observable() {
    let loose = ["solver.rtol=1e-6", "solver.atol=1e-8"];
    let (plain, _) = run(&scenario("nutation.toml", &loose));
    let level = 0.5 * plain.final_sample.drift;
    assert!(level.abs() > 1e-10, "the loose run drifts ({level:e})");
    let set = format!("observe=[{{ name = \"drift\", column = \"drift\", crosses = {level:e} }}]");
    let mut sets = loose.to_vec();
    sets.push(&set);
    let (out, _) = run(&scenario("nutation.toml", &sets));
    let events = observed(&out);
    let (_, sample) = events
        .first()
        .expect("the drift crosses half its final value");
    assert!(
        (sample.drift - level).abs() < 1e-6 * level.abs(),
        "drift {} at the event, level {level}",
        sample.drift
    );
}
