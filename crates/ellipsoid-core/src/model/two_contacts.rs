//! Two surfaces of the body in contact at once, both sliding (docs/physics.md, "Contact
//! spheres", "Two contacts"): Coulomb friction at each, F_i = N_i d_i with
//! d_i = e3 − μ ŝ_i (or Coulomb–Contensou's over a contact disc, with its drilling torque
//! per unit N_i). The body's geometry (`kin`) is that of the first surface, so z_G = h_1(ζ);
//! the second surface's gap h_1(ζ) − h_2(ζ) stays zero. With a_i = I⁻¹ℓ_i,
//! ℓ_i = r_i × d_i + τ_N,i, b = I⁻¹(τ − ω × Iω), the two acceleration constraints
//! ```text
//!   m z̈_G = N_1 + N_2 + f_z − m g,   z̈_G = −u_1·ω̇ − κ_1        (contact 1)
//!   (u_1 − u_2)·ω̇ = κ_2 − κ_1                                  (gap 2 stays zero)
//! ```
//! with I ω̇ = N_1 ℓ_1 + N_2 ℓ_2 + τ − ω × Iω, give the 2×2 system
//! ```text
//!   N_1 (1 + m u_1·a_1)     + N_2 (1 + m u_1·a_2)     = m g − f_z − m u_1·b − m κ_1
//!   N_1 (u_1 − u_2)·a_1     + N_2 (u_1 − u_2)·a_2     = κ_2 − κ_1 − (u_1 − u_2)·b
//! ```
//! Its determinant divided by the frictionless one (d_i = e3) is the law's Painlevé
//! denominator: 1 without friction, and ≤ 0 where sliding at both contacts has no
//! consistent normal forces.

use nalgebra::{Matrix2, UnitQuaternion, Vector2, Vector3};

use super::contensou::ContactDisc;
use super::{ContactLaw, Kinematics, Response};
use crate::body::{Body, Surface};
use crate::effects::Wrench;
use crate::geometry::{self, Contact};
use crate::state::{self, State};

/// Sliding at the body's surface in contact and at a second one, `other`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TwoContacts {
    /// Coulomb coefficient μ (≥ 0; 0 is frictionless).
    pub friction: f64,
    /// The contact disc at each contact; `None` is a point contact.
    pub disc: Option<ContactDisc>,
    /// The second surface in contact.
    pub other: Surface,
}

/// One contact's friction: the force direction d (world, d·e3 = 1) and the torque per
/// unit N it adds (body axes).
struct Friction {
    d: Vector3<f64>,
    torque: Vector3<f64>,
}

impl TwoContacts {
    /// The second contact's geometry and horizontal slip v_C2 = v_G + (ω × r_2)_h.
    #[inline]
    pub fn second(&self, body: &Body, kin: &Kinematics) -> (Contact, Vector2<f64>) {
        let c = Contact::of(body, self.other, kin.contact.zeta, kin.omega);
        let slip = kin.v_g.xy() + (kin.rot * kin.omega.cross(&c.r)).xy();
        (c, slip)
    }

    /// The friction of a contact slipping at `slip` with spin ω_n = ω·ζ: Coulomb's
    /// d = e3 − μ v̂ (no friction where the slip is exactly zero), or the disc's.
    #[inline]
    fn friction(&self, slip: Vector2<f64>, spin: f64, zeta: Vector3<f64>) -> Friction {
        let mu = self.friction;
        let (f, m) = match self.disc {
            Some(disc) => disc
                .law
                .traction(slip, spin, disc.radius)
                .unwrap_or((Vector2::zeros(), 0.0)),
            None => {
                let s = slip.norm();
                (if s > 0.0 { -slip / s } else { Vector2::zeros() }, 0.0)
            }
        };
        Friction {
            d: Vector3::new(mu * f.x, mu * f.y, 1.0),
            torque: (mu * m) * zeta,
        }
    }
}

impl ContactLaw for TwoContacts {
    const ROLLING: bool = false;

