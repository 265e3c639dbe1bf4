//! The integration state, declared once, and conversions to and from the paper's
//! z-x-z Euler angles (paper eq. 1; docs/physics.md "Body, frames, conventions").
//!
//! ```text
//! index  symbol        unit    meaning
//! 0..2   x_G, y_G      m       horizontal position of the centre of mass G
//! 2..6   q0,q1,q2,q3   -       unit quaternion (w, x, y, z), body -> world
//! 6..8   v_Gx, v_Gy    m/s     horizontal velocity of G (rolling: kept equal to −(ω×r)_h)
//! 8..11  ω1, ω2, ω3    rad/s   angular velocity in body axes
//! 11     W             J       work dissipated so far (contact friction and effects)
//! 12..14 s_x, s_y      -       slip reference direction (sliding; see `model::sliding`)
//!        z_G, v_Gz     m, m/s  in flight instead: height and vertical velocity of G
//! ```
//! In contact z_G and v_Gz are not states: they follow from the orientation (exact
//! contact). In flight (`model::flight`) they are, in the slots no contact law uses then.

use nalgebra::{Matrix3, Quaternion, SVector, UnitQuaternion, Vector2, Vector3};

/// Length of the state vector.
pub const DIM: usize = 14;
/// The state vector.
pub type State = SVector<f64, DIM>;

/// Index of x_G.
pub const POS: usize = 0;
/// Index of the quaternion's scalar part.
pub const QUAT: usize = 2;
/// Index of v_Gx.
pub const VEL: usize = 6;
/// Index of ω1.
pub const OMEGA: usize = 8;
/// Index of the dissipated work.
pub const WORK: usize = 11;
/// Index of the slip reference direction.
pub const SLIP_REF: usize = 12;
/// Index of z_G in flight (the slip reference's slots: no slip is tracked in flight).
pub const HEIGHT: usize = 12;
/// Index of v_Gz in flight.
pub const VEL_Z: usize = 13;

/// Horizontal position of G \[m\].
#[inline]
pub fn position(y: &State) -> Vector2<f64> {
    Vector2::new(y[POS], y[POS + 1])
}
/// Horizontal velocity of G [m/s].
#[inline]
pub fn velocity(y: &State) -> Vector2<f64> {
    Vector2::new(y[VEL], y[VEL + 1])
}
/// Body angular velocity [rad/s].
#[inline]
pub fn omega(y: &State) -> Vector3<f64> {
    Vector3::new(y[OMEGA], y[OMEGA + 1], y[OMEGA + 2])
}
/// The raw (possibly slightly unnormalised) quaternion.
#[inline]
pub fn quaternion(y: &State) -> Quaternion<f64> {
    Quaternion::new(y[QUAT], y[QUAT + 1], y[QUAT + 2], y[QUAT + 3])
}
/// Rotation body -> world, from the normalised quaternion.
#[inline]
pub fn rotation(y: &State) -> Matrix3<f64> {
    UnitQuaternion::new_normalize(quaternion(y))
        .to_rotation_matrix()
        .into_inner()
}
/// Slip reference direction (unit, world horizontal).
#[inline]
pub fn slip_ref(y: &State) -> Vector2<f64> {
    Vector2::new(y[SLIP_REF], y[SLIP_REF + 1])
}

/// Writes a unit quaternion into the state.
pub fn set_quaternion(y: &mut State, q: &UnitQuaternion<f64>) {
    y[QUAT] = q.w;
    y[QUAT + 1] = q.i;
    y[QUAT + 2] = q.j;
    y[QUAT + 3] = q.k;
}

/// q̇ = ½ q ⊗ (0, ω_b): the quaternion rate for body-frame angular velocity.
#[inline]
pub fn quaternion_rate(q: &Quaternion<f64>, omega_b: &Vector3<f64>) -> Quaternion<f64> {
    q * Quaternion::from_imag(*omega_b) * 0.5
}

/// The paper's z-x-z Euler angles and their rates [rad, rad/s].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct EulerAngles {
    pub theta: f64,
    pub phi: f64,
    pub psi: f64,
    pub theta_dot: f64,
    pub phi_dot: f64,
    pub psi_dot: f64,
}

/// Below this sin θ the split of φ and ψ (and of their rates) is undefined to round-off:
/// only φ + ψ and φ̇ + ψ̇ are. See [`EulerAngles::from_rotation`].
const UPRIGHT_SIN: f64 = 1e-12;

impl EulerAngles {
    /// R = Rz(φ) Rx(θ) Rz(ψ) (paper eq. 1).
    pub fn rotation(&self) -> UnitQuaternion<f64> {
        UnitQuaternion::from_axis_angle(&Vector3::z_axis(), self.phi)
            * UnitQuaternion::from_axis_angle(&Vector3::x_axis(), self.theta)
            * UnitQuaternion::from_axis_angle(&Vector3::z_axis(), self.psi)
    }

