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
    /// A plot could not be drawn (exit 1).
    #[error("cannot draw the plot: {0}")]
    Plot(String),
    /// A bad command-line value (exit 2).
    #[error("{0}")]
    Usage(String),
    /// `precision` found no trustworthy reference (exit 3).
    #[error("no reference: {0}")]
    Reference(String),
}

impl CliError {
    /// The process exit status for this error.
    pub fn exit_code(&self) -> u8 {
        match self {
            CliError::Scenario(_) => 2,
            CliError::Output(OutputError::UnknownFormat { .. } | OutputError::Hdf5Unavailable { .. }) => 2,
            CliError::Output(_) | CliError::Plot(_) => 1,
            CliError::Usage(_) => 2,
            CliError::Reference(_) => 3,
        }
    }
}

impl From<ScenarioError> for CliError {
    fn from(e: ScenarioError) -> Self {
        CliError::Scenario(Box::new(e))
    }
}
