//! Coulomb–Contensou friction over a flat contact disc of radius R under uniform pressure
//! (docs/physics.md, "Friction over a contact disc"; issue #14).
//!
//! ```text
//!   d   = |v| / (R |ω_n|)                     v: slip of the disc's centre, ω_n = ω·e3
//!   F   = −μ N f(d) v/|v|                     friction force (horizontal)
//!   M_n = −μ N R g(d) sgn ω_n                 drilling torque about the disc's centre
//!
//!   d ≤ 1 (k = d):    f = (4d/3π) k'² [K + (1 + k²) D/3]
//!                     g = (4/9π)  k'² [(3 − 2k²) K + (2/3)(2 − k²) k² D]
//!   d ≥ 1 (k = 1/d):  f = (4/3π)  k'² [K + (1 + k²) D/3]
//!                     g = (4d/9π) k'² [K + (2/3)(2k² − 1) D]
//!   K = R_F(0, k'², 1) = K(k),  D = R_D(0, 1, k'²) = 3 (E − k'²K)/(k² k'²),  k'² = 1 − k²
//!
//!   series (z = d² ≤ 1/2, or z = 1/d² ≤ 1/2):
//!     f = d ₂F₁(−½, ½; 2; d²),     g = (2/3) ₂F₁(−3/2, ½; 1; d²)
//!     f = ₂F₁(−½, ½; 2; 1/d²),     g = ₂F₁(½, ½; 3; 1/d²) / (4d)
//! ```
//! Written with K and D (Carlson's symmetric integrals) every term is positive where it
//! is used (k² ≥ ½), so nothing cancels; the textbook forms in K(k) and E(k) cancel like
//! 1/d² (f, small d) and d⁴ (g, large d). Limits: f ≈ d, g → 2/3 (d → 0); f → 1,
//! g ≈ 1/(4d) (d → ∞); f(1) = 8/(3π), g(1) = 8/(9π).
//!
//! Tested against a 2-D quadrature of the traction over the disc (mpmath,
//! `scripts/contensou_reference.py`, values in `tests/data/contensou/reference.json`) to
//! 2e-15 relative for d in [1e-8, 1e8] (`tests/contensou.rs`).
//!
//! For the dynamics the law is evaluated in a form that is smooth wherever (v, ω_n) ≠ 0:
//! with s = |v|, w = R|ω_n|, for s ≤ w it uses f(d)/d (→ 1) so that F ≈ −μN v/w at
//! v → 0, and for s > w it uses d·g(d) (→ 1/4) so that M_n ≈ −μN R² ω_n/(4 s) at ω_n → 0
//! ([`Law::traction`]).

use std::f64::consts::PI;

use nalgebra::Vector2;

/// Which f, g the disc uses (`[contact] contact_law`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Law {
    /// The exact law over a uniformly loaded disc (the elliptic-integral forms above).
    #[default]
    Exact,
    /// Zhuravlev's first-order Padé form: f = d/(1 + d), g = (2/3)/(1 + 8d/3).
    Pade,
    /// The ellipsoidal force set of Möller, Leine & Glocker (2009) with R_b = 3πR/16:
    /// (F/μN)² + (M_n/(μN R_b))² = 1 with the normal-cone (maximum-dissipation) rule,
    /// f = d/√(d² + ρ²), g = ρ²/√(d² + ρ²), ρ = R_b/R = 3π/16.
    Ellipse,
}

impl Law {
    /// Every law, in [`Law::NAMES`] order.
    pub const ALL: [Law; 3] = [Law::Exact, Law::Pade, Law::Ellipse];
    /// Their names in scenario files.
    pub const NAMES: [&'static str; 3] = ["exact", "pade", "ellipse"];

    /// Its name in scenario files.
    pub fn name(self) -> &'static str {
        Law::NAMES[self as usize]
    }

    /// The law of a scenario name.
    pub fn from_name(name: &str) -> Option<Law> {
        Law::NAMES
            .iter()
            .position(|n| *n == name)
            .map(|i| Law::ALL[i])
    }

