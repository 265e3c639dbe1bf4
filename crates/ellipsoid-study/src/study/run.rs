//! Running points: one through the same path as `ellipsoid run` and `ellipsoid.sweep`
//! (`ellipsoid_io::run::run`, summaries only), many on a rayon pool with the rows handed
//! to the caller's thread as they finish.
//!
//! A point always gives a row: a scenario the parser or the physics rejects is a row with
//! status `invalid` and the error as its message, a panic one with `internal_error`, and a
//! run that stops on an error (Painlevé, solver failure, …) a row with that status, its
//! message and the outcomes up to the stop. Only a cancelled run (Ctrl-C) gives none.

use std::borrow::Cow;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;

use ellipsoid_core::columns::{self, Layout};
use ellipsoid_core::simulate::{EventKind, Sample, Status, StatusKind};
use rayon::prelude::*;

use super::plan::{Cell, Resolution, Resolved, Role, Study};

/// Version recorded in the summaries the runs make (the workspace's).
pub const VERSION: &str = env!("CARGO_PKG_VERSION");

/// A row's status (its `status` cell): how its run ended, or why the point did not run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RowStatus {
    /// The run ended so.
    Ran(StatusKind),
    /// The point's scenario was rejected (parse error, or a state the physics refuses at
    /// t = 0).
    Invalid,
    /// The run panicked (a bug).
    InternalError,
}

impl RowStatus {
    /// Its name in the `status` column.
    pub fn name(self) -> &'static str {
        match self {
            RowStatus::Ran(kind) => kind.name(),
            RowStatus::Invalid => "invalid",
            RowStatus::InternalError => "internal_error",
        }
    }

    /// The status a `status` cell names; `None` for any other text.
    pub fn named(name: &str) -> Option<Self> {
        match name {
            "invalid" => Some(RowStatus::Invalid),
            "internal_error" => Some(RowStatus::InternalError),
            _ => StatusKind::named(name).map(RowStatus::Ran),
        }
    }

    /// The status of a row's outcome cells (the first is `status`), parsed once where
    /// rows come in from a journal; `Err` with the cell's text (`~` for no value) when
    /// it names no status.
    pub fn of(cells: &[Cell]) -> Result<Self, String> {
        match cells.first() {
            Some(Cell::Text(s)) => Self::named(s).ok_or_else(|| format!("{s:?}")),
            Some(Cell::Int(i)) => Err(i.to_string()),
            Some(Cell::Float(f)) => Err(f.to_string()),
            Some(Cell::Null) | None => Err("~".to_owned()),
        }
    }

    /// Every status a row can have: how a run ended ([`StatusKind::NAMES`]), `invalid`,
    /// `internal_error`.
    pub fn names() -> impl Iterator<Item = &'static str> {
        StatusKind::NAMES
            .into_iter()
            .chain([RowStatus::Invalid.name(), RowStatus::InternalError.name()])
    }

    /// Whether a row of this status counts as failed in the tally: its run did not end
    /// where the scene asked ([`StatusKind::finished`]), or the point did not run.
    pub fn failed(self) -> bool {
        !matches!(self, RowStatus::Ran(kind) if kind.finished())
    }
}

/// The outcome of one point: its key, its status and the outcome cells (status …
/// rhs_evals).
#[derive(Debug, Clone, PartialEq)]
pub struct PointResult {
    pub index: usize,
    pub key: String,
    /// How the point ended, typed: set where its run finishes, or parsed once where its
    /// row is read from a journal. Its `status` cell (the first of `cells`) is
    /// `status.name()`.
    pub status: RowStatus,
    pub cells: Vec<Cell>,
    /// The sampled trajectory, when asked for ([`Study::run_point_with`]) and the point
    /// ran (a point rejected before it starts has none).
    pub trajectory: Option<Trajectory>,
}

/// A run's samples, by column: the numeric columns of its body's layout
/// (`ellipsoid_core::columns::Layout::numeric_columns`: the fixed ones, then a body's
/// per-surface ones), named with their units in `names`, and the mode labels, all as
/// `ellipsoid run` writes them.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Trajectory {
    pub names: Vec<(Cow<'static, str>, &'static str)>,
    pub columns: Vec<Vec<f64>>,
    pub modes: Vec<Cow<'static, str>>,
}

