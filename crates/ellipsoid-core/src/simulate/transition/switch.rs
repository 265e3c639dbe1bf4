//! The switches on one contact that keep its surface (docs/physics.md, "The hybrid
//! machine"): the sliding phase's slip stop ([`slip_stop`]), the collapse of the normal
//! force's denominator ([`painleve`], in every sliding phase), rolling leaving the
//! friction cone ([`cone_left`]), and the normal force reaching zero ([`lift_off`]).

use crate::effects::Effect;
use crate::integrate::IntegrateError;
use crate::state::State;

use crate::simulate::context::{ContactSet, Context};
use crate::simulate::outcome::{EventKind, EventRecord, Mode, Status};
use crate::simulate::phase::Next;
use crate::simulate::scene::LiftOff;

use super::{
    Arrival, Placed, flight_is_consistent, on_plane, record_switch, renew_reference,
    start_sliding_from_rest, to_flight,
};

/// The slip stop located by the sliding phase at (t, y): a confirmed stop goes on the
/// plane ([`on_plane`]); one not confirmed is a turn of the slip by more than 90° within
/// a step, and sliding goes on with s_ref renewed.
pub(in crate::simulate) fn slip_stop<E: Effect + Copy + 'static>(
    ctx: &Context<'_, E>,
    contacts: &ContactSet,
    confirmed: bool,
    t: f64,
    y: &mut State,
    events: &mut Vec<EventRecord>,
) -> Next {
    if !confirmed {
        renew_reference(ctx, contacts, y);
        return Next::Go(Mode::Sliding);
    }
    events.push(EventRecord {
        kind: EventKind::SlipStop,
        t,
    });
    match on_plane(ctx, contacts, Arrival::SlipStop, y) {
        Placed::SlipStopped => Next::Stop(Status::SlipStopped, Mode::Sliding),
        Placed::In(mode) => {
            if mode != Mode::Sliding {
                record_switch(events, t, Mode::Sliding, mode);
            }
            Next::Go(mode)
        }
    }
}

/// The sliding normal force's denominator collapsed to `denominator`
/// (`numerics::PAINLEVE_COLLAPSE`) at t: N grows without bound, and Coulomb sliding has no
/// consistent contact force beyond. `error`: the integrator's failure where the collapse
/// was found by one, not by the phase's watch.
pub(in crate::simulate) fn painleve(
    mode: Mode,
    denominator: f64,
    error: Option<IntegrateError>,
    t: f64,
    events: &mut Vec<EventRecord>,
) -> Next {
    events.push(EventRecord {
        kind: EventKind::Painleve,
        t,
    });
    Next::Stop(Status::Painleve { denominator, error }, mode)
}

/// Rolling left the friction cone at (t, y): sliding from rest
/// ([`start_sliding_from_rest`]).
pub(in crate::simulate) fn cone_left<E: Effect + Copy + 'static>(
    ctx: &Context<'_, E>,
    contacts: &ContactSet,
    t: f64,
    y: &mut State,
    events: &mut Vec<EventRecord>,
) -> Next {
    start_sliding_from_rest(ctx, contacts, y);
    record_switch(events, t, Mode::Rolling, Mode::Sliding);
    Next::Go(Mode::Sliding)
}

/// N reached zero in contact mode `from` at (t, y): the run stops with
/// `on_lift_off = "stop"`; else the body flies where flight is consistent, its state
/// taking z_G = h(ζ), v_Gz and (rolling) v_G from the contact, so that E, L_G and the
/// position are continuous; else the run stops with `inconsistent_contact`.
pub(in crate::simulate) fn lift_off<E: Effect + Copy + 'static>(
    ctx: &Context<'_, E>,
    contacts: &ContactSet,
    from: Mode,
    t: f64,
    y: &mut State,
    events: &mut Vec<EventRecord>,
) -> Next {
    if ctx.scene.landing.lift_off == LiftOff::Stop {
        events.push(EventRecord {
            kind: EventKind::LostContact,
            t,
        });
        return Next::Stop(Status::LostContact, from);
    }
    if let Err(status) = flight_is_consistent(ctx, contacts, from, y) {
        return Next::Stop(status, from);
    }
    to_flight(ctx, contacts, from, y);
    events.push(EventRecord {
        kind: EventKind::LiftOff,
        t,
    });
    record_switch(events, t, from, Mode::Flight);
    Next::Go(Mode::Flight)
}
