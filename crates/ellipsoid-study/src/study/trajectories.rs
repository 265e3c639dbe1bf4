//! A study's trajectories (`ellipsoid study --trajectories RUNS.h5`; feature `hdf5`): one
//! HDF5 file, a group per distinct row key (points that run the same scenario share one),
//! laid out like `ellipsoid run`'s HDF5 output (`t`, …, `gap`, then a body's per-surface
//! columns such as `gap_stem`, each with `units`, and `mode`), with
//! the point, axis values, status and message of the first such row to finish as group
//! attributes. Written group by group as the runs finish, to a temporary renamed into
//! place by [`TrajectoryFile::commit`]; bounded by [`MAX_ROWS`] samples over all runs.

use std::collections::HashSet;
use std::path::Path;

use ellipsoid_core::columns::{Layout, NUMERIC};
use ellipsoid_io::OutputError;
use ellipsoid_io::hdf5::Hdf5Groups;

use super::plan::{Cell, Role, Study};
use super::run::{PointResult, Trajectory};

/// Most samples (trajectory rows) one trajectory file may hold over all its runs:
/// 10⁸ rows of 28 columns, about 22 GB.
pub const MAX_ROWS: u64 = 100_000_000;

/// Samples the study would write: points × the samples of point 0's scenario (its
/// `output.dt` grid over `output.t_end`). `None` if point 0 is not a valid scenario.
pub fn estimated_rows(study: &Study) -> Option<(u64, u64)> {
    let r = study.resolve(0).ok()?;
    let s = study.scenario(&r).ok()?;
    let per_run = s.scene.sample_times.len() as u64;
    Some((per_run, per_run.saturating_mul(study.len() as u64)))
}

/// Refuses a study whose trajectories would exceed [`MAX_ROWS`], naming the numbers.
pub fn check_size(study: &Study) -> Result<(), String> {
    match estimated_rows(study) {
        Some((per_run, total)) if total > MAX_ROWS => Err(format!(
            "--trajectories: {} runs × {per_run} samples = {total} trajectory rows, above the limit of {MAX_ROWS} (about 22 GB); sample less often (output.dt), run fewer points, or leave trajectories out",
            study.len()
        )),
        _ => Ok(()),
    }
}

/// The trajectory file being written.
pub struct TrajectoryFile {
    groups: Hdf5Groups,
    /// The keys that have a group already.
    keys: HashSet<String>,
}

impl TrajectoryFile {
    /// Creates the temporary beside `path`, with the root attributes `study` (the study
    /// file's text) and `version`.
    pub fn create(path: &Path, study: &Study) -> Result<Self, OutputError> {
        let groups = Hdf5Groups::create(
            path,
            &[
                ("study", &study.plan.source),
                ("version", super::run::VERSION),
                (
                    "layout",
                    "a group per run, named by its row's key; in each: the trajectory as in `ellipsoid run`'s HDF5 output, attributes key, point, the axis values, status, message",
                ),
            ],
        )?;
        Ok(TrajectoryFile {
            groups,
            keys: HashSet::new(),
        })
    }

    /// Adds run `r`'s trajectory `t` as the group named by its key (a point that never
    /// ran: `invalid-<point>`, with no samples). Points that run the same scenario share
    /// its key, so the first of them to finish makes the group and the others add
    /// nothing (their trajectories are the same). Refuses to go past [`MAX_ROWS`].
    pub fn add(&mut self, study: &Study, r: &PointResult, t: &Trajectory) -> Result<(), String> {
        if !r.key.is_empty() && !self.keys.insert(r.key.clone()) {
            return Ok(());
        }
        let rows = self.groups.rows() + t.len() as u64;
        if rows > MAX_ROWS {
            return Err(format!(
                "--trajectories: {rows} trajectory rows after {} runs, above the limit of {MAX_ROWS}; the runs were stopped (the rows so far are in the journal)",
                self.groups.groups() + 1
            ));
        }
        // A point that never ran: the fixed columns, empty.
        let empty;
        let (names, columns) = if t.columns.is_empty() {
            empty = (Layout::fixed().numeric_columns(), vec![Vec::new(); NUMERIC]);
            (&empty.0, &empty.1)
        } else {
            (&t.names, &t.columns)
        };
        let mut text: Vec<(String, String)> = vec![("key".into(), r.key.clone())];
        let mut numbers: Vec<(String, f64)> = vec![("point".into(), r.index as f64)];
        let axis_cols = study
            .columns
            .iter()
            .filter(|c| matches!(c.role, Role::Axis { .. }));
        for (c, cell) in axis_cols.zip(study.axis_cells(r.index)) {
            match cell {
                Cell::Float(v) => numbers.push((c.name.clone(), v)),
                Cell::Int(v) => numbers.push((c.name.clone(), v as f64)),
                Cell::Text(s) => text.push((c.name.clone(), s)),
                Cell::Null => {}
            }
        }
        for (c, cell) in study.outcome_columns().iter().zip(&r.cells) {
            if let (Role::Status | Role::Message, Cell::Text(s)) = (&c.role, cell) {
                text.push((c.name.clone(), s.clone()));
            }
        }
        let name = if r.key.is_empty() {
            format!("invalid-{}", r.index)
        } else {
            r.key.clone()
        };
        let text: Vec<(&str, &str)> = text.iter().map(|(k, v)| (k.as_str(), v.as_str())).collect();
        let numbers: Vec<(&str, f64)> = numbers.iter().map(|(k, v)| (k.as_str(), *v)).collect();
        self.groups
            .add(&name, names, columns, &t.modes, &text, &numbers)
            .map_err(|e| e.to_string())
    }

    /// Groups written so far.
    pub fn groups(&self) -> u64 {
        self.groups.groups()
    }

    /// Closes the file and renames it into place.
    pub fn commit(self) -> Result<(), OutputError> {
        self.groups.commit()
    }
}
