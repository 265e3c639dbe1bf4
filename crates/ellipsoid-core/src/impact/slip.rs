//! The curving slip phase of an impact (docs/physics.md, "Impact at touchdown"). The
//! impulse grows as dP/dσ = −α ŝ + β e3 and
//! ```text
//!   z = (v_C, P_x, P_y, W_n, W_f, σ),   ŝ = v_t/|v_t|
//!   dv_C/dσ = K (−α ŝ + β e3),   dP_t/dσ = −α ŝ,   dW_n/dσ = v_n,   dW_f/dσ = α |v_t|
//! ```
//! v_C is integrated, not recomputed as v_C⁻ + K P: near a stop the slip is a small
//! difference of large terms there, and its direction (on which everything depends)
//! would carry their round-off magnified by |v_C⁻|/|v_t|.
//! Coulomb: σ = p, α = μ, β = 1. No slip (μ → ∞): σ = μ p at p → 0, α = 1, β = 0; W_n is
//! then the normal work scaled by μ, which the homogeneous restitution criterion allows.
//!
//! Integrated by DOP853 (the crate's tableau, Hairer's error estimate) at a relative
//! tolerance of 1e-13, in one of two charts chosen at each step:
//! - `Impulse`: σ is the independent variable, with steps at most half the predicted
//!   distance to a slip stop, |v_t| / (−d|v_t|/dσ), so the singular ŝ is never crossed;
//! - `LogSlip`, on the final approach to a stop (small slip heading inward): the
//!   independent variable is λ = −ln |v_t|, dz/dλ = (dz/dσ) |v_t| / (−d|v_t|/dσ). Near a
//!   stop the direction converges to an incoming ray like |v_t|^b (b > 0 any real), so the
//!   path is not smooth in σ but decays exponentially in λ: a few steps reach
//!   |v_t| = SLIP_TOL |v_C⁻| exactly, where the stop is taken.
//!
//! Compression end (v_n = 0) and restitution end (W_n = (1 − e²) W_c) are located by
//! Newton on the length of the step from its start.

use nalgebra::{SVector, Vector2, Vector3};

use super::{Contact, Normal};
use crate::integrate::tableau::{DOP853, DOP853_BHH, DOP853_E5};

type Z = SVector<f64, 8>;
const P: usize = 3;
const WN: usize = 5;
const WF: usize = 6;
const SIGMA: usize = 7;

/// Relative tolerance of the slip integration.
const TOL: f64 = 1e-13;
/// Accepted plus rejected steps before the slip is taken as stopped (a safeguard: the
/// tests' 2·10⁴ random impacts need at most a few hundred).
const MAX_STEPS: u32 = 5_000;
/// The log-slip chart is used below this fraction of |v_C⁻| ...
const LOG_CHART_SLIP: f64 = 1e-2;
/// ... while the slip heads inward: d|v_t|/dσ < −cos 60° |dv_t/dσ|.
const LOG_CHART_INWARD: f64 = 0.5;
/// Relative turning rate of the slip direction below which a slip on the final approach
/// is finished as a straight line (its direction error then changes the result by less
/// than RAY_TOL |v_t| ≤ RAY_TOL LOG_CHART_SLIP |v_C⁻|).
const RAY_TOL: f64 = 1e-9;

/// How the impulse grows with σ: dP/dσ = −`friction` ŝ + `normal` e3.
#[derive(Debug, Clone, Copy)]
pub(super) struct Drive {
    pub friction: f64,
    pub normal: f64,
}

/// Why the slip phase ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum SlipEnd {
    /// |v_t| reached zero (a stick or a new straight slip follows).
    Stopped,
    /// Restitution ended while still slipping: the impact is over.
    Ended,
}

/// The state where the slip phase ended.
pub(super) struct Run {
    pub sigma: f64,
    pub impulse_t: Vector2<f64>,
    pub friction_work: f64,
    pub normal: Normal,
    pub end: SlipEnd,
    pub steps: u32,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Chart {
    Impulse,
    LogSlip,
}

struct Slip<'a> {
    contact: &'a Contact,
    drive: Drive,
    /// Error scales of the state components.
    scale: Z,
}

/// Integrates the slip from v_C⁻ to its stop or to the end of restitution (coefficient e).
pub(super) fn integrate(contact: &Contact, drive: Drive, e: f64) -> Run {
    let speed = contact.v0.norm();
    let p_scale = speed / contact.k.trace() * 3.0;
    let pt = p_scale * drive.friction.max(1.0);
    let slip = Slip {
        contact,
        drive,
        scale: Z::from_column_slice(&[
            speed,
            speed,
            speed,
            pt,
            pt,
            p_scale * speed,
            pt * speed,
            p_scale,
        ]),
    };
    slip.run(e, p_scale)
}

