//! Throughput of each stepper on a small system (the Arenstorf orbit, N = 4), and the
//! bare cost of its right-hand side, so the stepper overhead per stage can be quoted:
//! overhead ≈ time/step − (rhs calls/step)·time/rhs.
//!
//! `cargo bench -p ellipsoid-core --bench steppers`; throughput is reported in steps
//! (accepted + rejected) per second.

use std::hint::black_box;
use std::ops::ControlFlow;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use ellipsoid_core::integrate::problems::Arenstorf;
use ellipsoid_core::integrate::{Method, OdeSystem, Options, Solution, integrate};
use nalgebra::Vector4;

fn one_period(method: Method, options: &Options<4>) -> Solution<4> {
    integrate(
        method,
        &Arenstorf,
        0.0,
        Arenstorf::y0(),
        Arenstorf::PERIOD,
        options,
        &[],
        &[],
        &mut |_, _| ControlFlow::Continue(()),
    )
    .expect("valid input")
}

fn steppers(c: &mut Criterion) {
    let options = Options::new(1e-9, 1e-9);
    let mut group = c.benchmark_group("arenstorf_period");
    for method in [Method::Rk4 { h: 1e-3 }, Method::Dopri5, Method::Dop853] {
        let reference = one_period(method, &options);
        let steps = reference.stats.accepted + reference.stats.rejected;
        group.throughput(Throughput::Elements(steps));
        group.bench_function(method.name(), |b| {
            b.iter(|| one_period(black_box(method), black_box(&options)))
        });
    }
    group.finish();

    let mut group = c.benchmark_group("rhs");
    group.throughput(Throughput::Elements(1));
    let y = Vector4::from(Arenstorf::Y0);
    group.bench_function("arenstorf", |b| {
        b.iter(|| black_box(&Arenstorf).rhs(black_box(0.5), black_box(&y)))
    });
    group.finish();
}

criterion_group!(benches, steppers);
criterion_main!(benches);
