//! Reference problems shared by the integrator tests and benches, each with what is
//! known about its solution (closed form, period, published results).

use nalgebra::{SVector, Vector2, Vector4};

use super::OdeSystem;

/// x'' = −ω² x as y = (x, v): the solution is a rotation in phase space.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HarmonicOscillator {
    /// Angular frequency ω [rad/s].
    pub omega: f64,
}

impl HarmonicOscillator {
    /// The exact state at time `t` from `y0` at t = 0.
    pub fn exact(&self, t: f64, y0: &Vector2<f64>) -> Vector2<f64> {
        let (s, c) = (self.omega * t).sin_cos();
        Vector2::new(
            y0[0] * c + y0[1] / self.omega * s,
            -y0[0] * self.omega * s + y0[1] * c,
        )
    }
}

impl OdeSystem<2> for HarmonicOscillator {
    fn rhs(&self, _t: f64, y: &Vector2<f64>) -> Vector2<f64> {
        Vector2::new(y[1], -self.omega * self.omega * y[0])
    }
}

/// The restricted three-body problem with Arenstorf's periodic orbit (HNW I, Sect. II.0,
/// eq. (0.1), and the driver `dr_dop5.f`): y = (y1, y2, y1', y2').
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Arenstorf;

impl Arenstorf {
    /// Mass ratio μ.
    pub const MU: f64 = 0.012277471;
    /// Initial state of the periodic orbit.
    #[allow(clippy::excessive_precision)] // digits as published
    pub const Y0: [f64; 4] = [0.994, 0.0, 0.0, -2.00158510637908252240537862224];
    /// Period of the orbit.
    #[allow(clippy::excessive_precision)] // digits as published
    pub const PERIOD: f64 = 17.0652165601579625588917206249;

    pub fn y0() -> Vector4<f64> {
        Vector4::from(Self::Y0)
    }
}

impl OdeSystem<4> for Arenstorf {
    fn rhs(&self, _t: f64, y: &Vector4<f64>) -> Vector4<f64> {
        let mu = Self::MU;
        let mu1 = 1.0 - mu;
        let d1 = ((y[0] + mu).powi(2) + y[1] * y[1]).powf(1.5);
        let d2 = ((y[0] - mu1).powi(2) + y[1] * y[1]).powf(1.5);
        Vector4::new(
            y[2],
            y[3],
            y[0] + 2.0 * y[3] - mu1 * (y[0] + mu) / d1 - mu * (y[0] - mu1) / d2,
            y[1] - 2.0 * y[2] - mu1 * y[1] / d1 - mu * y[1] / d2,
        )
    }
}

/// Van der Pol's oscillator y1' = y2, y2' = α(1 − y1²)y2 − β·y1.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VanDerPol {
    pub alpha: f64,
    pub beta: f64,
}

impl VanDerPol {
    /// The usual form y2' = μ(1 − y1²)y2 − y1; stiff for large μ.
    pub fn standard(mu: f64) -> Self {
        VanDerPol {
            alpha: mu,
            beta: 1.0,
        }
    }

    /// Hairer's scaled form y2' = ((1 − y1²)y2 − y1)/ε (`dr_dop853.f`, HNW II Sect. IV.1).
    pub fn scaled(eps: f64) -> Self {
        VanDerPol {
            alpha: 1.0 / eps,
            beta: 1.0 / eps,
        }
    }
}

impl OdeSystem<2> for VanDerPol {
    fn rhs(&self, _t: f64, y: &Vector2<f64>) -> Vector2<f64> {
        Vector2::new(
            y[1],
            self.alpha * (1.0 - y[0] * y[0]) * y[1] - self.beta * y[0],
        )
    }
}

/// A nonlinear, non-autonomous, coupled 4-dimensional problem with a closed-form
/// solution, for measuring convergence orders (scalar or linear problems satisfy fewer
/// order conditions and can hide a wrong coefficient):
///
/// ```text
/// y1' = 2t·y1·y4          y1 = exp(sin t²)
/// y2' = 10t·exp(5(y3 − 1))·y4   y2 = exp(5 sin t²)
/// y3' = 2t·y4             y3 = sin t² + 1
/// y4' = −2t·ln y1         y4 = cos t²
/// ```
///
/// y(0) = (1, 1, 1, 1). Modelled on the test problems of HNW I, Sect. II.10.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExpSinSquared;

impl ExpSinSquared {
    pub fn exact(t: f64) -> Vector4<f64> {
        let (s, c) = (t * t).sin_cos();
        Vector4::new(s.exp(), (5.0 * s).exp(), s + 1.0, c)
    }
}

impl OdeSystem<4> for ExpSinSquared {
    fn rhs(&self, t: f64, y: &Vector4<f64>) -> Vector4<f64> {
        Vector4::new(
            2.0 * t * y[0] * y[3],
            10.0 * t * (5.0 * (y[2] - 1.0)).exp() * y[3],
            2.0 * t * y[3],
            -2.0 * t * y[0].ln(),
        )
    }
}

/// The Kepler two-body problem q'' = −q/|q|³ with y = (q1, q2, q1', q2'), started at
/// pericentre of an orbit of eccentricity e, semi-major axis 1 and period 2π. Nonlinear,
/// with a closed-form solution through Kepler's equation; its global error grows
/// steadily (phase drift), so measured convergence orders are clean.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Kepler {
    /// Eccentricity, 0 ≤ e < 1.
    pub e: f64,
}

impl Kepler {
    /// The pericentre state at t = 0.
    pub fn y0(&self) -> Vector4<f64> {
        let e = self.e;
        Vector4::new(1.0 - e, 0.0, 0.0, ((1.0 + e) / (1.0 - e)).sqrt())
    }

    /// The exact state at time `t`: Newton's method on Kepler's equation E − e·sin E = t.
    pub fn exact(&self, t: f64) -> Vector4<f64> {
        let e = self.e;
        let mut ecc_anom = t;
        for _ in 0..50 {
            let step = (ecc_anom - e * ecc_anom.sin() - t) / (1.0 - e * ecc_anom.cos());
            ecc_anom -= step;
            if step.abs() <= 1e-16 * ecc_anom.abs().max(1.0) {
                break;
            }
        }
        let (s, c) = ecc_anom.sin_cos();
        let b = (1.0 - e * e).sqrt();
        let r = 1.0 - e * c;
        Vector4::new(c - e, b * s, -s / r, b * c / r)
    }
}

impl OdeSystem<4> for Kepler {
    fn rhs(&self, _t: f64, y: &Vector4<f64>) -> Vector4<f64> {
        let r2 = y[0] * y[0] + y[1] * y[1];
        let r3 = r2 * r2.sqrt();
        Vector4::new(y[2], y[3], -y[0] / r3, -y[1] / r3)
    }
}

/// Scalar exponential decay y' = −λy with y = y0·e^(−λt); used for trivial sanity checks.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Decay {
    pub lambda: f64,
}

impl OdeSystem<1> for Decay {
    fn rhs(&self, _t: f64, y: &SVector<f64, 1>) -> SVector<f64, 1> {
        y * -self.lambda
    }
}
