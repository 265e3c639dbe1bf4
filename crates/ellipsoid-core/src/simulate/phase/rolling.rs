//! The rolling phase (docs/physics.md, model 3): no slip, F from the 3×3 constraint solve.
//! Watches: loss of contact (g = N) and, in the Coulomb model, the friction cone
//! (g = μN − |F_h|); leaving the cone starts sliding (`transition::cone_left`).

use crate::effects::Effect;
use crate::model::{Evaluation, Rolling, System};
use crate::state::State;

use super::{Next, Phase, other_surfaces, touch_gap};
use crate::body::Surface;
use crate::simulate::context::{ContactSet, Context};
use crate::simulate::outcome::{EventRecord, Mode};
use crate::simulate::scene::ContactModel;
use crate::simulate::transition::{cone_left, lift_off, second_touchdown};

pub(in crate::simulate) struct RollingPhase;

/// The rolling phase's watches.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(in crate::simulate) enum RollingWatch {
    /// g = N (loss of contact).
    Normal,
    /// g = μN − |F_h| (rolling leaves the friction cone), μ the scene's.
    Cone { friction: f64 },
    /// Another surface's gap ([`touch_gap`]).
    Touch(Surface),
}

impl Phase for RollingPhase {
    const MODE: Mode = Mode::Rolling;
    type Law = Rolling;
    type Watch = RollingWatch;

    fn law<E>(_ctx: &Context<'_, E>, _contacts: &ContactSet) -> Rolling {
        Rolling
    }

    fn watches<E>(ctx: &Context<'_, E>, contacts: &ContactSet) -> Vec<RollingWatch> {
        let cone = match ctx.scene.contact {
            ContactModel::Coulomb { friction } => Some(RollingWatch::Cone { friction }),
            _ => None,
        };
        std::iter::once(RollingWatch::Normal)
            .chain(cone)
            .chain(other_surfaces(ctx, contacts).map(RollingWatch::Touch))
            .collect()
    }

    fn watch<E: Effect>(
        ctx: &Context<'_, E>,
        _sys: &System<Rolling, E>,
        watch: RollingWatch,
        ev: &Evaluation,
        _y: &State,
    ) -> f64 {
        match watch {
            RollingWatch::Normal => ev.response.normal,
            RollingWatch::Cone { friction } => Rolling::cone_margin(&ev.response, friction),
            RollingWatch::Touch(surface) => touch_gap(ctx, ev, surface),
        }
    }

    fn gap_of<E>(_ctx: &Context<'_, E>, watch: RollingWatch, _ev: &Evaluation) -> Option<Surface> {
        match watch {
            RollingWatch::Touch(surface) => Some(surface),
            _ => None,
        }
    }

    fn on_event<E: Effect + Copy + 'static>(
        ctx: &Context<'_, E>,
        contacts: &mut ContactSet,
        watch: RollingWatch,
        t: &mut f64,
        y: &mut State,
        events: &mut Vec<EventRecord>,
    ) -> Next {
        match watch {
            RollingWatch::Normal => lift_off(ctx, contacts, Mode::Rolling, *t, y, events),
            RollingWatch::Cone { .. } => cone_left(ctx, contacts, *t, y, events),
            RollingWatch::Touch(surface) => {
                second_touchdown(ctx, contacts, Mode::Rolling, surface, t, y, events)
            }
        }
    }
}
