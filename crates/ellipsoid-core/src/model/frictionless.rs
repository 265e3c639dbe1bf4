//! Frictionless contact (paper §2; docs/physics.md model 1): F = N e3,
//! N = m (g + u·I⁻¹(ω × Iω) − κ) / (1 + m u·I⁻¹u) (with effects, see [`super::unilateral`]).

use nalgebra::Vector3;

use super::{ContactLaw, Response, unilateral};
use crate::body::Body;
use crate::effects::Wrench;
use crate::kinematics::Kinematics;
use crate::state::State;

/// The plane pushes only along its normal.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Frictionless;

impl ContactLaw for Frictionless {
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
        unilateral(body, gravity, kin, load, Vector3::z())
    }
}
