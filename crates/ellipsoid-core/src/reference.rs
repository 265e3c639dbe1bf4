//! Exact references for accuracy measurements: the nutation period of a frictionless
//! body of revolution from the one-degree-of-freedom reduction (docs/physics.md,
//! "Invariants"), by Gauss–Legendre quadrature.
//!
//! ```text
//!   ½ (I + m h'(θ)²) θ̇² + V(θ) = E_r,   V(θ) = (L_z − I3 n cos θ)² / (2 I sin²θ) + m g h(θ)
//!   h(θ) = sqrt(a² sin²θ + c² cos²θ) + g_z cos θ          (height of G; g_z = −D2)
//!   T    = 2 ∫_{θ1}^{θ2} sqrt((I + m h'²) / (2 (E_r − V))) dθ      (θ1, θ2: turning points)
//! ```
//!
//! Numerics. With θ = θ1 + Δ sin²p, p = (χ + π/2)/2, the inverse square-root endpoint
//! singularities cancel and the integrand is analytic in χ ∈ [−π/2, π/2], so
//! Gauss–Legendre converges exponentially. E_r − V(θ) is small next to each term of V
//! (the nutation energy of a fast top is ~1e-4 of its potential energy), so it is never
//! formed as a difference of two evaluations of V: it is written as V(θa) − V(θa + δ)
//! about the nearer turning point θa (where E_r = V(θa)), with every difference of cosines
//! and squared sines expanded into products of sines of half-angles. The node offsets
//! δ = Δ sin²p are computed from 1 ± x, exact in floating point for the nodes x near ∓1.
//! The result is good to a few units of 1e-15 relative (unit tests: the torque-free sphere,
//! T = 2π I/|L|, to 1e-14; agreement of 96- and 128-node rules).

use std::f64::consts::PI;

use nalgebra::Vector3;

use crate::body::Body;
use crate::state::{self, State};

/// Gauss–Legendre nodes and weights on [−1, 1] (Newton's method on P_n from the
/// Chebyshev-like initial guesses cos(π(i − ¼)/(n + ½))), in decreasing node order.
pub fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    (1..=n)
        .map(|i| {
            let mut x = (PI * (i as f64 - 0.25) / (n as f64 + 0.5)).cos();
            let mut dp = 0.0;
            for _ in 0..100 {
                let (mut p0, mut p1) = (1.0, x);
                for k in 2..=n {
                    let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                    p0 = p1;
                    p1 = p2;
                }
                dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
                let dx = p1 / dp;
                x -= dx;
                if dx.abs() < 1e-16 {
                    break;
                }
            }
            (x, 2.0 / ((1.0 - x * x) * dp * dp))
        })
        .collect()
}

/// Why a state has no nutation-period reference.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum NoReference {
    /// The reduction needs a = b, the centre of mass on the axis and I1 = I2 with no
    /// products of inertia.
    #[error(
        "not a body of revolution (needs a = b, the centre of mass on the symmetry axis, I1 = I2 and a diagonal inertia tensor)"
    )]
    NotRevolution,
    /// sin θ = 0: the axis is vertical and θ does not oscillate.
    #[error("the symmetry axis is vertical (θ = {theta} rad): no nutation")]
    Upright { theta: f64 },
    /// The potential does not confine θ inside (0, π): the axis can pass through the
    /// vertical, where the reduction in θ is singular.
    #[error("the axis can reach the vertical (L_z = ±I3 n): the reduction in θ does not apply")]
    ThroughVertical,
    /// θ sits at the minimum of V to round-off: steady precession, no period.
    #[error("steady precession (θ at the minimum of its potential): no nutation to time")]
    Steady,
}

/// The exact nutation of a frictionless body of revolution.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Nutation {
    /// Lower turning point θ1 \[rad\].
    pub theta_min: f64,
    /// Upper turning point θ2 \[rad\].
    pub theta_max: f64,
    /// Period of θ(t) \[s\] (128-node rule).
    pub period: f64,
    /// |T(128 nodes) − T(96 nodes)| \[s\]: the quadrature's own error bound.
    pub uncertainty: f64,
}

