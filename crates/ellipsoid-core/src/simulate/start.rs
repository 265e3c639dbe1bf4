//! The state a run starts from, and the checks it must pass: a finite state, a positive
//! normal force, a consistent sliding force, no velocity given for rolling.

use crate::effects::Effect;
use crate::error::{ModelError, number};
use crate::integrate::OdeSystem;
use crate::state::{self, State};

use super::machine::Machine;
use super::outcome::Mode;
use super::phase::{after_slip_stop, phase, set_reference, slip_is_zero};
use super::scene::{ContactModel, Scene};

impl<E: Effect + Copy + 'static> Machine<'_, E> {
    /// The initial phase and state, checked.
    pub(super) fn start(&self) -> Result<(Mode, State), ModelError> {
        let scene = self.scene;
        let init = &scene.initial;
        let mut y = State::zeros();
        y[state::POS] = init.position.x;
        y[state::POS + 1] = init.position.y;
        state::set_quaternion(&mut y, &init.angles.rotation());
        let omega = init.omega_body.unwrap_or_else(|| init.angles.omega_body());
        y.fixed_rows_mut::<3>(state::OMEGA).copy_from(&omega);
        match init.velocity {
            Some(v) => {
                y[state::VEL] = v.x;
                y[state::VEL + 1] = v.y;
            }
            None if matches!(scene.contact, ContactModel::Coulomb { .. }) => {
                self.roll.project(&mut y)
            }
            None => {}
        }
        let mode = match scene.contact {
            ContactModel::Frictionless => Mode::Frictionless,
            ContactModel::Sliding { .. } => Mode::Sliding,
            ContactModel::Rolling => Mode::Rolling,
            // A contact disc does not stick while it spins (docs/physics.md, "Friction
            // over a contact disc"): the Coulomb model slides.
            ContactModel::Coulomb { .. } if scene.disc.is_some() => Mode::Sliding,
            ContactModel::Coulomb { friction } => {
                if slip_is_zero(self, &y) {
                    after_slip_stop(self, friction, &mut y)
                } else {
                    Mode::Sliding
                }
            }
        };
        if mode == Mode::Rolling {
            if let (ContactModel::Rolling, Some(v)) = (scene.contact, init.velocity) {
                return Err(ModelError::invalid(
                    "initial.velocity",
                    format!("[{}, {}]", number(v.x), number(v.y)),
                    "not allowed for the rolling model, where the velocity of G is implied by ω (v_G = −ω × r)",
                ));
            }
            self.roll.project(&mut y);
        }
        if mode == Mode::Sliding && !slip_is_zero(self, &y) {
            let s = self.slide.evaluate(&y).kin.slip.normalize();
            set_reference(&mut y, s);
        }
        let response = phase::<E>(mode).response(self, &y);
        let (sample, inv) = phase::<E>(mode).sample(self, 0.0, &y, None);
        let derived = [
            ("the normal force N", response.normal, "N"),
            ("the energy E", inv.energy, "J"),
            ("the speed of G", sample.velocity.norm(), "m/s"),
            ("the angular speed", sample.omega.norm(), "rad/s"),
            ("the height of G", sample.position.z, "m"),
            (
                "the angular momentum L_z",
                inv.angular_momentum_z,
                "kg m^2/s",
            ),
            ("Jellett's quantity", inv.jellett, "kg m^3/s"),
        ];
        if let Some((name, value, unit)) = derived.into_iter().find(|(_, v, _)| !v.is_finite()) {
            return Err(ModelError::derived(
                "initial",
                "initial state",
                format!("{name} = {} {unit}", number(value)),
                "every quantity derived from [body] and [initial] must be finite at t = 0; these inputs overflow \
                 double precision (state the problem in SI units of ordinary magnitude)",
            ));
        }
        if let Some(mu) = scene.contact.friction()
            && !(response.painleve > 0.0)
        {
            return Err(ModelError::invalid(
                "contact.friction",
                number(mu),
                format!(
                    "Painlevé inconsistency at t = 0: with this coefficient the sliding normal-force denominator \
                     1 + m u·I⁻¹(r × d) = {} is not positive, so Coulomb sliding has no consistent contact force (reduce the friction)",
                    number(response.painleve)
                ),
            ));
        }
        if !(response.normal > 0.0) {
            return Err(ModelError::derived(
                "initial",
                "initial normal force N",
                format!("{} N", number(response.normal)),
                "the plane must push on the body at t = 0 (N > 0); with these angles and rates the body would leave the plane at once",
            ));
        }
        Ok((mode, y))
    }
}

impl Scene {
    /// The contact mode and state a run of this scene starts from, after the same checks
    /// as [`super::simulate`] (N > 0 and a consistent sliding force at t = 0; optional
    /// effects do not enter the initial state).
    pub fn initial_state(&self) -> Result<(Mode, State), ModelError> {
        self.validate()?;
        Machine::new(self, (), None).start()
    }
}
