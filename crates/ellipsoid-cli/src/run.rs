//! `ellipsoid run`: simulate, stream the trajectory to a file, write the summary.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use ellipsoid_core::scenario::Scenario;
use ellipsoid_core::simulate::{EventKind, Observe};
use ellipsoid_io::run::{Failure, Finished};
use ellipsoid_io::{Format, Metadata, OutputError, Summary, TrajectoryWriter, atomic};

use crate::cli::RunArgs;
use ellipsoid_core::error::number;

use crate::error::CliError;
use crate::interrupt::Interrupt;
use crate::progress::Progress;

/// Exit status of a run that stopped before t_end.
const EARLY_STOP: u8 = 3;

pub fn run(args: &RunArgs) -> Result<ExitCode, CliError> {
    let interrupt = Interrupt::install();
    let scenario = crate::plausible::load(
        &args.scenario,
        &args.set,
        args.quiet || args.quiet_plausibility,
    )?;
    let output = args
        .output
        .clone()
        .unwrap_or_else(|| Path::new("out").join(format!("{}.csv", scenario.stem())));
    Format::from_path(&output)?;
    let summary_path = args.summary.as_ref().filter(|p| p.as_os_str() != "-");
    let output_name = if args.output.is_some() {
        "-o"
    } else {
        "the default -o"
    };
    let mut named = vec![
        ("the scenario file", args.scenario.as_path()),
        (output_name, output.as_path()),
    ];
    named.extend(summary_path.map(|p| ("--summary", p.as_path())));
    if let Some(path) = &args.sections {
        if scenario.scene.sections.is_empty() {
            return Err(CliError::Usage(format!(
                "--sections {}: the scenario has no [[section]] (docs/scenarios.md, \"Poincaré sections\")",
                path.display()
            )));
        }
        named.push(("--sections", path.as_path()));
    }
    distinct(&named)?;
    for (_, path) in &named[1..] {
        atomic::check_target(path)?;
    }

    // Directories made for the outputs are removed again if the run ends in an error,
    // and the files appear only when all of them are complete.
    let mut made = Vec::new();
    let result = (|| -> Result<Summary, CliError> {
        for path in [Some(&output), summary_path, args.sections.as_ref()]
            .into_iter()
            .flatten()
        {
            make_parent(path, &mut made)?;
        }
        // Reserved first, so an unwritable summary fails before the run.
        let summary_file = summary_path
            .map(|p| atomic::AtomicFile::create(p))
            .transpose()?;
        let (trajectory, done) = simulate_to(&scenario, &output, &interrupt)?;
        let summary = done.summary;
        let mut files = vec![trajectory];
        if let Some(path) = &args.sections {
            let table = ellipsoid_io::csv::sections_table(&scenario, &done.outcome.sections);
            files.push(atomic::prepare(path, &table)?);
        }
        if let (Some(mut file), Some(path)) = (summary_file, summary_path) {
            file.write_all(summary.to_json().as_bytes())
                .map_err(|e| OutputError::Io {
                    path: path.clone(),
                    source: e,
                })?;
            files.push(file.prepare()?);
        }
        // The last moment to honour a signal: after it, the files are put in place.
        stop_if_interrupted(&interrupt, &scenario, Some(&summary))?;
        if args.summary.as_ref().is_some_and(|p| p.as_os_str() == "-") {
            std::io::stdout()
                .lock()
                .write_all(summary.to_json().as_bytes())
                .map_err(|e| OutputError::Io {
                    path: "<stdout>".into(),
                    source: e,
                })?;
        }
        atomic::commit_all(files)?;
        Ok(summary)
    })();
    // A signal during the writing (or during an error) still ends as an interruption.
    let result = match (result, interrupt.received()) {
        (Err(e), Some(_)) if !matches!(e, CliError::Interrupted { .. }) => {
            Err(stop_if_interrupted(&interrupt, &scenario, None)
                .err()
                .unwrap_or(e))
        }
        (r, _) => r,
    };
    if result.is_err() {
        for dir in made.iter().rev() {
            let _ = std::fs::remove_dir(dir);
        }
    }
    let summary = result?;
    // The run ended where the scene asked (t_end or a terminal observable).
    let finished = summary.status.finished();

    if !args.quiet || !finished {
        report(&summary, &scenario.scene.observe, &output, finished);
    }
    Ok(if finished {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(EARLY_STOP)
    })
}

