//! The work–precision study: what accuracy costs in time. [`measure`] runs every method
//! over a grid of settings and measures each run's error against a reference, its
//! invariant drift, wall time (median of repeats), right-hand-side evaluations and steps,
//! into a [`Report`]; [`write`] puts `precision.csv`, `error_vs_time.svg` and
//! `error_vs_evaluations.svg` into a directory and [`summary`] is the printed table with
//! the cheapest setting that reaches 1e-3, 1e-6, 1e-9 and 1e-12. `ellipsoid precision`
//! and Python's `ellipsoid.precision` are thin fronts over these.
//!
//! Error measures (stated in the CSV's `measure` column and in the printed summary):
//! - `period` (frictionless scenes of a body of revolution, no effects): the reference is
//!   exact, the nutation period T from the one-degree-of-freedom quadrature
//!   (`ellipsoid_core::reference`) and the invariants' initial values. The error is
//!   max(|T_run − T|/T, largest relative invariant drift), T_run the mean period between
//!   the first and last maxima of θ located (as events) in the run.
//! - `final_state` (every other scene): the reference is a DOP853 run at rtol = 1e-14,
//!   checked against one at 3e-15 (their difference is printed). The error is the
//!   largest of: the angle of R_refᵀR \[rad\], |x_G − x_ref|/ℓ, |v_G − v_ref|/(|v_G(0)| + |ω(0)|ℓ),
//!   |ω − ω_ref|/|ω(0)| and |t_f − t_f,ref|/t_f,ref, at the final state (ℓ = largest semi-axis).

use std::fmt::Write as _;
use std::ops::ControlFlow;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use ellipsoid_core::error::{Field, ModelError, number};
use ellipsoid_core::integrate::{self, Action, Direction, Event, Method, Options, StopReason};
use ellipsoid_core::invariants::Invariant;
use ellipsoid_core::model::{Frictionless, System};
use ellipsoid_core::reference::{self, Nutation};
use ellipsoid_core::scenario::{Scenario, ScenarioError};
use ellipsoid_core::simulate::{self, ContactModel, Drift, Outcome, Scene, Status};
use ellipsoid_core::state::{self, State};
use ellipsoid_io::{OutputError, atomic};
use nalgebra::Vector3;

use crate::plot::{self, Series};

/// Default end time: the scenario's, but at most this \[s\] (RK4 at h = 1e-6 s costs
/// about 0.5 s of wall time per simulated second).
pub const DEFAULT_T_END_CAP: f64 = 10.0;
/// The paper's method and step (RK4, h = 1e-4 s), marked on the plots.
pub const PAPER_STEP: f64 = 1e-4;
/// Accuracy targets answered in the summary.
pub const TARGETS: [f64; 4] = [1e-3, 1e-6, 1e-9, 1e-12];
/// Tolerance of the reference run and of the tighter run that checks it.
const REFERENCE_RTOL: f64 = 1e-14;
const CHECK_RTOL: f64 = 3e-15;
/// Invariant drifts are measured on this many equal intervals of [0, t_end].
const DRIFT_INTERVALS: usize = 100;
/// Timing: at least `repeats` runs, more while the total is below this \[s\] (at most
/// `BUDGET_REPEATS`).
const TIMING_BUDGET: f64 = 0.3;
const BUDGET_REPEATS: usize = 15;

/// One point of the grid.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Setting {
    pub method: Method,
    /// rtol and atol (unused by RK4).
    pub rtol: f64,
    pub atol: f64,
}

impl Setting {
    /// `h=1e-4` or `rtol=1e-10`.
    pub fn label(&self) -> String {
        match self.method {
            Method::Rk4 { h } => format!("h={h:e}"),
            _ => format!("rtol={:e}", self.rtol),
        }
    }
}

/// The grid: RK4 at h = 1e-2 … 1e-6 s (half decades, 1 and 3 × 10^k), DOPRI5 and DOP853
/// at rtol = 1e-3 … 1e-13 (decades), atol = rtol · `atol_ratio`. `quick`: three settings each.
pub fn grid(quick: bool, atol_ratio: f64) -> Vec<Setting> {
    let steps: &[f64] = if quick {
        &[1e-2, 1e-3, 1e-4]
    } else {
        &[1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 3e-5, 1e-5, 3e-6, 1e-6]
    };
    let rtols: &[f64] = if quick {
        &[1e-4, 1e-7, 1e-10]
    } else {
        &[
            1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12, 1e-13,
        ]
    };
    let mut out: Vec<Setting> = steps
        .iter()
        .map(|&h| Setting {
            method: Method::Rk4 { h },
            rtol: 1e-10,
            atol: 1e-10 * atol_ratio,
        })
        .collect();
    for method in [Method::Dopri5, Method::Dop853] {
        out.extend(rtols.iter().map(|&r| Setting {
            method,
            rtol: r,
            atol: r * atol_ratio,
        }));
    }
    out
}

