//! The impact law at touchdown (issue #13; docs/physics.md, "Impact at touchdown"):
//! `val_*` against closed forms or an independent integration, `inv_*` energy and
//! restitution over random impacts, `lim_*` the frictionless and no-slip limits.

use ellipsoid_core::impact::{Approach, Impact, Tangential, resolve};
use nalgebra::{Matrix3, Vector3};

#[path = "common/rng.rs"]
mod rng;

use rng::Rng;

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

// ------------------------------------------------------------------ collinear and planar

/// r ∥ e3 (any inertia, friction): k_tn = 0, so dv_n/dp = K_nn whatever the slip does
/// and the velocity ratio is −e, as for a frictionless impact.
#[test]
fn val_collinear_velocity_ratio_is_minus_e() {
    let mut rng = Rng(7);
    for k in 0..2_000 {
        let (mut body, _) = random_body(&mut rng);
        let a = body.r.norm();
        body.r = Vector3::new(0.0, 0.0, -a);
        let v_n = contact_velocity(&body).z;
        body.v_g.z -= v_n + rng.uniform(0.01, 1.0) * body.v_g.norm();
        let e = rng.uniform(0.0, 1.0);
        let out = resolve(
            &body,
            Tangential::Coulomb {
                friction: rng.uniform(0.0, 2.0),
            },
            e,
        );
        let (vn0, vn1) = out.normal_velocity;
        assert_close(
            &format!("case {k}: v_n⁺"),
            vn1,
            -e * vn0,
            1e-13 * contact_velocity(&body).norm(),
        );
    }
}

/// Planar impact (Stronge 2000 ch. 5): r = (r_x, 0, r_z), I⁻¹ diagonal, slip along x, so
/// K_xx = 1/m + d₂ r_z², K_xz = −d₂ r_x r_z, K_zz = 1/m + d₂ r_x² and every phase is
/// linear in p. The reference walks those phases by hand: slip with sign σ (dP_x/dp =
/// −μσ), a stop at p_s = −u₀/(du/dp), then stick (|K_xz/K_xx| ≤ μ, dP_x/dp = −K_xz/K_xx)
/// or reversal in the direction of K_xz; energetic restitution on the piecewise-quadratic
/// W_n. `body` = (m, d₂, r_x, r_z); returns (P_x, p_f, stuck).
fn planar_reference(
    body: (f64, f64, f64, f64),
    u0: f64,
    vn0: f64,
    mu: f64,
    e: f64,
) -> (f64, f64, bool) {
    let (m, d2, rx, rz) = body;
    let (kxx, kxz, kzz) = (
        1.0 / m + d2 * rz * rz,
        -d2 * rx * rz,
        1.0 / m + d2 * rx * rx,
    );
    let sgn = u0.signum();
    let (du1, dvn1, dpx1) = (-mu * sgn * kxx + kxz, -mu * sgn * kxz + kzz, -mu * sgn);
    let p_s = if du1 * sgn < 0.0 {
        -u0 / du1
    } else {
        f64::INFINITY
    };
    let a = -kxz / kxx;
    let stick = a.abs() <= mu;
    let (dvn2, dpx2) = if stick {
        (kzz - kxz * kxz / kxx, a)
    } else {
        let s2 = kxz.signum();
        (-mu * s2 * kxz + kzz, -mu * s2)
    };
    let segments = [(p_s, dvn1, dpx1), (f64::INFINITY, dvn2, dpx2)];
    let (mut p, mut vn, mut w, mut px) = (0.0, vn0, 0.0, 0.0);
    let mut target: Option<f64> = None;
    for (end, c, dpx) in segments {
        let advance = |x: f64, p: &mut f64, vn: &mut f64, w: &mut f64, px: &mut f64| {
            *w += *vn * x + 0.5 * c * x * x;
            *vn += c * x;
            *px += dpx * x;
            *p += x;
        };
        if target.is_none() && vn + c * (end - p) >= 0.0 {
            advance(-vn / c, &mut p, &mut vn, &mut w, &mut px);
            target = Some((1.0 - e * e) * w);
        }
        if let Some(t) = target {
            let x = (-vn + (vn * vn + 2.0 * c * (t - w)).sqrt()) / c;
            if p + x <= end {
                advance(x, &mut p, &mut vn, &mut w, &mut px);
                return (px, p, p > p_s && stick);
            }
        }
        advance(end - p, &mut p, &mut vn, &mut w, &mut px);
    }
    unreachable!()
}

