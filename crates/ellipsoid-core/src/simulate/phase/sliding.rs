//! The sliding phase (docs/physics.md, model 2): Coulomb friction F = N(e3 − μ ŝ) while
//! the contact point slips. Watches: loss of contact (g = N), the slip stop, watched by
//! two functions — the sign change of v_C·s_ref and, for a slip that grazes zero, |v_C|
//! falling to a floor far below the tolerance (see `model::sliding`) — and a Painlevé
//! inconsistency (g = 1 + m u·I⁻¹(r × d_b), or a solver failure where that denominator
//! has collapsed). At a slip stop the pure sliding model ends; the Coulomb model sticks
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
    self, Action, Direction, Event, EventFn, IntegrateError, Method, Options, StopReason,
};
use crate::model::SlipBand;
use crate::model::sliding::SLIP_FLOOR;
use crate::model::{Evaluation, Kinematics, Sliding, System};
use crate::state::{self, State};

use super::flight::lift_off;
use super::rolling::{after_slip_stop, rolls_once_stuck};
use super::{Next, Phase, Watch};
use crate::simulate::machine::Machine;
use crate::simulate::outcome::{EventKind, EventRecord, Mode, Status};
use crate::simulate::scene::{ContactModel, Scene};

/// Below this the sliding normal-force denominator (≥ 1 without friction) has collapsed:
/// a solver failure there is the Painlevé singularity, N → ∞, and is reported as such.
const PAINLEVE_COLLAPSE: f64 = 1e-3;

/// A fixed-step method cannot resolve a slip smaller than friction removes in a few
/// steps (μ g h each, times the lever's gain): below this many of those, the slip counts
/// as stopped. Chosen so that the paper's RK4 at h = 1e-4 s stops the paper's sliding
/// scene where DOP853 does instead of chattering on (see docs/hard-cases.md).
const RK4_SLIP_STEPS: f64 = 10.0;

/// A located slip stop is taken at once if |v_C| is within this many slip floors (see
/// [`slip_floor`]); above that it is checked by [`confirmed_by_tight_solve`].
const SLIP_ACCEPT: f64 = 2.0;

/// The tight solve of [`confirmed_by_tight_solve`]: its tolerances relative to the
/// scene's (never below [`CONFIRM_RTOL_MIN`]); its horizon in units of the time s/(μ g)
/// Coulomb friction of μ m g needs to remove the slip s (a slip being removed at less than
/// a tenth of that rate is not stopping); the largest s it is tried for, in slip floors
/// (the stop leaves s to the sticking impulse, so s must stay a small multiple of the
/// integration error: a crossing at a larger slip is a turn, docs/hard-cases.md row 2d);
/// the growth of the slip that refutes the stop; and its step budget.
const CONFIRM_TIGHTEN: f64 = 1e-3;
const CONFIRM_RTOL_MIN: f64 = 1e-13;
const CONFIRM_HORIZON: f64 = 10.0;
const CONFIRM_BAND: f64 = 20.0;
const CONFIRM_GROWTH: f64 = 2.0;
const CONFIRM_MAX_STEPS: u64 = 10_000;

/// Slips below this many slip floors (or absolute tolerances), and below [`SLIP_BAND_CAP`]
/// of the speed scale, have their friction direction blended towards s_ref
/// ([`slip_band`]; docs/physics.md, "The slip stop, numerically"). Measured on random
/// stick–slip scenes: 10 floors leaves DOPRI5 trapped at 20 floors on some (slip held at
/// 7e-7 m/s for 0.03 s where DOP853's grows to 3e-3), 100 floors frees it; a band of 1e-4
/// of the speed scale (100 floors at rtol 1e-6) changes the stick–slip sequence, 1e-5
/// does not.
const SLIP_BAND_FLOORS: f64 = 100.0;
const SLIP_BAND_CAP: f64 = 1e-5;

pub(in crate::simulate) struct SlidingPhase;

impl Phase for SlidingPhase {
    const MODE: Mode = Mode::Sliding;
    type Law = Sliding;

    fn system<'m, E: Effect>(m: &'m Machine<'_, E>) -> &'m System<Sliding, E> {
        &m.slide
    }

    fn watches<E: Effect + Copy>(m: &Machine<'_, E>) -> Vec<Watch> {
        if m.slide.contact.disc.is_some() {
            return vec![Watch::Normal, Watch::SlipFloor, Watch::Painleve];
        }
        vec![
            Watch::Normal,
            Watch::Slip,
            Watch::SlipFloor,
            Watch::Painleve,
        ]
    }

