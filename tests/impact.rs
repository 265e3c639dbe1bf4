//! The impact law at touchdown (issue #13; docs/physics.md, "Impact at touchdown"):
//! `val_*` against closed forms or an independent integration, `inv_*` energy and
//! restitution over random impacts, `lim_*` the frictionless and no-slip limits.

use ellipsoid_core::impact::{Approach, Impact, Tangential, resolve};
use nalgebra::{Matrix3, Rotation3, Unit, Vector3};

/// SplitMix64: a self-contained, reproducible generator.
struct Rng(u64);

impl Rng {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    fn vector(&mut self, scale: f64) -> Vector3<f64> {
        Vector3::new(
            self.uniform(-1.0, 1.0),
            self.uniform(-1.0, 1.0),
            self.uniform(-1.0, 1.0),
        ) * scale
    }
    fn rotation(&mut self) -> Rotation3<f64> {
        let axis = Unit::new_normalize(self.vector(1.0) + Vector3::new(1e-3, 0.0, 0.0));
        Rotation3::from_axis_angle(&axis, self.uniform(0.0, std::f64::consts::PI))
    }
}

/// A body with random mass, triaxial inertia (triangle inequality), orientation, lever
/// arm (pointing down, as at a touchdown) and velocities with the contact approaching.
/// Returns the body and its world inertia.
fn random_body(rng: &mut Rng) -> (Approach, Matrix3<f64>) {
    let mass = rng.uniform(0.1, 10.0);
    let len = rng.uniform(0.01, 1.0);
    let i1 = rng.uniform(0.05, 1.0) * mass * len * len;
    let i2 = rng.uniform(0.05, 1.0) * mass * len * len;
    let i3 = rng.uniform((i1 - i2).abs() * 1.0001, (i1 + i2) * 0.9999);
    let rot = rng.rotation();
    let inertia =
        rot.matrix() * Matrix3::from_diagonal(&Vector3::new(i1, i2, i3)) * rot.matrix().transpose();
    let inertia_inv = rot.matrix()
        * Matrix3::from_diagonal(&Vector3::new(1.0 / i1, 1.0 / i2, 1.0 / i3))
        * rot.matrix().transpose();
    let mut r = rng.vector(len);
    r.z = -r.z.abs() - 0.05 * len;
    let speed = rng.uniform(0.01, 10.0);
    let v_g = rng.vector(speed);
    let omega = rng.vector(speed / len);
    let mut body = Approach {
        mass,
        inertia_inv,
        r,
        v_g,
        omega,
    };
    let v_n = contact_velocity(&body).z;
    // make it approach: v_n uniformly in (−speed, 0), sometimes grazing
    let target = -speed * rng.uniform(0.0, 1.0).powi(3).max(1e-9);
    body.v_g.z += target - v_n;
    (body, inertia)
}

fn contact_velocity(b: &Approach) -> Vector3<f64> {
    b.v_g + b.omega.cross(&b.r)
}

fn kinetic(mass: f64, inertia: &Matrix3<f64>, v_g: &Vector3<f64>, omega: &Vector3<f64>) -> f64 {
    0.5 * mass * v_g.norm_squared() + 0.5 * omega.dot(&(inertia * omega))
}

fn after(b: &Approach, out: &Impact) -> Approach {
    Approach {
        v_g: out.v_g,
        omega: out.omega,
        ..*b
    }
}

fn assert_close(what: &str, got: f64, want: f64, tol: f64) {
    assert!(
        (got - want).abs() <= tol,
        "{what}: got {got:e}, want {want:e}, diff {:e} > {tol:e}",
        got - want
    );
}

fn assert_vec_close(what: &str, got: &Vector3<f64>, want: &Vector3<f64>, tol: f64) {
    let d = (got - want).norm();
    assert!(
        d <= tol,
        "{what}: got {got:?}, want {want:?}, |diff| {d:e} > {tol:e}"
    );
}

// ------------------------------------------------------------------ sphere (Stronge ch. 4)

