//! The one integration loop shared by every method: step-size bookkeeping, failure
//! detection, stiffness warnings, events and samples on the dense output.

use std::ops::ControlFlow;
use std::sync::atomic::Ordering;

use nalgebra::SVector;

use super::controller::{PiController, Verdict};
use super::dop853::Dop853;
use super::dopri5::Dopri5;
use super::events::{
    SCAN_POINTS, chord_gap, crossed, locate, lowest, may_cross_inside, time_tolerance,
};
use super::options::validate_inputs;
use super::rk4::Rk4;
use super::stepper::{Stepper, Trial};
use super::stiffness::StiffnessDetector;
use super::{
    Action, Event, EventRecord, IntegrateError, Method, OdeSystem, Options, Solution, Stats,
    StopReason, Warning,
};

/// Consecutive non-finite attempts, each shrinking h by `NONFINITE_SHRINK`, before
/// giving up (0.2^20 ≈ 1e-14: past that no step size can help).
const NONFINITE_RETRIES: u32 = 20;
const NONFINITE_SHRINK: f64 = 0.2;
/// A step-size collapse within this many attempts of a non-finite right-hand side is
/// reported as `NonFinite` (its cause), not `StepSizeTooSmall`.
const NONFINITE_MEMORY: u64 = 50;

/// A run whose pace after [`PACE_CHECK_STEPS`] steps projects more than this many times
/// `max_steps` to reach t_end fails at once ([`IntegrateError::Collapsed`]) instead of
/// grinding through `max_steps` to the same failure. The margin is wide: a slow start
/// that later relaxes is never stopped by it (a sliding onset of row 2b's repeated
/// stick–slip, docs/hard-cases.md, projects 1e9 steps at its check after 1e4 steps, 7e4×
/// the 14,005 it takes and 100× the default max_steps), while a scene beyond double
/// precision (semi-axes of 1e20 m, row 11) projects 1e33 and is stopped after 1e4 steps.
pub const HOPELESS_FACTOR: f64 = 1e6;
/// How many steps (accepted + rejected) a run takes before its pace is judged, and how
/// often after that.
const PACE_CHECK_STEPS: u64 = 10_000;
/// A run whose mean step is the motion's own pace (at least [`MOTION_PACE`] of
/// `Options::time_scale`) and projects more than this many times `max_steps` to reach
/// t_end, judged from [`BUDGET_CHECK_STEPS`] steps on, fails at once
/// ([`IntegrateError::OverBudget`]) instead of grinding through `max_steps` to a
/// `MaxSteps` failure. Measured (docs/hard-cases.md row 11b): from 1e5 steps on, runs at
/// such a pace that reach t_end project at most 1.16× the steps they take, while the
/// bundled scenes under a gravity of 1e12 m/s² project 10–550× the default max_steps.
pub const OVER_BUDGET_FACTOR: f64 = 10.0;
/// The smallest mean step, as a fraction of `Options::time_scale`, that counts as the
/// motion's own pace. Runs integrating the motion itself take mean steps of 1.4e-3 to 0.8
/// of √(L/g); the transients that project far beyond their end stay far below 1e-4
/// (docs/hard-cases.md row 11b): a DOP853 stick–slip onset 2e-8 to 9e-6 (over at 1.4e4
/// steps), DOPRI5's onset trap 7e-8 to 1.1e-6 (at rtol 1e-9 and 1e-8, up to 3.7e5 steps).
pub const MOTION_PACE: f64 = 1e-4;
/// The h·ρ (the step times the system's fastest rate ρ, from the stiffness test) at and
/// above which the steps follow that rate, or [`FAST_FRACTION`] of the h·ρ at which the
/// method's accurate steps resolve a rate to the run's tolerance, if that is smaller: a
/// stiff decay holds h·ρ at the method's stability boundary (3.25, 6.1); a fast rotation
/// is resolved at h·ρ ≈ C·rtol^(1/k) (`stiffness::StiffnessParams`: DOP853 0.2–0.36 at
/// rtol 1e-12 to 1e-10, DOPRI5 0.014–0.041, below this 0.1, hence the fraction); the
/// step-size collapses of transients such as stick–slip onsets are set by the accuracy
/// of a short episode, not by ρ.
pub const FAST_PACE: f64 = 0.1;
/// The fraction of the resolving h·ρ (C·rtol^(1/k), rtol the smallest of the run's)
/// that counts as following the rate when it is below [`FAST_PACE`]: 0.0084 for DOPRI5
/// at rtol 1e-10 and 0.0033 at 1e-12 (measured 0.04 and 0.014–0.016 on a fast spin),
/// 0.071 and 0.040 for DOP853 (measured 0.35 and 0.20).
pub const FAST_FRACTION: f64 = 0.2;
/// A run whose steps follow its fastest rate (h·ρ ≥ [`FAST_PACE`], or the calibrated
/// [`FAST_FRACTION`] of the resolving h·ρ) and whose pace over
/// the last [`PACE_CHECK_STEPS`] steps projects more than this many times `max_steps` to
/// reach t_end, judged from [`BUDGET_CHECK_STEPS`] steps on, fails at once
/// ([`IntegrateError::FastRate`]): such a pace is held by the system itself (a decay or a
/// spin does not slow down), and the margin covers the 1.16× by which steady runs'
/// projections were measured to exceed what they take (docs/hard-cases.md row 11b).
pub const FAST_BUDGET_FACTOR: f64 = 1.2;
/// How many steps a run takes before [`OVER_BUDGET_FACTOR`] is applied (then at every
/// pace check): enough for the mean step to average over many periods of the motion.
const BUDGET_CHECK_STEPS: u64 = 100_000;

