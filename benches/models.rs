//! Cost of the physics: one right-hand-side evaluation per contact model (and in flight), one step per
//! method on the ellipsoid, whole runs of every bundled scenario, and sweep throughput
//! on all cores against one.
//!
//! `cargo bench -p ellipsoid-core --bench models` (release profile). Inputs are built
//! outside the timed closures and passed through `black_box`.

use std::hint::black_box;
use std::ops::ControlFlow;
use std::path::Path;

use criterion::{BatchSize, Criterion, Throughput, criterion_group, criterion_main};
use ellipsoid_core::body::{Body, Rim, Surface};
use ellipsoid_core::effects::AirDrag;
use ellipsoid_core::geometry;
use ellipsoid_core::integrate::{Method, OdeSystem, Options, integrate};
use ellipsoid_core::model::contensou::Law;
use ellipsoid_core::model::{
    ContactDisc, ContactLaw, Flight, Frictionless, Rolling, Sliding, SlipBand, System,
};
use ellipsoid_core::scenario;
use ellipsoid_core::simulate::{Scene, simulate};
use ellipsoid_core::state::{self, EulerAngles, State};

use rayon::prelude::*;

/// The oblate top of the nutation scene.
fn top() -> Body {
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

/// A tilted, spinning, sliding state (slip along x).
fn state() -> State {
    let angles = EulerAngles {
        theta: 0.3,
        phi: 0.2,
        psi: 0.1,
        theta_dot: 1.0,
        phi_dot: 3.0,
        psi_dot: 60.0,
    };
    let mut y = State::zeros();
    state::set_quaternion(&mut y, &angles.rotation());
    y.fixed_rows_mut::<3>(state::OMEGA)
        .copy_from(&angles.omega_body());
    y[state::VEL] = 0.3;
    y[state::SLIP_REF] = 1.0;
    y
}

/// The top with a rounded rim round its equator (R = 22 mm, edge 3 mm).
fn rimmed() -> Body {
    top()
        .with_rims(vec![Rim {
            name: "rim".into(),
            center: nalgebra::Vector3::zeros(),
            radius: 0.022,
            edge: 0.003,
        }])
        .unwrap()
}

/// The gap function h(ζ) of each kind of surface (the flight phase's and the guard's
/// watch, evaluated at every step for every surface off the plane).
fn gap(c: &mut Criterion) {
    let zeta = nalgebra::Vector3::new(0.3, -0.2, 0.93).normalize();
    let body = rimmed();
    let mut group = c.benchmark_group("gap");
    group.throughput(Throughput::Elements(1));
    for (name, surface) in [("ellipsoid", Surface::Ellipsoid), ("rim", Surface::Rim(0))] {
        group.bench_function(name, |b| {
            b.iter(|| geometry::height(black_box(&body), surface, black_box(zeta)))
        });
    }
    group.finish();
}

fn system<C: ContactLaw>(contact: C) -> System<C, ()> {
    System {
        body: top(),
        gravity: 9.81,
        contact,
        effects: (),
    }
}

fn rhs(c: &mut Criterion) {
    let y = state();
    let mut group = c.benchmark_group("rhs");
    group.throughput(Throughput::Elements(1));
    let free = system(Frictionless);
    group.bench_function("frictionless", |b| {
        b.iter(|| black_box(&free).rhs(0.0, black_box(&y)))
    });
    let slide = system(Sliding {
        friction: 0.3,
        disc: None,
        band: SlipBand::NONE,
    });
    group.bench_function("sliding", |b| {
        b.iter(|| black_box(&slide).rhs(0.0, black_box(&y)))
    });
    let roll = system(Rolling);
    group.bench_function("rolling", |b| {
        b.iter(|| black_box(&roll).rhs(0.0, black_box(&y)))
    });
    // The same rolling state on a rounded rim of the top's size instead of its ellipsoid
    // (issue 44: a rim's contact costs at most the ellipsoid's).
    let on_rim = System {
        body: rimmed().touching(Surface::Rim(0)),
        ..system(Rolling)
    };
    group.bench_function("rolling_rim", |b| {
        b.iter(|| black_box(&on_rim).rhs(0.0, black_box(&y)))
    });
    // The sliding law over a contact disc (Coulomb–Contensou, issue #14) against the point
    // contact above: R = 0.5 mm puts d = |v_C|/(R|ω_n|) at 30 (the series in 1/d²),
    // R = 12 mm at 1.3 (Carlson's R_F and R_D, the costliest branch).
    for (name, radius) in [("sliding_disc", 5e-4), ("sliding_disc_d1", 1.2e-2)] {
        let disc = system(Sliding {
            friction: 0.3,
            disc: Some(ContactDisc {
                radius,
                law: Law::Exact,
            }),
            band: SlipBand::NONE,
        });
        group.bench_function(name, |b| {
            b.iter(|| black_box(&disc).rhs(0.0, black_box(&y)))
        });
    }
    // The same state off the plane (z_G and v_Gz are states in flight).
    let mut flying = y;
    flying[state::HEIGHT] = 0.05;
    flying[state::VEL_Z] = 0.1;
    let fly = system(Flight);
    group.bench_function("flight", |b| {
        b.iter(|| black_box(&fly).rhs(0.0, black_box(&flying)))
    });
    // The same sliding system with one effect present (air drag): what an absent effect
    // (the `()` above) saves.
    let dragged = System {
        body: top(),
        gravity: 9.81,
        contact: Sliding {
            friction: 0.3,
            disc: None,
            band: SlipBand::NONE,
        },
        effects: AirDrag {
            linear: 1e-3,
            angular: 1e-8,
        },
    };
    group.bench_function("sliding_air_drag", |b| {
        b.iter(|| black_box(&dragged).rhs(0.0, black_box(&y)))
    });
    group.finish();
}

/// 1000 steps of each method on the frictionless top: time per step.
fn steps(c: &mut Criterion) {
    let sys = system(Frictionless);
    let y = state();
    let mut group = c.benchmark_group("step_frictionless");
    for (method, options) in [
        (Method::Rk4 { h: 1e-4 }, Options::new(1e-10, 1e-12)),
        (Method::Dopri5, Options::new(1e-10, 1e-12)),
        (Method::Dop853, Options::new(1e-12, 1e-12)),
    ] {
        let run = || {
            integrate(
                method,
                &sys,
                0.0,
                y,
                1.0,
                &options,
                &[],
                &[],
                &mut |_, _| ControlFlow::Continue(()),
            )
            .unwrap()
        };
        let steps = run().stats.accepted;
        group.throughput(Throughput::Elements(steps));
        group.bench_function(method.name(), |b| b.iter(|| black_box(run())));
    }
    group.finish();
}

fn bundled() -> Vec<(String, Scene)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    files
        .iter()
        .map(|p| {
            (
                p.file_stem().unwrap().to_string_lossy().into_owned(),
                scenario::load(p, &[] as &[&str]).unwrap().scene,
            )
        })
        .collect()
}

