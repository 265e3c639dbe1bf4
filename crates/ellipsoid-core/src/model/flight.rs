//! Flight (docs/physics.md, "Flight"): off the plane no contact force acts. G moves
//! under gravity and the effects' force, the body turns under the effects' torque
//! (Euler's equations; torque-free without effects):
//! ```text
//!   m a_G = f − m g e3,   I ω̇_b = τ − ω_b × I ω_b,   ż_G = v_Gz
//! ```
//! Effects that act through the normal force (rolling resistance, spin friction) vanish
//! with it. The gap g = z_G − h(ζ) (`Kinematics::flying`) is the touchdown watch.

use super::{ContactLaw, Response};
use crate::body::Body;
use crate::effects::Wrench;
use crate::kinematics::Kinematics;
use crate::state::State;
use nalgebra::Vector3;

/// No contact: the body flies.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Flight;

impl ContactLaw for Flight {
    const ROLLING: bool = false;
    const FLIGHT: bool = true;

    #[inline]
    fn respond(
        &self,
        body: &Body,
        _gravity: f64,
        kin: &Kinematics,
        _y: &State,
        load: &Wrench,
    ) -> Response {
        let free = load.torque - kin.omega.cross(&(body.inertia() * kin.omega));
        Response {
            force: Vector3::zeros(),
            normal: 0.0,
            omega_dot: body.inertia_inv() * free,
            painleve: f64::INFINITY,
            other_normals: [0.0; super::MOST_CONTACTS - 1],
            contact_power: None,
        }
    }
}
