//! Contact phases: each declares its contact law as built from the scene (`Phase::law`;
//! the law's `ContactLaw::ROLLING` is its kinematics kind — whether v_G is a state or
//! follows from the no-slip constraint; z_G and v_Gz follow from the contact constraint in
//! every phase but flight, where they are states), its watch functions (an enum of its
//! own, matched exhaustively), and for each watch the transition it leads to
//! (`transition`, where every transition is written). A phase reads only its
//! [`Context`] — the scene, its numerics and effects —, the run's contact state
//! ([`ContactSet`], which only its transitions change) and the system it integrates; the
//! hybrid machine (`machine`) runs any of them through the registry [`phase`].
//!
//! A new phase touches four files: its module here; this file (its `mod` line, its
//! [`Mode`] and its arm of the registry [`phase`]); its transitions (`transition`); its
//! contact law (a module of `model`, named in `model/mod.rs`). The compiler lists every
//! match that must learn the new mode and watches. (The several-contact phases, the first added
//! this way, also needed the other contacts' normal forces and the law's own dissipated
//! power in `model::Response`, and their other surfaces in the [`ContactSet`].)
//!
//! | phase | law | watches (g falling through 0) | on the event |
//! |---|---|---|---|
//! | frictionless | F = N e3 | N | lift-off |
//! | sliding | Coulomb, F = N(e3 − μ ŝ) | N, v_C·s_ref, \|v_C\| − floor, Painlevé denominator | slip stop, Painlevé, lift-off |
//! | rolling | v_C = 0 | N, μN − \|F_h\| (Coulomb only) | cone left, lift-off |
//! | flight | F = 0 | gap z_G − h(ζ) + δz of the lowest surface | touchdown |
//! | viscous | F = N(e3 − μ_v v_C) | N, Painlevé denominator | lift-off, Painlevé |
//! | face | `model::Face`: Coulomb–Contensou over the face's disc | N, √(\|v_f\|² + (R Ω)²) − floor (with friction) | lift-off, rest on the face |
//! | two contacts, three contacts | each contact sliding or sticking (`model::Contacts`) | each N_i, each sliding slip − floor, each sticking hold, Painlevé denominator, another surface's gap | a surface leaves, a contact grips or slides, a third touches down; stop `slip_stopped`, `painleve`, or a fourth surface `several_contacts` |
//!
//! With contact spheres every contact phase also watches each other surface's gap
//! ([`touch_gap`]), whose touchdown is `transition::second_touchdown`.
//!
//! With a contact disc (`Scene::disc`) the sliding law is Coulomb–Contensou's and the
//! sliding phase watches N, √(\|v_C\|² + (R ω_n)²) − floor and the Painlevé denominator;
//! slip and spin stopping together ends the run (see `sliding`).

mod contacts;
mod face;
mod flight;
mod frictionless;
mod rolling;
mod sliding;
mod viscous;

use std::marker::PhantomData;

use crate::body::Surface;
use crate::effects::Effect;
use crate::error::ModelError;
use crate::geometry;
use crate::integrate::IntegrateError;
use crate::invariants::Invariants;
use crate::kinematics::Kinematics;
use crate::model::{ContactLaw, Evaluation, Response, System};
use crate::state::{EulerAngles, State};

use super::context::{ContactSet, Context};
use super::machine::{Segment, segment};
use super::outcome::{EventRecord, Status};
use super::recorder::Recorder;
use crate::columns::{Mode, Sample};

pub(super) use contacts::{ContactsPhase, above_stop, contacts_mode, grips, holds, normal};
pub(super) use face::FacePhase;
pub(super) use flight::FlightPhase;
pub(super) use frictionless::FrictionlessPhase;
pub(super) use rolling::RollingPhase;
pub(super) use sliding::{SlidingPhase, set_reference, slip_has_stopped, slip_is_zero};
pub(super) use viscous::ViscousPhase;

