//! The tilted steady motions of a body of revolution (docs/physics.md, "Steady motions
//! and their stability", "The tilted families"): frictionless precession with G fixed and
//! Routh's steady rolling on circles. The relation between θ, Ω and n against an
//! independent Newton–Euler balance in world axes; runs of the simulator started on the
//! steady motion (an independent path) staying on it, and started 1e-6 along a mode
//! following the predicted spectrum; the spectrum's invariance under the symmetries.

mod common;

use common::{assert_spectrum, completed as run, crossing_frequency, first_reaching};

use nalgebra::{Complex, Matrix3, Vector3};

use ellipsoid_core::scenario::{self, Scenario};
use ellipsoid_core::simulate::Scene;
use ellipsoid_core::steady::{self, Analysis, Family};

const G: f64 = 9.81;

/// A body of revolution: semi-axes (a, a, c), mass m, inertia diag(A, A, C) about G,
/// G a distance d below the centre on the axis.
#[derive(Clone, Copy)]
struct Body {
    name: &'static str,
    a: f64,
    c: f64,
    m: f64,
    big_a: f64,
    big_c: f64,
    d: f64,
}

/// A thin oblate spheroid, homogeneous: a disc-like lens.
fn lens() -> Body {
    let (a, c, m) = (0.03, 0.004, 0.05);
    Body {
        name: "lens",
        a,
        c,
        m,
        big_a: m * (a * a + c * c) / 5.0,
        big_c: 2.0 * m * a * a / 5.0,
        d: 0.0,
    }
}

/// A sphere with G 5 mm below its centre (a tippe top's ball).
fn offset_sphere() -> Body {
    Body {
        name: "offset-mass sphere",
        a: 0.02,
        c: 0.02,
        m: 0.015,
        big_a: 1.6e-6,
        big_c: 2.0e-6,
        d: 0.005,
    }
}

impl Body {
    /// The scenario: this body under `model` at tilt θ, precession rate φ̇ = Ω, yaw ψ
    /// about the axis and heading φ (the spin ψ̇ is the scenario's, which the tilted
    /// families replace by the solved one).
    fn scenario(&self, model: &str, theta: f64, omega: f64, psi: f64, phi: f64) -> Scenario {
        let Body {
            a,
            c,
            m,
            big_a,
            big_c,
            d,
            ..
        } = *self;
        let text = format!(
            r#"
[body]
a = {a:e}
c = {c:e}
mass = {m:e}
com_offset = {d:e}
inertia = [[{big_a:e}, 0.0, 0.0], [0.0, {big_a:e}, 0.0], [0.0, 0.0, {big_c:e}]]
[initial]
theta = {theta:e}
phi = {phi:e}
psi = {psi:e}
phi_dot = {omega:e}
psi_dot = 0.0
[contact]
model = "{model}"
[effects]
gravity = {G:e}
[solver]
method = "dop853"
rtol = 1e-12
atol = 1e-15
[output]
t_end = 1.0
dt = 1e-3
"#
        );
        scenario::parse(&text, self.name, &[] as &[&str]).unwrap()
    }

    fn scene(&self, model: &str, theta: f64, omega: f64) -> Scene {
        self.scenario(model, theta, omega, 0.0, 0.0).scene
    }

    /// The contact point C − G in world axes when the axis k = (sin θ, 0, cos θ) is tilted
    /// towards +x: the lowest point of the spheroid x^T M⁻¹ x = 1 about its centre,
    /// M = R diag(a², a², c²) Rᵀ, is −M e3/√(e3ᵀ M e3); G is d below the centre along k.
    fn lever(&self, theta: f64) -> Vector3<f64> {
        let k = Vector3::new(theta.sin(), 0.0, theta.cos());
        let m = Matrix3::identity() * (self.a * self.a)
            + k * k.transpose() * (self.c * self.c - self.a * self.a);
        let e3 = Vector3::z();
        let lowest = -(m * e3) / e3.dot(&(m * e3)).sqrt();
        lowest + k * self.d
    }