    /// Body angular velocity from the rates:
    /// ω_b = (φ̇ sθ sψ + θ̇ cψ, φ̇ sθ cψ − θ̇ sψ, φ̇ cθ + ψ̇).
    pub fn omega_body(&self) -> Vector3<f64> {
        let (st, ct) = self.theta.sin_cos();
        let (sp, cp) = self.psi.sin_cos();
        Vector3::new(
            self.phi_dot * st * sp + self.theta_dot * cp,
            self.phi_dot * st * cp - self.theta_dot * sp,
            self.phi_dot * ct + self.psi_dot,
        )
    }

    /// Angles and rates from a rotation and the body angular velocity.
    ///
    /// θ = atan2(√(R13² + R23²), R33), φ = atan2(R13, −R23), ψ = atan2(R31, R32); the
    /// rates θ̇ = (ω1 R32 − ω2 R31)/sin θ, φ̇ = (ω1 R31 + ω2 R32)/sin²θ, ψ̇ = ω3 − φ̇ R33
    /// (ω_b = (φ̇ sθ sψ + θ̇ cψ, φ̇ sθ cψ − θ̇ sψ, φ̇ cθ + ψ̇) solved, with R31 = sθ sψ,
    /// R32 = sθ cψ, R33 = cθ: the inverse of [`EulerAngles::omega_body`]). φ and ψ are
    /// unwrapped to lie within π of `previous` (continuous over a run).
    /// Upright (sin θ below round-off) only φ + ψ is defined: φ keeps its previous value,
    /// and the rates are reported as φ̇ = 0, ψ̇ = ω·e3*.
    pub fn from_rotation(
        r: &Matrix3<f64>,
        omega_b: &Vector3<f64>,
        previous: Option<&EulerAngles>,
    ) -> Self {
        let sin_theta = norm2(r[(0, 2)], r[(1, 2)]);
        let theta = atan2(sin_theta, r[(2, 2)]);
        let prev_phi = previous.map_or(0.0, |p| p.phi);
        let prev_psi = previous.map_or(0.0, |p| p.psi);
        let upright = sin_theta < UPRIGHT_SIN;
        let (phi, psi) = if upright {
            // θ ≈ 0: R = Rz(φ + ψ);  θ ≈ π: R = Rz(φ − ψ) diag(1, −1, −1). Keep φ.
            let angle = atan2(r[(1, 0)], r[(0, 0)]);
            let psi = if r[(2, 2)] > 0.0 {
                angle - prev_phi
            } else {
                prev_phi - angle
            };
            (prev_phi, unwrap(psi, prev_psi))
        } else {
            (
                unwrap(atan2(r[(0, 2)], -r[(1, 2)]), prev_phi),
                unwrap(atan2(r[(2, 0)], r[(2, 1)]), prev_psi),
            )
        };
        let (theta_dot, phi_dot, psi_dot) = if upright {
            let (sp, cp) = psi.sin_cos();
            (omega_b.x * cp - omega_b.y * sp, 0.0, omega_b.z)
        } else {
            // sin ψ sin θ = R31, cos ψ sin θ = R32 and cos θ = R33: the rates from the
            // rotation's entries, without evaluating sin ψ, cos ψ, cos θ again.
            let (sp_st, cp_st) = (r[(2, 0)], r[(2, 1)]);
            let phi_dot = (omega_b.x * sp_st + omega_b.y * cp_st) / (sin_theta * sin_theta);
            (
                (omega_b.x * cp_st - omega_b.y * sp_st) / sin_theta,
                phi_dot,
                omega_b.z - phi_dot * r[(2, 2)],
            )
        };
        EulerAngles {
            theta,
            phi,
            psi,
            theta_dot,
            phi_dot,
            psi_dot,
        }
    }
}

/// atan2(y, x) in (−π, π] by the `libm` crate (FreeBSD msun's `e_atan2.c` in Rust:
/// atan(|y/x|) by its minimax polynomial, within about 2 ulps of the correctly rounded
/// value). Each output row takes three (θ, φ, ψ); the platform's `atan2` (glibc's, correctly
/// rounded, with its errno wrapper) costs about 145 instructions a call, this one about
/// 100, and it gives the same value on every platform.
#[inline]
fn atan2(y: f64, x: f64) -> f64 {
    libm::atan2(y, x)
}

