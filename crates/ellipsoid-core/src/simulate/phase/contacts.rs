//! Several surfaces in contact at once, two (mode `two_contacts`) or three
//! (`three_contacts`), each sliding or sticking (docs/physics.md, "Contact spheres",
//! "Several contacts"; the law `model::Contacts`): the surface in contact
//! (`ContactSet::surface`) and the others (`ContactSet::others`, `ContactSet::count` in
//! all), which stick where `ContactSet::sticks` says. Watches: each normal force (g = N_i: that surface
//! leaves, and the body goes on touching with the others), each sliding contact's slip
//! falling to its stop ([`above_stop`]: in the Coulomb model it sticks there,
//! `transition::grip`; the sliding model and a contact disc end there, as on one contact),
//! each hold of the sticking ones (`model::Hold`: the cone left, that contact or two slide,
//! `transition::release`), the law's Painlevé denominator while a contact slides, and
//! each other surface's gap (on two, a third touches down, `transition::third_touchdown`;
//! four are not simulated: `several_contacts`).

use crate::body::Surface;
use crate::effects::Effect;
use crate::kinematics::Kinematics;
use crate::model::{Contacts, Evaluation, Hold, MOST_CONTACTS, Response, System};
use crate::state::State;

use super::{Next, Phase, SlidingPhase, touch_gap};
use crate::simulate::context::{ContactSet, Context};
use crate::simulate::numerics::PAINLEVE_COLLAPSE;
use crate::simulate::outcome::{EventKind, EventRecord, Mode, Status};
use crate::simulate::scene::ContactModel;
use crate::simulate::transition::{grip, leave, painleve, release, third_touchdown};

/// The phase of `N` surfaces in contact (2 or 3).
pub(in crate::simulate) struct ContactsPhase<const N: usize>;

/// The several-contact phase's watches.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(in crate::simulate) enum ContactsWatch {
    /// g = N_i (contact i leaves).
    Leaves(usize),
    /// g = contact i's slip above its stop ([`above_stop`]).
    Slip(usize),
    /// g = the margin of a sticking contact's hold ([`Hold`]).
    Holds(Hold),
    /// g = the law's Painlevé denominator − [`PAINLEVE_COLLAPSE`].
    Painleve,
    /// Another surface's gap ([`touch_gap`]).
    Touch(Surface),
}

/// The several-contact mode of `count` surfaces in contact.
pub(in crate::simulate) fn contacts_mode(count: usize) -> Mode {
    if count == 2 {
        Mode::TwoContacts
    } else {
        Mode::ThreeContacts
    }
}

/// The holds the law's sticking contacts watch: each one's cone, and with exactly two
/// sticking the line between them (`model::Hold`). Only in the Coulomb model (the rolling
/// model's friction is unbounded).
pub(in crate::simulate) fn holds<E>(ctx: &Context<'_, E>, contacts: &ContactSet) -> Vec<Hold> {
    if !matches!(ctx.scene.contact, ContactModel::Coulomb { .. }) {
        return Vec::new();
    }
    let sticks = contacts.sticks;
    let sticking: Vec<usize> = (0..contacts.count).filter(|&i| sticks[i]).collect();
    let line = (sticking.len() == 2).then_some(Hold::Line);
    sticking
        .into_iter()
        .map(Hold::Contact)
        .chain(line)
        .collect()
}

impl<const N: usize> Phase for ContactsPhase<N> {
    const MODE: Mode = if N == 2 {
        Mode::TwoContacts
    } else {
        Mode::ThreeContacts
    };
    type Law = Contacts;
    type Watch = ContactsWatch;

    fn law<E>(ctx: &Context<'_, E>, contacts: &ContactSet) -> Contacts {
        Contacts {
            friction: ctx.scene.contact.friction().unwrap_or(0.0),
            disc: ctx.scene.disc,
            others: contacts.others,
            count: N,
            sticks: contacts.sticks,
        }
    }

    fn watches<E>(ctx: &Context<'_, E>, contacts: &ContactSet) -> Vec<ContactsWatch> {
        use ContactsWatch::*;
        let touching = contacts.touching();
        let others = (ctx.scene.body.surfaces())
            .filter(|s| !touching.contains(s))
            .map(Touch);
        let sticks = contacts.sticks;
        let friction = ctx.scene.contact.friction().is_some_and(|mu| mu > 0.0);
        let slips = (0..N).filter(move |&i| friction && !sticks[i]).map(Slip);
        let painleve = (!sticks[..N].iter().all(|&s| s)).then_some(Painleve);
        (0..N)
            .map(Leaves)
            .chain(painleve)
            .chain(slips)
            .chain(holds(ctx, contacts).into_iter().map(Holds))
            .chain(others)
            .collect()
    }

