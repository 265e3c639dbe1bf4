//! The random-scene campaign of the hybrid machine (docs/hard-cases.md, "Random scenes"):
//! a seeded generator of valid scenes — every contact model, bodies of revolution and
//! triaxial ones with a full inertia tensor, starts on the plane and in flight, contact
//! discs with each law, restitution in [0, 1], g in {0, 9.81} m/s², every effect — and
//! the checks each run must pass. Shared by `tests/campaign.rs` (a fixed seed, in CI) and
//! `examples/campaign.rs` (`--seed`, `--count`, for thousands).

use std::ops::ControlFlow;

use ellipsoid_core::body::{Body, Sphere, uniform_inertia};
use ellipsoid_core::effects::{AirDrag, RollingResistance, SpinFriction};
use ellipsoid_core::integrate::Method;
use ellipsoid_core::invariants::Invariant;
use ellipsoid_core::model::ContactDisc;
use ellipsoid_core::model::contensou::Law;
use ellipsoid_core::simulate::{
    self, ContactModel, EffectSet, EventKind, InitialState, Landing, LiftOff, Outcome, Sample,
    Scene, SolverSettings, Status,
};
use ellipsoid_core::state::EulerAngles;
use nalgebra::{Matrix3, Rotation3, Unit, Vector2, Vector3};

#[path = "rng.rs"]
pub mod rng;

pub use rng::Rng;

/// The simulated time of a campaign run [s].
pub const T_END: f64 = 0.5;
/// The tolerance of the campaign's runs (rtol; atol is 1e-2 of it).
pub const RTOL: f64 = 1e-10;

/// A random body: semi-axes 5 mm–3 cm (of revolution in half the draws), 1–200 g, the
/// uniform body's principal moments scaled by 0.7–1.3 (kept if they obey the triangle
/// inequality), for triaxial bodies in half the draws rotated into a full tensor, the
/// centre of mass inside (on the axis for bodies of revolution).
fn body(rng: &mut Rng) -> Option<Body> {
    let a = rng.uniform(0.005, 0.03);
    let revolution = rng.chance(0.5);
    let b = if revolution {
        a
    } else {
        a * rng.uniform(0.5, 1.5)
    };
    let c = a * rng.uniform(0.3, 3.0);
    let m = rng.uniform(0.001, 0.2);
    let axes = Vector3::new(a, b, c);
    let u = uniform_inertia(axes, m);
    let k = if revolution {
        let k = rng.uniform(0.7, 1.3);
        Vector3::new(k, k, rng.uniform(0.7, 1.3))
    } else {
        Vector3::new(
            rng.uniform(0.7, 1.3),
            rng.uniform(0.7, 1.3),
            rng.uniform(0.7, 1.3),
        )
    };
    let d = Vector3::new(u[(0, 0)] * k.x, u[(1, 1)] * k.y, u[(2, 2)] * k.z);
    let mut inertia = Matrix3::from_diagonal(&d);
    let com = if revolution {
        Vector3::new(0.0, 0.0, c * rng.uniform(-0.4, 0.4))
    } else {
        if rng.chance(0.5) {
            let axis = Unit::new_normalize(rng.vector(1.0));
            let r = Rotation3::from_axis_angle(&axis, rng.uniform(-0.3, 0.3));
            inertia = r.matrix() * inertia * r.matrix().transpose();
            inertia = (inertia + inertia.transpose()) / 2.0;
        }
        Vector3::new(
            a * rng.uniform(-0.3, 0.3),
            b * rng.uniform(-0.3, 0.3),
            c * rng.uniform(-0.3, 0.3),
        )
    };
    Body::new(axes, m, inertia, com).ok()
}

