//! Parameter studies (`ellipsoid study`, `ellipsoid.study`; docs/studies.md): a base
//! scenario, axes over any of its keys, and a table with one row per point.
//!
//! ```text
//!   study file ──spec──▶ Plan ──Study::new──▶ Study ──resolve(i)──▶ changed document, key
//!   (or Python)          (data, JSON)          (columns)   └──run_point(i)──▶ outcome cells
//!                                                              (ellipsoid_io::run::run)
//!   execute: journal (done rows by point) ─▶ run the rest on a rayon pool ─▶ journal each
//!            row ─▶ rows read back from the journal in point order ─▶ table (CSV /
//!            Parquet / HDF5, atomic, streamed)
//! ```
//! Layout: [`axes`] (value generators), [`plan`] (the study as data, its points and
//! columns), [`spec`] (study files), [`run`] (one point, many in parallel), [`journal`]
//! (crash-safe, resumable), [`table`] (writers).

pub mod axes;
pub mod journal;
pub mod plan;
pub mod run;
pub mod spec;
pub mod table;
#[cfg(feature = "hdf5")]
pub mod trajectories;

use std::path::Path;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use rayon::prelude::*;

pub use journal::{Journal, JournalError};
pub use plan::{Base, Cell, Column, Combine, Outcomes, Plan, Study, Type};
pub use run::{PointResult, RowStatus, Trajectory, VERSION, max_threads, worker_threads};
pub use table::TableFormat;

/// How far a study has got (for progress displays).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Tally {
    /// Rows finished (including those found in the journal).
    pub done: usize,
    /// Of those, found in the journal.
    pub resumed: usize,
    /// Rows whose status is not `completed` or `observed`.
    pub failed: usize,
    pub total: usize,
}

/// Why a study did not finish.
#[derive(Debug, thiserror::Error)]
pub enum ExecError {
    #[error(transparent)]
    Journal(#[from] JournalError),
    /// Stopped by the cancel flag: the rows finished so far are in the journal.
    #[error("interrupted after {done} of {total} runs")]
    Interrupted { done: usize, total: usize },
    #[error("{0}")]
    Internal(String),
    /// Trajectories were asked for but the journal already holds finished rows (whose
    /// trajectories were not kept); nothing was run.
    #[error(
        "the journal {} already holds {resumed} finished runs, whose trajectories were not kept; add --fresh to run every point again with its trajectory",
        journal.display()
    )]
    Resumed {
        journal: std::path::PathBuf,
        resumed: usize,
    },
    /// The trajectory sink failed (or refused more rows); the runs stopped, the finished
    /// rows are in the journal.
    #[error("{0}")]
    Trajectories(String),
}

/// Receives each run's trajectory on the calling thread ([`execute_with`]); an error
/// stops the study.
pub type TrajectorySink<'a> = &'a mut dyn FnMut(&PointResult, &Trajectory) -> Result<(), String>;

/// Runs every point of `study` not already in the journal at `journal` (if any) on
/// `threads` threads (0: one per CPU), appending each finished row to the journal, and
/// returns one result per point (any order; [`Study::rows`] sorts them). `progress` is
/// called after every row. When `cancel` is set the runs in flight stop, the journal is
/// flushed, and the result is [`ExecError::Interrupted`].
pub fn execute(
    study: &Study,
    journal: Option<&Path>,
    threads: usize,
    cancel: &Arc<AtomicBool>,
    progress: impl FnMut(&Tally),
) -> Result<Vec<PointResult>, ExecError> {
    let n = study.len();
    let Some(path) = journal else {
        let mut results = Vec::with_capacity(n);
        let mut tally = Tally {
            total: n,
            ..Tally::default()
        };
        run_points(
            study,
            None,
            threads,
            cancel,
            None,
            progress,
            &mut tally,
            Some(&mut results),
        )?;
        return Ok(results);
    };
    let mut j = execute_with(study, path, threads, cancel, None, progress)?.journal;
    (0..n)
        .map(|index| {
            j.row(index)?.ok_or_else(|| {
                ExecError::Internal(format!("point {index} has no row in the journal"))
            })
        })
        .collect()
}

/// A study whose every row is in its journal: the table is written from it
/// ([`Finished::write_table`]), a row at a time.
pub struct Finished {
    pub journal: Journal,
    pub tally: Tally,
}

impl Finished {
    /// Writes the table of `study` to `path` (format by extension, atomically), reading
    /// the rows from the journal in point order: memory does not grow with the rows.
    pub fn write_table(
        &mut self,
        study: &Study,
        path: &Path,
    ) -> Result<(), ellipsoid_io::OutputError> {
        let journal = &mut self.journal;
        let rows = (0..study.len()).map(|index| {
            let fail = |m: String| ellipsoid_io::OutputError::Io {
                path: path.to_owned(),
                source: std::io::Error::other(m),
            };
            let r = journal
                .row(index)
                .map_err(|e| fail(e.to_string()))?
                .ok_or_else(|| fail(format!("point {index} has no row in the journal")))?;
            Ok(study.row(index, r.key, r.cells))
        });
        table::write_rows(path, &study.columns, rows, &study.plan.source)
    }
}

