//! Rigid-body impact at one contact point with the plane z = 0, integrated in normal
//! impulse (Keller 1986; Stronge, *Impact Mechanics*, 2000) with Coulomb friction and
//! Stronge's energetic coefficient of restitution (docs/physics.md, "Impact at
//! touchdown"):
//! ```text
//!   v_C(P) = v_C⁻ + K P,       K = 𝟙/m − [r]× I⁻¹ [r]×          (SPD, world frame)
//!   slip:   dP/dp = e3 − μ ŝ,  ŝ = v_t/|v_t|                       (ŝ may curve)
//!   stop:   stick if |K_tt⁻¹ k_tn| ≤ μ, else slide on along the constant ray
//!   end:    W_n(p_f) − W_n(p_c) = −e² W_n(p_c),  W_n(p) = ∫₀ᵖ v_n dp', v_n(p_c) = 0
//! ```
//! Energy never increases: T⁺ − T⁻ = W_n(p_f) − ∫ μ|v_t| dp = (1 − e²) W_n(p_c) − W_f ≤ 0.
//! The frictionless law is μ = 0; the no-slip law is the limit μ → ∞, in which the
//! tangential impulse is spent at zero normal impulse (see [`Tangential::NoSlip`]).
//! No heap allocation; a bounded number of phases (one curving slip, then stick or one
//! straight slip) and of integration steps.

use nalgebra::{Matrix2, Matrix3, Vector2, Vector3};

mod contacts;
mod slip;

pub use contacts::{ContactsImpact, resolve_contacts};

use slip::{Drive, SlipEnd};

/// Tangential law at the impact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Tangential {
    /// No tangential impulse: P = p e3.
    Frictionless,
    /// Coulomb friction |dP_t| ≤ μ dp, opposing the slip while it slips.
    Coulomb {
        /// μ ≥ 0 \[1\].
        friction: f64,
    },
    /// Unbounded friction, the limit μ → ∞ of [`Tangential::Coulomb`]: the slip is
    /// removed by a tangential impulse at zero normal impulse (its path opposing the
    /// slip), then the contact sticks.
    NoSlip,
}

/// The body at the instant of impact, world frame, SI units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Approach {
    /// m \[kg\].
    pub mass: f64,
    /// World inverse central inertia R I_b⁻¹ Rᵀ \[1/(kg·m²)\].
    pub inertia_inv: Matrix3<f64>,
    /// Lever arm r = C − G, world \[m\].
    pub r: Vector3<f64>,
    /// Velocity of G \[m/s\].
    pub v_g: Vector3<f64>,
    /// Angular velocity, world \[rad/s\].
    pub omega: Vector3<f64>,
}

/// The outcome of [`resolve`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Impact {
    /// Post-impact velocity of G, world \[m/s\].
    pub v_g: Vector3<f64>,
    /// Post-impact angular velocity, world \[rad/s\].
    pub omega: Vector3<f64>,
    /// Total impulse P at C, world \[N·s\]; P·e3 = p_f ≥ 0.
    pub impulse: Vector3<f64>,
    /// Kinetic energy before − after \[J\], ≥ 0 (see [`resolve`] for the round-off bound).
    pub energy_loss: f64,
    /// The tangential slip of the contact point is zero at the end.
    pub stuck: bool,
    /// v_n = e3·v_C before and after \[m/s\].
    pub normal_velocity: (f64, f64),
    /// W_n(p_c) = ∫₀^p_c v_n dp ≤ 0, the normal work of compression \[J\].
    pub compression_work: f64,
    /// W_n(p_f) − W_n(p_c) = −e² W_n(p_c) ≥ 0, the normal work of restitution \[J\].
    pub restitution_work: f64,
    /// ∫ |v_t| |dP_t| ≥ 0, the work dissipated by friction \[J\].
    pub friction_work: f64,
    /// Normal impulse at which the slip stopped, if it did (0 for NoSlip) \[N·s\].
    pub slip_stop: Option<f64>,
    /// Integration steps spent on the curving slip (0 when the law is closed-form).
    pub steps: u32,
}

/// Relative slip below which the contact counts as not slipping: |v_t| ≤ SLIP_TOL |v_C⁻|.
/// A hundred times the slip integration's tolerance (1e-13 on P, so ~1e-13 |v_C⁻| on
/// v_t): below it the computed slip is integration noise, and near an attracting slip
/// direction the numerical slip chatters there instead of reaching zero. Taking the stop
/// early changes the result by O(SLIP_TOL |v_C⁻|) (docs/physics.md).
pub const SLIP_TOL: f64 = 1e-11;

