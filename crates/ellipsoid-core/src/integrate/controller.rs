//! Hairer's step-size control: the scaled RMS error norm, the PI ("Lund-stabilised")
//! controller and the automatic initial step `hinit`, as in `dopri5.f` and `dop853.f`.

use nalgebra::SVector;

use super::{OdeSystem, Options, Stats};

/// Constants of Hairer's controller: h_new = h / fac with
/// fac = clamp(err^expo1 / err_old^beta / safe, 1/fac2, 1/fac1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct ControlParams {
    /// Exponent on the current error: 1/(q+1) − beta·(0.75 for DOPRI5, 0.2 for DOP853).
    pub expo1: f64,
    /// Exponent on the previous accepted error (the PI part).
    pub beta: f64,
    /// Smallest ratio h_new/h.
    pub fac1: f64,
    /// Largest ratio h_new/h.
    pub fac2: f64,
    /// Safety factor.
    pub safe: f64,
}

/// `dopri5.f` defaults: BETA = 0.04, FAC1 = 0.2, FAC2 = 10, SAFE = 0.9,
/// EXPO1 = 0.2 − 0.75·BETA.
pub(crate) const DOPRI5_CONTROL: ControlParams = ControlParams {
    expo1: 0.2 - 0.75 * 0.04,
    beta: 0.04,
    fac1: 0.2,
    fac2: 10.0,
    safe: 0.9,
};

/// `dop853.f` defaults: BETA = 0, FAC1 = 0.333, FAC2 = 6, SAFE = 0.9,
/// EXPO1 = 1/8 − 0.2·BETA.
pub(crate) const DOP853_CONTROL: ControlParams = ControlParams {
    expo1: 1.0 / 8.0 - 0.2 * 0.0,
    beta: 0.0,
    fac1: 0.333,
    fac2: 6.0,
    safe: 0.9,
};

/// ln 1e-4: FACOLD's floor and start value (`dopri5.f`).
const LN_FACOLD_MIN: f64 = -9.210340371976182;

/// The controller's decision on an attempted step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Verdict {
    Accept { h_next: f64 },
    Reject { h_next: f64 },
}

/// Hairer's PI controller with its memory (FACOLD, REJECT).
#[derive(Debug, Clone)]
pub(crate) struct PiController {
    p: ControlParams,
    /// ln FACOLD: the logarithm of the last accepted error (at least 1e-4).
    ln_facold: f64,
    after_reject: bool,
}

impl PiController {
    pub(crate) fn new(p: ControlParams) -> Self {
        // FACOLD = 1e-4 before the first step (dopri5.f, DOPCOR)
        PiController {
            p,
            ln_facold: LN_FACOLD_MIN,
            after_reject: false,
        }
    }

    /// Judges a step of size `h` with scaled error `err` (finite, ≥ 0).
    ///
    /// fac = err^expo1 / facold^beta is formed as exp(expo1·ln err − beta·ln facold) with
    /// ln facold kept from the last accepted step: one `ln` and one `exp` per step instead
    /// of Hairer's two `pow` (the same value up to round-off; `pow` was a quarter of
    /// DOPRI5's per-step cost). err = 0 gives ln err = −∞ and fac = 0, clamped below.
    pub(crate) fn judge(&mut self, err: f64, h: f64, h_max: f64) -> Verdict {
        let p = &self.p;
        let ln_err = err.ln();
        if err <= 1.0 {
            let fac = (p.expo1 * ln_err - p.beta * self.ln_facold).exp();
            let fac = (fac / p.safe).min(1.0 / p.fac1).max(1.0 / p.fac2);
            self.ln_facold = ln_err.max(LN_FACOLD_MIN);
            let mut h_next = (h / fac).min(h_max);
            if self.after_reject {
                // no increase right after a rejection
                h_next = h_next.min(h);
            }
            self.after_reject = false;
            Verdict::Accept { h_next }
        } else {
            self.after_reject = true;
            let fac11 = (p.expo1 * ln_err).exp();
            Verdict::Reject {
                h_next: h / (1.0 / p.fac1).min(fac11 / p.safe),
            }
        }
    }

    /// A step was thrown away for a non-finite right-hand side: treat it as a rejection.
    pub(crate) fn note_rejection(&mut self) {
        self.after_reject = true;
    }
}

/// Weight of component `i`: atol_i + rtol_i·max(|y0_i|, |y1_i|) (Hairer's SK).
#[inline(always)]
pub(crate) fn scale<const N: usize>(options: &Options<N>, i: usize, y0: f64, y1: f64) -> f64 {
    options.atol[i] + options.rtol[i] * y0.abs().max(y1.abs())
}

