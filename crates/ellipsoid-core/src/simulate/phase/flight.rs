//! The flight phase (docs/physics.md, "Flight", "Impact at touchdown", "Settling"): off
//! the plane G moves ballistically and the body turns torque-free (with the scene's
//! effects). Watches: each surface's gap g_k = z_G − h_k(ζ) falling through −δz
//! (`Numerics::gap_resolution`); the touchdown that follows is a transition
//! (`transition::touchdown`). Each surface is watched on its own, not the lowest point's
//! gap min_k g_k: a surface's gap that dips through the plane and out within one flight
//! step while another's crosses at the step's end leaves the minimum with one sign change
//! at the ends and its dip, between the scan points, unseen (a body with three contact
//! spheres passed one through the plane by 3e-5 m, docs/hard-cases.md row 33); each g_k
//! alone is smooth, and the driver's scan finds its dip.

use crate::body::Surface;
use crate::effects::Effect;
use crate::geometry;
use crate::model::{Evaluation, Flight, System};
use crate::state::{self, State};

use super::{Next, Phase};
use crate::simulate::context::{ContactSet, Context};
use crate::simulate::outcome::{EventRecord, Mode};
use crate::simulate::transition::touchdown;

pub(in crate::simulate) struct FlightPhase;

/// The factor on the effects' load at a flight segment's start in the bound of a gap's
/// acceleration ([`Phase::curvature`]).
const LOAD_MARGIN: f64 = 2.0;

/// The flight phase's watch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(in crate::simulate) enum FlightWatch {
    /// g_k = z_G − h_k(ζ) + δz of a surface (its touchdown).
    Gap(Surface),
}

impl Phase for FlightPhase {
    const MODE: Mode = Mode::Flight;
    type Law = Flight;
    type Watch = FlightWatch;

    fn law<E>(_ctx: &Context<'_, E>, _contacts: &ContactSet) -> Flight {
        Flight
    }

    fn watches<E>(ctx: &Context<'_, E>, _contacts: &ContactSet) -> Vec<FlightWatch> {
        ctx.scene.body.surfaces().map(FlightWatch::Gap).collect()
    }

    fn watch<E: Effect>(
        ctx: &Context<'_, E>,
        _sys: &System<Flight, E>,
        watch: FlightWatch,
        ev: &Evaluation,
        y: &State,
    ) -> f64 {
        let FlightWatch::Gap(surface) = watch;
        let height = geometry::height(&ctx.scene.body, surface, ev.kin.contact.zeta);
        y[state::HEIGHT] - height + ctx.numerics.gap_resolution(&ev.kin)
    }

    fn gap_of<E>(_ctx: &Context<'_, E>, watch: FlightWatch, _ev: &Evaluation) -> Option<Surface> {
        let FlightWatch::Gap(surface) = watch;
        Some(surface)
    }

    /// |g̈_k| ≤ |z̈_G| + |ḧ_k|: z̈_G = −g + f_z/m, and h_k's bound for a body turning at
    /// |ω| ≤ √(2T/I_min), T = ½ ωᵀIω (constant torque-free; air drag only lowers it), with
    /// |ω̇| ≤ (I_max |ω|² + |τ|)/I_min from I ω̇ = (Iω) × ω + τ
    /// (`geometry::height_acceleration_bound`); the effects' force and torque taken at
    /// [`LOAD_MARGIN`] times their values at the segment's start (air drag, the only
    /// effect in flight, grows with the speed a fall gains).
    fn curvature<E: Effect>(
        ctx: &Context<'_, E>,
        watch: FlightWatch,
        ev: &Evaluation,
    ) -> Option<f64> {
        let FlightWatch::Gap(surface) = watch;
        let body = &ctx.scene.body;
        let inertia = body.inertia();
        let moments = inertia.symmetric_eigenvalues();
        let (i_min, i_max) = (moments.min(), moments.max());
        let omega = ev.kin.omega;
        let w = (omega.dot(&(inertia * omega)) / i_min).sqrt();
        let w_dot = (i_max * w * w + LOAD_MARGIN * ev.load.torque.norm()) / i_min;
        let z_acc = ctx.scene.gravity + LOAD_MARGIN * ev.load.force.norm() / body.mass();
        let tilt = geometry::ring_direction(ev.kin.contact.zeta).1;
        Some(z_acc + geometry::height_acceleration_bound(body, surface, w, w_dot, tilt))
    }

    fn on_event<E: Effect + Copy + 'static>(
        ctx: &Context<'_, E>,
        contacts: &mut ContactSet,
        watch: FlightWatch,
        t: &mut f64,
        y: &mut State,
        events: &mut Vec<EventRecord>,
    ) -> Next {
        let FlightWatch::Gap(surface) = watch;
        touchdown(ctx, contacts, surface, t, y, events)
    }
}
