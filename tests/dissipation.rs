//! The dissipation laws of a rolling disc (docs/physics.md, "Dissipation of a rolling
//! disc"): each law's power on the thin uniform disc's steady motion against its closed
//! form, and the exponent of the tilt's approach to t0 measured on the simulated disc
//! under Moffatt's air film alone.

mod common;

use std::f64::consts::{FRAC_1_SQRT_2, FRAC_PI_4};

use common::{G, run};
use ellipsoid_core::body::{Body, Rim, Surface};
use ellipsoid_core::effects::{AirBoundaryLayer, AirFilm, Effect, RollingFriction};
use ellipsoid_core::kinematics::Kinematics;
use ellipsoid_core::simulate::{Mode, Sample, Status};
use ellipsoid_core::state::{self, EulerAngles, State};
use nalgebra::Vector3;

const MASS: f64 = 0.445;
const RADIUS: f64 = 0.0375;

/// A thin uniform disc of radius a, its centre G on its rim's plane (I_t = m a²/4).
fn thin_disc() -> Body {
    let (i_t, i_a) = (MASS * RADIUS * RADIUS / 4.0, MASS * RADIUS * RADIUS / 2.0);
    Body::of_revolution(RADIUS, RADIUS / 10.0, MASS, i_t, i_a, 0.0)
        .unwrap()
        .with_rims(vec![Rim {
            name: "edge".into(),
            center: Vector3::zeros(),
            radius: RADIUS,
            edge: 0.0,
        }])
        .unwrap()
        .without_ellipsoid_contact()
        .unwrap()
        .touching(Surface::Rim(0))
}

/// The disc's steady motion with its centre fixed at tilt α (docs/physics.md, "Rims"):
/// Ω² = 4g/(a sin α), ψ̇ = −Ω cos α; its kinematics (rolling) and Ω.
fn steady(body: &Body, alpha: f64, phi: f64) -> (Kinematics, f64) {
    let omega = (4.0 * G / (RADIUS * alpha.sin())).sqrt();
    let angles = EulerAngles {
        theta: alpha,
        phi,
        psi: 0.3,
        theta_dot: 0.0,
        phi_dot: omega,
        psi_dot: -omega * alpha.cos(),
    };
    let mut y = State::zeros();
    state::set_quaternion(&mut y, &angles.rotation());
    y.fixed_rows_mut::<3>(state::OMEGA)
        .copy_from(&angles.omega_body());
    (Kinematics::new(body, &y, true), omega)
}

/// The power an effect removes at `kin` with normal force N = m g: −(τ + N τ_N)·ω.
fn power(effect: &impl Effect, body: &Body, kin: &Kinematics) -> f64 {
    let w = effect.wrench(body, kin);
    assert_eq!(w.force, Vector3::zeros(), "the laws are couples");
    -(w.torque + MASS * G * w.torque_per_normal).dot(&kin.omega)
}

/// Each law's power on the rolling disc equals its closed form (docs/physics.md), and
/// its couple opposes the rocking rate ω_h.
#[test]
fn each_law_removes_its_closed_form_power_from_the_rolling_disc() {
    let body = thin_disc();
    let (mu, rho, mu_r, eps) = (1.8e-5, 1.2, 1e-4, 1e-3);
    let film = AirFilm { viscosity: mu };
    let layer = AirBoundaryLayer {
        viscosity: mu,
        density: rho,
    };
    let friction = RollingFriction {
        coefficient: mu_r,
        regularisation: eps,
    };
    for (alpha, phi) in [(0.3f64, 0.0), (0.05, 1.1), (2e-3, -2.0)] {
        let (kin, omega) = steady(&body, alpha, phi);
        let (s, c) = alpha.sin_cos();
        // The rolling disc's kinematics (docs/physics.md, "Dissipation of a rolling disc").
        let zeta = kin.contact.zeta;
        let omega_h = kin.omega - zeta * kin.omega.dot(&zeta);
        assert!((omega_h.norm() - omega * s * c).abs() < 1e-12 * omega);
        assert!((kin.omega.dot(&zeta) - omega * s * s).abs() < 1e-12 * omega);
        let travel = kin.contact.r_dot_surface.norm();
        assert!((travel - RADIUS * omega * c).abs() < 1e-11 * RADIUS * omega);
        let w = omega_h.norm();
        let cases = [
            (
                "air film",
                power(&film, &body, &kin),
                FRAC_PI_4 * mu * RADIUS.powi(3) * omega * omega * c * c / s,
            ),
            (
                "boundary layer",
                power(&layer, &body, &kin),
                (mu * rho).sqrt() * RADIUS.powi(4) * omega.powf(2.5) * c.powf(2.5) * FRAC_1_SQRT_2,
            ),
            (
                "rolling friction",
                power(&friction, &body, &kin),
                mu_r * MASS * G * RADIUS * omega * c * w / (w * w + eps * eps).sqrt(),
            ),
        ];
        for (law, got, want) in cases {
            assert!(
                (got - want).abs() < 1e-12 * want,
                "α = {alpha}: {law} {got:e} W vs {want:e} W"
            );
        }
        for couple in [
            film.wrench(&body, &kin).torque,
            layer.wrench(&body, &kin).torque,
            friction.wrench(&body, &kin).torque_per_normal,
        ] {
            assert!(couple.cross(&omega_h).norm() < 1e-12 * couple.norm() * w);
            assert!(couple.dot(&omega_h) < 0.0);
        }
    }
}

