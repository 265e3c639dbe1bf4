//! The state a run starts from, and the checks it must pass: a finite state, a positive
//! normal force (or flight: a start above the plane, or one the plane cannot hold with
//! `on_lift_off = "fly"`), a consistent sliding force, no velocity given for rolling on
//! the plane.

use crate::effects::Effect;
use crate::error::{Brackets, Digits, ModelError, Value, number};
use crate::kinematics::Kinematics;
use crate::state::{self, State};

use super::context::{ContactSet, Context};
use super::outcome::{EventKind, EventRecord, Mode, Status};
use super::phase::phase;
use super::scene::{ContactModel, LiftOff, Scene};
use super::transition::{Arrival, Placed, flight_is_consistent, on_plane, pushes, to_flight};

/// Where a run starts.
pub(super) struct Start {
    /// The initial phase.
    pub(super) mode: Mode,
    /// The initial state, checked.
    pub(super) y: State,
    /// The events at t = 0.
    pub(super) events: Vec<EventRecord>,
    /// Why the run ends at once, if it does (slip and spin already stopped).
    pub(super) stopped: Option<Status>,
    /// The initial contact state: the lowest surface in contact.
    pub(super) contacts: ContactSet,
}

impl<E: Effect + Copy + 'static> Context<'_, E> {
    /// The initial phase and state, checked: a start above the plane flies; one on it
    /// enters the phase `transition::on_plane` gives, and flies where the plane cannot
    /// hold it (N ≤ 0) with `on_lift_off = "fly"`.
    pub(super) fn start(&self) -> Result<Start, ModelError> {
        let scene = self.scene;
        let init = &scene.initial;
        let mut y = State::zeros();
        y[state::POS] = init.position.x;
        y[state::POS + 1] = init.position.y;
        state::set_quaternion(&mut y, &init.angles.rotation());
        let omega = init.omega_body.unwrap_or_else(|| init.angles.omega_body());
        y.fixed_rows_mut::<3>(state::OMEGA).copy_from(&omega);
        let flying = init.height > 0.0;
        // G starts at rest unless `velocity` is given (docs/scenarios.md): with friction
        // the contact then slides if ω makes it slip; rolling projects v_G below.
        if let Some(v) = init.velocity {
            y[state::VEL] = v.x;
            y[state::VEL + 1] = v.y;
        }
        // The surface that touches (or is nearest to) the plane: the lowest.
        let lowest = Kinematics::flying(&scene.body, &y).contact;
        let contacts = &ContactSet::new(lowest.surface);
        let go = |mode, y| Start {
            mode,
            y,
            events: Vec::new(),
            stopped: None,
            contacts: *contacts,
        };
        if flying {
            y[state::HEIGHT] = lowest.height + init.height;
            y[state::VEL_Z] = init.velocity_z.unwrap_or(0.0);
            self.check_finite(contacts, Mode::Flight, &y)?;
            return Ok(go(Mode::Flight, y));
        }
        if let (ContactModel::Rolling, Some(v)) = (scene.contact, init.velocity) {
            return Err(ModelError::invalid(
                "initial.velocity",
                Value::Numbers {
                    values: vec![v.x, v.y],
                    digits: Digits::Short,
                    brackets: Brackets::Square,
                },
                "not allowed for the rolling model, where the velocity of G is implied by ω (v_G = −ω × r)",
            ));
        }
        let (mode, stopped) = match on_plane(self, contacts, Arrival::Start, &mut y) {
            Placed::In(mode) => (mode, None),
            Placed::SlipStopped => (Mode::Sliding, Some(Status::SlipStopped)),
        };
        let response = phase::<E>(mode).response(self, contacts, &y);
        self.check_finite(contacts, mode, &y)?;
        let coefficient = match scene.contact {
            ContactModel::Viscous { viscous_friction } => {
                Some(("contact.viscous_friction", viscous_friction))
            }
            model => model.friction().map(|mu| ("contact.friction", mu)),
        };
        if let Some((key, mu)) = coefficient
            && !(response.painleve > 0.0)
        {
            return Err(ModelError::invalid(
                key,
                mu,
                format!(
                    "Painlevé inconsistency at t = 0: with this coefficient the sliding normal-force denominator \
                     1 + m u·I⁻¹(r × d) = {} is not positive, so sliding has no consistent contact force (reduce the friction)",
                    number(response.painleve)
                ),
            ));
        }
        // A slip stop needs the plane to push (N > 0); else the body leaves the plane as
        // below (docs/physics.md, "The hybrid machine").
        if let Some(status) = stopped.filter(|_| pushes(self, contacts, mode, &y)) {
            return Ok(Start {
                mode,
                y,
                events: vec![EventRecord {
                    kind: EventKind::SlipStop,
                    t: 0.0,
                }],
                stopped: Some(status),
                contacts: *contacts,
            });
        }
        if pushes(self, contacts, mode, &y) {
            return Ok(go(mode, y));
        }
        if scene.landing.lift_off == LiftOff::Stop {
            return Err(ModelError::derived(
                "initial",
                "initial normal force N",
                Value::Number(response.normal, "N"),
                "the plane must push on the body at t = 0 (N > 0) when contact.on_lift_off = \"stop\"; with these angles and rates the body would leave the plane at once",
            ));
        }
        if let Err(Status::InconsistentContact {
            gap_acceleration, ..
        }) = flight_is_consistent(self, contacts, mode, &y)
        {
            return Err(ModelError::derived(
                "initial",
                "initial normal force N",
                Value::Number(response.normal, "N"),
                format!(
                    "the plane would have to pull (N < 0) while without a contact force the body would fall into \
                     the plane (gap acceleration {} m/s²): neither contact nor flight is consistent at t = 0 \
                     (the rolling model's analogue of Painlevé's paradox; use model = \"coulomb\" with a finite friction)",
                    number(gap_acceleration)
                ),
            ));
        }
        // The plane cannot hold the body (N ≤ 0: e.g. no gravity): it flies at once.
        to_flight(self, contacts, mode, &mut y);
        Ok(go(Mode::Flight, y))
    }

    /// Rejects an initial state whose derived quantities overflow, then one whose spin
    /// double precision cannot integrate (`Scene::validate_spin`).
    fn check_finite(&self, contacts: &ContactSet, mode: Mode, y: &State) -> Result<(), ModelError> {
        let (sample, inv) = phase::<E>(mode).sample(self, contacts, 0.0, y, None);
        let derived = [
            ("the normal force N", sample.normal_force, "N"),
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
                Value::Named { name, value, unit },
                "every quantity derived from [body] and [initial] must be finite at t = 0; these inputs overflow \
                 double precision (state the problem in SI units of ordinary magnitude)",
            ));
        }
        self.scene.validate_spin()
    }
}

impl Scene {
    /// The contact mode and state a run of this scene starts from, after the same checks
    /// as [`super::simulate`] (N > 0 and a consistent sliding force at t = 0; optional
    /// effects do not enter the initial state).
    pub fn initial_state(&self) -> Result<(Mode, State), ModelError> {
        self.validate()?;
        let start = Context::new(self, (), None).start()?;
        Ok((start.mode, start.y))
    }
}