    /// The spin n = ω·k of the steady motion at tilt θ and precession rate Ω from the
    /// Newton–Euler balance about G in world axes, independently of the code: with
    /// ω = Ω e3 + ψ̇ k, H = A ω + (C − A)(ω·k) k, every vector turns at Ω e3, so
    /// dH/dt = Ω e3 × H; v_G = −ω × r rolling (0: G fixed, frictionless), a_G = Ω e3 × v_G,
    /// F = m a_G + m g e3, and dH/dt = r × F. The residual is affine in n: solved from
    /// its values at n = 0 and 1 along e3 × k; the balance's other components must vanish.
    fn newton_euler_spin(&self, theta: f64, omega: f64, rolling: bool) -> f64 {
        let k = Vector3::new(theta.sin(), 0.0, theta.cos());
        let e3 = Vector3::z();
        let r = self.lever(theta);
        let residual = |n: f64| {
            let w = e3 * omega + k * (n - omega * theta.cos());
            let h = w * self.big_a + k * ((self.big_c - self.big_a) * w.dot(&k));
            let v_g = if rolling {
                -w.cross(&r)
            } else {
                Vector3::zeros()
            };
            let force = e3.cross(&v_g) * (omega * self.m) + e3 * (self.m * G);
            e3.cross(&h) * omega - r.cross(&force)
        };
        let j = e3.cross(&k).normalize();
        let (r0, r1) = (residual(0.0), residual(1.0));
        let n = -r0.dot(&j) / (r1 - r0).dot(&j);
        let res = residual(n);
        let scale = r0.norm().max((r1 - r0).norm() * n.abs());
        assert!(
            res.norm() <= 1e-13 * scale,
            "{}: Newton–Euler balance not closed: {res}",
            self.name
        );
        n
    }
}

/// Routh's relation between θ, Ω and n for the rolling circles, and the precession's
/// for G fixed: the analysis's spin (solved from the meridian relation on the body's
/// contact geometry) equals the world-axes Newton–Euler balance's to 1e-12 relative, for
/// a disc-like lens and an offset-mass sphere, at tilts and precession rates of both
/// signs.
#[test]
fn val_routh_relation_against_newton_euler() {
    let mut worst: f64 = 0.0;
    for body in [lens(), offset_sphere()] {
        for (model, family, rolling) in [
            ("rolling", Family::RollingCircle, true),
            ("frictionless", Family::Precession, false),
        ] {
            for theta in [0.3, 0.9, 1.3, 2.0] {
                for omega in [-7.0, 2.5, 15.0] {
                    let scene = body.scene(model, theta, omega);
                    let what = format!("{} {model} θ = {theta} Ω = {omega}", body.name);
                    let an = match steady::analyse(&scene, family) {
                        Ok(an) => an,
                        Err(e) => panic!("{what}: {e}"),
                    };
                    let expected = body.newton_euler_spin(theta, omega, rolling);
                    let err = (an.motion.spin - expected).abs() / expected.abs().max(1.0);
                    worst = worst.max(err);
                    assert!(
                        err <= 1e-12,
                        "{what}: n = {} against {expected} ({err:.2e})",
                        an.motion.spin
                    );
                    assert_eq!(an.motion.precession, Some(omega));
                    assert_eq!(an.spectrum.modes.len(), 2, "{what}");
                    assert!((an.motion.normal_force / (body.m * G) - 1.0).abs() < 1e-12);
                }
            }
        }
    }
    eprintln!("largest relative difference of the spin: {worst:.2e}");
}

