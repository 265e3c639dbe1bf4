//! Errors of the command-line tool, each mapped to an exit status.

use ellipsoid_core::scenario::{ScenarioError, ScenarioErrors};
use ellipsoid_io::OutputError;

#[derive(Debug, thiserror::Error)]
pub enum CliError {
    /// The scenario is unreadable or invalid (exit 2): every independent error, one line each.
    #[error(transparent)]
    Scenario(Box<ScenarioErrors>),
    /// The trajectory or summary could not be written (exit 1; exit 2 for an output
    /// format this build cannot write).
    #[error(transparent)]
    Output(#[from] OutputError),
    /// A plot could not be drawn (exit 1).
    #[cfg(any(feature = "figures", feature = "study"))]
    #[error("cannot draw the plot: {0}")]
    Plot(String),
    /// A bad command-line value (exit 2).
    #[error("{0}")]
    Usage(String),
    /// `precision` found no trustworthy reference (exit 3).
    #[cfg(feature = "study")]
    #[error("no reference: {0}")]
    Reference(String),
    /// A command (or option) of a feature this build was compiled without (exit 2).
    #[error(
        "`ellipsoid {command}` needs the `{feature}` feature, which this build was compiled without: {}",
        crate::cli::feature_hint(feature)
    )]
    NoFeature {
        command: &'static str,
        feature: &'static str,
    },
    /// A run stopped by SIGINT or SIGTERM (exit 128 + the signal's number).
    #[error("{message}")]
    Interrupted { signal: i32, message: String },
}

impl CliError {
    /// The process exit status for this error.
    pub fn exit_code(&self) -> u8 {
        match self {
            CliError::Scenario(_) => 2,
            CliError::Output(
                OutputError::UnknownFormat { .. } | OutputError::Hdf5Unavailable { .. },
            ) => 2,
            CliError::Output(_) => 1,
            #[cfg(any(feature = "figures", feature = "study"))]
            CliError::Plot(_) => 1,
            CliError::Usage(_) | CliError::NoFeature { .. } => 2,
            #[cfg(feature = "study")]
            CliError::Reference(_) => 3,
            CliError::Interrupted { signal, .. } => u8::try_from(128 + signal).unwrap_or(130),
        }
    }
}

impl From<ScenarioError> for CliError {
    fn from(e: ScenarioError) -> Self {
        CliError::Scenario(Box::new(e.into()))
    }
}

impl From<ScenarioErrors> for CliError {
    fn from(e: ScenarioErrors) -> Self {
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

    #[test]
    fn a_command_compiled_out_names_its_feature_and_the_build_that_has_it() {
        let e = CliError::NoFeature {
            command: "plot",
            feature: "figures",
        };
        let text = message(&e);
        assert!(
            text.starts_with(
                "`ellipsoid plot` needs the `figures` feature, which this build was compiled without: "
            ),
            "{text}"
        );
        assert!(
            text.contains("`cargo build --release -p ellipsoid-cli`"),
            "{text}"
        );
        assert!(text.contains("`--features figures`"), "{text}");
        assert_eq!(e.exit_code(), 2);
    }
}
