//! Two surfaces in contact at once, each sliding or sticking (docs/physics.md, "Contact
//! spheres"; the law `model::TwoContacts`): the surface in contact (`Context::surface`)
//! and a second one (`Context::second`), which stick where `Context::sticks` says.
//! Watches: each normal force (g = N_1, g = N_2: that surface leaves, and the body goes
//! on touching with the other), each sliding contact's slip falling to its stop
//! ([`above_stop`]: in the Coulomb model it sticks there, `transition::grip`; the sliding
//! model and a contact disc end there, as on one contact), each hold of
//! the sticking ones (`model::Hold`: the cone left, that contact or both slide,
//! `transition::release`), the law's Painlevé denominator while a contact slides, and
//! any third surface's gap (three contacts are not simulated: `several_contacts`).

use crate::body::Surface;
use crate::effects::Effect;
use crate::model::{Evaluation, Hold, Kinematics, System, TwoContacts};
use crate::state::State;

use super::{Next, Phase, SlidingPhase, touch_gap};
use crate::simulate::context::Context;
use crate::simulate::numerics::PAINLEVE_COLLAPSE;
use crate::simulate::outcome::{EventKind, EventRecord, Mode, Status};
use crate::simulate::scene::ContactModel;
use crate::simulate::transition::{grip, leave_second, painleve, release};

pub(in crate::simulate) struct TwoContactsPhase;

/// The two-contact phase's watches.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(in crate::simulate) enum TwoContactsWatch {
    /// g = N_1 (the first surface leaves).
    First,
    /// g = N_2 (the second surface leaves).
    Second,
    /// g = the first contact's slip above its stop ([`above_stop`]).
    FirstSlip,
    /// g = the second contact's slip above its stop.
    SecondSlip,
    /// g = the margin of a sticking contact's hold ([`Hold`]).
    Holds(Hold),
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
            sticks: ctx.sticks.get(),
        }
    }

    fn watches<E>(ctx: &Context<'_, E>) -> Vec<TwoContactsWatch> {
        use TwoContactsWatch::*;
        let (first, second) = (ctx.surface.get(), ctx.second.get());
        let third = (ctx.scene.body.surfaces())
            .filter(|&s| s != first && s != second)
            .map(Touch);
        let sticks = ctx.sticks.get();
        let friction = ctx.scene.contact.friction().is_some_and(|mu| mu > 0.0);
        let slips = [FirstSlip, SecondSlip]
            .into_iter()
            .enumerate()
            .filter(move |&(i, _)| friction && !sticks[i])
            .map(|(_, w)| w);
        // Holds only in the Coulomb model (the rolling model's friction is unbounded).
        let coulomb = matches!(ctx.scene.contact, ContactModel::Coulomb { .. });
        let holds = match sticks {
            [true, true] => vec![Hold::Contact(0), Hold::Contact(1), Hold::Line],
            _ => (0..2).filter(|&i| sticks[i]).map(Hold::Contact).collect(),
        };
        let holds = holds.into_iter().filter(move |_| coulomb).map(Holds);
        let painleve = (sticks != [true, true]).then_some(Painleve);
        [First, Second]
            .into_iter()
            .chain(painleve)
            .chain(slips)
            .chain(holds)
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
        match watch {
            TwoContactsWatch::First => r.normal - r.second_normal,
            TwoContactsWatch::Second => r.second_normal,
            TwoContactsWatch::FirstSlip => above_stop(ctx, &ev.kin),
            TwoContactsWatch::SecondSlip => {
                above_stop(ctx, &sys.contact.each(&sys.body, &ev.kin)[1])
            }
            TwoContactsWatch::Holds(hold) => sys
                .contact
                .forces(&sys.body, sys.gravity, &ev.kin, &ev.load)
                .margin(hold, ctx.scene.contact.friction().unwrap_or(0.0)),
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
            TwoContactsWatch::FirstSlip | TwoContactsWatch::SecondSlip if !grips(ctx) => {
                events.push(EventRecord {
                    kind: EventKind::SlipStop,
                    t: *t,
                });
                Next::Stop(Status::SlipStopped, Mode::TwoContacts)
            }
            TwoContactsWatch::FirstSlip | TwoContactsWatch::SecondSlip => {
                let mut sticks = ctx.sticks.get();
                sticks[usize::from(watch == TwoContactsWatch::SecondSlip)] = true;
                grip(ctx, sticks, *t, y, events)
            }
            TwoContactsWatch::Holds(hold) => release(ctx, hold, *t, y, events),
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

/// Whether a contact whose slip stops on two contacts sticks there: in the Coulomb model
/// with point contacts. In the sliding model, and with a contact disc (which sticks only
/// where its spin has stopped too, which it does not take), the run ends there with
/// status `slip_stopped`, as on one contact (docs/physics.md, "Two contacts").
pub(in crate::simulate) fn grips<E>(ctx: &Context<'_, E>) -> bool {
    matches!(ctx.scene.contact, ContactModel::Coulomb { .. }) && ctx.scene.disc.is_none()
}

/// How far the slip of the contact with kinematics `kin` is above its stop on two contacts
/// \[m/s\]: with point contacts |v_C| − `Numerics::two_contact_stop`; with a contact disc
/// its stop speed √(|v_C|² + (R ω_n)²) (`Sliding::stop_speed`) less the threshold the
/// one-contact phase stops at (`Numerics::stop_threshold`): through v_C = 0 the disc's law
/// is smooth while it spins.
pub(in crate::simulate) fn above_stop<E>(ctx: &Context<'_, E>, kin: &Kinematics) -> f64 {
    match ctx.scene.disc {
        None => kin.slip.norm() - ctx.numerics.two_contact_stop(kin),
        Some(_) => SlidingPhase::law(ctx).stop_speed(kin) - ctx.numerics.stop_threshold(kin, true),
    }
}