/// `scene` started at the analysis's steady motion displaced by `epsilon` along mode
/// `k` (0: not displaced), sampled `count` times up to `t_end`.
fn started(scene: &Scene, an: &Analysis, k: usize, epsilon: f64, t_end: f64) -> Scene {
    let delta = an.perturbation(k, epsilon);
    let mut start = steady::started_at(scene, &an.motion.at, &delta);
    start.t_end = t_end;
    let count = 20_000;
    start.sample_times = (0..=count)
        .map(|i| (i as f64 * t_end / count as f64).min(t_end))
        .collect();
    start
}

/// The cases of the runs: (body, model, family, θ, Ω).
fn cases() -> Vec<(Body, &'static str, Family, f64, f64)> {
    vec![
        (lens(), "rolling", Family::RollingCircle, 1.2, 6.0),
        (offset_sphere(), "rolling", Family::RollingCircle, 0.9, 20.0),
        (lens(), "frictionless", Family::Precession, 0.8, 10.0),
        (
            offset_sphere(),
            "frictionless",
            Family::Precession,
            1.1,
            -15.0,
        ),
    ]
}

/// Independent path: a run of the simulator (DOP853, rtol 1e-12) started on the computed
/// steady motion stays on it: θ constant to 1e-9 rad and φ̇ to 1e-9 relative over three
/// turns about the vertical; G's speed is constant to 1e-9 of √(g a) (rolling: G
/// circles; frictionless: G stays put).
#[test]
fn val_runs_stay_on_the_steady_motion() {
    for (body, model, family, theta, omega) in cases() {
        let scene = body.scene(model, theta, omega);
        let an = steady::analyse(&scene, family).unwrap();
        let t_end = 3.0 * std::f64::consts::TAU / omega.abs();
        let samples = run(&started(&scene, &an, 0, 0.0, t_end));
        let what = format!("{} {model} θ = {theta} Ω = {omega}", body.name);
        let dtheta = samples
            .iter()
            .map(|s| (s.angles.theta - theta).abs())
            .fold(0.0, f64::max);
        let dphi = samples
            .iter()
            .map(|s| (s.angles.phi_dot / omega - 1.0).abs())
            .fold(0.0, f64::max);
        let speed0 = samples[0].velocity.norm();
        let dspeed = samples
            .iter()
            .map(|s| (s.velocity.norm() - speed0).abs())
            .fold(0.0, f64::max);
        eprintln!(
            "{what}: n = {}, |Δθ| ≤ {dtheta:.2e} rad, |Δφ̇/φ̇| ≤ {dphi:.2e}, |Δ|v_G|| ≤ {dspeed:.2e} m/s (|v_G| = {speed0:.4e}), stable: {}",
            an.motion.spin,
            an.spectrum.stable()
        );
        assert!(dtheta <= 1e-9, "{what}: θ drifts by {dtheta:e}");
        assert!(dphi <= 1e-9, "{what}: φ̇ drifts by {dphi:e}");
        let scale = speed0.max((G * body.a).sqrt());
        assert!(dspeed <= 1e-9 * scale, "{what}: |v_G| drifts by {dspeed:e}");
    }
}

/// Independent path: runs started 1e-6 along the nutation mode. Stable, θ − θ0
/// oscillates at |Im λ| (zero crossings over 40 periods, within 1e-6); unstable, it
/// grows from 1e-5 to 1e-4 rad at Re λ (within 1 %).
#[test]
fn val_perturbed_runs_follow_the_spectrum() {
    let mut seen = (0, 0);
    for (body, model, family, theta, omega) in cases().into_iter().chain(unstable_cases()) {
        let scene = body.scene(model, theta, omega);
        let what = format!("{} {model} θ = {theta} Ω = {omega}", body.name);
        if assert_follows(&scene, family, theta, &what) {
            seen.0 += 1;
        } else {
            seen.1 += 1;
        }
    }
    assert!(
        seen.0 >= 2 && seen.1 >= 1,
        "stable and unstable cases: {seen:?}"
    );
}