/// The registry: the phase of each mode.
pub(super) fn phase<E: Effect + Copy + 'static>(mode: Mode) -> &'static dyn AnyPhase<E> {
    match mode {
        Mode::Frictionless => &Registered::<FrictionlessPhase>(PhantomData),
        Mode::Sliding => &Registered::<SlidingPhase>(PhantomData),
        Mode::Rolling => &Registered::<RollingPhase>(PhantomData),
        Mode::Flight => &Registered::<FlightPhase>(PhantomData),
        Mode::TwoContacts => &Registered::<ContactsPhase<2>>(PhantomData),
        Mode::ThreeContacts => &Registered::<ContactsPhase<3>>(PhantomData),
        Mode::Viscous => &Registered::<ViscousPhase>(PhantomData),
        Mode::Face => &Registered::<FacePhase>(PhantomData),
    }
}

/// The other surfaces a contact phase watches (bodies with contact spheres): every
/// surface but the one in contact.
pub(super) fn other_surfaces<'c, E>(
    ctx: &'c Context<'_, E>,
    contacts: &ContactSet,
) -> impl Iterator<Item = Surface> + 'c {
    let touching = contacts.surface;
    ctx.scene.body.surfaces().filter(move |&s| s != touching)
}

/// The gap of `surface` while the body touches the plane with another, `ev` the contact
/// phase's evaluation, plus the gap's round-off: h_k(ζ) − h_j(ζ) + δz
/// (`geometry::height`; z_G = h_k in contact). Falling through zero, `surface` touches
/// down (`transition::second_touchdown`).
pub(super) fn touch_gap<E>(ctx: &Context<'_, E>, ev: &Evaluation, surface: Surface) -> f64 {
    let kin = &ev.kin;
    kin.contact.height - geometry::height(&ctx.scene.body, surface, kin.contact.zeta)
        + ctx.numerics.gap_resolution(kin)
}

/// Whether `surface`'s lowest material point moves down: v_Gz + e3·(R (ω × r_k)) below
/// minus its round-off (`Numerics::velocity_resolution`), r_k its lever arm from G. One at
/// rest (a body rolling about the line through both its contacts gives it zero, to
/// round-off: a dumbbell resting on the contacts of its two end spheres gives the ball
/// between them −1e-41 m/s) is watched from δz below instead: taken as a touchdown at
/// once, its null impact would lead back to the same phase and the same touchdown.
fn closing<E>(ctx: &Context<'_, E>, ev: &Evaluation, surface: Surface) -> bool {
    let kin = &ev.kin;
    let lever = geometry::Contact::of(&ctx.scene.body, surface, kin.contact.zeta, kin.omega).r;
    let v_n = kin.v_g.z + (kin.rot * kin.omega.cross(&lever)).z;
    v_n < -ctx.numerics.velocity_resolution(kin, lever.norm())
}

/// Multiple of the contact's angular acceleration at a segment's start taken as its bound
/// along the segment ([`contact_gap_curvature`]).
const CONTACT_TURN_MARGIN: f64 = 2.0;

/// A bound of |g̈| for the gap g = h_c(ζ) − h_k(ζ) of surface `other` while the body
/// touches the plane with c = `ev.kin.contact.surface` (docs/physics.md, "Flight"):
/// |ḧ_c| + |ḧ_k| (`geometry::height_acceleration_bound`) for |ω| ≤ w with
/// w² = 2(T + m g (z_G + L))/I_min, the energy at the segment's start above the lowest
/// z_G = −L can reach (no contact law or effect adds energy), and |ω̇| ≤ I_max w²/I_min +
/// [`CONTACT_TURN_MARGIN`] |ω̇| at the start: the contact's torque taken at twice its start
/// value, an estimate the guard (`Context::below_plane`) backs.
pub(super) fn contact_gap_curvature<E>(
    ctx: &Context<'_, E>,
    ev: &Evaluation,
    other: Surface,
) -> f64 {
    let body = &ctx.scene.body;
    let kin = &ev.kin;
    let inertia = body.inertia();
    let moments = inertia.symmetric_eigenvalues();
    let (i_min, i_max) = (moments.min(), moments.max());
    let m = body.mass();
    let reach = ctx.numerics.size() + body.com_offset().norm();
    let energy = 0.5 * m * kin.v_g.norm_squared()
        + 0.5 * kin.omega.dot(&(inertia * kin.omega))
        + m * ctx.scene.gravity * (kin.z_g() + reach);
    let w = (2.0 * energy.max(0.0) / i_min).sqrt();
    let w_dot = i_max * w * w / i_min + CONTACT_TURN_MARGIN * ev.response.omega_dot.norm();
    let tilt = geometry::ring_direction(kin.contact.zeta).1;
    geometry::height_acceleration_bound(body, kin.contact.surface, w, w_dot, tilt)
        + geometry::height_acceleration_bound(body, other, w, w_dot, tilt)
}

