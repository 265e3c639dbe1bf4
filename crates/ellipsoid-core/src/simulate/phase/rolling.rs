//! The rolling phase (docs/physics.md, model 3): no slip, F from the 3×3 constraint solve.
//! Watches: loss of contact (g = N) and, in the Coulomb model, the friction cone
//! (g = μN − |F_h|); leaving the cone starts sliding (`transition::cone_left`).

use crate::effects::Effect;
use crate::model::{Evaluation, Rolling, System};
use crate::state::State;

use super::{Next, Phase};
use crate::simulate::machine::Machine;
use crate::simulate::outcome::{EventRecord, Mode};
use crate::simulate::scene::ContactModel;
use crate::simulate::transition::{cone_left, lift_off};

pub(in crate::simulate) struct RollingPhase;

/// The rolling phase's watches.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(in crate::simulate) enum RollingWatch {
    /// g = N (loss of contact).
    Normal,
    /// g = μN − |F_h| (rolling leaves the friction cone), with μ.
    Cone(f64),
}

impl Phase for RollingPhase {
    const MODE: Mode = Mode::Rolling;
    type Law = Rolling;
    type Watch = RollingWatch;

    fn system<'m, E: Effect>(m: &'m Machine<'_, E>) -> &'m System<Rolling, E> {
        &m.roll
    }

    fn watches<E: Effect + Copy>(m: &Machine<'_, E>) -> Vec<RollingWatch> {
        let mut w = vec![RollingWatch::Normal];
        if let ContactModel::Coulomb { friction } = m.scene.contact {
            w.push(RollingWatch::Cone(friction));
        }
        w
    }

    fn watch<E: Effect + Copy>(
        _m: &Machine<'_, E>,
        watch: RollingWatch,
        ev: &Evaluation,
        _y: &State,
    ) -> f64 {
        match watch {
            RollingWatch::Normal => ev.response.normal,
            RollingWatch::Cone(mu) => Rolling::cone_margin(&ev.response, mu),
        }
    }

    fn on_event<E: Effect + Copy + 'static>(
        m: &Machine<'_, E>,
        watch: RollingWatch,
        t: &mut f64,
        y: &mut State,
        events: &mut Vec<EventRecord>,
    ) -> Next {
        match watch {
            RollingWatch::Normal => lift_off(m, Mode::Rolling, *t, y, events),
            RollingWatch::Cone(_) => cone_left(m, *t, y, events),
        }
    }
}
