//! The hybrid system's transitions, written once (docs/physics.md, "The hybrid
//! machine"): from a phase, on an event, under a condition, to a phase, with the state
//! map. The phases (`phase`) locate their events; everything that decides between phases
//! is here. The table is docs/physics.md's, row for row (each row's physics is there;
//! `the_transition_table_here_is_the_one_in_docs_physics_md`, tests/transitions.rs):
//!
//! | from | event | condition | to | state map |
//! |---|---|---|---|---|
//! | start | on the plane | the rule "on the plane" (`on_plane`) | its phase, or stop `slip_stopped` | s_ref ← ŝ; rolling: v_G ← −ω × r |
//! | start | above the plane (`height` > 0) | | flight | z_G = h(ζ) + height |
//! | flight | touchdown: gap ↓ −δz | rebound > v_settle | flight | back to gap = 0; impact; loss in W |
//! | flight | touchdown | rebound ≤ v_settle, N > 0 on the plane | the rule "on the plane" | back to gap = 0; plastic impact; z_G, v_Gz from the contact, their kinetic energy in W |
//! | flight | touchdown | rebound ≤ v_settle, N ≤ 0, flight consistent | flight | the plastic impact |
//! | flight | touchdown | rebound ≤ v_settle, N ≤ 0, flight inconsistent | stop `inconsistent_contact` | |
//! | flight | touchdown | another surface touches at the same instant and approaches after the impact ("Simultaneous touchdowns", `coinciding`) | by who stays after the impact at them all, as in the row of a pressed surface that approaches; no solution → stop `several_contacts` | back to gap = 0; impact at every such surface ("Impact at several contacts", `impact::resolve_contacts`), plastic where all stay and one rebounds; loss in W, an `impact` event per surface |
//! | any contact | another surface's gap ↓ −δz (contact spheres) | the pressed surface separates after the new one's impact | as a touchdown of the new surface | flight form; impact at the new surface |
//! | any contact | another surface's gap ↓ −δz | the pressed surface stays (\|v_k⁺\| ≤ v_settle), the new one's rebound ≤ its settling speed on the pressed one ("Settling at a second surface"), both N > 0 once the grip is settled (`settle_grip`; Coulomb model: a slip within the slip stop sticks; rolling model: both stick; otherwise both slipping above it); else the first consistent of the pressed one, the new one, none ("Which contacts stay", `active_set`) | two contacts (or as the set) | plastic impact at the new surface; contact form; the second constraint restored and sticking impulses, their energy change in W |
//! | any contact | another surface's gap ↓ −δz | the pressed surface stays, the new one rebounds | the rule "on the plane" for the pressed surface | impact at the new surface; contact form |
//! | any contact | another surface's gap ↓ −δz | the pressed surface approaches (v_k⁺ < −v_settle), or a further surface touches at the same instant ("Simultaneous touchdowns", `coinciding`), or the two rock (each one's rebound within its settling speed on the other) and their impact has a solution | by who stays: all → two (three) contacts, one → the rule "on the plane" for it, none → flight | impact at both contacts ("Impact at several contacts", `impact::resolve_contacts`; the rolling model: its no-slip law), plastic where both stay and one rebounds; loss in W, an `impact` event per surface with its share |
//! | any contact | another surface's gap ↓ −δz | otherwise (the pair impact has no solution; no consistent set of the two) | stop `several_contacts` | |
//! | two contacts | N_1 or N_2 ↓ 0 | | the rule "on the plane" for the other surface, or lift-off | |
//! | two or three contacts | a slip ↓ its stop (`above_stop`; with a contact disc: slip and spin together) | the sliding model, a contact disc | stop `slip_stopped`, as on one contact | a `slip_stop` event |
//! | two or three contacts | Painlevé denominator ↓ 10⁻³ | | stop `painleve` | |
//! | sliding | slip stop: v_C·s_ref ↓ 0 or \|v_C\| ↓ floor | confirmed | the rule "on the plane" (stuck) | sticking impulse (model 4) |
//! | sliding | slip stop | not confirmed: a turn | sliding | s_ref ← ŝ |
//! | sliding | Painlevé denominator ↓ 10⁻³ (N → ∞ beyond) | | stop `painleve` | |
//! | rolling | cone left: μN − \|F_h\| ↓ 0 (Coulomb) | | sliding | s_ref ← −F̂_h, seed slip in W |
//! | any contact | N ↓ 0 | `on_lift_off = "stop"` | stop `lost_contact` | |
//! | any contact | N ↓ 0 | flight consistent | flight | z_G, v_Gz (rolling: v_G) from the contact: continuous |
//! | any contact | N ↓ 0 | flight inconsistent | stop `inconsistent_contact` | |
//! | sliding | the integrator's pace check fails (`FastRate`) | point contact, fastest rate ≤ 30 μN/(m\|v_C\|): a slip held at the cone's edge ("The slip stop, numerically"; `SlidingPhase::on_failure`) | the rule "on the plane" (stuck) | sticking impulse, at the last accepted state |
//! | two or three contacts | a slip ↓ the slip stop (`Numerics::two_contact_stop`) | the Coulomb model, point contacts | the same contacts, that one sticking ("Several contacts": which contacts stick, `grip`; where it cannot stick alone, with those whose slip is within a release's seed) | sticking impulses, their energy in W; every hold checked; a `grip` event |
//! | two or three contacts | a hold's margin ↓ 0 (`model::Hold`; Coulomb) | | the same contacts, that one (for the line: both) sliding (`release`) | a seed of slip of twice the stop, its energy in W; a `grip` event |
//! | two contacts | a third surface's gap ↓ −δz | | by who stays after the impact at the three contacts, at rest together (`rest_on`), then the first consistent set of them ("Which contacts stay", `active_set`): three → three contacts (`onto_contacts`), two → two contacts, one → the rule "on the plane" for it, none → flight; no solution, or no consistent set → stop `several_contacts` | flight form, back to its zero gap; impact at the three contacts ("Impact at several contacts", `impact::resolve_contacts`), plastic where all stay and one rebounds; loss in W, an `impact` event per surface |
//! | three contacts | N_i ↓ 0 | | two contacts, the other two (`go_on`) | |
//! | three contacts | a fourth surface's gap ↓ −δz | | stop `several_contacts` (four contacts are not simulated) | |
//!
//! Flight is consistent where the gap's acceleration with no contact force is not into
//! the plane ([`flight_is_consistent`]).

use nalgebra::{Vector2, Vector3};

use crate::body::{Body, Surface};
use crate::effects::Effect;
use crate::geometry::Contact;
use crate::impact::{self, Approach, Tangential};
use crate::integrate::{IntegrateError, OdeSystem, rk4_step};
use crate::invariants::Invariants;
use crate::kinematics::Kinematics;
use crate::model::{Contacts, Hold, MOST_CONTACTS, Rolling, Sliding, System};
use crate::state::{self, State};

use super::context::{ContactSet, Context};
use super::numerics::{
    BACK_STEPS, GAP_ACCEL_ROUNDOFF, PAINLEVE_COLLAPSE, RELEASE_SEED_STOPS, SECOND_GAP_RISE,
    SLIP_SEED,
};
use super::outcome::{EventKind, EventRecord, ImpactReport, Mode, Status};
use super::phase::{
    ContactsPhase, FlightPhase, FrictionlessPhase, Next, RollingPhase, above_stop, contacts_mode,
    grips, holds, normal, phase, set_reference, slip_has_stopped, slip_is_zero,
};
use super::scene::{ContactModel, LiftOff};

/// How a state came onto the plane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Arrival {
    /// The run's initial state (rolling: v_G follows from ω, no sticking impulse).
    Start,
    /// A persistent landing; `stuck`: the impact left no slip.
    Landing { stuck: bool },
    /// A located and confirmed slip stop of the sliding phase.
    SlipStop,
}

/// Where a state on the plane goes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Placed {
    /// Into this contact phase.
    In(Mode),
    /// Nowhere: slip (and a contact disc's spin) has stopped in a model that ends there.
    SlipStopped,
}