    fn watch<E: Effect + Copy>(
        m: &Machine<'_, E>,
        watch: Watch,
        ev: &Evaluation,
        y: &State,
    ) -> f64 {
        match watch {
            Watch::Slip => Sliding::slip_along_reference(&ev.kin, y),
            Watch::SlipFloor => {
                if m.slide.contact.disc.is_some() {
                    m.slide.contact.stop_speed(&ev.kin) - stop_threshold(m, &ev.kin)
                } else {
                    let (floor, v_min) = slip_floor(m);
                    Sliding::slip_above_floor(&ev.kin, floor, v_min)
                }
            }
            Watch::Painleve => ev.response.painleve,
            _ => ev.response.normal,
        }
    }

    fn on_event<E: Effect + Copy + 'static>(
        m: &Machine<'_, E>,
        watch: Watch,
        t: f64,
        y: &mut State,
        events: &mut Vec<EventRecord>,
    ) -> Next {
        match watch {
            Watch::Painleve => {
                events.push(EventRecord {
                    kind: EventKind::Painleve,
                    t,
                });
                Next::Stop(Status::Painleve {
                    denominator: 0.0,
                    error: None,
                })
            }
            Watch::Slip | Watch::SlipFloor
                if !slip_has_stopped(m, y) && !confirmed_by_tight_solve(m, t, y) =>
            {
                // v_C·s_ref changed sign because the slip turned by more than 90° within
                // one (loose-tolerance) step, not because it stopped: go on sliding with
                // the reference renewed.
                *y = renewed(m, *y);
                Next::Go(Mode::Sliding)
            }
            Watch::Slip | Watch::SlipFloor => {
                events.push(EventRecord {
                    kind: EventKind::SlipStop,
                    t,
                });
                // With a contact disc, slip and spin stopped together (see the module docs).
                let (ContactModel::Coulomb { friction }, None) = (m.scene.contact, m.scene.disc)
                else {
                    return Next::Stop(Status::SlipStopped);
                };
                // Outside the cone the slip passes through zero and goes on (opposite to
                // the friction rolling would need).
                let next = after_slip_stop(m, friction, y);
                if next == Mode::Rolling {
                    events.push(EventRecord {
                        kind: EventKind::ModeSwitch {
                            from: Mode::Sliding,
                            to: next,
                        },
                        t,
                    });
                }
                Next::Go(next)
            }
            _ => lift_off(m, Mode::Sliding, t, y, events),
        }
    }

    fn on_failure<E: Effect + Copy>(
        m: &Machine<'_, E>,
        t: f64,
        y: &State,
        error: IntegrateError,
        events: &mut Vec<EventRecord>,
    ) -> Status {
        let denominator = m.slide.evaluate(y).response.painleve;
        if denominator < PAINLEVE_COLLAPSE {
            events.push(EventRecord {
                kind: EventKind::Painleve,
                t,
            });
            Status::Painleve {
                denominator,
                error: Some(error),
            }
        } else {
            Status::SolverFailure {
                mode: Mode::Sliding,
                error,
            }
        }
    }
}

/// The slip below which sliding counts as stopped: relative to |v_G| + |ω||r|, the
/// larger of [`SLIP_FLOOR`] and rtol (a slip below the integration error is no slip);
/// absolute, for fixed-step RK4, [`RK4_SLIP_STEPS`]·μ g h (a slip friction removes
/// within a few steps cannot be resolved).
pub(in crate::simulate) fn slip_floor<E>(m: &Machine<'_, E>) -> (f64, f64) {
    let scene = m.scene;
    let v_min = match (scene.solver.method, scene.contact.friction()) {
        (Method::Rk4 { h }, Some(friction)) => RK4_SLIP_STEPS * friction * scene.gravity * h,
        _ => 0.0,
    };
    (SLIP_FLOOR.max(scene.solver.rtol), v_min)
}

/// The band of slips whose friction direction is blended towards s_ref
/// (`Sliding::friction_direction`): [`SLIP_BAND_FLOORS`] slip floors (see [`slip_floor`])
/// or as many absolute tolerances (the error allowed in v_G alone, which dominates a slow
/// motion's), whichever is wider, and at most [`SLIP_BAND_CAP`] of the speed scale
/// |v_G| + |ω||r|; none for fixed-step RK4, whose absolute floor v_min already covers the
/// slips it cannot resolve.
pub(in crate::simulate) fn slip_band(scene: &Scene) -> SlipBand {
    if matches!(scene.solver.method, Method::Rk4 { .. }) {
        return SlipBand::NONE;
    }
    SlipBand {
        relative: SLIP_BAND_FLOORS * SLIP_FLOOR.max(scene.solver.rtol),
        absolute: SLIP_BAND_FLOORS * scene.solver.atol,
        cap: SLIP_BAND_CAP,
    }
}