#[test]
fn val_planar_stick_reversal_and_sliding() {
    let (m, d2, rx, rz) = (1.0, 50.0, 0.4, -0.1); // K_xx = 1.5, K_xz = 2, K_zz = 9
    let cases = [
        // (u₀, v_n⁻, μ, e, slip stops, stuck at the end)
        (-0.1, -1.0, 0.5, 0.7, true, false), // stop in compression, then reversal
        (-0.1, -1.0, 1.5, 0.7, true, true),  // stop, then stick
        (0.1, -1.0, 0.5, 0.7, false, false), // slip grows: one phase
        (-0.5, -1.0, 0.5, 1.0, true, false), // stop during restitution, then reversal
        (-0.1, -1.0, 0.5, 0.0, true, false), // plastic
    ];
    for (k, &(u0, vn0, mu, e, stops, stuck)) in cases.iter().enumerate() {
        let body = Approach {
            mass: m,
            inertia_inv: Matrix3::from_diagonal(&Vector3::new(30.0, d2, 20.0)),
            r: Vector3::new(rx, 0.0, rz),
            v_g: Vector3::new(u0, 0.0, vn0),
            omega: Vector3::zeros(),
        };
        let out = resolve(&body, Tangential::Coulomb { friction: mu }, e);
        let (px, pz, want_stuck) = planar_reference((m, d2, rx, rz), u0, vn0, mu, e);
        assert_eq!(want_stuck, stuck, "case {k}: reference branch");
        assert_eq!(out.stuck, stuck, "case {k}: stuck {out:?}");
        assert_eq!(out.slip_stop.is_some(), stops, "case {k}: stop {out:?}");
        let want = Vector3::new(px, 0.0, pz);
        assert_vec_close(
            &format!("case {k}: impulse"),
            &out.impulse,
            &want,
            1e-12 * want.norm(),
        );
        if stops && !stuck {
            // reversed: the slip after the impact has the sign of K_xz = 2 > 0
            assert!(
                contact_velocity(&after(&body, &out)).x > 0.0,
                "case {k}: reversal"
            );
        }
    }
}

// ------------------------------------------------------------------ curving slip vs RK4

