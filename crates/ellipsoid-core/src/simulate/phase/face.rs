//! The face phase (docs/physics.md, "Rims": "Lying on the face"): the body lies on the
//! flat face its rim in contact bounds, under the law `model::Face` — Coulomb–Contensou
//! friction over the face's disc with the scene's μ (and contact law), none for the
//! frictionless model. Watches: N (an effect lifting the body: `transition::lift_off`)
//! and, with friction, the face's stop speed √(|v_f|² + (R Ω)²) falling to the stop
//! threshold, where slip and spin stop together and the body rests on its face.

use crate::body::Surface;
use crate::effects::Effect;
use crate::model::contensou::Law;
use crate::model::{Evaluation, Face, System};
use crate::state::{self, State};

use super::{Next, Phase};
use crate::simulate::context::{ContactSet, Context};
use crate::simulate::outcome::{EventKind, EventRecord, Mode};
use crate::simulate::scene::ContactModel;
use crate::simulate::transition::lift_off;

pub(in crate::simulate) struct FacePhase;

/// The face phase's watches.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(in crate::simulate) enum FaceWatch {
    /// g = N (loss of contact).
    Normal,
    /// g = √(|v_f|² + (R Ω)²) − the stop threshold (slip and spin stop).
    Stop,
}

impl Phase for FacePhase {
    const MODE: Mode = Mode::Face;
    type Law = Face;
    type Watch = FaceWatch;

    fn law<E>(ctx: &Context<'_, E>, contacts: &ContactSet) -> Face {
        let Surface::Rim(k) = contacts.surface else {
            unreachable!("the face phase follows a rim's flat landing")
        };
        let rim = &ctx.scene.body.rims()[k];
        let law = ctx.scene.disc.map_or(Law::Exact, |disc| disc.law);
        let friction = match ctx.scene.contact {
            ContactModel::Sliding { friction } | ContactModel::Coulomb { friction } => {
                Some((friction, law))
            }
            _ => None,
        };
        Face {
            center: rim.center,
            edge: rim.edge,
            radius: rim.radius,
            friction,
        }
    }

    fn watches<E>(ctx: &Context<'_, E>, contacts: &ContactSet) -> Vec<FaceWatch> {
        let stop = Self::law(ctx, contacts).friction.map(|_| FaceWatch::Stop);
        std::iter::once(FaceWatch::Normal).chain(stop).collect()
    }

    fn watch<E: Effect>(
        ctx: &Context<'_, E>,
        sys: &System<Face, E>,
        watch: FaceWatch,
        ev: &Evaluation,
        _y: &State,
    ) -> f64 {
        match watch {
            FaceWatch::Normal => ev.response.normal,
            FaceWatch::Stop => {
                let (slip, spin) = sys.contact.slip(&sys.body, &ev.kin);
                slip.norm().hypot(sys.contact.radius * spin)
                    - ctx.numerics.stop_threshold(&ev.kin, true)
            }
        }
    }

    fn on_event<E: Effect + Copy + 'static>(
        ctx: &Context<'_, E>,
        contacts: &mut ContactSet,
        watch: FaceWatch,
        t: &mut f64,
        y: &mut State,
        events: &mut Vec<EventRecord>,
    ) -> Next {
        match watch {
            FaceWatch::Normal => lift_off(ctx, contacts, Mode::Face, *t, y, events),
            FaceWatch::Stop => {
                // Slip and spin stop together: the body rests on its face, the kinetic
                // energy left below the threshold booked in W.
                let body = ctx.body(contacts);
                let omega = state::omega(y);
                let v = nalgebra::Vector2::new(y[state::VEL], y[state::VEL + 1]);
                y[state::WORK] += 0.5 * body.mass() * v.norm_squared()
                    + 0.5 * omega.dot(&(body.inertia() * omega));
                y[state::VEL] = 0.0;
                y[state::VEL + 1] = 0.0;
                y.fixed_rows_mut::<3>(state::OMEGA).fill(0.0);
                events.push(EventRecord {
                    kind: EventKind::SlipStop,
                    t: *t,
                });
                Next::Go(Mode::Face)
            }
        }
    }
}