/// The motion of `family` of `scene` (tilted θ0 = `theta`), and a run started 1e-6 along
/// its nutation. Stable, θ − θ0 oscillates at |Im λ| (zero crossings over 40 periods,
/// within 1e-6); unstable, it grows from 1e-5 to 1e-4 rad at Re λ (within 1 %). Returns
/// whether the motion is stable.
fn assert_follows(scene: &Scene, family: Family, theta: f64, what: &str) -> bool {
    let an = steady::analyse(scene, family).unwrap();
    let lambda = an.spectrum.modes[0].eigenvalue;
    let what = format!("{what}: λ = {lambda}");
    assert_eq!(an.spectrum.modes[0].name, "nutation");
    let stable = an.spectrum.stable();
    if stable {
        let sigma = lambda.im.abs();
        let t_end = 41.0 * std::f64::consts::TAU / sigma;
        let samples = run(&started(scene, &an, 0, 1e-6, t_end));
        let (measured, count) = crossing_frequency(&samples, |s| s.angles.theta - theta);
        let err = measured / sigma - 1.0;
        eprintln!("{what}: θ oscillates at {measured} ({count} crossings): {err:.2e}");
        assert!(count >= 40, "{what}: {count} crossings");
        assert!(err.abs() < 1e-6, "{what}: {measured} ({err:.2e})");
    } else {
        let rate = lambda.re;
        let samples = run(&started(scene, &an, 0, 1e-6, 8.0 / rate));
        let t1 = first_reaching(&samples, theta, 1e-5);
        let t2 = first_reaching(&samples, theta, 1e-4);
        let fitted = 10f64.ln() / (t2 - t1);
        let err = fitted / rate - 1.0;
        eprintln!("{what}: θ grows at {fitted}: {err:.2e}");
        assert!(err.abs() < 1e-2, "{what}: {fitted} ({err:.2e})");
    }
    stable
}

/// The bundled diagram of Routh's rolling circles (scripts/steady-diagrams.py: the disc of
/// scenarios/disc.toml turning at φ̇ = 3 rad/s against its tilt) at three tilts: 60° and
/// 120° (stable: the nutation's frequency) and 90° (between the critical tilts 80.93° and
/// 99.07°: its growth), by runs started 1e-6 along the nutation.
#[test]
fn val_bundled_rolling_circles_runs_follow_the_spectrum() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/disc.toml");
    let mut verdicts = Vec::new();
    for tilt in [60.0, 90.0, 120.0_f64] {
        let sets = [
            format!("initial.theta_deg={tilt:e}"),
            "initial.phi_dot=3.0".to_owned(),
            "solver.rtol=1e-12".to_owned(),
            "solver.atol=1e-15".to_owned(),
        ];
        let scene = scenario::load(&path, &sets).unwrap().scene;
        let what = format!("disc.toml at {tilt}°");
        verdicts.push(assert_follows(
            &scene,
            Family::RollingCircle,
            tilt.to_radians(),
            &what,
        ));
    }
    assert_eq!(verdicts, [true, false, true]);
}

/// Unstable tilted motions (their spectra have a real pair ±α).
fn unstable_cases() -> Vec<(Body, &'static str, Family, f64, f64)> {
    vec![
        (lens(), "rolling", Family::RollingCircle, 1.7, 3.0),
        (lens(), "frictionless", Family::Precession, 1.7, 6.0),
    ]
}

/// The spectrum is invariant under the plane's symmetries and the body's: turning the
/// scene about the vertical (φ), moving it, and turning the body about its own axis (ψ,
/// which changes the reduced coordinates the Jacobian is taken in) change the
/// eigenvalues by round-off (1e-10 of their scale).
#[test]
fn inv_tilted_spectrum_is_invariant_under_the_symmetries() {
    for (body, model, family, theta, omega) in cases() {
        let what = format!("{} {model} θ = {theta} Ω = {omega}", body.name);
        let spectrum = |psi: f64, phi: f64| {
            let mut s = body.scenario(model, theta, omega, psi, phi).scene;
            s.initial.position = nalgebra::Vector2::new(phi, -2.0 * phi);
            steady::analyse(&s, family).unwrap().spectrum.eigenvalues()
        };
        let reference = spectrum(0.0, 0.0);
        for (psi, phi) in [(0.0, 1.0), (0.7, 0.0), (-2.0, 2.5), (2.9, -1.3)] {
            assert_spectrum(
                &spectrum(psi, phi),
                &reference,
                1e-10,
                &format!("{what}, ψ = {psi}, φ = {phi}"),
            );
        }
    }
}