    /// f(d): the friction force over μN (0 ≤ f < 1).
    pub fn f(self, d: f64) -> f64 {
        if d <= 1.0 {
            d * self.inner(d).0
        } else {
            self.outer(1.0 / d).0
        }
    }

    /// g(d): the drilling torque over μNR (0 < g ≤ 2/3 for the exact law).
    pub fn g(self, d: f64) -> f64 {
        if d <= 1.0 {
            self.inner(d).1
        } else {
            match self {
                // d·g computed from 1/d, then divided by d: one rounding less than
                // multiplying by 1/d.
                Law::Exact => outer_exact_dg(d) / d,
                _ => self.outer(1.0 / d).1 / d,
            }
        }
    }

    /// (f(d)/d, g(d)) for 0 ≤ d ≤ 1.
    #[inline]
    fn inner(self, d: f64) -> (f64, f64) {
        match self {
            Law::Exact => inner_exact(d),
            Law::Pade => (1.0 / (1.0 + d), 2.0 / (3.0 + 8.0 * d)),
            Law::Ellipse => {
                let h = d.hypot(ELLIPSE_RHO);
                (1.0 / h, ELLIPSE_RHO * ELLIPSE_RHO / h)
            }
        }
    }

    /// (f(d), d·g(d)) for t = 1/d in [0, 1].
    #[inline]
    fn outer(self, t: f64) -> (f64, f64) {
        match self {
            Law::Exact => outer_exact(t),
            Law::Pade => (1.0 / (1.0 + t), 2.0 / (8.0 + 3.0 * t)),
            Law::Ellipse => {
                let h = (ELLIPSE_RHO * t).hypot(1.0);
                (1.0 / h, ELLIPSE_RHO * ELLIPSE_RHO / h)
            }
        }
    }

    /// The disc's friction per unit μN: (F/(μN), M_n/(μN)) for slip `v` [m/s] and spin
    /// `omega_n` = ω·e3 [rad/s] over a disc of radius `radius` [m] (M_n in m). `None`
    /// where the law is set-valued: v = 0 and ω_n = 0.
    #[inline]
    pub fn traction(
        self,
        v: Vector2<f64>,
        omega_n: f64,
        radius: f64,
    ) -> Option<(Vector2<f64>, f64)> {
        let s = v.norm();
        let w = radius * omega_n.abs();
        if s <= w {
            if w == 0.0 {
                return None;
            }
            // d ≤ 1: F = −μN (f/d) v/w, smooth through v = 0.
            let (f_over_d, g) = self.inner(s / w);
            Some((-f_over_d / w * v, -radius * g * omega_n.signum()))
        } else {
            // d > 1: M_n = −μN R (d g) R ω_n / s, smooth through ω_n = 0.
            let (f, dg) = self.outer(w / s);
            Some((-f / s * v, -radius * dg * radius * omega_n / s))
        }
    }
}

/// ρ = R_b/R = 3π/16 of the ellipsoidal force set.
pub const ELLIPSE_RHO: f64 = 3.0 * PI / 16.0;

/// Above this z (= d² or 1/d²) the closed forms in K, D are used, below it the series.
const SERIES_LIMIT: f64 = 0.5;

/// (f/d, g) of the exact law, 0 ≤ d ≤ 1.
fn inner_exact(d: f64) -> (f64, f64) {
    let z = d * d;
    if z <= SERIES_LIMIT {
        return (
            hypergeometric(-0.5, 0.5, 2.0, z),
            2.0 / 3.0 * hypergeometric(-1.5, 0.5, 1.0, z),
        );
    }
    if d == 1.0 {
        return (8.0 / (3.0 * PI), 8.0 / (9.0 * PI));
    }
    let kp2 = (1.0 - d) * (1.0 + d);
    let (k, dd) = carlson_rf_rd(0.0, 1.0, kp2);
    (
        4.0 / (3.0 * PI) * kp2 * (k + (1.0 + z) * dd / 3.0),
        4.0 / (9.0 * PI) * kp2 * ((3.0 - 2.0 * z) * k + 2.0 / 3.0 * (2.0 - z) * z * dd),
    )
}