/// The phase a state on the plane enters, with its state map — the one rule for the
/// start, a landing and a slip stop:
/// - frictionless: frictionless;
/// - viscous: viscous (its law is smooth at zero slip: there is nothing to stop);
/// - rolling: rolling, on the constraint (the residual slip removed by the sticking
///   impulse, `Rolling::stick`, except at the start, where v_G follows from ω);
/// - a contact disc (sliding or Coulomb): stopped when slip and spin have both stopped
///   (or at a confirmed slip stop), else sliding — it does not stick while it spins;
/// - pure sliding: stopped when the slip is zero (or stuck, or a confirmed stop), else
///   sliding;
/// - Coulomb: when the slip is zero (or stuck, or a confirmed stop), rolling if the cone
///   holds after the sticking impulse, else sliding from rest opposite the friction
///   rolling needed ([`start_sliding_from_rest`]); else sliding.
///
/// Sliding starts with s_ref along the slip.
pub(super) fn on_plane<E: Effect + Copy + 'static>(
    ctx: &Context<'_, E>,
    contacts: &ContactSet,
    arrival: Arrival,
    y: &mut State,
) -> Placed {
    let stuck = match arrival {
        Arrival::Start => false,
        Arrival::Landing { stuck } => stuck,
        Arrival::SlipStop => true,
    };
    match ctx.scene.contact {
        ContactModel::Frictionless => Placed::In(Mode::Frictionless),
        ContactModel::Viscous { .. } => Placed::In(Mode::Viscous),
        ContactModel::Rolling => {
            if arrival != Arrival::Start {
                Rolling::stick(&ctx.body(contacts), y);
            }
            ctx.system::<RollingPhase>(contacts).project(y);
            Placed::In(Mode::Rolling)
        }
        ContactModel::Sliding { .. } | ContactModel::Coulomb { .. } if ctx.scene.disc.is_some() => {
            if arrival == Arrival::SlipStop || slip_has_stopped(ctx, contacts, y) {
                Placed::SlipStopped
            } else {
                renew_reference(ctx, contacts, y);
                Placed::In(Mode::Sliding)
            }
        }
        ContactModel::Sliding { .. } if stuck || slip_is_zero(ctx, contacts, y) => {
            Placed::SlipStopped
        }
        ContactModel::Coulomb { .. } if stuck || slip_is_zero(ctx, contacts, y) => {
            if rolls_once_stuck(ctx, contacts, y) {
                Placed::In(Mode::Rolling)
            } else {
                start_sliding_from_rest(ctx, contacts, y);
                Placed::In(Mode::Sliding)
            }
        }
        ContactModel::Sliding { .. } | ContactModel::Coulomb { .. } => {
            renew_reference(ctx, contacts, y);
            Placed::In(Mode::Sliding)
        }
    }
}

/// Whether the plane pushes on the body in `mode` at `y` (N > 0).
pub(super) fn pushes<E: Effect + Copy + 'static>(
    ctx: &Context<'_, E>,
    contacts: &ContactSet,
    mode: Mode,
    y: &State,
) -> bool {
    phase::<E>(mode).response(ctx, contacts, y).normal > 0.0
}

/// The slip stop located by the sliding phase at (t, y): a confirmed stop goes on the
/// plane ([`on_plane`]); one not confirmed is a turn of the slip by more than 90° within
/// a step, and sliding goes on with s_ref renewed.
pub(super) fn slip_stop<E: Effect + Copy + 'static>(
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
                switch(events, t, Mode::Sliding, mode);
            }
            Next::Go(mode)
        }
    }
}

/// The sliding normal force's denominator collapsed to `denominator`
/// (`numerics::PAINLEVE_COLLAPSE`) at t: N grows without bound, and Coulomb sliding has no
/// consistent contact force beyond. `error`: the integrator's failure where the collapse
/// was found by one, not by the phase's watch.
pub(super) fn painleve(
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
pub(super) fn cone_left<E: Effect + Copy + 'static>(
    ctx: &Context<'_, E>,
    contacts: &ContactSet,
    t: f64,
    y: &mut State,
    events: &mut Vec<EventRecord>,
) -> Next {
    start_sliding_from_rest(ctx, contacts, y);
    switch(events, t, Mode::Rolling, Mode::Sliding);
    Next::Go(Mode::Sliding)
}

/// N reached zero in contact mode `from` at (t, y): the run stops with
/// `on_lift_off = "stop"`; else the body flies where flight is consistent, its state
/// taking z_G = h(ζ), v_Gz and (rolling) v_G from the contact, so that E, L_G and the
/// position are continuous; else the run stops with `inconsistent_contact`.
pub(super) fn lift_off<E: Effect + Copy + 'static>(
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
    switch(events, t, from, Mode::Flight);
    Next::Go(Mode::Flight)
}

/// The state map of leaving the plane from contact mode `from`: z_G and v_Gz (and,
/// rolling, v_G) become flight states with the values the contact gave them.
pub(super) fn to_flight<E>(ctx: &Context<'_, E>, contacts: &ContactSet, from: Mode, y: &mut State) {
    let kin = Kinematics::new(&ctx.body(contacts), y, from == Mode::Rolling);
    y[state::VEL] = kin.v_g.x;
    y[state::VEL + 1] = kin.v_g.y;
    y[state::HEIGHT] = kin.contact.height;
    y[state::VEL_Z] = kin.v_g.z;
}

/// Whether flight is consistent at the contact state `y` of mode `from`, where N ≤ 0:
/// the gap's acceleration with no contact force,
/// ```text
///   g̈_free = −(m g − f_z − m u·I⁻¹T − m κ)/m,
/// ```
/// is not into the plane. Its numerator is that of the unilateral law
/// (`model::unilateral`) for every force direction, so a frictionless contact or a
/// sliding one with a positive Painlevé denominator has g̈_free ≥ 0 wherever N ≤ 0 and
/// leaves consistently. Rolling, whose friction need not vanish with N, can reach N ≤ 0
/// with g̈_free < 0: the plane would have to pull, and without it the body falls into
/// the plane — the rolling model's analogue of Painlevé's paradox (docs/physics.md,
/// "The hybrid machine"), reported as `Err` with the numbers.
pub(super) fn flight_is_consistent<E: Effect + Copy + 'static>(
    ctx: &Context<'_, E>,
    contacts: &ContactSet,
    from: Mode,
    y: &State,
) -> Result<(), Status> {
    let free = ctx.system::<FrictionlessPhase>(contacts).evaluate(y);
    let accel = -free.response.normal * free.response.painleve / ctx.scene.body.mass();
    if accel >= -gap_accel_roundoff(ctx, &free.kin, free.load.force.norm()) {
        return Ok(());
    }
    Err(Status::InconsistentContact {
        mode: from,
        normal: phase_normal(ctx, contacts, from, y),
        gap_acceleration: accel,
    })
}

/// The round-off of a gap's acceleration at kinematics `kin` under an applied force of
/// magnitude `force` \[m/s²\]: `GAP_ACCEL_ROUNDOFF` of its scale g + |ω|² a_max + |f|/m.
fn gap_accel_roundoff<E>(ctx: &Context<'_, E>, kin: &Kinematics, force: f64) -> f64 {
    let body = &ctx.scene.body;
    GAP_ACCEL_ROUNDOFF
        * (ctx.scene.gravity
            + kin.omega.norm_squared() * body.semi_axes().max()
            + force / body.mass())
}

/// N of contact mode `mode` at `y` \[N\].
fn phase_normal<E: Effect + Copy + 'static>(
    ctx: &Context<'_, E>,
    contacts: &ContactSet,
    mode: Mode,
    y: &State,
) -> f64 {
    match mode {
        Mode::Flight => {
            ctx.system::<FrictionlessPhase>(contacts)
                .evaluate(y)
                .response
                .normal
        }
        mode => phase::<E>(mode).response(ctx, contacts, y).normal,
    }
}

