//! Parameter studies (`ellipsoid study`, `ellipsoid.study`; docs/studies.md): a base
//! scenario, axes over any of its keys, and a table with one row per point.
//!
//! ```text
//!   study file ──spec──▶ Plan ──Study::new──▶ Study ──resolve(i)──▶ changed document, key
//!   (or Python)          (data, JSON)          (columns)   └──run_point(i)──▶ outcome cells
//!                                                              (ellipsoid_io::run::run)
//!   execute: journal (done rows by key) ─▶ run the rest on a rayon pool ─▶ journal each row
//!            ─▶ rows in point order ─▶ table (CSV / Parquet / HDF5, atomic)
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
pub use run::{
    INTERNAL_ERROR, INVALID, PointResult, Trajectory, VERSION, max_threads, worker_threads,
};
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

/// Whether a status counts as a failure in the tally.
pub fn is_failure(status: &str) -> bool {
    !matches!(status, "completed" | "observed")
}

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
    execute_with(study, journal, threads, cancel, None, progress)
}

/// [`execute`], handing every run's trajectory to `trajectories` (if given) as it
/// finishes; the results returned hold none. A journal that already holds rows is then
/// refused ([`ExecError::Resumed`]): those rows have no trajectory to give.
pub fn execute_with(
    study: &Study,
    journal: Option<&Path>,
    threads: usize,
    cancel: &Arc<AtomicBool>,
    mut trajectories: Option<TrajectorySink<'_>>,
    mut progress: impl FnMut(&Tally),
) -> Result<Vec<PointResult>, ExecError> {
    let n = study.len();
    let cells = study.outcome_columns().len();
    let mut tally = Tally {
        total: n,
        ..Tally::default()
    };
    let journal_path = journal.map(Path::to_path_buf);
    let (mut journal, done) = match journal {
        Some(p) => {
            let (j, d) = Journal::open(p, &study.outcome_fingerprint(), cells)?;
            (Some(j), d)
        }
        None => (None, Default::default()),
    };
    if trajectories.is_some() && !done.is_empty() {
        return Err(ExecError::Resumed {
            journal: journal_path.unwrap_or_default(),
            resumed: done.len(),
        });
    }
    let mut results: Vec<PointResult> = Vec::with_capacity(n);
    let mut journal_error = None;
    let mut sink_error = None;
    let keep = trajectories.is_some();
    // A finished run: its trajectory to the sink, its row to the journal and the tally.
    let mut finish = |mut r: PointResult, tally: &mut Tally, results: &mut Vec<PointResult>| {
        // A point that never ran (invalid) gets an empty trajectory: still a group.
        let t = r.trajectory.take().unwrap_or_default();
        if let Some(sink) = trajectories.as_mut()
            && sink_error.is_none()
            && let Err(e) = sink(&r, &t)
        {
            sink_error = Some(e);
            cancel.store(true, Ordering::Relaxed);
        }
        if let Some(j) = journal.as_mut()
            && journal_error.is_none()
            && let Err(e) = j.append(&r)
        {
            journal_error = Some(e);
            cancel.store(true, Ordering::Relaxed);
        }
        tally.done += 1;
        if matches!(r.cells.first(), Some(Cell::Text(s)) if is_failure(s)) {
            tally.failed += 1;
        }
        results.push(r);
    };
    if done.is_empty() {
        progress(&tally);
        let all: Vec<usize> = (0..n).collect();
        study
            .run_many_with(&all, threads, cancel, keep, |r| {
                finish(r, &mut tally, &mut results);
                progress(&tally);
            })
            .map_err(ExecError::Internal)?;
    } else {
        let mut rows = Rows {
            tally: &mut tally,
            results: &mut results,
            finish: &mut finish,
            progress: &mut progress,
        };
        resume(study, done, threads, cancel, keep, &mut rows)?;
    }
    if let Some(j) = journal.as_mut() {
        j.sync()?;
    }
    if let Some(e) = journal_error {
        return Err(e.into());
    }
    if let Some(e) = sink_error {
        return Err(ExecError::Trajectories(e));
    }
    if results.len() < n {
        return Err(ExecError::Interrupted {
            done: results.len(),
            total: n,
        });
    }
    Ok(results)
}

/// Points resolved together while resuming: the cancel flag is read between such chunks,
/// and only one chunk's resolved scenarios are held.
const RESUME_CHUNK: usize = 1 << 12;

/// Where the rows of a resumed study go: the tally, the results, what is done with a
/// finished run, and the progress display.
struct Rows<'a, F, P> {
    tally: &'a mut Tally,
    results: &'a mut Vec<PointResult>,
    finish: &'a mut F,
    progress: &'a mut P,
}

/// Resumes a study: the points whose rows the journal holds (`done`) are moved into the
/// results and counted as resumed, the others run. Each point is resolved once, in
/// parallel, a chunk at a time (a resolve is tens of microseconds: 10⁷ points take a
/// minute of CPU), and a chunk's pending points run with the scenarios resolved for their
/// keys; [`ExecError::Interrupted`] as soon as `cancel` is set.
fn resume<F, P>(
    study: &Study,
    mut done: journal::Done,
    threads: usize,
    cancel: &Arc<AtomicBool>,
    keep: bool,
    rows: &mut Rows<'_, F, P>,
) -> Result<(), ExecError>
where
    F: FnMut(PointResult, &mut Tally, &mut Vec<PointResult>),
    P: FnMut(&Tally),
{
    let n = study.len();
    // Rows already moved into `results`, by key (32 hexadecimal digits), for points that
    // run the same scenario: 24 bytes a row, not a second copy of the key and cells.
    let id = |k: &str| u128::from_str_radix(k, 16).ok();
    let mut taken: std::collections::HashMap<u128, usize> = Default::default();
    for start in (0..n).step_by(RESUME_CHUNK) {
        if cancel.load(Ordering::Relaxed) {
            return Err(ExecError::Interrupted {
                done: rows.tally.done,
                total: n,
            });
        }
        let resolved: Vec<_> = (start..n.min(start + RESUME_CHUNK))
            .into_par_iter()
            .map(|i| (i, study.resolve(i)))
            .collect();
        let mut pending = Vec::new();
        for (i, r) in resolved {
            let key = r.as_ref().ok().map(|r| r.key.as_str());
            let cells = key.and_then(|k| match done.remove(k) {
                Some(cells) => {
                    if let Some(id) = id(k) {
                        taken.insert(id, rows.results.len());
                    }
                    Some(cells)
                }
                None => id(k)
                    .and_then(|id| taken.get(&id))
                    .map(|&r| rows.results[r].cells.clone()),
            });
            let (Ok(r), Some(cells)) = (&r, cells) else {
                pending.push((i, r));
                continue;
            };
            rows.tally.done += 1;
            rows.tally.resumed += 1;
            if matches!(cells.first(), Some(Cell::Text(s)) if is_failure(s)) {
                rows.tally.failed += 1;
            }
            rows.results.push(PointResult {
                index: i,
                key: r.key.clone(),
                cells,
                trajectory: None,
            });
        }
        (rows.progress)(rows.tally);
        if pending.is_empty() {
            continue;
        }
        study
            .run_resolved_with(pending, threads, cancel, keep, |r| {
                (rows.finish)(r, rows.tally, rows.results);
                (rows.progress)(rows.tally);
            })
            .map_err(ExecError::Internal)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests;
