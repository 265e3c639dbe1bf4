//! Hairer's stiffness detection (`dopri5.f`/`dop853.f`; E. Hairer, G. Wanner, *Solving
//! ODEs II*, 2nd ed., Sect. IV.2):
//! h·ρ with ρ ≈ ‖f(ỹ) − f(ŷ)‖ / ‖ỹ − ŷ‖ from two stages at the same time estimates the
//! dominant eigenvalue; when it sits at the stability boundary for 15 tested steps in a
//! row, the problem is declared stiff. The test runs every NSTIFF-th accepted step, and on
//! every step once a positive has been seen, until 6 negatives in a row clear it.

/// Accepted steps between routine tests (IWORK(4) default in `dopri5.f`).
const NSTIFF: u64 = 1000;
/// Positives in a row that make a warning.
const POSITIVES: u32 = 15;
/// Negatives in a row that clear the count.
const NEGATIVES: u32 = 6;

/// A method's stiffness test: where h·ρ meets the stability boundary, and how finely the
/// method's accurate steps resolve a rate ρ.
#[derive(Debug, Clone, Copy)]
pub(crate) struct StiffnessParams {
    /// h·ρ at the stability boundary (Hairer's limit).
    pub(crate) limit: f64,
    /// (C, k): steps that resolve an oscillation or rotation at rate ρ to a relative
    /// tolerance rtol take h·ρ ≈ C·rtol^(1/k), the local error estimate being ∝ (h·ρ)^k
    /// (k = 5 for DOPRI5's 4th-order estimate; DOP853's blended 5th/3rd-order estimate
    /// goes as h^10/h^2 = h^8). C is measured on the harmonic oscillator x'' = −x at
    /// rtol = atol = 1e-10 (h·ρ = 0.042 and 0.354); the tippe-top disc spun at 1e6 rad/s
    /// gives 0.014–0.041 (DOPRI5, rtol 1e-12 and 1e-10) and 0.20–0.36 (DOP853).
    pub(crate) resolution: (f64, f64),
}

impl StiffnessParams {
    /// h·ρ ≈ C·rtol^(1/k) of the steps resolving a rate to `rtol`.
    pub(crate) fn resolved_pace(&self, rtol: f64) -> f64 {
        let (c, k) = self.resolution;
        c * rtol.powf(1.0 / k)
    }
}

pub(crate) const DOPRI5_STIFFNESS: StiffnessParams = StiffnessParams {
    limit: 3.25,
    resolution: (4.2, 5.0),
};
pub(crate) const DOP853_STIFFNESS: StiffnessParams = StiffnessParams {
    limit: 6.1,
    resolution: (6.3, 8.0),
};

#[derive(Debug, Clone)]
pub(crate) struct StiffnessDetector {
    limit: f64,
    hlamb: f64,
    /// ρ from the last estimate \[1/s\] (0 before any).
    rate: f64,
    positives: u32,
    negatives: u32,
}

impl StiffnessDetector {
    pub(crate) fn new(params: StiffnessParams) -> Self {
        StiffnessDetector {
            limit: params.limit,
            hlamb: 0.0,
            rate: 0.0,
            positives: 0,
            negatives: 0,
        }
    }

    /// Called after each accepted step of size `h`; `estimate` gives h·ρ for it. Returns
    /// true when the problem has just been found stiff.
    pub(crate) fn update(
        &mut self,
        accepted: u64,
        h: f64,
        estimate: impl FnOnce() -> Option<f64>,
    ) -> bool {
        if !accepted.is_multiple_of(NSTIFF) && self.positives == 0 {
            return false;
        }
        // HLAMB keeps its previous value when the denominator vanishes
        if let Some(hl) = estimate() {
            self.hlamb = hl;
            self.rate = hl / h;
        }
        if self.hlamb > self.limit {
            self.negatives = 0;
            self.positives += 1;
            self.positives == POSITIVES
        } else {
            self.negatives += 1;
            if self.negatives == NEGATIVES {
                self.positives = 0;
            }
            false
        }
    }

    /// The last estimate of h·ρ and of ρ \[1/s\], the dominant eigenvalue's magnitude:
    /// the fastest rate of the system (a decay or an oscillation) near the solution.
    pub(crate) fn last(&self) -> (f64, f64) {
        (self.hlamb, self.rate)
    }

    /// Whether the last tested step had h·ρ above the stability boundary: the steps are
    /// held by stability, not by accuracy.
    pub(crate) fn is_stiff(&self) -> bool {
        self.positives > 0 && self.hlamb > self.limit
    }
}