/// Surface `touching` reached the plane (its gap located at −δz) at (t, y) while the body
/// was in contact on another, `pressed`, in mode `from` (docs/physics.md, "Contact
/// spheres"). The state is put in flight form and taken back to `touching`'s zero gap, and
/// its impact is first taken alone, `pressed`'s impulse zero. With v_k⁺ the pressed
/// surface's normal velocity after it and v_settle,k its settling speed:
/// - v_k⁺ > v_settle,k: `pressed` separates, which solves the impact at two contacts; the
///   run goes on as after a touchdown from flight ([`touchdown`]'s rule);
/// - |v_k⁺| ≤ v_settle,k: `pressed` stays; `touching` stays too where its rebound is within
///   its own settling speed on `pressed` ([`second_settling_speed`]), and the impact is
///   then taken plastic;
/// - v_k⁺ < −v_settle,k: the impulse at `touching` alone would drive `pressed` into the
///   plane, and the impact is taken at both contacts at once ([`contacts_touchdown`]).
///
/// The impact is also taken at both, and at any further surface that touches at the same
/// instant ([`coinciding`], docs/physics.md "Simultaneous touchdowns"), where such a
/// surface exists, or where the two rock: `touching`'s rebound within its settling speed
/// on `pressed` and `pressed`'s separation within its own on `touching`; a rocking pair
/// whose impact has no solution is judged by the three cases above. The outcome goes on
/// the plane by [`settle`]. A pair impact that has no solution, or two
/// contacts the two-contact phase cannot take, stop the run with `several_contacts` at the
/// located state.
pub(super) fn second_touchdown<E: Effect + Copy + 'static>(
    ctx: &Context<'_, E>,
    contacts: &mut ContactSet,
    from: Mode,
    touching: Surface,
    t: &mut f64,
    y: &mut State,
    events: &mut Vec<EventRecord>,
) -> Next {
    let body = &ctx.scene.body;
    // The trials read the contact state as it was; the outcome's goes into `contacts`
    // where the run goes on.
    let was = &*contacts;
    let pressed = was.surface;
    let (t0, y0, before) = (*t, *y, events.len());
    to_flight(ctx, was, from, y);
    let strike = Strike::new(ctx, was, touching, t, y);
    let law = tangential(ctx.scene.contact);
    let single = strike.impact(law, ctx.scene.landing.restitution);
    let approach = normal_velocity(body, pressed, &single.1);
    // The pressed surface's settling speed: its own contact's deceleration.
    let pressed_settles = |y: &State| free_settling_speed(ctx, was, pressed, y);
    let onto_pressed = |y: &State| second_settling_speed(ctx, was, from, pressed, touching, y);
    let settle_k = pressed_settles(&single.1);
    // Where `touching` stays, `pressed`'s gap is a second surface's on it: a separation
    // within its settling speed there rises less than the located gap resolves, and both
    // stay. Judged by the free settling speed alone, the body rocked between the two at
    // 1e-8 m/s without end (the tippe top on its stem at the accumulation of its bounces).
    let rocking = single.0.normal_velocity.1 <= onto_pressed(&single.1)
        && approach <= second_settling_speed(ctx, was, from, touching, pressed, &single.1);
    let coincide = coinciding(ctx, was, &strike, &[pressed], &single.1);
    // The impact at both (and at any surface touching with them) where `pressed`
    // approaches, another surface touches at the same instant, or the two rock; a rocking
    // pair whose impact has no solution (the rolling model's no-slip law pulling) is
    // judged by `pressed`'s free settling speed alone, as any other.
    let joins = approach < -settle_k || !coincide.is_empty();
    let pair = (joins || rocking).then(|| {
        let settles = |s: Surface, y: &State| match s {
            s if s == touching => onto_pressed(y),
            s if s == pressed && rocking => {
                pressed_settles(y).max(second_settling_speed(ctx, was, from, touching, pressed, y))
            }
            s if s == pressed => pressed_settles(y),
            s => free_settling_speed(ctx, was, s, y),
        };
        let with: Vec<Surface> = (std::iter::once(pressed).chain(coincide))
            .take(MOST_CONTACTS - 1)
            .collect();
        contacts_touchdown(ctx, was, &strike, &with, law, settles)
    });
    let outcome = if let Some(pair) = pair.filter(|p| joins || p.is_some()) {
        pair
    } else if approach > settle_k {
        let flight_settles = |y: &State| settling_speed(ctx, &was.on(touching), y, &strike.kin);
        let (hit, after, settles) = strike.settled(law, single, flight_settles);
        let staying = if settles {
            Staying::One(touching)
        } else {
            Staying::Neither
        };
        Some((staying, after, vec![strike.report(&hit)]))
    } else {
        let (hit, after, settles) = strike.settled(law, single, onto_pressed);
        let staying = if settles {
            Staying::several(&[pressed, touching])
        } else {
            Staying::One(pressed)
        };
        Some((staying, after, vec![strike.report(&hit)]))
    };
    let mut placed = *was;
    let next = outcome.map(|(staying, after, reports)| {
        events.push(EventRecord {
            kind: EventKind::Touchdown {
                speed: -normal_velocity(body, touching, &strike.pre),
                surface: touching,
            },
            t: *t,
        });
        *y = after;
        settle(
            ctx,
            &mut placed,
            from,
            touching,
            staying,
            *t,
            y,
            &reports,
            events,
        )
    });
    match next {
        Some(Next::Stop(Status::SeveralContacts { .. }, _)) | None => {
            events.truncate(before);
            (*t, *y) = (t0, y0);
            Next::Stop(
                Status::SeveralContacts {
                    touching,
                    pressed,
                    approach,
                },
                from,
            )
        }
        Some(next) => {
            *contacts = placed;
            next
        }
    }
}

/// The impact of `strike` at its surface j and at the surfaces `pressed` at once
/// (`impact::resolve_contacts`, docs/physics.md "Impact at several contacts"), with the
/// scene's restitution and friction law. A contact stays where its normal velocity after
/// the impact is within its settling speed `settles(surface, y)`. Where all stay and one
/// of them rebounds, the impact is taken again with e = 0 (the plastic impact that ends a
/// bounce sequence the phase could not resolve, section "Settling"). A further surface
/// that touches the plane at the same instant and that the impact leaves approaching it
/// ([`coinciding`]) joins the impact, which is taken again, up to [`MOST_CONTACTS`]
/// surfaces. Returns who stays (the pressed surfaces first), the state after the impact
/// (flight form, its loss in W) and an impact report per surface (the loss on the struck
/// one's); `None` where the impact has no solution (the rolling model's no-slip law where
/// sticking the struck contact would pull; an iteration that does not converge).
fn contacts_touchdown<E: Effect + Copy + 'static>(
    ctx: &Context<'_, E>,
    contacts: &ContactSet,
    strike: &Strike,
    pressed: &[Surface],
    law: Tangential,
    settles: impl Fn(Surface, &State) -> f64,
) -> Option<(Staying, State, Vec<ImpactReport>)> {
    let kin = &strike.kin;
    let mut surfaces: Vec<Surface> = std::iter::once(strike.surface)
        .chain(pressed.iter().copied())
        .collect();
    let solve = |surfaces: &[Surface], e: f64| {
        let levers: Vec<Vector3<f64>> = (surfaces[1..].iter())
            .map(|&s| kin.rot * Contact::of(&ctx.scene.body, s, kin.contact.zeta, kin.omega).r)
            .collect();
        let hit = impact::resolve_contacts(&strike.approach, &levers, law, e)?;
        let after = strike.after(hit.v_g, hit.omega, hit.energy_loss);
        let stays: Vec<bool> = (surfaces.iter().enumerate())
            .map(|(i, &s)| hit.normal_velocity[i].1 <= settles(s, &after))
            .collect();
        Some((hit, after, stays))
    };
    let (mut hit, mut after, mut stays) = loop {
        let solved = solve(&surfaces, ctx.scene.landing.restitution)?;
        match coinciding(ctx, contacts, strike, &surfaces[1..], &solved.1).first() {
            Some(&more) if surfaces.len() < MOST_CONTACTS => surfaces.push(more),
            _ => break solved,
        }
    };
    if hit.restitution > 0.0
        && stays.iter().all(|&s| s)
        && hit.normal_velocity[..surfaces.len()]
            .iter()
            .any(|v| v.1 > 0.0)
    {
        (hit, after, stays) = solve(&surfaces, 0.0)?;
    }
    // The pressed surfaces first: the several-contact phase takes the first's geometry.
    let staying: Vec<Surface> = (1..surfaces.len())
        .chain([0])
        .filter(|&i| stays[i])
        .map(|i| surfaces[i])
        .collect();
    let staying = match staying.as_slice() {
        [] => Staying::Neither,
        [one] => Staying::One(*one),
        several => Staying::several(several),
    };
    // The loss is the impact's, reported at the struck surface: split between the
    // contacts as the work of each impulse, −P_i·(v_i⁻ + v_i⁺)/2, a share can be negative
    // (with friction one impulse can speed the body up while another slows it more).
    let reports = surfaces
        .iter()
        .enumerate()
        .map(|(i, &surface)| ImpactReport {
            impulse: hit.impulse[i],
            energy_loss: if i == 0 { hit.energy_loss } else { 0.0 },
            stuck: hit.stuck[i],
            rebound: hit.normal_velocity[i].1,
            persistent: false,
            surface,
        })
        .collect();
    Some((staying, after, reports))
}

/// A third surface `surface` touches down while two are in contact (the two-contact
/// phase's gap watch) at (t, y): the impact at the three contacts at once
/// ([`contacts_touchdown`]), in flight form, each pressed contact staying within its own
/// settling speed ([`settling_speed`] on that surface), the struck one within its
/// settling speed on the first pressed one ([`second_settling_speed`]). The outcome goes
/// on the plane by [`settle`] (three contacts, two, one, or flight). An impact with no
/// solution, or three contacts the three-contact phase cannot take, stop the run with
/// `several_contacts` at the located state.
pub(super) fn third_touchdown<E: Effect + Copy + 'static>(
    ctx: &Context<'_, E>,
    contacts: &mut ContactSet,
    surface: Surface,
    t: &mut f64,
    y: &mut State,
    events: &mut Vec<EventRecord>,
) -> Next {
    let body = &ctx.scene.body;
    // As in `second_touchdown`: the trials read `was`, the outcome goes into `contacts`.
    let was = &*contacts;
    let pressed = was.touching();
    let (t0, y0, before) = (*t, *y, events.len());
    to_flight(ctx, was, Mode::TwoContacts, y);
    let strike = Strike::new(ctx, was, surface, t, y);
    let law = tangential(ctx.scene.contact);
    let settles = |s: Surface, y: &State| match s {
        s if s == surface => {
            second_settling_speed(ctx, was, Mode::TwoContacts, pressed[0], surface, y)
        }
        s => free_settling_speed(ctx, was, s, y),
    };
    let mut placed = *was;
    let next = contacts_touchdown(ctx, was, &strike, &pressed, law, settles).map(
        |(staying, after, reports)| {
            events.push(EventRecord {
                kind: EventKind::Touchdown {
                    speed: -normal_velocity(body, surface, &strike.pre),
                    surface,
                },
                t: *t,
            });
            *y = after;
            settle(
                ctx,
                &mut placed,
                Mode::TwoContacts,
                surface,
                staying,
                *t,
                y,
                &reports,
                events,
            )
        },
    );
    match next {
        Some(Next::Stop(Status::SeveralContacts { .. }, _)) | None => {
            events.truncate(before);
            (*t, *y) = (t0, y0);
            Next::Stop(
                Status::SeveralContacts {
                    touching: surface,
                    pressed: pressed[0],
                    approach: normal_velocity(body, surface, &strike.pre),
                },
                Mode::TwoContacts,
            )
        }
        Some(next) => {
            *contacts = placed;
            next
        }
    }
}

