//! Dormand–Prince 8(5,3) as in Hairer's `dop853.f`: 12 stages, the combined 5th/3rd-order
//! error estimator, f(t + h, y1) evaluated after acceptance, and the 7th-order continuous
//! extension whose three extra stages are computed only for steps that need it.

use nalgebra::SVector;

use super::controller::{ControlParams, DOP853_CONTROL, scale};
use super::stepper::{Stepper, Trial, add_scaled, all_finite, combine, first_stage, stage_input};
use super::stiffness::{DOP853_STIFFNESS, StiffnessParams};
use super::tableau::{DOP853, DOP853_A_EXTRA, DOP853_BHH, DOP853_C_EXTRA, DOP853_D, DOP853_E5};
use super::{OdeSystem, Options, Stats};

/// Σ_j w_j k_j over the 16 stages of the extended list, `w` a row of a `const` table:
/// written out term by term, so that the weights fold into the code (the zero ones
/// vanish) and the sum can stay in registers. The same terms in the same order as
/// `stepper::combine` (bit for bit the same values).
macro_rules! combine16 {
    ($w:expr, $k:expr) => {{
        let (w, k): (&[f64; 16], &[SVector<f64, N>; 16]) = (&$w, &$k);
        let mut acc = SVector::<f64, N>::zeros();
        combine16!(@terms acc, w, k; 0 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15);
        acc
    }};
    (@terms $acc:ident, $w:ident, $k:ident; $($j:literal)*) => {
        $(add_scaled(&mut $acc, $w[$j], &$k[$j]);)*
    };
}

pub(crate) struct Dop853<const N: usize> {
    /// f(t, y) at the start of the next attempt.
    f_next: SVector<f64, N>,
    t0: f64,
    h: f64,
    y0: SVector<f64, N>,
    /// Stages of the last attempt, k[0] = f(t0, y0); after acceptance, indices 12..15
    /// hold f(t0 + h, y_new) and the three dense-output stages (the extended list of
    /// `dop853.f`).
    k: [SVector<f64, N>; 16],
    /// Input of stage 12, for the stiffness test.
    y_stage12: SVector<f64, N>,
    /// Candidate y1.
    y1: SVector<f64, N>,
    /// Accepted (projected) end state.
    y_new: SVector<f64, N>,
    /// Interpolation coefficients CONT(1..8).
    cont: [SVector<f64, N>; 8],
}

impl<const N: usize> Dop853<N> {
    pub(crate) fn new() -> Self {
        let z = SVector::zeros();
        Dop853 {
            f_next: z,
            t0: 0.0,
            h: 0.0,
            y0: z,
            k: [z; 16],
            y_stage12: z,
            y1: z,
            y_new: z,
            cont: [z; 8],
        }
    }

    /// Dense-output stage 14 + R (`k[13 + R]`) of the accepted step: a `const` index, so
    /// that the coupling row's zeros fold away. Its columns from 13 + R on are zero, so
    /// the sum over all 16 stages is the stage input over the stages before it.
    #[inline(always)]
    fn extra_stage<S: OdeSystem<N>, const R: usize>(&mut self, system: &S) {
        let mut yi = combine16!(DOP853_A_EXTRA[R], self.k);
        for (x, y) in yi.iter_mut().zip(self.y0.iter()) {
            *x = y + self.h * *x;
        }
        self.k[13 + R] = system.rhs(self.t0 + DOP853_C_EXTRA[R] * self.h, &yi);
    }
}

impl<const N: usize> Stepper<N> for Dop853<N> {
    const CONTROL: Option<ControlParams> = Some(DOP853_CONTROL);
    const STIFFNESS: Option<StiffnessParams> = Some(DOP853_STIFFNESS);
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
        let (f0, h) = first_stage(system, t0, y0, 8, h_max, options, stats)?;
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
        let k: &mut [SVector<f64, N>; 12] = (&mut self.k[..12]).try_into().expect("12 stages");
        k[0] = self.f_next;
        for i in 1..12 {
            let yi = stage_input(y, h, &DOP853.a[i], k, i);
            k[i] = system.rhs(t + DOP853.c[i] * h, &yi);
            if i == 11 {
                self.y_stage12 = yi;
            }
        }
        stats.rhs_evals += 11;
        let incr = combine(&DOP853.b, k);
        self.y1 = y + incr * h;
        let e5 = combine(&DOP853_E5, k);
        let e3 = incr - k[0] * DOP853_BHH[0] - k[8] * DOP853_BHH[1] - k[11] * DOP853_BHH[2];
        let (mut err5, mut err3) = (0.0, 0.0);
        for i in 0..N {
            let sk = scale(options, i, y[i], self.y1[i]);
            err5 += (e5[i] / sk).powi(2);
            err3 += (e3[i] / sk).powi(2);
        }
        // dop853.f: ERR = |h|·ERR5·sqrt(1/(N·(ERR5 + 0.01·ERR3)))
        let mut deno = err5 + 0.01 * err3;
        if deno <= 0.0 {
            deno = 1.0;
        }
        let mut err = h.abs() * err5 * (1.0 / (N as f64 * deno)).sqrt();
        if !err.is_finite() && deno.is_finite() {
            // 1/(N·deno) overflows where deno is subnormal, and gives 0·∞ where ERR5 = 0
            // (a state of size 1e-156: errors of 1e-170 against scales of 1e-12): the same
            // quantity without the reciprocal.
            err = h.abs() * err5 / (N as f64 * deno).sqrt();
        }
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
        system: &S,
        t_new: f64,
        y_new: &SVector<f64, N>,
        stats: &mut Stats,
    ) {
        // evaluated at the projected state, so the next step starts consistently
        self.f_next = system.rhs_accepted(t_new, y_new);
        stats.rhs_evals += 1;
        self.k[12] = self.f_next;
        self.y_new = *y_new;
    }

    fn stiffness_estimate(&self) -> Option<f64> {
        let num = (self.k[12] - self.k[11]).norm_squared();
        let den = (self.y_new - self.y_stage12).norm_squared();
        (den > 0.0).then(|| self.h.abs() * (num / den).sqrt())
    }

    fn prepare_dense<S: OdeSystem<N>>(&mut self, system: &S, stats: &mut Stats) {
        self.extra_stage::<S, 0>(system);
        self.extra_stage::<S, 1>(system);
        self.extra_stage::<S, 2>(system);
        stats.rhs_evals += 3;
        let (h, y0) = (self.h, self.y0);
        let ydiff = self.y_new - y0;
        let bspl = self.k[0] * h - ydiff;
        self.cont = [
            y0,
            ydiff,
            bspl,
            ydiff - self.k[12] * h - bspl,
            combine16!(DOP853_D[0], self.k) * h,
            combine16!(DOP853_D[1], self.k) * h,
            combine16!(DOP853_D[2], self.k) * h,
            combine16!(DOP853_D[3], self.k) * h,
        ];
    }

    fn dense(&self, t: f64) -> SVector<f64, N> {
        let theta = (t - self.t0) / self.h;
        let s1 = 1.0 - theta;
        let c = &self.cont;
        let par = c[4] + (c[5] + (c[6] + c[7] * theta) * s1) * theta;
        c[0] + (c[1] + (c[2] + (c[3] + par * s1) * theta) * s1) * theta
    }
}
