//! Flight, touchdown, impact and settling (docs/physics.md, "Flight", "Impact at
//! touchdown", "Settling"): each test checks the physics against an independent result —
//! the parabola, Euler–Poinsot and Jacobi's elliptic solution of the free top, the
//! bouncing ball's accumulation time, energy conservation through elastic impacts.

mod common;

use common::{G, angles, ball, run, scene};
use ellipsoid_core::body::{Body, uniform_inertia};
use ellipsoid_core::invariants::Invariant;
use ellipsoid_core::simulate::{
    ContactModel, EventKind, ImpactReport, Landing, LiftOff, Mode, Outcome, Sample, Scene, Status,
};
use nalgebra::{Matrix3, Vector2, Vector3};

/// A figure the test measured, printed for docs/hard-cases.md (`--nocapture`).
fn measured(case: &str, figure: String) {
    eprintln!("MEASURED {case}: {figure}");
}

fn triaxial() -> Body {
    let ax = Vector3::new(0.03, 0.02, 0.01);
    Body::new(ax, 0.2, uniform_inertia(ax, 0.2), Vector3::zeros()).unwrap()
}

/// Scene `s` in flight: `height` above the plane, velocity `v` (vz included), lift-off flies.
fn flying(mut s: Scene, v: Vector3<f64>, height: f64) -> Scene {
    s.landing = Landing {
        restitution: 0.0,
        lift_off: LiftOff::Fly,
        ..Landing::default()
    };
    s.initial.velocity = Some(v.xy());
    s.initial.height = height;
    s.initial.velocity_z = Some(v.z);
    s
}

fn rotation(s: &Sample) -> Matrix3<f64> {
    s.angles.rotation().to_rotation_matrix().into_inner()
}

/// World angular momentum about G, R I ω_b.
fn l_world(body: &Body, s: &Sample) -> Vector3<f64> {
    rotation(s) * (body.inertia() * s.omega)
}

fn impacts(out: &Outcome) -> usize {
    hits(out).len()
}

/// (time, report) of every impact.
fn hits(out: &Outcome) -> Vec<(f64, ImpactReport)> {
    out.events
        .iter()
        .filter_map(|e| match e.kind {
            EventKind::Impact(hit) => Some((e.t, hit)),
            _ => None,
        })
        .collect()
}

/// Times of the events of one kind.
fn times(out: &Outcome, kind: fn(&EventKind) -> bool) -> Vec<f64> {
    out.events
        .iter()
        .filter(|e| kind(&e.kind))
        .map(|e| e.t)
        .collect()
}

fn is_lift_off(k: &EventKind) -> bool {
    *k == EventKind::LiftOff
}

fn is_touchdown(k: &EventKind) -> bool {
    matches!(k, EventKind::Touchdown { .. })
}

/// In flight G follows the parabola exactly and L_G and the rotational energy are
/// constant (torque-free), to 1e-12 relative.
#[test]
fn flight_is_a_parabola_with_torque_free_rotation() {
    let body = triaxial();
    let (v0, h0) = (Vector3::new(0.3, -0.2, 1.0), 1.0);
    let sc = flying(
        scene(
            body.clone(),
            ContactModel::Coulomb { friction: 0.3 },
            angles(0.7, 0.2, -0.4, 3.0, 5.0, 20.0),
            None,
            0.5,
            1e-3,
            1e-14,
        ),
        v0,
        h0,
    );
    let (out, samples) = run(&sc);
    assert_eq!(out.status, Status::Completed);
    assert_eq!(impacts(&out), 0);
    let s0 = &samples[0];
    let (l0, k0) = (
        l_world(&body, s0),
        0.5 * s0.omega.dot(&(body.inertia() * s0.omega)),
    );
    let mut worst = [0.0f64; 3];
    for s in &samples {
        assert_eq!(s.mode, Mode::Flight);
        let t = s.t;
        let expect = s0.position + v0 * t - Vector3::new(0.0, 0.0, 0.5 * G * t * t);
        worst[0] = worst[0].max((s.position - expect).norm() / (h0 + v0.norm()));
        worst[1] = worst[1].max((l_world(&body, s) - l0).norm() / l0.norm());
        worst[2] = worst[2].max((0.5 * s.omega.dot(&(body.inertia() * s.omega)) - k0).abs() / k0);
        assert!(s.gap > 0.0 && s.normal_force == 0.0);
    }
    assert!(worst.iter().all(|w| *w < 1e-12), "{worst:?}");
    measured(
        "flight parabola",
        format!(
            "position {:.1e}, L_G {:.1e}, rotational energy {:.1e}",
            worst[0], worst[1], worst[2]
        ),
    );
}