/// Integrates dy/dt = f(t, y) from (t0, y0) to t_end.
///
/// - `events`: zero crossings of each g (filtered by direction) are located on the dense
///   output of the step in which g changes sign, to ~4·EPS·max(|t|, h); they are recorded
///   in time order, and a `Stop` event ends the integration at its time, with y the
///   dense-output state there passed through `OdeSystem::project`. A zero of g exactly at
///   t0 (or within the root tolerance of t0) is not an event.
/// - `sample_times`: sorted times in [t0, t_end]; `observer` receives the state at each
///   one reached (from the dense output of the step containing it, projected), and may
///   return `Break` to stop with `StopReason::Cancelled`.
///
/// Returns `Err` only for invalid input, detected before any right-hand-side call; a run
/// that cannot go on returns `Ok` with `StopReason::Failed` and the last good state.
#[allow(clippy::too_many_arguments)] // the public signature the physics code calls
pub fn integrate<S: OdeSystem<N>, const N: usize>(
    method: Method,
    system: &S,
    t0: f64,
    y0: SVector<f64, N>,
    t_end: f64,
    options: &Options<N>,
    events: &[Event<'_, N>],
    sample_times: &[f64],
    observer: &mut dyn FnMut(f64, &SVector<f64, N>) -> ControlFlow<()>,
) -> Result<Solution<N>, IntegrateError> {
    validate_inputs(method, t0, &y0, t_end, options, sample_times)?;
    let run = Run {
        method,
        system,
        t0,
        t_end,
        options,
        events,
        samples: sample_times,
        observer,
        next_sample: 0,
        g_before: vec![0.0; events.len()],
        g_prev: vec![0.0; events.len()],
        g_new: vec![0.0; events.len()],
        t_before: f64::NAN,
        scan: [(0.0, SVector::zeros()); SCAN_POINTS],
        found: Vec::with_capacity(events.len()),
        // allocated only when an event needs its count: a run without one allocates
        // no more than before sections existed (tests/val_integrators.rs counts them)
        crossings: if events
            .iter()
            .any(|e| matches!(e.action, Action::StopAfter(_)))
        {
            vec![0; events.len()]
        } else {
            Vec::new()
        },
        sol: Solution {
            t: t0,
            y: y0,
            stop: StopReason::Reached,
            events: Vec::new(),
            stats: Stats::default(),
            warnings: Vec::new(),
        },
    };
    Ok(match method {
        Method::Rk4 { h } => run.go(Rk4::new(h)),
        Method::Dopri5 => run.go(Dopri5::new()),
        Method::Dop853 => run.go(Dop853::new()),
    })
}

/// One integration: inputs, output cursor and buffers allocated once.
struct Run<'r, 'e, S, const N: usize> {
    method: Method,
    system: &'r S,
    t0: f64,
    t_end: f64,
    options: &'r Options<N>,
    events: &'r [Event<'e, N>],
    samples: &'r [f64],
    observer: &'r mut dyn FnMut(f64, &SVector<f64, N>) -> ControlFlow<()>,
    /// Index of the first sample not yet emitted.
    next_sample: usize,
    /// g at the start of the previous step, at the start and at the end of the current one.
    g_before: Vec<f64>,
    g_prev: Vec<f64>,
    g_new: Vec<f64>,
    /// Start of the previous step (NaN during the first).
    t_before: f64,
    /// The dense-output states at the interior scan points of the current step.
    scan: [(f64, SVector<f64, N>); SCAN_POINTS],
    /// (time, index) of the crossings located in the current step.
    found: Vec<(f64, usize)>,
    /// Crossings recorded so far, per event (for [`Action::StopAfter`]); empty when no
    /// event has that action.
    crossings: Vec<u64>,
    sol: Solution<N>,
}

