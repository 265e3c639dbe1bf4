//! The flight phase (docs/physics.md, "Flight", "Impact at touchdown", "Settling"): off
//! the plane G moves ballistically and the body turns torque-free (with the scene's
//! effects). Watch: the gap g = z_G − h(ζ) between the lowest point and the plane,
//! falling through −δz (`Numerics::gap_resolution`); the touchdown that follows is a
//! transition (`transition::touchdown`).

use crate::body::Surface;
use crate::effects::Effect;
use crate::model::{Evaluation, Flight, System};
use crate::state::State;

use super::{Next, Phase};
use crate::simulate::context::Context;
use crate::simulate::outcome::{EventRecord, Mode};
use crate::simulate::transition::touchdown;

pub(in crate::simulate) struct FlightPhase;

/// The flight phase's watch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(in crate::simulate) enum FlightWatch {
    /// g = z_G − h(ζ) + δz (touchdown).
    Gap,
}

impl Phase for FlightPhase {
    const MODE: Mode = Mode::Flight;
    type Law = Flight;
    type Watch = FlightWatch;

    fn law<E>(_ctx: &Context<'_, E>) -> Flight {
        Flight
    }

    fn watches<E>(_ctx: &Context<'_, E>) -> Vec<FlightWatch> {
        vec![FlightWatch::Gap]
    }

    fn watch<E: Effect>(
        ctx: &Context<'_, E>,
        _sys: &System<Flight, E>,
        watch: FlightWatch,
        ev: &Evaluation,
        _y: &State,
    ) -> f64 {
        match watch {
            FlightWatch::Gap => ev.kin.gap + ctx.numerics.gap_resolution(&ev.kin),
        }
    }

    fn gap_of<E>(_ctx: &Context<'_, E>, watch: FlightWatch, ev: &Evaluation) -> Option<Surface> {
        match watch {
            FlightWatch::Gap => Some(ev.kin.contact.surface),
        }
    }

    fn on_event<E: Effect + Copy + 'static>(
        ctx: &Context<'_, E>,
        watch: FlightWatch,
        t: &mut f64,
        y: &mut State,
        events: &mut Vec<EventRecord>,
    ) -> Next {
        match watch {
            FlightWatch::Gap => touchdown(ctx, t, y, events),
        }
    }
}
