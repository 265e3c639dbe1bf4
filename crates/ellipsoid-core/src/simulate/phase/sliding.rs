//! The sliding phase (docs/physics.md, model 2): Coulomb friction F = N(e3 − μ ŝ) while
//! the contact point slips. Watches: loss of contact (g = N), the slip stop, watched by
//! two functions — the sign change of v_C·s_ref and, for a slip that grazes zero, |v_C|
//! falling to a floor far below the tolerance (see `model::sliding`) — and a Painlevé
//! inconsistency (the denominator 1 + m u·I⁻¹(r × d_b) collapsing to `PAINLEVE_COLLAPSE`,
//! or a solver failure below it). At a slip stop the pure sliding model ends; the Coulomb model sticks
//! (`rolling::after_slip_stop`).
//!
//! With a contact disc (Coulomb–Contensou friction, `model::contensou`) the law is smooth
//! through v_C = 0 while the spin ω_n = ω·e3 is not zero: there is no slip stop then. The
//! one stop is v_C and ω_n vanishing together, where the law is set-valued: it is watched
//! as √(|v_C|² + (R ω_n)²) falling to the slip floor, and there the run ends with status
//! `slip_stopped`, in the sliding and the Coulomb model alike (rolling without spin,
//! which would need the disc's set of static friction forces and torques, is not
//! simulated).

use std::ops::ControlFlow;

use nalgebra::Vector2;

use crate::effects::Effect;
use crate::integrate::{
    self, Action, Direction, Event, EventFn, IntegrateError, Method, StopReason,
};
use crate::kinematics::Kinematics;
use crate::model::{Evaluation, Sliding, System};
use crate::state::{self, State};

use super::{Next, Phase, other_surfaces, touch_gap};
use crate::body::Surface;
use crate::simulate::context::{ContactSet, Context};
use crate::simulate::numerics::{
    CONFIRM_GROWTH, CONFIRM_HORIZON, PAINLEVE_COLLAPSE, SLIP_RATE_FACTOR,
};
use crate::simulate::outcome::{EventRecord, Mode, Status};
use crate::simulate::transition::{
    lift_off, painleve, renew_reference, rolls_once_stuck, second_touchdown, slip_stop,
};

pub(in crate::simulate) struct SlidingPhase;

/// The sliding phase's watches.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(in crate::simulate) enum SlidingWatch {
    /// g = N (loss of contact).
    Normal,
    /// g = v_C·s_ref (slip stop).
    Slip,
    /// g = |v_C| − max(ε·scale, v_min), or with a contact disc the stop speed less its
    /// threshold (a grazing slip stop; see [`slip_floor`]).
    SlipFloor,
    /// g = Painlevé denominator − [`PAINLEVE_COLLAPSE`].
    Painleve,
    /// Another surface's gap ([`touch_gap`]).
    Touch(Surface),
}

impl Phase for SlidingPhase {
    const MODE: Mode = Mode::Sliding;
    type Law = Sliding;
    type Watch = SlidingWatch;

    fn law<E>(ctx: &Context<'_, E>, _contacts: &ContactSet) -> Sliding {
        Self::sliding(ctx)
    }

    fn watches<E>(ctx: &Context<'_, E>, contacts: &ContactSet) -> Vec<SlidingWatch> {
        // A contact disc has no sign change of v_C·s_ref to watch (see the module docs).
        let slip = ctx.scene.disc.is_none().then_some(SlidingWatch::Slip);
        std::iter::once(SlidingWatch::Normal)
            .chain(slip)
            .chain([SlidingWatch::SlipFloor, SlidingWatch::Painleve])
            .chain(other_surfaces(ctx, contacts).map(SlidingWatch::Touch))
            .collect()
    }

    fn watch<E: Effect>(
        ctx: &Context<'_, E>,
        sys: &System<Sliding, E>,
        watch: SlidingWatch,
        ev: &Evaluation,
        y: &State,
    ) -> f64 {
        match watch {
            SlidingWatch::Normal => ev.response.normal,
            SlidingWatch::Slip => Sliding::slip_along_reference(&ev.kin, y),
            SlidingWatch::SlipFloor => {
                if sys.contact.disc.is_some() {
                    sys.contact.stop_speed(&ev.kin) - ctx.numerics.stop_threshold(&ev.kin, true)
                } else {
                    let n = &ctx.numerics;
                    Sliding::slip_above_floor(&ev.kin, n.slip_floor, n.v_min)
                }
            }
            SlidingWatch::Painleve => ev.response.painleve - PAINLEVE_COLLAPSE,
            SlidingWatch::Touch(surface) => touch_gap(ctx, ev, surface),
        }
    }