impl<S: OdeSystem<N>, const N: usize> Run<'_, '_, S, N> {
    fn go<St: Stepper<N>>(mut self, mut stepper: St) -> Solution<N> {
        let (t0, t_end) = (self.t0, self.t_end);
        let mut t = t0;
        let mut y = self.sol.y;
        while self
            .samples
            .get(self.next_sample)
            .is_some_and(|&ts| ts <= t0)
        {
            self.next_sample += 1;
            if (self.observer)(t0, &y).is_break() {
                return self.finish(t0, y, StopReason::Cancelled);
            }
        }
        if t_end == t0 {
            return self.finish(t0, y, StopReason::Reached);
        }
        let h_max = self.options.h_max.min(t_end - t0);
        let Some(h_first) = stepper.start(
            self.system,
            t0,
            &y,
            h_max,
            self.options,
            &mut self.sol.stats,
        ) else {
            return self.finish(
                t0,
                y,
                StopReason::Failed(IntegrateError::NonFinite { t: t0 }),
            );
        };
        // after f(t0, y0) (`OdeSystem::rhs_accepted`), whose work the events may share
        for (g, ev) in self.g_prev.iter_mut().zip(self.events) {
            *g = (ev.g)(t0, &y);
        }
        let mut h = h_first;
        let mut controller = St::CONTROL.map(PiController::new);
        let mut stiffness = St::STIFFNESS
            .filter(|_| self.options.stiffness_check)
            .map(StiffnessDetector::new);
        // the h·ρ from which the steps follow the fastest rate (FAST_PACE, FAST_FRACTION)
        let fast_pace = St::STIFFNESS.map_or(FAST_PACE, |p| {
            FAST_PACE.min(FAST_FRACTION * p.resolved_pace(self.options.rtol.min()))
        });
        let mut nonfinite_streak = 0u32;
        let mut since_nonfinite = u64::MAX;
        // (steps, t) at the last pace check: the start of the current window
        let mut window = (0u64, t0);

        loop {
            if self
                .options
                .cancel
                .as_ref()
                .is_some_and(|c| c.load(Ordering::Relaxed))
            {
                return self.finish(t, y, StopReason::Cancelled);
            }
            let stats = &mut self.sol.stats;
            let steps = stats.accepted + stats.rejected;
            if steps >= self.options.max_steps {
                let method = self.method;
                return self.finish(
                    t,
                    y,
                    StopReason::Failed(IntegrateError::MaxSteps { t, steps, method }),
                );
            }
            if steps >= PACE_CHECK_STEPS && steps.is_multiple_of(PACE_CHECK_STEPS) {
                let projected = steps as f64 * (t_end - t0) / (t - t0);
                let max_steps = self.options.max_steps;
                if !(projected <= HOPELESS_FACTOR * max_steps as f64) {
                    return self.finish(
                        t,
                        y,
                        StopReason::Failed(IntegrateError::Collapsed {
                            t,
                            h,
                            steps,
                            projected,
                        }),
                    );
                }
                let mean_step = (t - t0) / steps as f64;
                if steps >= BUDGET_CHECK_STEPS
                    && projected > OVER_BUDGET_FACTOR * max_steps as f64
                    && self
                        .options
                        .time_scale
                        .is_some_and(|scale| mean_step >= MOTION_PACE * scale)
                {
                    return self.finish(
                        t,
                        y,
                        StopReason::Failed(IntegrateError::OverBudget {
                            t,
                            steps,
                            projected,
                            max_steps,
                        }),
                    );
                }
                let pace = (t - window.1) / (steps - window.0) as f64;
                window = (steps, t);
                if steps >= BUDGET_CHECK_STEPS
                    && let Some(detector) = stiffness.as_ref()
                    && let (h_rho, rate) = detector.last()
                    && h_rho >= fast_pace
                {
                    let projected = steps as f64 + (t_end - t) / pace;
                    if !(projected <= FAST_BUDGET_FACTOR * max_steps as f64) {
                        return self.finish(
                            t,
                            y,
                            StopReason::Failed(IntegrateError::FastRate {
                                t,
                                h: pace,
                                rate,
                                stiff: detector.is_stiff(),
                                steps,
                                projected,
                                max_steps,
                            }),
                        );
                    }
                }
            }
            // Hairer: 0.1·|h| ≤ |t|·uround means t + h no longer resolves the stages.
            if controller.is_some() && (h <= 10.0 * f64::EPSILON * t.abs() || h < f64::MIN_POSITIVE)
            {
                let error = if since_nonfinite < NONFINITE_MEMORY {
                    IntegrateError::NonFinite { t }
                } else {
                    IntegrateError::StepSizeTooSmall { t, h }
                };
                return self.finish(t, y, StopReason::Failed(error));
            }
            let (t_new, last) = match controller {
                // fixed step: times t0 + n·h, so round-off does not accumulate in t
                None => {
                    let nominal = t0 + (stats.accepted + 1) as f64 * h_first;
                    if nominal + (St::LAST_STRETCH - 1.0) * h_first >= t_end {
                        (t_end, true)
                    } else {
                        (nominal, false)
                    }
                }
                Some(_) => {
                    if t + St::LAST_STRETCH * h >= t_end {
                        (t_end, true)
                    } else {
                        (t + h, false)
                    }
                }
            };
            let h_step = t_new - t;
            let err = match stepper.attempt(self.system, t, &y, h_step, self.options, stats) {
                Trial::Done { err } => err,
                Trial::NonFinite => {
                    stats.rejected += 1;
                    nonfinite_streak += 1;
                    since_nonfinite = 0;
                    let Some(c) = controller
                        .as_mut()
                        .filter(|_| nonfinite_streak < NONFINITE_RETRIES)
                    else {
                        return self.finish(
                            t,
                            y,
                            StopReason::Failed(IntegrateError::NonFinite { t }),
                        );
                    };
                    c.note_rejection();
                    h = h_step * NONFINITE_SHRINK;
                    continue;
                }
            };
            since_nonfinite = since_nonfinite.saturating_add(1);
            let h_next = match controller.as_mut().map(|c| c.judge(err, h_step, h_max)) {
                None => h_first,
                Some(Verdict::Accept { h_next }) => h_next,
                Some(Verdict::Reject { h_next }) => {
                    stats.rejected += 1;
                    h = h_next;
                    continue;
                }
            };
            stats.accepted += 1;
            if !last {
                stats.min_step = stats.min_step.min(h_step);
            }
            nonfinite_streak = 0;
            let mut y_new = *stepper.candidate();
            self.system.project(&mut y_new);
            stepper.accept(self.system, t_new, &y_new, stats);
            if let Some(detector) = stiffness.as_mut()
                && detector.update(stats.accepted, h_step, || stepper.stiffness_estimate())
            {
                self.sol.warnings.push(Warning::Stiff { t });
            }
            if let Some((t_stop, y_stop, stop)) = self.step_outputs(&mut stepper, t, t_new, &y_new)
            {
                return self.finish(t_stop, y_stop, stop);
            }
            t = t_new;
            y = y_new;
            h = h_next;
            if last {
                return self.finish(t, y, StopReason::Reached);
            }
        }
    }