/// The air laws act under a rim on the plane only: a body whose sphere touches, or a rim
/// in flight, feels none.
#[test]
fn the_air_laws_act_on_a_rim_on_the_plane_only() {
    let body = thin_disc();
    let (mut kin, _) = steady(&body, 0.2, 0.0);
    let film = AirFilm { viscosity: 1.8e-5 };
    assert!(film.wrench(&body, &kin).torque.norm() > 0.0);
    kin.gap = 1e-6;
    assert_eq!(film.wrench(&body, &kin).torque, Vector3::zeros());
}

/// Scenario text of the thin disc started on its steady motion at tilt α0, rolling,
/// under `effects`.
fn disc_scene(alpha0: f64, effects: &str, t_end: f64) -> ellipsoid_core::simulate::Scene {
    let omega = (4.0 * G / (RADIUS * alpha0.sin())).sqrt();
    let text = format!(
        "[body]\na = {RADIUS}\nc = {}\nmass = {MASS}\ninertia = [{i_t}, {i_t}, {i_a}]\n\
         ellipsoid_contact = false\n\
         [[body.rim]]\nname = \"edge\"\ncenter = [0.0, 0.0, 0.0]\nradius = {RADIUS}\nedge = 0.0\n\
         [initial]\ntheta = {alpha0}\nphi_dot = {omega}\npsi_dot = {}\n\
         [contact]\nmodel = \"rolling\"\n[effects]\ngravity = {G}\n{effects}\n\
         [solver]\nmethod = \"dop853\"\nrtol = 1e-11\natol = 1e-13\n\
         [output]\nt_end = {t_end}\ndt = 1e-3\n",
        RADIUS / 10.0,
        -omega * alpha0.cos(),
        i_t = MASS * RADIUS * RADIUS / 4.0,
        i_a = MASS * RADIUS * RADIUS / 2.0,
    );
    ellipsoid_core::scenario::parse(&text, "disc.toml", &[] as &[&str])
        .unwrap_or_else(|e| panic!("{e}\n{text}"))
        .scene
}

/// The least-squares line through (x, y): (slope, intercept, largest residual).
fn line(points: &[(f64, f64)]) -> (f64, f64, f64) {
    let n = points.len() as f64;
    let (mx, my) = points
        .iter()
        .fold((0.0, 0.0), |(a, b), &(x, y)| (a + x / n, b + y / n));
    let (sxy, sxx) = points.iter().fold((0.0, 0.0), |(a, b), &(x, y)| {
        (a + (x - mx) * (y - my), b + (x - mx) * (x - mx))
    });
    let slope = sxy / sxx;
    let intercept = my - slope * mx;
    let worst = points
        .iter()
        .map(|&(x, y)| (y - intercept - slope * x).abs())
        .fold(0.0, f64::max);
    (slope, intercept, worst)
}

/// The exponent p of α ∝ (t0 − t)^p over the samples with t0 − t in `window`, t0 chosen
/// (golden-section search) to make log α most nearly linear in log(t0 − t).
fn fitted_exponent(samples: &[Sample], window: (f64, f64), t0_range: (f64, f64)) -> (f64, f64) {
    let points = |t0: f64| -> Vec<(f64, f64)> {
        samples
            .iter()
            .filter(|s| s.mode != Mode::Face && (window.0..=window.1).contains(&(t0 - s.t)))
            .map(|s| ((t0 - s.t).ln(), s.angles.theta.ln()))
            .collect()
    };
    let misfit = |t0: f64| {
        let p = points(t0);
        let (slope, intercept, _) = line(&p);
        p.iter()
            .map(|&(x, y)| (y - intercept - slope * x).powi(2))
            .sum::<f64>()
    };
    let (mut lo, mut hi) = t0_range;
    let g = (5f64.sqrt() - 1.0) / 2.0;
    for _ in 0..80 {
        let (a, b) = (hi - g * (hi - lo), lo + g * (hi - lo));
        if misfit(a) < misfit(b) {
            hi = b;
        } else {
            lo = a;
        }
    }
    let t0 = 0.5 * (lo + hi);
    (line(&points(t0)).0, t0)
}