/// Euler–Poinsot: an axisymmetric body's axis precesses about the fixed L at |L|/I1.
#[test]
fn flight_axisymmetric_axis_precesses_at_l_over_i1() {
    let body = common::oblate();
    let i1 = body.inertia()[(0, 0)];
    let mut sc = flying(
        scene(
            body.clone(),
            ContactModel::Frictionless,
            angles(0.5, 0.0, 0.0, 0.0, 7.0, 40.0),
            None,
            1.0,
            1e-3,
            1e-12,
        ),
        Vector3::zeros(),
        0.2,
    );
    sc.gravity = 0.0;
    let (out, samples) = run(&sc);
    assert_eq!(out.status, Status::Completed);
    let l = l_world(&body, &samples[0]);
    let (lhat, rate) = (l.normalize(), l.norm() / i1);
    // The axis e3* in a frame (u, w, l̂) about L: its angle there advances at |L|/I1.
    let u = lhat.cross(&Vector3::x()).normalize();
    let w = lhat.cross(&u);
    let angle = |s: &Sample| {
        let axis = rotation(s) * Vector3::z();
        axis.dot(&w).atan2(axis.dot(&u))
    };
    let (a0, cone0) = (
        angle(&samples[0]),
        (rotation(&samples[0]) * Vector3::z()).dot(&lhat),
    );
    let mut worst: f64 = 0.0;
    for s in &samples {
        let expect = a0 + rate * s.t;
        let d = (angle(s) - expect + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU)
            - std::f64::consts::PI;
        worst = worst.max(d.abs());
        assert!(((rotation(s) * Vector3::z()).dot(&lhat) - cone0).abs() < 1e-12);
    }
    assert!(worst < 1e-10, "precession phase error {worst:e} rad");
    measured(
        "flight Euler-Poinsot",
        format!(
            "phase error {worst:.1e} rad over {:.1} turns",
            rate / std::f64::consts::TAU
        ),
    );
}

/// Jacobi's elliptic functions sn, cn, dn (u | m = k²) by the descending Landen / AGM
/// method (Abramowitz & Stegun 16.4), for the reference below.
fn jacobi(u: f64, m: f64) -> (f64, f64, f64) {
    let (mut a, mut b, mut c) = ([1.0f64; 12], [0.0f64; 12], [0.0f64; 12]);
    b[0] = (1.0 - m).sqrt();
    c[0] = m.sqrt();
    let mut n = 0;
    while c[n].abs() > 1e-17 && n < 11 {
        a[n + 1] = 0.5 * (a[n] + b[n]);
        b[n + 1] = (a[n] * b[n]).sqrt();
        c[n + 1] = 0.5 * (a[n] - b[n]);
        n += 1;
    }
    let mut phi = 2f64.powi(n as i32) * a[n] * u;
    for k in (1..=n).rev() {
        phi = 0.5 * (phi + (c[k] / a[k] * phi.sin()).asin());
    }
    let (sn, cn) = phi.sin_cos();
    (sn, cn, (1.0 - m * sn * sn).sqrt())
}