    /// Locates the events of the accepted step (t, t_new] and emits, in time order, its
    /// samples and events; returns where to stop if a terminal event or the observer says
    /// so.
    fn step_outputs<St: Stepper<N>>(
        &mut self,
        stepper: &mut St,
        t: f64,
        t_new: f64,
        y_new: &SVector<f64, N>,
    ) -> Option<(f64, SVector<f64, N>, StopReason)> {
        let events = self.events;
        self.found.clear();
        let tol = time_tolerance(t_new, t_new - t);
        let mut dense_ready = false;
        for (i, ev) in events.iter().enumerate() {
            let g = (ev.g)(t_new, y_new);
            self.g_new[i] = g;
            let at_ends = crossed(ev.direction, self.g_prev[i], g);
            if !at_ends
                && !may_cross_inside(
                    ev.direction,
                    [self.t_before, t, t_new],
                    [self.g_before[i], self.g_prev[i], g],
                    ev.curvature,
                )
            {
                continue;
            }
            if !dense_ready {
                stepper.prepare_dense(self.system, &mut self.sol.stats);
                dense_ready = true;
                for (j, point) in self.scan.iter_mut().enumerate() {
                    let s = t + (t_new - t) * (j + 1) as f64 / (SCAN_POINTS + 1) as f64;
                    *point = (s, stepper.dense(s));
                }
            }
            let Some((a, ga, b, gb)) = self.bracket(i, t, t_new, at_ends, |s| stepper.dense(s))
            else {
                continue;
            };
            let t_root = locate(|s| (ev.g)(s, &stepper.dense(s)), a, ga, b, gb, tol);
            // the zero g(t0) = 0 itself, found again by the root finder
            if t == self.t0 && t_root <= self.t0 + tol {
                continue;
            }
            self.found.push((t_root, i));
        }
        let sample_due = self
            .samples
            .get(self.next_sample)
            .is_some_and(|&ts| ts <= t_new);
        if self.found.is_empty() && !sample_due {
            self.end_step(t);
            return None;
        }
        if !dense_ready {
            stepper.prepare_dense(self.system, &mut self.sol.stats);
        }
        self.found
            .sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));

        let mut next_event = 0;
        loop {
            let te = self.found.get(next_event).map_or(f64::INFINITY, |f| f.0);
            let ts = match self.samples.get(self.next_sample) {
                Some(&ts) if ts <= t_new => ts,
                _ => f64::INFINITY,
            };
            if te == f64::INFINITY && ts == f64::INFINITY {
                break;
            }
            if ts <= te {
                // a sample at an event's time still belongs to the run
                self.next_sample += 1;
                let ys = self.state_at(stepper, ts, t_new, y_new);
                if (self.observer)(ts, &ys).is_break() {
                    return Some((ts, ys, StopReason::Cancelled));
                }
            } else {
                let (te, index) = self.found[next_event];
                next_event += 1;
                let ye = self.state_at(stepper, te, t_new, y_new);
                self.sol.events.push(EventRecord {
                    index,
                    t: te,
                    y: ye,
                });
                self.sol.stats.events += 1;
                let stop = match events[index].action {
                    Action::Continue => false,
                    Action::Stop => true,
                    Action::StopAfter(n) => {
                        self.crossings[index] += 1;
                        self.crossings[index] >= n
                    }
                };
                if stop {
                    return Some((te, ye, StopReason::Event { index }));
                }
            }
        }
        self.end_step(t);
        None
    }

    /// The bracket [a, b] (with g(a), g(b)) of the first crossing of event `i` in the
    /// step (t, t_new], from g at the step ends and at the scan points: the whole step
    /// when the scan shows just the one sign change the ends show (so a lone crossing is
    /// located exactly as without the scan); otherwise the first scan interval in which
    /// g crosses in the event's direction; otherwise, for a dip narrower than the scan
    /// spacing, the interval from the scan point before the lowest one to the minimum of
    /// σ g found around it (σ = sign g(t)), if that minimum is past zero; else `None`.
    /// With a bound A of |g''| ([`Event::curvature`]) the dip is searched for in every
    /// scan interval, in order, whose ends are within A Δ²/8 of zero (Δ its length),
    /// before the first sign change: no crossing hides elsewhere.
    fn bracket(
        &self,
        i: usize,
        t: f64,
        t_new: f64,
        at_ends: bool,
        dense: impl Fn(f64) -> SVector<f64, N>,
    ) -> Option<(f64, f64, f64, f64)> {
        let ev = &self.events[i];
        let value = |j: usize| match j {
            0 => (t, self.g_prev[i]),
            j if j > SCAN_POINTS => (t_new, self.g_new[i]),
            j => {
                let (s, y) = &self.scan[j - 1];
                (*s, (ev.g)(*s, y))
            }
        };
        let sigma = self.g_prev[i].signum();
        let (mut s0, mut g0) = value(0);
        let (mut first, mut changes, mut lowest_at) = (None, 0, 1);
        let mut lowest_g = f64::INFINITY;
        for j in 1..=SCAN_POINTS + 1 {
            let (s, g) = value(j);
            if g.signum() != g0.signum() && g0 != 0.0 {
                changes += 1;
            }
            if first.is_none() && crossed(ev.direction, g0, g) {
                first = Some((s0, g0, s, g));
            }
            if j <= SCAN_POINTS && sigma * g < lowest_g {
                (lowest_at, lowest_g) = (j, sigma * g);
            }
            (s0, g0) = (s, g);
        }
        if let Some(bound) = ev.curvature {
            let dt = (t_new - t) / (SCAN_POINTS + 1) as f64;
            for j in 0..=SCAN_POINTS {
                let ((s0, g0), (s1, g1)) = (value(j), value(j + 1));
                if first.is_some_and(|f| f.0 == s0) {
                    break;
                }
                let near = sigma * g0 > 0.0
                    && sigma * g1 > 0.0
                    && (sigma * g0).min(sigma * g1) <= chord_gap(bound, dt);
                if near {
                    let (s_min, f_min) = lowest(|s| sigma * (ev.g)(s, &dense(s)), s0, s1);
                    let g_min = sigma * f_min;
                    if crossed(ev.direction, g0, g_min) {
                        return Some((s0, g0, s_min, g_min));
                    }
                }
            }
        }
        if at_ends && changes == 1 {
            return Some((t, self.g_prev[i], t_new, self.g_new[i]));
        }
        if first.is_some() {
            return first;
        }
        let (lo, hi) = (value(lowest_at - 1), value(lowest_at + 1));
        let (s_min, f_min) = lowest(|s| sigma * (ev.g)(s, &dense(s)), lo.0, hi.0);
        let g_min = sigma * f_min;
        crossed(ev.direction, lo.1, g_min).then_some((lo.0, lo.1, s_min, g_min))
    }

    /// Shifts the event values and times by one step, after the step (t, t_new].
    fn end_step(&mut self, t: f64) {
        std::mem::swap(&mut self.g_before, &mut self.g_prev);
        std::mem::swap(&mut self.g_prev, &mut self.g_new);
        self.t_before = t;
    }

    /// The projected dense-output state at `s` in the accepted step ending at `t_new`.
    fn state_at<St: Stepper<N>>(
        &self,
        stepper: &St,
        s: f64,
        t_new: f64,
        y_new: &SVector<f64, N>,
    ) -> SVector<f64, N> {
        if s >= t_new {
            return *y_new;
        }
        let mut y = stepper.dense(s);
        self.system.project(&mut y);
        y
    }

    fn finish(self, t: f64, y: SVector<f64, N>, stop: StopReason) -> Solution<N> {
        Solution {
            t,
            y,
            stop,
            ..self.sol
        }
    }
}
