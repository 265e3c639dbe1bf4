//! Exact contact geometry of an ellipsoid touching the plane z = 0, for any semi-axes,
//! and of a contact sphere fixed in the body (docs/physics.md, "Contact spheres").
//!
//! docs/physics.md, "Contact geometry". With ζ = Rᵀe3 (world up in body axes) and
//! A = diag(a, b, c):
//! ```text
//!   s    = sqrt(ζᵀA²ζ)                      height of C0 (paper eq. 8: D1)
//!   p_c  = −A²ζ / s                          contact point C from C0, body axes
//!   r_b  = p_c − g_b                         lever arm C − G, body axes
//!   h    = s + ζ·g_b                         height of G;  ∇h = −r_b
//!   H    = A²/s − (A²ζ)(A²ζ)ᵀ/s³             Hessian of s (curvature of the support map)
//!   ζ̇    = ζ × ω_b,   ṙ_b = −H ζ̇             the contact point moves over the body
//!   u    = r_b × ζ,   κ = r_b·(ζ̇ × ω_b) − ζ̇ᵀHζ̇,   z̈_G = −u·ω̇_b − κ
//! ```
//! A sphere of radius ρ centred at c (body axes, from C0) is the ellipsoid A = ρI moved
//! by c: s = ρ|ζ| − c·ζ, p_c = c − ρζ/|ζ|, H = ρ(I/|ζ| − ζζᵀ/|ζ|³) (= ρ(I − ζζᵀ) on the
//! unit sphere of ζ); the rest is the same. A rim — the torus of a sphere of radius ρ
//! whose centre runs round the circle of radius R about body z centred at c — adds the
//! circle's support R|Pζ|, P = I − e3e3ᵀ (docs/physics.md, "Rims"):
//! ```text
//!   s    = ρ|ζ| − c·ζ + R|Pζ|,   p_c = c − ρζ/|ζ| − R Pζ/|Pζ|
//!   H    = ρ(I/|ζ| − ζζᵀ/|ζ|³) + R(P/|Pζ| − PζζᵀP/|Pζ|³)
//! ```
//! singular where the rim lies flat (|Pζ| = 0, its whole circle at the plane): the run
//! never integrates across it (the `flat` event).

use nalgebra::{Matrix3, Vector3};

use crate::body::{Body, Surface};

/// Contact quantities at one instant, all in body axes.
#[derive(Debug, Clone, Copy)]
pub struct Contact {
    /// The surface touching (or, in flight, nearest to) the plane.
    pub surface: Surface,
    /// ζ = Rᵀ e3, world up in body axes.
    pub zeta: Vector3<f64>,
    /// Contact point C relative to C0 \[m\].
    pub p_c: Vector3<f64>,
    /// Lever arm r = C − G \[m\].
    pub r: Vector3<f64>,
    /// Height of G above the plane \[m\].
    pub height: f64,
    /// ζ̇ = ζ × ω_b [1/s].
    pub zeta_dot: Vector3<f64>,
    /// Rate of the contact point over the body surface, ṙ_b = −H ζ̇ [m/s].
    pub r_dot_surface: Vector3<f64>,
    /// u = r × ζ \[m\].
    pub u: Vector3<f64>,
    /// κ = r·(ζ̇ × ω) − ζ̇ᵀHζ̇ [m/s²], so that z̈_G = −u·ω̇ − κ.
    pub kappa: f64,
}

impl Contact {
    /// Evaluates the contact geometry of the body's surface ([`Body::surface`]) for body
    /// orientation `zeta` (unit) and body angular velocity `omega` [rad/s].
    #[inline(always)]
    pub fn new(body: &Body, zeta: Vector3<f64>, omega: Vector3<f64>) -> Self {
        Contact::of(body, body.surface(), zeta, omega)
    }

    /// The contact geometry of `surface`.
    #[inline(always)]
    pub fn of(body: &Body, surface: Surface, zeta: Vector3<f64>, omega: Vector3<f64>) -> Self {
        match surface {
            Surface::Ellipsoid => Contact::ellipsoid(body, zeta, omega),
            Surface::Sphere(k) => {
                let sphere = &body.spheres()[k];
                Contact::torus(
                    body,
                    surface,
                    sphere.center,
                    0.0,
                    sphere.radius,
                    zeta,
                    omega,
                )
            }
            Surface::Rim(k) => {
                let rim = &body.rims()[k];
                Contact::torus(body, surface, rim.center, rim.radius, rim.edge, zeta, omega)
            }
        }
    }

