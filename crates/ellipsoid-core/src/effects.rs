//! Optional effects beyond gravity and the contact law, composed at compile time.
//!
//! Each effect contributes a [`Wrench`]: a world-frame force on G, a body-frame torque
//! about G, and a body-frame torque *per unit normal force* (for contact-borne
//! resistance, which scales with N). A scene's effects are a tuple of [`Effect`]s; the
//! empty tuple `()` contributes nothing and compiles to nothing, so an effect a scene
//! does not name costs nothing at run time. The work they dissipate is accounted in the
//! model's power balance (see `model`).

use nalgebra::Vector3;
use serde::Serialize;

use crate::body::Body;
use crate::model::Kinematics;

/// Generalised load of the optional effects.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Wrench {
    /// Force on G, world frame \[N\].
    pub force: Vector3<f64>,
    /// Torque about G, body frame [N·m].
    pub torque: Vector3<f64>,
    /// Torque about G per newton of normal force, body frame \[m\].
    pub torque_per_normal: Vector3<f64>,
}

impl Wrench {
    /// No load.
    pub const ZERO: Wrench = Wrench {
        force: Vector3::new(0.0, 0.0, 0.0),
        torque: Vector3::new(0.0, 0.0, 0.0),
        torque_per_normal: Vector3::new(0.0, 0.0, 0.0),
    };
}

impl std::ops::Add for Wrench {
    type Output = Wrench;
    fn add(self, o: Wrench) -> Wrench {
        Wrench {
            force: self.force + o.force,
            torque: self.torque + o.torque,
            torque_per_normal: self.torque_per_normal + o.torque_per_normal,
        }
    }
}

/// One optional physical effect.
pub trait Effect {
    /// The load this effect applies in the given kinematic state.
    fn wrench(&self, body: &Body, kin: &Kinematics) -> Wrench;
}

impl Effect for () {
    #[inline(always)]
    fn wrench(&self, _: &Body, _: &Kinematics) -> Wrench {
        Wrench::ZERO
    }
}

impl<A: Effect, B: Effect> Effect for (A, B) {
    #[inline(always)]
    fn wrench(&self, body: &Body, kin: &Kinematics) -> Wrench {
        self.0.wrench(body, kin) + self.1.wrench(body, kin)
    }
}

/// Viscous air drag: force −k v_G \[N\] and torque −k_ω ω [N·m].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct AirDrag {
    /// k [kg/s].
    pub linear: f64,
    /// k_ω [kg·m²/s].
    pub angular: f64,
}

impl Effect for AirDrag {
    #[inline]
    fn wrench(&self, _: &Body, kin: &Kinematics) -> Wrench {
        Wrench {
            force: -self.linear * kin.v_g,
            torque: -self.angular * kin.omega,
            torque_per_normal: Vector3::zeros(),
        }
    }
}

/// Rolling resistance: torque −c_r N ω_h/|ω_h|, ω_h the horizontal part of ω,
/// regularised as ω_h / √(|ω_h|² + ε²) so that it vanishes smoothly at ω_h = 0.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct RollingResistance {
    /// c_r \[m\].
    pub coefficient: f64,
    /// ε [rad/s].
    pub regularisation: f64,
}

impl Effect for RollingResistance {
    #[inline]
    fn wrench(&self, _: &Body, kin: &Kinematics) -> Wrench {
        let zeta = kin.contact.zeta;
        let omega_h = kin.omega - zeta * kin.omega.dot(&zeta);
        let scale = (omega_h.norm_squared() + self.regularisation * self.regularisation).sqrt();
        Wrench {
            force: Vector3::zeros(),
            torque: Vector3::zeros(),
            torque_per_normal: -self.coefficient * omega_h / scale,
        }
    }
}

/// Spin (drilling) friction: torque −c_s N sign(ω_z) e3, with sign regularised as
/// ω_z / √(ω_z² + ε²).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SpinFriction {
    /// c_s \[m\].
    pub coefficient: f64,
    /// ε [rad/s].
    pub regularisation: f64,
}

impl Effect for SpinFriction {
    #[inline]
    fn wrench(&self, _: &Body, kin: &Kinematics) -> Wrench {
        let zeta = kin.contact.zeta;
        let wz = kin.omega.dot(&zeta);
        let sign = wz / (wz * wz + self.regularisation * self.regularisation).sqrt();
        Wrench {
            force: Vector3::zeros(),
            torque: Vector3::zeros(),
            torque_per_normal: -self.coefficient * sign * zeta,
        }
    }
}