    fn watch<E: Effect>(
        ctx: &Context<'_, E>,
        sys: &System<Contacts, E>,
        watch: ContactsWatch,
        ev: &Evaluation,
        _y: &State,
    ) -> f64 {
        let r = &ev.response;
        match watch {
            ContactsWatch::Leaves(i) => normal(r, i),
            ContactsWatch::Slip(0) => above_stop(ctx, &ev.kin),
            ContactsWatch::Slip(i) => above_stop(ctx, &sys.contact.each(&sys.body, &ev.kin)[i]),
            ContactsWatch::Holds(hold) => sys
                .contact
                .forces(&sys.body, sys.gravity, &ev.kin, &ev.load)
                .margin(hold, ctx.scene.contact.friction().unwrap_or(0.0)),
            ContactsWatch::Painleve => r.painleve - PAINLEVE_COLLAPSE,
            ContactsWatch::Touch(surface) => touch_gap(ctx, ev, surface),
        }
    }

    fn gap_of<E>(_ctx: &Context<'_, E>, watch: ContactsWatch, _ev: &Evaluation) -> Option<Surface> {
        match watch {
            ContactsWatch::Touch(surface) => Some(surface),
            _ => None,
        }
    }

    fn on_event<E: Effect + Copy + 'static>(
        ctx: &Context<'_, E>,
        contacts: &mut ContactSet,
        watch: ContactsWatch,
        t: &mut f64,
        y: &mut State,
        events: &mut Vec<EventRecord>,
    ) -> Next {
        match watch {
            ContactsWatch::Leaves(i) => leave(ctx, contacts, i, *t, y, events),
            ContactsWatch::Slip(_) if !grips(ctx) => {
                events.push(EventRecord {
                    kind: EventKind::SlipStop,
                    t: *t,
                });
                Next::Stop(Status::SlipStopped, Self::MODE)
            }
            ContactsWatch::Slip(i) => {
                let mut sticks = contacts.sticks;
                sticks[i] = true;
                grip(ctx, contacts, sticks, *t, y, events)
            }
            ContactsWatch::Holds(hold) => release(ctx, contacts, hold, *t, y, events),
            ContactsWatch::Painleve => painleve(
                Self::MODE,
                ctx.system::<Self>(contacts).evaluate(y).response.painleve,
                None,
                *t,
                events,
            ),
            ContactsWatch::Touch(surface) if N < MOST_CONTACTS => {
                third_touchdown(ctx, contacts, surface, t, y, events)
            }
            ContactsWatch::Touch(surface) => Next::Stop(
                Status::SeveralContacts {
                    touching: surface,
                    pressed: contacts.surface,
                    approach: 0.0,
                },
                Self::MODE,
            ),
        }
    }
}

/// The normal force N_i of contact i (0: `ContactSet::surface`, then the others) in the
/// several-contact law's response \[N\].
pub(in crate::simulate) fn normal(r: &Response, i: usize) -> f64 {
    match i {
        0 => r.normal - r.other_normals.iter().sum::<f64>(),
        _ => r.other_normals[i - 1],
    }
}

/// Whether a contact whose slip stops on several contacts sticks there: in the Coulomb
/// model with point contacts. In the sliding model, and with a contact disc (which sticks
/// only where its spin has stopped too, which it does not take), the run ends there with
/// status `slip_stopped`, as on one contact (docs/physics.md, "Several contacts").
pub(in crate::simulate) fn grips<E>(ctx: &Context<'_, E>) -> bool {
    matches!(ctx.scene.contact, ContactModel::Coulomb { .. }) && ctx.scene.disc.is_none()
}

/// How far the slip of the contact with kinematics `kin` is above its stop on several
/// contacts \[m/s\]: with point contacts |v_C| − `Numerics::two_contact_stop`; with a
/// contact disc its stop speed √(|v_C|² + (R ω_n)²) (`Sliding::stop_speed`) less the
/// threshold the one-contact phase stops at (`Numerics::stop_threshold`): through v_C = 0
/// the disc's law is smooth while it spins.
pub(in crate::simulate) fn above_stop<E>(ctx: &Context<'_, E>, kin: &Kinematics) -> f64 {
    match ctx.scene.disc {
        None => kin.slip.norm() - ctx.numerics.two_contact_stop(kin),
        Some(_) => {
            SlidingPhase::sliding(ctx).stop_speed(kin) - ctx.numerics.stop_threshold(kin, true)
        }
    }
}
