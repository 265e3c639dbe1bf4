//! The viscous sliding law F = N(e3 − μ_v v_C) (docs/physics.md, "Viscous sliding"):
//! the closed-form slip decay of a ball, E + W and Jellett's J on a tippe top turning
//! over, and the refusal of bad coefficients.

mod common;

use common::{G, angles, ball, run, scene, tippe_top};
use nalgebra::{Vector2, Vector3};

use ellipsoid_core::invariants::Invariant;
use ellipsoid_core::scenario;
use ellipsoid_core::simulate::{ContactModel, Mode, Status};

const TOL: f64 = 1e-13;

/// A uniform ball (I = 2/5 m r²) thrown sliding: N = m g, and the slip obeys
/// dv_C/dt = −μ_v g (1 + m r²/I) v_C = −3.5 μ_v g v_C, so it keeps its direction and
/// decays as v_C(0) e^(−3.5 μ_v g t); G's velocity loses μ_v g ∫ v_C dt. Both to 1e-9 of
/// the initial slip, a spin about the vertical (which does not change the slip of a
/// sphere) included.
#[test]
fn val_ball_slip_decays_exponentially() {
    let (r, m, mu_v) = (0.028575, 0.17, 0.8);
    let v0 = Vector2::new(1.5, -0.7);
    let spin = 25.0;
    let mut s = scene(
        ball(r, m),
        ContactModel::Viscous {
            viscous_friction: mu_v,
        },
        angles(0.0, 0.0, 0.0, 0.0, 0.0, 0.0),
        Some(v0),
        1.0,
        1e-2,
        TOL,
    );
    s.initial.omega_body = Some(Vector3::new(0.0, 0.0, spin));
    let (out, samples) = run(&s);
    assert_eq!(out.status, Status::Completed, "{:?}", out.status);
    let k = 3.5 * mu_v * G;
    let mut worst: f64 = 0.0;
    for smp in &samples {
        assert_eq!(smp.mode, Mode::Viscous);
        let decay = (-k * smp.t).exp();
        let slip = v0.norm() * decay;
        let v_g = v0 - v0 * (mu_v * G) * (1.0 - decay) / k;
        worst = worst
            .max((smp.slip_speed - slip).abs())
            .max((smp.velocity.xy() - v_g).norm())
            .max((smp.normal_force - m * G).abs() / (m * G) * v0.norm());
    }
    eprintln!("ball: worst error {worst:e} m/s");
    assert!(worst < 1e-9 * v0.norm(), "{worst:e}");
    // The slip has decayed by e^(−3.5 μ_v g) ≈ 1e-12: the ball rolls at 5/7 of v0.
    let last = samples.last().unwrap();
    assert!((last.velocity.xy() - v0 * 5.0 / 7.0).norm() < 1e-9);
}

/// The tippe top spun nearly upright turns over under viscous friction: E + W is
/// conserved to 1e-9 of E and Jellett's J = L_G·(G − C) to 1e-9 (the friction acts at
/// the contact point of a spherical surface, whose lever arm is along G − C's normal).
#[test]
fn inv_tippe_top_turns_over_with_energy_and_jellett_conserved() {
    let s = scene(
        tippe_top(),
        ContactModel::Viscous {
            viscous_friction: 1.0,
        },
        angles(0.1, 0.0, 0.0, 0.0, 180.0, 0.0),
        Some(Vector2::zeros()),
        4.0,
        1e-3,
        TOL,
    );
    let (out, samples) = run(&s);
    assert_eq!(out.status, Status::Completed, "{:?}", out.status);
    let theta = out.final_sample.angles.theta;
    let e_w = out.drift.get(Invariant::EnergyPlusWork).unwrap();
    let j = out.drift.get(Invariant::Jellett).unwrap();
    eprintln!("tippe top: θ(end) = {theta}, E + W drift {e_w:e}, J drift {j:e}");
    assert!(theta > 2.5, "not turned over: θ = {theta}");
    assert!(e_w < 1e-9, "E + W drift {e_w:e}");
    assert!(j < 1e-9, "Jellett drift {j:e}");
    assert!(out.final_sample.work > 0.0);
    assert!(samples.iter().all(|s| s.mode == Mode::Viscous));
}

/// A scenario of the viscous model with `coefficient` as its `viscous_friction` line.
fn viscous_scenario(model: &str, coefficient: &str) -> String {
    format!(
        "[body]\na = 0.015\nc = 0.015\nmass = 0.006\ninertia = \"uniform\"\n\
         [contact]\nmodel = \"{model}\"\n{coefficient}\n\
         [output]\nt_end = 0.1\ndt = 0.01\n"
    )
}

fn parse_error(text: &str) -> String {
    match scenario::parse(text, "x.toml", &[] as &[&str]) {
        Ok(_) => panic!("accepted:\n{text}"),
        Err(e) => e.to_string(),
    }
}