/// A triaxial body in torque-free flight follows Jacobi's solution (Landau & Lifshitz,
/// Mechanics §37): ω1 = A cn τ, ω2 = B sn τ, ω3 = C dn τ.
#[test]
fn flight_triaxial_rotation_follows_jacobi() {
    let body = triaxial();
    let i = body.inertia();
    let (i1, i2, i3) = (i[(0, 0)], i[(1, 1)], i[(2, 2)]);
    assert!(i1 < i2 && i2 < i3);
    let w0 = Vector3::new(3.0, 0.0, 8.0);
    let mut sc = flying(
        scene(
            body.clone(),
            ContactModel::Frictionless,
            angles(0.9, 0.3, 0.2, 0.0, 0.0, 0.0),
            None,
            2.0,
            1e-3,
            1e-13,
        ),
        Vector3::zeros(),
        0.1,
    );
    sc.gravity = 0.0;
    sc.initial.omega_body = Some(w0);
    let two_e = i1 * w0.x * w0.x + i3 * w0.z * w0.z;
    let m2 = (i1 * w0.x).powi(2) + (i3 * w0.z).powi(2);
    assert!(m2 > two_e * i2, "the case M² > 2E I2");
    let amp = Vector3::new(
        ((two_e * i3 - m2) / (i1 * (i3 - i1))).sqrt(),
        ((two_e * i3 - m2) / (i2 * (i3 - i2))).sqrt(),
        ((m2 - two_e * i1) / (i3 * (i3 - i1))).sqrt(),
    );
    let rate = ((i3 - i2) * (m2 - two_e * i1) / (i1 * i2 * i3)).sqrt();
    let k2 = (i2 - i1) * (two_e * i3 - m2) / ((i3 - i2) * (m2 - two_e * i1));
    let (out, samples) = run(&sc);
    assert_eq!(out.status, Status::Completed);
    let mut worst: f64 = 0.0;
    for s in &samples {
        let (sn, cn, dn) = jacobi(rate * s.t, k2);
        let expect = Vector3::new(amp.x * cn, amp.y * sn, amp.z * dn);
        worst = worst.max((s.omega - expect).norm() / w0.norm());
    }
    assert!(worst < 1e-11, "ω against Jacobi's solution: {worst:e}");
    measured(
        "flight Jacobi",
        format!(
            "ω error {worst:.1e} relative over {:.1} periods",
            rate * 2.0 / 4.0 / 1.85
        ),
    );
}

/// The bouncing ball (uniform sphere, centred mass, frictionless, e = 1/2, dropped from
/// h): touchdowns at t₁ = √(2h/g) and then after flights 2 e^k v₁/g, accumulating at
/// t∞ = t₁ + (2 v₁/g) e/(1 − e). Contact becomes persistent there (to 1e-8 s) and the
/// ball rests on the plane: N = m g.
#[test]
fn zeno_bounces_accumulate_at_the_analytic_time_then_rest() {
    let (r, m, h, e) = (0.01, 0.1, 0.05, 0.5);
    let mut sc = flying(
        scene(
            ball(r, m),
            ContactModel::Frictionless,
            angles(0.0, 0.0, 0.0, 0.0, 0.0, 0.0),
            None,
            0.5,
            1e-3,
            1e-13,
        ),
        Vector3::zeros(),
        h,
    );
    sc.landing.restitution = e;
    let (out, samples) = run(&sc);
    assert_eq!(out.status, Status::Completed);
    let t1 = (2.0 * h / G).sqrt();
    let v1 = G * t1;
    let t_inf = t1 + 2.0 * v1 / G * e / (1.0 - e);
    let touchdowns = times(&out, is_touchdown);
    assert!(
        (touchdowns[0] - t1).abs() < 1e-12,
        "first touchdown {}",
        touchdowns[0]
    );
    for (k, w) in touchdowns.windows(2).take(10).enumerate() {
        let flight = 2.0 * v1 * e.powi(k as i32 + 1) / G;
        assert!(
            ((w[1] - w[0]) - flight).abs() < 1e-12,
            "flight {k}: {} vs {flight}",
            w[1] - w[0]
        );
    }
    let settled = out
        .events
        .iter()
        .find_map(|ev| match ev.kind {
            EventKind::Impact(hit) if hit.persistent => Some(ev.t),
            _ => None,
        })
        .expect("contact becomes persistent");
    assert!(
        (settled - t_inf).abs() < 1e-8,
        "settled at {settled}, t∞ = {t_inf}"
    );
    let last = samples.last().unwrap();
    assert_eq!(last.mode, Mode::Frictionless);
    assert!(
        (last.normal_force - m * G).abs() < 1e-12 * m * G,
        "N = {}",
        last.normal_force
    );
    assert!(last.velocity.norm() < 1e-7 && last.gap == 0.0);
    let balance = out.drift.get(Invariant::EnergyPlusWork).unwrap();
    assert!(balance < 1e-12, "E + W drift {balance:e}");
    assert!(
        out.drift.get(Invariant::Energy).is_none(),
        "E is not conserved with e < 1"
    );
    measured(
        "zeno",
        format!(
            "{} bounces; persistent contact {:.1e} s from t∞ = {t_inf:.10} s; E + W drift {balance:.1e}",
            touchdowns.len(),
            settled - t_inf
        ),
    );
}

