//! Stepper overhead: a whole integration against the bare cost of the right-hand-side
//! evaluations it makes, replayed on the very (t, y) the run visited.
//!
//! `cargo bench -p ellipsoid-core --bench overhead`. For each method on the frictionless
//! top (14-component state), criterion times `run/<method>` (integrate, no samples, no
//! events) and two replays of the recorded rhs calls: `rhs_replay_chained` (each input
//! depends on the previous result, as stages do: the latency-bound cost a stepper with
//! free bookkeeping would pay) and `rhs_replay` (independent calls, which the CPU
//! overlaps). Afterwards an interleaved measurement (medians of 31 triples, so a change
//! in background load hits all alike) prints overhead = run/chained − 1, and run/indep. − 1.
//! Target: ≤ 30 % for every method. Last, the whole loop's cost per step with a trivial
//! linear rhs bounds the stepper's bookkeeping from above.

use std::cell::RefCell;
use std::hint::black_box;
use std::ops::ControlFlow;
use std::time::Instant;

use criterion::{Criterion, Throughput};
use ellipsoid_core::body::Body;
use ellipsoid_core::integrate::{Method, OdeSystem, Options, Solution, integrate};
use ellipsoid_core::model::{Frictionless, System};
use ellipsoid_core::state::{self, DIM, EulerAngles, State};

fn top() -> System<Frictionless, ()> {
    let (a, c, m) = (0.025, 0.0175, 0.05);
    let body = Body::of_revolution(
        a,
        c,
        m,
        m * (a * a + c * c) / 5.0,
        2.0 * m * a * a / 5.0,
        0.003,
    )
    .unwrap();
    System {
        body,
        gravity: 9.81,
        contact: Frictionless,
        effects: (),
    }
}

/// The nutation scene's start, tilted and precessing a little so no component is zero.
fn start() -> State {
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
    y
}

/// Records every rhs call of the system it wraps.
struct Recording<'s, S> {
    inner: &'s S,
    calls: RefCell<Vec<(f64, State)>>,
}

impl<S: OdeSystem<DIM>> OdeSystem<DIM> for Recording<'_, S> {
    fn rhs(&self, t: f64, y: &State) -> State {
        self.calls.borrow_mut().push((t, *y));
        self.inner.rhs(t, y)
    }
    fn project(&self, y: &mut State) {
        self.inner.project(y)
    }
}

/// (name, method, options, t_end): the settings of `benches/models.rs`' step bench, over
/// spans that keep the recorded states within L2 (≤ ~1 MB).
fn cases() -> Vec<(&'static str, Method, Options<DIM>, f64)> {
    vec![
        (
            "rk4",
            Method::Rk4 { h: 1e-4 },
            Options::new(1e-10, 1e-12),
            0.1,
        ),
        ("dopri5", Method::Dopri5, Options::new(1e-10, 1e-12), 0.5),
        ("dop853", Method::Dop853, Options::new(1e-12, 1e-12), 1.0),
    ]
}

fn run<S: OdeSystem<DIM>>(
    sys: &S,
    method: Method,
    options: &Options<DIM>,
    t_end: f64,
) -> Solution<DIM> {
    integrate(
        method,
        sys,
        0.0,
        start(),
        t_end,
        options,
        &[],
        &[],
        &mut |_, _| ControlFlow::Continue(()),
    )
    .unwrap()
}

/// The recorded calls, independent of one another: the CPU overlaps consecutive
/// evaluations (throughput).
fn replay<S: OdeSystem<DIM>>(sys: &S, calls: &[(f64, State)]) -> f64 {
    let mut acc = 0.0;
    for (t, y) in calls {
        acc += black_box(sys.rhs(*t, black_box(y)))[0];
    }
    acc
}

/// The recorded calls, each input made to depend on the previous result (y + 0·f, the
/// same values) as a Runge–Kutta stage depends on the last: no overlap (latency), which
/// is what a stepper with free bookkeeping would achieve.
fn replay_chained<S: OdeSystem<DIM>>(sys: &S, calls: &[(f64, State)]) -> f64 {
    let mut f = State::zeros();
    for (t, y) in calls {
        let input = y + f * 0.0;
        f = sys.rhs(*t, black_box(&input));
    }
    f[0]
}