/// Runs every point of `study` whose row is not in the journal at `journal` yet, as
/// [`execute`] does, handing every run's trajectory to `trajectories` (if given) as it
/// finishes, and returns the journal, which then holds a row for every point. A journal
/// that already holds rows is refused when trajectories are asked for
/// ([`ExecError::Resumed`]): those rows have no trajectory to give.
///
/// Resuming with a journal of this very study (its plan fingerprint) skips its points
/// by index, without resolving them; rows of another plan or of the first journal
/// format are matched by key, which resolves every point not done ([`Journal`]).
pub fn execute_with(
    study: &Study,
    journal: &Path,
    threads: usize,
    cancel: &Arc<AtomicBool>,
    trajectories: Option<TrajectorySink<'_>>,
    progress: impl FnMut(&Tally),
) -> Result<Finished, ExecError> {
    let n = study.len();
    let mut tally = Tally {
        total: n,
        ..Tally::default()
    };
    let whom = journal::For {
        outcomes: &study.outcome_fingerprint(),
        plan: &study.plan_fingerprint(),
        cells: study.outcome_columns().len(),
        points: n,
    };
    let mut j = match Journal::open(journal, whom, cancel) {
        Err(JournalError::Interrupted { .. }) => {
            return Err(ExecError::Interrupted { done: 0, total: n });
        }
        r => r?,
    };
    let found = j.indexed() + j.keyed();
    if trajectories.is_some() && found > 0 {
        return Err(ExecError::Resumed {
            journal: journal.to_owned(),
            resumed: found,
        });
    }
    run_points(
        study,
        Some(&mut j),
        threads,
        cancel,
        trajectories,
        progress,
        &mut tally,
        None,
    )?;
    Ok(Finished { journal: j, tally })
}

/// Points handled a chunk at a time: the cancel flag is read between chunks, and a chunk's
/// pending points (as `u32`: 4 bytes each) are all that is held.
const CHUNK: usize = 1 << 16;
/// Points resolved together when rows are matched by key (a resolve is tens of
/// microseconds: 10⁷ points take a minute of CPU): a chunk's resolved scenarios are held,
/// and the cancel flag is read between chunks.
const KEY_CHUNK: usize = 1 << 12;

/// Runs the points of `study` that have no row in `journal` (all, without one), each
/// finished row to the journal, the trajectory sink, the tally and `results` (if given).
#[allow(clippy::too_many_arguments)]
fn run_points(
    study: &Study,
    mut journal: Option<&mut Journal>,
    threads: usize,
    cancel: &Arc<AtomicBool>,
    mut trajectories: Option<TrajectorySink<'_>>,
    mut progress: impl FnMut(&Tally),
    tally: &mut Tally,
    mut results: Option<&mut Vec<PointResult>>,
) -> Result<(), ExecError> {
    let n = study.len();
    let keep = trajectories.is_some();
    if let Some(j) = journal.as_deref() {
        tally.done = j.indexed();
        tally.resumed = j.indexed();
        tally.failed = j.failed();
    }
    let mut journal_error = None;
    let mut sink_error = None;
    // A finished row: its trajectory to the sink, the row to the journal and the tally.
    let mut finish = |mut r: PointResult,
                      tally: &mut Tally,
                      journal: &mut Option<&mut Journal>,
                      resumed: bool| {
        // A point that never ran (invalid) gets an empty trajectory: still a group.
        let t = r.trajectory.take().unwrap_or_default();
        if let Some(sink) = trajectories.as_mut()
            && sink_error.is_none()
            && let Err(e) = sink(&r, &t)
        {
            sink_error = Some(e);
            cancel.store(true, Ordering::Relaxed);
        }
        if let Some(j) = journal.as_deref_mut()
            && journal_error.is_none()
            && let Err(e) = j.append(&r)
        {
            journal_error = Some(e);
            cancel.store(true, Ordering::Relaxed);
        }
        tally.done += 1;
        tally.resumed += usize::from(resumed);
        if r.status.failed() {
            tally.failed += 1;
        }
        if let Some(out) = results.as_deref_mut() {
            out.push(r);
        }
    };
    progress(tally);
    let by_key = journal.as_deref().is_some_and(|j| j.keyed() > 0);
    let mut outcome = Ok(());
    let chunk = if by_key { KEY_CHUNK } else { CHUNK };
    for start in (0..n).step_by(chunk) {
        if cancel.load(Ordering::Relaxed) {
            break;
        }
        let end = n.min(start + chunk);
        let pending: Vec<u32> = (start..end)
            .filter(|&i| !journal.as_deref().is_some_and(|j| j.has(i)))
            .map(|i| u32::try_from(i).expect("at most MAX_POINTS points"))
            .collect();
        if pending.is_empty() {
            continue;
        }
        outcome = if by_key {
            // Rows known by key only: each pending point resolved (in parallel) and
            // matched, the others run with the scenarios resolved for their keys.
            let resolved: Vec<_> = pending
                .into_par_iter()
                .map(|i| (i as usize, study.resolve(i as usize)))
                .collect();
            let mut run = Vec::new();
            for (index, r) in resolved {
                let known = r.as_ref().ok().and_then(|r| {
                    let j = journal.as_deref()?;
                    let (status, cells) = j.by_key(&r.key)?;
                    Some((r.key.clone(), *status, cells.clone()))
                });
                match known {
                    Some((key, status, cells)) => {
                        let row = PointResult {
                            index,
                            key,
                            status,
                            cells,
                            trajectory: None,
                        };
                        finish(row, tally, &mut journal, true);
                    }
                    None => run.push((index, r)),
                }
            }
            progress(tally);
            study.run_resolved_with(run, threads, cancel, keep, |r| {
                finish(r, tally, &mut journal, false);
                progress(tally);
            })
        } else {
            study.run_indices_with(&pending, threads, cancel, keep, |r| {
                finish(r, tally, &mut journal, false);
                progress(tally);
            })
        };
        if outcome.is_err() {
            break;
        }
    }
    if let Some(j) = journal {
        j.sync()?;
    }
    outcome.map_err(ExecError::Internal)?;
    if let Some(e) = journal_error {
        return Err(e.into());
    }
    if let Some(e) = sink_error {
        return Err(ExecError::Trajectories(e));
    }
    if tally.done < n {
        return Err(ExecError::Interrupted {
            done: tally.done,
            total: n,
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests;