/// The settling speed of surface `surface`'s gap while the body touches the plane with
/// `pressed` in mode `mode` (docs/physics.md, "Settling at a second surface"), at the
/// flight-form state `y`: √(2 a k δz), a the deceleration of that gap under the phase's
/// dynamics ([`gap_deceleration`]) and k = `SECOND_GAP_RISE`. A rebound of `surface`
/// below it rises less than k δz before that dynamics brings it back, which the located
/// gap does not resolve.
fn second_settling_speed<E: Effect + Copy + 'static>(
    ctx: &Context<'_, E>,
    contacts: &ContactSet,
    mode: Mode,
    pressed: Surface,
    surface: Surface,
    y: &State,
) -> f64 {
    let contacts = &contacts.on(pressed);
    let mut on = *y;
    clear_flight_slots(ctx, contacts, &mut on);
    renew_reference(ctx, contacts, &mut on);
    let decel = gap_deceleration(ctx, contacts, mode, surface, &on);
    let kin = Kinematics::new(&ctx.body(contacts), &on, false);
    ctx.numerics.settling_speed(SECOND_GAP_RISE * decel, &kin)
}

/// The deceleration of surface `surface`'s gap g = h_1 − h_2 (z_G = h_1 on
/// `ContactSet::surface`, the pressed one) under the dynamics of mode `mode` at the
/// contact-form state `on` \[m/s²\],
/// ```text
///   a = −g̈ = (u_1 − u_2)·ω̇ + κ_1 − κ_2,
/// ```
/// ω̇ the phase's (u_i = r_i × ζ, κ_i as in z̈_G = −u·ω̇ − κ): a > 0 drives `surface`
/// into the plane.
fn gap_deceleration<E: Effect + Copy + 'static>(
    ctx: &Context<'_, E>,
    contacts: &ContactSet,
    mode: Mode,
    surface: Surface,
    on: &State,
) -> f64 {
    let kin = Kinematics::new(&ctx.body(contacts), on, false);
    let omega_dot = phase::<E>(mode).response(ctx, contacts, on).omega_dot;
    let other = Contact::of(&ctx.scene.body, surface, kin.contact.zeta, kin.omega);
    (kin.contact.u - other.u).dot(&omega_dot) + kin.contact.kappa - other.kappa
}

/// The normal velocity of `surface`'s lowest point at the flight-form state `y`,
/// v_n = v_Gz + e3·(R (ω × r)) \[m/s\].
fn normal_velocity(body: &Body, surface: Surface, y: &State) -> f64 {
    let kin = Kinematics::flying_at(body, surface, y);
    kin.v_g.z + (kin.rot * kin.omega.cross(&kin.contact.r)).z
}

/// The several-contact system of the surfaces in contact (`ContactSet::count` of them).
fn contacts_system<E: Copy>(ctx: &Context<'_, E>, contacts: &ContactSet) -> System<Contacts, E> {
    match contacts.count {
        2 => ctx.system::<ContactsPhase<2>>(contacts),
        _ => ctx.system::<ContactsPhase<3>>(contacts),
    }
}

/// The contact-form state `y` (on `ContactSet::surface`) on the surfaces in contact
/// (`ContactSet::surface`, `ContactSet::others`, `ContactSet::count`): the other contacts'
/// constraints restored ([`restore_contacts`], the energy it changes booked in W) and the
/// contacts' grip settled ([`settle_grip`]: in the Coulomb model a contact whose slip is
/// within its stop on several contacts (`phase::above_stop`) sticks; in the rolling model
/// all do). It goes into the several-contact phase where then every normal force is
/// positive and the law consistent; it is `Placed::SlipStopped` where, in the sliding
/// model or with a contact disc, a contact's slip is within its stop (the run ends there,
/// as it does on one contact); else `None`. Sets `contacts`' grip.
fn onto_contacts<E: Effect + Copy + 'static>(
    ctx: &Context<'_, E>,
    contacts: &mut ContactSet,
    mut y: State,
) -> Option<(State, Placed)> {
    restore_contacts(ctx, contacts, &mut y);
    let sticks = match ctx.scene.contact {
        ContactModel::Rolling => [true; MOST_CONTACTS],
        ContactModel::Frictionless | ContactModel::Viscous { .. } => [false; MOST_CONTACTS],
        _ if grips(ctx) => [false; MOST_CONTACTS],
        _ if stopped(ctx, contacts, &y).contains(&true) => return Some((y, Placed::SlipStopped)),
        _ => [false; MOST_CONTACTS],
    };
    settle_grip(ctx, contacts, sticks, &mut y);
    let r = contacts_system(ctx, contacts).evaluate(&y).response;
    let pressed = (0..contacts.count).all(|i| normal(&r, i) > 0.0);
    (pressed && r.painleve > PAINLEVE_COLLAPSE)
        .then_some((y, Placed::In(contacts_mode(contacts.count))))
}

/// The contact-form state `y` on the surfaces in contact with their constraints restored
/// (`Contacts::project`, no contact sticking: `ContactSet::sticks` cleared). The projection
/// removes the other contacts' residual gaps and normal velocities (within the gap's
/// resolution and the settling speed): the energy it takes is booked in W, as a
/// persistent landing books its rebound's, so that E + W stays exact.
fn restore_contacts<E: Effect + Copy + 'static>(
    ctx: &Context<'_, E>,
    contacts: &mut ContactSet,
    y: &mut State,
) {
    contacts.sticks = [false; MOST_CONTACTS];
    let sys = contacts_system(ctx, contacts);
    let energy = |y: &State| {
        Invariants::from_kinematics(&sys.body, sys.gravity, &sys.evaluate(y).kin, 0.0).energy
    };
    let before = energy(y);
    sys.project(y);
    y[state::WORK] += before - energy(y);
}

/// Whether each contact's slip at the contact-form state `y` (`ContactSet::sticks` as the
/// law's) is within its stop on several contacts (`phase::above_stop`).
fn stopped<E: Effect + Copy + 'static>(
    ctx: &Context<'_, E>,
    contacts: &ContactSet,
    y: &State,
) -> [bool; MOST_CONTACTS] {
    let sys = contacts_system(ctx, contacts);
    let each = sys.contact.each(&sys.body, &sys.evaluate(y).kin);
    std::array::from_fn(|i| i < contacts.count && above_stop(ctx, &each[i]) <= 0.0)
}

/// The grip of the contacts at `y`, from `sticks` on: in the Coulomb model (point
/// contacts) every contact whose slip is within the slip stop sticks too ([`stopped`]:
/// a slip left below the stop would never cross it, and its friction would flip with
/// every step); the sticking contacts' slips are brought to zero by impulses at the
/// contacts (`Contacts::impel`, the energy in W); then, in the Coulomb model, while a
/// hold of a sticking contact fails (`model::Hold`, its margin < 0), the one that fails
/// most is released ([`release_hold`]) and the rest checked again. Sets
/// `ContactSet::sticks`.
fn settle_grip<E: Effect + Copy + 'static>(
    ctx: &Context<'_, E>,
    contacts: &mut ContactSet,
    mut sticks: [bool; MOST_CONTACTS],
    y: &mut State,
) {
    let count = contacts.count;
    // Sticking one contact changes the others' slips: they are checked again after.
    for _ in 0..count {
        if grips(ctx) {
            let stopped = stopped(ctx, contacts, y);
            sticks = std::array::from_fn(|i| sticks[i] || stopped[i]);
        }
        contacts.sticks = sticks;
        if sticks[..count].contains(&true) {
            let sys = contacts_system(ctx, contacts);
            sys.contact
                .impel(&sys.body, y, [Vector2::zeros(); MOST_CONTACTS]);
        }
    }
    let ContactModel::Coulomb { friction } = ctx.scene.contact else {
        return;
    };
    for _ in 0..=count {
        let sys = contacts_system(ctx, contacts);
        let ev = sys.evaluate(y);
        let forces = sys
            .contact
            .forces(&sys.body, sys.gravity, &ev.kin, &ev.load);
        let worst = holds(ctx, contacts)
            .into_iter()
            .map(|h| (h, forces.margin(h, friction)))
            .min_by(|a, b| a.1.total_cmp(&b.1));
        match worst {
            Some((hold, margin)) if margin < 0.0 => release_hold(ctx, contacts, hold, y),
            _ => return,
        }
    }
}

