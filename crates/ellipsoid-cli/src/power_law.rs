//! `ellipsoid power-law`: simulate a scenario and fit the power law of one output column
//! over a window of t0 − t (`ellipsoid_study::power_law`, which Python's
//! `Trajectory.power_law` calls too); print it as JSON.

use std::ops::ControlFlow;
use std::process::ExitCode;

use ellipsoid_io::columns::Layout;
use ellipsoid_study::power_law::{self, T0};

use crate::cli::PowerLawArgs;
use crate::error::CliError;

/// Exit status of a run that stopped before t_end (as `ellipsoid run`'s).
const EARLY_STOP: u8 = 3;

pub fn power_law(args: &PowerLawArgs) -> Result<ExitCode, CliError> {
    let scenario = crate::plausible::load(&args.scenario, &args.set, args.quiet_plausibility)?;
    let layout = Layout::of(&scenario.scene.body);
    let k = layout.index(&args.column).ok_or_else(|| {
        CliError::Usage(format!(
            "--column {}: not a numeric output column of this scenario; the columns are {}",
            args.column,
            layout.names().join(", ")
        ))
    })?;
    let (lo, hi) = pair("--window", &args.window)?;
    let given = args.t0.as_deref().map(|text| {
        text.parse::<f64>()
            .map(T0::Given)
            .or_else(|_| pair("--t0", text).map(|(a, b)| T0::Fitted(a, b)))
    });
    let given = given.transpose()?;
    let (mut t, mut y) = (Vec::new(), Vec::new());
    let outcome = ellipsoid_core::simulate::simulate(&scenario.scene, &mut |s| {
        t.push(s.t);
        y.push(layout.value(s, k));
        ControlFlow::Continue(())
    })
    .map_err(|e| CliError::from(scenario.locate(&e)))?;
    if !outcome.status.finished() {
        eprintln!(
            "error: the run stopped early at t = {} s ({}): nothing fitted",
            outcome.final_sample.t,
            outcome.status.name()
        );
        return Ok(ExitCode::from(EARLY_STOP));
    }
    let t0 = given.unwrap_or(T0::Landing(power_law::landing(&outcome.events)));
    let fitted = power_law::fit(&args.column, &t, &y, (lo, hi), t0).map_err(CliError::Usage)?;
    let json = serde_json::to_string_pretty(&fitted).expect("a fit serialises");
    println!("{json}");
    Ok(ExitCode::SUCCESS)
}

/// `LO,HI` as two numbers.
fn pair(option: &str, text: &str) -> Result<(f64, f64), CliError> {
    let parsed = text
        .split_once(',')
        .and_then(|(a, b)| Some((a.trim().parse().ok()?, b.trim().parse().ok()?)));
    parsed
        .ok_or_else(|| CliError::Usage(format!("{option} {text}: expected two numbers LO,HI (s)")))
}
