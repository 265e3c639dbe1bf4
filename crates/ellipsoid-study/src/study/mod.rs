//! Parameter studies (`ellipsoid study`, `ellipsoid.study`; docs/studies.md): a base
//! scenario, axes over any of its keys, and a table with one row per point.
//!
//! ```text
//!   study file ──spec──▶ Plan ──Study::new──▶ Study ──resolve(i)──▶ overrides, resolved text, key
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

use std::path::Path;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use rayon::prelude::*;

pub use journal::{Journal, JournalError};
pub use plan::{Base, Cell, Column, Combine, Outcomes, Plan, Study, Type};
pub use run::{INTERNAL_ERROR, INVALID, PointResult, VERSION};
pub use table::TableFormat;

pub(crate) fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "a panic without a message".into())
}

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
}

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
    mut progress: impl FnMut(&Tally),
) -> Result<Vec<PointResult>, ExecError> {
    let n = study.len();
    let cells = study.outcome_columns().len();
    let mut tally = Tally {
        total: n,
        ..Tally::default()
    };
    let (mut journal, done) = match journal {
        Some(p) => {
            let (j, d) = Journal::open(p, &study.outcome_fingerprint(), cells)?;
            (Some(j), d)
        }
        None => (None, Default::default()),
    };
    let mut results: Vec<PointResult> = Vec::with_capacity(n);
    let pending: Vec<usize> = if done.is_empty() {
        (0..n).collect()
    } else {
        // Keys of every point, in parallel (a resolve is tens of microseconds).
        let keys: Vec<Option<String>> = (0..n)
            .into_par_iter()
            .map(|i| study.resolve(i).ok().map(|r| r.key))
            .collect();
        let mut pending = Vec::new();
        for (i, key) in keys.into_iter().enumerate() {
            match key.and_then(|k| done.get(&k).map(|c| (k, c))) {
                Some((key, c)) => {
                    tally.done += 1;
                    tally.resumed += 1;
                    if matches!(c.first(), Some(Cell::Text(s)) if is_failure(s)) {
                        tally.failed += 1;
                    }
                    results.push(PointResult {
                        index: i,
                        key,
                        cells: c.clone(),
                    });
                }
                None => pending.push(i),
            }
        }
        pending
    };
    progress(&tally);
    let mut journal_error = None;
    study
        .run_many(&pending, threads, cancel, |r| {
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
            progress(&tally);
        })
        .map_err(ExecError::Internal)?;
    if let Some(j) = journal.as_mut() {
        j.sync()?;
    }
    if let Some(e) = journal_error {
        return Err(e.into());
    }
    if results.len() < n {
        return Err(ExecError::Interrupted {
            done: results.len(),
            total: n,
        });
    }
    Ok(results)
}
#[cfg(test)]
mod tests;