/// (f, d·g) of the exact law from t = 1/d in [0, 1].
fn outer_exact(t: f64) -> (f64, f64) {
    let z = t * t;
    if z <= SERIES_LIMIT {
        return (
            hypergeometric(-0.5, 0.5, 2.0, z),
            0.25 * hypergeometric(0.5, 0.5, 3.0, z),
        );
    }
    if t == 1.0 {
        return (8.0 / (3.0 * PI), 8.0 / (9.0 * PI));
    }
    let kp2 = (1.0 - t) * (1.0 + t);
    outer_closed(z, kp2)
}

/// d·g of the exact law for d ≥ 1, with k'² = 1 − 1/d² formed from d itself.
fn outer_exact_dg(d: f64) -> f64 {
    let t = 1.0 / d;
    let z = t * t;
    if z <= SERIES_LIMIT {
        return 0.25 * hypergeometric(0.5, 0.5, 3.0, z);
    }
    if d == 1.0 {
        return 8.0 / (9.0 * PI);
    }
    outer_closed(z, (d - 1.0) * (d + 1.0) / (d * d)).1
}

/// (f, d·g) for d ≥ 1 from the closed form, z = k² = 1/d², kp2 = k'².
fn outer_closed(z: f64, kp2: f64) -> (f64, f64) {
    let (k, dd) = carlson_rf_rd(0.0, 1.0, kp2);
    (
        4.0 / (3.0 * PI) * kp2 * (k + (1.0 + z) * dd / 3.0),
        // d·g = (4 d²/9π) k'² [K + (2/3)(2k² − 1) D], d² = 1/z
        4.0 / (9.0 * PI) * kp2 * (k + 2.0 / 3.0 * (2.0 * z - 1.0) * dd) / z,
    )
}

/// ₂F₁(a, b; c; z) by its series for 0 ≤ z ≤ 1/2, summed with Neumaier's compensation.
/// The terms shrink at least like z^n n^{a+b−c−1}; the sum stops when a term no longer
/// changes it.
fn hypergeometric(a: f64, b: f64, c: f64, z: f64) -> f64 {
    let (mut sum, mut comp, mut term) = (1.0f64, 0.0f64, 1.0f64);
    let mut n = 0.0;
    loop {
        term *= (a + n) * (b + n) / ((c + n) * (n + 1.0)) * z;
        n += 1.0;
        let t = sum + term;
        comp += if sum.abs() >= term.abs() {
            (sum - t) + term
        } else {
            (term - t) + sum
        };
        sum = t;
        if term.abs() <= 1e-18 * sum.abs() || n > 200.0 {
            return sum + comp;
        }
    }
}

/// Carlson's R_F(x, y, z) by duplication (Carlson, Numer. Algorithms 10, 1995, §2), for
/// x, y, z ≥ 0 with at most one zero. Stops when the arguments agree to 1e-3, where the
/// truncation error of the fifth-order series is below 1e-18.
pub fn carlson_rf(mut x: f64, mut y: f64, mut z: f64) -> f64 {
    loop {
        let a = (x + y + z) / 3.0;
        let (dx, dy) = (1.0 - x / a, 1.0 - y / a);
        let dz = -dx - dy;
        if dx.abs().max(dy.abs()).max(dz.abs()) < 1e-3 {
            let e2 = dx * dy - dz * dz;
            let e3 = dx * dy * dz;
            return (1.0 - e2 / 10.0 + e3 / 14.0 + e2 * e2 / 24.0 - 3.0 * e2 * e3 / 44.0)
                / a.sqrt();
        }
        let (sx, sy, sz) = (x.sqrt(), y.sqrt(), z.sqrt());
        let lambda = sx * (sy + sz) + sy * sz;
        x = 0.25 * (x + lambda);
        y = 0.25 * (y + lambda);
        z = 0.25 * (z + lambda);
    }
}

