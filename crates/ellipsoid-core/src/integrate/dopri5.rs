//! Dormand–Prince 5(4) as in Hairer's `dopri5.f`: FSAL, 4th-order error estimate, and
//! the 4th-order continuous extension with coefficients d1..d7.

use nalgebra::SVector;

use super::controller::{ControlParams, DOPRI5_CONTROL, rms_error};
use super::stepper::{Stepper, Trial, all_finite, combine, first_stage, stage_input};
use super::stiffness::{DOPRI5_STIFFNESS, StiffnessParams};
use super::tableau::{DOPRI5, DOPRI5_D, DOPRI5_E};
use super::{OdeSystem, Options, Stats};

pub(crate) struct Dopri5<const N: usize> {
    /// f at the start of the next attempt (FSAL: stage 7 of the last accepted step).
    f_next: SVector<f64, N>,
    t0: f64,
    h: f64,
    y0: SVector<f64, N>,
    /// Stages of the last attempt; k[0] = f(t0, y0), k[6] = f(t0 + h, y1).
    k: [SVector<f64, N>; 7],
    /// Input of stage 6 (YSTI), for the stiffness test.
    y_stiff: SVector<f64, N>,
    /// Candidate y1 (input of stage 7).
    y1: SVector<f64, N>,
    /// Accepted (projected) end state.
    y_new: SVector<f64, N>,
    /// Interpolation coefficients RCONT1..5.
    cont: [SVector<f64, N>; 5],
}

impl<const N: usize> Dopri5<N> {
    pub(crate) fn new() -> Self {
        let z = SVector::zeros();
        Dopri5 {
            f_next: z,
            t0: 0.0,
            h: 0.0,
            y0: z,
            k: [z; 7],
            y_stiff: z,
            y1: z,
            y_new: z,
            cont: [z; 5],
        }
    }
}

impl<const N: usize> Stepper<N> for Dopri5<N> {
    const CONTROL: Option<ControlParams> = Some(DOPRI5_CONTROL);
    const STIFFNESS: Option<StiffnessParams> = Some(DOPRI5_STIFFNESS);
    const LAST_STRETCH: f64 = 1.01;

    fn start<S: OdeSystem<N>>(
        &mut self,
        system: &S,
        t0: f64,
        y0: &SVector<f64, N>,
        h_max: f64,
        options: &Options<N>,
        stats: &mut Stats,
    ) -> Option<f64> {
        let (f0, h) = first_stage(system, t0, y0, 5, h_max, options, stats)?;
        self.f_next = f0;
        Some(h)
    }

    fn attempt<S: OdeSystem<N>>(
        &mut self,
        system: &S,
        t: f64,
        y: &SVector<f64, N>,
        h: f64,
        options: &Options<N>,
        stats: &mut Stats,
    ) -> Trial {
        self.t0 = t;
        self.h = h;
        self.y0 = *y;
        self.k[0] = self.f_next;
        for i in 1..7 {
            let yi = stage_input(y, h, &DOPRI5.a[i], &self.k, i);
            self.k[i] = system.rhs(t + DOPRI5.c[i] * h, &yi);
            match i {
                5 => self.y_stiff = yi,
                6 => self.y1 = yi,
                _ => {}
            }
        }
        stats.rhs_evals += 6;
        let e = combine(&DOPRI5_E, &self.k) * h;
        let err = rms_error(&e, y, &self.y1, options);
        if err.is_finite() && all_finite(&self.y1) {
            Trial::Done { err }
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
        y_new: &SVector<f64, N>,
        _stats: &mut Stats,
    ) {
        // Stage 7 was evaluated at the unprojected y1; a projection moves y by about the
        // local error, so reusing it costs O(h·L·δ), below the error being controlled.
        self.f_next = self.k[6];
        self.y_new = *y_new;
    }

    fn stiffness_estimate(&self) -> Option<f64> {
        let num = (self.k[6] - self.k[5]).norm_squared();
        let den = (self.y1 - self.y_stiff).norm_squared();
        (den > 0.0).then(|| self.h * (num / den).sqrt())
    }

    fn prepare_dense<S: OdeSystem<N>>(&mut self, _system: &S, _stats: &mut Stats) {
        let h = self.h;
        let ydiff = self.y_new - self.y0;
        let bspl = self.k[0] * h - ydiff;
        self.cont = [
            self.y0,
            ydiff,
            bspl,
            ydiff - self.k[6] * h - bspl,
            combine(&DOPRI5_D, &self.k) * h,
        ];
    }

    fn dense(&self, t: f64) -> SVector<f64, N> {
        let theta = (t - self.t0) / self.h;
        let s1 = 1.0 - theta;
        let [c0, c1, c2, c3, c4] = &self.cont;
        c0 + (c1 + (c2 + (c3 + c4 * s1) * theta) * s1) * theta
    }
}