    /// The ellipsoid's contact geometry (the right-hand side's path: kept inline).
    #[inline(always)]
    fn ellipsoid(body: &Body, zeta: Vector3<f64>, omega: Vector3<f64>) -> Self {
        let (a2, a2z, s) = support(body.semi_axes(), zeta);
        let zeta_dot = zeta.cross(&omega);
        // H ζ̇ without forming H: A²ζ̇/s − A²ζ (A²ζ·ζ̇)/s³.
        let h_zd = a2.component_mul(&zeta_dot) / s - a2z * (a2z.dot(&zeta_dot) / (s * s * s));
        Contact::complete(
            body,
            Surface::Ellipsoid,
            zeta,
            omega,
            zeta_dot,
            s,
            -a2z / s,
            h_zd,
        )
    }

    /// The contact geometry of a torus about body z: a sphere of radius `edge` centred
    /// at `center` moved round a circle of radius `ring` (a contact sphere: `ring` = 0; a
    /// rim). At |Pζ| = 0 (a rim lying flat) the circle's support point is taken on body x
    /// and its curvature left out: the machine ends the rim's contact before (`flat`).
    #[inline(never)]
    fn torus(
        body: &Body,
        surface: Surface,
        center: Vector3<f64>,
        ring: f64,
        edge: f64,
        zeta: Vector3<f64>,
        omega: Vector3<f64>,
    ) -> Self {
        let (rho, c) = (edge, center);
        let n = zeta.norm();
        let zeta_dot = zeta.cross(&omega);
        // ρ(ζ̇/|ζ| − ζ (ζ·ζ̇)/|ζ|³).
        let mut h_zd = rho * (zeta_dot / n - zeta * (zeta.dot(&zeta_dot) / (n * n * n)));
        let mut s = rho * n - c.dot(&zeta);
        let mut p_c = c - zeta * (rho / n);
        if ring > 0.0 {
            let (out, m) = ring_direction(zeta);
            s += ring * m;
            p_c -= ring * out;
            if m > 0.0 {
                // R(Pζ̇/|Pζ| − Pζ (Pζ·ζ̇)/|Pζ|³), Pζ = m·out.
                let pzd = Vector3::new(zeta_dot.x, zeta_dot.y, 0.0);
                h_zd += ring * (pzd - out * out.dot(&zeta_dot)) / m;
            }
        }
        Contact::complete(body, surface, zeta, omega, zeta_dot, s, p_c, h_zd)
    }

    /// The rest of the geometry from the support height s, the contact point p_c and H ζ̇.
    #[allow(clippy::too_many_arguments)] // the support map's pieces, each from its surface
    #[inline(always)]
    fn complete(
        body: &Body,
        surface: Surface,
        zeta: Vector3<f64>,
        omega: Vector3<f64>,
        zeta_dot: Vector3<f64>,
        s: f64,
        p_c: Vector3<f64>,
        h_zd: Vector3<f64>,
    ) -> Self {
        let g = body.com_offset();
        let r = p_c - g;
        let kappa = r.dot(&zeta_dot.cross(&omega)) - zeta_dot.dot(&h_zd);
        Contact {
            surface,
            zeta,
            p_c,
            r,
            height: s + zeta.dot(&g),
            zeta_dot,
            r_dot_surface: -h_zd,
            u: r.cross(&zeta),
            kappa,
        }
    }

    /// The contact geometry of the surface nearest the plane (the one G would stand
    /// highest on, touching: the body's lowest point; [`height`]), the ellipsoid on a tie.
    #[inline]
    pub fn lowest(body: &Body, zeta: Vector3<f64>, omega: Vector3<f64>) -> Self {
        if body.plain() {
            return Contact::of(body, Surface::Ellipsoid, zeta, omega);
        }
        let lowest = body
            .surfaces()
            .map(|s| (s, height(body, s, zeta)))
            .fold((body.surface(), f64::NEG_INFINITY), |best, x| {
                if x.1 > best.1 { x } else { best }
            })
            .0;
        Contact::of(body, lowest, zeta, omega)
    }

    /// Vertical velocity of G while touching, v_Gz = −r·ζ̇ = −e3·(ω × r) [m/s].
    #[inline]
    pub fn vz(&self) -> f64 {
        -self.r.dot(&self.zeta_dot)
    }
}

/// The height of G when `surface` touches the plane, h(ζ) = s(ζ) + ζ·g \[m\]: the
/// surface's gap is z_G − h(ζ), and the surface with the largest h is the lowest.
#[inline]
pub fn height(body: &Body, surface: Surface, zeta: Vector3<f64>) -> f64 {
    let s = match surface {
        Surface::Ellipsoid => support(body.semi_axes(), zeta).2,
        Surface::Sphere(k) => {
            let sphere = &body.spheres()[k];
            sphere.radius * zeta.norm() - sphere.center.dot(&zeta)
        }
        Surface::Rim(k) => {
            let rim = &body.rims()[k];
            rim.edge * zeta.norm() - rim.center.dot(&zeta) + rim.radius * ring_direction(zeta).1
        }
    };
    s + zeta.dot(&body.com_offset())
}