fn recorded(method: Method, options: &Options<DIM>, t_end: f64) -> Vec<(f64, State)> {
    let sys = top();
    let rec = Recording {
        inner: &sys,
        calls: RefCell::new(Vec::new()),
    };
    let sol = run(&rec, method, options, t_end);
    let calls = rec.calls.into_inner();
    assert_eq!(calls.len() as u64, sol.stats.rhs_evals);
    calls
}

fn groups(c: &mut Criterion) {
    let sys = top();
    for (name, method, options, t_end) in cases() {
        let calls = recorded(method, &options, t_end);
        let mut group = c.benchmark_group("overhead");
        group.throughput(Throughput::Elements(calls.len() as u64));
        group.bench_function(format!("run/{name}"), |b| {
            b.iter(|| black_box(run(black_box(&sys), method, &options, t_end)))
        });
        group.bench_function(format!("rhs_replay/{name}"), |b| {
            b.iter(|| replay(black_box(&sys), black_box(&calls)))
        });
        group.bench_function(format!("rhs_replay_chained/{name}"), |b| {
            b.iter(|| replay_chained(black_box(&sys), black_box(&calls)))
        });
        group.finish();
    }
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Interleaved timing; prints one line per method.
fn table() {
    let sys = top();
    println!(
        "\nstepper overhead, interleaved medians of 31 (run, chained replay, independent replay) triples:"
    );
    println!(
        "{:<8} {:>6} {:>6} {:>10} {:>10} {:>10} {:>8} {:>8} {:>9} {:>10} {:>10}",
        "method",
        "steps",
        "rhs",
        "run",
        "chained",
        "indep.",
        "ns/rhs",
        "ns/rhs",
        "ns/step",
        "overhead",
        "vs indep."
    );
    for (name, method, options, t_end) in cases() {
        let calls = recorded(method, &options, t_end);
        let steps = run(&sys, method, &options, t_end).stats.accepted;
        let (mut runs, mut chained, mut replays) = (Vec::new(), Vec::new(), Vec::new());
        for _ in 0..31 {
            let t0 = Instant::now();
            black_box(run(black_box(&sys), method, &options, t_end));
            runs.push(t0.elapsed().as_secs_f64());
            let t0 = Instant::now();
            black_box(replay_chained(black_box(&sys), black_box(&calls)));
            chained.push(t0.elapsed().as_secs_f64());
            let t0 = Instant::now();
            black_box(replay(black_box(&sys), black_box(&calls)));
            replays.push(t0.elapsed().as_secs_f64());
        }
        let (r, c, p) = (median(runs), median(chained), median(replays));
        let n = calls.len() as f64;
        println!(
            "{name:<8} {steps:>6} {:>6} {:>8.1}µs {:>8.1}µs {:>8.1}µs {:>8.1} {:>8.1} {:>9.1} {:>9.1}% {:>9.1}%",
            calls.len(),
            r * 1e6,
            c * 1e6,
            p * 1e6,
            c / n * 1e9,
            p / n * 1e9,
            (r - c) / steps as f64 * 1e9,
            (r / c - 1.0) * 100.0,
            (r / p - 1.0) * 100.0
        );
    }
}

/// dy/dt = P y − y/2 with P the cyclic shift: 14 additions and multiplications, so a run
/// costs little more than its stepper's bookkeeping.
struct Shift;

impl OdeSystem<DIM> for Shift {
    fn rhs(&self, _t: f64, y: &State) -> State {
        State::from_fn(|i, _| y[(i + 1) % DIM] - 0.5 * y[i])
    }
}

/// Best of 15 runs of each method on `Shift` over 20 s, per accepted step.
fn bookkeeping() {
    println!("\nwhole loop with a trivial rhs (upper bound of the bookkeeping), best of 15:");
    let y0 = State::from_fn(|i, _| 1.0 + 0.1 * i as f64);
    for (name, method, options, _) in cases() {
        let mut best = f64::INFINITY;
        let mut steps = 0;
        for _ in 0..15 {
            let t0 = Instant::now();
            let sol = integrate(
                method,
                black_box(&Shift),
                0.0,
                y0,
                20.0,
                &options,
                &[],
                &[],
                &mut |_, _| ControlFlow::Continue(()),
            );
            best = best.min(t0.elapsed().as_secs_f64());
            steps = sol.unwrap().stats.accepted;
        }
        println!(
            "{name:<8} {steps:>7} steps {:>8.1} ns/step",
            best / steps as f64 * 1e9
        );
    }
}

fn main() {
    let mut c = Criterion::default().configure_from_args();
    groups(&mut c);
    c.final_summary();
    table();
    bookkeeping();
}