/// An event function of a segment: one of its phase's watches (by its index in
/// [`Phase::watches`]), an observable of the scene, or a section of the scene.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Slot {
    Phase(usize),
    Observe(usize),
    Section(usize),
    /// The guard: the deepest surface not in contact falling through the penetration
    /// tolerance (`Context::below_plane`).
    Guard,
    /// A rim in contact going flat (`flat::tilt`).
    Flat,
}

/// What a phase's event leads to.
pub(super) enum Next {
    /// The run ends with this status, its state in this mode.
    Stop(Status, Mode),
    /// The run goes on in this phase (the same one for a renewed state).
    Go(Mode),
}

/// A contact phase (see the module docs).
pub(super) trait Phase {
    const MODE: Mode;
    type Law: ContactLaw;
    /// Its watch functions.
    type Watch: Copy;
    /// Its contact law, as the scene and the contact state give it.
    fn law<E>(ctx: &Context<'_, E>, contacts: &ContactSet) -> Self::Law;
    /// Its watch functions (each falling through zero is an event).
    fn watches<E>(ctx: &Context<'_, E>, contacts: &ContactSet) -> Vec<Self::Watch>;
    /// The value of one of its watches at a state, `ev` its evaluation under `sys`.
    fn watch<E: Effect>(
        ctx: &Context<'_, E>,
        sys: &System<Self::Law, E>,
        watch: Self::Watch,
        ev: &Evaluation,
        y: &State,
    ) -> f64;
    /// The surface whose gap (its lowest point's height above the plane) `watch` is, if it
    /// is one: a gap at or below zero and closing where a segment starts is its event at
    /// once (the integrator finds only the zeros it crosses after t0).
    fn gap_of<E>(_ctx: &Context<'_, E>, _watch: Self::Watch, _ev: &Evaluation) -> Option<Surface> {
        None
    }
    /// A bound of |d²/dt²| of `watch` over a segment that starts at the evaluation `ev`,
    /// where the phase knows one (`integrate::Event::curvature`): its zeros are then found
    /// however long the integrator's steps. A contact phase's gap of another surface k,
    /// h_c(ζ) − h_k(ζ) (c the surface in contact): [`contact_gap_curvature`].
    fn curvature<E: Effect>(
        ctx: &Context<'_, E>,
        watch: Self::Watch,
        ev: &Evaluation,
    ) -> Option<f64> {
        let other = Self::gap_of(ctx, watch, ev)?;
        Some(contact_gap_curvature(ctx, ev, other))
    }
    /// What the event of `watch` at (t, y) leads to (`transition`); may change `y` (the
    /// state map at the switch), `t` (a touchdown taken back to gap = 0) and `contacts`
    /// (the surfaces in contact and their grip), and records what happened in `events`.
    fn on_event<E: Effect + Copy + 'static>(
        ctx: &Context<'_, E>,
        contacts: &mut ContactSet,
        watch: Self::Watch,
        t: &mut f64,
        y: &mut State,
        events: &mut Vec<EventRecord>,
    ) -> Next;
    /// Where the run goes when the integrator fails in this phase at (t, y), the last
    /// accepted state: a stop whose status says what that failure means physically
    /// (recorded in `events`, if anything), or on in a mode where the failure was a
    /// transition the phase's watches cannot see.
    fn on_failure<E: Effect + Copy + 'static>(
        _ctx: &Context<'_, E>,
        _contacts: &mut ContactSet,
        _t: &mut f64,
        _y: &mut State,
        error: IntegrateError,
        _events: &mut Vec<EventRecord>,
    ) -> Next {
        Next::Stop(
            Status::SolverFailure {
                mode: Self::MODE,
                error,
            },
            Self::MODE,
        )
    }
}