/// The reduced one-degree-of-freedom problem.
struct Reduced {
    /// a², c², g_z (G − C0 along the axis) [m², m², m].
    a2: f64,
    c2: f64,
    gz: f64,
    /// m \[kg\], g [m/s²], I (transverse, about G) [kg m²].
    m: f64,
    g: f64,
    i1: f64,
    /// I3 n and L_z [kg m²/s].
    k: f64,
    l: f64,
}

impl Reduced {
    fn s(&self, theta: f64) -> f64 {
        let (sn, cs) = theta.sin_cos();
        (self.a2 * sn * sn + self.c2 * cs * cs).sqrt()
    }

    /// h'(θ) \[m\].
    fn dh(&self, theta: f64) -> f64 {
        let (sn, cs) = theta.sin_cos();
        (self.a2 - self.c2) * sn * cs / self.s(theta) - self.gz * sn
    }

    /// V(θa) − V(θa + δ) \[J\], without cancellation between nearby values of V.
    fn drop(&self, theta_a: f64, delta: f64) -> f64 {
        let theta = theta_a + delta;
        let (sa, ua) = theta_a.sin_cos();
        let (s, u) = theta.sin_cos();
        // cos θ − cos θa and sin²θa − sin²θ as products
        let du = -2.0 * (theta_a + 0.5 * delta).sin() * (0.5 * delta).sin();
        let dsin2 = -delta.sin() * (2.0 * theta_a + delta).sin();
        // W(u) = (L − K u)²/(2 I (1 − u²)):
        // W(ua) − W(u) = (u − ua)[K(A + B) − L(A u + B ua)] / (2 I sin²θa sin²θ)
        let (a, b) = (self.l - self.k * ua, self.l - self.k * u);
        let gyro =
            du * (self.k * (a + b) - self.l * (a * u + b * ua)) / (2.0 * self.i1 * sa * sa * s * s);
        // m g (h(θa) − h(θ)), h = s + g_z cos θ, s(θa) − s(θ) = (a² − c²)(sin²θa − sin²θ)/(s(θa) + s(θ))
        let grav = self.m
            * self.g
            * ((self.a2 - self.c2) * dsin2 / (self.s(theta_a) + self.s(theta)) - self.gz * du);
        gyro + grav
    }
}