/// A sweep of the tilt along the lens's rolling circles at Ω = 8 rad/s: the circles near
/// θ = π/2 (the lens nearly on its edge, turning slowly) are unstable, and the nutation
/// pair passes through zero (kind `real`) at two critical tilts. The lens is symmetric
/// under k → −k (θ → π − θ, n → −n), so the two are symmetric about π/2 (1e-12), and the
/// pair's size at each is below 1e-5 of the motion's rate.
#[test]
fn val_sweep_of_the_tilt_locates_symmetric_critical_values() {
    let body = lens();
    let base = body.scenario("rolling", 1.0, 8.0, 0.0, 0.0);
    let values: Vec<f64> = (0..=6)
        .map(|i| std::f64::consts::FRAC_PI_3 * (1.0 + i as f64 / 6.0))
        .collect();
    let sw = steady::sweep(&base, Family::RollingCircle, "initial.theta", &values).unwrap();
    assert_eq!(sw.critical.len(), 2, "{:?}", sw.critical);
    let (lo, hi) = (&sw.critical[0], &sw.critical[1]);
    for (c, above) in [(lo, false), (hi, true)] {
        assert_eq!(c.kind, steady::CriticalKind::Real, "{c:?}");
        assert_eq!(c.stable_above, above, "{c:?}");
        let an =
            steady::analyse(&body.scene("rolling", c.value, 8.0), Family::RollingCircle).unwrap();
        let size = an.spectrum.modes[0].eigenvalue.norm();
        assert!(size <= 1e-5 * an.spectrum.floor, "{c:?}: |λ| = {size}");
    }
    let asymmetry = (lo.value + hi.value) / std::f64::consts::PI - 1.0;
    eprintln!(
        "critical tilts {} and {} rad: asymmetry {asymmetry:.2e}",
        lo.value, hi.value
    );
    assert!(asymmetry.abs() <= 1e-12, "{asymmetry:e}");
}

/// Given two of (θ, Ω, n), the third: from the spin solved at (θ, Ω), solving for the
/// precession rate (the root nearest a guess 10 % off) and for the tilt (Newton from 0.05
/// rad off) returns Ω and θ to 1e-12 relative, and each solved motion closes the
/// world-axes Newton–Euler balance to 1e-12.
#[test]
fn val_two_of_theta_omega_n_give_the_third() {
    for body in [lens(), offset_sphere()] {
        for (model, family, rolling) in [
            ("rolling", Family::RollingCircle, true),
            ("frictionless", Family::Precession, false),
        ] {
            for (theta, omega) in [(0.9, 6.0), (1.3, -7.0), (2.0, 15.0)] {
                let what = format!("{} {model} θ = {theta} Ω = {omega}", body.name);
                let n = steady::analyse(&body.scene(model, theta, omega), family)
                    .unwrap()
                    .motion
                    .spin;
                // The scenario's spin φ̇ cos θ + ψ̇ is n at the guessed φ̇ and θ.
                let mut scene = body.scene(model, theta, 1.1 * omega);
                scene.initial.angles.psi_dot = n - 1.1 * omega * theta.cos();
                let an = steady::analyse_solving(&scene, family, steady::Solve::PhiDot)
                    .unwrap_or_else(|e| panic!("{what}: {e}"));
                let got = an.motion.precession.unwrap();
                assert!((got / omega - 1.0).abs() <= 1e-12, "{what}: Ω = {got}");
                assert!((an.motion.spin / n - 1.0).abs() <= 1e-15, "{what}");
                let check = body.newton_euler_spin(theta, got, rolling);
                assert!(
                    (check / n - 1.0).abs() <= 1e-12,
                    "{what}: {check} against {n}"
                );
                let guess = theta + 0.05;
                let mut scene = body.scene(model, guess, omega);
                scene.initial.angles.psi_dot = n - omega * guess.cos();
                let an = steady::analyse_solving(&scene, family, steady::Solve::Theta)
                    .unwrap_or_else(|e| panic!("{what}: {e}"));
                let got = an.motion.theta;
                assert!((got / theta - 1.0).abs() <= 1e-12, "{what}: θ = {got}");
                let check = body.newton_euler_spin(got, omega, rolling);
                assert!(
                    (check / n - 1.0).abs() <= 1e-12,
                    "{what}: {check} against {n}"
                );
            }
        }
    }
}

