//! Validation of the ODE integrators against closed-form solutions, Hairer's published
//! Fortran results and the defining properties of events, samples and failures.
//!
//! Naming: `val_*` compare with an analytic or external reference, `inv_*` check a
//! property that must hold whatever the numbers (input validation, conservation).
//! Run in release for speed: `cargo test --release -p ellipsoid-core --test val_integrators`.

use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};
use std::ops::ControlFlow;

use ellipsoid_core::integrate::problems::{
    Arenstorf, Decay, ExpSinSquared, HarmonicOscillator, VanDerPol,
};
use ellipsoid_core::integrate::{
    Action, Direction, Event, EventFn, IntegrateError, Method, OdeSystem, Options, Solution,
    StopReason, Warning, integrate,
};
use nalgebra::{SVector, Vector2, Vector4};

const ADAPTIVE: [Method; 2] = [Method::Dopri5, Method::Dop853];

/// Counts heap allocations per thread, so a test can check that the work per step
/// allocates nothing (other tests running in parallel are on other threads).
struct CountingAllocator;

thread_local! {
    static ALLOCATIONS: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
}

// SAFETY: forwards to the system allocator; only adds a thread-local counter.
unsafe impl std::alloc::GlobalAlloc for CountingAllocator {
    unsafe fn alloc(&self, layout: std::alloc::Layout) -> *mut u8 {
        let _ = ALLOCATIONS.try_with(|n| n.set(n.get() + 1));
        unsafe { std::alloc::System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: std::alloc::Layout) {
        unsafe { std::alloc::System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

fn allocations() -> u64 {
    ALLOCATIONS.with(|n| n.get())
}

/// Integrates without events or samples.
fn solve<S: OdeSystem<N>, const N: usize>(
    method: Method,
    system: &S,
    y0: SVector<f64, N>,
    t_end: f64,
    options: &Options<N>,
) -> Solution<N> {
    integrate(
        method,
        system,
        0.0,
        y0,
        t_end,
        options,
        &[],
        &[],
        &mut |_, _| ControlFlow::Continue(()),
    )
    .expect("valid input")
}

/// Least-squares slope of ln(err) against ln(h).
fn fitted_slope(points: &[(f64, f64)]) -> f64 {
    let n = points.len() as f64;
    let (lx, ly): (Vec<f64>, Vec<f64>) = points.iter().map(|&(h, e)| (h.ln(), e.ln())).unzip();
    let (mx, my) = (lx.iter().sum::<f64>() / n, ly.iter().sum::<f64>() / n);
    let sxy: f64 = lx.iter().zip(&ly).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = lx.iter().map(|x| (x - mx).powi(2)).sum();
    sxy / sxx
}

/// Nine step counts spread log-uniformly over one decade from `n0`.
fn decade_of_step_counts(n0: usize) -> Vec<usize> {
    (0..=8)
        .map(|i| (n0 as f64 * 10f64.powf(i as f64 / 8.0)).round() as usize)
        .collect()
}

/// Runs `method` on [`ExpSinSquared`] over [0, t_end] with exactly `n` equal steps and
/// returns the largest relative error at the step ends.
///
/// Adaptive methods take fixed steps through the public options: h0 = h_max = h and
/// rtol = atol = 1, so every error test passes by a wide margin and the controller's
/// proposal (≥ h) is capped at h_max. The caller checks `accepted == n, rejected == 0`,
/// which proves the step sequence really was the fixed one; the measured slope is then
/// the order of the propagated solution, not an artefact of step-size selection.
fn fixed_step_error(method: Method, n: usize, t_end: f64) -> f64 {
    let h = t_end / n as f64;
    let method = match method {
        Method::Rk4 { .. } => Method::Rk4 { h },
        m => m,
    };
    let mut options = Options::new(1.0, 1.0);
    options.h0 = Some(h);
    options.h_max = h;
    let nodes: Vec<f64> = (1..=n).map(|k| (k as f64 * h).min(t_end)).collect();
    let mut worst: f64 = 0.0;
    let mut observe = |t: f64, y: &Vector4<f64>| {
        let exact = ExpSinSquared::exact(t);
        let rel = (y - exact)
            .component_div(&exact.map(|v| v.abs().max(1.0)))
            .amax();
        worst = worst.max(rel);
        ControlFlow::Continue(())
    };
    let sol = integrate(
        method,
        &ExpSinSquared,
        0.0,
        ExpSinSquared::exact(0.0),
        t_end,
        &options,
        &[],
        &nodes,
        &mut observe,
    )
    .expect("valid input");
    assert_eq!(sol.stop, StopReason::Reached);
    assert_eq!(
        (sol.stats.accepted, sol.stats.rejected),
        (n as u64, 0),
        "{}: not a fixed-step run",
        method.name()
    );
    worst
}

/// Global order measured over a decade of fixed step sizes on a nonlinear,
/// non-autonomous system (a linear or scalar problem would not test every order
/// condition). Intervals and step ranges are chosen in the asymptotic range, above
/// round-off: errors span ~1e-3..1e-7 (RK4), ~1e-6..1e-11 (DOPRI5), ~1e-6..1e-14 (DOP853).
fn measured_order(method: Method, n0: usize, t_end: f64) -> f64 {
    let points: Vec<(f64, f64)> = decade_of_step_counts(n0)
        .into_iter()
        .map(|n| (t_end / n as f64, fixed_step_error(method, n, t_end)))
        .collect();
    fitted_slope(&points)
}

#[test]
fn val_rk4_global_order_is_4() {
    let p = measured_order(Method::Rk4 { h: 0.0 }, 20, 1.0);
    assert!((p - 4.0).abs() <= 0.3, "RK4 measured order {p:.3}");
}

#[test]
fn val_dopri5_global_order_is_5() {
    let p = measured_order(Method::Dopri5, 40, 1.5);
    assert!((p - 5.0).abs() <= 0.3, "DOPRI5 measured order {p:.3}");
}

#[test]
fn val_dop853_global_order_is_8() {
    let p = measured_order(Method::Dop853, 4, 1.0);
    assert!((p - 8.0).abs() <= 0.3, "DOP853 measured order {p:.3}");
}

/// Hairer's `dopri5.f` on the Arenstorf orbit with RTOL = ATOL = 1e-7 and an initial
/// step of 1e-4 (the driver in russell_ode's `data/fortran_dopri5_arenstorf.txt`):
/// 217 accepted, 21 rejected steps, and the final state printed there. Hairer counts
/// 1430 function calls because DOPCOR adds 2 for the start whether or not HINIT runs;
/// we count the 1429 real ones.
#[test]
fn val_dopri5_arenstorf_matches_hairer_dopri5f() {
    let mut options = Options::new(1e-7, 1e-7);
    options.h0 = Some(1e-4);
    let sol = solve(
        Method::Dopri5,
        &Arenstorf,
        Arenstorf::y0(),
        Arenstorf::PERIOD,
        &options,
    );
    assert_eq!(sol.stop, StopReason::Reached);
    assert_eq!(sol.t, Arenstorf::PERIOD);
    assert_eq!((sol.stats.accepted, sol.stats.rejected), (217, 21));
    assert_eq!(sol.stats.rhs_evals, 1429);
    let fortran = Vector4::new(
        9.940021704030663e-01,
        9.040891036151961e-06,
        1.459758305600828e-03,
        -2.001245515834718e+00,
    );
    assert!(
        (sol.y - fortran).amax() < 1e-9,
        "final state differs from dopri5.f: {:?}",
        sol.y - fortran
    );
}

/// Hairer's `dop853.f` on Van der Pol's equation in its scaled form (ε = 1e-3, y(0) =
/// (2, 0), t ∈ [0, 2], RTOL = ATOL = 1e-9, H = 1e-6; russell_ode's
/// `data/logs/fortran_dop853_van_der_pol.txt`): 1348 accepted, 121 rejected steps.
#[test]
fn val_dop853_van_der_pol_matches_hairer_dop853f() {
    let mut options = Options::new(1e-9, 1e-9);
    options.h0 = Some(1e-6);
    let sol = solve(
        Method::Dop853,
        &VanDerPol::scaled(1e-3),
        Vector2::new(2.0, 0.0),
        2.0,
        &options,
    );
    assert_eq!(sol.stop, StopReason::Reached);
    assert_eq!((sol.stats.accepted, sol.stats.rejected), (1348, 121));
    let fortran = Vector2::new(1.763234540172087e+00, -8.35688681930191e-01);
    assert!(
        (sol.y - fortran).amax() < 1e-11,
        "final state differs from dop853.f: {:?}",
        sol.y - fortran
    );
}

/// After one period the Arenstorf orbit is back at its start; the error there shrinks in
/// proportion to the tolerance (Hairer's controllers are close to tolerance
/// proportional: the error/tol ratio stays within a factor ~10 over six decades).
#[test]
fn val_arenstorf_returns_after_one_period_with_error_following_tolerance() {
    for (method, tols) in [
        (Method::Dopri5, [1e-7, 1e-9, 1e-11, 1e-12]),
        (Method::Dop853, [1e-6, 1e-8, 1e-10, 1e-12]),
    ] {
        let mut points = Vec::new();
        let mut prev = f64::INFINITY;
        for tol in tols {
            let sol = solve(
                method,
                &Arenstorf,
                Arenstorf::y0(),
                Arenstorf::PERIOD,
                &Options::new(tol, tol),
            );
            assert_eq!(sol.stop, StopReason::Reached);
            let err = (sol.y - Arenstorf::y0()).amax();
            assert!(
                err < 1e5 * tol,
                "{}: error {err:e} at tol {tol:e}",
                method.name()
            );
            assert!(
                err < prev / 5.0,
                "{}: error {err:e} at tol {tol:e} did not shrink (before: {prev:e})",
                method.name()
            );
            prev = err;
            points.push((tol, err));
        }
        let slope = fitted_slope(&points);
        assert!(
            (0.7..=1.3).contains(&slope),
            "{}: d ln(err)/d ln(tol) = {slope:.2}",
            method.name()
        );
    }
}

/// Over one step of size h from (t0, y(t0)), the dense output at mid-step must have the
/// error of a continuous extension of order q, i.e. O(h^(q+1)) like a local error:
/// q = 3 (RK4), 4 (DOPRI5), 7 (DOP853). Measured as the slope of the mid-step error
/// over a range of h (at least q + 1; DOP853's interpolant is in fact as good as its
/// O(h⁹) local error at θ = 1/2 in this range), and compared with the error at the step
/// end. A wrong dense coefficient breaks an order condition and drops the slope.
#[test]
fn val_dense_output_mid_step_error_scales_like_a_local_error() {
    let t0 = 0.5;
    for (method, q, hs) in [
        (Method::Rk4 { h: 0.0 }, 3.0, [0.1, 0.05, 0.025, 0.0125]),
        (Method::Dopri5, 4.0, [0.1, 0.05, 0.025, 0.0125]),
        (Method::Dop853, 7.0, [0.2, 0.14, 0.1, 0.07]),
    ] {
        let mut points = Vec::new();
        for h in hs {
            let method = match method {
                Method::Rk4 { .. } => Method::Rk4 { h },
                m => m,
            };
            let mut options = Options::new(1.0, 1.0);
            options.h0 = Some(h);
            let mut mid = Vector4::zeros();
            let sol = integrate(
                method,
                &ExpSinSquared,
                t0,
                ExpSinSquared::exact(t0),
                t0 + h,
                &options,
                &[],
                &[t0 + h / 2.0],
                &mut |_, y| {
                    mid = *y;
                    ControlFlow::Continue(())
                },
            )
            .unwrap();
            assert_eq!(sol.stats.accepted + sol.stats.rejected, 1, "one step");
            let err_mid = (mid - ExpSinSquared::exact(t0 + h / 2.0)).amax();
            let err_end = (sol.y - ExpSinSquared::exact(t0 + h)).amax();
            // mid-step error within reach of the step's own local error
            assert!(
                err_mid < 1e3 * err_end.max(1e-15),
                "{}: mid {err_mid:e}, end {err_end:e}",
                method.name()
            );
            points.push((h, err_mid));
        }
        let slope = fitted_slope(&points);
        assert!(
            (q + 0.7..=q + 2.5).contains(&slope),
            "{}: mid-step error ∝ h^{slope:.2}, expected at least h^{}",
            method.name(),
            q + 1.0
        );
    }
}

fn oscillator_events<'a>(direction: Direction, action: Action) -> Vec<Event<'a, 2>> {
    vec![Event {
        g: Box::new(|_, y: &Vector2<f64>| y[0]),
        direction,
        action,
        curvature: None,
    }]
}

/// Runs the oscillator x = cos 2t (ω = 2, y0 = (1, 0)) with the given events.
fn oscillator_run(
    method: Method,
    events: &[Event<'_, 2>],
    t_end: f64,
    samples: &[f64],
) -> (Solution<2>, Vec<f64>) {
    let osc = HarmonicOscillator { omega: 2.0 };
    let mut seen = Vec::new();
    let sol = integrate(
        method,
        &osc,
        0.0,
        Vector2::new(1.0, 0.0),
        t_end,
        &Options::new(1e-12, 1e-12),
        events,
        samples,
        &mut |t, _| {
            seen.push(t);
            ControlFlow::Continue(())
        },
    )
    .unwrap();
    (sol, seen)
}

fn event_methods() -> [Method; 3] {
    [Method::Rk4 { h: 1e-3 }, Method::Dopri5, Method::Dop853]
}

/// x = cos 2t crosses zero at t = π/4 + kπ/2; every crossing is found, in order, to 1e-10.
#[test]
fn val_events_locate_oscillator_zero_crossings() {
    for method in event_methods() {
        let events = oscillator_events(Direction::Either, Action::Continue);
        let (sol, _) = oscillator_run(method, &events, 10.0, &[]);
        assert_eq!(sol.stop, StopReason::Reached);
        let expected: Vec<f64> = (0..)
            .map(|k| FRAC_PI_4 + k as f64 * FRAC_PI_2)
            .take_while(|&t| t < 10.0)
            .collect();
        assert_eq!(sol.events.len(), expected.len(), "{}", method.name());
        assert_eq!(sol.stats.events, expected.len() as u64);
        for (rec, t) in sol.events.iter().zip(&expected) {
            assert_eq!(rec.index, 0);
            assert!(
                (rec.t - t).abs() < 1e-10,
                "{}: event at {} instead of {t}",
                method.name(),
                rec.t
            );
            assert!(
                rec.y[0].abs() < 1e-9,
                "{}: g = {} at the event",
                method.name(),
                rec.y[0]
            );
        }
    }
}

/// Rising crossings of cos 2t are at 3π/4 + kπ; Falling ones at π/4 + kπ.
#[test]
fn val_event_direction_filter() {
    for method in event_methods() {
        for (direction, first) in [
            (Direction::Rising, 3.0 * FRAC_PI_4),
            (Direction::Falling, FRAC_PI_4),
        ] {
            let events = oscillator_events(direction, Action::Continue);
            let (sol, _) = oscillator_run(method, &events, 10.0, &[]);
            let expected: Vec<f64> = (0..)
                .map(|k| first + k as f64 * PI)
                .take_while(|&t| t < 10.0)
                .collect();
            let found: Vec<f64> = sol.events.iter().map(|e| e.t).collect();
            assert_eq!(
                found.len(),
                expected.len(),
                "{} {direction:?}: {found:?}",
                method.name()
            );
            for (f, e) in found.iter().zip(&expected) {
                assert!(
                    (f - e).abs() < 1e-10,
                    "{} {direction:?}: {f} vs {e}",
                    method.name()
                );
            }
        }
    }
}

/// A terminal event ends the run at its time with the dense state there; no sample after
/// it is emitted.
#[test]
fn val_terminal_event_stops_at_the_crossing() {
    let samples: Vec<f64> = (0..=100).map(|i| i as f64 * 0.1).collect();
    for method in event_methods() {
        let events = oscillator_events(Direction::Falling, Action::Stop);
        let (sol, seen) = oscillator_run(method, &events, 10.0, &samples);
        assert_eq!(sol.stop, StopReason::Event { index: 0 });
        assert!(
            (sol.t - FRAC_PI_4).abs() < 1e-10,
            "{}: stopped at {}",
            method.name(),
            sol.t
        );
        assert!(
            (sol.y - Vector2::new(0.0, -2.0)).amax() < 1e-9,
            "{}: y = {:?}",
            method.name(),
            sol.y
        );
        assert_eq!(sol.events.len(), 1);
        assert_eq!(sol.events[0].t, sol.t);
        assert_eq!(sol.events[0].y, sol.y);
        assert_eq!(
            seen,
            samples
                .iter()
                .copied()
                .filter(|&t| t <= FRAC_PI_4)
                .collect::<Vec<_>>()
        );
    }
}

/// The oscillator x = cos 2t over [0, 20] s at rtol = atol = 1e-6 under `method`, with
/// one event: `g` falling through zero, continuing, with the bound `curvature` of |g''|.
fn falling_crossings(method: Method, g: EventFn<'_, 2>, curvature: Option<f64>) -> Solution<2> {
    let events = vec![Event {
        g,
        direction: Direction::Falling,
        action: Action::Continue,
        curvature,
    }];
    integrate(
        method,
        &HarmonicOscillator { omega: 2.0 },
        0.0,
        Vector2::new(1.0, 0.0),
        20.0,
        &Options::new(1e-6, 1e-6),
        &events,
        &[],
        &mut |_, _| ControlFlow::Continue(()),
    )
    .unwrap()
}

/// A dip shorter than one step: x = cos 2t passes below −0.999 for acos(0.999) ≈ 0.045 s
/// around each trough, while DOP853 and DOPRI5 at rtol 1e-6 take steps of more than
/// twice that, so g = x + 0.999 is positive at both ends of the step that contains the
/// dip. Every dip is found by the scan of the dense output inside such steps
/// (docs/integrators.md, "Events"): one falling crossing per period, each at
/// t = (π − acos 0.999)/2 + kπ to the accuracy the tolerance gives the dense output
/// (|δx| ~ 1e-6 over |ẋ| ≈ 0.09 m/s: 1e-4 s).
#[test]
fn val_event_dip_shorter_than_a_step_is_found() {
    let depth: f64 = 0.999;
    let first = (PI - depth.acos()) / 2.0;
    let width = depth.acos();
    for method in [Method::Dopri5, Method::Dop853] {
        let sol = falling_crossings(
            method,
            Box::new(move |_, y: &Vector2<f64>| y[0] + depth),
            None,
        );
        let mean_step = 20.0 / sol.stats.accepted as f64;
        assert!(
            mean_step > 2.0 * width,
            "{}: steps of {mean_step} s resolve the dip ({width} s) without the scan: the test proves nothing",
            method.name()
        );
        let expected: Vec<f64> = (0..)
            .map(|k| first + k as f64 * PI)
            .take_while(|&t| t < 20.0)
            .collect();
        let found: Vec<f64> = sol.events.iter().map(|e| e.t).collect();
        assert_eq!(found.len(), expected.len(), "{}: {found:?}", method.name());
        for (f, e) in found.iter().zip(&expected) {
            assert!((f - e).abs() < 1e-4, "{}: {f} vs {e}", method.name());
        }
    }
}

/// A dip that leaves no trace at the step ends: g(t) = 1 − k exp(−(t − t_d)²/w²) with
/// k = 1 + 1e-4, w = 0.01 s, below zero only for |t − t_d| < w √(ln k) ≈ 1e-4 s, while
/// the oscillator's steps are ~0.1 s. At the step ends g is 1 to 1e-16 and flat, so the
/// heuristic judge (no curvature given) sees no reason to scan and misses it; with the
/// bound |g''| ≤ 2k/w² (`Event::curvature`) the step is scanned and the dip found
/// (docs/integrators.md, "Dense output, samples and events"): one falling crossing at
/// t_d − w √(ln k), to the root finder's tolerance.
#[test]
fn val_event_dip_without_trace_is_found_with_a_curvature_bound() {
    let (k, w, t_d): (f64, f64, f64) = (1.0 + 1e-4, 0.01, 7.3);
    let crossing = t_d - w * k.ln().sqrt();
    for method in [Method::Dopri5, Method::Dop853] {
        let found = |curvature: Option<f64>| {
            let g = move |t: f64, _: &Vector2<f64>| 1.0 - k * (-((t - t_d) / w).powi(2)).exp();
            let sol = falling_crossings(method, Box::new(g), curvature);
            sol.events.iter().map(|e| e.t).collect::<Vec<f64>>()
        };
        assert!(
            found(None).is_empty(),
            "{}: the heuristic found the dip: the test proves nothing",
            method.name()
        );
        let with_bound = found(Some(2.0 * k / (w * w)));
        assert_eq!(with_bound.len(), 1, "{}: {with_bound:?}", method.name());
        assert!(
            (with_bound[0] - crossing).abs() < 1e-12,
            "{}: {} vs {crossing}",
            method.name(),
            with_bound[0]
        );
    }
}

/// g = v = −2 sin 2t is exactly zero at t0 = 0 (as after a mode switch): not an event.
/// The first event is the next zero, t = π/2.
#[test]
fn val_event_zero_at_start_is_ignored() {
    for method in event_methods() {
        let events = vec![Event {
            g: Box::new(|_, y: &Vector2<f64>| y[1]),
            direction: Direction::Either,
            action: Action::Stop,
            curvature: None,
        }];
        let (sol, _) = oscillator_run(method, &events, 10.0, &[]);
        assert_eq!(sol.stop, StopReason::Event { index: 0 });
        assert!(
            (sol.t - FRAC_PI_2).abs() < 1e-10,
            "{}: stopped at {}",
            method.name(),
            sol.t
        );
    }
}

/// Two crossings inside one (deliberately long) step come out in time order; a terminal
/// one drops the later crossings of that step.
#[test]
fn val_events_in_one_step_are_ordered_and_terminal_cuts_the_step() {
    // one RK4 step [0, 1]: cos 2t = 0.5 at t = π/6 ≈ 0.524, = 0.4 at t ≈ 0.580
    let early = 0.5f64.acos() / 2.0;
    let late = 0.4f64.acos() / 2.0;
    let make = |first_action: Action, second_action: Action| -> Vec<Event<'static, 2>> {
        vec![
            Event {
                g: Box::new(|_, y: &Vector2<f64>| y[0] - 0.4),
                direction: Direction::Falling,
                action: first_action,
                curvature: None,
            },
            Event {
                g: Box::new(|_, y: &Vector2<f64>| y[0] - 0.5),
                direction: Direction::Falling,
                action: second_action,
                curvature: None,
            },
        ]
    };
    let osc = HarmonicOscillator { omega: 2.0 };
    let run = |events: &[Event<'_, 2>]| {
        integrate(
            Method::Rk4 { h: 1.0 },
            &osc,
            0.0,
            Vector2::new(1.0, 0.0),
            2.0,
            &Options::new(1e-6, 1e-6),
            events,
            &[],
            &mut |_, _| ControlFlow::Continue(()),
        )
        .unwrap()
    };
    // RK4 with h = 1 is crude (roots ~0.1 early), but each located time is a zero of g
    // on its own dense output
    let sol = run(&make(Action::Continue, Action::Continue));
    let idx: Vec<usize> = sol.events.iter().map(|e| e.index).collect();
    assert_eq!(idx, [1, 0], "time order, not index order");
    assert!(sol.events[0].t < sol.events[1].t && sol.events[1].t < 1.0);
    assert!((sol.events[0].y[0] - 0.5).abs() < 1e-12 && (sol.events[1].y[0] - 0.4).abs() < 1e-12);
    assert!((sol.events[0].t - early).abs() < 0.15 && (sol.events[1].t - late).abs() < 0.15);

    let sol = run(&make(Action::Continue, Action::Stop));
    assert_eq!(sol.stop, StopReason::Event { index: 1 });
    assert_eq!(
        sol.events.len(),
        1,
        "the later crossing in the same step is not reported"
    );
    assert_eq!(sol.stats.accepted, 1);
}

/// A sample at t0 gives y0 itself; interior samples come from the dense output within the
/// tolerance; Break from the observer stops the run there.
#[test]
fn val_samples_and_cancellation() {
    let osc = HarmonicOscillator { omega: 2.0 };
    let y0 = Vector2::new(1.0, 0.0);
    let samples: Vec<f64> = (0..=40).map(|i| i as f64 * 0.25).collect();
    for method in [Method::Rk4 { h: 1e-3 }, Method::Dopri5, Method::Dop853] {
        let mut got = Vec::new();
        let sol = integrate(
            method,
            &osc,
            0.0,
            y0,
            10.0,
            &Options::new(1e-10, 1e-10),
            &[],
            &samples,
            &mut |t, y| {
                got.push((t, *y));
                ControlFlow::Continue(())
            },
        )
        .unwrap();
        assert_eq!(sol.stop, StopReason::Reached);
        assert_eq!(sol.t, 10.0);
        assert_eq!(got.len(), samples.len());
        assert_eq!(got[0], (0.0, y0));
        for (t, y) in &got {
            assert!(
                (y - osc.exact(*t, &y0)).amax() < 1e-7,
                "{} at t = {t}",
                method.name()
            );
        }

        let mut count = 0;
        let sol = integrate(
            method,
            &osc,
            0.0,
            y0,
            10.0,
            &Options::new(1e-10, 1e-10),
            &[],
            &samples,
            &mut |_, _| {
                count += 1;
                if count == 5 {
                    ControlFlow::Break(())
                } else {
                    ControlFlow::Continue(())
                }
            },
        )
        .unwrap();
        assert_eq!(sol.stop, StopReason::Cancelled);
        assert_eq!(sol.t, samples[4]);
        assert!((sol.y - osc.exact(samples[4], &y0)).amax() < 1e-7);
    }
}

/// RK4's last step is shortened to land exactly on t_end; an exact multiple of h takes
/// exactly n steps despite round-off in n·h.
#[test]
fn val_rk4_lands_on_t_end() {
    let osc = HarmonicOscillator { omega: 1.0 };
    let y0 = Vector2::new(1.0, 0.0);
    let opts = Options::new(1e-6, 1e-6);
    let sol = solve(Method::Rk4 { h: 0.3 }, &osc, y0, 1.0, &opts);
    assert_eq!((sol.t, sol.stats.accepted), (1.0, 4));
    let sol = solve(Method::Rk4 { h: 0.1 }, &osc, y0, 1.0, &opts);
    assert_eq!(
        (sol.t, sol.stats.accepted, sol.stats.rhs_evals),
        (1.0, 10, 40)
    );
    let sol = solve(Method::Rk4 { h: 1e-3 }, &osc, y0, 7.0, &opts);
    assert_eq!((sol.t, sol.stats.accepted), (7.0, 7000));
}

/// `project` is applied to every accepted state and to every state handed out: a rotation
/// on the unit circle stays exactly on it although the tolerance is loose.
#[test]
fn inv_projection_applies_to_steps_samples_and_events() {
    struct Circle;
    impl OdeSystem<2> for Circle {
        fn rhs(&self, _t: f64, y: &Vector2<f64>) -> Vector2<f64> {
            Vector2::new(-y[1], y[0])
        }
        fn project(&self, y: &mut Vector2<f64>) {
            y.normalize_mut();
        }
    }
    for method in [Method::Rk4 { h: 0.3 }, Method::Dopri5, Method::Dop853] {
        let events = vec![Event {
            g: Box::new(|_, y: &Vector2<f64>| y[1]),
            direction: Direction::Either,
            action: Action::Continue,
            curvature: None,
        }];
        let samples: Vec<f64> = (1..50).map(|i| i as f64 * 0.37).collect();
        let mut worst: f64 = 0.0;
        let sol = integrate(
            method,
            &Circle,
            0.0,
            Vector2::new(1.0, 0.0),
            20.0,
            &Options::new(1e-3, 1e-3),
            &events,
            &samples,
            &mut |_, y| {
                worst = worst.max((y.norm() - 1.0).abs());
                ControlFlow::Continue(())
            },
        )
        .unwrap();
        assert!(
            (sol.y.norm() - 1.0).abs() < 4.0 * f64::EPSILON,
            "{}",
            method.name()
        );
        assert!(
            worst < 4.0 * f64::EPSILON,
            "{}: sample off the circle by {worst:e}",
            method.name()
        );
        assert!(!sol.events.is_empty());
        for e in &sol.events {
            assert!((e.y.norm() - 1.0).abs() < 4.0 * f64::EPSILON);
        }
    }
}

/// Van der Pol with μ = 1000 is stiff: the explicit methods must say so (Hairer's test)
/// and stop cleanly at max_steps instead of crawling for millions of steps.
#[test]
fn val_stiff_van_der_pol_warns_and_stops_at_max_steps() {
    for method in ADAPTIVE {
        let mut options = Options::new(1e-6, 1e-6);
        options.max_steps = 100_000;
        let sol = solve(
            method,
            &VanDerPol::standard(1000.0),
            Vector2::new(2.0, 0.0),
            3000.0,
            &options,
        );
        let stiff_at = sol.warnings.iter().map(|Warning::Stiff { t }| *t).next();
        assert!(
            stiff_at.is_some(),
            "{}: no stiffness warning",
            method.name()
        );
        match &sol.stop {
            StopReason::Failed(
                err @ IntegrateError::MaxSteps {
                    t,
                    steps,
                    method: used,
                },
            ) => {
                assert_eq!(*steps, 100_000);
                assert_eq!(*t, sol.t);
                assert_eq!(*used, method);
                assert!(sol.t < 3000.0 && sol.y.iter().all(|v| v.is_finite()));
                let msg = err.to_string();
                assert!(msg.contains("100000") && msg.contains("max_steps"), "{msg}");
                // The DOPRI5 remedy is offered to DOPRI5 runs only.
                assert_eq!(
                    msg.contains("use method = \"dop853\""),
                    method == Method::Dopri5,
                    "{msg}"
                );
                assert!(msg.contains(method.name()), "{msg}");
            }
            other => panic!("{}: expected MaxSteps, got {other:?}", method.name()),
        }
        assert_eq!(sol.stats.accepted + sol.stats.rejected, 100_000);
    }
}

/// A run that keeps the motion's own pace but whose t_end lies more than
/// `OVER_BUDGET_FACTOR` × max_steps such steps away fails after 1e5 steps with
/// `OverBudget`, naming the projection, max_steps and the remedy: the harmonic oscillator
/// (period 2π s) over 1e7 s, ~5e7 steps, against max_steps = 2e5. Without a time scale,
/// or with one so long that the steps are a transient's (mean step below `MOTION_PACE`
/// of it), the steps still follow the system's own rate ρ = ω, so it fails after 1e5
/// steps with `FastRate` instead: DOP853's at h·ρ ≈ 0.35 ≥ `FAST_PACE`, DOPRI5's at
/// h·ρ ≈ 0.04, above `FAST_FRACTION` of the h·ρ at which it resolves a rate at rtol =
/// 1e-10 (0.0084). The same oscillator over a t_end that takes 1.5e5 steps (DOPRI5
/// 6e3 s, DOP853 5e4 s), within max_steps = 2e5, completes: a run that legitimately
/// takes many small steps is not stopped.
#[test]
fn inv_run_out_of_budget_at_the_motions_pace_fails_early() {
    use ellipsoid_core::integrate::{MOTION_PACE, OVER_BUDGET_FACTOR};
    let osc = HarmonicOscillator { omega: 1.0 };
    let y0 = Vector2::new(1.0, 0.0);
    for method in ADAPTIVE {
        let run = |time_scale| {
            let mut options = Options::new(1e-10, 1e-10);
            options.max_steps = 200_000;
            options.time_scale = time_scale;
            solve(method, &osc, y0, 1e7, &options)
        };
        let sol = run(Some(1.0));
        let StopReason::Failed(
            e @ IntegrateError::OverBudget {
                t,
                steps,
                projected,
                max_steps,
            },
        ) = &sol.stop
        else {
            panic!("{}: expected OverBudget, got {:?}", method.name(), sol.stop);
        };
        assert_eq!(
            (*steps, *max_steps),
            (100_000, 200_000),
            "{}",
            method.name()
        );
        assert_eq!(sol.stats.accepted + sol.stats.rejected, 100_000);
        assert_eq!(*t, sol.t);
        assert!(sol.y.iter().all(|v| v.is_finite()));
        assert!(
            *projected > OVER_BUDGET_FACTOR * 200_000.0 && sol.t / 100_000.0 >= MOTION_PACE * 1.0,
            "{}: projected {projected:e}, mean step {:e}",
            method.name(),
            sol.t / 100_000.0
        );
        let msg = e.to_string();
        assert!(
            msg.contains("100000 steps")
                && msg.contains(&format!("t = {t} s"))
                && msg.contains(&format!("~{projected:.1e} steps"))
                && msg.contains("max_steps (200000)")
                && msg.contains("raise max_steps")
                && msg.contains("units"),
            "{msg}"
        );
        for time_scale in [None, Some(1e5)] {
            let sol = run(time_scale);
            let StopReason::Failed(IntegrateError::FastRate {
                stiff: false,
                steps: 100_000,
                rate,
                ..
            }) = sol.stop
            else {
                panic!(
                    "{} with time_scale {time_scale:?}: {:?}",
                    method.name(),
                    sol.stop
                );
            };
            assert!((0.5..2.0).contains(&rate), "{}: ρ = {rate}", method.name());
            assert_eq!(sol.stats.accepted + sol.stats.rejected, 100_000);
        }
        let mut options = Options::new(1e-10, 1e-10);
        options.max_steps = 200_000;
        let t_end = if method == Method::Dopri5 { 6e3 } else { 5e4 };
        let sol = solve(method, &osc, y0, t_end, &options);
        assert_eq!(sol.stop, StopReason::Reached, "{}", method.name());
        let steps = sol.stats.accepted + sol.stats.rejected;
        assert!(
            (120_000..200_000).contains(&steps),
            "{}: {steps}",
            method.name()
        );
        let exact = Vector2::new(t_end.cos(), -t_end.sin());
        assert!(
            (sol.y - exact).norm() < 1e-4,
            "{}: {}",
            method.name(),
            (sol.y - exact).norm()
        );
    }
}

/// y' = cos t: the steps follow the motion's time scale, but f does not depend on y, so
/// the system has no rate ρ (the stiffness test's estimate is 0).
struct Quadrature;

impl OdeSystem<1> for Quadrature {
    fn rhs(&self, t: f64, _y: &SVector<f64, 1>) -> SVector<f64, 1> {
        SVector::from([t.cos()])
    }
}

/// A decay far faster than the time asked for (y' = −λy, λ = 1e6 1/s, to t_end = 1e3 s):
/// once y has died out the explicit steps are held at the stability boundary
/// (h ≈ 3.3/λ, 6.1/λ), 2e8–3e8 of them to t_end against max_steps = 1e7. It fails after
/// 1e5 steps (a tenth of a second) with `FastRate`, stiff, naming ρ, the projection and
/// the remedies, instead of grinding through max_steps. The same decay to t_end = 1 s
/// (1.6e5–3e5 steps, within max_steps) completes; a run whose steps do not follow a rate
/// of the system (quadrature of cos t, ρ = 0) goes on to `MaxSteps`.
#[test]
fn inv_stiff_decay_out_of_reach_fails_after_1e5_steps() {
    use ellipsoid_core::integrate::FAST_BUDGET_FACTOR;
    let decay = Decay { lambda: 1e6 };
    let y0 = SVector::from([1.0]);
    for method in ADAPTIVE {
        let options = Options::new(1e-10, 1e-12);
        let sol = solve(method, &decay, y0, 1e3, &options);
        let StopReason::Failed(
            e @ IntegrateError::FastRate {
                stiff: true,
                steps: 100_000,
                rate,
                projected,
                max_steps: 10_000_000,
                ..
            },
        ) = &sol.stop
        else {
            panic!("{}: {:?}", method.name(), sol.stop);
        };
        assert_eq!(sol.stats.accepted + sol.stats.rejected, 100_000);
        assert!(
            (0.8e6..1.25e6).contains(rate),
            "{}: ρ = {rate:e}",
            method.name()
        );
        assert!(*projected > FAST_BUDGET_FACTOR * 1e7, "{projected:e}");
        let msg = e.to_string();
        assert!(
            msg.contains("stiff")
                && msg.contains(&format!("~{projected:.1e} steps"))
                && msg.contains("max_steps (10000000)")
                && msg.contains("damping")
                && msg.contains("shorten t_end"),
            "{msg}"
        );

        let sol = solve(method, &decay, y0, 1.0, &options);
        assert_eq!(sol.stop, StopReason::Reached, "{}", method.name());
        assert!(sol.stats.accepted > 100_000, "{}", method.name());

        let mut options = Options::new(1e-12, 1e-12);
        options.max_steps = 200_000;
        let sol = solve(method, &Quadrature, y0, 1e7, &options);
        assert!(
            matches!(
                sol.stop,
                StopReason::Failed(IntegrateError::MaxSteps { steps: 200_000, .. })
            ),
            "{}: {:?}",
            method.name(),
            sol.stop
        );
    }
}

#[test]
fn inv_invalid_input_is_rejected_before_any_step() {
    let osc = HarmonicOscillator { omega: 1.0 };
    let y0 = Vector2::new(1.0, 0.0);
    let calls = std::cell::Cell::new(0);
    struct Counting<'a>(&'a std::cell::Cell<u32>);
    impl OdeSystem<2> for Counting<'_> {
        fn rhs(&self, _t: f64, y: &Vector2<f64>) -> Vector2<f64> {
            self.0.set(self.0.get() + 1);
            *y
        }
    }
    let err = |method, opts: &Options<2>, t_end, samples: &[f64]| {
        integrate(
            method,
            &Counting(&calls),
            0.0,
            y0,
            t_end,
            opts,
            &[],
            samples,
            &mut |_, _| ControlFlow::Continue(()),
        )
        .expect_err("invalid input must be refused")
    };
    let e = err(Method::Dopri5, &Options::new(1e-20, 1e-10), 1.0, &[]);
    let msg = e.to_string();
    assert!(
        matches!(e, IntegrateError::InvalidOptions { .. })
            && msg.contains("rtol")
            && msg.contains("1e-20"),
        "{msg}"
    );
    assert!(matches!(
        err(Method::Dop853, &Options::new(1e-6, 0.0), 1.0, &[]),
        IntegrateError::InvalidOptions { .. }
    ));
    assert!(matches!(
        err(Method::Dop853, &Options::new(1e-6, -1.0), 1.0, &[]),
        IntegrateError::InvalidOptions { .. }
    ));
    let mut o = Options::new(1e-6, 1e-6);
    o.h0 = Some(0.0);
    assert!(matches!(
        err(Method::Dopri5, &o, 1.0, &[]),
        IntegrateError::InvalidOptions { .. }
    ));
    assert!(matches!(
        err(Method::Rk4 { h: -0.1 }, &Options::new(1e-6, 1e-6), 1.0, &[]),
        IntegrateError::InvalidOptions { .. }
    ));
    assert!(matches!(
        err(Method::Dopri5, &Options::new(1e-6, 1e-6), f64::NAN, &[]),
        IntegrateError::InvalidOptions { .. }
    ));
    for scale in [0.0, -1.0, f64::NAN] {
        let mut o = Options::new(1e-6, 1e-6);
        o.time_scale = Some(scale);
        let e = err(Method::Dop853, &o, 1.0, &[]);
        assert!(e.to_string().contains("time_scale"), "{e}");
    }
    let e = err(Method::Dopri5, &Options::new(1e-6, 1e-6), 1.0, &[0.5, 0.2]);
    assert!(e.to_string().contains("sorted"), "{e}");
    assert!(matches!(
        err(Method::Dopri5, &Options::new(1e-6, 1e-6), 1.0, &[1.5]),
        IntegrateError::InvalidOptions { .. }
    ));
    assert_eq!(calls.get(), 0, "no rhs call before validation");
    let bad_y0 = integrate(
        Method::Dopri5,
        &osc,
        0.0,
        Vector2::new(f64::NAN, 0.0),
        1.0,
        &Options::new(1e-6, 1e-6),
        &[],
        &[],
        &mut |_, _| ControlFlow::Continue(()),
    );
    assert!(matches!(bad_y0, Err(IntegrateError::InvalidOptions { .. })));
}

/// A right-hand side that turns NaN past t = 1 ends the run with `NonFinite` near t = 1,
/// keeping the last good state; one that is NaN from the start fails at t0.
#[test]
fn val_nan_from_rhs_fails_cleanly() {
    struct NanAfter(f64);
    impl OdeSystem<2> for NanAfter {
        fn rhs(&self, t: f64, y: &Vector2<f64>) -> Vector2<f64> {
            if t > self.0 {
                Vector2::repeat(f64::NAN)
            } else {
                Vector2::new(y[1], -y[0])
            }
        }
    }
    for method in [Method::Rk4 { h: 0.01 }, Method::Dopri5, Method::Dop853] {
        let sol = solve(
            method,
            &NanAfter(1.0),
            Vector2::new(1.0, 0.0),
            5.0,
            &Options::new(1e-8, 1e-8),
        );
        match sol.stop {
            StopReason::Failed(IntegrateError::NonFinite { t }) => {
                assert_eq!(t, sol.t);
                assert!(
                    (0.95..=1.0).contains(&t),
                    "{}: failed at t = {t}",
                    method.name()
                );
            }
            ref other => panic!("{}: expected NonFinite, got {other:?}", method.name()),
        }
        assert!(
            sol.y.iter().all(|v| v.is_finite()),
            "{}: last good state must be finite",
            method.name()
        );
        assert!((sol.y - Vector2::new(sol.t.cos(), -sol.t.sin())).amax() < 1e-5);

        let sol = solve(
            method,
            &NanAfter(-1.0),
            Vector2::new(1.0, 0.0),
            5.0,
            &Options::new(1e-8, 1e-8),
        );
        assert_eq!(
            sol.stop,
            StopReason::Failed(IntegrateError::NonFinite { t: 0.0 }),
            "{}",
            method.name()
        );
        assert_eq!(sol.t, 0.0);
    }
}

/// The messages carry the numbers a user needs.
#[test]
fn inv_error_messages_carry_numbers() {
    let e = IntegrateError::StepSizeTooSmall {
        t: 1.234,
        h: 3.2e-15,
    };
    assert_eq!(
        e.to_string(),
        "step size 3.200e-15 s fell below the round-off limit at t = 1.234 s"
    );
    assert!(
        IntegrateError::NonFinite { t: 2.5 }
            .to_string()
            .contains("t = 2.5 s")
    );
}

/// Integrating over an empty interval returns the initial state and emits a sample at t0.
#[test]
fn val_empty_interval() {
    let osc = HarmonicOscillator { omega: 1.0 };
    let y0 = Vector2::new(0.3, 0.1);
    for method in [Method::Rk4 { h: 0.1 }, Method::Dopri5, Method::Dop853] {
        let mut seen = 0;
        let sol = integrate(
            method,
            &osc,
            2.0,
            y0,
            2.0,
            &Options::new(1e-6, 1e-6),
            &[],
            &[2.0],
            &mut |_, _| {
                seen += 1;
                ControlFlow::Continue(())
            },
        )
        .unwrap();
        assert_eq!(
            (sol.t, sol.y, sol.stop, seen, sol.stats.rhs_evals),
            (2.0, y0, StopReason::Reached, 1, 0)
        );
    }
}

/// The cost of a run in heap allocations does not depend on its number of steps,
/// samples or event checks: everything per step lives in fixed-size arrays.
#[test]
fn inv_no_allocation_per_step() {
    let osc = HarmonicOscillator { omega: 2.0 };
    let y0 = Vector2::new(1.0, 0.0);
    for method in [Method::Rk4 { h: 1e-3 }, Method::Dopri5, Method::Dop853] {
        let count = |t_end: f64| {
            // an event that is checked every step but never fires, and a terminal one
            let events = vec![
                Event {
                    g: Box::new(|_, y: &Vector2<f64>| y[0] - 2.0),
                    direction: Direction::Either,
                    action: Action::Continue,
                    curvature: None,
                },
                Event {
                    g: Box::new(|_, y: &Vector2<f64>| y[1] - 3.0),
                    direction: Direction::Rising,
                    action: Action::Stop,
                    curvature: None,
                },
            ];
            let samples: Vec<f64> = (0..=(t_end as usize * 10))
                .map(|i| i as f64 * 0.1)
                .collect();
            let options = Options::new(1e-10, 1e-10);
            let before = allocations();
            let sol = integrate(
                method,
                &osc,
                0.0,
                y0,
                t_end,
                &options,
                &events,
                &samples,
                &mut |_, _| ControlFlow::Continue(()),
            )
            .unwrap();
            let used = allocations() - before;
            assert_eq!(sol.stop, StopReason::Reached);
            (used, sol.stats.accepted)
        };
        let (short, short_steps) = count(1.0);
        let (long, long_steps) = count(100.0);
        assert!(long_steps > 50 * short_steps);
        assert_eq!(
            short,
            long,
            "{}: allocations grow with the number of steps",
            method.name()
        );
        assert!(
            short <= 4,
            "{}: {short} allocations for a run",
            method.name()
        );
    }
}

/// A state of size 1e-150 to 1e-170 (a body at rest on the plane carries velocities of
/// that size, round-off of round-off): y' = −y from such y0 under atol 1e-12. DOP853's error norm,
/// |h| ERR5 √(1/(N (ERR5 + 0.01 ERR3))) as in dop853.f, took the reciprocal of a subnormal
/// sum of squares (errors of 1e-170 against scales of 1e-12), which overflowed: the step
/// was `NonFinite`, and a dumbbell at rest on two contacts ended `solver_failure`. Every
/// method reaches t_end, with y(1) = y0/e to 1e-2 (its error is measured against atol,
/// so a few steps take the whole interval: 5e-4 under DOPRI5).
#[test]
fn a_state_whose_error_norm_is_subnormal_integrates() {
    let decay = Decay { lambda: 1.0 };
    for (method, size) in ADAPTIVE
        .into_iter()
        .flat_map(|m| (150..=170).map(move |k| (m, k)))
    {
        let y0 = SVector::from([10f64.powi(-size)]);
        let sol = solve(method, &decay, y0, 1.0, &Options::new(1e-10, 1e-12));
        assert!(
            matches!(sol.stop, StopReason::Reached),
            "{}, y0 = {:e}: {:?}",
            method.name(),
            y0[0],
            sol.stop
        );
        let exact = y0[0] * (-1.0_f64).exp();
        assert!(
            (sol.y[0] - exact).abs() <= 1e-2 * exact,
            "{}: {:e} against {exact:e}",
            method.name(),
            sol.y[0]
        );
    }
}
