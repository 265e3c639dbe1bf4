//! `ellipsoid run`: simulate, stream the trajectory to a file, write the summary.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use ellipsoid_core::scenario::{self, Scenario};
use ellipsoid_io::run::Failure;
use ellipsoid_io::{atomic, Format, Metadata, OutputError, Summary, TrajectoryWriter};

use crate::cli::RunArgs;
use crate::error::CliError;
use crate::progress::Progress;

/// Exit status of a run that stopped before t_end.
const EARLY_STOP: u8 = 3;

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
    let finished = ellipsoid_io::run::run(scenario, Some(output.display().to_string()), env!("CARGO_PKG_VERSION"), None, |s| {
        progress.update(s.t);
        writer.write(s)
    });
    progress.finish();
    // Errors of the physics layer are input errors found late (e.g. N ≤ 0 at t = 0):
    // they are placed in the scenario file. The unfinished output is dropped, so deleted.
    let finished = finished.map_err(|f| match f {
        Failure::Scenario(e) => CliError::Scenario(e),
        Failure::Sink(e) => CliError::from(e),
    })?;
    writer.finish(&Metadata { scenario_text: &scenario.text, summary: &finished.summary })?;
    Ok((finished.summary, finished.non_finite))
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