/// `Err(Interrupted)` if SIGINT or SIGTERM came: nothing is put in place (the temporaries
/// are deleted when dropped), and the message says where the run stopped.
fn stop_if_interrupted(
    interrupt: &Interrupt,
    scenario: &Scenario,
    summary: Option<&Summary>,
) -> Result<(), CliError> {
    let Some((signal, name)) = interrupt.received() else {
        return Ok(());
    };
    let t_end = scenario.scene.t_end;
    let at = summary
        .map(|s| s.final_sample.t)
        .filter(|t| t.is_finite())
        .map_or_else(String::new, |t| {
            format!(" at t = {} s of {} s", number(t), number(t_end))
        });
    Err(CliError::Interrupted {
        signal,
        message: format!(
            "interrupted by {name}{at}: the run was stopped and nothing was written (its temporary files are removed; existing output files are untouched)"
        ),
    })
}

/// Refuses two of the named paths (scenario, trajectory, summary) that are one file.
fn distinct(named: &[(&str, &Path)]) -> Result<(), CliError> {
    let ids: Vec<PathBuf> = named.iter().map(|(_, p)| identity(p)).collect();
    for i in 0..named.len() {
        for j in i + 1..named.len() {
            if ids[i] == ids[j] {
                let ((a, pa), (b, pb)) = (named[i], named[j]);
                return Err(CliError::Usage(format!(
                    "{a} {} and {b} {} are the same file ({}); give {b} a different path",
                    pa.display(),
                    pb.display(),
                    ids[i].display()
                )));
            }
        }
    }
    Ok(())
}

/// The file `path` names: canonical if it exists, else its longest existing prefix made
/// canonical, followed by the rest of the path (`.` and `..` taken lexically).
fn identity(path: &Path) -> PathBuf {
    use std::path::Component;
    if let Ok(p) = path.canonicalize() {
        return p;
    }
    let absolute = std::path::absolute(path).unwrap_or_else(|_| path.to_owned());
    let components: Vec<Component> = absolute.components().collect();
    for known in (1..components.len()).rev() {
        let prefix: PathBuf = components[..known].iter().collect();
        if let Ok(mut id) = prefix.canonicalize() {
            for c in &components[known..] {
                match c {
                    Component::ParentDir => {
                        id.pop();
                    }
                    Component::Normal(name) => id.push(name),
                    _ => {}
                }
            }
            return id;
        }
    }
    absolute
}

/// Runs the scene, writing the trajectory for `output` (complete, not yet in place);
/// returns it and the run's summary and outcome (its status and its Poincaré sections).
fn simulate_to(
    scenario: &Scenario,
    output: &Path,
    interrupt: &Interrupt,
) -> Result<(atomic::Prepared, Finished), CliError> {
    let mut writer = TrajectoryWriter::for_scenario(output, scenario)?;
    let mut progress = Progress::new(scenario.scene.t_end);
    let cancel = Some(std::sync::Arc::clone(&interrupt.any));
    let finished = ellipsoid_io::run::run(
        scenario,
        Some(output.display().to_string()),
        env!("CARGO_PKG_VERSION"),
        cancel,
        |s| {
            progress.update(s.t);
            writer.write(s)
        },
    );
    progress.finish();
    // Errors of the physics layer are input errors found late (e.g. N ≤ 0 at t = 0):
    // they are placed in the scenario file. The unfinished output is dropped, so deleted.
    let finished = finished.map_err(|f| match f {
        Failure::Scenario(e) => CliError::from(*e),
        Failure::Sink(e) => CliError::from(e),
    })?;
    // Stopped by a signal: no need to finish writing the file.
    stop_if_interrupted(interrupt, scenario, Some(&finished.summary))?;
    let trajectory = writer.prepare(&Metadata {
        scenario_text: &scenario.text,
        summary: &finished.summary,
    })?;
    Ok((trajectory, finished))
}

