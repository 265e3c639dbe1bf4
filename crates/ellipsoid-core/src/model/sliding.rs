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
//!
//! Below a band of a few integration errors ([`SlipBand`], set by the sliding phase from
//! the tolerance) the slip's direction is set by integration error, and its exact
//! dynamics are stiff (friction turns it at a rate ∝ 1/|v_C|): there the law takes its
//! friction along a smooth blend of ŝ and s_ref ([`Sliding::friction_direction`];
//! docs/physics.md, "The slip stop, numerically").

use nalgebra::{Vector2, Vector3};

use super::contensou::ContactDisc;
use super::{ContactLaw, Response, unilateral};
use crate::body::Body;
use crate::effects::Wrench;
use crate::kinematics::Kinematics;
use crate::state::{self, State};

/// Coulomb friction while the contact point slips.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sliding {
    /// Coulomb coefficient μ (≥ 0).
    pub friction: f64,
    /// The contact disc; `None` is a point contact.
    pub disc: Option<ContactDisc>,
    /// The band of slips whose direction is blended towards s_ref (see
    /// [`Sliding::friction_direction`]); [`SlipBand::NONE`] for none.
    pub band: SlipBand,
}

/// The slips whose direction the law blends towards s_ref: |v_C| below
/// min(max(`relative`·(|v_G| + |ω||r|), `absolute`), `cap`·(|v_G| + |ω||r|)) [m/s].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SlipBand {
    /// Width relative to the speed scale |v_G| + |ω||r| (see [`Sliding::speed_scale`]).
    pub relative: f64,
    /// Absolute width [m/s].
    pub absolute: f64,
    /// The widest band, relative to the speed scale.
    pub cap: f64,
}

impl SlipBand {
    /// No band: the friction direction is ŝ for every slip.
    pub const NONE: SlipBand = SlipBand {
        relative: 0.0,
        absolute: 0.0,
        cap: 0.0,
    };

    /// The band's width at `kin`, min(max(relative·S, absolute), cap·S) with
    /// S = |v_G| + |ω||r| the speed scale [m/s] (0 for [`SlipBand::NONE`]).
    #[inline]
    pub fn width(&self, kin: &Kinematics) -> f64 {
        self.width_at(Sliding::speed_scale(kin))
    }

    /// The band's width for the speed scale `scale` [m/s].
    #[inline]
    pub fn width_at(&self, scale: f64) -> f64 {
        (self.relative * scale)
            .max(self.absolute)
            .min(self.cap * scale)
    }
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
        if Sliding::is_roundoff(kin, speed) {
            reference
        } else if kin.slip.dot(&reference) >= 0.0 {
            kin.slip / speed
        } else {
            -kin.slip / speed
        }
    }

    /// The direction the law's friction opposes: ŝ of [`Sliding::direction`] above the
    /// band of width b ([`SlipBand::width`]), and below it
    /// ```text
    ///   ŝ_f = (w ŝ + (1 − w) s_ref) / |w ŝ + (1 − w) s_ref|,  w = ρ²(3 − 2ρ),  ρ = |v_C|/b
    /// ```
    /// (docs/physics.md, "The slip stop, numerically"). w and its slope are continuous at
    /// ρ = 1, so the law stays smooth (C¹) across the band's edge, and ŝ·s_ref ≥ 0 keeps
    /// the blend away from zero. Inside the band ŝ_f no longer turns at the rate ∝ 1/|v_C|
    /// of the exact law, but follows ŝ through s_ref, which [`ContactLaw::project`]
    /// renews to ŝ_f after every step. As for [`Sliding::is_roundoff`], the 1-norm bound
    /// decides most slips without the three square roots of the speed scale.
    #[inline]
    pub fn friction_direction(&self, kin: &Kinematics, reference: Vector2<f64>) -> Vector2<f64> {
        let s = Sliding::direction(kin, reference);
        let band = &self.band;
        if band.relative == 0.0 && band.absolute == 0.0 {
            return s;
        }
        let speed = kin.slip.norm();
        if speed > 2.0 * band.relative * Sliding::speed_bound(kin) && speed > band.absolute {
            return s;
        }
        let width = band.width(kin);
        if speed >= width {
            return s;
        }
        let rho = speed / width;
        let w = rho * rho * (3.0 - 2.0 * rho);
        let blend = w * s + (1.0 - w) * reference;
        let n = blend.norm();
        if n > 0.0 { blend / n } else { s }
    }

    /// Whether slip speed `speed` = |v_C| is round-off of the body's velocities:
    /// |v_C| ≤ ε (|v_G| + |ω||r|) with ε = [`SLIP_ROUNDOFF`], or |v_C| = 0. The 1-norms
    /// bound the 2-norms from above, so a speed above 2ε (|v_G|₁ + |ω|₁|r|₁) is not
    /// (the factor 2 covers the rounding of both sides): the three square roots of
    /// [`Sliding::speed_scale`] are taken only near the bound.
    #[inline]
    fn is_roundoff(kin: &Kinematics, speed: f64) -> bool {
        if speed > 2.0 * SLIP_ROUNDOFF * Sliding::speed_bound(kin) {
            return false;
        }
        speed <= SLIP_ROUNDOFF * Sliding::speed_scale(kin) || speed == 0.0
    }

    /// An upper bound of the speed scale without square roots, |v_G|₁ + |ω|₁|r|₁ [m/s]:
    /// the 1-norms bound the 2-norms of [`Sliding::speed_scale`] from above.
    #[inline]
    fn speed_bound(kin: &Kinematics) -> f64 {
        let l1 = |v: &Vector3<f64>| v.x.abs() + v.y.abs() + v.z.abs();
        l1(&kin.v_g) + l1(&kin.omega) * l1(&kin.contact.r)
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

    /// The generalised slip w = (v_C, R ω_n) of a contact disc [m/s] (ω_n = ω·e3; R = 0
    /// for a point contact): the law is smooth while w ≠ 0.
    #[inline]
    pub fn generalised_slip(&self, kin: &Kinematics) -> Vector3<f64> {
        let spin = self
            .disc
            .map_or(0.0, |disc| disc.radius * kin.omega.dot(&kin.contact.zeta));
        Vector3::new(kin.slip.x, kin.slip.y, spin)
    }

    /// The speed whose vanishing stops the sliding phase: |v_C| for a point contact,
    /// |w| = √(|v_C|² + (R ω_n)²) for a contact disc (see [`Sliding::generalised_slip`])
    /// [m/s].
    #[inline]
    pub fn stop_speed(&self, kin: &Kinematics) -> f64 {
        match self.disc {
            None => kin.slip.norm(),
            Some(_) => self.generalised_slip(kin).norm(),
        }
    }
}