/// A phase seen through the scene's effects `E` (object-safe, for the registry).
pub(super) trait AnyPhase<E> {
    fn segment(
        &self,
        ctx: &Context<'_, E>,
        contacts: &ContactSet,
        t0: f64,
        y0: State,
        rec: &mut Recorder<'_>,
    ) -> Result<Segment, ModelError>;
    fn sample(
        &self,
        ctx: &Context<'_, E>,
        contacts: &ContactSet,
        t: f64,
        y: &State,
        prev: Option<&EulerAngles>,
    ) -> (Sample, Invariants);
    fn response(&self, ctx: &Context<'_, E>, contacts: &ContactSet, y: &State) -> Response;
    /// The kinematics of `y` under the phase's law.
    fn kinematics(&self, ctx: &Context<'_, E>, contacts: &ContactSet, y: &State) -> Kinematics;
    /// The first of the phase's gaps ([`Phase::gap_of`]) at or below zero and closing at
    /// `y`, by its watch number.
    fn overdue(&self, ctx: &Context<'_, E>, contacts: &ContactSet, y: &State) -> Option<usize>;
    /// [`Phase::on_event`] of its watch number `watch`.
    fn on_event(
        &self,
        ctx: &Context<'_, E>,
        contacts: &mut ContactSet,
        watch: usize,
        t: &mut f64,
        y: &mut State,
        events: &mut Vec<EventRecord>,
    ) -> Next;
    fn on_failure(
        &self,
        ctx: &Context<'_, E>,
        contacts: &mut ContactSet,
        t: &mut f64,
        y: &mut State,
        error: IntegrateError,
        events: &mut Vec<EventRecord>,
    ) -> Next;
}

struct Registered<P>(PhantomData<P>);

impl<P: Phase, E: Effect + Copy + 'static> AnyPhase<E> for Registered<P> {
    fn segment(
        &self,
        ctx: &Context<'_, E>,
        contacts: &ContactSet,
        t0: f64,
        y0: State,
        rec: &mut Recorder<'_>,
    ) -> Result<Segment, ModelError> {
        segment::<P, E>(ctx, contacts, t0, y0, rec)
    }
    fn sample(
        &self,
        ctx: &Context<'_, E>,
        contacts: &ContactSet,
        t: f64,
        y: &State,
        prev: Option<&EulerAngles>,
    ) -> (Sample, Invariants) {
        let sys = ctx.system::<P>(contacts);
        ctx.sample(&sys, contacts, P::MODE, t, y, &sys.evaluate(y), prev)
    }
    fn response(&self, ctx: &Context<'_, E>, contacts: &ContactSet, y: &State) -> Response {
        ctx.system::<P>(contacts).evaluate(y).response
    }
    fn kinematics(&self, ctx: &Context<'_, E>, contacts: &ContactSet, y: &State) -> Kinematics {
        ctx.system::<P>(contacts).evaluate(y).kin
    }
    fn overdue(&self, ctx: &Context<'_, E>, contacts: &ContactSet, y: &State) -> Option<usize> {
        let sys = ctx.system::<P>(contacts);
        let ev = sys.evaluate(y);
        // A gap watch is the gap plus its round-off δz.
        let dz = ctx.numerics.gap_resolution(&ev.kin);
        P::watches(ctx, contacts).into_iter().position(|w| {
            P::gap_of(ctx, w, &ev).is_some_and(|surface| {
                P::watch(ctx, &sys, w, &ev, y) < dz && closing(ctx, &ev, surface)
            })
        })
    }
    fn on_event(
        &self,
        ctx: &Context<'_, E>,
        contacts: &mut ContactSet,
        watch: usize,
        t: &mut f64,
        y: &mut State,
        events: &mut Vec<EventRecord>,
    ) -> Next {
        let watch = P::watches(ctx, contacts)[watch];
        P::on_event(ctx, contacts, watch, t, y, events)
    }
    fn on_failure(
        &self,
        ctx: &Context<'_, E>,
        contacts: &mut ContactSet,
        t: &mut f64,
        y: &mut State,
        error: IntegrateError,
        events: &mut Vec<EventRecord>,
    ) -> Next {
        P::on_failure(ctx, contacts, t, y, error, events)
    }
}