/// What the errors are measured against.
pub enum Reference {
    /// The exact nutation period and the invariants (frictionless body of revolution).
    Period { nutation: Nutation, y0: State },
    /// The final state of a tight DOP853 run; `uncertainty` is its distance (same
    /// measure) from a tighter run.
    State {
        outcome: Box<Outcome>,
        rtol: f64,
        uncertainty: f64,
    },
}

impl Reference {
    /// The CSV's `measure` column.
    pub fn measure(&self) -> &'static str {
        match self {
            Reference::Period { .. } => "period",
            Reference::State { .. } => "final_state",
        }
    }

    /// The status every accurate run must end with: `completed` for the period, the
    /// reference run's otherwise (a scene may end at an event such as the slip stopping).
    pub fn status(&self) -> &'static str {
        match self {
            Reference::Period { .. } => "completed",
            Reference::State { outcome, .. } => outcome.status.name(),
        }
    }

    /// One-paragraph definition for the summary.
    pub fn describe(&self) -> String {
        match self {
            Reference::Period { nutation, .. } => format!(
                "reference: exact nutation period T = {:.15} s (quadrature of the 1-DOF reduction, ±{:.1e} s), θ in [{:.9}, {:.9}] rad\n\
                 error (measure `period`) = max(|T_run − T|/T, largest relative drift of the conserved invariants), \
                 T_run = mean period between the first and last θ maxima of the run",
                nutation.period, nutation.uncertainty, nutation.theta_min, nutation.theta_max
            ),
            Reference::State {
                outcome,
                rtol,
                uncertainty,
            } => format!(
                "reference: final state of DOP853 at rtol = {rtol:e} (t_f = {} s, {}), {uncertainty:.1e} from a run at rtol = {CHECK_RTOL:e}: \
                 errors below ~{uncertainty:.0e} are not resolved\n\
                 error (measure `final_state`) = max(angle of R_ref^T R [rad], |Δx_G|/ℓ, |Δv_G|/(|v_G(0)| + |ω(0)|ℓ), |Δω|/|ω(0)|, |Δt_f|/t_f), \
                 ℓ = largest semi-axis, at the final state",
                outcome.final_sample.t,
                outcome.status.name(),
            ),
        }
    }
}

/// One measured setting.
#[derive(Debug, Clone)]
pub struct Row {
    pub setting: Setting,
    pub status: &'static str,
    pub t_final: f64,
    /// The headline error (see the module docs).
    pub error: f64,
    pub period_error: Option<f64>,
    pub state_error: Option<f64>,
    /// Relative drift of E (conservative scenes) or of E + W.
    pub energy_drift: Option<f64>,
    /// Largest relative drift of the invariants the scene conserves.
    pub invariant_drift: Option<f64>,
    pub wall_median: f64,
    pub wall_min: f64,
    pub repeats: usize,
    pub rhs_evals: u64,
    pub accepted: u64,
    pub rejected: u64,
}

/// The whole report of one scene.
pub struct Report {
    pub scene_name: String,
    pub t_end: f64,
    pub reference: Reference,
    pub rows: Vec<Row>,
    /// Notes made while measuring (e.g. why no exact period reference was formed).
    pub notes: Vec<String>,
}

/// What the study is asked to do (`ellipsoid precision`'s options; the scenario's
/// `--set` overrides are applied before).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct StudyOptions {
    /// Simulated time per run \[s\]; `None`: the scenario's t_end, at most
    /// [`DEFAULT_T_END_CAP`].
    pub t_end: Option<f64>,
    /// Three settings per method and one timed run each.
    pub quick: bool,
    /// Fewest timed runs per setting (1 to [`MAX_REPEATS`]); `None`: 3, or 1 with `quick`.
    pub repeats: Option<u64>,
}

/// How a front end writes the study's options in its messages: the CLI's `--t-end 11`,
/// Python's `t_end=11`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Spelling {
    /// Written before the end time's value: `"--t-end "` or `"t_end="`.
    pub t_end: &'static str,
    /// Written before the repeats' value: `"--repeats "` or `"repeats="`.
    pub repeats: &'static str,
    /// The quick grid: `"--quick"` or `"quick=True"`.
    pub quick: &'static str,
}

impl Spelling {
    /// The command line's flags.
    pub const CLI: Spelling = Spelling {
        t_end: "--t-end ",
        repeats: "--repeats ",
        quick: "--quick",
    };
    /// Python's keyword arguments.
    pub const PYTHON: Spelling = Spelling {
        t_end: "t_end=",
        repeats: "repeats=",
        quick: "quick=True",
    };
}

/// A study option.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StudyOption {
    /// The end time (`--t-end`, `t_end=`), or the scenario's `output.t_end` when none was given.
    TEnd,
    /// `--repeats`, `repeats=`.
    Repeats,
}

impl StudyOption {
    /// Its name as a key: `t_end` or `repeats`.
    pub fn key(self) -> &'static str {
        match self {
            StudyOption::TEnd => "t_end",
            StudyOption::Repeats => "repeats",
        }
    }
}

