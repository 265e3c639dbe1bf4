//! The flight phase (docs/physics.md, "Flight", "Impact at touchdown", "Settling"): off
//! the plane G moves ballistically and the body turns torque-free (with the scene's
//! effects). Watch: the gap g = z_G − h(ζ) between the lowest point and the plane. At
//! touchdown the impact law (`crate::impact`) of the scene's contact model gives the
//! velocities after the impact, its energy loss is booked in W, and the body flies on,
//! or, when the rebound is below the settling speed, contact becomes persistent.
//!
//! Lift-off ([`lift_off`]) is the contact phases' loss-of-contact event when the scene
//! says `on_lift_off = "fly"`.

use crate::effects::Effect;
use crate::impact::{self, Approach, Tangential};
use crate::integrate::OdeSystem;
use crate::invariants::Invariants;
use crate::model::{Evaluation, Flight, Kinematics, Rolling, System};
use crate::state::{self, State};

use super::rolling::after_slip_stop;
use super::sliding::{set_reference, slip_has_stopped, slip_is_zero};
use super::{Next, Phase, Watch, phase};
use crate::simulate::machine::Machine;
use crate::simulate::outcome::{EventKind, EventRecord, ImpactReport, Mode, Status};
use crate::simulate::scene::{ContactModel, LiftOff};

/// Round-off of the gap z_G − h(ζ), in units of ε (|z_G| + L) (see [`gap_resolution`]).
const GAP_ROUNDOFF: f64 = 4.0;

pub(in crate::simulate) struct FlightPhase;

impl Phase for FlightPhase {
    const MODE: Mode = Mode::Flight;
    type Law = Flight;

    fn system<'m, E: Effect>(m: &'m Machine<'_, E>) -> &'m System<Flight, E> {
        &m.fly
    }

    fn watches<E: Effect + Copy>(_m: &Machine<'_, E>) -> Vec<Watch> {
        vec![Watch::Gap]
    }

    fn watch<E: Effect + Copy>(
        m: &Machine<'_, E>,
        _watch: Watch,
        ev: &Evaluation,
        _y: &State,
    ) -> f64 {
        ev.kin.gap + gap_resolution(m, &ev.kin)
    }

    fn on_event<E: Effect + Copy + 'static>(
        m: &Machine<'_, E>,
        _watch: Watch,
        t: f64,
        y: &mut State,
        events: &mut Vec<EventRecord>,
    ) -> Next {
        touchdown(m, t, y, events)
    }
}

/// The loss-of-contact event of a contact phase `from` at (t, y): with
/// `on_lift_off = "fly"` the body flies on from the same position and velocity (z_G and
/// v_Gz, until now given by the contact, become states), else the run stops.
pub(in crate::simulate) fn lift_off<E: Effect>(
    m: &Machine<'_, E>,
    from: Mode,
    t: f64,
    y: &mut State,
    events: &mut Vec<EventRecord>,
) -> Next {
    if m.scene.landing.lift_off == LiftOff::Stop {
        events.push(EventRecord {
            kind: EventKind::LostContact,
            t,
        });
        return Next::Stop(Status::LostContact);
    }
    let kin = Kinematics::new(&m.scene.body, y, from == Mode::Rolling);
    y[state::VEL] = kin.v_g.x;
    y[state::VEL + 1] = kin.v_g.y;
    y[state::HEIGHT] = kin.contact.height;
    y[state::VEL_Z] = kin.v_g.z;
    events.push(EventRecord {
        kind: EventKind::LiftOff,
        t,
    });
    events.push(EventRecord {
        kind: EventKind::ModeSwitch {
            from,
            to: Mode::Flight,
        },
        t,
    });
    Next::Go(Mode::Flight)
}

/// The gap's round-off δz = 4ε(|z_G| + L), L the largest semi-axis: the gap z_G − h(ζ)
/// is a difference of two heights of that size, each a few roundings deep. Touchdown is
/// the gap falling through −δz, so that a gap that is zero to round-off (a body
/// leaving the plane, or touching it without approaching) is no touchdown.
fn gap_resolution<E>(m: &Machine<'_, E>, kin: &Kinematics) -> f64 {
    let size = m.scene.body.semi_axes().max();
    GAP_ROUNDOFF * f64::EPSILON * (kin.z_g().abs() + size)
}

/// The settling speed (docs/physics.md, "Settling"): a rebound at v_n rises v_n²/(2g)
/// before it falls back, and a rise below the gap's round-off δz ([`gap_resolution`])
/// cannot be resolved, so contact is persistent below
/// ```text
///   v_settle = √(2 g δz)
/// ```
/// The bounces given up would have lasted 2 v_n / (g (1 − e)) in all (at most
/// 2√(2δz/g)/(1 − e): 1e-8 s for a centimetre body at e = 1/2). Without gravity no
/// rebound settles.
fn settling_speed<E>(m: &Machine<'_, E>, kin: &Kinematics) -> f64 {
    (2.0 * m.scene.gravity * gap_resolution(m, kin)).sqrt()
}

/// The impact law of the scene's contact model: frictionless, Coulomb (sliding and
/// coulomb models) or its no-slip limit (rolling).
fn tangential(contact: ContactModel) -> Tangential {
    match contact {
        ContactModel::Frictionless => Tangential::Frictionless,
        ContactModel::Sliding { friction } | ContactModel::Coulomb { friction } => {
            Tangential::Coulomb { friction }
        }
        ContactModel::Rolling => Tangential::NoSlip,
    }
}

