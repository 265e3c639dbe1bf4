//! `ellipsoid run`: simulate, stream the trajectory to a file, write the summary.

use std::io::Write;
use std::ops::ControlFlow;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use ellipsoid_core::scenario::{self, Scenario};
use ellipsoid_core::simulate::{self, Sample};
use ellipsoid_io::{atomic, columns, Format, Metadata, OutputError, Summary, TrajectoryWriter};

use crate::cli::RunArgs;
use crate::error::CliError;
use crate::progress::Progress;

/// Exit status of a run that stopped before t_end.
const EARLY_STOP: u8 = 3;

/// Why the observer stopped the run.
enum Stop {
    /// A sample held NaN or infinity (it is not written).
    NonFinite { t: f64, column: &'static str, value: f64 },
    /// The trajectory file could not be written.
    Write(OutputError),
}

pub fn run(args: &RunArgs) -> Result<ExitCode, CliError> {
    let scenario = scenario::load(&args.scenario, &args.set)?;
    let output = args.output.clone().unwrap_or_else(|| Path::new("out").join(format!("{}.csv", scenario.stem())));
    Format::from_path(&output)?;
    let summary_path = args.summary.as_ref().filter(|p| p.as_os_str() != "-");

    // Directories made for the outputs are removed again if the run is rejected.
    let mut made = Vec::new();
    let result = (|| {
        for path in [Some(&output), summary_path].into_iter().flatten() {
            make_parent(path, &mut made)?;
        }
        simulate_to(&scenario, &output)
    })();
    if result.is_err() {
        for dir in made.iter().rev() {
            let _ = std::fs::remove_dir(dir);
        }
    }
    let (summary, stop_note) = result?;

    if let Some(target) = &args.summary {
        let json = summary.to_json();
        if target.as_os_str() == "-" {
            std::io::stdout().lock().write_all(json.as_bytes()).map_err(|e| OutputError::Io { path: "<stdout>".into(), source: e })?;
        } else {
            atomic::write(target, json.as_bytes())?;
        }
    }
    let completed = summary.status == "completed" && stop_note.is_none();
    if !args.quiet || !completed {
        report(&summary, &output, stop_note.as_deref());
    }
    Ok(if completed { ExitCode::SUCCESS } else { ExitCode::from(EARLY_STOP) })
}

/// Runs the scene, writing the trajectory to `output`; returns the summary and, if the
/// run was stopped for a non-finite value, why.
fn simulate_to(scenario: &Scenario, output: &Path) -> Result<(Summary, Option<String>), CliError> {
    let mut writer = TrajectoryWriter::create(output)?;
    let mut progress = Progress::new(scenario.scene.t_end);
    let mut stop: Option<Stop> = None;
    let start = Instant::now();
    let result = simulate::simulate(&scenario.scene, &mut |s| {
        if stop.is_none() {
            stop = accept(s, &mut writer).err();
        }
        if stop.is_some() {
            return ControlFlow::Break(());
        }
        progress.update(s.t);
        ControlFlow::Continue(())
    });
    let wall_time_s = start.elapsed().as_secs_f64();
    progress.finish();
    // Errors of the physics layer are input errors found late (e.g. N ≤ 0 at t = 0):
    // place them in the scenario file. The unfinished output is dropped, so deleted.
    let outcome = result.map_err(|e| scenario.locate(&e))?;
    let note = match stop {
        Some(Stop::Write(e)) => return Err(e.into()),
        Some(Stop::NonFinite { t, column, value }) => Some(format!(
            "stopped at t = {t} s: the state became non-finite ({column} = {value}); the trajectory before it is written"
        )),
        None => None,
    };
    let mut summary = Summary::new(scenario, &outcome, wall_time_s, writer.rows(), Some(output.display().to_string()), env!("CARGO_PKG_VERSION"));
    if let Some(n) = &note {
        summary.message = n.clone();
    }
    writer.finish(&Metadata { scenario_text: &scenario.text, summary: &summary })?;
    Ok((summary, note))
}

/// Writes a sample, or says why the run must stop: a non-finite value (never written) or
/// a write error.
fn accept(s: &Sample, writer: &mut TrajectoryWriter) -> Result<(), Stop> {
    if let Some((column, value)) = columns::non_finite(s) {
        return Err(Stop::NonFinite { t: s.t, column, value });
    }
    writer.write(s).map_err(Stop::Write)
}

/// Creates the parent directories of `path`, recording the ones it made.
fn make_parent(path: &Path, made: &mut Vec<PathBuf>) -> Result<(), CliError> {
    let Some(parent) = path.parent().filter(|p| !p.as_os_str().is_empty()) else { return Ok(()) };
    let mut missing: Vec<&Path> = parent.ancestors().filter(|a| !a.as_os_str().is_empty() && !a.exists()).collect();
    missing.reverse();
    for dir in missing {
        std::fs::create_dir(dir).map_err(|e| OutputError::Io { path: dir.to_owned(), source: e })?;
        made.push(dir.to_owned());
    }
    Ok(())
}

/// A few lines on standard error: how the run ended, where the output is, the drifts.
fn report(summary: &Summary, output: &Path, stop_note: Option<&str>) {
    let t = summary.final_state.get("t").and_then(|v| v.as_f64()).unwrap_or(f64::NAN);
    let s = &summary.stats;
    let work = format!("{} samples, {} steps ({} rejected), {:.3} s", summary.samples, s.accepted, s.rejected, summary.wall_time_s);
    let mut lines = Vec::new();
    if summary.status == "completed" && stop_note.is_none() {
        lines.push(format!("ellipsoid: completed at t = {t} s: {work} -> {}", output.display()));
    } else {
        lines.push(format!("ellipsoid: stopped early ({}): {} [{work} -> {}]", summary.status, summary.message, output.display()));
    }
    let drifts: Vec<String> = serde_json::to_value(summary.drift)
        .ok()
        .and_then(|v| v.as_object().cloned())
        .into_iter()
        .flatten()
        .filter_map(|(k, v)| v.as_f64().map(|d| format!("{k} {d:.2e}")))
        .collect();
    if !drifts.is_empty() {
        lines.push(format!("ellipsoid: relative drift: {}", drifts.join(", ")));
    }
    for w in &summary.warnings {
        lines.push(format!("ellipsoid: warning: {w}"));
    }
    let failed = summary.failed_checks();
    if !failed.is_empty() {
        lines.push(format!("ellipsoid: warning: the scenario's [check] expectations were not met: {}", failed.join("; ")));
    }
    eprintln!("{}", lines.join("\n"));
}

#[cfg(test)]
mod tests {
    use super::*;
    use ellipsoid_core::simulate::Mode;
    use ellipsoid_core::state::EulerAngles;
    use nalgebra::Vector3;

    fn sample(t: f64) -> Sample {
        Sample {
            t,
            position: Vector3::zeros(),
            angles: EulerAngles::default(),
            omega: Vector3::new(0.0, 0.0, 1.0),
            velocity: Vector3::zeros(),
            energy: 1.0,
            work: 0.0,
            normal_force: 1.0,
            slip_speed: 0.0,
            mode: Mode::Rolling,
        }
    }

    #[test]
    fn a_non_finite_sample_stops_the_run_and_is_not_written() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("t.csv");
        let mut writer = TrajectoryWriter::create(&path).unwrap();
        assert!(accept(&sample(0.0), &mut writer).is_ok());
        let mut bad = sample(0.1);
        bad.omega.y = f64::NAN;
        match accept(&bad, &mut writer) {
            Err(Stop::NonFinite { t, column, value }) => assert!(t == 0.1 && column == "omega_y" && value.is_nan()),
            _ => panic!("a NaN sample must stop the run"),
        }
        assert_eq!(writer.rows(), 1);
        let summary_free = std::fs::read_dir(dir.path()).unwrap().count();
        assert_eq!(summary_free, 1, "only the temporary exists before finish");
    }
}
