//! Coulomb sliding friction (paper §3; docs/physics.md model 2): F = N d with
//! d = e3 − μ ŝ, ŝ the unit slip direction of the material contact point,
//! N = m (g + u·I⁻¹(ω × Iω) − κ) / (1 + m u·I⁻¹(r × d_b)).
//!
//! ŝ = v_C/|v_C| is discontinuous where the slip stops. So that the stop can be located
//! accurately on the dense output, the state carries a reference direction s_ref (the
//! slip direction at the start of the current step, refreshed by [`ContactLaw::project`]),
//! and the law uses ŝ = sign(v_C·s_ref) v_C/|v_C|: the friction direction continues
//! smoothly through v_C = 0 instead of flipping, and the event function
//! g = v_C·s_ref (see [`Sliding::slip_along_reference`]) changes sign cleanly at the stop.
//! Beyond that point the continued motion is unphysical and never reported: the stop is
//! a terminal event. With |v_C| at round-off level (the instant sliding starts from
//! rolling), ŝ = s_ref.

use nalgebra::{Vector2, Vector3};

use super::contensou::ContactDisc;
use super::{ContactLaw, Kinematics, Response, unilateral};
use crate::body::Body;
use crate::effects::Wrench;
use crate::state::{self, State};

/// Coulomb friction while the contact point slips.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sliding {
    /// Coulomb coefficient μ (≥ 0).
    pub friction: f64,
    /// The contact disc; `None` is a point contact.
    pub disc: Option<ContactDisc>,
}

/// Relative size below which a slip speed is round-off of the body's velocities.
const SLIP_ROUNDOFF: f64 = 1e-13;

/// Smallest relative slip speed at which a grazing slip counts as stopped (see
/// [`Sliding::slip_above_floor`]); it moves a clean stop time by about
/// 1e-10 (|v_G| + |ω||r|)/|v̇_C|, e.g. 3e-11 s for a billiard ball at 2 m/s.
pub const SLIP_FLOOR: f64 = 1e-10;

impl Sliding {
    /// The unit slip direction ŝ the law uses (see the module docs).
    #[inline]
    pub fn direction(kin: &Kinematics, reference: Vector2<f64>) -> Vector2<f64> {
        let speed = kin.slip.norm();
        if speed <= SLIP_ROUNDOFF * Sliding::speed_scale(kin) || speed == 0.0 {
            reference
        } else if kin.slip.dot(&reference) >= 0.0 {
            kin.slip / speed
        } else {
            -kin.slip / speed
        }
    }

    /// Event function for the slip stop: g = v_C·s_ref [m/s], positive while sliding.
    #[inline]
    pub fn slip_along_reference(kin: &Kinematics, y: &State) -> f64 {
        kin.slip.dot(&state::slip_ref(y))
    }

    /// The speed of the body's points near the contact, |v_G| + |ω||r| [m/s]: the
    /// scale of the slip velocity's round-off and integration error.
    #[inline]
    pub fn speed_scale(kin: &Kinematics) -> f64 {
        kin.v_g.norm() + kin.omega.norm() * kin.contact.r.norm()
    }

    /// Second event function for the slip stop: g = |v_C| − max(ε (|v_G| + |ω||r|), v_min)
    /// [m/s], with a relative floor ε ≥ [`SLIP_FLOOR`] and an absolute floor v_min. When
    /// the slip grazes zero (friction barely able to stop it, e.g. just after leaving
    /// rolling at the cone's edge) its direction turns at a rate ∝ 1/|v_C|, the steps
    /// collapse, and v_C·s_ref may never change sign; the slip is then stopped at this
    /// floor, below the integration error (a fixed-step method cannot resolve a slip
    /// smaller than what friction removes in one step: v_min = μ g h).
    #[inline]
    pub fn slip_above_floor(kin: &Kinematics, floor: f64, v_min: f64) -> f64 {
        kin.slip.norm() - (floor * Sliding::speed_scale(kin)).max(v_min)
    }

    /// The speed whose vanishing stops the sliding phase: |v_C| for a point contact,
    /// √(|v_C|² + (R ω_n)²) for a contact disc (the law is smooth while either is
    /// nonzero) [m/s].
    #[inline]
    pub fn stop_speed(&self, kin: &Kinematics) -> f64 {
        match self.disc {
            None => kin.slip.norm(),
            Some(disc) => kin
                .slip
                .norm()
                .hypot(disc.radius * kin.omega.dot(&kin.contact.zeta)),
        }
    }
}

impl ContactLaw for Sliding {
    const ROLLING: bool = false;

    #[inline]
    fn respond(
        &self,
        body: &Body,
        gravity: f64,
        kin: &Kinematics,
        y: &State,
        load: &Wrench,
    ) -> Response {
        if self.disc.is_some() {
            return self.respond_loaded(body, gravity, kin, y, *load).1;
        }
        let s = Sliding::direction(kin, state::slip_ref(y));
        unilateral(
            body,
            gravity,
            kin,
            load,
            Vector3::new(-self.friction * s.x, -self.friction * s.y, 1.0),
        )
    }

    /// With a contact disc: F = N(e3 − μ f v̂) and the drilling torque per unit N,
    /// −μ R g sgn(ω_n) ζ, added to the load. At the set-valued point v_C = 0, ω_n = 0 (where
    /// the run stops) the force is taken along −s_ref with no torque.
    #[inline]
    fn respond_loaded(
        &self,
        body: &Body,
        gravity: f64,
        kin: &Kinematics,
        y: &State,
        load: Wrench,
    ) -> (Wrench, Response) {
        let Some(disc) = self.disc else {
            let response = self.respond(body, gravity, kin, y, &load);
            return (load, response);
        };
        let zeta = kin.contact.zeta;
        let (force, torque) = disc
            .law
            .traction(kin.slip, kin.omega.dot(&zeta), disc.radius)
            .unwrap_or_else(|| (-state::slip_ref(y), 0.0));
        let mu = self.friction;
        let load = Wrench {
            torque_per_normal: load.torque_per_normal + (mu * torque) * zeta,
            ..load
        };
        let d = Vector3::new(mu * force.x, mu * force.y, 1.0);
        (load, unilateral(body, gravity, kin, &load, d))
    }

    /// s_ref ← ŝ, keeping its orientation relative to the previous s_ref, so the sign of
    /// g = v_C·s_ref is unchanged by the refresh.
    fn project(&self, body: &Body, y: &mut State) {
        let kin = Kinematics::new(body, y, false);
        let s = Sliding::direction(&kin, state::slip_ref(y));
        y[state::SLIP_REF] = s.x;
        y[state::SLIP_REF + 1] = s.y;
    }
}