/// Releases `hold` at `y`: the contact (or, for [`Hold::Line`], both of the line) starts
/// to slide, with a seed of slip opposite the friction sticking needed — across the line
/// C_1C_2 where the other contact of a sticking pair sticks on, along it for the line — of
/// [`RELEASE_SEED_STOPS`] several-contact slip stops ([`seed_size`]), so that the slip-stop
/// watch starts above its zero (as the one-contact sliding phase seeds its onset,
/// docs/physics.md "Friction along the slip, and the onset's seed"); the seed's kinetic
/// energy is booked in W (`Contacts::impel`).
fn release_hold<E: Effect + Copy + 'static>(
    ctx: &Context<'_, E>,
    contacts: &mut ContactSet,
    hold: Hold,
    y: &mut State,
) {
    let sys = contacts_system(ctx, contacts);
    let ev = sys.evaluate(y);
    let forces = sys
        .contact
        .forces(&sys.body, sys.gravity, &ev.kin, &ev.load);
    let size = (sys.contact.each(&sys.body, &ev.kin)).map(|kin| seed_size(ctx, &kin));
    let unit = |v: Vector2<f64>, fallback: Vector2<f64>| {
        if v.norm() > 0.0 {
            v.normalize()
        } else {
            fallback
        }
    };
    let line = forces.line;
    let mut sticks = contacts.sticks;
    let mut seed = [Vector2::zeros(); MOST_CONTACTS];
    match hold {
        Hold::Contact(i) => {
            let t = forces.tangential[i];
            let across = t - t.dot(&line) * line;
            seed[i] = -unit(across, Vector2::new(-line.y, line.x)) * size[i];
            sticks[i] = false;
        }
        Hold::Line => {
            let [i, j] = forces.pair;
            let along = (forces.tangential[i] + forces.tangential[j]).dot(&line);
            let s = -along.signum() * line * size[i].max(size[j]);
            for k in [i, j] {
                seed[k] = s;
                sticks[k] = false;
            }
        }
    }
    sys.contact.impel(&sys.body, y, seed);
    contacts.sticks = sticks;
}

/// The slip a contact with kinematics `kin` is released with on several contacts
/// \[m/s\]: [`RELEASE_SEED_STOPS`] several-contact slip stops.
fn seed_size<E>(ctx: &Context<'_, E>, kin: &Kinematics) -> f64 {
    RELEASE_SEED_STOPS * ctx.numerics.two_contact_stop(kin)
}

/// A sliding contact of the several-contact phase stopped slipping at (t, y) (Coulomb
/// model, point contacts): it sticks where its cone holds ([`settle_grip`], from
/// `sticks`), and the phase goes on with the new grip; where a normal force is then not
/// positive, that surface leaves ([`leave`]). Where it cannot stick alone (its hold
/// fails and releases it again), every other sliding contact whose slip is within a
/// release's seed ([`seed_size`]) stops with it, and the grip is settled again from `y`
/// with those: a seed of that size falls back to the stop within nanoseconds, and two
/// contacts stopping together would otherwise trade seeds without end (docs/physics.md,
/// "Several contacts").
pub(super) fn grip<E: Effect + Copy + 'static>(
    ctx: &Context<'_, E>,
    contacts: &mut ContactSet,
    sticks: [bool; MOST_CONTACTS],
    t: f64,
    y: &mut State,
    events: &mut Vec<EventRecord>,
) -> Next {
    let before = contacts.sticks;
    let with_near = {
        let sys = contacts_system(ctx, contacts);
        let each = sys.contact.each(&sys.body, &sys.evaluate(y).kin);
        std::array::from_fn(|i| {
            sticks[i] || (i < contacts.count && each[i].slip.norm() <= seed_size(ctx, &each[i]))
        })
    };
    let (mut gripped, mut settled) = (*contacts, *y);
    settle_grip(ctx, &mut gripped, sticks, &mut settled);
    if gripped.sticks == before && with_near != sticks {
        settle_grip(ctx, contacts, with_near, y);
    } else {
        (*contacts, *y) = (gripped, settled);
    }
    record_grip(contacts, before, t, events);
    go_on(ctx, contacts, t, y, events)
}

/// A hold of the several-contact phase failed at (t, y) (its margin reached zero): that
/// contact, or the two of the line, slide from here ([`release_hold`], then
/// [`settle_grip`]).
pub(super) fn release<E: Effect + Copy + 'static>(
    ctx: &Context<'_, E>,
    contacts: &mut ContactSet,
    hold: Hold,
    t: f64,
    y: &mut State,
    events: &mut Vec<EventRecord>,
) -> Next {
    let before = contacts.sticks;
    release_hold(ctx, contacts, hold, y);
    let sticks = contacts.sticks;
    settle_grip(ctx, contacts, sticks, y);
    record_grip(contacts, before, t, events);
    go_on(ctx, contacts, t, y, events)
}

/// Records a `grip` event for each contact whose sticking changed from `before`.
fn record_grip(
    contacts: &ContactSet,
    before: [bool; MOST_CONTACTS],
    t: f64,
    events: &mut Vec<EventRecord>,
) {
    let surfaces = contacts.touching();
    let now = contacts.sticks;
    for i in (0..surfaces.len()).filter(|&i| now[i] != before[i]) {
        events.push(EventRecord {
            kind: EventKind::Grip {
                surface: surfaces[i],
                sticks: now[i],
            },
            t,
        });
    }
}

/// The several-contact phase goes on at (t, y) where every normal force is positive; else
/// the surface whose is least leaves ([`leave`]).
fn go_on<E: Effect + Copy + 'static>(
    ctx: &Context<'_, E>,
    contacts: &mut ContactSet,
    t: f64,
    y: &mut State,
    events: &mut Vec<EventRecord>,
) -> Next {
    let r = contacts_system(ctx, contacts).evaluate(y).response;
    let count = contacts.count;
    let least = (0..count)
        .map(|i| (i, normal(&r, i)))
        .min_by(|a, b| a.1.total_cmp(&b.1));
    match least {
        Some((i, n)) if !(n > 0.0) => leave(ctx, contacts, i, t, y, events),
        _ => Next::Go(contacts_mode(count)),
    }
}

/// Contact `i` of the several-contact phase leaves the plane (its normal force reached
/// zero) at (t, y): the body goes on touching with the others — with two, the
/// two-contact phase ([`go_on`]); with one, the phase the rule "on the plane" gives
/// ([`on_plane`]), or it leaves the plane as well where that one does not push
/// ([`lift_off`]).
pub(super) fn leave<E: Effect + Copy + 'static>(
    ctx: &Context<'_, E>,
    contacts: &mut ContactSet,
    i: usize,
    t: f64,
    y: &mut State,
    events: &mut Vec<EventRecord>,
) -> Next {
    let count = contacts.count;
    let from = contacts_mode(count);
    let mut surfaces = contacts.touching();
    let mut sticks = contacts.sticks[..count].to_vec();
    surfaces.remove(i);
    sticks.remove(i);
    if i == 0 {
        touch(contacts, surfaces[0], t, events);
    }
    if count > 2 {
        *contacts = ContactSet {
            sticks: std::array::from_fn(|k| sticks.get(k).copied().unwrap_or(false)),
            ..contacts.with_surfaces(&surfaces)
        };
        switch(events, t, from, contacts_mode(count - 1));
        return go_on(ctx, contacts, t, y, events);
    }
    let mut placed = *y;
    match on_plane(
        ctx,
        contacts,
        Arrival::Landing { stuck: sticks[0] },
        &mut placed,
    ) {
        // Leaving the plane wins over a slip stop where the plane does not push (N ≤ 0),
        // as at a landing.
        Placed::SlipStopped if !pushes(ctx, contacts, Mode::Sliding, &placed) => {
            *y = placed;
            lift_off(ctx, contacts, Mode::Sliding, t, y, events)
        }
        Placed::SlipStopped => {
            *y = placed;
            events.push(EventRecord {
                kind: EventKind::SlipStop,
                t,
            });
            Next::Stop(Status::SlipStopped, Mode::Sliding)
        }
        Placed::In(mode) => {
            *y = placed;
            if pushes(ctx, contacts, mode, y) {
                switch(events, t, from, mode);
                Next::Go(mode)
            } else {
                lift_off(ctx, contacts, mode, t, y, events)
            }
        }
    }
}

