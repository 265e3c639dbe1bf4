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
//! | start | on the plane, a rim flat (sin α ≤ `flat_tilt`) | | face | as a flat landing |
//! | flight | touchdown of a rim flat (sin α ≤ `flat_tilt`) | | face (`flat::land_flat`) | back to gap = 0; attitude turned flat; plastic impact of the face ("Rims"); loss in W, a `flat` event |
//! | frictionless, sliding, rolling, viscous (a rim in contact) | sin α ↓ `flat_tilt` (`flat`) | | face (`flat::land_flat`); the face's centre of pressure off the face → stop `several_contacts` | attitude turned flat; plastic impact of the face ("Rims"); loss in W, a `flat` event |
//! | face | √(\|v_f\|² + (R Ω)²) ↓ stop threshold (friction) | | face, at rest | v_G ← 0, ω ← 0; the kinetic energy left in W |
//! | face | N ↓ 0 | | as frictionless | as frictionless |
//!
//! Flight is consistent where the gap's acceleration with no contact force is not into
//! the plane ([`flight_is_consistent`]).
//!
//! Layout, one job each: [`switch`] (the switches on one contact: slip stop, Painlevé,
//! cone left, lift-off), [`landing`] (touchdowns, their impacts and settling speeds),
//! [`contacts`] (several contacts: second and third touchdowns, where an impact leaves
//! the body, grip, release, a surface leaving); here, the rule "on the plane"
//! ([`on_plane`]) and the state maps and checks they share.

mod contacts;
mod landing;
mod switch;

pub(super) use contacts::{grip, leave, release, second_touchdown, third_touchdown};
pub(super) use landing::touchdown;
pub(super) use switch::{cone_left, lift_off, painleve, slip_stop};

use nalgebra::Vector2;

use crate::body::Surface;
use crate::effects::Effect;
use crate::integrate::OdeSystem;
use crate::invariants::Invariants;
use crate::kinematics::Kinematics;
use crate::model::{Rolling, Sliding};
use crate::state::{self, State};

use crate::simulate::context::{ContactSet, Context};
use crate::simulate::numerics::{GAP_ACCEL_ROUNDOFF, SLIP_SEED};
use crate::simulate::outcome::{EventKind, EventRecord, Mode, Status};
use crate::simulate::phase::{
    FrictionlessPhase, RollingPhase, phase, set_reference, slip_has_stopped, slip_is_zero,
};
use crate::simulate::scene::ContactModel;

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

/// Makes `surface` the one in contact from t on, recording the change of surface (bodies
/// with contact spheres only).
fn touch(contacts: &mut ContactSet, surface: Surface, t: f64, events: &mut Vec<EventRecord>) {
    let from = std::mem::replace(&mut contacts.surface, surface);
    if from != surface {
        events.push(EventRecord {
            kind: EventKind::ContactSurface { from, to: surface },
            t,
        });
    }
}

/// Records a mode switch.
fn record_switch(events: &mut Vec<EventRecord>, t: f64, from: Mode, to: Mode) {
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