/// A run of the disc from α0 under one law: the fitted exponent and t0 over t0 − t in
/// [0.03 s, 3 s] (two decades before the laws' breakdown), with E + W balanced to 1e-9.
fn approach(alpha0: f64, effects: &str, t0: f64, t_end: f64) -> (f64, f64, Vec<Sample>) {
    let (out, samples) = run(&disc_scene(alpha0, effects, t_end));
    assert_eq!(out.status, Status::Completed, "{effects}: {:?}", out.events);
    let e0 = samples[0].energy + samples[0].work;
    for s in &samples {
        assert!(
            (s.energy + s.work - e0).abs() < 1e-9 * e0,
            "{effects}, t = {}: E + W moved by {:e}",
            s.t,
            (s.energy + s.work - e0) / e0
        );
    }
    let (p, fitted_t0) = fitted_exponent(&samples, (0.03, 3.0), (0.9 * t0, 1.1 * t0));
    (p, fitted_t0, samples)
}

/// Under Moffatt's air film alone the tilt goes as (t0 − t)^{1/3}: measured over two
/// decades of t0 − t, within 2 %, t0 within 1 % of Moffatt's α0³ m/(2π μ a). Near t0 the
/// film's couple, growing as 1/α³, overdamps the rocking before the normal force can fall
/// to zero: the disc stays on the plane and creeps down as the weight's moment m g a
/// drives the film, α⁻² = 8 m g (t − t1)/(π μ a²) (docs/physics.md), within 2 %.
#[test]
fn moffatts_film_alone_brings_the_disc_down_as_the_cube_root_of_the_time_left() {
    let (alpha0, mu) = (0.05f64, 1.8e-5);
    let t0 = alpha0.powi(3) * MASS / (2.0 * std::f64::consts::PI * mu * RADIUS);
    let film = format!("air_film = {{ viscosity = {mu} }}");
    let (p, fitted_t0, samples) = approach(alpha0, &film, t0, t0 + 1.0);
    assert!(
        (p - 1.0 / 3.0).abs() < 0.02 / 3.0,
        "exponent {p}, t0 {fitted_t0}"
    );
    assert!((fitted_t0 - t0).abs() < 0.01 * t0, "t0 {fitted_t0} vs {t0}");
    assert!(
        samples
            .iter()
            .all(|s| s.mode == Mode::Rolling && s.normal_force > 0.0)
    );
    let creep: Vec<(f64, f64)> = (samples.iter())
        .filter(|s| s.t > t0 + 0.3)
        .map(|s| (s.t, s.angles.theta.powi(-2)))
        .collect();
    let (slope, _, _) = line(&creep);
    let want = 8.0 * MASS * G / (std::f64::consts::PI * mu * RADIUS * RADIUS);
    let least = samples
        .iter()
        .map(|s| s.normal_force)
        .fold(f64::MAX, f64::min);
    eprintln!(
        "MEASURED film: exponent {p:.5}, t0 {fitted_t0:.4} s vs {t0:.4} s, least N {:.3} m g, creep slope {:.4} of the law's",
        least / (MASS * G),
        slope / want
    );
    assert!(
        (slope / want - 1.0).abs() < 0.02,
        "creep {slope:e} vs {want:e} per s"
    );
}

/// Under rolling friction alone (a force μ_r N against the contact point's travel) the
/// tilt goes as (t0 − t)^{2/3}, t0 = α0^{3/2}/(2 μ_r √(g/a)) (docs/physics.md), within
/// 2 % and 1 %; the disc then lands flat and lies at rest on its face.
#[test]
fn rolling_friction_alone_brings_the_disc_down_as_the_time_left_to_the_two_thirds() {
    let (alpha0, mu_r) = (0.05f64, 1e-4);
    let t0 = alpha0.powf(1.5) / (2.0 * mu_r * (G / RADIUS).sqrt());
    let law = format!("rolling_friction = {mu_r}");
    let (p, fitted_t0, samples) = approach(alpha0, &law, t0, t0 + 1.0);
    assert!(
        (p - 2.0 / 3.0).abs() < 0.02 * 2.0 / 3.0,
        "exponent {p}, t0 {fitted_t0}"
    );
    assert!((fitted_t0 - t0).abs() < 0.01 * t0, "t0 {fitted_t0} vs {t0}");
    let landed = samples.iter().find(|s| s.mode == Mode::Face).map(|s| s.t);
    eprintln!(
        "MEASURED rolling friction: exponent {p:.5}, t0 {fitted_t0:.4} s vs {t0:.4} s, on the face by {landed:?} s"
    );
    let last = samples.last().unwrap();
    assert_eq!(last.mode, Mode::Face);
    assert_eq!((last.velocity.norm(), last.omega.norm()), (0.0, 0.0));
}