/// A random scene (see the module docs); `None` where the draw is not a valid scene (its
/// body or its start is refused), which the campaign then skips.
pub fn scene(rng: &mut Rng, method: Method) -> Option<Scene> {
    let body = body(rng)?;
    let size = body.semi_axes().max();
    let mass = body.mass();
    let mu = rng.uniform(0.05, 0.6);
    let contact = match rng.below(4) {
        0 => ContactModel::Frictionless,
        1 => ContactModel::Sliding { friction: mu },
        2 => ContactModel::Rolling,
        _ => ContactModel::Coulomb { friction: mu },
    };
    let disc = (contact.friction().is_some() && rng.chance(0.3)).then(|| ContactDisc {
        radius: size * rng.uniform(0.005, 0.2),
        law: [Law::Exact, Law::Pade, Law::Ellipse][rng.below(3)],
    });
    let restitution = match rng.below(10) {
        0 => 0.0,
        1 => 1.0,
        _ => rng.uniform(0.0, 1.0),
    };
    let gravity = if rng.chance(0.15) { 0.0 } else { 9.81 };
    let effects = EffectSet {
        air_drag: rng.chance(0.15).then(|| AirDrag {
            linear: mass * rng.uniform(0.0, 0.5),
            angular: mass * size * size * rng.uniform(0.0, 0.5),
        }),
        rolling_resistance: rng.chance(0.15).then(|| RollingResistance {
            coefficient: size * rng.uniform(0.0, 0.05),
            regularisation: rng.uniform(0.01, 1.0),
        }),
        spin_friction: rng.chance(0.15).then(|| SpinFriction {
            coefficient: size * rng.uniform(0.0, 0.05),
            regularisation: rng.uniform(0.01, 1.0),
        }),
        // Not drawn: the air laws need a rim (the campaign's bodies are ellipsoids), and
        // rolling friction is the rolling resistance with the contact path's radius of
        // curvature for its arm (tests/dissipation.rs).
        rolling_friction: None,
        air_film: None,
        air_boundary_layer: None,
    };
    let theta = if rng.chance(0.1) {
        0.0
    } else {
        rng.uniform(0.0, std::f64::consts::PI)
    };
    let spin = rng.uniform(0.0, 80.0);
    let dir = rng.vector(1.0);
    let flying = rng.chance(0.3);
    let velocity = (contact != ContactModel::Rolling && rng.chance(0.5))
        .then(|| Vector2::new(rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3)));
    let initial = InitialState {
        angles: EulerAngles {
            theta,
            phi: rng.uniform(-3.1, 3.1),
            psi: rng.uniform(-3.1, 3.1),
            theta_dot: 0.0,
            phi_dot: 0.0,
            psi_dot: 0.0,
        },
        omega_body: Some(dir.normalize() * spin),
        position: Vector2::zeros(),
        velocity: if flying {
            Some(Vector2::new(rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3)))
        } else {
            velocity
        },
        height: if flying { rng.uniform(1e-4, 0.03) } else { 0.0 },
        velocity_z: flying.then(|| rng.uniform(-0.5, 0.5)),
    };
    let n = 50;
    let scene = Scene {
        body,
        gravity,
        contact,
        disc,
        landing: Landing {
            restitution,
            lift_off: LiftOff::Fly,
            ..Landing::default()
        },
        effects,
        initial,
        solver: SolverSettings {
            method,
            rtol: RTOL,
            atol: 1e-2 * RTOL,
            initial_step: None,
            max_steps: 2_000_000,
        },
        t_end: T_END,
        sample_times: (0..=n).map(|k| T_END * k as f64 / n as f64).collect(),
        observe: Vec::new(),
        sections: Vec::new(),
    };
    starts(&scene).then_some(scene)
}

/// `scene` with one or two random contact spheres (docs/physics.md, "Contact spheres"):
/// centres at 0.5–1.1 of the body's size L from C0 in a random direction, radii
/// 0.1–0.5 L, so that they protrude in most draws; `None` where the start is refused.
pub fn with_spheres(scene: &Scene, rng: &mut Rng) -> Option<Scene> {
    let size = scene.body.semi_axes().max();
    let spheres = (0..1 + rng.below(2))
        .map(|k| Sphere {
            name: format!("s{k}"),
            center: rng.vector(1.0).normalize() * (size * rng.uniform(0.5, 1.1)),
            radius: size * rng.uniform(0.1, 0.5),
        })
        .collect();
    let mut s = scene.clone();
    s.body = s.body.with_spheres(spheres).ok()?;
    starts(&s).then_some(s)
}