/// The stop speed below which the slip counts as stopped, from [`slip_floor`]:
/// max(ε (|v_G| + |ω||r|), v_min) [m/s].
fn stop_threshold<E>(m: &Machine<'_, E>, kin: &Kinematics) -> f64 {
    let (floor, v_min) = slip_floor(m);
    (floor * Sliding::speed_scale(kin)).max(v_min)
}

/// Whether the slip at `y` has stopped: its stop speed within [`SLIP_ACCEPT`] times
/// [`stop_threshold`].
pub(in crate::simulate) fn slip_has_stopped<E: Effect>(m: &Machine<'_, E>, y: &State) -> bool {
    let kin = m.slide.evaluate(y).kin;
    m.slide.contact.stop_speed(&kin) <= SLIP_ACCEPT * stop_threshold(m, &kin)
}

/// Whether a located slip stop whose |v_C| = s exceeds [`SLIP_ACCEPT`] floors is one all
/// the same: the sliding law, integrated on from the located state by DOP853 at
/// [`CONFIRM_TIGHTEN`] times the scene's tolerances, brings the stop speed down to the
/// scene's slip floor within [`CONFIRM_HORIZON`]·s/(μ g), before it grows to
/// [`CONFIRM_GROWTH`]·s; or, for s inside the slip band (`Sliding::band_width`), grows to
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
/// and `after_slip_stop` decides between rolling and a new slip. A confirmed stop is
/// taken at the located time and state, as one within the floor is.
fn confirmed_by_tight_solve<E: Effect + Copy>(m: &Machine<'_, E>, t: f64, y: &State) -> bool {
    let scene = m.scene;
    let decel = m.slide.contact.friction * scene.gravity;
    if matches!(scene.solver.method, Method::Rk4 { .. }) || !(decel > 0.0) {
        return false;
    }
    let speed = |y: &State| m.slide.contact.stop_speed(&m.slide.evaluate(y).kin);
    let kin = m.slide.evaluate(y).kin;
    let s0 = m.slide.contact.stop_speed(&kin);
    if s0 > CONFIRM_BAND * stop_threshold(m, &kin) {
        return false;
    }
    let within_band = s0 <= m.slide.contact.band_width(&kin);
    let y0 = renewed(m, *y);
    let rtol = (scene.solver.rtol * CONFIRM_TIGHTEN).max(CONFIRM_RTOL_MIN);
    let mut options = Options::new(rtol, scene.solver.atol * CONFIRM_TIGHTEN);
    options.max_steps = CONFIRM_MAX_STEPS;
    options.stiffness_check = false;
    options.cancel = m.cancel.clone();
    let events = [
        stop_when_falling(Box::new(|_, y: &State| {
            SlidingPhase::watch(m, Watch::SlipFloor, &m.slide.evaluate(y), y)
        })),
        stop_when_falling(Box::new(|_, y: &State| CONFIRM_GROWTH * s0 - speed(y))),
    ];
    let t_end = t + CONFIRM_HORIZON * s0 / decel;
    integrate::integrate(
        Method::Dop853,
        &m.slide,
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
            within_band
                && m.slide.contact.disc.is_none()
                && rolls_once_stuck(m, m.slide.contact.friction, &mut { *y })
        }
        _ => false,
    })
}

/// `y` with the slip reference s_ref set to the slip's direction (kept where the slip is
/// zero): the sliding law's friction then opposes the slip again, as it must after a
/// located crossing, where v_C·s_ref = 0.
fn renewed<E: Effect>(m: &Machine<'_, E>, mut y: State) -> State {
    let slip = m.slide.evaluate(&y).kin.slip;
    if slip != Vector2::zeros() {
        set_reference(&mut y, slip.normalize());
    }
    y
}

/// A terminal event at g falling through zero.
fn stop_when_falling(g: EventFn<'_, { state::DIM }>) -> Event<'_, { state::DIM }> {
    Event {
        g,
        direction: Direction::Falling,
        action: Action::Stop,
    }
}

/// Whether the material contact point's slip is zero to round-off.
pub(in crate::simulate) fn slip_is_zero<E: Effect>(m: &Machine<'_, E>, y: &State) -> bool {
    let kin = m.slide.evaluate(y).kin;
    Sliding::direction(&kin, Vector2::zeros()) == Vector2::zeros()
}

/// Sets the slip reference direction s_ref of the state.
pub(in crate::simulate) fn set_reference(y: &mut State, s: Vector2<f64>) {
    y[state::SLIP_REF] = s.x;
    y[state::SLIP_REF + 1] = s.y;
}