impl Body {
    /// G's height h(θ) and its first two derivatives (h' = s): the sphere's
    /// a − d cos θ, the centred spheroid's support function √(a² sin²θ + c² cos²θ).
    fn height(&self, theta: f64) -> [f64; 3] {
        let (st, ct) = theta.sin_cos();
        if self.d != 0.0 {
            assert_eq!(self.a, self.c, "an offset G only on the sphere");
            return [self.a - self.d * ct, self.d * st, self.d * ct];
        }
        assert_eq!(self.d, 0.0);
        let k = self.a * self.a - self.c * self.c;
        let h = (self.a * self.a * st * st + self.c * self.c * ct * ct).sqrt();
        let h1 = k * st * ct / h;
        let h2 = (k * (2.0 * theta).cos() - h1 * h1) / h;
        [h, h1, h2]
    }

    /// The frictionless precession at tilt θ and rate Ω through the Routhian (see
    /// `val_frictionless_nutation_against_the_routhian`): the spin n of the Newton–Euler
    /// balance, V'(θ) (zero on a steady precession) and the nutation's
    /// λ² = −V''/(A + m h'²).
    fn routhian_nutation(&self, theta: f64, omega: f64) -> (f64, f64, f64) {
        let n = self.newton_euler_spin(theta, omega, false);
        let p_phi = self.big_a * omega * theta.sin().powi(2) + self.big_c * n * theta.cos();
        let (st, ct) = theta.sin_cos();
        let q = p_phi - self.big_c * n * ct;
        let (q1, q2) = (self.big_c * n * st, self.big_c * n * ct);
        let (g0, g1, g2) = (q * q, 2.0 * q * q1, 2.0 * (q1 * q1 + q * q2));
        let (s0, s1, s2) = (st * st, (2.0 * theta).sin(), 2.0 * (2.0 * theta).cos());
        let [_, h1, h2] = self.height(theta);
        let v1 = (g1 / s0 - g0 * s1 / (s0 * s0)) / (2.0 * self.big_a) + self.m * G * h1;
        let v2 = (g2 / s0 - 2.0 * g1 * s1 / (s0 * s0) - g0 * s2 / (s0 * s0)
            + 2.0 * g0 * s1 * s1 / (s0 * s0 * s0))
            / (2.0 * self.big_a)
            + self.m * G * h2;
        (n, v1, -v2 / (self.big_a + self.m * h1 * h1))
    }
}