/// Why the study did not produce a report.
#[derive(Debug, thiserror::Error)]
pub enum StudyError {
    /// The scenario cannot run (an error found at t = 0, placed in the scenario file).
    #[error(transparent)]
    Scenario(Box<ScenarioError>),
    /// An option breaks its rule; `what` names it as the front end writes it
    /// (`--t-end 11`), `value` is the value as written, found before anything runs.
    #[error("{what}: {rule}")]
    Option {
        option: StudyOption,
        value: String,
        what: String,
        rule: String,
    },
    /// No trustworthy reference: the DOP853 reference run did not finish cleanly.
    #[error("no reference: {message}")]
    Reference {
        message: String,
        /// The reference run.
        outcome: Box<Outcome>,
    },
    /// The cancel flag was set (e.g. Ctrl-C in Python).
    #[error("the precision study was cancelled")]
    Cancelled,
}

/// Why [`write`] failed.
#[derive(Debug, thiserror::Error)]
pub enum WriteError {
    /// The file system refused.
    #[error(transparent)]
    Output(#[from] OutputError),
    /// A plot could not be drawn.
    #[error("cannot draw the plot: {0}")]
    Plot(String),
}

/// What the study reports while it runs, and how it is stopped.
pub struct Hooks<'a> {
    /// A progress line: the reference, then one line per setting.
    pub progress: &'a dyn Fn(&str),
    /// A note the user must see (no exact reference could be formed); also kept in
    /// [`Report::notes`].
    pub note: &'a dyn Fn(&str),
    /// Stops the study (with [`StudyError::Cancelled`]) at the next integration step of
    /// the run in progress once set.
    pub cancel: Option<Arc<AtomicBool>>,
}

impl Hooks<'_> {
    /// No output, no cancellation.
    pub const SILENT: Hooks<'static> = Hooks {
        progress: &|_| {},
        note: &|_| {},
        cancel: None,
    };

    fn cancelled(&self) -> bool {
        self.cancel
            .as_ref()
            .is_some_and(|c| c.load(Ordering::Relaxed))
    }
}

/// Runs the grid on `scenario` (its end time and `repeats` checked before anything runs;
/// nothing is written here). `spelling` names the options in error messages.
pub fn measure(
    scenario: &Scenario,
    options: &StudyOptions,
    spelling: &Spelling,
    hooks: &Hooks<'_>,
) -> Result<Report, StudyError> {
    let StudyOptions {
        t_end,
        quick,
        repeats,
    } = *options;
    let base = &scenario.scene;
    let scene = scene_for(scenario, t_end, quick, spelling)?;
    let t_end = scene.t_end;
    let atol_ratio = base.solver.atol / base.solver.rtol;
    let repeats = repeats_or_default(repeats, quick, spelling)?;

    (hooks.progress)(&format!(
        "precision: {} (t_end = {t_end} s): establishing the reference",
        scenario.stem()
    ));
    let mut notes = Vec::new();
    let reference = establish_reference(scenario, &scene, atol_ratio, hooks, &mut notes)?;
    (hooks.progress)(&reference.describe());

    let mut rows = Vec::new();
    // A fixed step longer than the run cannot be taken (`Scene::validate`).
    for setting in grid(quick, atol_ratio)
        .into_iter()
        .filter(|s| !matches!(s.method, Method::Rk4 { h } if h > t_end))
    {
        let row = measure_setting(scenario, &scene, &setting, &reference, repeats, hooks)?;
        (hooks.progress)(&format!(
            "  {:<7} {:<12} error {:>8.1e}  time {:>9.3e} s  evals {:>9}  {}",
            setting.method.name(),
            setting.label(),
            row.error,
            row.wall_median,
            row.rhs_evals,
            row.status
        ));
        rows.push(row);
    }
    Ok(Report {
        scene_name: scenario.stem(),
        t_end,
        reference,
        rows,
        notes,
    })
}

/// Most timed runs per setting `repeats` may ask for.
pub const MAX_REPEATS: u64 = 1000;

/// The timed runs per setting: `repeats` (1 to [`MAX_REPEATS`]) or 3 (1 with `quick`).
fn repeats_or_default(
    repeats: Option<u64>,
    quick: bool,
    spelling: &Spelling,
) -> Result<usize, StudyError> {
    match repeats {
        None => Ok(if quick { 1 } else { 3 }),
        Some(n) if (1..=MAX_REPEATS).contains(&n) => Ok(n as usize),
        Some(n) => Err(repeats_error(&n.to_string(), spelling)),
    }
}

/// The error for a `repeats` value outside 1 to [`MAX_REPEATS`] (`value` as written; a
/// front end whose integers may be negative reports those with it too).
pub fn repeats_error(value: &str, spelling: &Spelling) -> StudyError {
    StudyError::Option {
        option: StudyOption::Repeats,
        value: value.to_owned(),
        what: format!("{}{value}", spelling.repeats),
        rule: format!("give 1 to {MAX_REPEATS} timed runs per setting"),
    }
}

