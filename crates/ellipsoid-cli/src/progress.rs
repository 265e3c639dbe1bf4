//! A progress bar on standard error, for runs that last more than a second and only
//! when standard error is a terminal (never in pipes, logs or tests).

use std::io::IsTerminal;
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// Runs shorter than this show no bar.
const DELAY: Duration = Duration::from_secs(1);
/// Resolution of the bar (positions per run).
const STEPS: u64 = 1000;

pub struct Progress {
    enabled: bool,
    start: Instant,
    t_end: f64,
    bar: Option<ProgressBar>,
    position: u64,
}

impl Progress {
    pub fn new(t_end: f64) -> Self {
        Progress {
            enabled: std::io::stderr().is_terminal(),
            start: Instant::now(),
            t_end,
            bar: None,
            position: 0,
        }
    }

    /// Reports that simulated time has reached `t` \[s\].
    pub fn update(&mut self, t: f64) {
        if !self.enabled {
            return;
        }
        let position = ((t / self.t_end).clamp(0.0, 1.0) * STEPS as f64) as u64;
        if position == self.position && self.bar.is_some() {
            return;
        }
        self.position = position;
        if self.bar.is_none() {
            if self.start.elapsed() < DELAY {
                return;
            }
            let bar = ProgressBar::with_draw_target(Some(STEPS), ProgressDrawTarget::stderr());
            let style =
                ProgressStyle::with_template("{elapsed_precise} [{wide_bar}] {msg} (eta {eta})")
                    .unwrap_or_else(|_| ProgressStyle::default_bar());
            bar.set_style(style.progress_chars("=> "));
            self.bar = Some(bar);
        }
        if let Some(bar) = &self.bar {
            bar.set_position(position);
            bar.set_message(format!("t = {t:.4} s of {} s", self.t_end));
        }
    }

    /// Removes the bar.
    pub fn finish(&mut self) {
        if let Some(bar) = self.bar.take() {
            bar.finish_and_clear();
        }
    }
}
