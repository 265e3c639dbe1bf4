//! Bodies and scenes from docs/physics.md shared by the physics tests.
#![allow(dead_code)] // each test binary uses a different subset

pub mod campaign;

use std::ops::ControlFlow;

use ellipsoid_core::body::{Body, uniform_inertia};
use ellipsoid_core::integrate::Method;
use ellipsoid_core::simulate::{
    self, ContactModel, EffectSet, EventKind, InitialState, Landing, LiftOff, Outcome, Sample,
    Scene, SolverSettings,
};
use ellipsoid_core::state::EulerAngles;
use nalgebra::{Matrix3, Vector2, Vector3};

pub const G: f64 = 9.81;

/// The oblate nutation body: a = 0.025, c = 0.0175, D2 = 0.003 m, m = 0.05 kg,
/// I = m(a² + c²)/5, I3 = 2 m a²/5.
pub fn oblate() -> Body {
    let (a, c, m) = (0.025, 0.0175, 0.05);
    Body::of_revolution(
        a,
        c,
        m,
        m * (a * a + c * c) / 5.0,
        2.0 * m * a * a / 5.0,
        0.003,
    )
    .unwrap()
}

/// Leine & Glocker's tippe top: sphere R = 15 mm, CM 3 mm below the centre, m = 6 g,
/// I1 = I2 = 8e-7, I3 = 7e-7 kg m².
pub fn tippe_top() -> Body {
    Body::of_revolution(0.015, 0.015, 6e-3, 8e-7, 7e-7, 0.003).unwrap()
}

/// Kane & Levinson's rattleback: semi-axes 0.20, 0.03, 0.02 m, CM 0.01 m below the
/// centre, m = 1 kg, A = 2e-4, B = 1.6e-3, C = 1.7e-3, D = −2e-5 kg m².
pub fn rattleback() -> Body {
    let i = Matrix3::new(2e-4, -2e-5, 0.0, -2e-5, 1.6e-3, 0.0, 0.0, 0.0, 1.7e-3);
    Body::new(
        Vector3::new(0.2, 0.03, 0.02),
        1.0,
        i,
        Vector3::new(0.0, 0.0, -0.01),
    )
    .unwrap()
}

/// A uniform sphere (billiard ball) of radius r and mass m.
pub fn ball(r: f64, m: f64) -> Body {
    let ax = Vector3::new(r, r, r);
    Body::new(ax, m, uniform_inertia(ax, m), Vector3::zeros()).unwrap()
}

pub fn angles(
    theta: f64,
    phi: f64,
    psi: f64,
    theta_dot: f64,
    phi_dot: f64,
    psi_dot: f64,
) -> EulerAngles {
    EulerAngles {
        theta,
        phi,
        psi,
        theta_dot,
        phi_dot,
        psi_dot,
    }
}

/// A scene run with DOP853 at rtol = atol = `tol`, sampled every `dt` up to `t_end`.
pub fn scene(
    body: Body,
    contact: ContactModel,
    angles: EulerAngles,
    velocity: Option<Vector2<f64>>,
    t_end: f64,
    dt: f64,
    tol: f64,
) -> Scene {
    let n = (t_end / dt).round() as usize;
    Scene {
        body,
        gravity: G,
        contact,
        disc: None,
        // The round-one questions: a loss of contact ends the run (flight tests say "fly").
        landing: Landing {
            lift_off: LiftOff::Stop,
            ..Landing::default()
        },
        effects: EffectSet::default(),
        initial: InitialState {
            angles,
            omega_body: None,
            position: Vector2::zeros(),
            velocity,
            height: 0.0,
            velocity_z: None,
        },
        solver: SolverSettings {
            method: Method::Dop853,
            rtol: tol,
            atol: tol,
            initial_step: None,
            max_steps: 50_000_000,
        },
        t_end,
        sample_times: (0..=n).map(|k| (k as f64 * dt).min(t_end)).collect(),
        observe: Vec::new(),
        sections: Vec::new(),
    }
}

/// Runs a scene, collecting every sample.
pub fn run(scene: &Scene) -> (Outcome, Vec<Sample>) {
    let mut samples = Vec::new();
    let outcome = simulate::simulate(scene, &mut |s| {
        samples.push(*s);
        ControlFlow::Continue(())
    })
    .expect("valid scene");
    (outcome, samples)
}

/// The times of a run's slip stops [s].
pub fn slip_stop_times(out: &Outcome) -> Vec<f64> {
    out.events
        .iter()
        .filter(|e| e.kind == EventKind::SlipStop)
        .map(|e| e.t)
        .collect()
}

/// A run of `scene` that must reach t_end: its samples.
pub fn completed(scene: &Scene) -> Vec<Sample> {
    let (out, samples) = run(scene);
    assert_eq!(
        out.status,
        ellipsoid_core::simulate::Status::Completed,
        "{:?}",
        out.status
    );
    samples
}

/// The time at which θ's deviation from `theta0` first reaches `level`, interpolated
/// in its logarithm between samples (an exponential growth is a straight line there).
pub fn first_reaching(samples: &[Sample], theta0: f64, level: f64) -> f64 {
    let dev = |s: &Sample| (s.angles.theta - theta0).abs();
    let w = samples
        .windows(2)
        .find(|w| dev(&w[0]) < level && dev(&w[1]) >= level)
        .expect("the tilt's deviation reaches the level");
    let (l0, l1) = (dev(&w[0]).ln(), dev(&w[1]).ln());
    w[0].t + (level.ln() - l0) / (l1 - l0) * (w[1].t - w[0].t)
}

/// The angular frequency of `f` over the samples from its upward zero crossings (each
/// interpolated linearly between samples), and how many there are (at least 2).
pub fn crossing_frequency(samples: &[Sample], f: impl Fn(&Sample) -> f64) -> (f64, usize) {
    let crossings: Vec<f64> = samples
        .windows(2)
        .filter(|w| f(&w[0]) < 0.0 && f(&w[1]) >= 0.0)
        .map(|w| {
            let (a, b) = (f(&w[0]), f(&w[1]));
            w[0].t - a / (b - a) * (w[1].t - w[0].t)
        })
        .collect();
    let n = crossings.len();
    assert!(n >= 2, "{n} crossings");
    (
        std::f64::consts::TAU * (n - 1) as f64 / (crossings[n - 1] - crossings[0]),
        n,
    )
}

/// Each expected eigenvalue has its own computed one within `tol` of the scale.
pub fn assert_spectrum(
    computed: &[nalgebra::Complex<f64>],
    expected: &[nalgebra::Complex<f64>],
    tol: f64,
    what: &str,
) {
    let scale = expected.iter().map(|z| z.norm()).fold(0.0, f64::max);
    let mut left: Vec<nalgebra::Complex<f64>> = computed.to_vec();
    for e in expected {
        let (k, d) = left
            .iter()
            .enumerate()
            .map(|(k, z)| (k, (z - e).norm()))
            .fold((0, f64::INFINITY), |a, b| if b.1 < a.1 { b } else { a });
        assert!(
            d <= tol * scale,
            "{what}: expected {e} not found (nearest off by {:.3e} of {scale:.3e}); computed {computed:?}",
            d / scale
        );
        left.remove(k);
    }
}
