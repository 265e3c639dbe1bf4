//! The rolling phase (docs/physics.md, model 3): no slip, F from the 3×3 constraint solve.
//! Watches: loss of contact (g = N) and, in the Coulomb model, the friction cone
//! (g = μN − |F_h|); leaving the cone starts sliding opposite to the friction rolling
//! needed.

use nalgebra::Vector2;

use crate::effects::Effect;
use crate::integrate::OdeSystem;
use crate::model::{Evaluation, Kinematics, Rolling, Sliding, System};
use crate::state;
use crate::state::State;

use super::flight::lift_off;
use super::sliding::set_reference;
use super::{Next, Phase, Watch};
use crate::simulate::machine::Machine;
use crate::simulate::outcome::{EventKind, EventRecord, Mode};
use crate::simulate::scene::ContactModel;

pub(in crate::simulate) struct RollingPhase;

impl Phase for RollingPhase {
    const MODE: Mode = Mode::Rolling;
    type Law = Rolling;

    fn system<'m, E: Effect>(m: &'m Machine<'_, E>) -> &'m System<Rolling, E> {
        &m.roll
    }

    fn watches<E: Effect + Copy>(m: &Machine<'_, E>) -> Vec<Watch> {
        let mut w = vec![Watch::Normal];
        if let ContactModel::Coulomb { friction } = m.scene.contact {
            w.push(Watch::Cone(friction));
        }
        w
    }

    fn watch<E: Effect + Copy>(
        _m: &Machine<'_, E>,
        watch: Watch,
        ev: &Evaluation,
        _y: &State,
    ) -> f64 {
        match watch {
            Watch::Cone(mu) => Rolling::cone_margin(&ev.response, mu),
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
        if let Watch::Cone(_) = watch {
            start_sliding_from_rest(m, y);
            events.push(EventRecord {
                kind: EventKind::ModeSwitch {
                    from: Mode::Rolling,
                    to: Mode::Sliding,
                },
                t,
            });
            Next::Go(Mode::Sliding)
        } else {
            lift_off(m, Mode::Rolling, t, y, events)
        }
    }
}

/// At zero slip under Coulomb friction (a residual slip removed by [`Rolling::stick`]):
/// roll if the cone holds (|F_h| ≤ μN), else start sliding opposite to the friction
/// rolling would need.
pub(in crate::simulate) fn after_slip_stop<E: Effect>(
    m: &Machine<'_, E>,
    mu: f64,
    y: &mut State,
) -> Mode {
    if rolls_once_stuck(m, mu, y) {
        Mode::Rolling
    } else {
        start_sliding_from_rest(m, y);
        Mode::Sliding
    }
}

/// Removes the slip of `y` (`Rolling::stick`, onto the rolling constraint) and tells
/// whether rolling holds there: the friction it needs within the cone, μN − |F_h| ≥ 0.
pub(in crate::simulate) fn rolls_once_stuck<E: Effect>(
    m: &Machine<'_, E>,
    mu: f64,
    y: &mut State,
) -> bool {
    Rolling::stick(&m.scene.body, y);
    m.roll.project(y);
    Rolling::cone_margin(&m.roll.evaluate(y).response, mu) >= 0.0
}

/// Sets the slip reference to −F_h/|F_h| of the rolling contact force: the slip that
/// develops when rolling fails opposes the friction it needed. The slip starts as
/// [`SLIP_SEED`] of the speed scale along that direction, not as zero: the sliding law's
/// watch g = v_C·s_ref then starts positive, so a slip that round-off turns against s_ref
/// is a located crossing (a stop), never a run on with friction along the slip
/// (docs/physics.md, "Friction along the slip, and the onset's seed").
fn start_sliding_from_rest<E: Effect>(m: &Machine<'_, E>, y: &mut State) {
    let f_h = m.roll.evaluate(y).response.force.xy();
    let s = if f_h.norm() > 0.0 {
        -f_h.normalize()
    } else {
        Vector2::x()
    };
    set_reference(y, s);
    let seed = s * (SLIP_SEED * Sliding::speed_scale(&Kinematics::new(&m.scene.body, y, false)));
    // E + W stays exact: the seed's kinetic energy m (v_G·δv + |δv|²/2) is booked in W.
    let v = state::velocity(y);
    y[state::WORK] -= m.scene.body.mass() * (v.dot(&seed) + 0.5 * seed.norm_squared());
    y[state::VEL] += seed.x;
    y[state::VEL + 1] += seed.y;
}

/// The slip a sliding onset starts with, relative to the speed scale |v_G| + |ω||r|: ten
/// times the round-off bound of `model::sliding` (below it the law takes s_ref for the
/// slip's direction), far below every slip floor (≥ 1e-10).
const SLIP_SEED: f64 = 1e-12;
