//! Loading a scenario for a command: its errors, and its plausibility warnings
//! (`ellipsoid_core::scenario::plausibility`: likely unit slips) on standard error
//! unless silenced by `--quiet-plausibility`. A warning never stops the command.

use std::path::Path;

use ellipsoid_core::scenario::{self, Scenario, ScenarioErrors};

/// Reads `path` with the `--set` overrides `set`, then prints each plausibility warning
/// on standard error (one line, `file:line:col: warning: key = value: slip`) unless
/// `quiet`.
pub fn load(path: &Path, set: &[String], quiet: bool) -> Result<Scenario, ScenarioErrors> {
    let scenario = scenario::load_all(path, set)?;
    if !quiet {
        for w in scenario::warnings(&scenario) {
            eprintln!("{w}");
        }
    }
    Ok(scenario)
}