/// Steps the grid's finest RK4 setting may take (10 s at h = 1e-6 s, 1000 s with
/// `--quick`): an end time beyond it would run for minutes per setting.
const RK4_STEP_BUDGET: f64 = 1e7;

/// The scene every setting runs: the scenario's, ending at `t_end` (default: the
/// scenario's, at most [`DEFAULT_T_END_CAP`]) and sampled for the drifts. The end time must
/// pass the rules `run` applies to a scenario's (see `Scene::validate`; the grid replaces
/// the scenario's own solver, so its settings are not checked here) and keep the grid's
/// finest RK4 setting within [`RK4_STEP_BUDGET`] steps.
fn scene_for(
    scenario: &Scenario,
    t_end: Option<f64>,
    quick: bool,
    spelling: &Spelling,
) -> Result<Scene, StudyError> {
    let base = &scenario.scene;
    let end = t_end.unwrap_or(base.t_end.min(DEFAULT_T_END_CAP));
    // Name the option when the end time came from it; the scenario's was checked on load.
    let what = match t_end {
        Some(t) => format!("{}{}", spelling.t_end, number(t)),
        None => format!(
            "t_end = {} s (the scenario's output.t_end, at most {DEFAULT_T_END_CAP} s)",
            number(end)
        ),
    };
    let option_error = |rule: String| StudyError::Option {
        option: StudyOption::TEnd,
        value: number(end),
        what: what.clone(),
        rule,
    };
    let mut scene = base.clone();
    scene.t_end = end;
    scene.sample_times = if end.is_finite() && end > 0.0 {
        (0..=DRIFT_INTERVALS)
            .map(|k| end * k as f64 / DRIFT_INTERVALS as f64)
            .collect()
    } else {
        Vec::new()
    };
    scene.solver.method = Method::Dop853;
    scene.solver.initial_step = None;
    if let Err(e) = scene.validate() {
        return Err(match &e {
            _ if t_end.is_none() => located(scenario, &e),
            ModelError::Invalid {
                field: Field::Key(key),
                rule,
                ..
            } if key == "output.t_end" => option_error(rule.clone()),
            _ => option_error(format!("with this end time, {e}")),
        });
    }
    let smallest = finest_rk4_step(quick);
    let needed = (end / smallest).ceil();
    if needed > RK4_STEP_BUDGET {
        let longest = number(RK4_STEP_BUDGET * smallest);
        let hint = if quick {
            format!("give {}{longest} or less", spelling.t_end)
        } else {
            format!(
                "give {}{longest} or less, or use {} (finest step {} s)",
                spelling.t_end,
                spelling.quick,
                number(finest_rk4_step(true))
            )
        };
        return Err(option_error(format!(
            "RK4 at the grid's finest step h = {} s would take {} steps, more than the report allows ({}); {hint}",
            number(smallest),
            count(needed),
            count(RK4_STEP_BUDGET)
        )));
    }
    Ok(scene)
}

fn located(scenario: &Scenario, e: &ModelError) -> StudyError {
    StudyError::Scenario(Box::new(scenario.locate(e)))
}

/// A whole number of steps: in full below 1e15, else to two digits (1.0e304).
fn count(n: f64) -> String {
    if n < 1e15 {
        format!("{n}")
    } else {
        format!("{n:.1e}")
    }
}

/// The grid's finest RK4 step.
fn finest_rk4_step(quick: bool) -> f64 {
    grid(quick, 1.0)
        .iter()
        .filter_map(|s| {
            if let Method::Rk4 { h } = s.method {
                Some(h)
            } else {
                None
            }
        })
        .fold(f64::INFINITY, f64::min)
}

/// The scene with one setting's solver.
fn with_setting(scene: &Scene, s: &Setting) -> Scene {
    let mut sc = scene.clone();
    sc.solver.method = s.method;
    sc.solver.rtol = s.rtol;
    sc.solver.atol = s.atol;
    if let Method::Rk4 { h } = s.method {
        // RK4 takes t_end/h steps (at most RK4_STEP_BUDGET, see `scene_for`); the
        // scene's step limit is meant for adaptive runs.
        sc.solver.max_steps = sc.solver.max_steps.max((sc.t_end / h).ceil() as u64 + 10);
    }
    sc
}

/// One run of `scene`; a run stopped by the cancel flag is [`StudyError::Cancelled`].
fn run(scenario: &Scenario, scene: &Scene, hooks: &Hooks<'_>) -> Result<Outcome, StudyError> {
    let outcome = simulate::simulate_cancellable(
        scene,
        &mut |_| ControlFlow::Continue(()),
        hooks.cancel.clone(),
    )
    .map_err(|e| located(scenario, &e))?;
    if hooks.cancelled() {
        return Err(StudyError::Cancelled);
    }
    Ok(outcome)
}