    fn gap_of<E>(_ctx: &Context<'_, E>, watch: SlidingWatch, _ev: &Evaluation) -> Option<Surface> {
        match watch {
            SlidingWatch::Touch(surface) => Some(surface),
            _ => None,
        }
    }

    fn on_event<E: Effect + Copy + 'static>(
        ctx: &Context<'_, E>,
        contacts: &mut ContactSet,
        watch: SlidingWatch,
        t: &mut f64,
        y: &mut State,
        events: &mut Vec<EventRecord>,
    ) -> Next {
        match watch {
            SlidingWatch::Normal => lift_off(ctx, contacts, Mode::Sliding, *t, y, events),
            SlidingWatch::Painleve => painleve(
                Mode::Sliding,
                ctx.system::<Self>(contacts).evaluate(y).response.painleve,
                None,
                *t,
                events,
            ),
            SlidingWatch::Touch(surface) => {
                second_touchdown(ctx, contacts, Mode::Sliding, surface, t, y, events)
            }
            // Taken at once within the floor, else confirmed by a tight solve; one not
            // confirmed is a turn of the slip by more than 90° within a loose step.
            SlidingWatch::Slip | SlidingWatch::SlipFloor => {
                let sys = ctx.system::<Self>(contacts);
                let kin = sys.evaluate(y).kin;
                let speed = sys.contact.stop_speed(&kin);
                let disc = sys.contact.disc.is_some();
                let confirmed = ctx.numerics.has_stopped(speed, &kin, disc)
                    || (ctx.numerics.may_confirm(speed, &kin, disc)
                        && confirmed_by_tight_solve(ctx, contacts, &sys, *t, y));
                slip_stop(ctx, contacts, confirmed, *t, y, events)
            }
        }
    }

    /// A failure where the Painlevé denominator collapsed is that singularity
    /// ([`painleve`]). A `FastRate` failure whose fastest rate ρ is the relaxation of a
    /// small slip's direction, ρ ≤ [`SLIP_RATE_FACTOR`]·μN/(m|v_C|), is a slip stop that
    /// no watch sees: with the friction rolling needs at the edge of the cone (measured
    /// 2e-4 of μN beyond it), the slip neither falls to the floor nor crosses zero nor
    /// grows, and that rate, growing as the slip shrinks, holds an explicit method's steps
    /// at its stability boundary (docs/physics.md, "The slip stop, numerically"). The
    /// stop is taken at the last accepted state, where `transition::on_plane` decides
    /// between rolling and a new slip. Any other failure is a solver failure.
    fn on_failure<E: Effect + Copy + 'static>(
        ctx: &Context<'_, E>,
        contacts: &mut ContactSet,
        t: &mut f64,
        y: &mut State,
        error: IntegrateError,
        events: &mut Vec<EventRecord>,
    ) -> Next {
        let sys = ctx.system::<Self>(contacts);
        let ev = sys.evaluate(y);
        if ev.response.painleve < PAINLEVE_COLLAPSE {
            return painleve(Mode::Sliding, ev.response.painleve, Some(error), *t, events);
        }
        if let IntegrateError::FastRate { rate, .. } = error
            && sys.contact.disc.is_none()
        {
            let slip = sys.contact.stop_speed(&ev.kin);
            let relaxation = sys.contact.friction * ev.response.normal / (sys.body.mass() * slip);
            if rate <= SLIP_RATE_FACTOR * relaxation {
                return slip_stop(ctx, contacts, true, *t, y, events);
            }
        }
        Next::Stop(
            Status::SolverFailure {
                mode: Mode::Sliding,
                error,
            },
            Mode::Sliding,
        )
    }
}

impl SlidingPhase {
    /// Coulomb's law with the scene's μ (Coulomb–Contensou's with a contact disc) and
    /// the numerics' slip band (the phase's law, which its contact state does not enter).
    pub(in crate::simulate) fn sliding<E>(ctx: &Context<'_, E>) -> Sliding {
        Sliding {
            friction: ctx.scene.contact.friction().unwrap_or(0.0),
            disc: ctx.scene.disc,
            band: ctx.numerics.band,
        }
    }
}

/// Whether the slip (and a contact disc's spin) at `y` on `contacts` has stopped
/// (`Numerics::has_stopped`).
pub(in crate::simulate) fn slip_has_stopped<E: Effect + Copy>(
    ctx: &Context<'_, E>,
    contacts: &ContactSet,
    y: &State,
) -> bool {
    let sys = ctx.system::<SlidingPhase>(contacts);
    let kin = sys.evaluate(y).kin;
    let disc = sys.contact.disc.is_some();
    ctx.numerics
        .has_stopped(sys.contact.stop_speed(&kin), &kin, disc)
}

