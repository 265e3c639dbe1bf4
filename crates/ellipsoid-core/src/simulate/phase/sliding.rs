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

use nalgebra::Vector2;

use crate::effects::Effect;
use crate::integrate::{IntegrateError, Method};
use crate::model::sliding::SLIP_FLOOR;
use crate::model::{Evaluation, Sliding, System};
use crate::state::{self, State};

use super::flight::lift_off;
use super::rolling::after_slip_stop;
use super::{Next, Phase, Watch};
use crate::simulate::machine::Machine;
use crate::simulate::outcome::{EventKind, EventRecord, Mode, Status};
use crate::simulate::scene::ContactModel;

/// Below this the sliding normal-force denominator (≥ 1 without friction) has collapsed:
/// a solver failure there is the Painlevé singularity, N → ∞, and is reported as such.
const PAINLEVE_COLLAPSE: f64 = 1e-3;

/// A fixed-step method cannot resolve a slip smaller than friction removes in a few
/// steps (μ g h each, times the lever's gain): below this many of those, the slip counts
/// as stopped. Chosen so that the paper's RK4 at h = 1e-4 s stops the paper's sliding
/// scene where DOP853 does instead of chattering on (see docs/hard-cases.md).
const RK4_SLIP_STEPS: f64 = 10.0;

/// A located slip stop is taken only if |v_C| is within this many slip floors (see
/// [`slip_floor`]); otherwise v_C·s_ref changed sign because the slip direction turned by
/// more than 90° within one step, and sliding goes on.
const SLIP_ACCEPT: f64 = 2.0;

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
                let (floor, v_min) = slip_floor(m);
                if m.slide.contact.disc.is_some() {
                    m.slide.contact.stop_speed(&ev.kin)
                        - (floor * Sliding::speed_scale(&ev.kin)).max(v_min)
                } else {
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
            Watch::Slip | Watch::SlipFloor if !slip_has_stopped(m, y) => {
                // v_C·s_ref changed sign because the slip turned by more than 90° within
                // one (loose-tolerance) step, not because it stopped: go on sliding with
                // the reference renewed.
                let slip = m.slide.evaluate(y).kin.slip;
                if slip != Vector2::zeros() {
                    set_reference(y, slip.normalize());
                }
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

/// Whether a located slip-stop event is one: |v_C| within [`SLIP_ACCEPT`] times the
/// floor of [`slip_floor`].
pub(in crate::simulate) fn slip_has_stopped<E: Effect>(m: &Machine<'_, E>, y: &State) -> bool {
    let kin = m.slide.evaluate(y).kin;
    let (floor, v_min) = slip_floor(m);
    m.slide.contact.stop_speed(&kin)
        <= SLIP_ACCEPT * (floor * Sliding::speed_scale(&kin)).max(v_min)
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