/// Touchdown of `surface` from flight, located at its gap = −δz on the flight's dense
/// output at (t, y): the impact is taken where the gap is zero ([`back_to_contact`], which
/// moves `t` back), its loss booked in W, with the scene's restitution unless the rebound
/// is within the settling speed after it (then plastic, the surface staying in contact);
/// the outcome goes on the plane by [`settle`]. Other surfaces that touch the plane at the
/// same instant ([`coinciding`]) and that the impact would leave approaching it take the
/// impact with it, at once ([`contacts_touchdown`], docs/physics.md "Simultaneous
/// touchdowns"): taken in turn, each impact drives the other surface into the plane
/// within the time resolution of the located touchdown, where no event can be seen, and
/// the body fell through the plane. An impact at them with no solution stops the run with
/// `several_contacts` at the located state.
pub(super) fn touchdown<E: Effect + Copy + 'static>(
    ctx: &Context<'_, E>,
    contacts: &mut ContactSet,
    surface: Surface,
    t: &mut f64,
    y: &mut State,
    events: &mut Vec<EventRecord>,
) -> Next {
    let body = &ctx.scene.body;
    let (t0, y0) = (*t, *y);
    let strike = Strike::new(ctx, contacts, surface, t, y);
    let law = tangential(ctx.scene.contact);
    let single = strike.impact(law, ctx.scene.landing.restitution);
    let coincide = coinciding(ctx, contacts, &strike, &[], &single.1);
    let (staying, after, reports, speed) = if coincide.is_empty() {
        // The settling speed after the impact: its rates decide what presses the body down.
        let settles = |y: &State| free_settling_speed(ctx, contacts, surface, y);
        let (hit, after, settles) = strike.settled(law, single, settles);
        let staying = if settles {
            Staying::One(surface)
        } else {
            Staying::Neither
        };
        let speed = -hit.normal_velocity.0;
        (staying, after, vec![strike.report(&hit)], speed)
    } else {
        let settles = |s: Surface, y: &State| free_settling_speed(ctx, contacts, s, y);
        let with = &coincide[..coincide.len().min(MOST_CONTACTS - 1)];
        let Some(outcome) = contacts_touchdown(ctx, contacts, &strike, with, law, settles) else {
            (*t, *y) = (t0, y0);
            return Next::Stop(
                Status::SeveralContacts {
                    touching: surface,
                    pressed: coincide[0],
                    approach: normal_velocity(body, coincide[0], &single.1),
                },
                Mode::Flight,
            );
        };
        let (staying, after, reports) = outcome;
        let speed = -normal_velocity(body, surface, &strike.pre);
        (staying, after, reports, speed)
    };
    touch(contacts, surface, *t, events);
    events.push(EventRecord {
        kind: EventKind::Touchdown { speed, surface },
        t: *t,
    });
    *y = after;
    settle(
        ctx,
        contacts,
        Mode::Flight,
        surface,
        staying,
        *t,
        y,
        &reports,
        events,
    )
}

/// The surfaces other than `strike`'s and `joined` that touch the plane at the instant of
/// its touchdown and approach it at `after` (a flight-form state at that instant) faster
/// than their settling speed: at the located touchdown their gap g_k is within its
/// round-off δz, or within what their approach v_k covers in the time resolution τ of
/// the located event (`Numerics::time_resolution`),
/// ```text
///   g_k ≤ δz + τ max(0, −v_k),    v_k < −v_settle,k,
/// ```
/// where the integrator, which takes no zero within round-off of the start of a
/// segment, would never see them touch down. Most approaching first.
fn coinciding<E: Effect + Copy + 'static>(
    ctx: &Context<'_, E>,
    contacts: &ContactSet,
    strike: &Strike,
    joined: &[Surface],
    after: &State,
) -> Vec<Surface> {
    let body = &ctx.scene.body;
    let tau = ctx.numerics.time_resolution(strike.t);
    let mut near: Vec<(f64, Surface)> = body
        .surfaces()
        .filter(|s| *s != strike.surface && !joined.contains(s))
        .filter_map(|s| {
            let at = Kinematics::flying_at(body, s, &strike.pre);
            let v = normal_velocity(body, s, after);
            let settle = free_settling_speed(ctx, contacts, s, after);
            let reach = ctx.numerics.gap_resolution(&at) + tau * (-v).max(0.0);
            (at.gap <= reach && v < -settle).then_some((v, s))
        })
        .collect();
    near.sort_by(|a, b| a.0.total_cmp(&b.0));
    near.into_iter().map(|(_, s)| s).collect()
}

/// A surface at its touchdown: the flight-form state taken back to the surface's zero gap
/// ([`back_to_contact`]) and the body there as the impact law sees it.
struct Strike {
    surface: Surface,
    /// The instant of the touchdown \[s\].
    t: f64,
    /// The state at zero gap, before the impact (flight form).
    pre: State,
    kin: Kinematics,
    approach: Approach,
}

impl Strike {
    /// `surface` touching down at (t, y), `t` moved back to its zero gap.
    fn new<E: Effect + Copy + 'static>(
        ctx: &Context<'_, E>,
        contacts: &ContactSet,
        surface: Surface,
        t: &mut f64,
        y: &State,
    ) -> Self {
        let body = &ctx.scene.body;
        let pre;
        (*t, pre) = back_to_contact(ctx, contacts, surface, *t, y);
        let kin = Kinematics::flying_at(body, surface, &pre);
        let rot = kin.rot;
        let approach = Approach {
            mass: body.mass(),
            inertia_inv: rot * body.inertia_inv() * rot.transpose(),
            r: rot * kin.contact.r,
            v_g: kin.v_g,
            omega: rot * kin.omega,
        };
        Strike {
            surface,
            t: *t,
            pre,
            kin,
            approach,
        }
    }

    /// The state after an impact that leaves G at `v_g` and the body turning at `omega`
    /// (world), its kinetic-energy `loss` booked in W, and no gap (it is zero to round-off
    /// at the located contact).
    fn after(&self, v_g: Vector3<f64>, omega: Vector3<f64>, loss: f64) -> State {
        let mut y = self.pre;
        y[state::VEL] = v_g.x;
        y[state::VEL + 1] = v_g.y;
        y[state::VEL_Z] = v_g.z;
        y.fixed_rows_mut::<3>(state::OMEGA)
            .copy_from(&self.kin.rot.tr_mul(&omega));
        y[state::WORK] += loss;
        y[state::HEIGHT] = self.kin.contact.height;
        y
    }

    /// The impact at the surface alone with restitution `e`, and the state after it.
    fn impact(&self, law: Tangential, e: f64) -> (impact::Impact, State) {
        let hit = impact::resolve(&self.approach, law, e);
        let after = self.after(hit.v_g, hit.omega, hit.energy_loss);
        (hit, after)
    }

    /// The impact `hit` (with the state after it) kept where its rebound exceeds the
    /// settling speed `settles` gives at the state after it, else taken again plastic;
    /// with whether the surface stays on the plane.
    fn settled(
        &self,
        law: Tangential,
        (hit, after): (impact::Impact, State),
        settles: impl Fn(&State) -> f64,
    ) -> (impact::Impact, State, bool) {
        let rebound = hit.normal_velocity.1;
        if rebound > settles(&after) {
            return (hit, after, false);
        }
        if rebound > 0.0 {
            let (hit, after) = self.impact(law, 0.0);
            return (hit, after, true);
        }
        (hit, after, true)
    }

    /// The report of the impact `hit` at the surface (its outcome, `persistent`, is filled
    /// in by [`settle`]).
    fn report(&self, hit: &impact::Impact) -> ImpactReport {
        ImpactReport {
            impulse: hit.impulse,
            energy_loss: hit.energy_loss,
            stuck: hit.stuck,
            rebound: hit.normal_velocity.1,
            persistent: false,
            surface: self.surface,
        }
    }
}

/// The surfaces an impact leaves on the plane.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Staying {
    Neither,
    One(Surface),
    /// Several, the first `count` of `surfaces`: the first the one whose geometry the
    /// several-contact phase takes.
    Several {
        surfaces: [Surface; MOST_CONTACTS],
        count: usize,
    },
}

impl Staying {
    /// `surfaces` (two or three) stay.
    fn several(surfaces: &[Surface]) -> Staying {
        Staying::Several {
            surfaces: std::array::from_fn(|i| surfaces.get(i).copied().unwrap_or(surfaces[0])),
            count: surfaces.len(),
        }
    }
}

