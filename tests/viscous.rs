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