impl Slip<'_> {
    fn velocity(&self, z: &Z) -> Vector3<f64> {
        z.fixed_rows::<3>(0).into_owned()
    }

    fn slip(&self, z: &Z) -> (f64, Vector2<f64>) {
        let v = self.velocity(z).xy();
        let s = v.norm();
        (s, if s > 0.0 { v / s } else { Vector2::zeros() })
    }

    /// dz/dσ.
    fn rate(&self, z: &Z) -> Z {
        let (s, s_hat) = self.slip(z);
        let a = self.drive.friction;
        let dp = Vector3::new(-a * s_hat.x, -a * s_hat.y, self.drive.normal);
        let dv = self.contact.k * dp;
        Z::from_column_slice(&[dv.x, dv.y, dv.z, dp.x, dp.y, z[2], a * s, 1.0])
    }

    /// (d|v_t|/dσ, |dv_t/dσ|, dv_n/dσ), with dv/dσ = K dP/dσ.
    fn slip_rates(&self, z: &Z) -> (f64, f64, f64) {
        let (_, s_hat) = self.slip(z);
        let dp = Vector3::new(
            -self.drive.friction * s_hat.x,
            -self.drive.friction * s_hat.y,
            self.drive.normal,
        );
        let dv = self.contact.k * dp;
        (s_hat.dot(&dv.xy()), dv.xy().norm(), dv.z)
    }

    /// dz/dt in the chart (t = σ or λ = −ln |v_t|); NaN where the log chart is invalid.
    fn rhs(&self, chart: Chart, z: &Z) -> Z {
        let f = self.rate(z);
        match chart {
            Chart::Impulse => f,
            Chart::LogSlip => {
                let (s, _) = self.slip(z);
                let (ds, _, _) = self.slip_rates(z);
                if ds < 0.0 {
                    f * (s / -ds)
                } else {
                    Z::repeat(f64::NAN)
                }
            }
        }
    }

    /// One DOP853 step of length h from z with k1 = dz/dt(z): the 8th-order result and
    /// Hairer's error norm (`dop853.f`: ERR = |h| ERR5 / √(N (ERR5 + 0.01 ERR3))).
    fn step(&self, chart: Chart, z: &Z, k1: &Z, h: f64) -> (Z, f64) {
        let mut k = [Z::zeros(); 12];
        k[0] = *k1;
        for i in 1..12 {
            let mut zi = *z;
            for (j, kj) in k.iter().enumerate().take(i) {
                if DOP853.a[i][j] != 0.0 {
                    zi += kj * (h * DOP853.a[i][j]);
                }
            }
            k[i] = self.rhs(chart, &zi);
        }
        let combine = |w: &[f64; 12]| {
            k.iter()
                .zip(w)
                .fold(Z::zeros(), |acc, (kj, wj)| acc + kj * *wj)
        };
        let incr = combine(&DOP853.b);
        let z1 = z + incr * h;
        let e5 = combine(&DOP853_E5);
        let e3 = incr - k[0] * DOP853_BHH[0] - k[8] * DOP853_BHH[1] - k[11] * DOP853_BHH[2];
        let (mut err5, mut err3) = (0.0, 0.0);
        for i in 0..8 {
            let sk = TOL * (self.scale[i] + z[i].abs().max(z1[i].abs()));
            err5 += (e5[i] / sk).powi(2);
            err3 += (e3[i] / sk).powi(2);
        }
        let deno = if err5 + 0.01 * err3 > 0.0 {
            err5 + 0.01 * err3
        } else {
            1.0
        };
        (z1, h.abs() * err5 / (8.0 * deno).sqrt())
    }

    fn finish(&self, z: &Z, compression: Option<f64>, end: SlipEnd, steps: u32) -> Run {
        Run {
            sigma: z[SIGMA],
            impulse_t: Vector2::new(z[P], z[P + 1]),
            friction_work: z[WF],
            normal: Normal {
                impulse: self.drive.normal * z[SIGMA],
                velocity: self.velocity(z).z,
                work: z[WN],
                compression,
                rate: 0.0,
            },
            end,
            steps,
        }
    }

    /// The chart for a step from z: log-slip on a small slip heading inward.
    fn chart(&self, z: &Z) -> Chart {
        let (s, _) = self.slip(z);
        let (ds, dv, _) = self.slip_rates(z);
        if s < LOG_CHART_SLIP * self.contact.v0.norm() && ds < -LOG_CHART_INWARD * dv {
            Chart::LogSlip
        } else {
            Chart::Impulse
        }
    }

    fn run(&self, e: f64, p_scale: f64) -> Run {
        let mut z = Z::zeros();
        z.fixed_rows_mut::<3>(0).copy_from(&self.contact.v0);
        let mut compression: Option<f64> = None;
        let mut steps = 0;
        let tol = self.contact.slip_tol;
        if self.contact.v0.xy().norm() <= tol {
            return self.finish(&z, compression, SlipEnd::Stopped, steps);
        }
        let (mut h_sigma, mut h_log) = (self.initial_step(p_scale), 1.0_f64);
        while steps < MAX_STEPS {
            steps += 1;
            let chart = self.chart(&z);
            if chart == Chart::LogSlip && self.on_attracting_ray(&z) {
                return self.straight_to_stop(&z, compression, e, steps);
            }
            let (s, _) = self.slip(&z);
            let (h_try, to_stop) = match chart {
                Chart::Impulse => {
                    let (ds, _, _) = self.slip_rates(&z);
                    (
                        if ds < 0.0 {
                            h_sigma.min(0.5 * s / -ds)
                        } else {
                            h_sigma
                        },
                        false,
                    )
                }
                Chart::LogSlip => {
                    let left = (s / tol).ln();
                    (h_log.min(left), h_log >= left)
                }
            };
            let k1 = self.rhs(chart, &z);
            let (z1, err) = self.step(chart, &z, &k1, h_try);
            let factor = if err.is_finite() {
                0.8 * err.powf(-1.0 / 9.0)
            } else {
                0.2
            };
            let h_next = h_try
                * if err <= 1.0 {
                    factor.clamp(0.333, 6.0)
                } else {
                    factor.max(0.2)
                };
            match chart {
                Chart::Impulse => h_sigma = h_next,
                Chart::LogSlip => h_log = h_next,
            }
            if !(err <= 1.0) {
                continue;
            }
            let z_next = match compression {
                None if self.velocity(&z1).z >= 0.0 => {
                    let zc = self.locate(chart, &z, &k1, h_try, |z| {
                        (self.velocity(z).z, self.slip_rates(z).2)
                    });
                    compression = Some(zc[WN]);
                    if e == 0.0 {
                        return self.finish(&zc, compression, SlipEnd::Ended, steps);
                    }
                    zc
                }
                Some(w_c) if z1[WN] >= Normal::target(w_c, e) => {
                    let target = Normal::target(w_c, e);
                    let zr = self.locate(chart, &z, &k1, h_try, |z| {
                        (z[WN] - target, self.velocity(z).z)
                    });
                    return self.finish(&zr, compression, SlipEnd::Ended, steps);
                }
                _ if to_stop => return self.finish(&z1, compression, SlipEnd::Stopped, steps),
                _ => z1,
            };
            z = z_next;
            if self.slip(&z).0 <= tol {
                return self.finish(&z, compression, SlipEnd::Stopped, steps);
            }
        }
        self.finish(&z, compression, SlipEnd::Stopped, steps)
    }

    /// The slip heads straight at zero (d ŝ/dσ below RAY_TOL of |dv_t/dσ| / |v_t|) along
    /// an incoming ray that attracts nearby directions (or, for one that does not, the
    /// turning rate is round-off): with ψ the slip's angle,
    /// d(ŝ⊥·dv_t/dσ)/dψ = −ŝ·dv_t/dσ − α ŝ⊥ᵀ K_tt ŝ⊥ < 0. The attraction is fast when the
    /// approach is slow (rate |ŝ·dv_t/dσ| ≪ α K_tt), which makes the ODE stiff there.
    fn on_attracting_ray(&self, z: &Z) -> bool {
        let (_, s_hat) = self.slip(z);
        let perp = Vector2::new(-s_hat.y, s_hat.x);
        let a = self.drive.friction;
        let g = self.contact.k_tt() * (-a * s_hat) + self.contact.k_tn() * self.drive.normal;
        let (radial, turning) = (s_hat.dot(&g), perp.dot(&g));
        let attracting = -radial - a * perp.dot(&(self.contact.k_tt() * perp)) < 0.0;
        // a ray that repels can only be followed from exactly on it (planar or symmetric
        // impacts), i.e. to round-off
        let tol = if attracting {
            RAY_TOL
        } else {
            64.0 * f64::EPSILON
        };
        radial < 0.0 && turning.abs() <= tol * g.norm()
    }

    /// The rest of a straight slip to its stop, in closed form: dz/dσ is constant except
    /// v_n = v + c x, W_n = W + v x + c x²/2, W_f = W_f + α (s x − λ x²/2), |v_t| = s − λ x,
    /// up to x = s/λ, or to an earlier compression end (x = −v/c) or restitution end
    /// (the first root of W_n(x) = (1 − e²) W_c).
    fn straight_to_stop(&self, z: &Z, compression: Option<f64>, e: f64, steps: u32) -> Run {
        let (s, _) = self.slip(z);
        let (ds, _, c) = self.slip_rates(z);
        let rate = self.rate(z);
        let (v, w) = (z[2], z[WN]);
        let x_stop = s / -ds;
        let at = |x: f64| {
            let mut zx = z + rate * x;
            zx[WN] = w + v * x + 0.5 * c * x * x;
            zx[WF] = z[WF] + self.drive.friction * (s * x + 0.5 * ds * x * x);
            zx
        };
        let (mut compression, mut from) = (compression, 0.0);
        if compression.is_none() {
            if !(c > 0.0 && -v < c * x_stop) {
                return self.finish(&at(x_stop), compression, SlipEnd::Stopped, steps);
            }
            from = (-v / c).max(0.0);
            compression = Some(at(from)[WN]);
            if e == 0.0 {
                return self.finish(&at(from), compression, SlipEnd::Ended, steps);
            }
        }
        let target = Normal::target(compression.unwrap_or(0.0), e);
        match first_root_after(0.5 * c, v, w - target, from).filter(|&x| x <= x_stop) {
            Some(x) => self.finish(&at(x), compression, SlipEnd::Ended, steps),
            None => self.finish(&at(x_stop), compression, SlipEnd::Stopped, steps),
        }
    }

    /// A tenth of the nearest predicted event: compression −v_n/(dv_n/dσ) or slip stop
    /// |v_t|/(−d|v_t|/dσ), and at most a tenth of the impulse scale.
    fn initial_step(&self, p_scale: f64) -> f64 {
        let mut z = Z::zeros();
        z.fixed_rows_mut::<3>(0).copy_from(&self.contact.v0);
        let (ds, _, dvn) = self.slip_rates(&z);
        let mut h = p_scale / self.drive.friction.max(1.0);
        if dvn > 0.0 {
            h = h.min(-self.contact.v0.z / dvn);
        }
        if ds < 0.0 {
            h = h.min(self.contact.v0.xy().norm() / -ds);
        }
        0.1 * h
    }

    /// The state at the step length x ∈ (0, h] from z where g crosses zero upward (g < 0
    /// at 0, ≥ 0 at h), by Newton with dg/dt = (dg/dσ)(dσ/dt), kept in a shrinking
    /// bracket; each trial is one DOP853 step from z, as accurate as the step it shortens.
    /// `g` returns (g, dg/dσ).
    fn locate(&self, chart: Chart, z: &Z, k1: &Z, h: f64, g: impl Fn(&Z) -> (f64, f64)) -> Z {
        let (g0, _) = g(z);
        let (z1, _) = self.step(chart, z, k1, h);
        let (g1, _) = g(&z1);
        let (mut lo, mut hi) = (0.0, h);
        let mut x = if g1 > g0 {
            h * (-g0 / (g1 - g0)).clamp(0.0, 1.0)
        } else {
            h
        };
        let mut zx = z1;
        for _ in 0..60 {
            zx = self.step(chart, z, k1, x).0;
            let (gx, dg) = g(&zx);
            if gx < 0.0 {
                lo = x;
            } else {
                hi = x;
            }
            let mut next = x - gx / (dg * self.rhs(chart, &zx)[SIGMA]);
            if !(next > lo && next < hi) {
                next = 0.5 * (lo + hi);
            }
            if (next - x).abs() <= 2.0 * f64::EPSILON * x || hi - lo <= 2.0 * f64::EPSILON * hi {
                break;
            }
            x = next;
        }
        zx
    }
}

/// The smallest root x > from of a x² + b x + c0 = 0 (c0 < 0 there: the root is where the
/// quadratic rises through zero), by the cancellation-free formulas.
fn first_root_after(a: f64, b: f64, c0: f64, from: f64) -> Option<f64> {
    let roots = if a == 0.0 {
        [(b != 0.0).then(|| -c0 / b), None]
    } else {
        let disc = b * b - 4.0 * a * c0;
        if disc < 0.0 {
            return None;
        }
        let q = -0.5 * (b + b.signum() * disc.sqrt());
        [(q != 0.0).then(|| q / a), (q != 0.0).then(|| c0 / q)]
    };
    roots
        .into_iter()
        .flatten()
        .filter(|&x| x > from)
        .fold(None, |best: Option<f64>, x| {
            Some(best.map_or(x, |b| b.min(x)))
        })
}
