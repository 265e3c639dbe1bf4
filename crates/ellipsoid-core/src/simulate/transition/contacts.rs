//! Several surfaces in contact (docs/physics.md, "Contact spheres", "Several contacts",
//! "Which contacts stay"): a second or third surface touching down while the body touches
//! the plane ([`second_touchdown`], [`third_touchdown`]); where the body goes after any
//! impact ([`settle`]: at rest on the surfaces that stay, [`rest_on`], then the first
//! consistent set of them, [`active_set`]); onto several contacts ([`onto_contacts`]) with
//! their grip settled ([`settle_grip`]); a contact that grips or is released ([`grip`],
//! [`release`]), and a surface that leaves ([`leave`]).

use nalgebra::Vector2;

use crate::body::Surface;
use crate::effects::Effect;
use crate::integrate::OdeSystem;
use crate::invariants::Invariants;
use crate::kinematics::Kinematics;
use crate::model::{Contacts, Hold, MOST_CONTACTS, System};
use crate::state::{self, State};

use crate::simulate::context::{ContactSet, Context};
use crate::simulate::numerics::{PAINLEVE_COLLAPSE, RELEASE_SEED_STOPS};
use crate::simulate::outcome::{EventKind, EventRecord, ImpactReport, Mode, Status};
use crate::simulate::phase::{
    ContactsPhase, Next, above_stop, contacts_mode, grips, holds, normal,
};
use crate::simulate::scene::ContactModel;

use super::landing::{
    Staying, Strike, coinciding, contacts_touchdown, free_settling_speed, gap_deceleration,
    normal_velocity, second_settling_speed, settling_speed, tangential,
};
use super::switch::lift_off;
use super::{
    Arrival, Placed, clear_flight_slots, flight_is_consistent, gap_accel_roundoff, on_plane,
    pushes, record_switch, to_flight, touch,
};

/// Surface `touching` reached the plane (its gap located at −δz) at (t, y) while the body
/// was in contact on another, `pressed`, in mode `from` (docs/physics.md, "Contact
/// spheres"). The state is put in flight form and taken back to `touching`'s zero gap, and
/// its impact is first taken alone, `pressed`'s impulse zero. With v_k⁺ the pressed
/// surface's normal velocity after it and v_settle,k its settling speed:
/// - v_k⁺ > v_settle,k: `pressed` separates, which solves the impact at two contacts; the
///   run goes on as after a touchdown from flight ([`super::touchdown`]'s rule);
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
pub(in crate::simulate) fn second_touchdown<E: Effect + Copy + 'static>(
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

/// A third surface `surface` touches down while two are in contact (the two-contact
/// phase's gap watch) at (t, y): the impact at the three contacts at once
/// ([`contacts_touchdown`]), in flight form, each pressed contact staying within its own
/// settling speed ([`settling_speed`] on that surface), the struck one within its
/// settling speed on the first pressed one ([`second_settling_speed`]). The outcome goes
/// on the plane by [`settle`] (three contacts, two, one, or flight). An impact with no
/// solution, or three contacts the three-contact phase cannot take, stop the run with
/// `several_contacts` at the located state.
pub(in crate::simulate) fn third_touchdown<E: Effect + Copy + 'static>(
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
pub(super) fn settle<E: Effect + Copy + 'static>(
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
            record_switch(events, t, from, to);
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
pub(in crate::simulate) fn grip<E: Effect + Copy + 'static>(
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
pub(in crate::simulate) fn release<E: Effect + Copy + 'static>(
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
pub(in crate::simulate) fn leave<E: Effect + Copy + 'static>(
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
        record_switch(events, t, from, contacts_mode(count - 1));
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
                record_switch(events, t, from, mode);
                Next::Go(mode)
            } else {
                lift_off(ctx, contacts, mode, t, y, events)
            }
        }
    }
}
