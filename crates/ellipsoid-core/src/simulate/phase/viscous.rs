//! The viscous sliding phase (docs/physics.md, "Viscous sliding"): F = N(e3 − μ_v v_C),
//! smooth through v_C = 0, so it has no slip stop. Watches: loss of contact (g = N,
//! `transition::lift_off`) and a Painlevé inconsistency (the denominator
//! 1 + m u·I⁻¹(r × d_b) collapsing to `PAINLEVE_COLLAPSE`, as in the sliding phase). A
//! body with contact spheres is refused under this model (`Scene::validate`), so there
//! is no other surface to watch.

use crate::effects::Effect;
use crate::model::{Evaluation, System, Viscous};
use crate::state::State;

use super::{Next, Phase};
use crate::simulate::context::{ContactSet, Context};
use crate::simulate::numerics::PAINLEVE_COLLAPSE;
use crate::simulate::outcome::{EventRecord, Mode};
use crate::simulate::scene::ContactModel;
use crate::simulate::transition::{lift_off, painleve};

pub(in crate::simulate) struct ViscousPhase;

/// The viscous phase's watches.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(in crate::simulate) enum ViscousWatch {
    /// g = N (loss of contact).
    Normal,
    /// g = Painlevé denominator − [`PAINLEVE_COLLAPSE`].
    Painleve,
}

impl Phase for ViscousPhase {
    const MODE: Mode = Mode::Viscous;
    type Law = Viscous;
    type Watch = ViscousWatch;

    /// The viscous law with the scene's μ_v (0 under another model).
    fn law<E>(ctx: &Context<'_, E>, _contacts: &ContactSet) -> Viscous {
        let coefficient = match ctx.scene.contact {
            ContactModel::Viscous { viscous_friction } => viscous_friction,
            _ => 0.0,
        };
        Viscous { coefficient }
    }

    fn watches<E>(_ctx: &Context<'_, E>, _contacts: &ContactSet) -> Vec<ViscousWatch> {
        vec![ViscousWatch::Normal, ViscousWatch::Painleve]
    }

    fn watch<E: Effect>(
        _ctx: &Context<'_, E>,
        _sys: &System<Viscous, E>,
        watch: ViscousWatch,
        ev: &Evaluation,
        _y: &State,
    ) -> f64 {
        match watch {
            ViscousWatch::Normal => ev.response.normal,
            ViscousWatch::Painleve => ev.response.painleve - PAINLEVE_COLLAPSE,
        }
    }

    fn on_event<E: Effect + Copy + 'static>(
        ctx: &Context<'_, E>,
        contacts: &mut ContactSet,
        watch: ViscousWatch,
        t: &mut f64,
        y: &mut State,
        events: &mut Vec<EventRecord>,
    ) -> Next {
        match watch {
            ViscousWatch::Normal => lift_off(ctx, contacts, Mode::Viscous, *t, y, events),
            ViscousWatch::Painleve => painleve(
                Mode::Viscous,
                ctx.system::<Self>(contacts).evaluate(y).response.painleve,
                None,
                *t,
                events,
            ),
        }
    }
}