/// Resolves the impact of `body` on the plane with the tangential law and Stronge's
/// energetic coefficient of restitution e ∈ \[0, 1\] (docs/physics.md, "Impact at
/// touchdown"). No impact (zero impulse) unless the contact approaches, v_n⁻ < 0.
///
/// `energy_loss` = −P·(v_C⁻ + v_C⁺)/2, the exact kinetic-energy change of an impulse. A
/// negative value within 64 ε |P| (|v_C⁻| + |v_C⁺|) (its round-off bound) is reported as
/// 0; anything below that is returned as it is, never hidden.
pub fn resolve(body: &Approach, tangential: Tangential, restitution: f64) -> Impact {
    debug_assert!(body.mass > 0.0, "mass {}", body.mass);
    debug_assert!((0.0..=1.0).contains(&restitution), "e = {restitution}");
    let e = restitution.clamp(0.0, 1.0);
    let contact = Contact::new(body);
    let v_n = contact.v0.z;
    if !(v_n < 0.0) {
        return Impact::none(body, v_n);
    }
    match tangential {
        Tangential::Frictionless => frictionless(body, &contact, e),
        Tangential::Coulomb { friction } if !(friction > 0.0) => frictionless(body, &contact, e),
        Tangential::Coulomb { friction } => with_friction(body, &contact, e, Some(friction)),
        Tangential::NoSlip => with_friction(body, &contact, e, None),
    }
}

/// The contact-point velocity as a linear function of the impulse, v_C(P) = v0 + K P.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Contact {
    /// Inverse effective mass K = 𝟙/m − [r]× I⁻¹ [r]× \[1/kg\].
    pub k: Matrix3<f64>,
    /// v_C⁻ = v_G + ω × r \[m/s\].
    pub v0: Vector3<f64>,
    /// Slip below which the contact point is taken as not slipping \[m/s\].
    pub slip_tol: f64,
}

impl Contact {
    fn new(body: &Approach) -> Self {
        let rx = body.r.cross_matrix();
        let k = Matrix3::identity() / body.mass - rx * body.inertia_inv * rx;
        // exactly symmetric, so K_tt's eigen-decomposition and the Schur rate are clean
        let k = (k + k.transpose()) * 0.5;
        let v0 = body.v_g + body.omega.cross(&body.r);
        Contact {
            k,
            v0,
            slip_tol: SLIP_TOL * v0.norm(),
        }
    }

    pub fn velocity(&self, p: &Vector3<f64>) -> Vector3<f64> {
        self.v0 + self.k * p
    }

    /// K_tt, the tangential block.
    fn k_tt(&self) -> Matrix2<f64> {
        self.k.fixed_view::<2, 2>(0, 0).into_owned()
    }

    /// k_tn, the coupling of the normal impulse into the slip.
    fn k_tn(&self) -> Vector2<f64> {
        self.k.fixed_view::<2, 1>(0, 2).into_owned()
    }

    /// Tangential impulse rate that keeps v_t = 0: a = −K_tt⁻¹ k_tn.
    fn sticking_rate(&self) -> Vector2<f64> {
        let kt = self.k_tt();
        kt.cholesky()
            .map_or(Vector2::zeros(), |c| -c.solve(&self.k_tn()))
    }

    /// Tangential impulse that removes a slip u at fixed normal impulse: −K_tt⁻¹ u.
    fn slip_removal(&self, u: &Vector2<f64>) -> Vector2<f64> {
        self.k_tt()
            .cholesky()
            .map_or(Vector2::zeros(), |c| -c.solve(u))
    }
}

/// Frictionless (μ = 0): dv_n/dp = K_nn, so p_f = −(1 + e) v_n⁻ / K_nn and v_n⁺ = −e v_n⁻.
fn frictionless(body: &Approach, contact: &Contact, e: f64) -> Impact {
    let end = Normal::start(contact.v0.z, contact.k[(2, 2)]).finish(e);
    let p = Vector3::new(0.0, 0.0, end.impulse);
    Impact::from_impulse(body, contact, p, end, 0.0, None, 0)
}

