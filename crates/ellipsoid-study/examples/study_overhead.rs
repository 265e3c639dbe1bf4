//! The study's cost per run against the bare `simulate` of the same scenes, in CPU time of
//! the measuring thread (less sensitive to other processes on a shared machine than the
//! wall time criterion reports): 100 points of the tippe-top map (every 16th), bare and
//! through `Study::run_point`, interleaved, 7 rounds; prints the medians and the overhead.
//! Also the cost of the study's own steps for one point (resolve + parse, summary).
//!
//! `cargo run --release -p ellipsoid-study --example study_overhead [STUDY.toml]`
//!
//! With a second argument `stats` it prints the points' right-hand-side evaluations and
//! steps, and a hash of their final states (equal for bit-identical results). With `bare`, `study` or `none` it runs the points once that way and prints
//! nothing: for instruction counts, which do not depend on the machine's load
//! (`perf stat -e instructions target/release/examples/study_overhead STUDY.toml bare`;
//! `none` is the common setup, to subtract).

use std::hint::black_box;
use std::ops::ControlFlow;
use std::path::{Path, PathBuf};

use ellipsoid_core::simulate::simulate;
use ellipsoid_study::study::{Study, spec};

fn cpu_seconds() -> f64 {
    let mut ts = libc_timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // CLOCK_THREAD_CPUTIME_ID = 3 on Linux.
    unsafe { clock_gettime(3, &mut ts) };
    ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9
}

#[repr(C)]
struct libc_timespec {
    tv_sec: i64,
    tv_nsec: i64,
}

unsafe extern "C" {
    fn clock_gettime(clock: i32, ts: *mut libc_timespec) -> i32;
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let path = std::env::args()
        .nth(1)
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../../studies/tippe-top-map.toml")
        });
    let study = Study::new(spec::load(&path).expect("study")).expect("valid");
    let points: Vec<usize> = (0..study.len())
        .step_by((study.len() / 100).max(1))
        .collect();
    let scenes: Vec<_> = points
        .iter()
        .map(|&i| study.scenario(&study.resolve(i).unwrap()).unwrap().scene)
        .collect();
    match std::env::args().nth(2).as_deref() {
        Some("none") => return,
        Some("bare") => {
            for s in &scenes {
                black_box(simulate(black_box(s), &mut |x| {
                    black_box(x);
                    ControlFlow::Continue(())
                }))
                .ok();
            }
            return;
        }
        Some("stats") => {
            // What the points cost in the integrator's own units, to turn instruction
            // counts and times into figures per right-hand side.
            // The FNV-1a hash of every final state's bits tells two builds' results
            // apart (equal: bit-identical).
            let (mut rhs, mut steps, mut hash) = (0u64, 0u64, 0xcbf2_9ce4_8422_2325u64);
            for s in &scenes {
                let out = simulate(s, &mut |_| ControlFlow::Continue(())).expect("runs");
                rhs += out.stats.rhs_evals;
                steps += out.stats.accepted + out.stats.rejected;
                for b in out
                    .final_state
                    .iter()
                    .flat_map(|x| x.to_bits().to_le_bytes())
                {
                    hash = (hash ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
                }
            }
            println!(
                "{} points: {rhs} rhs evaluations ({:.0} per run), {steps} steps, final states {hash:016x}",
                scenes.len(),
                rhs as f64 / scenes.len() as f64
            );
            return;
        }
        Some("study") => {
            for &i in &points {
                black_box(study.run_point(black_box(i), None));
            }
            return;
        }
        _ => {}
    }
    let (mut bare, mut full) = (Vec::new(), Vec::new());
    for _ in 0..7 {
        let t = cpu_seconds();
        for s in &scenes {
            black_box(simulate(black_box(s), &mut |x| {
                black_box(x);
                ControlFlow::Continue(())
            }))
            .ok();
        }
        bare.push(cpu_seconds() - t);
        let t = cpu_seconds();
        for &i in &points {
            black_box(study.run_point(black_box(i), None));
        }
        full.push(cpu_seconds() - t);
    }
    let (b, f) = (median(bare), median(full));
    let n = points.len() as f64;
    println!(
        "{} points: bare simulate {:.3} ms/run, study {:.3} ms/run: overhead {:+.2} % ({:.1} µs/run)",
        points.len(),
        b / n * 1e3,
        f / n * 1e3,
        (f / b - 1.0) * 100.0,
        (f - b) / n * 1e6
    );
    // The study's own steps for one point, without the run.
    let reps = 2000;
    let t = cpu_seconds();
    for k in 0..reps {
        black_box(study.resolve(points[k % points.len()]).unwrap());
    }
    let resolve = (cpu_seconds() - t) / reps as f64;
    let r = study.resolve(points[0]).unwrap();
    let t = cpu_seconds();
    for _ in 0..reps {
        black_box(study.scenario(black_box(&r)).unwrap());
    }
    let parse = (cpu_seconds() - t) / reps as f64;
    println!(
        "per point: resolve + hash {:.1} µs, parse the scenario {:.1} µs",
        resolve * 1e6,
        parse * 1e6
    );
}
