//! Why an integration could not start or could not go on.

/// An integrator error. `InvalidOptions` is returned as `Err` before any step; the
/// others end a run as [`StopReason::Failed`](super::StopReason::Failed), with the last
/// good state kept in the [`Solution`](super::Solution).
#[derive(thiserror::Error, Debug, Clone, PartialEq)]
pub enum IntegrateError {
    /// The inputs cannot be integrated (tolerances, times, initial state, step sizes).
    #[error("invalid integrator input: {reason}")]
    InvalidOptions { reason: String },
    /// The step size fell below what t can resolve (10·EPS·|t|, as in Hairer's codes).
    #[error("step size {h:.3e} s fell below the round-off limit at t = {t} s")]
    StepSizeTooSmall { t: f64, h: f64 },
    /// More than `max_steps` steps (accepted plus rejected) were needed.
    #[error(
        "gave up at t = {t} s after {steps} steps (accepted + rejected); raise max_steps or loosen the tolerances"
    )]
    MaxSteps { t: f64, steps: u64 },
    /// The steps have collapsed: at the pace of the first `steps` steps, reaching t_end
    /// would take `projected` steps, more than [`HOPELESS_FACTOR`](super::HOPELESS_FACTOR)
    /// times max_steps.
    #[error(
        "the steps collapsed: after {steps} steps the integration reached only t = {t} s (last step {h:.1e} s), so t_end would take ~{projected:.0e} steps; \
         the scene's magnitudes are likely beyond what double precision can integrate (check the units and sizes: spins, coefficients, semi-axes, g)"
    )]
    Collapsed {
        t: f64,
        h: f64,
        steps: u64,
        projected: f64,
    },
    /// The right-hand side kept returning NaN or infinity although the step was reduced.
    #[error(
        "the right-hand side returned a non-finite value (NaN or infinity) just after t = {t} s, and reducing the step did not help"
    )]
    NonFinite { t: f64 },
}

impl IntegrateError {
    pub(crate) fn invalid(reason: impl Into<String>) -> Self {
        IntegrateError::InvalidOptions {
            reason: reason.into(),
        }
    }
}