/// Where the body goes after an impact in mode `from` at `struck` (the touching surface)
/// at t, `y` the flight-form state after it: the one tail of every touchdown.
/// - Neither surface stays: flight.
/// - One stays: that surface's phase by the rule "on the plane" ([`on_plane`], with z_G,
///   v_Gz from the contact, their kinetic energy in W), where the plane pushes there
///   (N > 0); else flight from the state on the plane where flight is consistent, else
///   stop `inconsistent_contact`; a landing the rule ends stops `slip_stopped`.
/// - Several stay: all at rest on the plane first ([`rest_on`]), then the first
///   consistent set of them ([`active_set`]) goes on: several → the several-contact
///   phase ([`onto_contacts`]) or a stop `slip_stopped` where the model ends at the slip
///   stop, one or none as above; where no set is consistent, stop `several_contacts`.
///
/// Records each surface's impact (`reports`, persistent where it stays on the plane), the
/// mode switch and, entering two contacts, a `grip` event for each contact that sticks.
#[allow(clippy::too_many_arguments)]
fn settle<E: Effect + Copy + 'static>(
    ctx: &Context<'_, E>,
    contacts: &mut ContactSet,
    from: Mode,
    struck: Surface,
    staying: Staying,
    t: f64,
    y: &mut State,
    reports: &[ImpactReport],
    events: &mut Vec<EventRecord>,
) -> Next {
    let record = |events: &mut Vec<EventRecord>, on: &[Surface]| {
        for r in reports {
            events.push(EventRecord {
                kind: EventKind::Impact(ImpactReport {
                    persistent: on.contains(&r.surface),
                    ..*r
                }),
                t,
            });
        }
    };
    let go = |events: &mut Vec<EventRecord>, to: Mode| {
        if to != from {
            switch(events, t, from, to);
        }
        Next::Go(to)
    };
    let stuck = |surface: Surface| reports.iter().any(|r| r.surface == surface && r.stuck);
    let several_contacts = |surfaces: &[Surface], y: &State| {
        Next::Stop(
            Status::SeveralContacts {
                touching: surfaces[surfaces.len() - 1],
                pressed: surfaces[0],
                approach: normal_velocity(&ctx.scene.body, surfaces[0], y),
            },
            from,
        )
    };
    let staying = match staying {
        Staying::Several { surfaces, count } => {
            rest_on(ctx, contacts, &surfaces[..count], y);
            match active_set(ctx, contacts, &surfaces[..count], stuck, y) {
                Some(set) => set,
                None => return several_contacts(&surfaces[..count], y),
            }
        }
        staying => staying,
    };
    match staying {
        Staying::Neither => {
            touch(contacts, struck, t, events);
            record(events, &[]);
            go(events, Mode::Flight)
        }
        Staying::One(surface) => {
            touch(contacts, surface, t, events);
            let mut landed = *y;
            clear_flight_slots(ctx, contacts, &mut landed);
            let placed = on_plane(
                ctx,
                contacts,
                Arrival::Landing {
                    stuck: stuck(surface),
                },
                &mut landed,
            );
            *y = landed;
            // A stop needs the body on the plane: where the plane does not push (N ≤ 0),
            // leaving it wins over the slip stop (docs/physics.md, "The hybrid
            // machine"; docs/scenarios.md, the status table).
            let placed = match placed {
                Placed::SlipStopped if !pushes(ctx, contacts, Mode::Sliding, y) => {
                    Placed::In(Mode::Sliding)
                }
                placed => placed,
            };
            match placed {
                Placed::SlipStopped => {
                    record(events, &[surface]);
                    events.push(EventRecord {
                        kind: EventKind::SlipStop,
                        t,
                    });
                    Next::Stop(Status::SlipStopped, Mode::Sliding)
                }
                Placed::In(mode) if pushes(ctx, contacts, mode, y) => {
                    record(events, &[surface]);
                    go(events, mode)
                }
                // The body's own motion lifts it: it flies on from rest relative to the
                // plane, unless flight is inconsistent there too. The state it flies from
                // is the one on the plane (for rolling, stuck): the consistency of flight
                // was decided there.
                Placed::In(mode) => match flight_is_consistent(ctx, contacts, mode, y) {
                    Ok(()) => {
                        record(events, &[]);
                        to_flight(ctx, contacts, mode, y);
                        go(events, Mode::Flight)
                    }
                    Err(status) => {
                        record(events, &[surface]);
                        Next::Stop(status, mode)
                    }
                },
            }
        }
        Staying::Several { surfaces, count } => {
            touch(contacts, surfaces[0], t, events);
            *contacts = contacts.with_surfaces(&surfaces[..count]);
            let mut on = *y;
            clear_flight_slots(ctx, contacts, &mut on);
            match onto_contacts(ctx, contacts, on) {
                Some((on, placed)) => {
                    record(events, &surfaces[..count]);
                    *y = on;
                    match placed {
                        Placed::In(mode) => {
                            let next = go(events, mode);
                            record_grip(contacts, [false; MOST_CONTACTS], t, events);
                            next
                        }
                        Placed::SlipStopped => {
                            events.push(EventRecord {
                                kind: EventKind::SlipStop,
                                t,
                            });
                            Next::Stop(Status::SlipStopped, contacts_mode(count))
                        }
                    }
                }
                None => several_contacts(&surfaces[..count], y),
            }
        }
    }
}

/// The flight-form state `y` with each of `surfaces` (two or three, at zero gap within
/// the located δz and normal velocities within their settling speeds) at rest on the
/// plane: their constraints restored together ([`restore_contacts`]; the grip is
/// settled by the placement after).
/// Each then starts at zero gap and zero normal velocity, whichever go on in contact
/// ([`active_set`]): one left out is not driven into the plane by the removal of the
/// others' residual velocities, and its gap's acceleration alone decides.
fn rest_on<E: Effect + Copy + 'static>(
    ctx: &Context<'_, E>,
    contacts: &ContactSet,
    surfaces: &[Surface],
    y: &mut State,
) {
    let contacts = &mut contacts.with_surfaces(surfaces);
    clear_flight_slots(ctx, contacts, y);
    restore_contacts(ctx, contacts, y);
    to_flight(ctx, contacts, contacts_mode(surfaces.len()), y);
}

/// The surfaces in contact after an impact that leaves `staying` (two or three, the
/// pressed ones first) on the plane, at the flight-form state `y` (docs/physics.md,
/// "Which contacts stay"): the first of their subsets, the larger first and within a
/// size in the order of `staying`, then none, that is consistent ([`consistent`]). For
/// frictionless contacts that is the solution of the complementarity problem of the
/// normal forces, which exists and is unique (its matrix, the Delassus matrix
/// W^T M⁻¹ W, is positive definite); with friction there may be none — the rolling
/// model's analogue of Painlevé's paradox — and the answer is `None`. `stuck(s)`: the
/// impact left no slip at surface s.
fn active_set<E: Effect + Copy + 'static>(
    ctx: &Context<'_, E>,
    contacts: &ContactSet,
    staying: &[Surface],
    stuck: impl Fn(Surface) -> bool,
    y: &State,
) -> Option<Staying> {
    let n = staying.len();
    let sets = (0..=n)
        .rev()
        .flat_map(|k| (0..1usize << n).filter(move |m| m.count_ones() as usize == k));
    for mask in sets {
        let pick = |inside: bool| -> Vec<Surface> {
            (0..n)
                .filter(|i| (mask >> i & 1 == 1) == inside)
                .map(|i| staying[i])
                .collect()
        };
        let (set, out) = (pick(true), pick(false));
        if consistent(ctx, contacts, &set, &out, &stuck, y) {
            return Some(match set.as_slice() {
                [] => Staying::Neither,
                [one] => Staying::One(*one),
                several => Staying::several(several),
            });
        }
    }
    None
}

/// Whether the surfaces `set` in contact and `out` off the plane, all at zero gap at the
/// flight-form state `y`, are consistent: placed as [`settle`] places them
/// ([`onto_contacts`] for several, [`on_plane`] for one), every contact pushes (N_i > 0)
/// and no surface of `out` is driven into the plane (its [`gap_deceleration`] within
/// round-off of zero or below); with none in contact, flight is consistent at each
/// ([`flight_is_consistent`]). A placement that stops the run at the slip stop counts as
/// consistent: the model ends there. `contacts`: the contact state the trial places
/// `set` from.
fn consistent<E: Effect + Copy + 'static>(
    ctx: &Context<'_, E>,
    contacts: &ContactSet,
    set: &[Surface],
    out: &[Surface],
    stuck: &impl Fn(Surface) -> bool,
    y: &State,
) -> bool {
    let opens = |contacts: &ContactSet, mode: Mode, on: &State| {
        let kin = Kinematics::new(&ctx.body(contacts), on, false);
        let roundoff = gap_accel_roundoff(ctx, &kin, 0.0);
        out.iter()
            .all(|&j| gap_deceleration(ctx, contacts, mode, j, on) <= roundoff)
    };
    let contact_form = |contacts: &ContactSet| {
        let mut on = *y;
        clear_flight_slots(ctx, contacts, &mut on);
        on
    };
    match set {
        [] => out.iter().all(|&j| {
            let contacts = &contacts.on(j);
            let on = contact_form(contacts);
            flight_is_consistent(ctx, contacts, Mode::Frictionless, &on).is_ok()
        }),
        [one] => {
            let contacts = &contacts.on(*one);
            let mut on = contact_form(contacts);
            match on_plane(
                ctx,
                contacts,
                Arrival::Landing { stuck: stuck(*one) },
                &mut on,
            ) {
                Placed::SlipStopped => true,
                Placed::In(mode) => pushes(ctx, contacts, mode, &on) && opens(contacts, mode, &on),
            }
        }
        several => {
            let contacts = &mut contacts.with_surfaces(several);
            let on = contact_form(contacts);
            match onto_contacts(ctx, contacts, on) {
                Some((on, Placed::In(mode))) => opens(contacts, mode, &on),
                Some((_, Placed::SlipStopped)) => true,
                None => false,
            }
        }
    }
}

/// Makes `surface` the one in contact from t on, recording the change of surface (bodies
/// with contact spheres only).
pub(super) fn touch(
    contacts: &mut ContactSet,
    surface: Surface,
    t: f64,
    events: &mut Vec<EventRecord>,
) {
    let from = std::mem::replace(&mut contacts.surface, surface);
    if from != surface {
        events.push(EventRecord {
            kind: EventKind::ContactSurface { from, to: surface },
            t,
        });
    }
}