/// Hairer's RMS norm of an error estimate `e` (already multiplied by h):
/// sqrt(Σ (e_i / sk_i)² / N).
#[inline]
pub(crate) fn rms_error<const N: usize>(
    e: &SVector<f64, N>,
    y0: &SVector<f64, N>,
    y1: &SVector<f64, N>,
    options: &Options<N>,
) -> f64 {
    let mut sum = 0.0;
    for i in 0..N {
        let r = e[i] / scale(options, i, y0[i], y1[i]);
        sum += r * r;
    }
    (sum / N as f64).sqrt()
}

/// Hairer's automatic initial step (function HINIT of `dopri5.f`/`dop853.f`): an explicit
/// Euler step of size h = 0.01·‖y0‖/‖f0‖ estimates the second derivative, then
/// h = min(100·h, (0.01 / max(‖f0‖, ‖y''‖))^(1/order), h_max). One rhs call.
#[allow(clippy::too_many_arguments)] // mirrors HINIT's argument list
pub(crate) fn hinit<S: OdeSystem<N>, const N: usize>(
    system: &S,
    t0: f64,
    y0: &SVector<f64, N>,
    f0: &SVector<f64, N>,
    order: i32,
    h_max: f64,
    options: &Options<N>,
    stats: &mut Stats,
) -> f64 {
    // HINIT uses sums of squares, not means, and scales with |y0| only.
    let sk = |i: usize| options.atol[i] + options.rtol[i] * y0[i].abs();
    let (mut dnf, mut dny) = (0.0, 0.0);
    for i in 0..N {
        dnf += (f0[i] / sk(i)).powi(2);
        dny += (y0[i] / sk(i)).powi(2);
    }
    let mut h = if dnf <= 1.0e-10 || dny <= 1.0e-10 {
        1.0e-6
    } else {
        (dny / dnf).sqrt() * 0.01
    };
    h = h.min(h_max);
    let y1 = y0 + f0 * h;
    let f1 = system.rhs(t0 + h, &y1);
    stats.rhs_evals += 1;
    let mut der2 = 0.0;
    for i in 0..N {
        der2 += ((f1[i] - f0[i]) / sk(i)).powi(2);
    }
    let der2 = der2.sqrt() / h;
    let der12 = der2.abs().max(dnf.sqrt());
    let h1 = if der12 <= 1.0e-15 {
        (h * 1.0e-3).max(1.0e-6)
    } else {
        (0.01 / der12).powf(1.0 / order as f64)
    };
    // f64::min ignores a NaN h1 (non-finite f1): the first step then reveals the problem.
    (100.0 * h).min(h1).min(h_max)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ln_facold_floor_is_ln_1e_minus_4() {
        assert_eq!(LN_FACOLD_MIN, 1.0e-4_f64.ln());
    }

    /// The log-space controller agrees with Hairer's pow formula
    /// (fac = err^expo1 / facold^beta, `dopri5.f` DOPCOR) to round-off, across a run of
    /// accepted and rejected steps, and keeps its rules (no growth after a rejection).
    #[test]
    fn judge_matches_hairers_pow_formula() {
        let p = DOPRI5_CONTROL;
        let mut c = PiController::new(p);
        let (mut facold, mut after_reject) = (1.0e-4_f64, false);
        let h = 1.0e-3;
        for &err in &[0.3_f64, 1e-9, 0.0, 2.5, 0.99, 1.0, 40.0, 0.5, 1e-6] {
            let fac11 = err.powf(p.expo1);
            let fac = (fac11 / facold.powf(p.beta) / p.safe)
                .min(1.0 / p.fac1)
                .max(1.0 / p.fac2);
            let (want_accept, want_h) = if err <= 1.0 {
                let hn = if after_reject {
                    (h / fac).min(h)
                } else {
                    h / fac
                };
                facold = err.max(1.0e-4);
                after_reject = false;
                (true, hn)
            } else {
                after_reject = true;
                (false, h / (1.0 / p.fac1).min(fac11 / p.safe))
            };
            let (accepted, got) = match c.judge(err, h, 1.0) {
                Verdict::Accept { h_next } => (true, h_next),
                Verdict::Reject { h_next } => (false, h_next),
            };
            assert_eq!(accepted, want_accept, "err = {err}");
            assert!(
                (got - want_h).abs() <= 1e-14 * want_h,
                "err = {err}: {got} vs {want_h}"
            );
        }
    }
}