/// A frictionless body like those that fell through the plane (issue 48): a = b = 7.1 mm,
/// c = 18.6 mm, G 8.7 mm from C0 on the axis (either side), 5–100 g, tilted θ0 = 0.758 rad
/// and spun ψ̇0 = 210 rad/s on the plane, with 1–8 small contact spheres (radius
/// 0.15–1.1 mm, centres 40–48 mm from C0 in random directions: stems far out of the
/// body), restitution in [0, 1]; `None` where the start is refused.
pub fn frictionless_with_stems(rng: &mut Rng) -> Option<Scene> {
    let base = scene(rng, Method::Dop853)?;
    let (a, c) = (0.0071, 0.0186);
    let m = rng.uniform(0.005, 0.1);
    let axes = Vector3::new(a, a, c);
    let u = uniform_inertia(axes, m);
    let k = rng.uniform(0.7, 1.3);
    let inertia = Matrix3::from_diagonal(&Vector3::new(
        u[(0, 0)] * k,
        u[(0, 0)] * k,
        u[(2, 2)] * rng.uniform(0.7, 1.3),
    ));
    let side = if rng.chance(0.5) { 1.0 } else { -1.0 };
    let spheres = (0..1 + rng.below(8))
        .map(|k| Sphere {
            name: format!("s{k}"),
            center: rng.vector(1.0).normalize() * rng.uniform(0.04, 0.048),
            radius: rng.uniform(0.00015, 0.0011),
        })
        .collect();
    let body = Body::new(axes, m, inertia, Vector3::new(0.0, 0.0, 0.0087 * side))
        .and_then(|b| b.with_spheres(spheres))
        .ok()?;
    let mut s = Scene {
        body,
        gravity: 9.81,
        contact: ContactModel::Frictionless,
        disc: None,
        effects: EffectSet::default(),
        ..base
    };
    s.landing.restitution = rng.uniform(0.0, 1.0);
    s.initial = InitialState {
        angles: EulerAngles {
            theta: 0.758,
            phi: 0.0,
            psi: 0.0,
            theta_dot: 0.0,
            phi_dot: rng.uniform(-5.0, 5.0),
            psi_dot: 210.0,
        },
        omega_body: None,
        position: Vector2::zeros(),
        velocity: None,
        height: 0.0,
        velocity_z: None,
    };
    starts(&s).then_some(s)
}

/// Whether a run of `scene` starts: the checks `simulate` makes at t = 0, with the
/// scene's effects (`Scene::initial_state` leaves them out, and a rolling scene with
/// effects can pass it and still be refused as the rolling model's Painlevé case at t = 0;
/// seed 25 of `examples/campaign.rs --spheres` drew one at scene 100-999). A run is
/// cancelled at its first sample, as `ellipsoid check` does.
fn starts(scene: &Scene) -> bool {
    simulate::simulate(scene, &mut |_| ControlFlow::Break(())).is_ok()
}

/// One run's samples and outcome.
pub struct Run {
    pub outcome: Outcome,
    pub samples: Vec<Sample>,
}

pub fn run(scene: &Scene) -> Run {
    let mut samples = Vec::new();
    let outcome = simulate::simulate(scene, &mut |s| {
        samples.push(*s);
        ControlFlow::Continue(())
    })
    .expect("a valid scene");
    Run { outcome, samples }
}

/// The scene with another method and tolerance.
pub fn with(scene: &Scene, method: Method, rtol: f64) -> Scene {
    let mut s = scene.clone();
    s.solver.method = method;
    s.solver.rtol = rtol;
    s.solver.atol = 1e-2 * rtol;
    s
}

/// Whether a status is allowed to end a campaign run: every outcome of the physics
/// (completed, lost contact, a slip stop, the two inconsistencies of rigid contact with
/// friction — Painlevé's for sliding, its analogue for rolling — which are answers of the
/// model, not failures of the numerics; and, with contact spheres, a rest on two surfaces,
/// which is not simulated), and never `chattering`, `solver_failure`,
/// `non_finite` or `cancelled`.
pub fn allowed(status: &Status) -> bool {
    matches!(
        status,
        Status::Completed
            | Status::Observed { .. }
            | Status::LostContact
            | Status::SlipStopped
            | Status::Painleve { .. }
            | Status::InconsistentContact { .. }
            | Status::SeveralContacts { .. }
    )
}

