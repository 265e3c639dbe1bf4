//! Method choice and tolerances, validated once before any step.

use std::sync::Arc;
use std::sync::atomic::AtomicBool;

use nalgebra::SVector;

use super::IntegrateError;

/// The integration method.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Method {
    /// Classical 4th-order Runge–Kutta with a fixed step `h` \[s\] (the last step is
    /// shortened to land on t_end). No error control: the tolerances are not used.
    Rk4 { h: f64 },
    /// Dormand–Prince 5(4) with Hairer's controller (`dopri5.f`).
    Dopri5,
    /// Dormand–Prince 8(5,3) with Hairer's controller (`dop853.f`).
    Dop853,
}

impl Method {
    /// Every method, its parameters at placeholder values (rk4's step 0), in the order
    /// of [`Method::NAMES`].
    pub const ALL: [Method; 3] = [Method::Rk4 { h: 0.0 }, Method::Dopri5, Method::Dop853];
    /// Their names, as scenario files spell them.
    pub const NAMES: [&'static str; 3] = [
        Method::ALL[0].name(),
        Method::ALL[1].name(),
        Method::ALL[2].name(),
    ];

    /// Short lowercase name, as used in scenario files, tables and file names.
    pub const fn name(&self) -> &'static str {
        match self {
            Method::Rk4 { .. } => "rk4",
            Method::Dopri5 => "dopri5",
            Method::Dop853 => "dop853",
        }
    }
}

/// Tolerances and limits. Build with [`Options::new`] and change fields as needed.
#[derive(Debug, Clone)]
pub struct Options<const N: usize> {
    /// Relative tolerance per component (≥ 10·EPS).
    pub rtol: SVector<f64, N>,
    /// Absolute tolerance per component, in the component's unit (> 0).
    pub atol: SVector<f64, N>,
    /// Initial step \[s\]; `None` = Hairer's automatic guess (`hinit`). Ignored by RK4.
    pub h0: Option<f64>,
    /// Largest step \[s\]; infinity means |t_end − t0|.
    pub h_max: f64,
    /// Limit on accepted + rejected steps.
    pub max_steps: u64,
    /// Hairer's stiffness test (DOPRI5, DOP853), reported as `Warning::Stiff`.
    pub stiffness_check: bool,
    /// A time scale of the motion \[s\] (the simulation gives √(L/g)), if the system
    /// has one: a mean step of at least [`MOTION_PACE`](super::MOTION_PACE) of it is
    /// the motion's own pace, which is trusted to hold, so a run projecting more than
    /// [`OVER_BUDGET_FACTOR`](super::OVER_BUDGET_FACTOR) × `max_steps` at it fails
    /// early (`IntegrateError::OverBudget`). `None` (the default) turns that check off,
    /// and so does an infinite scale.
    pub time_scale: Option<f64>,
    /// Checked before every step attempt: once set (e.g. from another thread on
    /// Ctrl-C), the integration ends with `StopReason::Cancelled` at the last accepted
    /// state.
    pub cancel: Option<Arc<AtomicBool>>,
}

impl<const N: usize> Options<N> {
    /// Scalar tolerances for every component; other fields at their defaults.
    pub fn new(rtol: f64, atol: f64) -> Self {
        Options {
            rtol: SVector::repeat(rtol),
            atol: SVector::repeat(atol),
            h0: None,
            h_max: f64::INFINITY,
            max_steps: 10_000_000,
            stiffness_check: true,
            time_scale: None,
            cancel: None,
        }
    }

    /// Checks tolerances and limits.
    pub fn validate(&self) -> Result<(), IntegrateError> {
        let rtol_min = 10.0 * f64::EPSILON;
        for (i, (&r, &a)) in self.rtol.iter().zip(self.atol.iter()).enumerate() {
            if !r.is_finite() || !a.is_finite() {
                return Err(IntegrateError::invalid(format!(
                    "tolerances must be finite (component {i}: rtol = {r:e}, atol = {a:e})"
                )));
            }
            if r < rtol_min {
                return Err(IntegrateError::invalid(format!(
                    "rtol[{i}] = {r:e} is below 10·EPS = {rtol_min:.1e}: no step can be that accurate in f64"
                )));
            }
            if a <= 0.0 {
                return Err(IntegrateError::invalid(format!(
                    "atol[{i}] = {a:e} must be positive"
                )));
            }
        }
        if let Some(h0) = self.h0
            && !(h0.is_finite() && h0 > 0.0)
        {
            return Err(IntegrateError::invalid(format!(
                "h0 = {h0:e} s must be positive and finite"
            )));
        }
        if self.h_max.is_nan() || self.h_max <= 0.0 {
            return Err(IntegrateError::invalid(format!(
                "h_max = {:e} s must be positive",
                self.h_max
            )));
        }
        if let Some(scale) = self.time_scale
            && !(scale > 0.0)
        {
            return Err(IntegrateError::invalid(format!(
                "time_scale = {scale:e} s must be positive"
            )));
        }
        if self.max_steps == 0 {
            return Err(IntegrateError::invalid("max_steps must be at least 1"));
        }
        Ok(())
    }
}

/// Checks everything `integrate` is given, before any right-hand-side call.
pub(crate) fn validate_inputs<const N: usize>(
    method: Method,
    t0: f64,
    y0: &SVector<f64, N>,
    t_end: f64,
    options: &Options<N>,
    sample_times: &[f64],
) -> Result<(), IntegrateError> {
    options.validate()?;
    if let Method::Rk4 { h } = method
        && !(h.is_finite() && h > 0.0)
    {
        return Err(IntegrateError::invalid(format!(
            "RK4 step h = {h:e} s must be positive and finite"
        )));
    }
    if !t0.is_finite() || !t_end.is_finite() {
        return Err(IntegrateError::invalid(format!(
            "t0 = {t0} s and t_end = {t_end} s must be finite"
        )));
    }
    if t_end < t0 {
        return Err(IntegrateError::invalid(format!(
            "t_end = {t_end} s is before t0 = {t0} s; only forward integration is supported"
        )));
    }
    if let Some(i) = y0.iter().position(|v| !v.is_finite()) {
        return Err(IntegrateError::invalid(format!(
            "y0[{i}] = {} is not finite",
            y0[i]
        )));
    }
    let mut prev = t0;
    for (i, &ts) in sample_times.iter().enumerate() {
        if !(ts >= t0 && ts <= t_end) {
            return Err(IntegrateError::invalid(format!(
                "sample_times[{i}] = {ts} s lies outside [t0, t_end] = [{t0}, {t_end}] s"
            )));
        }
        if ts < prev {
            return Err(IntegrateError::invalid(format!(
                "sample_times must be sorted: sample_times[{i}] = {ts} s comes after {prev} s"
            )));
        }
        prev = ts;
    }
    Ok(())
}
