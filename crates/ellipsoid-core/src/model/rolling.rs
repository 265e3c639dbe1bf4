//! Rolling without slipping (paper §4, corrected; docs/physics.md model 3). v_C = 0, so
//! v_G = −ω × r and the contact force F (body frame F_b) solves the 3×3 system
//! ```text
//!   (I₃ − m [r]× I⁻¹ ([r]× + τ_N ζᵀ)) F_b = m g ζ − f_b + m [r]× I⁻¹ T − m ω × ṙ_tot
//! ```
//! with T = τ − ω × Iω and ṙ_tot = ω × r + ṙ_surface (the contact point moving over the
//! body: omitting ṙ_surface is the classic error that breaks energy conservation).
//! Without effects the matrix is I₃ + m [r]×ᵀ I⁻¹ [r]×, symmetric positive definite.
//! The paper's own §4 substitutes this nonholonomic constraint into the Lagrangian and
//! is wrong (docs/paper-notes.md); this is the Newton–Euler form.

use nalgebra::{Matrix3, Vector3};

use super::{ContactLaw, Response};
use crate::body::Body;
use crate::effects::Wrench;
use crate::kinematics::Kinematics;
use crate::state::{self, State};

/// No slip at the contact point.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Rolling;

impl Rolling {
    /// Brings a residual slip v_C (what is left when a slip stop is taken, below the
    /// integration error or a fixed step's resolution) to zero by a frictional impulse
    /// P at C, and books the kinetic energy it removes as dissipated work:
    /// ```text
    ///   K P = −v_C,   K = I₃/m − [r]× I⁻¹ [r]×   (body axes, SPD)
    ///   v_G += P/m,   ω += I⁻¹ (r × P),   W += −½ v_C·P
    /// ```
    /// Angular momentum about C and E + W are unchanged, so the rolling motion that
    /// follows is the one the exact stop would give (a billiard ball rolls at 5 v0/7).
    pub fn stick(body: &Body, y: &mut State) {
        let kin = Kinematics::new(body, y, false);
        let v_c = kin.rot.tr_mul(&Vector3::new(kin.slip.x, kin.slip.y, 0.0));
        let r_cross = kin.contact.r.cross_matrix();
        let k = Matrix3::identity() / body.mass() - r_cross * body.inertia_inv() * r_cross;
        let Some(impulse) = k.cholesky().map(|c| -c.solve(&v_c)) else {
            return;
        };
        let dv = kin.rot * impulse / body.mass();
        let domega = body.inertia_inv() * kin.contact.r.cross(&impulse);
        y[state::VEL] += dv.x;
        y[state::VEL + 1] += dv.y;
        for i in 0..3 {
            y[state::OMEGA + i] += domega[i];
        }
        y[state::WORK] -= 0.5 * v_c.dot(&impulse);
    }

    /// Friction-cone margin μ N − |F_h| \[N\]: rolling needs it ≥ 0.
    pub fn cone_margin(response: &Response, friction: f64) -> f64 {
        friction * response.normal - response.force.xy().norm()
    }
}

impl ContactLaw for Rolling {
    const ROLLING: bool = true;

    #[inline(always)]
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
        let c = &kin.contact;
        let w = kin.omega;
        let r_cross = c.r.cross_matrix();
        let free = load.torque - w.cross(&(body.inertia() * w));
        let r_dot = w.cross(&c.r) + c.r_dot_surface;
        let matrix = Matrix3::identity()
            - m * r_cross * i_inv * (r_cross + load.torque_per_normal * c.zeta.transpose());
        let rhs = m * gravity * c.zeta - kin.rot.tr_mul(&load.force)
            + m * (r_cross * (i_inv * free))
            - m * w.cross(&r_dot);
        // The matrix is I₃ plus a positive semi-definite part (plus a small τ_N term):
        // always invertible for physical loads; a singular one would mean a torque per
        // newton of normal force larger than the lever arm, which effects cannot produce.
        let f_b = matrix
            .try_inverse()
            .map_or(Vector3::from_element(f64::NAN), |inv| inv * rhs);
        let normal = f_b.dot(&c.zeta);
        Response {
            force: kin.rot * f_b,
            normal,
            omega_dot: i_inv * (c.r.cross(&f_b) + normal * load.torque_per_normal + free),
            painleve: f64::INFINITY,
            other_normals: [0.0; super::MOST_CONTACTS - 1],
            contact_power: None,
        }
    }

    /// v_G ← −(ω × r)_h: the stored horizontal velocity follows the constraint exactly.
    fn project(&self, body: &Body, y: &mut State) {
        let kin = Kinematics::new(body, y, true);
        y[state::VEL] = kin.v_g.x;
        y[state::VEL + 1] = kin.v_g.y;
    }
}