/// A tilted ellipsoid dropped on a frictionless plane with e = 1 keeps its energy over
/// 100 bounces to 1e-9 (each impact is elastic to round-off; flight and contact are
/// conservative).
#[test]
fn elastic_bounces_of_a_tilted_ellipsoid_keep_the_energy() {
    let ax = Vector3::new(0.02, 0.02, 0.04);
    let body = Body::new(ax, 0.1, uniform_inertia(ax, 0.1), Vector3::zeros()).unwrap();
    let mut sc = flying(
        scene(
            body,
            ContactModel::Frictionless,
            angles(0.7, 0.0, 0.0, 0.0, 0.0, 0.0),
            None,
            20.0,
            1e-2,
            1e-12,
        ),
        Vector3::zeros(),
        0.02,
    );
    sc.landing.restitution = 1.0;
    let (out, _) = run(&sc);
    assert!(out.status.finished(), "{:?}", out.status);
    let n = impacts(&out);
    assert!(n >= 100, "{n} impacts");
    let drift = out
        .drift
        .get(Invariant::Energy)
        .expect("elastic and frictionless: E conserved");
    assert!(drift < 1e-9, "energy drift {drift:e} over {n} impacts");
    measured(
        "elastic bounces",
        format!("{n} impacts in 20 s, energy drift {drift:.1e}"),
    );
}

fn bundled(name: &str) -> Scene {
    let path = format!("{}/../../scenarios/{name}", env!("CARGO_MANIFEST_DIR"));
    ellipsoid_core::scenario::load(std::path::Path::new(&path), &[] as &[&str])
        .unwrap()
        .scene
}

/// scenarios/egg-jump.toml: the fast egg on weak friction (hard case 10) no longer stops
/// at its first loss of contact: it flies, lands (e = 0) and goes on, jumping again and
/// again; E + W balances through every phase, flights have a positive gap and N = 0, and
/// contact phases N ≥ 0.
#[test]
fn the_jumping_egg_flies_lands_and_goes_on() {
    let (out, samples) = run(&bundled("egg-jump.toml"));
    assert_eq!(out.status, Status::Completed);
    let (lifts, downs) = (times(&out, is_lift_off), times(&out, is_touchdown));
    assert!(
        (lifts[0] - 1.963235).abs() < 1e-5,
        "lift-off at {}",
        lifts[0]
    );
    assert!(lifts.len() > 10 && downs.len() == lifts.len());
    let flight: Vec<&Sample> = samples.iter().filter(|s| s.mode == Mode::Flight).collect();
    assert!(flight.iter().all(|s| s.gap >= 0.0 && s.normal_force == 0.0));
    assert!(
        samples
            .iter()
            .filter(|s| s.mode != Mode::Flight)
            .all(|s| s.normal_force >= 0.0 && s.gap == 0.0)
    );
    let apex = flight.iter().map(|s| s.gap).fold(0.0, f64::max);
    let longest = lifts
        .iter()
        .zip(&downs)
        .map(|(a, b)| b - a)
        .fold(0.0, f64::max);
    let balance = out.drift.get(Invariant::EnergyPlusWork).unwrap();
    assert!(balance < 1e-9, "E + W drift {balance:e}");
    measured(
        "egg jump",
        format!(
            "{} jumps from t = {:.6} s; first {:.4} s, longest {longest:.4} s; highest sample gap {apex:.2e} m; E + W drift {balance:.1e}",
            lifts.len(),
            lifts[0],
            downs[0] - lifts[0],
        ),
    );
}

/// scenarios/drop.toml: a tilted ellipsoid dropped with friction and e = 0.6 bounces,
/// every impact dissipating (never a gain), and settles into persistent contact; E + W
/// balances; after settling it stays on the plane.
#[test]
fn a_dropped_ellipsoid_bounces_and_settles() {
    let (out, samples) = run(&bundled("drop.toml"));
    assert_eq!(out.status, Status::Completed);
    let hits = hits(&out);
    assert!(hits.len() > 5, "{} impacts", hits.len());
    assert!(
        hits.iter()
            .all(|(_, h)| h.energy_loss >= 0.0 && h.impulse.z >= 0.0)
    );
    let (t_settle, last) = hits.last().unwrap();
    assert!(last.persistent, "the last impact makes contact persistent");
    assert!(
        samples
            .iter()
            .filter(|s| s.t > *t_settle)
            .all(|s| s.mode != Mode::Flight)
    );
    let balance = out.drift.get(Invariant::EnergyPlusWork).unwrap();
    assert!(balance < 1e-9, "E + W drift {balance:e}");
    measured(
        "drop",
        format!(
            "{} impacts, persistent contact at t = {t_settle:.6} s; E + W drift {balance:.1e}",
            hits.len()
        ),
    );
}

