//! `ellipsoid study STUDY.toml -o RESULTS.parquet|.csv|.h5`: a thin front over
//! `ellipsoid_study::study` (study files, journal and tables are documented there and in
//! docs/studies.md). Loads the study, runs what the journal does not hold yet on all cores
//! with a progress line on a terminal, writes the table atomically.
//!
//! Ctrl-C or SIGTERM stops the runs at their next step; the finished rows are already in
//! the journal (`RESULTS.journal`), no table is written, and the exit status is
//! 128 + the signal. SIGKILL loses only the runs in flight: rerunning the same command
//! finishes the study and writes the same table.

use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::{Duration, Instant};

use ellipsoid_io::OutputError;
use ellipsoid_study::study::{
    self, ExecError, JournalError, PointResult, Study, TableFormat, Tally, Trajectory, spec,
};

use crate::cli::StudyArgs;
use crate::error::CliError;
use crate::interrupt::Interrupt;
use crate::progress::{bar, clock};

/// The journal beside `table`: `RESULTS.parquet` → `RESULTS.parquet.journal`.
pub fn journal_path(table: &Path) -> PathBuf {
    let mut name = table.file_name().unwrap_or_default().to_os_string();
    name.push(".journal");
    table.with_file_name(name)
}

pub fn study(args: &StudyArgs) -> Result<ExitCode, CliError> {
    TableFormat::from_path(&args.output)
        .map_err(|rule| CliError::Usage(format!("{}: {rule}", args.output.display())))?;
    let plan = spec::load(&args.study)?;
    let study = Study::new(plan)?;
    if !(args.quiet || args.quiet_plausibility) {
        for w in study.warnings() {
            eprintln!("{w}");
        }
    }
    let max = study::max_threads();
    if let Some(j) = args.jobs.filter(|j| !(1..=max).contains(j)) {
        return Err(CliError::Usage(format!(
            "--jobs {j}: give 1 to {max} worker threads (4 per CPU, at least 8); more than one per CPU only adds overhead"
        )));
    }
    if let Some(t) = &args.trajectories {
        check_trajectories(t, &args.output, &study)?;
    }
    ellipsoid_io::atomic::check_target(&args.output)?;
    for path in std::iter::once(&args.output).chain(&args.trajectories) {
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(|e| OutputError::Io {
                path: dir.to_owned(),
                source: e,
            })?;
            ellipsoid_io::atomic::remove_stale(dir);
        }
    }
    let journal = journal_path(&args.output);
    if args.fresh {
        match std::fs::remove_file(&journal) {
            Ok(()) => {}
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
            Err(e) => {
                return Err(OutputError::Io {
                    path: journal,
                    source: e,
                }
                .into());
            }
        }
    }
    let interrupt = Interrupt::install();
    let start = Instant::now();
    let mut bar = Bar::new(!args.quiet && std::io::stderr().is_terminal());
    let mut last = Tally::default();
    let mut traj_file = match &args.trajectories {
        Some(p) => Some(TrajFile::create(p, &study)?),
        None => None,
    };
    let mut sink = |r: &PointResult, t: &Trajectory| match traj_file.as_mut() {
        Some(f) => f.add(&study, r, t),
        None => Ok(()),
    };
    let result = study::execute_with(
        &study,
        &journal,
        args.jobs.unwrap_or(0),
        &interrupt.any,
        args.trajectories
            .is_some()
            .then_some(&mut sink as study::TrajectorySink<'_>),
        |t| {
            last = *t;
            bar.update(start.elapsed(), t);
        },
    );
    bar.finish();
    let mut finished = match result {
        Ok(f) => f,
        Err(ExecError::Interrupted { done, total }) => {
            let (signal, name) = interrupt.received().unwrap_or((2, "SIGINT"));
            return Err(CliError::Interrupted {
                signal,
                message: format!(
                    "interrupted by {name} after {done} of {total} runs; the finished rows are kept in {} (rerun the same command to finish the study)",
                    journal.display()
                ),
            });
        }
        Err(ExecError::Journal(JournalError::Io { path, source })) => {
            return Err(OutputError::Io { path, source }.into());
        }
        // A journal of another study, or not a journal: bad input, nothing was run.
        Err(ExecError::Journal(e)) => return Err(CliError::Usage(e.to_string())),
        Err(e @ (ExecError::Resumed { .. } | ExecError::Trajectories(_))) => {
            return Err(CliError::Usage(e.to_string()));
        }
        Err(ExecError::Internal(msg)) => {
            return Err(CliError::Usage(format!(
                "internal error: {msg}; please report it"
            )));
        }
    };
    // Streamed from the journal in point order: the rows are never all held.
    finished.write_table(&study, &args.output)?;
    if let Some(f) = traj_file {
        f.commit()?;
    }
    if !args.quiet {
        let secs = start.elapsed().as_secs_f64();
        let ran = last.done - last.resumed;
        eprintln!(
            "study: {} runs ({} run now in {secs:.1} s, {:.0} runs/s; {} from the journal), {} not completed; wrote {}",
            last.total,
            ran,
            ran as f64 / secs.max(1e-9),
            last.resumed,
            last.failed,
            args.output.display()
        );
        if let Some(t) = &args.trajectories {
            eprintln!("study: wrote the trajectories to {}", t.display());
        }
    }
    Ok(ExitCode::SUCCESS)
}