/// Coulomb friction μ (`Some`) or its limit μ → ∞ (`None`): a curving slip phase
/// integrated in p (or, for μ → ∞, in the tangential impulse at p = 0), then after a slip
/// stop a straight phase, stick or slip along a constant ray, in closed form.
fn with_friction(body: &Approach, contact: &Contact, e: f64, friction: Option<f64>) -> Impact {
    let drive = match friction {
        Some(mu) => Drive {
            friction: mu,
            normal: 1.0,
        },
        None => Drive {
            friction: 1.0,
            normal: 0.0,
        },
    };
    let run = slip::integrate(contact, drive, e);
    let mut p = Vector3::new(run.impulse_t.x, run.impulse_t.y, drive.normal * run.sigma);
    let mut friction_work = run.friction_work;
    let (mut normal, slip_stop) = match friction {
        Some(_) => (
            run.normal,
            (run.end == SlipEnd::Stopped).then_some(run.sigma),
        ),
        // μ → ∞: the normal impulse and its work are zero during the slip
        None => (
            run.normal.scaled_to_zero(),
            (run.end == SlipEnd::Stopped).then_some(0.0),
        ),
    };
    if run.end == SlipEnd::Ended {
        return Impact::from_impulse(body, contact, p, normal, friction_work, None, run.steps);
    }
    // The slip stopped: remove the residual below SLIP_TOL exactly, booking its loss.
    let residual = contact.velocity(&p).xy();
    let dp_t = contact.slip_removal(&residual);
    p.x += dp_t.x;
    p.y += dp_t.y;
    friction_work -= 0.5 * residual.dot(&dp_t);
    let ray = after_stop(contact, friction);
    let direction = Vector3::new(ray.rate.x, ray.rate.y, 1.0);
    normal.velocity = contact.velocity(&p).z;
    normal.rate = (contact.k * direction).z;
    let end = normal.finish(e);
    let dp = end.impulse - normal.impulse;
    p += direction * dp;
    friction_work += friction.unwrap_or(0.0) * ray.slip_rate * 0.5 * dp * dp;
    Impact::from_impulse(body, contact, p, end, friction_work, slip_stop, run.steps)
}

/// The straight phase after a slip stop: dP_t/dp = `rate`, slip |v_t| = `slip_rate` (p − p_s).
struct Ray {
    rate: Vector2<f64>,
    slip_rate: f64,
}

/// Stick if the sticking rate a = −K_tt⁻¹ k_tn lies in the cone |a| ≤ μ (always for
/// μ → ∞); else slip resumes along the unique ŝ with −μ K_tt ŝ + k_tn = λ ŝ, λ > 0
/// (Stronge 2000 ch. 8; Bhatt & Koechling 1995): ŝ = (λ𝟙 + μ K_tt)⁻¹ k_tn, |ŝ| = 1.
fn after_stop(contact: &Contact, friction: Option<f64>) -> Ray {
    let stick = contact.sticking_rate();
    let Some(mu) = friction.filter(|&mu| stick.norm() > mu) else {
        return Ray {
            rate: stick,
            slip_rate: 0.0,
        };
    };
    let (lambda, s_hat) = ray_direction(&contact.k_tt(), &contact.k_tn(), mu);
    Ray {
        rate: -mu * s_hat,
        slip_rate: lambda,
    }
}

/// Solves |(λ𝟙 + μ K_tt)⁻¹ k| = 1 for λ > 0 (the left side falls monotonically from
/// |K_tt⁻¹ k|/μ > 1 to 0) in K_tt's eigenbasis, by Newton on 1/|x(λ)| − 1 (the
/// trust-region secular equation's well-conditioned form) kept inside a bracket.
fn ray_direction(k_tt: &Matrix2<f64>, k: &Vector2<f64>, mu: f64) -> (f64, Vector2<f64>) {
    let eig = k_tt.symmetric_eigen();
    let q = eig.eigenvectors.transpose() * k;
    let x = |lambda: f64| {
        Vector2::new(
            q.x / (lambda + mu * eig.eigenvalues.x),
            q.y / (lambda + mu * eig.eigenvalues.y),
        )
    };
    let (mut lo, mut hi) = (0.0, k.norm());
    let mut lambda = 0.0;
    for _ in 0..200 {
        let xv = x(lambda);
        let n = xv.norm();
        let phi = 1.0 / n - 1.0;
        if phi < 0.0 {
            lo = lambda
        } else {
            hi = lambda
        }
        // d|x|/dλ = −Σ x_i² / (λ + μκ_i) / |x|
        let d_norm = -(xv.x * xv.x / (lambda + mu * eig.eigenvalues.x)
            + xv.y * xv.y / (lambda + mu * eig.eigenvalues.y))
            / n;
        let d_phi = -d_norm / (n * n);
        let mut next = lambda - phi / d_phi;
        if !(next > lo && next < hi) {
            next = 0.5 * (lo + hi);
        }
        if (next - lambda).abs() <= 4.0 * f64::EPSILON * next {
            lambda = next;
            break;
        }
        lambda = next;
    }
    let s = eig.eigenvectors * x(lambda);
    (lambda, s / s.norm())
}

