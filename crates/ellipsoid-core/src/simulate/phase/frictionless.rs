//! The frictionless phase (docs/physics.md, model 1): F = N e3; it ends when N reaches 0
//! (a lift-off, `flight::lift_off`).

use crate::effects::Effect;
use crate::model::{Evaluation, Frictionless, System};
use crate::state::State;

use super::flight::lift_off;
use super::{Next, Phase, Watch};
use crate::simulate::machine::Machine;
use crate::simulate::outcome::{EventRecord, Mode};

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

    fn on_event<E: Effect + Copy + 'static>(
        m: &Machine<'_, E>,
        _watch: Watch,
        t: f64,
        y: &mut State,
        events: &mut Vec<EventRecord>,
    ) -> Next {
        lift_off(m, Mode::Frictionless, t, y, events)
    }
}
