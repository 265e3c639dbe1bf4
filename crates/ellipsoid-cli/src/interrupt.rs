//! Ctrl-C (SIGINT) and SIGTERM during `ellipsoid run`, `study`, `steady --vary` and
//! `animate`: the first one sets a flag that the work reads as it goes (the integrator
//! before every step, a sweep before each value, an animation before each frame), so it
//! stops within a step; the command then drops its temporary files (deleting them),
//! removes the directories it made, leaves existing outputs untouched, says so on
//! standard error and exits 128 + the signal's number (130 for SIGINT, 143 for SIGTERM).
//! A second signal of the same kind ends the process at once, by the signal's default
//! action (its temporaries are then removed by the next run writing to the same
//! directory, see `ellipsoid_io::atomic`).

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use signal_hook::consts::{SIGINT, SIGTERM};

#[cfg(any(feature = "study", feature = "animate"))]
use crate::error::CliError;

/// The signals a run stops on, with their names.
const SIGNALS: [(i32, &str); 2] = [(SIGINT, "SIGINT"), (SIGTERM, "SIGTERM")];

pub struct Interrupt {
    /// Set by either signal: the run's cancel flag.
    pub any: Arc<AtomicBool>,
    /// One flag per signal of [`SIGNALS`], to tell which one came.
    each: Vec<Arc<AtomicBool>>,
}

impl Interrupt {
    /// Installs the handlers. If the platform refuses, the signals keep their default
    /// action (the process dies, as before), which the temporaries' names make harmless.
    pub fn install() -> Self {
        let any = Arc::new(AtomicBool::new(false));
        let mut each = Vec::new();
        for (sig, _) in SIGNALS {
            let flag = Arc::new(AtomicBool::new(false));
            // Registered first, so it sees the flag before this signal sets it: only a
            // second signal takes the default action.
            let _ = signal_hook::flag::register_conditional_default(sig, Arc::clone(&flag));
            let _ = signal_hook::flag::register(sig, Arc::clone(&flag));
            let _ = signal_hook::flag::register(sig, Arc::clone(&any));
            each.push(flag);
        }
        Interrupt { any, each }
    }

    /// The signal that came (number and name), if one did.
    pub fn received(&self) -> Option<(i32, &'static str)> {
        if !self.any.load(Ordering::SeqCst) {
            return None;
        }
        SIGNALS
            .iter()
            .zip(&self.each)
            .find(|(_, f)| f.load(Ordering::SeqCst))
            .map(|(s, _)| *s)
            .or(Some(SIGNALS[0]))
    }

    /// `Err(Interrupted)` if a signal came: `what` (e.g. "the sweep") was stopped and
    /// nothing written. (`run` says more: where the run stopped.)
    #[cfg(any(feature = "study", feature = "animate"))]
    pub fn check(&self, what: &str) -> Result<(), CliError> {
        match self.received() {
            None => Ok(()),
            Some((signal, name)) => Err(CliError::Interrupted {
                signal,
                message: format!(
                    "interrupted by {name}: {what} was stopped and nothing was written (existing output files are untouched)"
                ),
            }),
        }
    }
}