/// The normal progress of the impact: v_n and W_n at impulse p, and whether (and with
/// what work W_n(p_c)) the compression has ended.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Normal {
    pub impulse: f64,
    pub velocity: f64,
    pub work: f64,
    pub compression: Option<f64>,
    /// dv_n/dp of the current straight phase \[1/kg\].
    pub rate: f64,
}

impl Normal {
    fn start(v_n: f64, rate: f64) -> Self {
        Normal {
            impulse: 0.0,
            velocity: v_n,
            work: 0.0,
            compression: None,
            rate,
        }
    }

    /// μ → ∞: the curving slip happened at p = 0 and did no normal work.
    fn scaled_to_zero(self) -> Self {
        Normal {
            impulse: 0.0,
            work: 0.0,
            compression: self.compression.map(|_| 0.0),
            ..self
        }
    }

    /// Restitution ends where W_n = (1 − e²) W_n(p_c).
    pub fn target(compression: f64, e: f64) -> f64 {
        (1.0 - e * e) * compression
    }

    /// Runs a straight phase, v_n = v + c x, W_n = W + v x + c x²/2 (x = p − p_now, c > 0),
    /// to the end of restitution: compression at x_c = −v/c with W_c = W − v²/(2c), then
    /// x = x_c + e √(−2 W_c / c); or, compression already over, the root of
    /// W_n(x) = (1 − e²) W_c, x = 2d / (v + √(v² + 2cd)), d = target − W.
    fn finish(self, e: f64) -> Self {
        let c = self.rate;
        let (v, w) = (self.velocity, self.work);
        let (compression, x) = match self.compression {
            None => {
                let x_c = (-v / c).max(0.0);
                let w_c = (w - 0.5 * v * v / c).min(w);
                (w_c, x_c + e * (-2.0 * w_c / c).max(0.0).sqrt())
            }
            Some(w_c) => {
                let d = (Self::target(w_c, e) - w).max(0.0);
                let root = (v * v + 2.0 * c * d).sqrt();
                let x = if v >= 0.0 {
                    2.0 * d / (v + root)
                } else {
                    (root - v) / c
                };
                (w_c, if x.is_finite() { x } else { 0.0 })
            }
        };
        Normal {
            impulse: self.impulse + x,
            velocity: v + c * x,
            work: w + v * x + 0.5 * c * x * x,
            compression: Some(compression),
            rate: c,
        }
    }
}

impl Impact {
    fn none(body: &Approach, v_n: f64) -> Self {
        Impact {
            v_g: body.v_g,
            omega: body.omega,
            impulse: Vector3::zeros(),
            energy_loss: 0.0,
            stuck: false,
            normal_velocity: (v_n, v_n),
            compression_work: 0.0,
            restitution_work: 0.0,
            friction_work: 0.0,
            slip_stop: None,
            steps: 0,
        }
    }

    /// v_G⁺ = v_G⁻ + P/m, ω⁺ = ω⁻ + I⁻¹ (r × P); ΔT = P·(v_C⁻ + v_C⁺)/2.
    fn from_impulse(
        body: &Approach,
        contact: &Contact,
        p: Vector3<f64>,
        normal: Normal,
        friction_work: f64,
        slip_stop: Option<f64>,
        steps: u32,
    ) -> Self {
        let v_after = contact.velocity(&p);
        let mean = 0.5 * (contact.v0 + v_after);
        let mut loss = -p.dot(&mean);
        let round_off = 64.0 * f64::EPSILON * p.norm() * (contact.v0.norm() + v_after.norm());
        if loss < 0.0 && loss > -round_off {
            loss = 0.0;
        }
        let w_c = normal.compression.unwrap_or(0.0);
        Impact {
            v_g: body.v_g + p / body.mass,
            omega: body.omega + body.inertia_inv * body.r.cross(&p),
            impulse: p,
            energy_loss: loss,
            stuck: v_after.xy().norm() <= contact.slip_tol,
            normal_velocity: (contact.v0.z, v_after.z),
            compression_work: w_c,
            restitution_work: normal.work - w_c,
            friction_work,
            slip_stop,
            steps,
        }
    }
}