impl Trajectory {
    /// Samples held.
    pub fn len(&self) -> usize {
        self.modes.len()
    }

    pub fn is_empty(&self) -> bool {
        self.modes.is_empty()
    }
}

/// Most worker threads a study (or a sweep) may start: 4 per CPU, at least 8. More threads
/// than CPUs only add overhead (each run is CPU-bound and takes an 8 MiB stack); 10⁵ of
/// them took minutes to start and ended in a failed stack guard page.
pub fn max_threads() -> usize {
    let cpus = std::thread::available_parallelism().map_or(1, |n| n.get());
    (4 * cpus).max(8)
}

/// The worker threads started for `points` runs when `requested` were asked (0: one per
/// CPU): never more than [`max_threads`], never more than the runs, at least one.
pub fn worker_threads(requested: usize, points: usize) -> usize {
    let wanted = if requested == 0 {
        std::thread::available_parallelism().map_or(1, |n| n.get())
    } else {
        requested
    };
    wanted.min(max_threads()).min(points).max(1)
}

impl Study {
    /// Runs point `index`; `None` if it was cancelled.
    pub fn run_point(&self, index: usize, cancel: Option<&Arc<AtomicBool>>) -> Option<PointResult> {
        self.run_point_with(index, cancel, false)
    }

    /// Runs point `index`, keeping its sampled trajectory if `keep`; `None` if it was
    /// cancelled.
    pub fn run_point_with(
        &self,
        index: usize,
        cancel: Option<&Arc<AtomicBool>>,
        keep: bool,
    ) -> Option<PointResult> {
        self.run_job(index, self.resolve(index), cancel, keep)
    }

    /// Runs point `index` as `resolved` ([`Study::resolve`]'s answer for it).
    fn run_job(
        &self,
        index: usize,
        resolved: Resolution,
        cancel: Option<&Arc<AtomicBool>>,
        keep: bool,
    ) -> Option<PointResult> {
        let resolved = match resolved {
            Ok(r) => r,
            Err((key, rule)) => {
                return Some(PointResult {
                    index,
                    key: String::new(),
                    status: RowStatus::Invalid,
                    cells: self.failed(RowStatus::Invalid, format!("{key}: {rule}")),
                    trajectory: None,
                });
            }
        };
        let key = resolved.key.clone();
        let (status, cells, trajectory) = catch_unwind(AssertUnwindSafe(|| {
            self.run_resolved(&resolved, cancel, keep)
        }))
        .unwrap_or_else(|p| {
            Some((
                RowStatus::InternalError,
                self.failed(
                    RowStatus::InternalError,
                    ellipsoid_core::error::panic_message(&*p),
                ),
                None,
            ))
        })?;
        Some(PointResult {
            index,
            key,
            status,
            cells,
            trajectory,
        })
    }

