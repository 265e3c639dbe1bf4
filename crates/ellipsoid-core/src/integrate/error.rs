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
    /// More than `max_steps` steps (accepted plus rejected) were needed. So many steps
    /// mostly mean steps that became short, not a long run (docs/physics.md, "The slip
    /// stop, numerically"): the message names the remedies in that order.
    #[error(
        "gave up at t = {t} s after {steps} steps (accepted + rejected) of method {method}: the steps became too short to reach t_end. \
         {advice}Look for stiffness (a \"looks stiff\" warning) or magnitudes beyond double precision (check the units); \
         raise max_steps only if t was close to t_end",
        method = .method.name(),
        advice = if matches!(.method, super::Method::Dopri5) {
            "On a stick–slip (coulomb) scene this is likely DOPRI5 near zero slip: use method = \"dop853\". "
        } else {
            ""
        }
    )]
    MaxSteps {
        t: f64,
        steps: u64,
        method: super::Method,
    },
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
    /// t_end is out of reach at the motion's own pace: after `steps` steps whose mean is
    /// at least [`MOTION_PACE`](super::MOTION_PACE) of `Options::time_scale`, reaching
    /// t_end would take `projected` steps, more than
    /// [`OVER_BUDGET_FACTOR`](super::OVER_BUDGET_FACTOR) times `max_steps`.
    #[error(
        "t_end is out of reach: after {steps} steps at the pace of the motion itself the integration reached t = {t} s, so t_end would take ~{projected:.1e} steps, \
         over {factor} times max_steps ({max_steps}). If the run is wanted, raise max_steps above that (the run would take ~{ratio:.0}× as long as it has so far) or shorten t_end; \
         otherwise check the units and magnitudes (g, sizes, t_end): t_end spans too many of the motion's periods, whose time scale is √(L/g)",
        factor = super::OVER_BUDGET_FACTOR,
        ratio = .projected / *.steps as f64
    )]
    OverBudget {
        t: f64,
        steps: u64,
        projected: f64,
        max_steps: u64,
    },
    /// The steps follow the system's fastest rate `rate` = ρ (h·ρ ≥
    /// [`FAST_PACE`](super::FAST_PACE), or [`FAST_FRACTION`](super::FAST_FRACTION) of the
    /// h·ρ at which the method resolves a rate to the run's rtol if that is smaller: held
    /// at the stability boundary of a stiff decay
    /// when `stiff`, resolving a fast oscillation or rotation otherwise), and at the pace
    /// `h` of the last steps reaching t_end would take `projected` steps, more than
    /// [`FAST_BUDGET_FACTOR`](super::FAST_BUDGET_FACTOR) times `max_steps`.
    #[error(
        "t_end is out of reach at the pace of the fastest rate in the motion: {cause} (rate ρ ≈ {rate:.1e} 1/s, time scale 1/ρ ≈ {tau:.1e} s, steps of {h:.1e} s); \
         after {steps} steps the integration reached t = {t} s, so t_end would take ~{projected:.1e} steps, more than max_steps ({max_steps}). {remedy}",
        tau = 1.0 / .rate,
        cause = if *.stiff {
            "the problem is stiff, an explicit method's steps are held at the stability boundary of a decay far faster than the motion"
        } else {
            "the steps resolve an oscillation or rotation far faster than the rest of the motion"
        },
        remedy = if *.stiff {
            "Such a decay usually comes from a strong damping of a light or small body (air drag: rates k/m and k_ω/I): lower the damping, make the body heavier, or shorten t_end; raising max_steps above the projection also works, at that cost"
        } else {
            "Such a pace usually comes from a fast spin: if the run is wanted, raise max_steps above the projection or shorten t_end; otherwise check the spin's value and units (rad/s)"
        }
    )]
    FastRate {
        t: f64,
        h: f64,
        rate: f64,
        stiff: bool,
        steps: u64,
        projected: f64,
        max_steps: u64,
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