/// A uniform sphere (I = 2/5 m a²), centre of mass at the centre: K_tt = 7/(2m) 𝟙,
/// k_tn = 0, K_nn = 1/m. p_f = (1 + e) m |v_n|; the slip |v_t| falls at (7/2) μ / m per
/// unit p in a constant direction. Stick iff |v_t| ≤ (7/2) μ (1 + e) |v_n|; then
/// P_t = −(2m/7) v_t (G keeps 5/7 of the slip part, v_Gt⁺ = v_Gt − (2/7) v_t), else
/// P_t = −μ p_f ŝ. Spin: ω⁺ = ω + 5/(2 m a²) r × P, r × P = (a P_y, −a P_x, 0).
fn sphere_case(
    v_g: Vector3<f64>,
    omega: Vector3<f64>,
    mu: f64,
    e: f64,
) -> (Impact, Vector3<f64>, Vector3<f64>, bool) {
    let (m, a) = (0.17, 0.028575); // a pool ball [kg, m]
    let i = 0.4 * m * a * a;
    let body = Approach {
        mass: m,
        inertia_inv: Matrix3::identity() / i,
        r: Vector3::new(0.0, 0.0, -a),
        v_g,
        omega,
    };
    let out = resolve(&body, Tangential::Coulomb { friction: mu }, e);
    let v_c = contact_velocity(&body);
    let v_t = Vector3::new(v_c.x, v_c.y, 0.0);
    let v_n = v_c.z;
    let p_f = (1.0 + e) * m * -v_n;
    let sticks = v_t.norm() <= 3.5 * mu * (1.0 + e) * -v_n;
    let p_t = if sticks {
        -v_t * (2.0 * m / 7.0)
    } else {
        -v_t.normalize() * (mu * p_f)
    };
    let p = p_t + Vector3::new(0.0, 0.0, p_f);
    let v_g_after = v_g + p / m;
    let omega_after = omega + Vector3::new(a * p.y, -a * p.x, 0.0) * (5.0 / (2.0 * m * a * a));
    (out, v_g_after, omega_after, sticks)
}

#[test]
fn val_sphere_stick_and_slip_stronge_ch4() {
    let cases = [
        // (v_G, ω, μ, e, expect stick)
        (
            Vector3::new(0.3, 0.1, -2.0),
            Vector3::new(5.0, -3.0, 40.0),
            0.3,
            0.8,
            true,
        ),
        (
            Vector3::new(3.0, -1.0, -1.0),
            Vector3::new(0.0, 20.0, 7.0),
            0.2,
            0.5,
            false,
        ),
        (
            Vector3::new(0.5, 0.0, -0.5),
            Vector3::zeros(),
            0.5,
            0.0,
            true,
        ),
        (
            Vector3::new(1.5, 0.0, -0.5),
            Vector3::zeros(),
            0.1,
            1.0,
            false,
        ),
    ];
    for (k, &(v_g, omega, mu, e, stick)) in cases.iter().enumerate() {
        let (out, v_want, w_want, sticks) = sphere_case(v_g, omega, mu, e);
        assert_eq!(sticks, stick, "case {k}: closed form branch");
        assert_eq!(out.stuck, stick, "case {k}: stuck");
        assert_eq!(out.slip_stop.is_some(), stick, "case {k}: slip stop");
        assert_vec_close(
            &format!("case {k}: v_G"),
            &out.v_g,
            &v_want,
            1e-13 * v_want.norm(),
        );
        assert_vec_close(
            &format!("case {k}: ω"),
            &out.omega,
            &w_want,
            1e-13 * w_want.norm(),
        );
        let (vn0, vn1) = out.normal_velocity;
        assert_close(
            &format!("case {k}: v_n⁺ = −e v_n⁻"),
            vn1,
            -e * vn0,
            1e-14 * vn0.abs(),
        );
        if stick {
            // loss: ½ m v_n² (1 − e²) + (m/7) |v_t|²
            let v_c = v_g + omega.cross(&Vector3::new(0.0, 0.0, -0.028575));
            let m = 0.17;
            let want = 0.5 * m * v_c.z * v_c.z * (1.0 - e * e) + m / 7.0 * v_c.xy().norm_squared();
            assert_close(
                &format!("case {k}: loss"),
                out.energy_loss,
                want,
                1e-13 * want,
            );
        }
    }
}

/// At the stick/slip boundary |v_t| = (7/2) μ (1 + e) |v_n| both branches agree; on each
/// side the law takes the right one.
#[test]
fn val_sphere_branch_boundary() {
    let (vn, e, mu) = (-1.0, 0.6, 0.25);
    let threshold = 3.5 * mu * (1.0 + e) * -vn;
    for factor in [0.999, 1.001] {
        let v_g = Vector3::new(threshold * factor, 0.0, vn);
        let (out, v_want, w_want, sticks) = sphere_case(v_g, Vector3::zeros(), mu, e);
        assert_eq!(out.stuck, sticks);
        assert_vec_close("v_G", &out.v_g, &v_want, 1e-12);
        assert_vec_close("ω", &out.omega, &w_want, 1e-9);
    }
}