#[cfg(feature = "hdf5")]
type TrajFile = study::trajectories::TrajectoryFile;

/// Refuses a trajectory file this build cannot write, that is the table itself, or that
/// would exceed the size limit.
fn check_trajectories(path: &Path, output: &Path, study: &Study) -> Result<(), CliError> {
    let usage = |m: String| CliError::Usage(format!("--trajectories {}: {m}", path.display()));
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
    if !matches!(ext, "h5" | "hdf5") {
        return Err(usage(
            "the trajectory file is HDF5: give it the extension .h5".into(),
        ));
    }
    if path == output {
        return Err(usage("the trajectory file cannot be the table".into()));
    }
    #[cfg(not(feature = "hdf5"))]
    {
        let _ = study;
        Err(usage(ellipsoid_io::HDF5_HINT.into()))
    }
    #[cfg(feature = "hdf5")]
    {
        ellipsoid_io::atomic::check_target(path)?;
        study::trajectories::check_size(study).map_err(CliError::Usage)
    }
}

/// Stands in for the trajectory file in a build without HDF5 (refused before it is made).
#[cfg(not(feature = "hdf5"))]
struct TrajFile;

#[cfg(not(feature = "hdf5"))]
impl TrajFile {
    fn create(_: &Path, _: &Study) -> Result<Self, CliError> {
        unreachable!("refused by check_trajectories")
    }
    fn add(&mut self, _: &Study, _: &PointResult, _: &Trajectory) -> Result<(), String> {
        unreachable!()
    }
    fn commit(self) -> Result<(), CliError> {
        unreachable!()
    }
}

/// Shortest time between two frames.
const REFRESH: Duration = Duration::from_millis(200);
/// Clears the terminal line and returns to its start.
const CLEAR: &str = "\r\x1b[2K";

/// The progress line on a terminal: `00:00:12 [=====>     ] 4000/10000 runs, 331 runs/s, 12 failed (eta 00:00:18)`.
struct Bar {
    enabled: bool,
    /// When the last frame was drawn.
    last: Option<Duration>,
}

impl Bar {
    fn new(enabled: bool) -> Bar {
        Bar {
            enabled,
            last: None,
        }
    }

    fn update(&mut self, elapsed: Duration, t: &Tally) {
        if !self.enabled || (t.done < t.total && self.last.is_some_and(|l| elapsed < l + REFRESH)) {
            return;
        }
        self.last = Some(elapsed);
        let mut err = std::io::stderr();
        let _ = write!(err, "{CLEAR}{}", frame(elapsed, t));
        let _ = err.flush();
    }

    fn finish(&mut self) {
        if self.last.is_some() {
            let _ = write!(std::io::stderr(), "{CLEAR}");
        }
    }
}

/// The progress line's text after `elapsed`.
pub fn frame(elapsed: Duration, t: &Tally) -> String {
    let f = if t.total > 0 {
        t.done as f64 / t.total as f64
    } else {
        1.0
    };
    let bar = bar(f);
    let ran = t.done - t.resumed;
    let secs = elapsed.as_secs_f64();
    let rate = if secs > 0.0 { ran as f64 / secs } else { 0.0 };
    let eta = if rate > 0.0 {
        clock((t.total - t.done) as f64 / rate)
    } else {
        "--:--:--".into()
    };
    format!(
        "{} [{bar}] {}/{} runs, {rate:.0} runs/s, {} failed (eta {eta})",
        clock(secs),
        t.done,
        t.total,
        t.failed
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_line_shows_done_total_rate_failures_and_eta() {
        let t = Tally {
            done: 4000,
            resumed: 1000,
            failed: 12,
            total: 10000,
        };
        let f = frame(Duration::from_secs(10), &t);
        assert_eq!(
            f,
            "00:00:10 [============>                 ] 4000/10000 runs, 300 runs/s, 12 failed (eta 00:00:20)"
        );
        assert_eq!(
            journal_path(Path::new("out/r.parquet")),
            Path::new("out/r.parquet.journal")
        );
    }
}
