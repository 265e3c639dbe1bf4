//! A rim going flat (docs/physics.md, "Rims": "The flat landing"): as its tilt α → 0 the
//! whole circle reaches the plane at once and its support point is singular there. The
//! moment is an event, located where sin α = |Pζ| falls through the scene's flat tilt
//! (`[contact] flat_tilt`, by default `geometry::FLAT_TILT`; the watch [`tilt`]), and the
//! body lands on the face the rim bounds: its attitude is set flat (the axis turned onto
//! the vertical, by at most the flat tilt), and the face's impact is plastic — v_Gz and
//! the horizontal ω vanish, the horizontal v_G and the vertical angular momentum
//! L_z = e3·I_w ω are kept (the face's normal impulses have no vertical moment), and
//! with the rolling model the face grips (the body stops). The
//! impulse J = −m v_Gz must press (J ≥ 0) and its centre of pressure, where
//! J (r × e3) = ΔL_h, lie on the face: otherwise the flat landing is not simulated and
//! the run stops `several_contacts`. The mechanical energy the landing removes is booked
//! in W (E + W is continuous across it).

use nalgebra::Vector3;

use crate::body::Surface;
use crate::effects::Effect;
use crate::geometry;
use crate::invariants::Invariants;
use crate::kinematics::Kinematics;
use crate::model::Face;
use crate::state::{self, State};

use super::context::{ContactSet, Context};
use super::outcome::{EventKind, EventRecord, Mode, Status};
use super::phase::{Next, phase};
use super::scene::ContactModel;

/// The flat watch of a rim in contact at `kin`: sin α − `flat_tilt` (the scene's
/// `Landing::flat_tilt`), |Pζ| = sin α the rim's tilt (`geometry::ring_direction`);
/// falling through zero, the rim lands flat.
pub(super) fn tilt(kin: &Kinematics, flat_tilt: f64) -> f64 {
    geometry::ring_direction(kin.contact.zeta).1 - flat_tilt
}

/// The rim in contact on `contacts` (touching down from flight: the rim touching) is flat
/// at (t, y) in mode `from`: the body lands on its face (see the module docs).
pub(super) fn land_flat<E: Effect + Copy + 'static>(
    ctx: &Context<'_, E>,
    contacts: &mut ContactSet,
    from: Mode,
    t: f64,
    y: &mut State,
    events: &mut Vec<EventRecord>,
) -> Next {
    let surface = contacts.surface;
    let Surface::Rim(k) = surface else {
        unreachable!("only a rim lands flat")
    };
    let scene = ctx.scene;
    let body = &scene.body.touching(surface);
    let (m, gravity) = (body.mass(), scene.gravity);
    let kin = if from == Mode::Flight {
        Kinematics::flying_at(body, surface, y)
    } else {
        phase::<E>(from).kinematics(ctx, contacts, y)
    };
    let energy = |kin: &Kinematics| Invariants::from_kinematics(body, gravity, kin, 0.0).energy;
    let before = energy(&kin);
    let omega = kin.rot * kin.omega;
    // The far side: the circle's point opposite the contact, its approach speed.
    let rim = &body.rims()[k];
    let (out, _) = geometry::ring_direction(kin.contact.zeta);
    let far =
        kin.rot * (rim.center + rim.radius * out - rim.edge * kin.contact.zeta - body.com_offset());
    let speed = -(kin.v_g + omega.cross(&far)).z;
    // The attitude set flat: the rim's axis, upward, turned onto the vertical (on a copy:
    // a landing that is not simulated leaves the state as it found it).
    let mut landed = *y;
    Face::flatten(&mut landed);
    let rot = state::rotation(&landed);
    let inertia = rot * body.inertia() * rot.transpose();
    // The plastic impact of the face.
    let grips = scene.contact == ContactModel::Rolling;
    let spin = if grips {
        0.0
    } else {
        (inertia * omega).z / inertia[(2, 2)]
    };
    let after = Vector3::new(0.0, 0.0, spin);
    let impulse = -m * kin.v_g.z;
    let moment = inertia * (after - omega);
    let lever = rot * (rim.center - rim.edge * rot.transpose() * Vector3::z() - body.com_offset());
    // Centre of pressure from G: J (r_y, −r_x) = ΔL_h.
    let offset = if impulse > 0.0 {
        (Vector3::new(-moment.y / impulse, moment.x / impulse, 0.0) - lever)
            .xy()
            .norm()
    } else if moment.xy().norm() == 0.0 {
        0.0
    } else {
        f64::INFINITY
    };
    if !grips && offset > rim.radius {
        return Next::Stop(
            Status::SeveralContacts {
                touching: surface,
                pressed: surface,
                approach: speed,
            },
            from,
        );
    }
    let v = if grips {
        Vector3::zeros()
    } else {
        Vector3::new(kin.v_g.x, kin.v_g.y, 0.0)
    };
    landed[state::VEL] = v.x;
    landed[state::VEL + 1] = v.y;
    landed[state::HEIGHT] = 0.0;
    landed[state::VEL_Z] = 0.0;
    landed
        .fixed_rows_mut::<3>(state::OMEGA)
        .copy_from(&(rot.transpose() * after));
    let energy_loss = before - energy(&Kinematics::new(body, &landed, false));
    landed[state::WORK] += energy_loss;
    *y = landed;
    events.push(EventRecord {
        kind: EventKind::Flat {
            surface,
            speed,
            energy_loss,
        },
        t,
    });
    events.push(EventRecord {
        kind: EventKind::ModeSwitch {
            from,
            to: Mode::Face,
        },
        t,
    });
    Next::Go(Mode::Face)
}