fn establish_reference(
    scenario: &Scenario,
    scene: &Scene,
    atol_ratio: f64,
    hooks: &Hooks<'_>,
    notes: &mut Vec<String>,
) -> Result<Reference, StudyError> {
    if is_conservative_frictionless(scene) {
        let y0 = scene.initial_state().map_err(|e| located(scenario, &e))?.1;
        match reference::nutation(&scene.body, scene.gravity, &y0) {
            Ok(nutation) => return Ok(Reference::Period { nutation, y0 }),
            Err(why) => {
                let note = format!(
                    "precision: no exact period reference ({why}); using a DOP853 reference run"
                );
                (hooks.note)(&note);
                notes.push(note);
            }
        }
    }
    let tight = |rtol: f64| {
        with_setting(
            scene,
            &Setting {
                method: Method::Dop853,
                rtol,
                atol: rtol * atol_ratio,
            },
        )
    };
    let reference = run(scenario, &tight(REFERENCE_RTOL), hooks)?;
    if reference.status.is_error() || reference.status == Status::Cancelled {
        return Err(StudyError::Reference {
            message: format!(
                "the DOP853 reference run at rtol = {REFERENCE_RTOL:e} did not finish cleanly ({}): {:?}",
                reference.status.name(),
                reference.status
            ),
            outcome: Box::new(reference),
        });
    }
    let check = run(scenario, &tight(CHECK_RTOL), hooks)?;
    let uncertainty = state_error(scene, &check, &reference);
    Ok(Reference::State {
        outcome: Box::new(reference),
        rtol: REFERENCE_RTOL,
        uncertainty,
    })
}

/// Frictionless with no effects: the 1-DOF reduction applies if the body is one of revolution.
fn is_conservative_frictionless(scene: &Scene) -> bool {
    scene.contact == ContactModel::Frictionless && !scene.effects.any()
}

fn measure_setting(
    scenario: &Scenario,
    scene: &Scene,
    setting: &Setting,
    reference: &Reference,
    repeats: usize,
    hooks: &Hooks<'_>,
) -> Result<Row, StudyError> {
    let sc = with_setting(scene, setting);
    let mut times = Vec::new();
    let mut outcome = None;
    let started = Instant::now();
    while times.len() < repeats
        || (started.elapsed().as_secs_f64() < TIMING_BUDGET && times.len() < BUDGET_REPEATS)
    {
        let t0 = Instant::now();
        let out = run(scenario, &sc, hooks)?;
        times.push(t0.elapsed().as_secs_f64());
        outcome.get_or_insert(out);
    }
    let outcome = outcome.expect("at least one run");
    times.sort_by(f64::total_cmp);
    let wall_median = median(&times);
    let completed = outcome.status.completed();
    let invariant_drift = max_drift(&outcome.drift);
    let energy_drift = energy_drift(&outcome.drift);
    let (period_error, state_error, error) = match reference {
        Reference::Period { nutation, y0 } => {
            let p = if completed {
                period_error(&sc, y0, nutation, hooks.cancel.clone())
            } else {
                None
            };
            if hooks.cancelled() {
                return Err(StudyError::Cancelled);
            }
            let e = match (p, invariant_drift) {
                (Some(p), Some(d)) => p.max(d),
                _ => f64::INFINITY,
            };
            (p, None, e)
        }
        Reference::State { outcome: r, .. } => {
            let e = state_error(scene, &outcome, r);
            (None, Some(e), e)
        }
    };
    Ok(Row {
        setting: *setting,
        status: outcome.status.name(),
        t_final: outcome.final_sample.t,
        error: if error.is_nan() { f64::INFINITY } else { error },
        period_error,
        state_error,
        energy_drift,
        invariant_drift,
        wall_median,
        wall_min: times[0],
        repeats: times.len(),
        rhs_evals: outcome.stats.rhs_evals,
        accepted: outcome.stats.accepted,
        rejected: outcome.stats.rejected,
    })
}

fn median(sorted: &[f64]) -> f64 {
    let n = sorted.len();
    if n % 2 == 1 {
        sorted[n / 2]
    } else {
        0.5 * (sorted[n / 2 - 1] + sorted[n / 2])
    }
}

/// The largest relative drift of the invariants the scene conserves.
fn max_drift(d: &Drift) -> Option<f64> {
    d.max()
}

/// The drift of E (conservative scenes), else of E + W.
fn energy_drift(d: &Drift) -> Option<f64> {
    d.get(Invariant::Energy)
        .or(d.get(Invariant::EnergyPlusWork))
}