// ------------------------------------------------------------------ random impacts

/// Frictionless (μ = 0, any body): v_n⁺ = −e v_n⁻ to round-off (kinematic, kinetic and
/// energetic coefficients coincide), and e = 1 conserves the kinetic energy.
#[test]
fn inv_frictionless_random_restitution_and_energy() {
    let mut rng = Rng(13);
    let (mut worst_ratio, mut worst_energy) = (0.0f64, 0.0f64);
    for k in 0..10_000 {
        let (body, inertia) = random_body(&mut rng);
        let e = if k % 2 == 0 {
            1.0
        } else {
            rng.uniform(0.0, 1.0)
        };
        let law = if k % 3 == 0 {
            Tangential::Coulomb { friction: 0.0 }
        } else {
            Tangential::Frictionless
        };
        let out = resolve(&body, law, e);
        let (vn0, vn1) = out.normal_velocity;
        let scale = contact_velocity(&body).norm();
        let ratio_err = (vn1 + e * vn0).abs() / scale;
        worst_ratio = worst_ratio.max(ratio_err);
        assert!(
            ratio_err <= 1e-14,
            "case {k}: v_n⁺ + e v_n⁻ = {:e} (|v_C| {scale:e})",
            vn1 + e * vn0
        );
        assert_eq!(out.impulse.xy().norm(), 0.0);
        let t0 = kinetic(body.mass, &inertia, &body.v_g, &body.omega);
        let t1 = kinetic(body.mass, &inertia, &out.v_g, &out.omega);
        if e == 1.0 {
            let rel = (t1 - t0).abs() / t0;
            worst_energy = worst_energy.max(rel);
            assert!(rel <= 1e-14, "case {k}: e = 1 energy change {rel:e}");
            assert!(
                out.energy_loss.abs() <= 1e-14 * t0,
                "case {k}: reported loss {:e}",
                out.energy_loss
            );
        }
    }
    eprintln!(
        "frictionless: max |v_n⁺ + e v_n⁻|/|v_C| = {worst_ratio:e}, e = 1 max |ΔT|/T = {worst_energy:e}"
    );
}

/// Coulomb friction, μ ∈ [0, 2], e ∈ [0, 1], 2·10⁴ random bodies and approaches:
/// - energy never increases (T from the velocities, with the world inertia);
/// - the reported loss equals T⁻ − T⁺ and, independently, the work of the impulse along
///   its path, −W_n(p_f) + W_f;
/// - the normal work of restitution is −e² times that of compression (Stronge);
/// - a stuck end has zero slip; the work stays bounded.
#[test]
fn inv_coulomb_random_energy_never_increases() {
    let mut rng = Rng(2024);
    let mut worst = Worst::default();
    let (mut stops, mut stuck, mut resumed) = (0, 0, 0);
    for k in 0..20_000 {
        let (mut body, inertia) = random_body(&mut rng);
        if k % 3 == 0 {
            // mostly normal approach, so that the slip stops early
            let v_c = contact_velocity(&body);
            let f = rng.uniform(0.0, 1.0);
            body.v_g -= Vector3::new(v_c.x, v_c.y, 0.0) * f;
        }
        // small μ often: a slip that stops then mostly resumes (|K_tt⁻¹ k_tn| > μ)
        let mu = match k % 10 {
            0 => 2.0,
            1..=4 => rng.uniform(0.0, 0.3),
            _ => rng.uniform(0.0, 2.0),
        };
        let e = match k % 7 {
            0 => 0.0,
            1 => 1.0,
            _ => rng.uniform(0.0, 1.0),
        };
        let out = resolve(&body, Tangential::Coulomb { friction: mu }, e);
        worst.check(k, &body, &inertia, &out, e);
        stops += out.slip_stop.is_some() as u32;
        stuck += (out.slip_stop.is_some() && out.stuck) as u32;
        resumed += (out.slip_stop.is_some() && !out.stuck) as u32;
    }
    eprintln!("coulomb: {worst:?}; slip stops {stops} (stick {stuck}, slip resumed {resumed})");
    assert!(
        stuck > 1000 && resumed >= 10,
        "the set must exercise both ends of a slip stop"
    );
}

