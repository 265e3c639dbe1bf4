//! `ellipsoid precision`: a thin front over the work–precision study of
//! `ellipsoid_study::precision` (grid, reference, error measures, CSV and plots are
//! documented there): loads the scenario, runs the study with progress on standard
//! error, writes the three files and prints the table.

use std::path::Path;
use std::process::ExitCode;

use ellipsoid_study::precision::{self, Hooks, Spelling, StudyError, StudyOptions, WriteError};

use crate::cli::PrecisionArgs;
use crate::error::CliError;

pub fn precision(args: &PrecisionArgs) -> Result<ExitCode, CliError> {
    let scenario = crate::plausible::load(&args.scenario, &args.set, args.quiet_plausibility)?;
    let dir = args
        .output
        .clone()
        .unwrap_or_else(|| Path::new("out").join("precision").join(scenario.stem()));
    let progress = |s: &str| {
        if !args.quiet {
            eprintln!("{s}");
        }
    };
    let hooks = Hooks {
        progress: &progress,
        note: &|s| eprintln!("{s}"),
        cancel: None,
    };
    let options = StudyOptions {
        t_end: args.t_end,
        quick: args.quick,
        repeats: args.repeats,
    };
    let report =
        precision::measure(&scenario, &options, &Spelling::CLI, &hooks).map_err(study_error)?;
    let files = precision::write(&report, &dir).map_err(|e| match e {
        WriteError::Output(e) => CliError::Output(e),
        WriteError::Plot(e) => CliError::Plot(e),
    })?;
    print!("{}", precision::summary(&report));
    println!(
        "wrote {}",
        files
            .iter()
            .map(|p| p.display().to_string())
            .collect::<Vec<_>>()
            .join(", ")
    );
    Ok(ExitCode::SUCCESS)
}

fn study_error(e: StudyError) -> CliError {
    match e {
        StudyError::Scenario(e) => CliError::from(*e),
        StudyError::Option { .. } => CliError::Usage(e.to_string()),
        StudyError::Reference { message, .. } => CliError::Reference(message),
        // Nothing sets the flag here (Ctrl-C ends the process).
        StudyError::Cancelled => CliError::Usage(e.to_string()),
    }
}