    fn run_resolved(
        &self,
        resolved: &Resolved,
        cancel: Option<&Arc<AtomicBool>>,
        keep: bool,
    ) -> Option<(RowStatus, Vec<Cell>, Option<Trajectory>)> {
        let invalid = |message: String| {
            Some((
                RowStatus::Invalid,
                self.failed(RowStatus::Invalid, message),
                None,
            ))
        };
        let scenario = match self.scenario(resolved) {
            Ok(s) => s,
            Err(e) => return invalid(e.first().to_string()),
        };
        let cols = self.outcome_columns();
        let layout = Layout::of(&scenario.scene.body);
        // Column `c`'s output column (`Final`, `Min`, `Max` of the base layout's column
        // `i`) in this point's layout: the same name, `None` if this body lacks it.
        let at = |c: &super::plan::Column, i: usize| {
            if i < columns::NUMERIC {
                Some(i)
            } else {
                c.name.split_once('.').and_then(|(_, n)| layout.index(n))
            }
        };
        // The value of this layout's numeric column `k` in a sample whose fixed columns
        // are `v`.
        let value = |s: &Sample, v: &[f64; columns::NUMERIC], k: usize| {
            if k < columns::NUMERIC {
                v[k]
            } else {
                layout.value(s, k)
            }
        };
        let extremes: Vec<(Option<usize>, bool)> = cols
            .iter()
            .filter_map(|c| match c.role {
                Role::Min(i) => Some((at(c, i), false)),
                Role::Max(i) => Some((at(c, i), true)),
                _ => None,
            })
            .collect();
        let mut ext: Vec<f64> = extremes
            .iter()
            .map(|(_, max)| {
                if *max {
                    f64::NEG_INFINITY
                } else {
                    f64::INFINITY
                }
            })
            .collect();
        let mut samples = 0u64;
        let mut traj = keep.then(|| {
            let n = scenario.scene.sample_times.len();
            Trajectory {
                names: layout.numeric_columns(),
                columns: (0..layout.numeric())
                    .map(|_| Vec::with_capacity(n))
                    .collect(),
                modes: Vec::with_capacity(n),
            }
        });
        let mut surface = Vec::with_capacity(layout.extra());
        let finished =
            ellipsoid_io::run::run(&scenario, None, VERSION, cancel.cloned(), |s: &Sample| {
                samples += 1;
                if !extremes.is_empty() || traj.is_some() {
                    let v = columns::values(s);
                    for ((k, max), e) in extremes.iter().zip(ext.iter_mut()) {
                        if let Some(k) = *k {
                            let x = value(s, &v, k);
                            *e = if *max { e.max(x) } else { e.min(x) };
                        }
                    }
                    if let Some(t) = traj.as_mut() {
                        surface.clear();
                        layout.surface_values(s, &mut surface);
                        for (c, x) in t.columns.iter_mut().zip(v.iter().chain(&surface)) {
                            c.push(*x);
                        }
                        t.modes.push(layout.mode(s));
                    }
                }
                Ok::<(), std::convert::Infallible>(())
            });
        let finished = match finished {
            Ok(f) => f,
            Err(ellipsoid_io::run::Failure::Scenario(e)) => {
                return invalid(e.to_string());
            }
            Err(ellipsoid_io::run::Failure::Sink(never)) => match never {},
        };
        let outcome = &finished.outcome;
        if matches!(outcome.status, Status::Cancelled) {
            return None;
        }
        let finite = |v: f64| {
            if v.is_finite() {
                Cell::Float(v)
            } else {
                Cell::Null
            }
        };
        let status = RowStatus::Ran(finished.summary.status.kind());
        let last = &outcome.final_sample;
        let fin = columns::values(last);
        let mut e = 0;
        let cells = cols
            .iter()
            .map(|c| match &c.role {
                Role::Status => Cell::Text(status.name().to_owned()),
                Role::Message => Cell::Text(finished.summary.message.clone()),
                Role::TFinal => finite(outcome.final_sample.t),
                Role::Observed(name) => outcome
                    .events
                    .iter()
                    .find(|ev| {
                        matches!(&ev.kind, EventKind::Observed { index, .. }
                        if scenario.scene.observe.get(*index).is_some_and(|o| &o.name == name))
                    })
                    .map_or(Cell::Null, |ev| finite(ev.t)),
                Role::Final(i) => at(c, *i).map_or(Cell::Null, |k| finite(value(last, &fin, k))),
                Role::FinalMode => Cell::Text(layout.mode(last).into_owned()),
                Role::Min(_) | Role::Max(_) => {
                    let (v, k) = (ext[e], extremes[e].0);
                    e += 1;
                    if samples > 0 && k.is_some() {
                        finite(v)
                    } else {
                        Cell::Null
                    }
                }
                Role::Drift(inv) => outcome.drift.get(*inv).map_or(Cell::Null, finite),
                Role::WallTime => finite(finished.summary.wall_time_s),
                Role::RhsEvals => {
                    Cell::Int(i64::try_from(outcome.stats.rhs_evals).unwrap_or(i64::MAX))
                }
                Role::Point | Role::Axis { .. } | Role::Key => Cell::Null,
            })
            .collect();
        Some((status, cells, traj))
    }