/// The checks of one run (docs/hard-cases.md, "Random scenes"); the first one broken.
pub fn check(scene: &Scene, run: &Run) -> Result<(), String> {
    let out = &run.outcome;
    if !allowed(&out.status) {
        return Err(format!("status {:?}", out.status));
    }
    let energy = out.initial_invariants.energy.abs() + 1e-300;
    let mut last_w = f64::NEG_INFINITY;
    for s in &run.samples {
        let values = ellipsoid_core::columns::values(s);
        if values.iter().any(|v| !v.is_finite()) {
            return Err(format!("a non-finite sample at t = {}", s.t));
        }
        // W never decreases (to round-off of the energy).
        if s.work < last_w - 1e-12 * energy.max(s.energy.abs()) {
            return Err(format!("W fell by {:e} J at t = {}", last_w - s.work, s.t));
        }
        last_w = last_w.max(s.work);
    }
    // Time never runs back by more than [`STEP_BACK`]: a touchdown is taken back to its
    // zero gap, at most a few fall times through the gap's round-off.
    if let Some(w) = (out.events.windows(2)).find(|w| w[1].t < w[0].t - STEP_BACK) {
        return Err(format!(
            "an event at t = {} after one at t = {}",
            w[1].t, w[0].t
        ));
    }
    for e in &out.events {
        if let EventKind::Impact(r) = &e.kind
            && r.energy_loss < -1e-12 * energy
        {
            return Err(format!(
                "an impact added {:e} J at t = {}",
                -r.energy_loss, e.t
            ));
        }
    }
    if let Some(d) = out.drift.get(Invariant::EnergyPlusWork)
        && d.abs() > 1e-8
    {
        return Err(format!("E + W drift {d:e}"));
    }
    let _ = scene;
    Ok(())
}

/// The most an event may come before the one recorded ahead of it \[s\]: a touchdown
/// located at gap −δz is taken back to its zero gap, at most 4√(2δz/a) along the flight
/// (a: g, or without gravity the gap's free deceleration; `transition::back_to_contact`),
/// which with δz ~ 1e-16 m is 1e-8 s at g and 1e-6 s at a = 1e-3 m/s².
pub const STEP_BACK: f64 = 1e-6;

/// DOP853's own error at rtol 1e-10 above which a motion counts as sensitive at that
/// tolerance (it amplifies the tolerance a thousandfold by t_end).
pub const SENSITIVE: f64 = 1e-7;

/// Whether DOPRI5 and DOP853 agree on a scene: their final states within 1e-6 of the
/// scene's scales ([`distance`]); or, where DOP853's own error (its run at rtol 1e-10
/// against one at 1e-12, `tight`) exceeds [`SENSITIVE`], DOPRI5 within a hundred times that
/// error of the tight run.
pub fn agree(
    scene: &Scene,
    r853: &Run,
    r5: &Run,
    tight: impl FnOnce() -> Run,
) -> Result<(), String> {
    let (a, b) = (&r853.outcome.final_sample, &r5.outcome.final_sample);
    let d = distance(scene, a, b);
    if d <= 1e-6 {
        return Ok(());
    }
    let tight = tight();
    let reference = &tight.outcome.final_sample;
    let own = distance(scene, a, reference);
    let dopri5 = distance(scene, b, reference);
    if own > SENSITIVE && dopri5 <= 100.0 * own {
        return Ok(());
    }
    Err(format!(
        "dopri5 and dop853 differ by {d:.1e}; against dop853 at rtol 1e-12: dop853 {own:.1e}, dopri5 {dopri5:.1e}"
    ))
}

/// The distance between two runs' final states, relative to the scene's scales: time in
/// t_end, position in L, velocities in √(gL) + |v|, rates in √(g/L) + |ω|.
pub fn distance(scene: &Scene, a: &Sample, b: &Sample) -> f64 {
    let l = scene.body.semi_axes().max();
    let g = scene.gravity.max(1.0);
    let v = (g * l).sqrt() + a.velocity.norm();
    let w = (g / l).sqrt() + a.omega_world.norm();
    [
        (a.t - b.t).abs() / scene.t_end,
        (a.position - b.position).norm() / l,
        (a.velocity - b.velocity).norm() / v,
        (a.omega_world - b.omega_world).norm() / w,
    ]
    .into_iter()
    .fold(0.0, f64::max)
}

/// Whether `events` hold an impact at three surfaces at one instant (a third surface's
/// touchdown while two are in contact, docs/physics.md "A third surface touching down").
pub fn impact_at_three(events: &[simulate::EventRecord]) -> bool {
    let impact = |e: &simulate::EventRecord| match e.kind {
        EventKind::Impact(report) => Some((e.t, report.surface)),
        _ => None,
    };
    events
        .windows(3)
        .any(|w| match (impact(&w[0]), impact(&w[1]), impact(&w[2])) {
            (Some(a), Some(b), Some(c)) => {
                a.0 == b.0 && b.0 == c.0 && a.1 != b.1 && b.1 != c.1 && a.1 != c.1
            }
            _ => false,
        })
}