/// The frictionless nutation from the Routhian, independently of the linearisation:
/// without friction G moves only vertically (ż_G = h'θ̇), so with the integrals
/// p_ψ = C n and p_φ = A φ̇ sin²θ + C n cos θ the tilt obeys a one-degree-of-freedom
/// system with mass A + m h'² and potential V(θ) = (p_φ − C n cos θ)²/(2A sin²θ) + m g h;
/// the steady precession is V'(θ0) = 0 and the nutation λ² = −V''/(A + m h'²). The
/// spectrum's pair equals it within 1e-9 of its size (measured 2.4e-10 for the thin lens
/// spinning at 600 rad/s, where the ζ differences' round-off is largest, 1.9e-12 for the
/// sphere), for the lens and the sphere, stable (±iσ) and unstable (±α) motions.
#[test]
fn val_frictionless_nutation_against_the_routhian() {
    let mut kinds = (0, 0);
    let mut worst: f64 = 0.0;
    for body in [lens(), offset_sphere()] {
        for theta in [0.4, 0.9, 1.3, 1.7, 2.2] {
            for omega in [-12.0, 3.0, 6.0, 20.0] {
                let what = format!("{} θ = {theta} Ω = {omega}", body.name);
                let (n, v1, lambda2) = body.routhian_nutation(theta, omega);
                let scale_v = body.m * G * body.a;
                assert!(
                    v1.abs() <= 1e-12 * scale_v.max(body.big_a * omega * omega),
                    "{what}: V' = {v1}"
                );
                let expected = if lambda2 >= 0.0 {
                    kinds.1 += 1;
                    let a = lambda2.sqrt();
                    [Complex::new(a, 0.0), Complex::new(-a, 0.0)]
                } else {
                    kinds.0 += 1;
                    let s = (-lambda2).sqrt();
                    [Complex::new(0.0, s), Complex::new(0.0, -s)]
                };
                let an = steady::analyse(
                    &body.scene("frictionless", theta, omega),
                    Family::Precession,
                )
                .unwrap();
                let err = an
                    .spectrum
                    .eigenvalues()
                    .iter()
                    .map(|z| (z - expected[0]).norm().min((z - expected[1]).norm()))
                    .fold(0.0, f64::max)
                    / expected[0].norm();
                eprintln!("{what}: n = {n:.3}, λ = {}, {err:.2e}", expected[0]);
                worst = worst.max(err);
                assert_spectrum(&an.spectrum.eigenvalues(), &expected, 1e-9, &what);
            }
        }
    }
    eprintln!("stable, unstable: {kinds:?}; largest difference {worst:.2e} of |λ|");
    assert!(kinds.0 > 0 && kinds.1 > 0, "{kinds:?}");
}

/// Under the Coulomb model the rolling circle is its rolling phase: the same spin and
/// spectrum as the rolling model's, and the friction cone's margin μN − |F_h| with
/// |F_h| = m Ω² R_G, the force that turns G on its circle of radius R_G.
#[test]
fn val_coulomb_rolling_circle_is_the_rolling_one_within_its_cone() {
    let body = lens();
    for (theta, omega) in [(1.2, 6.0), (0.9, -3.0)] {
        let rolling =
            steady::analyse(&body.scene("rolling", theta, omega), Family::RollingCircle).unwrap();
        let mut scenario = body.scenario("rolling", theta, omega, 0.0, 0.0);
        scenario.text = scenario
            .text
            .replace("model = \"rolling\"", "model = \"coulomb\"\nfriction = 0.3");
        let coulomb = scenario::parse(&scenario.text, "lens", &[] as &[&str]).unwrap();
        let an = steady::analyse(&coulomb.scene, Family::RollingCircle).unwrap();
        assert_eq!(an.motion.spin, rolling.motion.spin);
        assert_eq!(an.spectrum.eigenvalues(), rolling.spectrum.eigenvalues());
        let radius = an.motion.circles.unwrap().center;
        let expected = 0.3 * body.m * G - body.m * omega * omega * radius;
        let margin = an.motion.cone_margin.unwrap();
        assert!(
            (margin - expected).abs() <= 1e-12 * body.m * G,
            "θ = {theta}, Ω = {omega}: margin {margin} against {expected}"
        );
        assert!(rolling.motion.cone_margin.is_none());
    }
}

