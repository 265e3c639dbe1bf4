//! What a sample costs (issue #18): 10 s of the frictionless nutation scene
//! (scenarios/nutation.toml at rtol = 1e-8, atol = 1e-10) with a sample every 1 ms
//! (10 001 rows), run through `ellipsoid_io::run::run` as `ellipsoid run` does it:
//!
//! - `integration`: no samples but the first and last (the physics alone);
//! - `samples`: every row built (dense output, Euler angles, invariants) and dropped;
//! - `kept`: every row built and kept in a `Vec`, as the Python package's `simulate`
//!   does (its numpy columns are made from it on first access; benches/python_samples.py
//!   measures that side);
//! - `columns`: the kept rows turned into one vector per column
//!   (`ellipsoid_io::columns::column_major`, the Rust side of the package's first column
//!   access; no run);
//! - `csv_rows`: every row formatted as CSV and thrown away (`io::sink`: the CPU cost);
//! - `csv`: every row formatted into a CSV file (a temporary file, written and synced to
//!   disk as `ellipsoid run` does before renaming it into place, then removed);
//! - `hdf5`: every row kept and written as one HDF5 file (default build).
//!
//! Throughput is in rows, so criterion's per-element time of `csv` minus `integration`
//! is the cost of one CSV row end to end. `cargo bench -p ellipsoid-io --bench output`.

use std::path::Path;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use ellipsoid_core::scenario::{self, Scenario};
use ellipsoid_io::csv::CsvWriter;
use ellipsoid_io::run::{Finished, run};
use ellipsoid_io::{Metadata, TrajectoryWriter};

const ROWS: u64 = 10_001;

fn nutation(dt: &str) -> Scenario {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/nutation.toml");
    let sets = [
        "solver.rtol=1e-8".to_owned(),
        "solver.atol=1e-10".to_owned(),
        format!("output.dt={dt}"),
    ];
    scenario::load(&path, &sets).expect("the bundled nutation scene")
}

fn finished<E>(r: Result<Finished, ellipsoid_io::run::Failure<E>>) -> Finished {
    match r {
        Ok(f) => f,
        Err(_) => panic!("the nutation scene runs"),
    }
}

/// Runs `scene` into a trajectory file at `path` and completes it without putting it in
/// place (the temporary file is removed when the prepared file drops).
fn to_file(scene: &Scenario, path: &Path) -> u64 {
    let mut w = TrajectoryWriter::create(path).expect("a writable temporary directory");
    let f = finished(run(scene, None, "bench", None, |s| w.write(s)));
    let rows = w.rows();
    let meta = Metadata {
        scenario_text: &scene.text,
        summary: &f.summary,
    };
    drop(w.prepare(&meta).expect("the file completes"));
    rows
}

fn output(c: &mut Criterion) {
    let dir = tempfile::tempdir().expect("a temporary directory");
    let sampled = nutation("1e-3");
    let bare = nutation("10");
    let mut g = c.benchmark_group("nutation_10s_1ms");
    g.sample_size(20);
    g.throughput(Throughput::Elements(ROWS));
    g.bench_function("integration", |b| {
        b.iter(|| {
            finished(run(&bare, None, "bench", None, |_| {
                Ok::<(), ellipsoid_io::OutputError>(())
            }))
        })
    });
    g.bench_function("samples", |b| {
        b.iter(|| {
            finished(run(&sampled, None, "bench", None, |_| {
                Ok::<(), ellipsoid_io::OutputError>(())
            }))
        })
    });
    g.bench_function("kept", |b| {
        b.iter(|| {
            let mut kept = Vec::new();
            finished(run(&sampled, None, "bench", None, |s| {
                kept.push(*s);
                Ok::<(), ellipsoid_io::OutputError>(())
            }));
            kept.len()
        })
    });
    let mut kept = Vec::new();
    finished(run(&sampled, None, "bench", None, |s| {
        kept.push(*s);
        Ok::<(), ellipsoid_io::OutputError>(())
    }));
    let layout = ellipsoid_io::columns::Layout::of(&sampled.scene.body);
    g.bench_function("columns", |b| {
        b.iter(|| ellipsoid_io::columns::column_major(&layout, &kept))
    });
    g.bench_function("csv_rows", |b| {
        b.iter(|| {
            let mut w = CsvWriter::new(std::io::sink()).expect("a sink takes the header");
            finished(run(&sampled, None, "bench", None, |s| w.write(s)));
            w.rows()
        })
    });
    let mut formats = vec!["csv"];
    if cfg!(feature = "hdf5") {
        formats.push("h5");
    }
    for ext in formats {
        let path = dir.path().join(format!("nutation.{ext}"));
        assert_eq!(to_file(&sampled, &path), ROWS);
        g.bench_function(if ext == "h5" { "hdf5" } else { ext }, |b| {
            b.iter(|| to_file(&sampled, &path))
        });
    }
    g.finish();
}

criterion_group!(benches, output);
criterion_main!(benches);
