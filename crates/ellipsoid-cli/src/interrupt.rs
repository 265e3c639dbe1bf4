//! Ctrl-C (SIGINT) and SIGTERM during `ellipsoid run`: the first one sets a flag that the
//! integrator reads before every step, so the run stops at its next step; the command
//! then drops its temporary files (deleting them), removes the directories it made, leaves
//! existing outputs untouched, says so on standard error and exits 128 + the signal's
//! number (130 for SIGINT, 143 for SIGTERM). A second signal of the same kind ends the
//! process at once, by the signal's default action (its temporaries are then removed by
//! the next run writing to the same directory, see `ellipsoid_io::atomic`).

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use signal_hook::consts::{SIGINT, SIGTERM};

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
}
