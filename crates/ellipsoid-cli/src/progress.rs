//! A progress bar on standard error, for runs that last more than a second and only
//! when standard error is a terminal (never in pipes, logs or tests).
//!
//! One line, redrawn at most every [`REFRESH`] and only when its text changes:
//! `00:00:05 [=========>          ] t = 361.2 s of 1500 s, 24% (eta 00:00:16)`.
//! Elapsed is wall time since the run started (not since the bar appeared); the ETA
//! assumes the remaining simulated time costs what the elapsed part did per simulated
//! second. The clock is a parameter, so both are tested with a fake one.

use std::io::{IsTerminal, Write};
use std::time::{Duration, Instant};

/// Runs shorter than this show no bar.
const DELAY: Duration = Duration::from_secs(1);
/// Shortest time between two frames.
const REFRESH: Duration = Duration::from_millis(100);
/// Characters of the bar itself.
const WIDTH: usize = 30;
/// Clears the terminal line and returns to its start.
const CLEAR: &str = "\r\x1b[2K";

/// Wall time since the run started.
pub trait Clock {
    fn elapsed(&self) -> Duration;
}

/// The real clock, started when the run starts.
pub struct Wall(Instant);

impl Clock for Wall {
    fn elapsed(&self) -> Duration {
        self.0.elapsed()
    }
}

pub struct Progress<C: Clock = Wall, W: Write = std::io::Stderr> {
    enabled: bool,
    clock: C,
    out: W,
    t_end: f64,
    /// When the last frame was drawn, and its text.
    last: Option<(Duration, String)>,
}

impl Progress {
    pub fn new(t_end: f64) -> Self {
        Progress::with(
            std::io::stderr().is_terminal(),
            Wall(Instant::now()),
            std::io::stderr(),
            t_end,
        )
    }
}

impl<C: Clock, W: Write> Progress<C, W> {
    pub fn with(enabled: bool, clock: C, out: W, t_end: f64) -> Self {
        Progress {
            enabled,
            clock,
            out,
            t_end,
            last: None,
        }
    }

    /// Reports that simulated time has reached `t` \[s\].
    pub fn update(&mut self, t: f64) {
        if !self.enabled {
            return;
        }
        let now = self.clock.elapsed();
        if now < DELAY
            || self
                .last
                .as_ref()
                .is_some_and(|(at, _)| now < *at + REFRESH)
        {
            return;
        }
        let line = frame(now, t, self.t_end);
        if self.last.as_ref().is_some_and(|(_, text)| *text == line) {
            return;
        }
        // One write per frame.
        let _ = write!(self.out, "{CLEAR}{line}");
        let _ = self.out.flush();
        self.last = Some((now, line));
    }

    /// Removes the bar.
    pub fn finish(&mut self) {
        if self.last.take().is_some() {
            let _ = write!(self.out, "{CLEAR}");
            let _ = self.out.flush();
        }
    }
}

/// The bar's text after `elapsed` wall time, at simulated `t` of `t_end`.
pub fn frame(elapsed: Duration, t: f64, t_end: f64) -> String {
    let f = if t_end > 0.0 && t.is_finite() {
        (t / t_end).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let bar = bar(f);
    let eta = if f > 0.0 {
        clock(elapsed.as_secs_f64() * (1.0 - f) / f)
    } else {
        "--:--:--".to_owned()
    };
    format!(
        "{} [{bar}] t = {t:.1} s of {t_end} s, {:.0}% (eta {eta})",
        clock(elapsed.as_secs_f64()),
        (f * 100.0).floor()
    )
}

/// The bar `=====>     ` for the done fraction `f` ∈ [0, 1], WIDTH characters.
pub(crate) fn bar(f: f64) -> String {
    let filled = (f * WIDTH as f64).floor() as usize;
    (0..WIDTH)
        .map(|i| match i.cmp(&filled) {
            std::cmp::Ordering::Less => '=',
            std::cmp::Ordering::Equal => '>',
            std::cmp::Ordering::Greater => ' ',
        })
        .collect()
}

/// Seconds as hh:mm:ss (rounded to the nearest second).
pub(crate) fn clock(s: f64) -> String {
    let s = s.round().min(359_999.0) as u64;
    format!("{:02}:{:02}:{:02}", s / 3600, s / 60 % 60, s % 60)
}

#[cfg(test)]
mod tests {
    use std::cell::Cell;
    use std::rc::Rc;

    use super::*;

    #[derive(Clone, Default)]
    struct Fake(Rc<Cell<Duration>>);

    impl Clock for Fake {
        fn elapsed(&self) -> Duration {
            self.0.get()
        }
    }

    impl Fake {
        fn set(&self, secs: f64) {
            self.0.set(Duration::from_secs_f64(secs));
        }
    }

    fn frames(out: &[u8]) -> Vec<String> {
        String::from_utf8(out.to_vec())
            .unwrap()
            .split(CLEAR)
            .filter(|f| !f.is_empty())
            .map(str::to_owned)
            .collect()
    }

    #[test]
    fn elapsed_counts_from_the_run_start_and_eta_from_the_rate_so_far() {
        // The rattleback trial: the bar first appears at simulated 361 s of 1500 s.
        let clock = Fake::default();
        let mut out = Vec::new();
        let mut p = Progress::with(true, clock.clone(), &mut out, 1500.0);
        clock.set(0.5);
        p.update(100.0); // before DELAY: nothing
        clock.set(2.0);
        p.update(361.0);
        clock.set(65.0);
        p.update(750.0);
        p.finish();
        let f = frames(&out);
        assert_eq!(f.len(), 2, "{f:?}");
        // 2 s for 361 s simulated: 1139 s left take 6.3 s.
        assert!(f[0].starts_with("00:00:02 ["), "{}", f[0]);
        assert!(
            f[0].ends_with("t = 361.0 s of 1500 s, 24% (eta 00:00:06)"),
            "{}",
            f[0]
        );
        // 65 s for half the run: 65 s left.
        assert!(f[1].starts_with("00:01:05 [===============>"), "{}", f[1]);
        assert!(f[1].ends_with("50% (eta 00:01:05)"), "{}", f[1]);
    }

    #[test]
    fn each_frame_is_drawn_once_and_not_more_often_than_the_refresh() {
        let clock = Fake::default();
        let mut out = Vec::new();
        let mut p = Progress::with(true, clock.clone(), &mut out, 10.0);
        clock.set(1.5);
        p.update(1.0);
        p.update(1.0); // same instant: not drawn again
        clock.set(1.55);
        p.update(2.0); // within REFRESH
        clock.set(1.7);
        p.update(2.0);
        p.finish();
        let text = String::from_utf8(out).unwrap();
        assert_eq!(
            text.matches(CLEAR).count(),
            3,
            "two frames and the final clear: {text:?}"
        );
        assert_eq!(frames(text.as_bytes()).len(), 2);
    }

    #[test]
    fn a_disabled_bar_writes_nothing() {
        let clock = Fake::default();
        let mut out = Vec::new();
        let mut p = Progress::with(false, clock.clone(), &mut out, 10.0);
        clock.set(5.0);
        p.update(5.0);
        p.finish();
        assert!(out.is_empty());
    }

    #[test]
    fn eta_is_unknown_before_any_progress() {
        assert!(frame(Duration::from_secs(3), 0.0, 10.0).ends_with("0% (eta --:--:--)"));
        assert!(frame(Duration::from_secs(3), 10.0, 10.0).ends_with("100% (eta 00:00:00)"));
    }
}
