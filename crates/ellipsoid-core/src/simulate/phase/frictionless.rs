//! The frictionless phase (docs/physics.md, model 1): F = N e3; it ends when N reaches 0
//! (`transition::lift_off`).

use crate::effects::Effect;
use crate::model::{Evaluation, Frictionless, System};
use crate::state::State;

use super::{Next, Phase};
use crate::simulate::context::Context;
use crate::simulate::outcome::{EventRecord, Mode};
use crate::simulate::transition::lift_off;

pub(in crate::simulate) struct FrictionlessPhase;

/// The frictionless phase's watch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(in crate::simulate) enum FrictionlessWatch {
    /// g = N (loss of contact).
    Normal,
}

impl Phase for FrictionlessPhase {
    const MODE: Mode = Mode::Frictionless;
    type Law = Frictionless;
    type Watch = FrictionlessWatch;

    fn law<E>(_ctx: &Context<'_, E>) -> Frictionless {
        Frictionless
    }

    fn watches<E>(_ctx: &Context<'_, E>) -> Vec<FrictionlessWatch> {
        vec![FrictionlessWatch::Normal]
    }

    fn watch<E: Effect>(
        _ctx: &Context<'_, E>,
        _sys: &System<Frictionless, E>,
        watch: FrictionlessWatch,
        ev: &Evaluation,
        _y: &State,
    ) -> f64 {
        match watch {
            FrictionlessWatch::Normal => ev.response.normal,
        }
    }

    fn on_event<E: Effect + Copy + 'static>(
        ctx: &Context<'_, E>,
        watch: FrictionlessWatch,
        t: &mut f64,
        y: &mut State,
        events: &mut Vec<EventRecord>,
    ) -> Next {
        match watch {
            FrictionlessWatch::Normal => lift_off(ctx, Mode::Frictionless, *t, y, events),
        }
    }
}