/// The nutation of the frictionless body of revolution `body` started from state `y`
/// under gravity `gravity` [m/s²]: turning points and period.
pub fn nutation(body: &Body, gravity: f64, y: &State) -> Result<Nutation, NoReference> {
    let (ax, inertia, g_b) = (body.semi_axes(), body.inertia(), body.com_offset());
    let revolution = ax.x == ax.y
        && g_b.x == 0.0
        && g_b.y == 0.0
        && inertia[(0, 0)] == inertia[(1, 1)]
        && inertia[(0, 1)] == 0.0
        && inertia[(0, 2)] == 0.0
        && inertia[(1, 2)] == 0.0;
    if !revolution {
        return Err(NoReference::NotRevolution);
    }
    let rot = state::rotation(y);
    let zeta = Vector3::new(rot[(2, 0)], rot[(2, 1)], rot[(2, 2)]);
    let w = state::omega(y);
    let sin0 = zeta.x.hypot(zeta.y);
    let theta0 = sin0.atan2(zeta.z);
    if sin0 == 0.0 {
        return Err(NoReference::Upright { theta: theta0 });
    }
    let (i1, i3) = (inertia[(0, 0)], inertia[(2, 2)]);
    let red = Reduced {
        a2: ax.x * ax.x,
        c2: ax.z * ax.z,
        gz: g_b.z,
        m: body.mass(),
        g: gravity,
        i1,
        k: i3 * w.z,
        l: i1 * (zeta.x * w.x + zeta.y * w.y) + i3 * zeta.z * w.z,
    };
    // d(cos θ)/dt = (ζ × ω_b)·e3 = −sin θ θ̇
    let theta_dot0 = -(zeta.x * w.y - zeta.y * w.x) / sin0;
    let kinetic0 = 0.5 * (i1 + red.m * red.dh(theta0).powi(2)) * theta_dot0 * theta_dot0;
    // E_r − V(θ) > 0 between the turning points
    let f = |theta: f64| kinetic0 + red.drop(theta0, theta - theta0);

    // Bracket the turning points of the well the motion is in: walk a grid outward from
    // θ0 to the first point on each side where E_r − V < 0 (an oblate body has wells
    // near θ = 0 and θ = π; the global maximum of E_r − V may lie in the other one).
    // With none on a side the axis can pass through the vertical (V finite there).
    const GRID: usize = 20_000;
    let grid = |k: usize| k as f64 * PI / GRID as f64;
    let k0 = ((theta0 / PI * GRID as f64) as usize).clamp(1, GRID - 1);
    let below = (1..=k0).rev().map(grid).find(|&t| t < theta0 && f(t) < 0.0);
    let above = (k0..GRID).map(grid).find(|&t| t > theta0 && f(t) < 0.0);
    let (Some(lo_end), Some(hi_end)) = (below, above) else {
        return Err(NoReference::ThroughVertical);
    };
    let inside = (1..GRID).map(grid).filter(|&t| t > lo_end && t < hi_end);
    let peak = inside
        .chain([theta0])
        .max_by(|x, y| f(*x).total_cmp(&f(*y)))
        .expect("θ0 is inside");
    if !(f(peak) > 0.0) {
        return Err(NoReference::Steady);
    }
    // Bisection to the last bit: f(lo) and f(hi) have opposite signs.
    let root = |mut lo: f64, mut hi: f64| {
        let flo = f(lo);
        loop {
            let mid = 0.5 * (lo + hi);
            if mid == lo || mid == hi {
                break 0.5 * (lo + hi);
            }
            if (f(mid) > 0.0) == (flo > 0.0) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
    };
    let t1 = root(lo_end, peak);
    let t2 = root(peak, hi_end);
    if !(t2 > t1) {
        return Err(NoReference::Steady);
    }
    let width = t2 - t1;
    let half = 0.5 * width;
    let period = |n: usize| {
        let sum: f64 = gauss_legendre(n)
            .iter()
            .map(|&(x, w)| {
                // χ = xπ/2; p = (1 + x)π/4, q = (1 − x)π/4; θ − θ1 = Δ sin²p, θ2 − θ = Δ sin²q
                let (theta, gap) = if x < 0.0 {
                    let d = width * ((1.0 + x) * PI / 4.0).sin().powi(2);
                    (t1 + d, red.drop(t1, d))
                } else {
                    let d = width * ((1.0 - x) * PI / 4.0).sin().powi(2);
                    (t2 - d, red.drop(t2, -d))
                };
                let cos_chi = (x * PI / 2.0).cos();
                let integrand =
                    half * cos_chi * ((i1 + red.m * red.dh(theta).powi(2)) / (2.0 * gap)).sqrt();
                w * integrand * PI / 2.0
            })
            .sum();
        2.0 * sum
    };
    let (t96, t128) = (period(96), period(128));
    Ok(Nutation {
        theta_min: t1,
        theta_max: t2,
        period: t128,
        uncertainty: (t128 - t96).abs(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::state::EulerAngles;
    use nalgebra::{Matrix3, UnitQuaternion};

    fn state_of(angles: &EulerAngles) -> State {
        let mut y = State::zeros();
        state::set_quaternion(&mut y, &angles.rotation());
        y.fixed_rows_mut::<3>(state::OMEGA)
            .copy_from(&angles.omega_body());
        y
    }

    #[test]
    fn val_gauss_legendre_is_exact_for_degree_2n_minus_1() {
        for n in [8, 64, 128] {
            let rule = gauss_legendre(n);
            let w: f64 = rule.iter().map(|p| p.1).sum();
            assert!((w - 2.0).abs() < 1e-14, "n = {n}: Σw = {w}");
            // ∫ x^(2n−2) over [−1, 1] = 2/(2n − 1)
            let k = 2 * n as i32 - 2;
            let q: f64 = rule.iter().map(|&(x, w)| w * x.powi(k)).sum();
            assert!((q - 2.0 / (k + 1) as f64).abs() < 1e-14, "n = {n}: {q}");
        }
    }

    /// A sphere whose centre of mass is its centre feels no torque: the axis precesses
    /// about the fixed L at |L|/I, so θ(t) is periodic with T = 2π I / |L| exactly.
    #[test]
    fn val_torque_free_sphere_period_is_2pi_i_over_l() {
        let (r, m, i, i3) = (0.02, 0.1, 1.6e-5, 2.4e-5);
        let body = Body::new(
            Vector3::new(r, r, r),
            m,
            Matrix3::from_diagonal(&Vector3::new(i, i, i3)),
            Vector3::zeros(),
        )
        .unwrap();
        for (theta, theta_dot, phi_dot, psi_dot) in [
            (0.3, 1.0, 2.0, 40.0),
            (1.2, -3.0, 5.0, -20.0),
            (2.5, 0.0, 7.0, 10.0),
        ] {
            let a = EulerAngles {
                theta,
                phi: 0.4,
                psi: 1.1,
                theta_dot,
                phi_dot,
                psi_dot,
            };
            let y = state_of(&a);
            let l = (body.inertia() * a.omega_body()).norm();
            let exact = 2.0 * PI * i / l;
            let nut = nutation(&body, 9.81, &y).unwrap();
            assert!(
                (nut.period - exact).abs() < 1e-14 * exact,
                "θ0 = {theta}: {} vs {exact}",
                nut.period
            );
            assert!(nut.uncertainty < 1e-14 * exact);
        }
    }

    #[test]
    fn val_nutation_scene_quadrature_converges() {
        let (a, c, m) = (0.025, 0.0175, 0.05);
        let body = Body::of_revolution(
            a,
            c,
            m,
            m * (a * a + c * c) / 5.0,
            2.0 * m * a * a / 5.0,
            0.003,
        )
        .unwrap();
        let y = state_of(&EulerAngles {
            theta: 10f64.to_radians(),
            psi_dot: 60.0,
            ..Default::default()
        });
        let nut = nutation(&body, 9.81, &y).unwrap();
        assert!(nut.uncertainty < 1e-15 * nut.period, "{nut:?}");
        // started at rest in θ: θ0 is a turning point
        let theta0 = 10f64.to_radians();
        assert!(
            (nut.theta_min - theta0)
                .abs()
                .min((nut.theta_max - theta0).abs())
                < 1e-12,
            "{nut:?}"
        );
        assert!(nut.theta_max > nut.theta_min + 1e-3, "{nut:?}");
    }

    /// An oblate body has potential wells near θ = 0 and θ = π; started near π (almost
    /// upside down, slow spin) it nutates there, although E_r − V is larger in the other
    /// well. (Bracketing from the global maximum once picked the wrong one.)
    #[test]
    fn val_turning_points_are_those_of_the_well_containing_theta0() {
        let (a, c, m) = (0.025, 0.0175, 0.05);
        let body = Body::of_revolution(
            a,
            c,
            m,
            m * (a * a + c * c) / 5.0,
            2.0 * m * a * a / 5.0,
            0.001,
        )
        .unwrap();
        let theta0 = 162.81f64.to_radians();
        let y = state_of(&EulerAngles {
            theta: theta0,
            psi_dot: 0.2,
            ..Default::default()
        });
        let nut = nutation(&body, 9.81, &y).unwrap();
        assert!(
            nut.theta_min <= theta0 + 1e-12 && theta0 - 1e-12 <= nut.theta_max,
            "{nut:?}"
        );
        assert!(nut.theta_min > 2.8 && nut.theta_max < PI, "{nut:?}");
    }

    #[test]
    fn no_reference_for_an_upright_axis_or_a_triaxial_body() {
        let (a, c, m) = (0.025, 0.0175, 0.05);
        let body = Body::of_revolution(
            a,
            c,
            m,
            m * (a * a + c * c) / 5.0,
            2.0 * m * a * a / 5.0,
            0.003,
        )
        .unwrap();
        let upright = state_of(&EulerAngles {
            psi_dot: 60.0,
            ..Default::default()
        });
        assert!(matches!(
            nutation(&body, 9.81, &upright),
            Err(NoReference::Upright { .. })
        ));
        let tri = Body::new(
            Vector3::new(0.03, 0.02, 0.01),
            1.0,
            Matrix3::from_diagonal(&Vector3::new(1e-4, 2e-4, 2.5e-4)),
            Vector3::zeros(),
        )
        .unwrap();
        let mut y = State::zeros();
        state::set_quaternion(&mut y, &UnitQuaternion::from_euler_angles(0.3, 0.0, 0.0));
        assert_eq!(nutation(&tri, 9.81, &y), Err(NoReference::NotRevolution));
    }
}