/// The root of `f` between `lo` and `hi` (where it changes sign), bisected until the
/// bracket is 1e-15 relative wide (or no double lies between its ends).
fn bisect(f: impl Fn(f64) -> f64, mut lo: f64, mut hi: f64) -> f64 {
    let at_lo = f(lo).signum();
    assert_ne!(at_lo, f(hi).signum(), "no sign change in [{lo}, {hi}]");
    while (hi - lo).abs() > 1e-15 * lo.abs().max(hi.abs()) {
        let mid = 0.5 * (lo + hi);
        if mid == lo || mid == hi {
            break;
        }
        if f(mid).signum() == at_lo {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// Critical values along the tilted families located to 1e-10 relative, each against an
/// independent path:
/// - frictionless precession of the lens and the offset-mass sphere against the tilt:
///   the root of the Routhian's closed-form λ²(θ) = −V''/(A + m h'²) (with n from the
///   world-axes Newton–Euler balance), bisected to 1e-15 — no linearisation at all;
/// - Routh's rolling circles of the lens and of `scenarios/disc.toml` against the tilt:
///   the root of det J = λ1 λ2 (ω² on the stable side, −α² on the unstable one, smooth
///   through the crossing), bisected on fresh analyses — a different function of the
///   spectrum from the sweep's verdict (which flips where Re λ leaves zero).
#[test]
fn val_critical_values_along_the_tilted_families_to_1e_10() {
    let tilts: Vec<f64> = (0..=22).map(|i| 0.3 + 0.1 * i as f64).collect();
    let mut worst: f64 = 0.0;
    let mut found = 0;
    for body in [lens(), offset_sphere()] {
        for omega in [3.0, 6.0, 20.0] {
            let base = body.scenario("frictionless", 1.0, omega, 0.0, 0.0);
            let sw = steady::sweep(&base, Family::Precession, "initial.theta", &tilts).unwrap();
            for c in &sw.critical {
                let k = tilts.iter().position(|t| *t > c.value).unwrap();
                let exact = bisect(
                    |t| body.routhian_nutation(t, omega).2,
                    tilts[k - 1],
                    tilts[k],
                );
                let err = c.value / exact - 1.0;
                eprintln!(
                    "{} precession Ω = {omega}: critical θ {} against the Routhian's {exact}: {err:.2e}",
                    body.name, c.value
                );
                worst = worst.max(err.abs());
                found += 1;
            }
        }
    }
    let disc = {
        let path =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/disc.toml");
        scenario::load(&path, &["initial.phi_dot=3.0"]).unwrap()
    };
    let degrees: Vec<f64> = (0..=12).map(|i| 30.0 + 10.0 * i as f64).collect();
    for (base, key, values) in [
        (
            lens().scenario("rolling", 1.0, 8.0, 0.0, 0.0),
            "initial.theta",
            &tilts,
        ),
        (disc, "initial.theta_deg", &degrees),
    ] {
        let sw = steady::sweep(&base, Family::RollingCircle, key, values).unwrap();
        assert_eq!(sw.critical.len(), 2, "{key}: {:?}", sw.critical);
        let det = |v: f64| {
            let an = steady::sweep::analyse_at(
                &base,
                (Family::RollingCircle, steady::Solve::Spin),
                key,
                v,
            )
            .unwrap();
            an.spectrum
                .eigenvalues()
                .iter()
                .product::<Complex<f64>>()
                .re
        };
        for c in &sw.critical {
            let k = values.iter().position(|t| *t > c.value).unwrap();
            let root = bisect(det, values[k - 1], values[k]);
            let err = c.value / root - 1.0;
            eprintln!(
                "{} rolling circles: critical {key} {} against det J's root {root}: {err:.2e}",
                base.source, c.value
            );
            worst = worst.max(err.abs());
            found += 1;
        }
    }
    eprintln!("{found} critical values; largest difference {worst:.2e}");
    assert!(found >= 5, "{found} critical values");
    assert!(worst <= 1e-10, "{worst:e}");
}