#[derive(Debug, Default)]
struct Worst {
    /// max (T⁺ − T⁻)/T⁻ (a gain is positive).
    energy_gain: f64,
    /// max |reported loss − (T⁻ − T⁺)|/T⁻.
    loss_vs_velocities: f64,
    /// max |loss − (−W_n(p_f) + W_f)|/T⁻.
    loss_vs_path_work: f64,
    /// max |W_r + e² W_c|/|W_c|.
    restitution_work: f64,
    steps: u32,
}

impl Worst {
    fn check(&mut self, k: usize, body: &Approach, inertia: &Matrix3<f64>, out: &Impact, e: f64) {
        for x in [out.v_g, out.omega, out.impulse] {
            assert!(
                x.iter().all(|c| c.is_finite()),
                "case {k}: non-finite {out:?}"
            );
        }
        let t0 = kinetic(body.mass, inertia, &body.v_g, &body.omega);
        let t1 = kinetic(body.mass, inertia, &out.v_g, &out.omega);
        let gain = (t1 - t0) / t0;
        self.energy_gain = self.energy_gain.max(gain);
        assert!(
            gain <= 1e-13,
            "case {k}: energy gain {gain:e}: {body:?} {out:?}"
        );
        assert!(
            out.energy_loss >= 0.0,
            "case {k}: reported loss {:e}",
            out.energy_loss
        );
        let d = (out.energy_loss - (t0 - t1)).abs() / t0;
        self.loss_vs_velocities = self.loss_vs_velocities.max(d);
        assert!(
            d <= 1e-13,
            "case {k}: loss {:e} vs T⁻ − T⁺ {:e}",
            out.energy_loss,
            t0 - t1
        );
        let path = -(out.compression_work + out.restitution_work) + out.friction_work;
        let d = (out.energy_loss - path).abs() / t0;
        self.loss_vs_path_work = self.loss_vs_path_work.max(d);
        assert!(
            d <= 1e-10,
            "case {k}: loss {:e} vs path work {path:e} ({d:e}): {out:?}",
            out.energy_loss
        );
        assert!(out.compression_work <= 0.0 && out.friction_work >= 0.0);
        if out.compression_work < 0.0 {
            let d =
                (out.restitution_work + e * e * out.compression_work).abs() / -out.compression_work;
            self.restitution_work = self.restitution_work.max(d);
            assert!(
                d <= 1e-10,
                "case {k}: W_r {:e} vs −e² W_c {:e}",
                out.restitution_work,
                -e * e * out.compression_work
            );
        }
        assert!(out.impulse.z >= 0.0);
        if out.stuck {
            assert!(
                contact_velocity(&after(body, out)).xy().norm()
                    <= 1e-12 * contact_velocity(body).norm()
            );
        }
        self.steps = self.steps.max(out.steps);
        assert!(out.steps <= 2000, "case {k}: {} steps", out.steps);
    }
}

/// A slip that ends on a slowly approached, strongly attracting ray (|K_tt⁻¹ k_tn| close
/// to μ): stiff in the slip direction. It took 4 760 steps in the log-slip chart before
/// the straight-line finish; the result agrees with that run to 1e-12.
#[test]
fn inv_stiff_slip_approach_is_cheap() {
    let body = Approach {
        mass: 6.053136325492379,
        inertia_inv: Matrix3::new(
            62.63792561774601,
            3.848049851149736,
            -1.1545032148308594,
            3.848049851149735,
            94.7086419935684,
            9.821341483119166,
            -1.1545032148308594,
            9.821341483119166,
            43.06642386773954,
        ),
        r: Vector3::new(
            -0.007689978910498502,
            0.03007209382128479,
            -0.07056906359520311,
        ),
        v_g: Vector3::new(
            -0.33885180700282863,
            -0.06734623879319364,
            -0.7888555774241311,
        ),
        omega: Vector3::new(-6.237345225342496, -4.786801726979026, -8.28932013807878),
    };
    let out = resolve(
        &body,
        Tangential::Coulomb {
            friction: 0.2924367058226638,
        },
        0.46540243316769514,
    );
    assert!(out.stuck && out.steps <= 200, "{out:?}");
    // the 4 760-step run (log-slip chart all the way down to SLIP_TOL)
    let long = Vector3::new(0.23572346834630675, -1.0061143247807363, 6.889137790486399);
    assert_vec_close("impulse", &out.impulse, &long, 1e-12 * long.norm());
}