/// Carlson's R_D(x, y, z) = R_J(x, y, z, z) by duplication (Carlson 1995, §4), for
/// x, y ≥ 0 (not both zero) and z > 0.
pub fn carlson_rd(mut x: f64, mut y: f64, mut z: f64) -> f64 {
    let (mut sum, mut fac) = (0.0, 1.0);
    loop {
        let a = (x + y + 3.0 * z) / 5.0;
        let (dx, dy) = (1.0 - x / a, 1.0 - y / a);
        let dz = -(dx + dy) / 3.0;
        if dx.abs().max(dy.abs()).max(dz.abs()) < 1e-3 {
            let xy = dx * dy;
            let z2 = dz * dz;
            let e2 = xy - 6.0 * z2;
            let e3 = (3.0 * xy - 8.0 * z2) * dz;
            let e4 = 3.0 * (xy - z2) * z2;
            let e5 = xy * z2 * dz;
            let series = 1.0 - 3.0 * e2 / 14.0 + e3 / 6.0 + 9.0 * e2 * e2 / 88.0
                - 3.0 * e4 / 22.0
                - 9.0 * e2 * e3 / 52.0
                + 3.0 * e5 / 26.0;
            return 3.0 * sum + fac * series / (a * a.sqrt());
        }
        let (sx, sy, sz) = (x.sqrt(), y.sqrt(), z.sqrt());
        let lambda = sx * (sy + sz) + sy * sz;
        sum += fac / (sz * (z + lambda));
        fac *= 0.25;
        x = 0.25 * (x + lambda);
        y = 0.25 * (y + lambda);
        z = 0.25 * (z + lambda);
    }
}

/// (R_F(x, y, z), R_D(x, y, z)) in one duplication loop: both integrals' duplication
/// steps are the same map of (x, y, z), so the square roots are shared; each series is
/// evaluated once its own arguments agree to 1e-3 (as in [`carlson_rf`], [`carlson_rd`]).
pub fn carlson_rf_rd(mut x: f64, mut y: f64, mut z: f64) -> (f64, f64) {
    let (mut sum, mut fac) = (0.0, 1.0);
    let mut rf = None;
    loop {
        if rf.is_none() {
            let a = (x + y + z) / 3.0;
            let (dx, dy) = (1.0 - x / a, 1.0 - y / a);
            let dz = -dx - dy;
            if dx.abs().max(dy.abs()).max(dz.abs()) < 1e-3 {
                let e2 = dx * dy - dz * dz;
                let e3 = dx * dy * dz;
                rf = Some(
                    (1.0 - e2 / 10.0 + e3 / 14.0 + e2 * e2 / 24.0 - 3.0 * e2 * e3 / 44.0)
                        / a.sqrt(),
                );
            }
        }
        let a = (x + y + 3.0 * z) / 5.0;
        let (dx, dy) = (1.0 - x / a, 1.0 - y / a);
        let dz = -(dx + dy) / 3.0;
        if let Some(rf) = rf
            && dx.abs().max(dy.abs()).max(dz.abs()) < 1e-3
        {
            let xy = dx * dy;
            let z2 = dz * dz;
            let e2 = xy - 6.0 * z2;
            let e3 = (3.0 * xy - 8.0 * z2) * dz;
            let e4 = 3.0 * (xy - z2) * z2;
            let e5 = xy * z2 * dz;
            let series = 1.0 - 3.0 * e2 / 14.0 + e3 / 6.0 + 9.0 * e2 * e2 / 88.0
                - 3.0 * e4 / 22.0
                - 9.0 * e2 * e3 / 52.0
                + 3.0 * e5 / 26.0;
            return (rf, 3.0 * sum + fac * series / (a * a.sqrt()));
        }
        let (sx, sy, sz) = (x.sqrt(), y.sqrt(), z.sqrt());
        let lambda = sx * (sy + sz) + sy * sz;
        sum += fac / (sz * (z + lambda));
        fac *= 0.25;
        x = 0.25 * (x + lambda);
        y = 0.25 * (y + lambda);
        z = 0.25 * (z + lambda);
    }
}

