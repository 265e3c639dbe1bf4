//! Viscous sliding friction (docs/physics.md, "Viscous sliding"): the tangential force
//! is proportional to the normal force and to the slip velocity of the material contact
//! point,
//! ```text
//!   F = N (e3 − μ_v v_C),   N = m (g + u·I⁻¹(ω × Iω) − κ) / (1 + m u·I⁻¹(r × d_b))
//! ```
//! with μ_v [s/m] and d = e3 − μ_v v_C: the sliding model's unilateral solve
//! ([`super::unilateral`]) with a force direction that is smooth (linear) in the slip,
//! so the law has no slip stop and can be linearised about a motion without slip
//! (Moffatt & Shimomura 2002; Bou-Rabee, Marsden & Romero 2004).

use nalgebra::Vector3;

use super::{ContactLaw, Response, unilateral};
use crate::body::Body;
use crate::effects::Wrench;
use crate::kinematics::Kinematics;
use crate::state::State;

/// Viscous friction F_t = −μ_v N v_C.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Viscous {
    /// μ_v ≥ 0 [s/m].
    pub coefficient: f64,
}

impl ContactLaw for Viscous {
    const ROLLING: bool = false;

    #[inline(always)]
    fn respond(
        &self,
        body: &Body,
        gravity: f64,
        kin: &Kinematics,
        _y: &State,
        load: &Wrench,
    ) -> Response {
        let mu = self.coefficient;
        let d = Vector3::new(-mu * kin.slip.x, -mu * kin.slip.y, 1.0);
        unilateral(body, gravity, kin, load, d)
    }
}