    /// The outcome cells of a point that produced no run.
    fn failed(&self, status: RowStatus, message: String) -> Vec<Cell> {
        self.outcome_columns()
            .iter()
            .map(|c| match c.role {
                Role::Status => Cell::Text(status.name().to_owned()),
                Role::Message => Cell::Text(message.clone()),
                _ => Cell::Null,
            })
            .collect()
    }

    /// Runs the points `indices` on `threads` worker threads (0: one per CPU; at most
    /// [`max_threads`] and the number of points, see [`worker_threads`]), handing
    /// each result to `on_row` on the calling thread as it finishes (in completion order).
    /// Stops starting points once `cancel` is set; runs in flight stop at their next
    /// integration step and give no row.
    pub fn run_many(
        &self,
        indices: &[usize],
        threads: usize,
        cancel: &Arc<AtomicBool>,
        on_row: impl FnMut(PointResult),
    ) -> Result<(), String> {
        self.run_many_with(indices, threads, cancel, false, on_row)
    }

    /// [`Study::run_many`], keeping each run's trajectory in its result if `keep`.
    pub fn run_many_with(
        &self,
        indices: &[usize],
        threads: usize,
        cancel: &Arc<AtomicBool>,
        keep: bool,
        on_row: impl FnMut(PointResult),
    ) -> Result<(), String> {
        self.run_par(
            indices.par_iter().copied(),
            indices.len(),
            threads,
            cancel,
            on_row,
            |i| self.run_point_with(i, Some(cancel), keep),
        )
    }

    /// [`Study::run_many_with`] over point indices held as `u32` (a resumed study's
    /// pending points: half the memory).
    pub(crate) fn run_indices_with(
        &self,
        indices: &[u32],
        threads: usize,
        cancel: &Arc<AtomicBool>,
        keep: bool,
        on_row: impl FnMut(PointResult),
    ) -> Result<(), String> {
        self.run_par(
            indices.par_iter().map(|&i| i as usize),
            indices.len(),
            threads,
            cancel,
            on_row,
            |i| self.run_point_with(i, Some(cancel), keep),
        )
    }

    /// [`Study::run_many_with`] over points already resolved (`(index, resolution)`), as a
    /// resumed study has them: each runs without being resolved again.
    pub(crate) fn run_resolved_with(
        &self,
        jobs: Vec<(usize, Resolution)>,
        threads: usize,
        cancel: &Arc<AtomicBool>,
        keep: bool,
        on_row: impl FnMut(PointResult),
    ) -> Result<(), String> {
        let n = jobs.len();
        self.run_par(
            jobs.into_par_iter(),
            n,
            threads,
            cancel,
            on_row,
            |(i, r)| self.run_job(i, r, Some(cancel), keep),
        )
    }

    /// Runs `run` on each of the `n` `items` on a pool of worker threads, handing each
    /// row to `on_row` on the calling thread as it finishes; items not yet started when
    /// `cancel` is set are skipped.
    fn run_par<I>(
        &self,
        items: I,
        n: usize,
        threads: usize,
        cancel: &Arc<AtomicBool>,
        mut on_row: impl FnMut(PointResult),
        run: impl Fn(I::Item) -> Option<PointResult> + Sync + Send,
    ) -> Result<(), String>
    where
        I: IndexedParallelIterator,
    {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(worker_threads(threads, n))
            .stack_size(8 << 20)
            .thread_name(|i| format!("ellipsoid-study-{i}"))
            .build()
            .map_err(|e| format!("cannot start the worker threads: {e}"))?;
        let (tx, rx) = mpsc::channel::<PointResult>();
        std::thread::scope(|scope| {
            let worker = scope.spawn(move || {
                pool.install(|| {
                    items.with_max_len(1).for_each_with(tx, |tx, item| {
                        if cancel.load(Ordering::Relaxed) {
                            return;
                        }
                        if let Some(r) = run(item) {
                            let _ = tx.send(r);
                        }
                    });
                });
            });
            for r in rx {
                on_row(r);
            }
            worker
                .join()
                .map_err(|p| ellipsoid_core::error::panic_message(&*p))
        })
    }
}