/// |T_run − T|/T with T_run the mean period between the first and last maxima of θ,
/// located as events (d cos θ/dt = (ζ × ω_b)·e3 rising through zero) on the same method
/// and setting. The events do not change the step sequence, so this run's steps are the
/// timed run's. `cancel` stops the run (the result is then `None`).
pub fn period_error(
    scene: &Scene,
    y0: &State,
    nutation: &Nutation,
    cancel: Option<Arc<AtomicBool>>,
) -> Option<f64> {
    let sys = System {
        body: scene.body.clone(),
        gravity: scene.gravity,
        contact: Frictionless,
        effects: (),
    };
    let events = [Event {
        g: Box::new(|_t, y: &State| {
            let rot = state::rotation(y);
            rot[(2, 0)] * y[state::OMEGA + 1] - rot[(2, 1)] * y[state::OMEGA]
        }),
        direction: Direction::Rising,
        action: Action::Continue,
        curvature: None,
    }];
    let mut options = Options::new(scene.solver.rtol, scene.solver.atol);
    options.h0 = None;
    options.max_steps = scene.solver.max_steps;
    options.cancel = cancel;
    let sol = integrate::integrate(
        scene.solver.method,
        &sys,
        0.0,
        *y0,
        scene.t_end,
        &options,
        &events,
        &[],
        &mut |_, _| ControlFlow::Continue(()),
    )
    .ok()?;
    if sol.stop != StopReason::Reached || sol.events.len() < 2 {
        return None;
    }
    let (first, last) = (sol.events[0].t, sol.events[sol.events.len() - 1].t);
    let t_run = (last - first) / (sol.events.len() - 1) as f64;
    Some((t_run - nutation.period).abs() / nutation.period)
}

/// The `final_state` error of `out` against `reference` (see the module docs).
pub fn state_error(scene: &Scene, out: &Outcome, reference: &Outcome) -> f64 {
    let ell = scene.body.semi_axes().max();
    let (a, b) = (&out.final_sample, &reference.final_sample);
    let ra = state::rotation(&out.final_state);
    let rb = state::rotation(&reference.final_state);
    // rotation angle of R_bᵀ R_a from its trace, via atan2 for accuracy at small angles
    let d = rb.transpose() * ra;
    let axis = Vector3::new(
        d[(2, 1)] - d[(1, 2)],
        d[(0, 2)] - d[(2, 0)],
        d[(1, 0)] - d[(0, 1)],
    );
    let angle = axis.norm().atan2(d.trace() - 1.0);
    let omega0 = scene
        .initial
        .omega_body
        .unwrap_or_else(|| scene.initial.angles.omega_body())
        .norm();
    let v0 = scene.initial.velocity.map_or(0.0, |v| v.norm());
    let v_scale = v0 + omega0 * ell;
    let rel = |num: f64, den: f64| if den > 0.0 { num / den } else { num };
    [
        angle,
        (a.position - b.position).norm() / ell,
        rel((a.velocity - b.velocity).norm(), v_scale),
        rel((a.omega - b.omega).norm(), omega0),
        rel((a.t - b.t).abs(), b.t),
    ]
    .into_iter()
    .fold(0.0, |m, e| if e.is_nan() { f64::NAN } else { m.max(e) })
}

/// Column names of `precision.csv`.
pub const CSV_HEADER: &str = "scene,t_end,measure,method,setting,h,rtol,atol,status,t_final,error,period_error,state_error,energy_drift,invariant_drift,wall_time_median_s,wall_time_min_s,repeats,rhs_evals,steps,rejected";

/// One column of the report's table, a value per row.
#[derive(Debug, Clone, PartialEq)]
pub enum Column {
    Text(Vec<String>),
    /// `None` where the CSV cell is empty (h of the adaptive methods, rtol and atol of
    /// RK4, the error measures and drifts that do not apply).
    Float(Vec<Option<f64>>),
    Count(Vec<u64>),
}

impl Column {
    /// The CSV cell of row `i`: floats in the shortest form that reads back exactly
    /// (`{:e}`), absent values empty.
    fn cell(&self, i: usize) -> String {
        match self {
            Column::Text(v) => v[i].clone(),
            Column::Float(v) => v[i].map_or_else(String::new, |x| format!("{x:e}")),
            Column::Count(v) => v[i].to_string(),
        }
    }
}

/// The table of the report by column, named and ordered as in [`CSV_HEADER`]: the one
/// declaration the CSV and Python's `PrecisionTable` are both built from.
pub fn columns(report: &Report) -> Vec<(&'static str, Column)> {
    let rows = &report.rows;
    let text = |f: &dyn Fn(&Row) -> String| Column::Text(rows.iter().map(f).collect());
    let float = |f: &dyn Fn(&Row) -> Option<f64>| Column::Float(rows.iter().map(f).collect());
    let count = |f: &dyn Fn(&Row) -> u64| Column::Count(rows.iter().map(f).collect());
    let h = |r: &Row| match r.setting.method {
        Method::Rk4 { h } => Some(h),
        _ => None,
    };
    let adaptive = |r: &Row, v: f64| match r.setting.method {
        Method::Rk4 { .. } => None,
        _ => Some(v),
    };
    vec![
        ("scene", text(&|_| report.scene_name.clone())),
        ("t_end", float(&|_| Some(report.t_end))),
        ("measure", text(&|_| report.reference.measure().to_owned())),
        ("method", text(&|r| r.setting.method.name().to_owned())),
        ("setting", text(&|r| r.setting.label())),
        ("h", float(&h)),
        ("rtol", float(&|r| adaptive(r, r.setting.rtol))),
        ("atol", float(&|r| adaptive(r, r.setting.atol))),
        ("status", text(&|r| r.status.to_owned())),
        ("t_final", float(&|r| Some(r.t_final))),
        ("error", float(&|r| Some(r.error))),
        ("period_error", float(&|r| r.period_error)),
        ("state_error", float(&|r| r.state_error)),
        ("energy_drift", float(&|r| r.energy_drift)),
        ("invariant_drift", float(&|r| r.invariant_drift)),
        ("wall_time_median_s", float(&|r| Some(r.wall_median))),
        ("wall_time_min_s", float(&|r| Some(r.wall_min))),
        ("repeats", count(&|r| r.repeats as u64)),
        ("rhs_evals", count(&|r| r.rhs_evals)),
        ("steps", count(&|r| r.accepted)),
        ("rejected", count(&|r| r.rejected)),
    ]
}