/// A negative, NaN, infinite or huge μ_v is refused naming the key, its value, its line
/// and the rule; so is a missing one, and one under another model.
#[test]
fn bad_viscous_friction_is_refused_naming_key_value_and_rule() {
    for bad in ["-0.5", "nan", "inf", "1e6"] {
        let e = parse_error(&viscous_scenario(
            "viscous",
            &format!("viscous_friction = {bad}"),
        ));
        assert!(
            e.starts_with(&format!("x.toml:8:1: contact.viscous_friction = {bad}"))
                && e.contains("must be finite and within [0, 100000] s/m"),
            "{e}"
        );
    }
    let e = parse_error(&viscous_scenario("viscous", ""));
    assert!(
        e.contains("contact.viscous_friction") && e.contains("the viscous model needs μ_v"),
        "{e}"
    );
    let e = parse_error(&viscous_scenario(
        "sliding",
        "viscous_friction = 0.5\nfriction = 0.3",
    ));
    assert!(
        e.contains("contact.viscous_friction = 0.5") && e.contains("takes no viscous coefficient"),
        "{e}"
    );
    let e = parse_error(&viscous_scenario(
        "viscous",
        "viscous_friction = 0.5\nfriction = 0.3",
    ));
    assert!(e.contains("contact.friction = 0.3"), "{e}");
    let ok = scenario::parse(
        &viscous_scenario("viscous", "viscous_friction = 0.5"),
        "x.toml",
        &[] as &[&str],
    )
    .unwrap();
    assert_eq!(
        ok.scene.contact,
        ContactModel::Viscous {
            viscous_friction: 0.5
        }
    );
    // A scene built in code is validated too.
    let mut scene = ok.scene.clone();
    scene.contact = ContactModel::Viscous {
        viscous_friction: -1.0,
    };
    let e = scene.validate().unwrap_err().to_string();
    assert!(
        e.contains("contact.viscous_friction") && e.contains("-1"),
        "{e}"
    );
}

// ---------------------------------------------------------------- steady spins

use ellipsoid_core::body::Body;
use ellipsoid_core::simulate::Scene;
use ellipsoid_core::steady::{Family, viscous};

/// A tippe top: a sphere of radius 15 mm, G a distance α R below its centre, m = 6 g,
/// I3 = 7e-7 kg m², I1 = I2 = ratio I3, under viscous friction μ_v, spinning at `spin`
/// about the upward vertical in the `family`'s attitude.
fn tippe(alpha: f64, ratio: f64, mu_v: f64, spin: f64, family: Family) -> Scene {
    let (r, i3) = (0.015, 7e-7);
    let body = Body::of_revolution(r, r, 6e-3, ratio * i3, i3, alpha * r).unwrap();
    let (theta, psi_dot) = match family {
        Family::Inverted => (std::f64::consts::PI, -spin),
        _ => (0.0, spin),
    };
    scene(
        body,
        ContactModel::Viscous {
            viscous_friction: mu_v,
        },
        angles(theta, 0.0, 0.0, 0.0, 0.0, psi_dot),
        Some(Vector2::zeros()),
        1.0,
        1e-3,
        1e-12,
    )
}

/// The stability boundary in I1/I3 of `family` at spin n, bisected on the verdict
/// between `lo` and `hi` (whose verdicts differ) to 1e-12.
fn boundary(family: Family, alpha: f64, n: f64, mut lo: f64, mut hi: f64) -> f64 {
    let stable = |ratio: f64| {
        viscous::analyse(&tippe(alpha, ratio, 1.0, n, family), family)
            .unwrap()
            .stable()
    };
    let at_lo = stable(lo);
    assert_ne!(
        at_lo,
        stable(hi),
        "{family:?} n = {n}: no change in [{lo}, {hi}]"
    );
    while hi - lo > 1e-12 {
        let mid = 0.5 * (lo + hi);
        if stable(mid) == at_lo {
            lo = mid
        } else {
            hi = mid
        }
    }
    0.5 * (lo + hi)
}

/// The tippe top's criterion under viscous friction: at large spin the upright spin is
/// unstable and the inverted one stable exactly for 1 − α < I1/I3 < 1 + α (Bou-Rabee,
/// Marsden & Romero 2004). Upright is stable below its boundary and unstable above it,
/// inverted stable below its boundary; the boundaries tend to 1 − α and 1 + α as 1/n²
/// (each doubling of n divides the distance by 4, within 0.5 %), for α = 0.2 and 0.4.
#[test]
fn val_tippe_top_criterion_is_the_large_spin_limit() {
    for alpha in [0.2, 0.4] {
        for (family, limit, lo, hi) in [
            (Family::Upright, 1.0 - alpha, 0.55, 1.0),
            (Family::Inverted, 1.0 + alpha, 1.0, 1.0 + 2.0 * alpha),
        ] {
            let spins = [100.0, 200.0, 400.0, 800.0];
            let distance: Vec<f64> = spins
                .iter()
                .map(|&n| boundary(family, alpha, n, lo, hi) - limit)
                .collect();
            eprintln!("α = {alpha} {family:?}: boundary − limit at n = {spins:?}: {distance:?}");
            for w in distance.windows(2) {
                let ratio = w[0] / w[1];
                assert!(
                    (ratio - 4.0).abs() < 0.2,
                    "{family:?} α = {alpha}: {distance:?}"
                );
            }
            assert!(distance[3].abs() < 2e-3, "{distance:?}");
            // Stable on the side of smaller I1/I3 for both.
            let below = viscous::analyse(&tippe(alpha, limit - 0.05, 1.0, 800.0, family), family);
            let above = viscous::analyse(&tippe(alpha, limit + 0.05, 1.0, 800.0, family), family);
            assert!(below.unwrap().stable() && !above.unwrap().stable());
        }
    }
}

