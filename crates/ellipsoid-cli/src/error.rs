//! Errors of the command-line tool, each mapped to an exit status.

use ellipsoid_core::scenario::ScenarioError;
use ellipsoid_io::OutputError;

#[derive(Debug, thiserror::Error)]
pub enum CliError {
    /// The scenario is unreadable or invalid (exit 2).
    #[error(transparent)]
    Scenario(Box<ScenarioError>),
    /// The trajectory or summary could not be written (exit 1; exit 2 for an output
    /// format this build cannot write).
    #[error(transparent)]
    Output(#[from] OutputError),
}

impl CliError {
    /// The process exit status for this error.
    pub fn exit_code(&self) -> u8 {
        match self {
            CliError::Scenario(_) => 2,
            CliError::Output(OutputError::UnknownFormat { .. } | OutputError::Hdf5Unavailable { .. }) => 2,
            CliError::Output(_) => 1,
        }
    }
}

impl From<ScenarioError> for CliError {
    fn from(e: ScenarioError) -> Self {
        CliError::Scenario(Box::new(e))
    }
}
