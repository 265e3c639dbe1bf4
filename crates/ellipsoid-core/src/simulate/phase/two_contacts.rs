//! Two surfaces in contact at once, both sliding (docs/physics.md, "Contact spheres"; the
//! law `model::TwoContacts`): the surface in contact (`Context::surface`) and a second
//! one (`Context::second`). Watches: each normal force (g = N_1, g = N_2: that surface
//! leaves, and the body goes on touching with the other), each contact's slip falling to
//! its stop (the slip band's width), the law's Painlevé denominator, and any third
//! surface's gap. A slip that stops or a third contact ends the run (`several_contacts`:
//! sticking at one of two contacts, or three contacts, is not simulated).

use crate::body::Surface;
use crate::effects::Effect;
use crate::model::{Evaluation, Kinematics, System, TwoContacts};
use crate::state::State;

use super::{Next, Phase, touch_gap};
use crate::simulate::context::Context;
use crate::simulate::numerics::PAINLEVE_COLLAPSE;
use crate::simulate::outcome::{EventRecord, Mode, Status};
use crate::simulate::transition::{leave_second, painleve};

pub(in crate::simulate) struct TwoContactsPhase;

/// The two-contact phase's watches.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(in crate::simulate) enum TwoContactsWatch {
    /// g = N_1 (the first surface leaves).
    First,
    /// g = N_2 (the second surface leaves).
    Second,
    /// g = |v_C1| − its stop (the first contact's slip stops; `Numerics::two_contact_stop`).
    FirstSlip,
    /// g = |v_C2| − its stop.
    SecondSlip,
    /// g = the law's Painlevé denominator − [`PAINLEVE_COLLAPSE`].
    Painleve,
    /// A third surface's gap ([`touch_gap`]).
    Touch(Surface),
}

impl Phase for TwoContactsPhase {
    const MODE: Mode = Mode::TwoContacts;
    type Law = TwoContacts;
    type Watch = TwoContactsWatch;

    fn law<E>(ctx: &Context<'_, E>) -> TwoContacts {
        TwoContacts {
            friction: ctx.scene.contact.friction().unwrap_or(0.0),
            disc: ctx.scene.disc,
            other: ctx.second.get(),
        }
    }

    fn watches<E>(ctx: &Context<'_, E>) -> Vec<TwoContactsWatch> {
        use TwoContactsWatch::*;
        let (first, second) = (ctx.surface.get(), ctx.second.get());
        let third = (ctx.scene.body.surfaces())
            .filter(|&s| s != first && s != second)
            .map(Touch);
        let slips = ctx
            .scene
            .contact
            .friction()
            .is_some_and(|mu| mu > 0.0)
            .then_some([FirstSlip, SecondSlip])
            .into_iter()
            .flatten();
        [First, Second, Painleve]
            .into_iter()
            .chain(slips)
            .chain(third)
            .collect()
    }

    fn watch<E: Effect>(
        ctx: &Context<'_, E>,
        sys: &System<TwoContacts, E>,
        watch: TwoContactsWatch,
        ev: &Evaluation,
        _y: &State,
    ) -> f64 {
        let r = &ev.response;
        let above_stop = |kin: &Kinematics| kin.slip.norm() - ctx.numerics.two_contact_stop(kin);
        match watch {
            TwoContactsWatch::First => r.normal - r.second_normal,
            TwoContactsWatch::Second => r.second_normal,
            TwoContactsWatch::FirstSlip => above_stop(&ev.kin),
            TwoContactsWatch::SecondSlip => {
                let (contact, slip) = sys.contact.second(&sys.body, &ev.kin);
                above_stop(&Kinematics {
                    contact,
                    slip,
                    ..ev.kin
                })
            }
            TwoContactsWatch::Painleve => r.painleve - PAINLEVE_COLLAPSE,
            TwoContactsWatch::Touch(surface) => touch_gap(ctx, ev, surface),
        }
    }

    fn gap_of<E>(
        _ctx: &Context<'_, E>,
        watch: TwoContactsWatch,
        _ev: &Evaluation,
    ) -> Option<Surface> {
        match watch {
            TwoContactsWatch::Touch(surface) => Some(surface),
            _ => None,
        }
    }

    fn on_event<E: Effect + Copy + 'static>(
        ctx: &Context<'_, E>,
        watch: TwoContactsWatch,
        t: &mut f64,
        y: &mut State,
        events: &mut Vec<EventRecord>,
    ) -> Next {
        let stop = |touching| {
            Next::Stop(
                Status::SeveralContacts {
                    touching,
                    pressed: ctx.surface.get(),
                    approach: 0.0,
                },
                Mode::TwoContacts,
            )
        };
        match watch {
            TwoContactsWatch::First => leave_second(ctx, true, *t, y, events),
            TwoContactsWatch::Second => leave_second(ctx, false, *t, y, events),
            TwoContactsWatch::FirstSlip | TwoContactsWatch::SecondSlip => stop(ctx.second.get()),
            TwoContactsWatch::Painleve => painleve(
                Mode::TwoContacts,
                ctx.system::<Self>().evaluate(y).response.painleve,
                None,
                *t,
                events,
            ),
            TwoContactsWatch::Touch(surface) => stop(surface),
        }
    }
}
