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
            CliError::Output(
                OutputError::UnknownFormat { .. } | OutputError::Hdf5Unavailable { .. },
            ) => 2,
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

/// The error's text, followed by each underlying cause that it does not already quote
/// (an I/O error's message already ends with the OS message of its source).
pub fn message(e: &CliError) -> String {
    let mut text = e.to_string();
    let mut cause = std::error::Error::source(e);
    while let Some(c) = cause {
        let more = c.to_string();
        if !text.contains(&more) {
            text.push_str(": ");
            text.push_str(&more);
        }
        cause = c.source();
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_io_error_names_the_os_message_once() {
        let e = CliError::from(OutputError::Io {
            path: "d".into(),
            source: std::io::Error::from_raw_os_error(21),
        });
        let text = message(&e);
        assert_eq!(text.matches("os error 21").count(), 1, "{text}");
        assert!(text.starts_with("d: "), "{text}");
    }
}