/// Under Bildsten's boundary layer alone the tilt goes as (t0 − t)^{4/9}, t0 = α0^{9/4} m /
/// (6 √(μρ) g^{1/4} a^{7/4}) (docs/physics.md), within 2 % and 1 %, the disc on the plane.
#[test]
fn the_boundary_layer_alone_brings_the_disc_down_as_the_time_left_to_the_four_ninths() {
    let (alpha0, mu, rho) = (0.05f64, 1.8e-5f64, 1.2);
    let t0 =
        alpha0.powf(2.25) * MASS / (6.0 * (mu * rho).sqrt() * G.powf(0.25) * RADIUS.powf(1.75));
    let law = format!("air_boundary_layer = {{ viscosity = {mu}, density = {rho} }}");
    // Past t0 the disc creeps against a couple ever stiffer (docs/physics.md): the run
    // stops short of that.
    let (p, fitted_t0, samples) = approach(alpha0, &law, t0, t0 + 0.05);
    let least = samples
        .iter()
        .map(|s| s.normal_force)
        .fold(f64::MAX, f64::min);
    eprintln!(
        "MEASURED boundary layer: exponent {p:.5}, t0 {fitted_t0:.4} s vs {t0:.4} s, least N {:.3} m g, θ {:.2e} at t0 + 0.05 s",
        least / (MASS * G),
        samples.last().unwrap().angles.theta
    );
    assert!(
        (p - 4.0 / 9.0).abs() < 0.02 * 4.0 / 9.0,
        "exponent {p}, t0 {fitted_t0}"
    );
    assert!((fitted_t0 - t0).abs() < 0.01 * t0, "t0 {fitted_t0} vs {t0}");
}

/// The laws' keys refuse bad values with the key, the value and the rule, and the air
/// laws refuse a body without a rim.
#[test]
fn the_laws_keys_refuse_bad_values_by_name() {
    let disc = |effects: &str| {
        let text = format!(
            "[body]\na = {RADIUS}\nc = 0.004\nmass = {MASS}\ninertia = \"uniform\"\nellipsoid_contact = false\n\
             [[body.rim]]\nname = \"edge\"\ncenter = [0.0, 0.0, 0.0]\nradius = {RADIUS}\nedge = 0.0\n\
             [initial]\ntheta = 0.3\n[contact]\nmodel = \"rolling\"\n[effects]\n{effects}\n\
             [output]\nt_end = 1.0\ndt = 0.1\n"
        );
        ellipsoid_core::scenario::parse(&text, "disc.toml", &[] as &[&str])
            .err()
            .map(|e| e.to_string())
    };
    assert_eq!(disc("air_film = { viscosity = 1.8e-5 }"), None);
    for (effects, says) in [
        (
            "air_film = { viscosity = -1.0 }",
            "effects.air_film.viscosity = -1",
        ),
        ("air_film = { viscosity = 100.0 }", "at most 10 Pa s"),
        ("air_film = {}", "give mu, the air's dynamic viscosity"),
        (
            "air_boundary_layer = { viscosity = 1.8e-5 }",
            "effects.air_boundary_layer.density",
        ),
        (
            "air_boundary_layer = { viscosity = 1.8e-5, density = 1e9 }",
            "at most 1e4 kg/m^3",
        ),
        ("rolling_friction = -1e-4", "non-negative (1)"),
        ("rolling_friction = 2.0", "μ_r must be at most 1"),
    ] {
        let got = disc(effects).unwrap_or_else(|| panic!("{effects} accepted"));
        assert!(got.contains(says), "{effects}: {got}");
    }
    let ball = "[body]\na = 0.02\nc = 0.02\nmass = 0.1\ninertia = \"uniform\"\n\
                [contact]\nmodel = \"rolling\"\n[effects]\nair_film = { viscosity = 1.8e-5 }\n\
                [output]\nt_end = 1.0\ndt = 0.1\n";
    let got = ellipsoid_core::scenario::parse(ball, "ball.toml", &[] as &[&str])
        .err()
        .map(|e| e.to_string())
        .expect("refused");
    assert!(
        got.contains("effects.air_film.viscosity") && got.contains("no [[body.rim]]"),
        "{got}"
    );
}
