//! Cost of the stability analysis: one linearisation with its spectrum, and whole
//! diagrams of 200 spins (each value re-parses the scenario, finds the steady motion,
//! linearises and solves the eigenproblem; critical values are located by bisection).
//! The target: a 200-value diagram under a second on one core.
//!
//! `cargo bench -p ellipsoid-core --bench steady` (release profile).

use std::hint::black_box;
use std::path::Path;

use criterion::{Criterion, criterion_group, criterion_main};
use ellipsoid_core::scenario::{self, Scenario};
use ellipsoid_core::steady::{self, Family};

fn load(name: &str, sets: &[&str]) -> Scenario {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenarios")
        .join(name);
    scenario::load(&path, sets).unwrap()
}

fn bench(c: &mut Criterion) {
    // The tippe top inverted under Coulomb friction's rolling phase: one collision at
    // ±19.07 rad/s in −200…200.
    let tippe = load("tippe-top.toml", &["initial.theta=0.0"]);
    let spins: Vec<f64> = (0..200).map(|i| -200.0 + 2.0 * i as f64 + 1.0).collect();
    c.bench_function("steady/analyse tippe top inverted", |b| {
        b.iter(|| steady::analyse(black_box(&tippe.scene), Family::Inverted).unwrap())
    });
    c.bench_function("steady/diagram 200 spins, tippe top inverted", |b| {
        b.iter(|| {
            steady::sweep(
                black_box(&tippe),
                Family::Inverted,
                "initial.phi_dot",
                &spins,
            )
            .unwrap()
        })
    });
    // Routh's rolling circles of the disc against its tilt (two critical tilts).
    let disc = load("disc.toml", &["initial.phi_dot=8.0"]);
    let tilts: Vec<f64> = (0..200).map(|i| 30.0 + 120.0 * i as f64 / 199.0).collect();
    c.bench_function("steady/diagram 200 tilts, rolling disc circles", |b| {
        b.iter(|| {
            steady::sweep(
                black_box(&disc),
                Family::RollingCircle,
                "initial.theta_deg",
                &tilts,
            )
            .unwrap()
        })
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