/// The CSV text.
pub fn csv(report: &Report) -> String {
    let columns = columns(report);
    let mut s = String::new();
    s.push_str(CSV_HEADER);
    s.push('\n');
    for i in 0..report.rows.len() {
        let cells: Vec<String> = columns.iter().map(|(_, c)| c.cell(i)).collect();
        s.push_str(&cells.join(","));
        s.push('\n');
    }
    s
}

/// Writes the CSV and both plots atomically into `dir` (created as needed); returns the
/// paths.
pub fn write(report: &Report, dir: &Path) -> Result<Vec<PathBuf>, WriteError> {
    let series = |x: fn(&Row) -> f64| -> Vec<Series> {
        ["rk4", "dopri5", "dop853"]
            .iter()
            .map(|&m| Series {
                name: m,
                points: report
                    .rows
                    .iter()
                    .filter(|r| r.setting.method.name() == m && r.error.is_finite())
                    .map(|r| (x(r), r.error))
                    .collect(),
            })
            .collect()
    };
    let paper = |x: fn(&Row) -> f64| {
        report
            .rows
            .iter()
            .find(|r| r.setting.method == (Method::Rk4 { h: PAPER_STEP }) && r.error.is_finite())
            .map(|r| (x(r), r.error))
    };
    let title = |what: &str| {
        format!(
            "{}: error ({}) vs {what}, t_end = {} s",
            report.scene_name,
            report.reference.measure(),
            report.t_end
        )
    };
    let time = |r: &Row| r.wall_median;
    let evals = |r: &Row| r.rhs_evals as f64;
    let svg_time = plot::svg(
        &title("wall time"),
        "wall time, median (s)",
        &series(time),
        paper(time),
        &TARGETS,
    )
    .map_err(WriteError::Plot)?;
    let svg_evals = plot::svg(
        &title("evaluations"),
        "right-hand-side evaluations",
        &series(evals),
        paper(evals),
        &TARGETS,
    )
    .map_err(WriteError::Plot)?;
    std::fs::create_dir_all(dir).map_err(|e| OutputError::Io {
        path: dir.to_owned(),
        source: e,
    })?;
    let files = [
        ("precision.csv", csv(report)),
        ("error_vs_time.svg", svg_time),
        ("error_vs_evaluations.svg", svg_evals),
    ];
    let mut out = Vec::new();
    for (name, text) in files {
        let path = dir.join(name);
        atomic::write(&path, text.as_bytes())?;
        out.push(path);
    }
    Ok(out)
}

/// The cheapest (median wall time) setting whose error is at most `target` and whose run
/// ended as the reference's did.
pub fn cheapest<'r>(rows: &'r [Row], reference: &Reference, target: f64) -> Option<&'r Row> {
    rows.iter()
        .filter(|r| r.status == reference.status() && r.error <= target)
        .min_by(|a, b| a.wall_median.total_cmp(&b.wall_median))
}