/// Whether a located slip stop whose stop speed s is above the accepted floor is one all
/// the same (tried for a point contact's crossing within `Numerics::may_confirm`, and for a
/// contact disc where its generalised slip enters the slip band): the sliding law, integrated on from the located state by DOP853 at tighter
/// tolerances (`Numerics::confirm_options`), brings the stop speed down to the scene's
/// slip floor within [`CONFIRM_HORIZON`]·s/(μ g), before it grows to
/// [`CONFIRM_GROWTH`]·s; or, for s inside the slip band (`SlipBand::width`), grows to
/// that first while rolling would hold at the located state (`rolls_once_stuck`)
/// (docs/physics.md, "The slip stop, numerically").
///
/// Why: at a true stop the residual |v_C| at the crossing is integration error, not slip.
/// Where v_C·s_ref = 0 the slip left is its sideways part, a stiff component near v_C = 0
/// (friction relaxes the slip's direction at the rate ~μ g/|v_C|) that carries error in
/// from earlier steps: measured at DOPRI5's crossings, 2.5–5 floors, 30× the step's own
/// error estimate and 5× the dense output's error against a fine re-integration of the
/// step. A fixed acceptance of 2 floors refused those stops, and the run slid on at zero
/// slip, crossing again and again with collapsing steps (docs/hard-cases.md row 2e).
/// That residue scales with the tolerance, so a solve 1000× tighter takes it far below
/// the scene's floor, while a slip that a loose step turned through 90° (row 2d) is real
/// and does not fall to the floor. A slip inside the band whose direction integration
/// error set may also grow from the crossing where the contact's mobility is anisotropic,
/// although rolling holds (measured: 6–14 floors at DOPRI5's crossings, doubling within
/// 1e-7 s, refused 10 000 times in a row; docs/hard-cases.md row 2g): that is a stop too,
/// and `transition::on_plane` decides between rolling and a new slip. A confirmed stop is
/// taken at the located time and state, as one within the floor is.
fn confirmed_by_tight_solve<E: Effect + Copy + 'static>(
    ctx: &Context<'_, E>,
    contacts: &ContactSet,
    sys: &System<Sliding, E>,
    t: f64,
    y: &State,
) -> bool {
    let law = &sys.contact;
    let decel = law.friction * ctx.scene.gravity;
    let speed = |y: &State| law.stop_speed(&sys.evaluate(y).kin);
    let kin = sys.evaluate(y).kin;
    let s0 = law.stop_speed(&kin);
    let disc = law.disc.is_some();
    if !(decel > 0.0) {
        return false;
    }
    let within_band = s0 <= law.band.width(&kin);
    let mut y0 = *y;
    renew_reference(ctx, contacts, &mut y0);
    let mut options = ctx.numerics.confirm_options();
    options.cancel = ctx.cancel.clone();
    let events = [
        stop_when_falling(Box::new(|_, y: &State| {
            SlidingPhase::watch(ctx, sys, SlidingWatch::SlipFloor, &sys.evaluate(y), y)
        })),
        stop_when_falling(Box::new(|_, y: &State| CONFIRM_GROWTH * s0 - speed(y))),
    ];
    let t_end = t + CONFIRM_HORIZON * s0 / decel;
    integrate::integrate(
        Method::Dop853,
        sys,
        t,
        y0,
        t_end,
        &options,
        &events,
        &[],
        &mut |_, _| ControlFlow::Continue(()),
    )
    .is_ok_and(|sol| match sol.stop {
        StopReason::Event { index: 0 } => true,
        StopReason::Event { index: 1 } => {
            within_band && !disc && rolls_once_stuck(ctx, contacts, &mut { *y })
        }
        _ => false,
    })
}

/// A terminal event at g falling through zero.
fn stop_when_falling(g: EventFn<'_, { state::DIM }>) -> Event<'_, { state::DIM }> {
    Event {
        g,
        direction: Direction::Falling,
        action: Action::Stop,
        curvature: None,
    }
}

/// Whether the material contact point's slip is zero to round-off.
pub(in crate::simulate) fn slip_is_zero<E>(
    ctx: &Context<'_, E>,
    contacts: &ContactSet,
    y: &State,
) -> bool {
    let kin = Kinematics::new(&ctx.body(contacts), y, false);
    Sliding::direction(&kin, Vector2::zeros()) == Vector2::zeros()
}

/// Sets the slip reference direction s_ref of the state.
pub(in crate::simulate) fn set_reference(y: &mut State, s: Vector2<f64>) {
    y[state::SLIP_REF] = s.x;
    y[state::SLIP_REF + 1] = s.y;
}