/// A run started on the upright spin of the Leine–Glocker tippe top (I1/I3 = 8/7,
/// α = 0.2) at n = 200 rad/s, displaced by 1e-6 along the unstable mode, tilts from
/// 1e-5 to 1e-4 rad at the predicted Re λ within 1 %.
#[test]
fn val_perturbed_upright_spin_grows_at_the_predicted_rate() {
    assert_upright_growth(200.0);
}

/// A run started on the upright spin at `spin`, displaced by 1e-6 along the unstable
/// mode, tilts from 1e-5 to 1e-4 rad at the predicted Re λ within 1 %.
fn assert_upright_growth(spin: f64) {
    let base = tippe(0.2, 8.0 / 7.0, 1.0, spin, Family::Upright);
    let an = viscous::analyse(&base, Family::Upright).unwrap();
    let rate = an.eigenvalues[0].re;
    assert!(rate > 0.0 && !an.stable(), "{:?}", an.eigenvalues);
    let mut start = viscous::started_at(&base, &an.at(), &an.perturbation(0, 1e-6));
    start.t_end = 14.0 / rate;
    start.sample_times = (0..=8000)
        .map(|i| i as f64 * start.t_end / 8000.0)
        .collect();
    let (out, samples) = run(&start);
    assert_eq!(out.status, Status::Completed, "{:?}", out.status);
    let t1 = common::first_reaching(&samples, 0.0, 1e-5);
    let t2 = common::first_reaching(&samples, 0.0, 1e-4);
    let fitted = 10f64.ln() / (t2 - t1);
    eprintln!("upright tippe top at {spin} rad/s: growth {fitted} /s against Re λ = {rate} /s");
    assert!(
        (fitted / rate - 1.0).abs() < 0.01,
        "{fitted} against {rate}"
    );
}

/// The bundled diagram of the tippe top against spin (scripts/steady-diagrams.py: the
/// top of scenarios/tippe-top.toml under viscous sliding, μ_v = 1 s/m) at three spins:
/// upright at 100 and 300 rad/s (unstable above 21.70 rad/s) a run displaced 1e-6 along
/// the unstable mode grows at Re λ within 1 %; inverted at 200 rad/s (stable above
/// 79.73 rad/s) ζ1 = sin θ sin ψ of a run displaced 1e-6 along each of the two slowly
/// damped pairs oscillates at its |Im λ| within 1e-6 (zero crossings over `periods`
/// periods: fewer for the pair damped at 0.9 /s, whose amplitude must stay well above the
/// integrator's tolerance).
#[test]
fn val_bundled_tippe_top_runs_follow_the_spectrum() {
    for spin in [100.0, 300.0] {
        assert_upright_growth(spin);
    }
    let base = tippe(0.2, 8.0 / 7.0, 1.0, 200.0, Family::Inverted);
    let an = viscous::analyse(&base, Family::Inverted).unwrap();
    assert!(an.stable(), "{:?}", an.eigenvalues);
    for (k, periods) in [(0, 40.0), (2, 10.0)] {
        let lambda = an.eigenvalues[k];
        let omega = lambda.im.abs();
        let mut start = viscous::started_at(&base, &an.at(), &an.perturbation(k, 1e-6));
        start.t_end = (periods + 1.0) * std::f64::consts::TAU / omega;
        let count = ((periods + 1.0) * 400.0) as usize;
        start.sample_times = (0..=count)
            .map(|i| (i as f64 * start.t_end / count as f64).min(start.t_end))
            .collect();
        let (out, samples) = run(&start);
        assert_eq!(out.status, Status::Completed, "{:?}", out.status);
        let (measured, crossings) =
            common::crossing_frequency(&samples, |s| s.angles.theta.sin() * s.angles.psi.sin());
        let err = measured / omega - 1.0;
        eprintln!(
            "inverted tippe top, mode {k} (λ = {lambda}): ζ1 oscillates at {measured} ({crossings} crossings): {err:.2e}"
        );
        assert!(crossings as f64 >= periods, "{crossings} crossings");
        assert!(
            err.abs() < 1e-6,
            "mode {k}: {measured} against {omega} ({err:.2e})"
        );
    }
}