/// √(a² + b²) of two entries of a rotation (|a|, |b| ≤ 1, so a² + b² cannot overflow):
/// within 1 ulp of `hypot` (two roundings and the square root's), at a fraction of its
/// cost; `hypot` itself where a² + b² < 1e-300 would lose digits to underflow.
#[inline]
fn norm2(a: f64, b: f64) -> f64 {
    let s = a * a + b * b;
    if s >= 1e-300 { s.sqrt() } else { a.hypot(b) }
}

/// The angle equal to `angle` modulo 2π that lies within π of `reference`.
fn unwrap(angle: f64, reference: f64) -> f64 {
    use std::f64::consts::TAU;
    angle + TAU * ((reference - angle) / TAU).round()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Angles → rotation and ω → angles and rates is the identity away from θ = 0, π.
    #[test]
    fn euler_round_trip() {
        for k in 0..200 {
            let x = k as f64;
            let a = EulerAngles {
                theta: 0.01 + 3.1 * (0.37 * x).sin().abs(),
                phi: 3.0 * (0.71 * x).sin(),
                psi: 3.0 * (1.13 * x).cos(),
                theta_dot: (0.3 * x).sin() * 5.0,
                phi_dot: (0.5 * x).cos() * 7.0,
                psi_dot: 60.0 * (0.9 * x).sin(),
            };
            let r = a.rotation().to_rotation_matrix().into_inner();
            let b = EulerAngles::from_rotation(&r, &a.omega_body(), Some(&a));
            for (p, q) in [(a.theta, b.theta), (a.phi, b.phi), (a.psi, b.psi)] {
                assert!((p - q).abs() < 1e-12, "{a:?} -> {b:?}");
            }
            for (p, q) in [
                (a.theta_dot, b.theta_dot),
                (a.phi_dot, b.phi_dot),
                (a.psi_dot, b.psi_dot),
            ] {
                assert!((p - q).abs() < 1e-9 * (1.0 + p.abs()), "{a:?} -> {b:?}");
            }
        }
    }

    /// The rates read from the rotation's entries are the rates through sin ψ, cos ψ and
    /// cos θ of the angles (ψ = atan2(R31, R32), θ = atan2(sin θ, R33)) to round-off:
    /// within a few ulps of |ω|/sin θ (θ̇), |ω|/sin²θ (φ̇) and |ω3| + |φ̇| (ψ̇), from near
    /// upright to near inverted, for rotations made from unit quaternions as a run makes them.
    #[test]
    fn rates_from_entries_are_the_trigonometric_rates_to_round_off() {
        let eps = f64::EPSILON;
        let mut worst = [0.0f64; 3];
        for k in 0..2000 {
            let x = k as f64;
            let q = UnitQuaternion::new_normalize(nalgebra::Quaternion::new(
                (1.3 * x).sin(),
                (0.7 * x).cos(),
                (2.9 * x + 0.3).sin(),
                (0.11 * x * x).cos(),
            ));
            // Every tenth one near upright or inverted (sin θ from 1e-11 to 1e-3).
            let q = if k % 10 == 0 {
                let tilt = 10f64.powf(-11.0 + 8.0 * (0.37 * x).sin().abs());
                let flip = if k % 20 == 0 {
                    std::f64::consts::PI
                } else {
                    0.0
                };
                UnitQuaternion::from_axis_angle(&Vector3::z_axis(), x)
                    * UnitQuaternion::from_axis_angle(&Vector3::x_axis(), flip + tilt)
            } else {
                q
            };
            let r = q.to_rotation_matrix().into_inner();
            let w = Vector3::new(
                3.0 * (0.3 * x).sin(),
                -40.0 * (0.5 * x).cos(),
                180.0 * (0.9 * x).sin(),
            );
            let a = EulerAngles::from_rotation(&r, &w, None);
            let st = r[(0, 2)].hypot(r[(1, 2)]);
            if st < UPRIGHT_SIN {
                continue;
            }
            let (sp, cp) = a.psi.sin_cos();
            let theta_dot = w.x * cp - w.y * sp;
            let phi_dot = (w.x * sp + w.y * cp) / st;
            let psi_dot = w.z - phi_dot * a.theta.cos();
            let scale = [
                w.norm() / st,
                w.norm() / (st * st),
                w.z.abs() + phi_dot.abs(),
            ];
            for (i, (p, q)) in [
                (a.theta_dot, theta_dot),
                (a.phi_dot, phi_dot),
                (a.psi_dot, psi_dot),
            ]
            .into_iter()
            .enumerate()
            {
                let ulps = (p - q).abs() / (eps * scale[i]);
                worst[i] = worst[i].max(ulps);
                assert!(
                    ulps < 16.0,
                    "rate {i} at {r:?}, {w:?}: {p} against {q} ({ulps} ulps)"
                );
            }
        }
        assert!(
            worst.iter().all(|&u| u > 0.0),
            "{worst:?}: no difference at all"
        );
    }

    /// The row's angles through `libm`'s atan2 and √(a² + b²) are those through the
    /// platform's `atan2` and `hypot` to 1e-15 relative (a few ulps), for random rotations
    /// (uniform unit quaternions) and rotations within 1e-14 to 1e-2 rad of upright and of
    /// inverted, tilted either side of the upright branch's threshold, each unwrapped from
    /// a random previous row.
    #[test]
    fn angles_are_the_platform_angles_to_round_off() {
        use std::f64::consts::PI;
        // splitmix64: reproducible uniform draws in [0, 1)
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        let mut uniform = move || {
            seed = seed.wrapping_add(0x9e37_79b9_7f4a_7c15);
            let mut z = seed;
            z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
        };
        let (mut worst, mut differ) = ([0.0f64; 3], 0);
        for k in 0..20_000 {
            let q = if k % 4 == 0 {
                let tilt = 10f64.powf(-14.0 + 12.0 * uniform());
                let flip = if k % 8 == 0 {
                    std::f64::consts::PI
                } else {
                    0.0
                };
                UnitQuaternion::from_axis_angle(&Vector3::z_axis(), 20.0 * uniform() - 10.0)
                    * UnitQuaternion::from_axis_angle(&Vector3::x_axis(), flip + tilt)
                    * UnitQuaternion::from_axis_angle(&Vector3::z_axis(), 20.0 * uniform() - 10.0)
            } else {
                // Gaussian-free uniform rotation (Shoemake's subgroup algorithm)
                let (u1, u2, u3) = (uniform(), 2.0 * PI * uniform(), 2.0 * PI * uniform());
                let (a, b) = ((1.0 - u1).sqrt(), u1.sqrt());
                UnitQuaternion::new_unchecked(Quaternion::new(
                    b * u3.cos(),
                    a * u2.sin(),
                    a * u2.cos(),
                    b * u3.sin(),
                ))
            };
            let r = q.to_rotation_matrix().into_inner();
            let prev = EulerAngles {
                phi: 200.0 * uniform() - 100.0,
                psi: 2000.0 * uniform() - 1000.0,
                ..Default::default()
            };
            let a = EulerAngles::from_rotation(&r, &Vector3::new(1.0, 2.0, 3.0), Some(&prev));
            // the same formulas through the platform's functions
            let st = r[(0, 2)].hypot(r[(1, 2)]);
            let theta = st.atan2(r[(2, 2)]);
            let (phi, psi) = if st < UPRIGHT_SIN {
                let angle = r[(1, 0)].atan2(r[(0, 0)]);
                let psi = if r[(2, 2)] > 0.0 {
                    angle - prev.phi
                } else {
                    prev.phi - angle
                };
                (prev.phi, unwrap(psi, prev.psi))
            } else {
                (
                    unwrap(r[(0, 2)].atan2(-r[(1, 2)]), prev.phi),
                    unwrap(r[(2, 0)].atan2(r[(2, 1)]), prev.psi),
                )
            };
            for (i, (p, q)) in [(a.theta, theta), (a.phi, phi), (a.psi, psi)]
                .into_iter()
                .enumerate()
            {
                let rel = if p == q {
                    0.0
                } else {
                    (p - q).abs() / p.abs().max(q.abs())
                };
                if rel > 0.0 {
                    differ += 1;
                }
                worst[i] = worst[i].max(rel);
                assert!(
                    rel <= 1e-15,
                    "angle {i} of {r:?}: {p} against {q} ({rel:e})"
                );
            }
        }
        // the test compares two implementations, not one with itself
        assert!(differ > 0, "{worst:?}");
    }

    /// Upright, only φ + ψ is defined: φ keeps its previous value, ψ takes the rest, the
    /// rates are (φ̇, ψ̇) = (0, ω3), and angles unwrap continuously across ±π.
    #[test]
    fn upright_and_unwrapping() {
        let prev = EulerAngles {
            phi: 0.4,
            psi: 3.0,
            ..Default::default()
        };
        let up = EulerAngles {
            phi: 0.4,
            psi: 3.0 + 0.3,
            ..Default::default()
        };
        let r = up.rotation().to_rotation_matrix().into_inner();
        let b = EulerAngles::from_rotation(&r, &Vector3::new(0.0, 0.0, 5.0), Some(&prev));
        assert_eq!(b.theta, 0.0);
        assert!(
            (b.phi - 0.4).abs() < 1e-15 && (b.psi - 3.3).abs() < 1e-12,
            "{b:?}"
        );
        assert_eq!((b.phi_dot, b.psi_dot), (0.0, 5.0));
    }
}