/// scenarios/tippe-top-jump.toml: the top with a large offset hops while turning over.
#[test]
fn a_tippe_top_with_a_large_offset_hops_while_turning_over() {
    let (out, samples) = run(&bundled("tippe-top-jump.toml"));
    assert_eq!(out.status, Status::Completed);
    let lifts = times(&out, is_lift_off);
    let over = out
        .events
        .iter()
        .find(|e| matches!(e.kind, EventKind::Observed { .. }))
        .expect("θ passes π/2")
        .t;
    assert!(lifts.len() >= 5 && lifts[0] < over && lifts[lifts.len() - 1] > over);
    let apex = samples.iter().map(|s| s.gap).fold(0.0, f64::max);
    assert!(apex > 1e-4, "hops {apex:e} m high");
    let balance = out.drift.get(Invariant::EnergyPlusWork).unwrap();
    assert!(balance < 1e-9, "E + W drift {balance:e}");
    measured(
        "tippe-top jump",
        format!(
            "{} hops, θ passes π/2 at t = {over:.5} s, highest sample gap {apex:.2e} m",
            lifts.len()
        ),
    );
}

/// Hard case: a grazing touchdown. A triaxial body (semi-axes 0.03, 0.02, 0.01 m) turns
/// steadily about its long axis without gravity, so its lowest point's height h(t) rises
/// to b = 0.02 m twice a turn. G held at z_G = b (1 + δ): with δ = 1e-12 the body passes
/// without touching (no event, the gap stays ≥ 0), with δ = −1e-9 the touchdown is found
/// at the first pass, at the analytic time where h = z_G, although the gap's slope there
/// is only 8e-6 m/s.
#[test]
fn hard_grazing_touchdown_is_found_or_rightly_missed() {
    let (b, c, w) = (0.02, 0.01, 10.0);
    let run_at = |delta: f64| {
        let z_g = b * (1.0 + delta);
        let mut sc = flying(
            scene(
                triaxial(),
                ContactModel::Frictionless,
                angles(0.0, 0.0, 0.0, 0.0, 0.0, 0.0),
                None,
                1.0,
                1e-3,
                1e-12,
            ),
            Vector3::zeros(),
            z_g - c,
        );
        sc.gravity = 0.0;
        sc.landing.restitution = 1.0;
        sc.initial.omega_body = Some(Vector3::new(w, 0.0, 0.0));
        (z_g, run(&sc))
    };
    let (_, (miss, samples)) = run_at(1e-12);
    assert_eq!(miss.status, Status::Completed);
    assert_eq!(impacts(&miss), 0, "{:?}", miss.events);
    assert!(samples.iter().all(|s| s.gap >= 0.0));
    let (z_g, (hit, _)) = run_at(-1e-9);
    let t = hit
        .events
        .iter()
        .find(|e| matches!(e.kind, EventKind::Touchdown { .. }))
        .expect("a touchdown")
        .t;
    // h(t)² = b² sin²(ωt) + c² cos²(ωt) = z_G² at the first pass.
    let expect = (((z_g * z_g - c * c) / (b * b - c * c)).sqrt().asin()) / w;
    assert!(
        (t - expect).abs() < 1e-7,
        "touchdown at {t}, expected {expect}"
    );
    let drift = hit.drift.get(Invariant::Energy).unwrap();
    assert!(
        drift < 1e-12,
        "elastic frictionless: energy drift {drift:e}"
    );
    measured(
        "grazing touchdown",
        format!(
            "found {:.1e} s from the analytic time; a pass 2e-14 m above the plane is no touchdown",
            t - expect
        ),
    );
}

