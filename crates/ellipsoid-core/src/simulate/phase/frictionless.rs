//! The frictionless phase (docs/physics.md, model 1): F = N e3; it ends when N reaches 0
//! (`transition::lift_off`).

use crate::effects::Effect;
use crate::model::{Evaluation, Frictionless, System};
use crate::state::State;

use super::{Next, Phase, other_surfaces, touch_gap};
use crate::body::Surface;
use crate::simulate::context::{ContactSet, Context};
use crate::simulate::outcome::{EventRecord, Mode};
use crate::simulate::transition::{lift_off, second_touchdown};

pub(in crate::simulate) struct FrictionlessPhase;

/// The frictionless phase's watch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(in crate::simulate) enum FrictionlessWatch {
    /// g = N (loss of contact).
    Normal,
    /// Another surface's gap ([`touch_gap`]).
    Touch(Surface),
}

impl Phase for FrictionlessPhase {
    const MODE: Mode = Mode::Frictionless;
    type Law = Frictionless;
    type Watch = FrictionlessWatch;

    fn law<E>(_ctx: &Context<'_, E>, _contacts: &ContactSet) -> Frictionless {
        Frictionless
    }

    fn watches<E>(ctx: &Context<'_, E>, contacts: &ContactSet) -> Vec<FrictionlessWatch> {
        let touches = other_surfaces(ctx, contacts).map(FrictionlessWatch::Touch);
        std::iter::once(FrictionlessWatch::Normal)
            .chain(touches)
            .collect()
    }

    fn watch<E: Effect>(
        ctx: &Context<'_, E>,
        _sys: &System<Frictionless, E>,
        watch: FrictionlessWatch,
        ev: &Evaluation,
        _y: &State,
    ) -> f64 {
        match watch {
            FrictionlessWatch::Normal => ev.response.normal,
            FrictionlessWatch::Touch(surface) => touch_gap(ctx, ev, surface),
        }
    }

    fn gap_of<E>(
        _ctx: &Context<'_, E>,
        watch: FrictionlessWatch,
        _ev: &Evaluation,
    ) -> Option<Surface> {
        match watch {
            FrictionlessWatch::Touch(surface) => Some(surface),
            _ => None,
        }
    }

    fn on_event<E: Effect + Copy + 'static>(
        ctx: &Context<'_, E>,
        contacts: &mut ContactSet,
        watch: FrictionlessWatch,
        t: &mut f64,
        y: &mut State,
        events: &mut Vec<EventRecord>,
    ) -> Next {
        match watch {
            FrictionlessWatch::Normal => lift_off(ctx, contacts, Mode::Frictionless, *t, y, events),
            FrictionlessWatch::Touch(surface) => {
                second_touchdown(ctx, contacts, Mode::Frictionless, surface, t, y, events)
            }
        }
    }
}