/// Independent reference: classical RK4 at a fixed step in p on (P_x, P_y, W_n), with
/// v_C = v_C⁻ + K P recomputed each stage; compression end and restitution end found by
/// bisection on the length of a last RK4 step. Valid for slips that never stop.
fn rk4_reference(body: &Approach, mu: f64, e: f64, steps: usize) -> Vector3<f64> {
    let rx = body.r.cross_matrix();
    let k = Matrix3::identity() / body.mass - rx * body.inertia_inv * rx;
    let v0 = contact_velocity(body);
    let f = |p: f64, y: &Vector3<f64>| {
        let v = v0 + k * Vector3::new(y.x, y.y, p);
        let s = v.xy().normalize();
        Vector3::new(-mu * s.x, -mu * s.y, v.z)
    };
    let rk4 = |p: f64, y: &Vector3<f64>, h: f64| {
        let k1 = f(p, y);
        let k2 = f(p + 0.5 * h, &(y + k1 * (0.5 * h)));
        let k3 = f(p + 0.5 * h, &(y + k2 * (0.5 * h)));
        let k4 = f(p + h, &(y + k3 * h));
        y + (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (h / 6.0)
    };
    let v_n = |p: f64, y: &Vector3<f64>| (v0 + k * Vector3::new(y.x, y.y, p)).z;
    // the frictionless p_f bounds the scale of the impact
    let h = (1.0 + e) * -v0.z / k[(2, 2)] / steps as f64;
    let (mut p, mut y) = (0.0, Vector3::zeros());
    let march = |p: &mut f64, y: &mut Vector3<f64>, done: &dyn Fn(f64, &Vector3<f64>) -> bool| loop {
        let y1 = rk4(*p, y, h);
        if done(*p + h, &y1) {
            let (mut lo, mut hi) = (0.0, h);
            for _ in 0..200 {
                let mid = 0.5 * (lo + hi);
                if done(*p + mid, &rk4(*p, y, mid)) {
                    hi = mid
                } else {
                    lo = mid
                }
            }
            *y = rk4(*p, y, hi);
            *p += hi;
            return;
        }
        *y = y1;
        *p += h;
    };
    march(&mut p, &mut y, &|p, y| v_n(p, y) >= 0.0);
    let target = (1.0 - e * e) * y.z;
    march(&mut p, &mut y, &|_, y| y.z >= target);
    Vector3::new(y.x, y.y, p)
}

/// 3-D impacts whose slip direction turns by more than 0.3 rad without stopping (coupled
/// K_tt, k_tn): the impulse agrees with the RK4 reference to 1e-10.
#[test]
fn val_curving_slip_against_rk4() {
    let mut rng = Rng(99);
    let (mut found, mut worst, mut max_turn) = (0, 0.0f64, 0.0f64);
    for _ in 0..5_000 {
        let (body, _) = random_body(&mut rng);
        let (mu, e) = (rng.uniform(0.05, 1.0), rng.uniform(0.0, 1.0));
        let out = resolve(&body, Tangential::Coulomb { friction: mu }, e);
        let before = contact_velocity(&body).xy();
        let after_t = contact_velocity(&after(&body, &out)).xy();
        let turn = before.angle(&after_t);
        if out.slip_stop.is_some() || turn < 0.3 || out.normal_velocity.0 > -0.05 * before.norm() {
            continue;
        }
        let reference = rk4_reference(&body, mu, e, 20_000);
        let err = (out.impulse - reference).norm() / reference.norm();
        worst = worst.max(err);
        max_turn = max_turn.max(turn);
        assert!(
            err <= 1e-10,
            "impulse {:?} vs RK4 {reference:?}: {err:e} (turn {turn})",
            out.impulse
        );
        found += 1;
        if found == 20 {
            break;
        }
    }
    eprintln!(
        "curving slip: {found} cases, max relative impulse error vs RK4 {worst:e}, max turn {max_turn:.2} rad"
    );
    assert_eq!(found, 20);
}

// ------------------------------------------------------------------ limits

/// NoSlip is the limit μ → ∞ of Coulomb: the difference falls as 1/μ (100 times from
/// μ = 1e5 to 1e7; the constant is largest, ~170/μ, where the tangential impulse alone
/// separates the contact and the impact ends slipping with zero normal impulse).
#[test]
fn lim_no_slip_is_the_large_friction_limit() {
    let mut rng = Rng(5);
    let (mut worst6, mut worst_ratio) = (0.0f64, 0.0f64);
    let mut ended_slipping = 0;
    for k in 0..500 {
        let (body, inertia) = random_body(&mut rng);
        let e = rng.uniform(0.0, 1.0);
        let limit = resolve(&body, Tangential::NoSlip, e);
        let mut w = Worst::default();
        w.check(k, &body, &inertia, &limit, e);
        ended_slipping += !limit.stuck as u32;
        let err = |mu: f64| {
            let out = resolve(&body, Tangential::Coulomb { friction: mu }, e);
            (out.impulse - limit.impulse).norm() / limit.impulse.norm()
        };
        let (e5, e6, e7) = (err(1e5), err(1e6), err(1e7));
        worst6 = worst6.max(e6);
        assert!(e6 <= 1e-3, "case {k}: μ = 1e6 differs by {e6:e}");
        if e5 > 1e-9 {
            worst_ratio = worst_ratio.max(e7 / e5);
            assert!(
                e7 <= 0.012 * e5,
                "case {k}: no O(1/μ) convergence: {e5:e} → {e7:e}"
            );
        }
    }
    eprintln!(
        "no-slip limit: max rel. diff at μ = 1e6 {worst6:e}, max err(1e7)/err(1e5) {worst_ratio:e}, {ended_slipping} ended slipping"
    );
}

/// No impact, grazing, plastic, elastic, μ = 0, no initial slip: finite, sensible results.
#[test]
fn inv_edge_cases_are_finite() {
    let sphere = |v_g: Vector3<f64>, omega: Vector3<f64>| Approach {
        mass: 1.0,
        inertia_inv: Matrix3::identity() / 0.4,
        r: Vector3::new(0.0, 0.0, -1.0),
        v_g,
        omega,
    };
    let laws = [
        Tangential::Frictionless,
        Tangential::Coulomb { friction: 0.0 },
        Tangential::Coulomb { friction: 0.5 },
        Tangential::NoSlip,
    ];
    for law in laws {
        for e in [0.0, 0.5, 1.0] {
            // separating or resting: no impulse
            for vz in [0.0, 1.0] {
                let out = resolve(
                    &sphere(Vector3::new(1.0, 0.0, vz), Vector3::zeros()),
                    law,
                    e,
                );
                assert_eq!(out.impulse, Vector3::zeros());
                assert_eq!(out.energy_loss, 0.0);
            }
            for (v_g, omega) in [
                (Vector3::new(1.0, 0.5, -1e-300), Vector3::new(0.0, 3.0, 1.0)), // grazing
                (Vector3::new(0.0, 0.0, -2.0), Vector3::zeros()),               // no slip at all
                (Vector3::new(1.0, 0.0, -1e-12), Vector3::zeros()),             // nearly grazing
                (Vector3::new(1e-300, 0.0, -1.0), Vector3::zeros()),            // tiny slip
            ] {
                let body = sphere(v_g, omega);
                let out = resolve(&body, law, e);
                let all = [out.v_g, out.omega, out.impulse];
                assert!(
                    all.iter().all(|x| x.iter().all(|c| c.is_finite())),
                    "{law:?} e {e}: {out:?}"
                );
                assert!(
                    out.energy_loss >= 0.0 && out.impulse.z >= 0.0,
                    "{law:?} e {e}: {out:?}"
                );
                assert!(out.normal_velocity.1 >= -1e-15, "{law:?} e {e}: {out:?}");
            }
        }
    }
}
