//! The frictionless phase (docs/physics.md, model 1): F = N e3; it ends when N reaches 0.

use crate::effects::Effect;
use crate::model::{Evaluation, Frictionless, System};
use crate::state::State;

use super::{Next, Phase, Watch};
use crate::simulate::machine::Machine;
use crate::simulate::outcome::{EventKind, EventRecord, Mode, Status};

pub(in crate::simulate) struct FrictionlessPhase;

impl Phase for FrictionlessPhase {
    const MODE: Mode = Mode::Frictionless;
    type Law = Frictionless;

    fn system<'m, E: Effect>(m: &'m Machine<'_, E>) -> &'m System<Frictionless, E> {
        &m.free
    }

    fn watches<E: Effect + Copy>(_m: &Machine<'_, E>) -> Vec<Watch> {
        vec![Watch::Normal]
    }

    fn watch<E: Effect + Copy>(
        _m: &Machine<'_, E>,
        _watch: Watch,
        ev: &Evaluation,
        _y: &State,
    ) -> f64 {
        ev.response.normal
    }

    fn on_event<E: Effect + Copy>(
        _m: &Machine<'_, E>,
        _watch: Watch,
        t: f64,
        _y: &mut State,
        events: &mut Vec<EventRecord>,
    ) -> Next {
        events.push(EventRecord {
            kind: EventKind::LostContact,
            t,
        });
        Next::Stop(Status::LostContact)
    }
}
