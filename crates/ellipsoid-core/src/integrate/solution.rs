//! What an integration returns: where it ended, why, what it found and what it cost.

use nalgebra::SVector;

use super::IntegrateError;

/// Why the integration ended.
#[derive(Debug, Clone, PartialEq)]
pub enum StopReason {
    /// t_end was reached.
    Reached,
    /// A terminal event (index into the `events` slice) was located.
    Event { index: usize },
    /// The observer returned `ControlFlow::Break` at a sample, or `Options::cancel` was set.
    Cancelled,
    /// The integrator could not go on; `Solution::t`/`y` hold the last good state.
    Failed(IntegrateError),
}

/// A located zero crossing of an event function.
#[derive(Debug, Clone, PartialEq)]
pub struct EventRecord<const N: usize> {
    /// Index into the `events` slice.
    pub index: usize,
    /// Time of the crossing \[s\], on the side where g has already changed sign.
    pub t: f64,
    /// Dense-output state at `t`, passed through `OdeSystem::project`.
    pub y: SVector<f64, N>,
}

/// Work counters.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Stats {
    /// Accepted steps.
    pub accepted: u64,
    /// Rejected steps (error test failed, or a non-finite right-hand side).
    pub rejected: u64,
    /// Calls of `OdeSystem::rhs` (including the initial-step guess and dense stages).
    pub rhs_evals: u64,
    /// Located events.
    pub events: u64,
    /// Smallest accepted step \[s\] (∞ before the first), shortened last steps excluded.
    pub min_step: f64,
}

impl Default for Stats {
    fn default() -> Self {
        Stats {
            accepted: 0,
            rejected: 0,
            rhs_evals: 0,
            events: 0,
            min_step: f64::INFINITY,
        }
    }
}

/// Something the caller should know although the integration went on.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub enum Warning {
    /// Hairer's test found h·ρ at the stability boundary for 15 tested steps in a row:
    /// the problem looks stiff from `t` \[s\] on; an explicit method will crawl.
    Stiff { t: f64 },
}

/// The result of [`integrate`](super::integrate).
#[derive(Debug, Clone, PartialEq)]
pub struct Solution<const N: usize> {
    /// Where integration ended \[s\]: t_end, a terminal event, a cancelling sample, or the
    /// last good point of a failure.
    pub t: f64,
    /// State at `t`.
    pub y: SVector<f64, N>,
    pub stop: StopReason,
    /// Every located event, in time order.
    pub events: Vec<EventRecord<N>>,
    pub stats: Stats,
    pub warnings: Vec<Warning>,
}