/// The outward direction Pζ/|Pζ| in the plane of a rim (body x at |Pζ| = 0) and |Pζ|,
/// P = I − e3e3ᵀ: the rim's lowest point is its circle's point −R Pζ/|Pζ| from its centre,
/// and |Pζ| = sin α for a rim tilted α from the plane (docs/physics.md, "Rims").
#[inline(always)]
pub fn ring_direction(zeta: Vector3<f64>) -> (Vector3<f64>, f64) {
    // √(x² + y²) rather than hypot: |ζ| ≤ 1 cannot overflow, and hypot costs as much as
    // the rest of the gap.
    let m = (zeta.x * zeta.x + zeta.y * zeta.y).sqrt();
    if m > 0.0 {
        (Vector3::new(zeta.x / m, zeta.y / m, 0.0), m)
    } else {
        (Vector3::x(), 0.0)
    }
}

/// A bound of |d²h/dt²| for surface `surface`'s height h(ζ) ([`height`]) while the body
/// turns at |ω| ≤ `w` with |ω̇| ≤ `w_dot` \[m/s²\] (docs/physics.md, "Flight"). With ζ̇ = ζ × ω
/// and ζ̈ = ζ̇ × ω + ζ × ω̇, |ζ̇| ≤ w and |ζ̈| ≤ w² + ẇ (|ζ| = 1):
/// - a sphere, h = ρ − (c − g)·ζ: |ḧ| ≤ (w² + ẇ)|c − g|;
/// - the ellipsoid, h = s(ζ) + g·ζ, ḧ = (∇s + g)·ζ̈ + ζ̇ᵀHζ̇ with |∇s| = |A²ζ|/s ≤ a_max
///   and ‖H‖ ≤ a_max²/s ≤ a_max²/a_min: |ḧ| ≤ (w² + ẇ)(a_max + |g|) + w² a_max²/a_min;
/// - a rim, h = r − (c − g)·ζ + R|Pζ|: |ḧ| ≤ (w² + ẇ)(|c − g| + R) + w² R/|Pζ|, the last
///   term unbounded as the rim goes flat; taken with |Pζ| at half its value `tilt` at the
///   segment's start (floored at [`FLAT_TILT`]), an estimate the guard backs.
pub fn height_acceleration_bound(
    body: &Body,
    surface: Surface,
    w: f64,
    w_dot: f64,
    tilt: f64,
) -> f64 {
    let turn = w * w + w_dot;
    let g = body.com_offset();
    match surface {
        Surface::Ellipsoid => {
            let a = body.semi_axes();
            let (a_min, a_max) = (a.min(), a.max());
            turn * (a_max + g.norm()) + w * w * a_max * a_max / a_min
        }
        Surface::Sphere(k) => turn * (body.spheres()[k].center - g).norm(),
        Surface::Rim(k) => {
            let rim = &body.rims()[k];
            turn * ((rim.center - g).norm() + rim.radius)
                + w * w * rim.radius / (0.5 * tilt).max(FLAT_TILT)
        }
    }
}

/// The tilt |Pζ| = sin α below which a rim counts as lying flat: its circle's far side
/// then lies within 2R·[`FLAT_TILT`] of the plane (docs/physics.md, "Rims").
pub const FLAT_TILT: f64 = 1e-6;

/// The support map of the ellipsoid with semi-axes `a` at `zeta` (any length): A², A²ζ
/// and s = √(ζᵀA²ζ) \[m\], the height of the centre C0 above the ellipsoid's lowest point
/// when ζ is world up in body axes (docs/physics.md, "Contact geometry").
#[inline(always)]
fn support(a: Vector3<f64>, zeta: Vector3<f64>) -> (Vector3<f64>, Vector3<f64>, f64) {
    let a2 = a.component_mul(&a);
    let a2z = a2.component_mul(&zeta);
    let s = zeta.dot(&a2z).sqrt();
    (a2, a2z, s)
}

/// The support point of the ellipsoid with semi-axes `a` \[m\] for world up `zeta` in
/// body axes: its lowest point, p_c = −A²ζ/√(ζᵀA²ζ), from its centre C0, in body axes
/// \[m\] (docs/physics.md, "Contact geometry"; the contact point of [`Contact`]).
pub fn support_point(a: Vector3<f64>, zeta: Vector3<f64>) -> Vector3<f64> {
    let (_, a2z, s) = support(a, zeta);
    -a2z / s
}