fn run(scene: &Scene) -> usize {
    let mut rows = 0;
    simulate(scene, &mut |_| {
        rows += 1;
        ControlFlow::Continue(())
    })
    .unwrap();
    rows
}

/// Each bundled scenario, whole, at its own settings.
fn scenarios(c: &mut Criterion) {
    let mut group = c.benchmark_group("scenario");
    group.sample_size(10);
    for (name, scene) in bundled() {
        group.bench_function(&name, |b| b.iter(|| black_box(run(black_box(&scene)))));
    }
    group.finish();
}

/// The cost of a contact sphere that never touches (issue #25: at most one gap evaluation
/// per step while it is open): `tippe-top-disc` whole, alone and with a sphere inside its
/// ball (the same trajectory, bit for bit; tests/spheres.rs).
fn idle_sphere(c: &mut Criterion) {
    let base = bundled()
        .into_iter()
        .find(|(n, _)| n == "tippe-top-disc")
        .unwrap()
        .1;
    let mut with = base.clone();
    with.body = with
        .body
        .with_spheres(vec![ellipsoid_core::body::Sphere {
            name: "inside".into(),
            center: nalgebra::Vector3::new(0.0, 0.0, 0.005),
            radius: 0.004,
        }])
        .unwrap();
    let mut group = c.benchmark_group("idle_sphere");
    group.sample_size(10);
    group.bench_function("tippe-top-disc", |b| {
        b.iter(|| black_box(run(black_box(&base))))
    });
    group.bench_function("tippe-top-disc+sphere", |b| {
        b.iter(|| black_box(run(black_box(&with))))
    });
    group.finish();
}

/// 16 nutation runs (1 s each, tilts 0.05–0.8 rad): one core against all cores.
fn sweep(c: &mut Criterion) {
    let base = bundled()
        .into_iter()
        .find(|(n, _)| n == "nutation")
        .unwrap()
        .1;
    let scenes: Vec<Scene> = (0..16)
        .map(|k| {
            let mut s = base.clone();
            s.t_end = 1.0;
            s.sample_times.retain(|&t| t <= 1.0);
            s.initial.angles.theta = 0.05 + 0.05 * k as f64;
            s
        })
        .collect();
    let mut group = c.benchmark_group("sweep16");
    group.sample_size(10);
    group.throughput(Throughput::Elements(scenes.len() as u64));
    group.bench_function("one_core", |b| {
        b.iter_batched(
            || scenes.clone(),
            |s| s.iter().map(run).sum::<usize>(),
            BatchSize::SmallInput,
        )
    });
    group.bench_function("all_cores", |b| {
        b.iter_batched(
            || scenes.clone(),
            |s| s.par_iter().map(run).sum::<usize>(),
            BatchSize::SmallInput,
        )
    });
    group.finish();
}

criterion_group!(benches, rhs, gap, steps, scenarios, idle_sphere, sweep);
criterion_main!(benches);