/// A flat contact disc (`[contact] contact_radius`, `contact_law`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactDisc {
    /// R \[m\], > 0.
    pub radius: f64,
    pub law: Law,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Carlson's own test values (Carlson 1995, §2 and §4; also DLMF 19.36 checks).
    #[test]
    fn carlson_values() {
        let close = |a: f64, b: f64| (a - b).abs() <= 4e-16 * b.abs();
        assert!(close(carlson_rf(1.0, 2.0, 0.0), 1.311_028_777_146_059_9));
        assert!(close(carlson_rf(2.0, 3.0, 4.0), 0.584_082_841_677_151_7));
        assert!(close(carlson_rd(0.0, 2.0, 1.0), 1.797_210_352_103_388_3));
        assert!(close(carlson_rd(2.0, 3.0, 4.0), 0.165_105_272_942_610_5));
        // K(k) and E(k) at k² = 1/2
        let k = carlson_rf(0.0, 0.5, 1.0);
        assert!(close(k, 1.854_074_677_301_372));
        for (x, y, z) in [
            (0.0, 1.0, 0.5),
            (0.0, 1.0, 1e-12),
            (2.0, 3.0, 4.0),
            (0.0, 2.0, 1.0),
        ] {
            let (rf, rd) = carlson_rf_rd(x, y, z);
            assert!(close(rf, carlson_rf(x, y, z)) && close(rd, carlson_rd(x, y, z)));
        }
    }

    /// The limits the issue states, and continuity where the evaluation changes form.
    #[test]
    fn limits_and_joins() {
        for law in Law::ALL {
            assert!(
                (law.f(1e-9) / 1e-9
                    - if law == Law::Ellipse {
                        1.0 / ELLIPSE_RHO
                    } else {
                        1.0
                    })
                .abs()
                    < 1e-8
            );
            assert!((law.f(1e12) - 1.0).abs() < 1e-11);
        }
        assert!((Law::Exact.g(0.0) - 2.0 / 3.0).abs() < 1e-16);
        assert!((Law::Exact.g(1e9) * 4e9 - 1.0).abs() < 1e-15);
        assert!((Law::Pade.g(1e9) * 4e9 - 1.0).abs() < 1e-8);
        for d in [SERIES_LIMIT.sqrt(), 1.0, 1.0 / SERIES_LIMIT.sqrt()] {
            for law in Law::ALL {
                let (lo, hi) = (d * (1.0 - 1e-15), d * (1.0 + 1e-15));
                assert!((law.f(lo) - law.f(hi)).abs() < 1e-14, "{law:?} f at {d}");
                assert!((law.g(lo) - law.g(hi)).abs() < 1e-14, "{law:?} g at {d}");
            }
        }
    }

    /// The dynamics form equals the plain one and is smooth at v = 0 and at ω_n = 0.
    #[test]
    fn traction_forms() {
        let r = 5e-4;
        for law in Law::ALL {
            for (v, w) in [
                (Vector2::new(0.03, -0.04), 20.0),
                (Vector2::new(1e-3, 2e-3), -3.0),
                (Vector2::new(0.3, 0.4), 1e-3),
            ] {
                let (f, m) = law.traction(v, w, r).unwrap();
                let d = v.norm() / (r * w.abs());
                let fe = -law.f(d) * v / v.norm();
                let me = -r * law.g(d) * w.signum();
                assert!((f - fe).norm() <= 1e-15 * fe.norm(), "{law:?} {f} {fe}");
                assert!((m - me).abs() <= 1e-15 * me.abs(), "{law:?} {m} {me}");
            }
            let (f0, _) = law.traction(Vector2::zeros(), 10.0, r).unwrap();
            assert_eq!(f0, Vector2::zeros());
            let (_, m0) = law.traction(Vector2::new(0.1, 0.0), 0.0, r).unwrap();
            assert_eq!(m0, 0.0);
            assert!(law.traction(Vector2::zeros(), 0.0, r).is_none());
        }
    }
}