/// The Hessian H of the support height of the body's surface ([`Body::surface`]), see the
/// module docs: the ellipsoid's A²/s − (A²ζ)(A²ζ)ᵀ/s³, a sphere's ρ(I/|ζ| − ζζᵀ/|ζ|³), a
/// rim's adds R(P/|Pζ| − PζζᵀP/|Pζ|³) (left out at |Pζ| = 0, where it is singular). Used
/// by the steady analysis (rest attitudes) and tests; the right-hand side applies H to a
/// vector without forming it.
pub fn hessian(body: &Body, zeta: Vector3<f64>) -> Matrix3<f64> {
    let ball = |rho: f64| {
        let n = zeta.norm();
        (Matrix3::identity() / n - zeta * zeta.transpose() / (n * n * n)) * rho
    };
    match body.surface() {
        Surface::Ellipsoid => {
            let (a2, a2z, s) = support(body.semi_axes(), zeta);
            Matrix3::from_diagonal(&a2) / s - a2z * a2z.transpose() / (s * s * s)
        }
        Surface::Sphere(k) => ball(body.spheres()[k].radius),
        Surface::Rim(k) => {
            let rim = &body.rims()[k];
            let (out, m) = ring_direction(zeta);
            let mut h = ball(rim.edge);
            if m > 0.0 {
                let p = Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, 0.0));
                h += (p - out * out.transpose()) * (rim.radius / m);
            }
            h
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::body::uniform_inertia;

    fn body() -> Body {
        let ax = Vector3::new(0.03, 0.02, 0.01);
        Body::new(
            ax,
            1.0,
            uniform_inertia(ax, 1.0),
            Vector3::new(0.001, -0.002, -0.003),
        )
        .unwrap()
    }

    /// The contact point is the lowest point: p_c lies on the surface and its outward
    /// normal A⁻²p_c is parallel to −ζ.
    #[test]
    fn contact_point_is_the_support_point() {
        let b = body();
        let zeta = Vector3::new(0.3, -0.5, 0.8).normalize();
        let c = Contact::new(&b, zeta, Vector3::zeros());
        let a = b.semi_axes();
        assert_eq!(c.p_c, support_point(a, zeta));
        let q = c.p_c.component_div(&a);
        assert!((q.norm_squared() - 1.0).abs() < 1e-14);
        let normal = c.p_c.component_div(&a.component_mul(&a));
        assert!(normal.normalize().dot(&-zeta) > 1.0 - 1e-14);
    }

    /// Finite differences, on every kind of surface: ∇h = −r and the Hessian of s is H.
    #[test]
    fn height_gradient_and_hessian_match_finite_differences() {
        use crate::body::{Rim, Sphere};
        let plain = body();
        let stem = Sphere {
            name: "stem".into(),
            center: Vector3::new(0.002, -0.001, 0.013),
            radius: 0.004,
        };
        let rim = Rim {
            name: "rim".into(),
            center: Vector3::new(0.0, 0.0, -0.004),
            radius: 0.02,
            edge: 0.002,
        };
        let sphered = plain.clone().with_spheres(vec![stem]).unwrap();
        let rimmed = plain.clone().with_rims(vec![rim]).unwrap();
        let bodies = [
            plain,
            sphered.touching(Surface::Sphere(0)),
            rimmed.touching(Surface::Rim(0)),
        ];
        let zeta = Vector3::new(0.3, -0.5, 0.8).normalize();
        let eps = 1e-6;
        for b in &bodies {
            let c0 = Contact::new(b, zeta, Vector3::zeros());
            let h = hessian(b, zeta);
            for k in 0..3 {
                let mut dz = Vector3::zeros();
                dz[k] = eps;
                let cp = Contact::new(b, zeta + dz, Vector3::zeros());
                let cm = Contact::new(b, zeta - dz, Vector3::zeros());
                // h is defined for any ζ (not only unit): s(ζ) + ζ·g.
                let grad = (cp.height - cm.height) / (2.0 * eps);
                assert!(
                    (grad + c0.r[k]).abs() < 1e-9,
                    "{:?}: gradient {k}",
                    b.surface()
                );
                // −p_c = ∇s, so ∂(−p_c)/∂ζ_k = H[:, k].
                let col = -(cp.p_c - cm.p_c) / (2.0 * eps);
                let err = (col - h.column(k)).norm();
                assert!(err < 1e-7, "{:?}: hessian column {k}, {err:e}", b.surface());
            }
        }
    }
}
