//! Classical RK4 with a fixed step and its 3rd-order continuous extension.

use nalgebra::SVector;

use super::stepper::{Stepper, Trial, all_finite, combine, stage_input};
use super::stiffness::StiffnessParams;
use super::tableau::{RK4, rk4_dense_weights};
use super::{OdeSystem, Options, Stats};

pub(crate) struct Rk4<const N: usize> {
    /// The fixed step \[s\].
    h_fixed: f64,
    t0: f64,
    h: f64,
    y0: SVector<f64, N>,
    k: [SVector<f64, N>; 4],
    y1: SVector<f64, N>,
}

impl<const N: usize> Rk4<N> {
    pub(crate) fn new(h: f64) -> Self {
        let z = SVector::zeros();
        Rk4 {
            h_fixed: h,
            t0: 0.0,
            h: 0.0,
            y0: z,
            k: [z; 4],
            y1: z,
        }
    }
}

/// One classical RK4 step of size `h` (negative steps go back in time) from (t, y),
/// leaving its stages in `k`.
pub(crate) fn step<S: OdeSystem<N>, const N: usize>(
    system: &S,
    t: f64,
    y: &SVector<f64, N>,
    h: f64,
    k: &mut [SVector<f64, N>; 4],
) -> SVector<f64, N> {
    k[0] = system.rhs(t, y);
    for i in 1..4 {
        let yi = stage_input(y, h, &RK4.a[i], k, i);
        k[i] = system.rhs(t + RK4.c[i] * h, &yi);
    }
    y + combine(&RK4.b, k) * h
}

/// RK4's last-step stretch: it only absorbs the round-off of t0 + n·h; the last step is
/// otherwise never longer. A run of length T takes ⌈T/h − (RK4_LAST_STRETCH − 1)⌉ steps.
pub(crate) const RK4_LAST_STRETCH: f64 = 1.0 + 1.0e-9;

impl<const N: usize> Stepper<N> for Rk4<N> {
    const CONTROL: Option<super::controller::ControlParams> = None;
    const STIFFNESS: Option<StiffnessParams> = None;
    const LAST_STRETCH: f64 = RK4_LAST_STRETCH;

    fn start<S: OdeSystem<N>>(
        &mut self,
        _system: &S,
        _t0: f64,
        _y0: &SVector<f64, N>,
        h_max: f64,
        _options: &Options<N>,
        _stats: &mut Stats,
    ) -> Option<f64> {
        Some(self.h_fixed.min(h_max))
    }

    fn attempt<S: OdeSystem<N>>(
        &mut self,
        system: &S,
        t: f64,
        y: &SVector<f64, N>,
        h: f64,
        _options: &Options<N>,
        stats: &mut Stats,
    ) -> Trial {
        self.t0 = t;
        self.h = h;
        self.y0 = *y;
        self.y1 = step(system, t, y, h, &mut self.k);
        stats.rhs_evals += 4;
        if all_finite(&self.y1) {
            Trial::Done { err: 0.0 }
        } else {
            Trial::NonFinite
        }
    }

    fn candidate(&self) -> &SVector<f64, N> {
        &self.y1
    }

    fn accept<S: OdeSystem<N>>(
        &mut self,
        _system: &S,
        _t_new: f64,
        _y_new: &SVector<f64, N>,
        _stats: &mut Stats,
    ) {
    }

    fn stiffness_estimate(&self) -> Option<f64> {
        None
    }

    fn prepare_dense<S: OdeSystem<N>>(&mut self, _system: &S, _stats: &mut Stats) {}

    fn dense(&self, t: f64) -> SVector<f64, N> {
        let theta = (t - self.t0) / self.h;
        self.y0 + combine(&rk4_dense_weights(theta), &self.k) * self.h
    }
}