/// Hard case: an impact at the moment of lift-off. The tumbling body of hard case 3 at
/// the spin where its normal force just reaches zero (found by bisection, then 1e-6
/// above): it lifts off, flies a moment, lands at a speed near zero, and contact becomes
/// persistent again — no chattering, E + W exact, N ≥ 0 in every contact sample.
#[test]
fn hard_impact_at_the_moment_of_lift_off() {
    let ax = Vector3::new(0.02, 0.02, 0.04);
    let body = Body::new(ax, 0.1, uniform_inertia(ax, 0.1), Vector3::zeros()).unwrap();
    let tumble = |rate: f64, lift_off: LiftOff| {
        let mut sc = scene(
            body.clone(),
            ContactModel::Frictionless,
            angles(1.5, 0.0, 0.0, -rate, 0.0, 0.0),
            Some(Vector2::zeros()),
            0.3,
            1e-4,
            1e-12,
        );
        sc.landing.lift_off = lift_off;
        run(&sc)
    };
    let (mut lo, mut hi) = (35.0, 45.0);
    for _ in 0..40 {
        let mid = 0.5 * (lo + hi);
        if tumble(mid, LiftOff::Stop).0.status == Status::LostContact {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let (out, samples) = tumble(hi * (1.0 + 1e-6), LiftOff::Fly);
    assert_eq!(out.status, Status::Completed, "{:?}", out.events);
    let lift = out
        .events
        .iter()
        .find(|e| e.kind == EventKind::LiftOff)
        .expect("lift-off")
        .t;
    let (down, speed) = out
        .events
        .iter()
        .find_map(|e| match e.kind {
            EventKind::Touchdown { speed, .. } => Some((e.t, speed)),
            _ => None,
        })
        .expect("touchdown");
    assert!(
        down - lift < 1e-2 && speed < 1e-3,
        "flight {:e} s, landing at {speed:e} m/s",
        down - lift
    );
    assert!(
        samples
            .iter()
            .filter(|s| s.mode != Mode::Flight)
            .all(|s| s.normal_force >= 0.0)
    );
    assert!(samples.last().unwrap().mode == Mode::Frictionless);
    let balance = out.drift.get(Invariant::EnergyPlusWork).unwrap();
    assert!(balance < 1e-10, "E + W drift {balance:e}");
    measured(
        "impact at lift-off",
        format!(
            "θ̇ = {hi:.9} rad/s: flight {:.1e} s, landing at {speed:.1e} m/s, {} events; E + W drift {balance:.1e}",
            down - lift,
            out.events.len()
        ),
    );
}

/// Without gravity the plane cannot hold the body: it flies from t = 0 (it used to be
/// rejected, N = 0), and a body spinning about its axis stays in flight.
#[test]
fn without_gravity_the_body_flies_from_the_start() {
    let mut sc = scene(
        common::oblate(),
        ContactModel::Frictionless,
        angles(0.3, 0.0, 0.0, 0.0, 0.0, 50.0),
        Some(Vector2::new(0.1, 0.0)),
        1.0,
        1e-2,
        1e-12,
    );
    sc.gravity = 0.0;
    sc.landing.lift_off = LiftOff::Fly;
    let (out, samples) = run(&sc);
    assert_eq!(out.status, Status::Completed);
    // A body of revolution spinning steadily about its axis: the gap stays 0 to round-off.
    let worst = samples.iter().map(|s| s.gap.abs()).fold(0.0, f64::max);
    assert!(
        samples.iter().all(|s| s.mode == Mode::Flight),
        "{:?}",
        out.events
    );
    assert!(worst < 1e-16, "gap {worst:e}");
    sc.landing.lift_off = LiftOff::Stop;
    assert!(
        sc.initial_state().is_err(),
        "N = 0 at t = 0 with on_lift_off = stop"
    );
}

/// A rolling scene lands with the no-slip limit of the impact law: every impact ends with
/// the contact stuck, and contact becomes persistent in rolling, E + W exact.
#[test]
fn a_rolling_scene_lands_without_slip() {
    let mut sc = bundled("drop.toml");
    sc.contact = ContactModel::Rolling;
    let (out, samples) = run(&sc);
    assert_eq!(out.status, Status::Completed);
    let hits = hits(&out);
    assert!(!hits.is_empty() && hits.iter().all(|(_, h)| h.energy_loss >= 0.0));
    assert!(hits.last().unwrap().1.persistent);
    assert_eq!(samples.last().unwrap().mode, Mode::Rolling);
    assert!(samples.last().unwrap().slip_speed < 1e-9);
    let balance = out.drift.get(Invariant::EnergyPlusWork).unwrap();
    assert!(balance < 1e-9, "E + W drift {balance:e}");
}