/// Touchdown at (t, y): resolves the impact, books its loss in W, and either flies on
/// (a rebound above the settling speed) or makes contact persistent, with a plastic
/// impact standing for the Zeno tail of ever smaller bounces, in the scene's contact
/// phase — if the plane must push there (N > 0); else the body flies on from rest
/// relative to the plane.
fn touchdown<E: Effect + Copy + 'static>(
    m: &Machine<'_, E>,
    t: f64,
    y: &mut State,
    events: &mut Vec<EventRecord>,
) -> Next {
    let body = &m.scene.body;
    let kin = Kinematics::flying(body, y);
    let rot = kin.rot;
    let approach = Approach {
        mass: body.mass(),
        inertia_inv: rot * body.inertia_inv() * rot.transpose(),
        r: rot * kin.contact.r,
        v_g: kin.v_g,
        omega: rot * kin.omega,
    };
    let law = tangential(m.scene.contact);
    let mut hit = impact::resolve(&approach, law, m.scene.landing.restitution);
    let persistent = hit.normal_velocity.1 <= settling_speed(m, &kin);
    if persistent && hit.normal_velocity.1 > 0.0 {
        hit = impact::resolve(&approach, law, 0.0);
    }
    events.push(EventRecord {
        kind: EventKind::Touchdown {
            speed: -hit.normal_velocity.0,
        },
        t,
    });
    y[state::VEL] = hit.v_g.x;
    y[state::VEL + 1] = hit.v_g.y;
    y[state::VEL_Z] = hit.v_g.z;
    y.fixed_rows_mut::<3>(state::OMEGA)
        .copy_from(&rot.tr_mul(&hit.omega));
    y[state::WORK] += hit.energy_loss;
    // On the plane to round-off already: no gap, no penetration.
    y[state::HEIGHT] = kin.contact.height;
    let report = |persistent| ImpactReport {
        impulse: hit.impulse,
        energy_loss: hit.energy_loss,
        stuck: hit.stuck,
        rebound: hit.normal_velocity.1,
        persistent,
    };
    if !persistent {
        events.push(EventRecord {
            kind: EventKind::Impact(report(false)),
            t,
        });
        return Next::Go(Mode::Flight);
    }
    let mut landed = *y;
    let next = land(m, hit.stuck, &mut landed);
    let pushes = match next {
        Next::Go(mode) => phase::<E>(mode).response(m, &landed).normal > 0.0,
        Next::Stop(_) => true,
    };
    events.push(EventRecord {
        kind: EventKind::Impact(report(pushes)),
        t,
    });
    if !pushes {
        return Next::Go(Mode::Flight);
    }
    *y = landed;
    events.push(EventRecord {
        kind: match next {
            Next::Go(to) => EventKind::ModeSwitch {
                from: Mode::Flight,
                to,
            },
            Next::Stop(_) => EventKind::SlipStop,
        },
        t,
    });
    next
}

/// The contact phase a persistent landing goes on in, with its state map. The slots of
/// z_G and v_Gz are cleared (or take the slip reference): the contact gives them now,
/// and the kinetic energy of the rebound that this removes (below the settling speed) is
/// booked in W, so E + W stays exact. A contact that stuck rolls in the rolling model,
/// and in the Coulomb model if the cone allows (`rolling::after_slip_stop`); the pure
/// sliding model ends there, as it does at a slip stop on the plane.
fn land<E: Effect + Copy + 'static>(m: &Machine<'_, E>, stuck: bool, y: &mut State) -> Next {
    let body = &m.scene.body;
    let energy =
        |kin: &Kinematics| Invariants::from_kinematics(body, m.scene.gravity, kin, 0.0).energy;
    let flying = energy(&Kinematics::flying(body, y));
    y[state::HEIGHT] = 0.0;
    y[state::VEL_Z] = 0.0;
    y[state::WORK] += flying - energy(&Kinematics::new(body, y, false));
    let slides = |y: &mut State| {
        let s = m.slide.evaluate(y).kin.slip.normalize();
        set_reference(y, s);
        Next::Go(Mode::Sliding)
    };
    match m.scene.contact {
        ContactModel::Frictionless => Next::Go(Mode::Frictionless),
        ContactModel::Rolling => {
            Rolling::stick(body, y);
            m.roll.project(y);
            Next::Go(Mode::Rolling)
        }
        // A contact disc does not stick while it spins: it slides on, unless slip and spin
        // have both stopped (`sliding`'s module docs).
        ContactModel::Sliding { .. } | ContactModel::Coulomb { .. } if m.scene.disc.is_some() => {
            if slip_has_stopped(m, y) {
                Next::Stop(Status::SlipStopped)
            } else {
                let slip = m.slide.evaluate(y).kin.slip;
                if slip != nalgebra::Vector2::zeros() {
                    set_reference(y, slip.normalize());
                }
                Next::Go(Mode::Sliding)
            }
        }
        ContactModel::Sliding { .. } if stuck || slip_is_zero(m, y) => {
            Next::Stop(Status::SlipStopped)
        }
        ContactModel::Coulomb { friction } if stuck || slip_is_zero(m, y) => {
            Next::Go(after_slip_stop(m, friction, y))
        }
        ContactModel::Sliding { .. } | ContactModel::Coulomb { .. } => slides(y),
    }
}