impl ContactLaw for Sliding {
    const ROLLING: bool = false;

    #[inline(always)]
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
        let s = self.friction_direction(kin, state::slip_ref(y));
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
    #[inline(always)]
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
        let s = self.friction_direction(&kin, state::slip_ref(y));
        y[state::SLIP_REF] = s.x;
        y[state::SLIP_REF + 1] = s.y;
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::Vector3;

    use super::*;
    use crate::body::{Body, uniform_inertia};

    /// The short cut of [`Sliding::is_roundoff`] decides as the exact test does, on slips
    /// from far below to far above the round-off bound and at it, in every direction.
    #[test]
    fn roundoff_test_matches_the_exact_one() {
        let ax = Vector3::new(0.03, 0.02, 0.01);
        let body = Body::new(ax, 1.0, uniform_inertia(ax, 1.0), Vector3::zeros()).unwrap();
        let mut y = State::zeros();
        y[state::QUAT] = 1.0;
        let mut kin = Kinematics::new(&body, &y, false);
        let (mut below, mut above) = (0, 0);
        for k in 0..20_000u32 {
            // a fixed pseudo-random sequence (Weyl), so the test is reproducible
            let u =
                |j: u32| ((f64::from(k) * 0.754_877_666 + f64::from(j) * 0.569_840_29) % 1.0) - 0.5;
            kin.v_g = Vector3::new(u(1), u(2), u(3)) * 10f64.powf(4.0 * u(4));
            kin.omega = Vector3::new(u(5), u(6), u(7)) * 10f64.powf(4.0 * u(8));
            kin.contact.r = Vector3::new(u(9), u(10), u(11)) * 0.05;
            let scale = Sliding::speed_scale(&kin);
            // speeds within a factor 3 of the bound, and exactly at it
            let speed = if k % 7 == 0 {
                SLIP_ROUNDOFF * scale
            } else {
                SLIP_ROUNDOFF * scale * 3f64.powf(2.0 * u(12))
            };
            let exact = speed <= SLIP_ROUNDOFF * scale || speed == 0.0;
            assert_eq!(Sliding::is_roundoff(&kin, speed), exact, "{kin:?} {speed}");
            if exact { below += 1 } else { above += 1 }
        }
        assert!(below > 5_000 && above > 5_000, "{below} {above}");
        kin.v_g = Vector3::zeros();
        kin.omega = Vector3::zeros();
        assert!(Sliding::is_roundoff(&kin, 0.0));
        assert!(!Sliding::is_roundoff(&kin, 1e-300));
    }
}
