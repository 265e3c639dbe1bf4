//! Conserved and balanced quantities (docs/physics.md, "Invariants").
//!
//! ```text
//!   E   = ½ m |v_G|² + ½ ω_bᵀ I ω_b + m g z_G          energy
//!   p   = m v_G (horizontal)                            momentum (frictionless)
//!   L_z = e3·(R I ω_b) = ζ·(I ω_b)                      vertical angular momentum about G
//!   n   = ω·e3* = ω_b,3                                 axial spin (body of revolution)
//!   J   = L_G·(G − C) = −(I ω_b)·r_b                    Jellett's quantity (sphere, CM on axis)
//!   E + W                                               work–energy balance (W dissipated)
//! ```

use nalgebra::Vector2;
use serde::Serialize;

use crate::body::Body;
use crate::model::Kinematics;
use crate::state::{self, State};

/// The invariant quantities of one state (SI units).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Invariants {
    /// E \[J\].
    pub energy: f64,
    /// E + W \[J\].
    pub energy_plus_work: f64,
    /// m v_G, horizontal [kg·m/s].
    pub momentum: [f64; 2],
    /// L_z about G [kg·m²/s].
    pub angular_momentum_z: f64,
    /// ω·e3* [rad/s].
    pub axial_spin: f64,
    /// J = L_G·(G − C) [kg·m³/s].
    pub jellett: f64,
}

impl Invariants {
    /// Evaluates the invariants; `rolling` takes v_G from the no-slip constraint.
    pub fn of(body: &Body, gravity: f64, y: &State, rolling: bool) -> Self {
        let kin = Kinematics::new(body, y, rolling);
        Invariants::from_kinematics(body, gravity, &kin, y[state::WORK])
    }

    /// Evaluates the invariants from already computed kinematics and dissipated work W \[J\].
    pub fn from_kinematics(body: &Body, gravity: f64, kin: &Kinematics, work: f64) -> Self {
        let m = body.mass();
        let l_body = body.inertia() * kin.omega;
        let energy = 0.5 * m * kin.v_g.norm_squared()
            + 0.5 * kin.omega.dot(&l_body)
            + m * gravity * kin.contact.height;
        let p: Vector2<f64> = m * kin.v_g.xy();
        Invariants {
            energy,
            energy_plus_work: energy + work,
            momentum: [p.x, p.y],
            angular_momentum_z: kin.contact.zeta.dot(&l_body),
            axial_spin: kin.omega.z,
            jellett: -l_body.dot(&kin.contact.r),
        }
    }
}