    fn respond(
        &self,
        body: &Body,
        gravity: f64,
        kin: &Kinematics,
        _y: &State,
        load: &Wrench,
    ) -> Response {
        let m = body.mass();
        let i_inv = body.inertia_inv();
        let (c1, slip1) = (&kin.contact, kin.slip);
        let (c2, slip2) = self.second(body, kin);
        let spin = kin.omega.dot(&c1.zeta);
        let (f1, f2) = (
            self.friction(slip1, spin, c1.zeta),
            self.friction(slip2, spin, c1.zeta),
        );
        let free = load.torque - kin.omega.cross(&(body.inertia() * kin.omega));
        let b = i_inv * free;
        let du = c1.u - c2.u;
        let lever = |c: &Contact, d: Vector3<f64>, t: Vector3<f64>| {
            i_inv * (c.r.cross(&kin.rot.tr_mul(&d)) + t + load.torque_per_normal)
        };
        let matrix = |a1: Vector3<f64>, a2: Vector3<f64>| {
            Matrix2::new(
                1.0 + m * c1.u.dot(&a1),
                1.0 + m * c1.u.dot(&a2),
                du.dot(&a1),
                du.dot(&a2),
            )
        };
        let (a1, a2) = (lever(c1, f1.d, f1.torque), lever(&c2, f2.d, f2.torque));
        let system = matrix(a1, a2);
        let rhs = Vector2::new(
            m * gravity - load.force.z - m * c1.u.dot(&b) - m * c1.kappa,
            c2.kappa - c1.kappa - du.dot(&b),
        );
        let det = system.determinant();
        let frictionless = matrix(
            lever(c1, Vector3::z(), Vector3::zeros()),
            lever(&c2, Vector3::z(), Vector3::zeros()),
        )
        .determinant();
        let n = Vector2::new(
            rhs.x * system.m22 - system.m12 * rhs.y,
            system.m11 * rhs.y - system.m21 * rhs.x,
        ) / det;
        let (n1, n2) = (n.x, n.y);
        let per_normal = load.torque_per_normal;
        let power = -n1 * (f1.d.xy().dot(&slip1) + (f1.torque + per_normal).dot(&kin.omega))
            - n2 * (f2.d.xy().dot(&slip2) + (f2.torque + per_normal).dot(&kin.omega));
        Response {
            force: n1 * f1.d + n2 * f2.d,
            normal: n1 + n2,
            omega_dot: b + n1 * a1 + n2 * a2,
            painleve: det / frictionless,
            second_normal: n2,
            contact_power: Some(power),
        }
    }

    /// Restores the second contact on an accepted state: the attitude turned by the
    /// smallest rotation δφ (body axes) that makes the gap g = h_1(ζ) − h_2(ζ) zero
    /// (∇_ζ g = r_2 − r_1, and ζ turns by ζ × δφ), then ω corrected along the same axis so
    /// that ġ = (r_2 − r_1)·(ζ × ω) is zero (one Newton step each: the drift is of the
    /// size of the integration error).
    fn project(&self, body: &Body, y: &mut State) {
        let rot = state::rotation(y);
        let zeta = Vector3::new(rot[(2, 0)], rot[(2, 1)], rot[(2, 2)]);
        let surface = body.surface();
        let gap = geometry::height(body, surface, zeta) - geometry::height(body, self.other, zeta);
        let omega = state::omega(y);
        let dr = Contact::of(body, self.other, zeta, omega).r
            - Contact::of(body, surface, zeta, omega).r;
        // g changes by (r_2 − r_1)·(ζ × δφ) = δφ·((r_2 − r_1) × ζ) = δφ·axis.
        let axis = dr.cross(&zeta);
        let n2 = axis.norm_squared();
        if !(n2 > 0.0) {
            return;
        }
        let turn = -gap / n2 * axis;
        let q = UnitQuaternion::new_normalize(state::quaternion(y))
            * UnitQuaternion::from_scaled_axis(turn);
        state::set_quaternion(y, &q);
        // ġ = (r_2 − r_1)·(ζ × ω) = ω·axis.
        let correction = omega.dot(&axis) / n2 * axis;
        for i in 0..3 {
            y[state::OMEGA + i] -= correction[i];
        }
    }
}