/// Creates the parent directories of `path`, recording the ones it made.
fn make_parent(path: &Path, made: &mut Vec<PathBuf>) -> Result<(), CliError> {
    let Some(parent) = path.parent().filter(|p| !p.as_os_str().is_empty()) else {
        return Ok(());
    };
    let mut missing: Vec<&Path> = parent
        .ancestors()
        .filter(|a| !a.as_os_str().is_empty() && !a.exists())
        .collect();
    missing.reverse();
    for dir in missing {
        std::fs::create_dir(dir).map_err(|e| OutputError::Io {
            path: dir.to_owned(),
            source: e,
        })?;
        made.push(dir.to_owned());
    }
    Ok(())
}

/// A few lines on standard error: how the run ended, where the output is, the
/// observables' crossings (`observe`: the scene's), the drifts. `finished`: the run ended
/// where the scene asked (t_end or a terminal observable).
fn report(summary: &Summary, observe: &[Observe], output: &Path, finished: bool) {
    let t = summary.final_sample.t;
    let s = &summary.stats;
    let work = format!(
        "{} samples, {} steps ({} rejected), {:.3} s",
        summary.samples, s.accepted, s.rejected, summary.wall_time_s
    );
    let mut lines = Vec::new();
    let status = summary.status.name();
    if summary.status.completed() {
        lines.push(format!(
            "ellipsoid: completed at t = {t} s: {work} -> {}",
            output.display()
        ));
    } else if finished {
        lines.push(format!(
            "ellipsoid: ended ({status}): {} [{work} -> {}]",
            summary.message,
            output.display()
        ));
    } else {
        lines.push(format!(
            "ellipsoid: stopped early ({status}): {} [{work} -> {}]",
            summary.message,
            output.display()
        ));
    }
    if let Some(line) = crossings(summary, observe) {
        lines.push(line);
    }
    let drifts: Vec<String> = summary
        .drift
        .iter()
        .filter_map(|(which, d)| {
            d.filter(|d| d.is_finite())
                .map(|d| format!("{} {d:.2e}", which.name()))
        })
        .collect();
    if !drifts.is_empty() {
        lines.push(format!("ellipsoid: relative drift: {}", drifts.join(", ")));
    }
    for w in &summary.warnings {
        lines.push(format!("ellipsoid: warning: {w}"));
    }
    let failed = summary.failed_checks();
    if !failed.is_empty() {
        lines.push(format!(
            "ellipsoid: warning: the scenario's [check] expectations were not met: {}",
            failed.join("; ")
        ));
    }
    eprintln!("{}", lines.join("\n"));
}

/// `ellipsoid: observed: inverted at t = 0.9779 s; tilt 3 times, t = 0.1 s to 2.5 s`: each
/// observable that crossed its value, with the times; None when none did.
fn crossings(summary: &Summary, observe: &[Observe]) -> Option<String> {
    let parts: Vec<String> = observe
        .iter()
        .enumerate()
        .filter_map(|(k, o)| {
            let times: Vec<f64> = summary
                .events
                .iter()
                .filter(|e| matches!(e.kind, EventKind::Observed { index, .. } if index == k))
                .map(|e| e.t)
                .collect();
            match times.as_slice() {
                [] => None,
                [t] => Some(format!("{} at t = {} s", o.name, number(*t))),
                [first, .., last] => Some(format!(
                    "{} {} times, t = {} s to {} s",
                    o.name,
                    times.len(),
                    number(*first),
                    number(*last)
                )),
            }
        })
        .collect();
    (!parts.is_empty()).then(|| format!("ellipsoid: observed: {}", parts.join("; ")))
}
