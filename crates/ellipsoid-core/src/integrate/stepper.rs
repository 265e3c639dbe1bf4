//! The contract between the driver and a Runge–Kutta method: one attempt, acceptance,
//! dense output. Steppers own work buffers only (fixed-size arrays, no allocation).

use nalgebra::SVector;

use super::controller::ControlParams;
use super::stiffness::StiffnessParams;
use super::{OdeSystem, Options, Stats};

/// Outcome of one step attempt.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Trial {
    /// Stages computed; `err` is the scaled error norm (≤ 1 passes; 0 for RK4).
    Done { err: f64 },
    /// A stage, the candidate or its error estimate is NaN or infinite.
    NonFinite,
}

/// One explicit Runge–Kutta method, driven by `driver::Run::go`.
pub(crate) trait Stepper<const N: usize> {
    /// Step-size controller constants; `None` for a fixed step.
    const CONTROL: Option<ControlParams>;
    /// Hairer's stiffness test's constants; `None` if the method has no such test.
    const STIFFNESS: Option<StiffnessParams>;
    /// A last step up to `LAST_STRETCH·h` long is stretched to land on t_end rather than
    /// leaving a sliver (1.01 in `dopri5.f`/`dop853.f`).
    const LAST_STRETCH: f64;

    /// Evaluates what the first step needs at (t0, y0) and returns the first step size,
    /// at most `h_max`; `None` if f(t0, y0) is not finite.
    fn start<S: OdeSystem<N>>(
        &mut self,
        system: &S,
        t0: f64,
        y0: &SVector<f64, N>,
        h_max: f64,
        options: &Options<N>,
        stats: &mut Stats,
    ) -> Option<f64>;

    /// Computes all stages of a step of size `h` from (t, y), the candidate y₁ and its
    /// error norm.
    fn attempt<S: OdeSystem<N>>(
        &mut self,
        system: &S,
        t: f64,
        y: &SVector<f64, N>,
        h: f64,
        options: &Options<N>,
        stats: &mut Stats,
    ) -> Trial;

    /// The candidate y₁ of the last attempt.
    fn candidate(&self) -> &SVector<f64, N>;

    /// The last attempt is accepted; `y_new` is the candidate after
    /// `OdeSystem::project`, at `t_new`.
    fn accept<S: OdeSystem<N>>(
        &mut self,
        system: &S,
        t_new: f64,
        y_new: &SVector<f64, N>,
        stats: &mut Stats,
    );

    /// h·ρ, Hairer's estimate of the step size times the dominant eigenvalue, for the
    /// accepted step; `None` when it cannot be formed.
    fn stiffness_estimate(&self) -> Option<f64>;

    /// Makes `dense` valid on the accepted step (DOP853 computes its three extra stages
    /// here, so only steps that need the interpolant pay for it).
    fn prepare_dense<S: OdeSystem<N>>(&mut self, system: &S, stats: &mut Stats);

    /// The continuous extension at time `t` inside the accepted step.
    fn dense(&self, t: f64) -> SVector<f64, N>;
}

/// `y + h Σ_{j<i} a_j k_j`, the input of stage `i` (zero coefficients skipped; the
/// tables are `const`, so this unrolls). Plain loops over the components, so that they
/// compile to packed arithmetic; the sums run in the same order as nalgebra's `axpy`
/// (bit for bit the same values).
#[inline(always)]
pub(crate) fn stage_input<const N: usize, const S: usize>(
    y: &SVector<f64, N>,
    h: f64,
    a: &[f64; S],
    k: &[SVector<f64, N>; S],
    i: usize,
) -> SVector<f64, N> {
    let mut acc = SVector::<f64, N>::zeros();
    for j in 0..i {
        add_scaled(&mut acc, a[j], &k[j]);
    }
    for (x, y) in acc.as_mut_slice().iter_mut().zip(y.as_slice()) {
        *x = y + h * *x;
    }
    acc
}

/// Σ_j w_j k_j over all stages (zero weights skipped).
#[inline(always)]
pub(crate) fn combine<const N: usize, const S: usize>(
    w: &[f64; S],
    k: &[SVector<f64, N>; S],
) -> SVector<f64, N> {
    let mut acc = SVector::<f64, N>::zeros();
    for j in 0..S {
        add_scaled(&mut acc, w[j], &k[j]);
    }
    acc
}

/// acc += w·k, component by component (nothing for w = 0).
#[inline(always)]
pub(crate) fn add_scaled<const N: usize>(acc: &mut SVector<f64, N>, w: f64, k: &SVector<f64, N>) {
    if w != 0.0 {
        for (x, kx) in acc.as_mut_slice().iter_mut().zip(k.as_slice()) {
            *x += w * kx;
        }
    }
}

/// The first stage f(t0, y0) and the first step of an adaptive method of order `order`:
/// the caller's h0 (at most `h_max`) or Hairer's `hinit`; `None` if f(t0, y0) is not
/// finite.
pub(crate) fn first_stage<S: OdeSystem<N>, const N: usize>(
    system: &S,
    t0: f64,
    y0: &SVector<f64, N>,
    order: i32,
    h_max: f64,
    options: &Options<N>,
    stats: &mut Stats,
) -> Option<(SVector<f64, N>, f64)> {
    let f0 = system.rhs_accepted(t0, y0);
    stats.rhs_evals += 1;
    if !all_finite(&f0) {
        return None;
    }
    let h = match options.h0 {
        Some(h0) => h0.min(h_max),
        None => super::controller::hinit(system, t0, y0, &f0, order, h_max, options, stats),
    };
    Some((f0, h))
}

/// Whether every component is finite.
#[inline]
pub(crate) fn all_finite<const N: usize>(v: &SVector<f64, N>) -> bool {
    v.iter().all(|x| x.is_finite())
}