/// The state on the flight's trajectory through (t, y) where the gap of `surface` is
/// zero: touchdown is located at gap = −δz (`phase::flight`), and an impact taken there,
/// with the penetration then removed, would add 2 a δz to v_n² at every bounce (a: the
/// gap's free deceleration) — enough to stall a Zeno sequence above the settling speed
/// whenever a e²/(1 − e²) > g (docs/physics.md, "Settling"). Newton's iteration on s,
/// gap(t + s) = 0 with d gap/dt = v_n, that surface's lowest point's normal velocity,
/// each y(t + s) one RK4 step of the flight system from (t, y); s is kept in
/// [−4√(2δz/g), 0]: the touchdown is never moved past the located event (from a grazing
/// one, v_n ≈ −1e-18 m/s, a Newton step from the lower bound went 0.07 s forward, over
/// samples already due), and never back further than a fall from rest takes through a
/// few δz, |s| ≈ δz/|v_n| being a few ns otherwise: a grazing touchdown
/// (v_n → 0, as when a body rocks between two surfaces) would otherwise send one RK4 step
/// seconds back along the flight. Without gravity the fall is at the gap's free
/// deceleration |a| ([`settling_speed`]'s), and where that is zero too there is no going
/// back: a bound from g alone was none at g = 0, and a surface leaving two contacts at
/// N ↓ 0 with its gap and normal velocity at round-off below zero (−1e-16 m, −2e-11 m/s)
/// was taken back 5 µs along a flight that never happened, to a state in which the body
/// had been touching with both.
fn back_to_contact<E: Effect + Copy + 'static>(
    ctx: &Context<'_, E>,
    contacts: &ContactSet,
    surface: Surface,
    t: f64,
    y: &State,
) -> (f64, State) {
    let body = &ctx.scene.body;
    let dz = ctx
        .numerics
        .gap_resolution(&Kinematics::flying_at(body, surface, y));
    let fall = if ctx.scene.gravity > 0.0 {
        ctx.scene.gravity
    } else {
        free_deceleration(ctx, &contacts.on(surface), y).abs()
    };
    let most = if fall > 0.0 {
        4.0 * (2.0 * dz / fall).sqrt()
    } else {
        0.0
    };
    let gap_and_rate = |y: &State| {
        let kin = Kinematics::flying_at(body, surface, y);
        let v_n = kin.v_g.z + (kin.rot * kin.omega.cross(&kin.contact.r)).z;
        (kin.gap, v_n)
    };
    let fly = ctx.system::<FlightPhase>(contacts);
    let mut k = [State::zeros(); 4];
    let (mut s, mut ys) = (0.0, *y);
    for _ in 0..BACK_STEPS {
        let (gap, v_n) = gap_and_rate(&ys);
        if gap == 0.0 || !(v_n < 0.0) {
            break;
        }
        s = (s - gap / v_n).clamp(-most, 0.0);
        ys = rk4_step(&fly, t, y, s, &mut k);
    }
    (t + s, ys)
}

/// The settling speed at the touchdown state `y` (`Numerics::settling_speed`), with the
/// gap's deceleration with no contact force ([`free_deceleration`]).
fn settling_speed<E: Effect + Copy + 'static>(
    ctx: &Context<'_, E>,
    contacts: &ContactSet,
    y: &State,
    kin: &Kinematics,
) -> f64 {
    ctx.numerics
        .settling_speed(free_deceleration(ctx, contacts, y), kin)
}

/// The settling speed of `surface` at the flight-form state `y` ([`settling_speed`] with
/// `surface` as the one in contact).
fn free_settling_speed<E: Effect + Copy + 'static>(
    ctx: &Context<'_, E>,
    contacts: &ContactSet,
    surface: Surface,
    y: &State,
) -> f64 {
    let kin = Kinematics::flying_at(&ctx.scene.body, surface, y);
    settling_speed(ctx, &contacts.on(surface), y, &kin)
}

/// The deceleration of the gap of the surface in contact with no contact force at `y`,
/// a = (m g − f_z − m u·I⁻¹T − m κ)/m \[m/s²\] (see [`flight_is_consistent`]).
fn free_deceleration<E: Effect + Copy + 'static>(
    ctx: &Context<'_, E>,
    contacts: &ContactSet,
    y: &State,
) -> f64 {
    let free = ctx.system::<FrictionlessPhase>(contacts).evaluate(y);
    free.response.normal * free.response.painleve / ctx.scene.body.mass()
}

/// The impact law of the scene's contact model: frictionless, Coulomb (sliding and
/// Coulomb models) or its no-slip limit (rolling). The viscous model's impact is taken
/// frictionless: its tangential impulse −μ_v ∫ v_C dp is neglected (docs/physics.md,
/// "Viscous sliding").
fn tangential(contact: ContactModel) -> Tangential {
    match contact {
        ContactModel::Frictionless | ContactModel::Viscous { .. } => Tangential::Frictionless,
        ContactModel::Sliding { friction } | ContactModel::Coulomb { friction } => {
            Tangential::Coulomb { friction }
        }
        ContactModel::Rolling => Tangential::NoSlip,
    }
}

/// Records a mode switch.
fn switch(events: &mut Vec<EventRecord>, t: f64, from: Mode, to: Mode) {
    events.push(EventRecord {
        kind: EventKind::ModeSwitch { from, to },
        t,
    });
}

/// Removes the slip of `y` (`Rolling::stick`, onto the rolling constraint) and tells
/// whether rolling holds there: the friction it needs within the scene's cone,
/// μN − |F_h| ≥ 0.
pub(super) fn rolls_once_stuck<E: Effect + Copy>(
    ctx: &Context<'_, E>,
    contacts: &ContactSet,
    y: &mut State,
) -> bool {
    let roll = ctx.system::<RollingPhase>(contacts);
    Rolling::stick(&ctx.body(contacts), y);
    roll.project(y);
    let mu = ctx.scene.contact.friction().unwrap_or(0.0);
    Rolling::cone_margin(&roll.evaluate(y).response, mu) >= 0.0
}

/// Sets the slip reference to −F_h/|F_h| of the rolling contact force: the slip that
/// develops when rolling fails opposes the friction it needed. The slip starts as
/// [`SLIP_SEED`] of the speed scale along that direction, not as zero: the sliding law's
/// watch g = v_C·s_ref then starts positive, so a slip that round-off turns against s_ref
/// is a located crossing (a stop), never a run on with friction along the slip
/// (docs/physics.md, "Friction along the slip, and the onset's seed").
fn start_sliding_from_rest<E: Effect + Copy + 'static>(
    ctx: &Context<'_, E>,
    contacts: &ContactSet,
    y: &mut State,
) {
    let f_h = ctx
        .system::<RollingPhase>(contacts)
        .evaluate(y)
        .response
        .force
        .xy();
    let s = if f_h.norm() > 0.0 {
        -f_h.normalize()
    } else {
        Vector2::x()
    };
    set_reference(y, s);
    let seed =
        s * (SLIP_SEED * Sliding::speed_scale(&Kinematics::new(&ctx.body(contacts), y, false)));
    // E + W stays exact: the seed's kinetic energy m (v_G·δv + |δv|²/2) is booked in W.
    let v = state::velocity(y);
    y[state::WORK] -= ctx.scene.body.mass() * (v.dot(&seed) + 0.5 * seed.norm_squared());
    y[state::VEL] += seed.x;
    y[state::VEL + 1] += seed.y;
}

/// Sets s_ref to the slip's direction (kept where the slip is zero): the sliding law's
/// friction opposes the slip from the segment's start, where v_C·s_ref > 0.
pub(super) fn renew_reference<E: Effect + Copy + 'static>(
    ctx: &Context<'_, E>,
    contacts: &ContactSet,
    y: &mut State,
) {
    let slip = Kinematics::new(&ctx.body(contacts), y, false).slip;
    if slip != Vector2::zeros() {
        set_reference(y, slip.normalize());
    }
}

/// A persistent landing's state with z_G and v_Gz given by the contact from now on
/// (their slots cleared for the slip reference): the kinetic energy of the rebound this
/// removes (below the settling speed) is booked in W, so E + W stays exact. Taking v_Gz
/// from the contact removes the residual normal velocity v_n = v_Gz + u·ω by a change of
/// v_Gz alone, which changes the energy by m(v_n²/2 − v_Gz v_n): where that is a gain
/// (unless v_Gz has v_n's sign and at least half its size), v_n is removed instead by a normal
/// impulse P at the contact, P = −v_n/(1/m + u·I⁻¹u), ω += I⁻¹u P (body axes), which
/// takes ½ v_n²/(1/m + u·I⁻¹u) ≥ 0 out (docs/physics.md, "Settling").
fn clear_flight_slots<E>(ctx: &Context<'_, E>, contacts: &ContactSet, y: &mut State) {
    let body = &ctx.body(contacts);
    let energy =
        |kin: &Kinematics| Invariants::from_kinematics(body, ctx.scene.gravity, kin, 0.0).energy;
    let flying = energy(&Kinematics::flying(body, y));
    let mut cleared = *y;
    cleared[state::HEIGHT] = 0.0;
    cleared[state::VEL_Z] = 0.0;
    let kin = Kinematics::new(body, &cleared, false);
    if energy(&kin) > flying {
        let u = kin.contact.u;
        let v_n = y[state::VEL_Z] + u.dot(&kin.omega);
        let turn = body.inertia_inv() * u;
        let impulse = -v_n / (1.0 / body.mass() + u.dot(&turn));
        for i in 0..3 {
            cleared[state::OMEGA + i] += turn[i] * impulse;
        }
    }
    cleared[state::WORK] += flying - energy(&Kinematics::new(body, &cleared, false));
    *y = cleared;
}
