//! Parameter studies (issue #15): trajectories per second for the tippe-top turn-over map
//! (studies/tippe-top-map.toml: 8 s each, rtol 1e-8, summaries only) on one and
//! on two cores, and the study's own cost per run against the bare `simulate` of the same
//! scenarios (parse, resolve and hash the point, run through `ellipsoid_io::run`, record
//! the outcomes).
//!
//! `cargo bench -p ellipsoid-study --bench study`. The sample is 100 of the map's 1600
//! points (every 16th, so it crosses the whole map); the scenes for the bare runs are
//! parsed outside the timed closure.

use std::hint::black_box;
use std::ops::ControlFlow;
use std::path::Path;
use std::sync::Arc;
use std::sync::atomic::AtomicBool;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use ellipsoid_core::simulate::simulate;
use ellipsoid_study::study::{Study, spec};

fn map() -> Study {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../studies/tippe-top-map.toml");
    Study::new(spec::load(&path).expect("the map study")).expect("valid")
}

fn sample(study: &Study) -> Vec<usize> {
    (0..study.len()).step_by(16).collect()
}

fn throughput(c: &mut Criterion) {
    let study = map();
    let points = sample(&study);
    let cancel = Arc::new(AtomicBool::new(false));
    let mut g = c.benchmark_group("tippe_top_map");
    g.sample_size(10);
    g.throughput(Throughput::Elements(points.len() as u64));
    for threads in [1, 2] {
        g.bench_function(format!("cores_{threads}"), |b| {
            b.iter(|| {
                let mut n = 0;
                study
                    .run_many(black_box(&points), threads, &cancel, |r| {
                        black_box(r);
                        n += 1;
                    })
                    .unwrap();
                assert_eq!(n, points.len());
            })
        });
    }
    g.finish();
}

fn overhead(c: &mut Criterion) {
    let study = map();
    let points = sample(&study);
    let scenes: Vec<_> = points
        .iter()
        .map(|&i| study.scenario(&study.resolve(i).unwrap()).unwrap().scene)
        .collect();
    let mut g = c.benchmark_group("per_run");
    g.sample_size(10);
    g.throughput(Throughput::Elements(points.len() as u64));
    g.bench_function("bare_simulate", |b| {
        b.iter(|| {
            for s in &scenes {
                black_box(simulate(black_box(s), &mut |x| {
                    black_box(x);
                    ControlFlow::Continue(())
                }))
                .ok();
            }
        })
    });
    g.bench_function("study_run_point", |b| {
        b.iter(|| {
            for &i in &points {
                black_box(study.run_point(black_box(i), None));
            }
        })
    });
    g.finish();
}

criterion_group!(benches, throughput, overhead);
criterion_main!(benches);