/// The printed table and answers.
pub fn summary(report: &Report) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "precision: {} over t_end = {} s",
        report.scene_name, report.t_end
    );
    let _ = writeln!(s, "{}", report.reference.describe());
    let _ = writeln!(
        s,
        "{:<7} {:<12} {:>9} {:>9} {:>11} {:>10} {:>9}  status",
        "method", "setting", "error", "drift", "time (s)", "rhs evals", "steps"
    );
    for r in &report.rows {
        let _ = writeln!(
            s,
            "{:<7} {:<12} {:>9.2e} {:>9} {:>11.3e} {:>10} {:>9}  {}",
            r.setting.method.name(),
            r.setting.label(),
            r.error,
            r.invariant_drift
                .map_or_else(|| "-".into(), |d| format!("{d:.1e}")),
            r.wall_median,
            r.rhs_evals,
            r.accepted,
            r.status
        );
    }
    let _ = writeln!(
        s,
        "cheapest setting (median wall time) reaching each error:"
    );
    for t in TARGETS {
        match cheapest(&report.rows, &report.reference, t) {
            Some(r) => {
                let _ = writeln!(
                    s,
                    "  {t:>6.0e}: {:<7} {:<12} error {:.1e}, {:.3e} s, {} rhs evals",
                    r.setting.method.name(),
                    r.setting.label(),
                    r.error,
                    r.wall_median,
                    r.rhs_evals
                );
            }
            None => {
                let _ = writeln!(s, "  {t:>6.0e}: not reached by any setting");
            }
        }
    }
    if let Some(p) = report
        .rows
        .iter()
        .find(|r| r.setting.method == (Method::Rk4 { h: PAPER_STEP }))
    {
        let _ = writeln!(
            s,
            "paper's setting (RK4, h = 1e-4 s): error {:.1e}, {:.3e} s",
            p.error, p.wall_median
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn nutation_scenario() -> Scenario {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/nutation.toml");
        ellipsoid_core::scenario::load(&path, &["output.t_end=0.3", "output.dt=0.1"]).unwrap()
    }

    /// The period runs integrate the frictionless system directly: they must start from
    /// the state `simulate` builds and take the very same steps.
    #[test]
    fn period_runs_take_the_steps_of_simulate() {
        let scenario = nutation_scenario();
        for method in [Method::Rk4 { h: 1e-3 }, Method::Dopri5, Method::Dop853] {
            let scene = with_setting(
                &scenario.scene,
                &Setting {
                    method,
                    rtol: 1e-9,
                    atol: 1e-11,
                },
            );
            let out = run(&scenario, &scene, &Hooks::SILENT).unwrap();
            let sys = System {
                body: scene.body.clone(),
                gravity: scene.gravity,
                contact: Frictionless,
                effects: (),
            };
            let mut options = Options::new(1e-9, 1e-11);
            options.max_steps = scene.solver.max_steps;
            let y0 = scene.initial_state().unwrap().1;
            let sol = integrate::integrate(
                method,
                &sys,
                0.0,
                y0,
                scene.t_end,
                &options,
                &[],
                &[],
                &mut |_, _| ControlFlow::Continue(()),
            )
            .unwrap();
            assert_eq!(
                (sol.stats.accepted, sol.stats.rejected),
                (out.stats.accepted, out.stats.rejected),
                "{method:?}"
            );
            assert_eq!(
                sol.y, out.final_state,
                "{method:?}: same final state, bit for bit"
            );
        }
    }

    #[test]
    fn grid_spans_the_documented_ranges_and_includes_the_papers_step() {
        let g = grid(false, 1e-2);
        let steps: Vec<f64> = g
            .iter()
            .filter_map(|s| {
                if let Method::Rk4 { h } = s.method {
                    Some(h)
                } else {
                    None
                }
            })
            .collect();
        assert_eq!((steps[0], *steps.last().unwrap()), (1e-2, 1e-6));
        assert!(steps.contains(&PAPER_STEP));
        for m in [Method::Dopri5, Method::Dop853] {
            let r: Vec<&Setting> = g.iter().filter(|s| s.method == m).collect();
            assert_eq!(
                (r[0].rtol, r.last().unwrap().rtol, r.len()),
                (1e-3, 1e-13, 11)
            );
            assert!(r.iter().all(|s| s.atol == s.rtol * 1e-2));
        }
        assert_eq!(grid(true, 1e-2).len(), 9);
    }

    #[test]
    fn the_csv_header_names_the_columns() {
        let report = Report {
            scene_name: "x".into(),
            t_end: 1.0,
            reference: Reference::State {
                outcome: Box::new(
                    run(
                        &nutation_scenario(),
                        &nutation_scenario().scene,
                        &Hooks::SILENT,
                    )
                    .unwrap(),
                ),
                rtol: REFERENCE_RTOL,
                uncertainty: 0.0,
            },
            rows: Vec::new(),
            notes: Vec::new(),
        };
        let names: Vec<&str> = columns(&report).iter().map(|c| c.0).collect();
        assert_eq!(names.join(","), CSV_HEADER);
        assert_eq!(csv(&report), format!("{CSV_HEADER}\n"));
    }

    #[test]
    fn cancelling_stops_the_study_with_its_own_error() {
        let cancel = Arc::new(AtomicBool::new(true));
        let hooks = Hooks {
            cancel: Some(cancel),
            ..Hooks::SILENT
        };
        let options = StudyOptions {
            quick: true,
            ..StudyOptions::default()
        };
        let e = measure(&nutation_scenario(), &options, &Spelling::CLI, &hooks)
            .err()
            .expect("cancelled");
        assert!(matches!(e, StudyError::Cancelled), "{e}");
    }

    #[test]
    fn median_of_odd_and_even_counts() {
        assert_eq!(median(&[1.0, 2.0, 9.0]), 2.0);
        assert_eq!(median(&[1.0, 2.0, 4.0, 9.0]), 3.0);
    }
}
