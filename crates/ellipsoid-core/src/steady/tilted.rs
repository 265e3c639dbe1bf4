//! The tilted steady motions of a body of revolution (docs/physics.md, "Steady motions
//! and their stability", "The tilted families"): the axis k at a constant tilt θ from the
//! vertical turns about it at Ω = φ̇, the body spins about k at ψ̇, n = ω·k = Ω cos θ + ψ̇.
//!
//! "precession" (frictionless): G fixed, the contact point on a circle about G's
//! vertical. "rolling-circle" (rolling, or the Coulomb model's rolling phase): Routh's
//! steady rolling, G and the contact point on circles about a common vertical. With
//! (u, w) the contact point's coordinates from G in the meridian plane (u along
//! e = (cos θ k − e3)/sin θ, w along k), s = u cos θ + w sin θ its horizontal offset
//! towards the lean (= dh/dθ) and h = u sin θ − w cos θ the height of G, Euler's
//! equation about G gives N = m g and
//! ```text
//!   F(θ, Ω, n) = Ω sin θ (C n − A Ω cos θ) + m g s + κ m h Ω (n u + Ω w sin θ) = 0,
//! ```
//! κ = 0 frictionless, 1 rolling (the friction force that turns G on its circle).
//!
//! In body axes ζ and ω turn about k at −ψ̇ (ζ̇ = −ψ̇ k × ζ), so the motion is an
//! equilibrium of the reduced field in the frame turning about k at ν = −ψ̇. Three zero
//! eigenvalues there are not the motion's: the turn about k (the body's symmetry) and
//! the two directions of the family (the null space of ∇F).
//!
//! At Ω = 0, F = m g s does not depend on n: where s = 0 (the contact point straight
//! below G, a disc on its edge) every spin is steady, rolling straight on (κ = 1) or
//! spinning in place (κ = 0); the spin is then the scenario's.

use nalgebra::Vector3;

use super::families::{
    Circles, Family, RESIDUAL_TOLERANCE, SteadyMotion, check_derived_rate, check_rate,
};
use super::reduce::{ReducedField, join};
use crate::body::Body;
use crate::error::{Brackets, Digits, ModelError, Value, number};
use crate::geometry::Contact;

/// Which of (θ, Ω, n) a tilted family solves for; the scenario gives the other two
/// (θ = `initial.theta`, Ω = `initial.phi_dot`, n = φ̇ cos θ + ψ̇ of the scenario's rates).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Solve {
    /// The spin n (F is linear in n: one solution).
    #[default]
    Spin,
    /// The precession rate Ω (F is quadratic in Ω: the root nearest the scenario's φ̇).
    PhiDot,
    /// The tilt θ (Newton from the scenario's θ).
    Theta,
}

impl Solve {
    /// The names, as `--solve` and Python's `solve` take them.
    pub const NAMES: [&'static str; 3] = ["spin", "phi_dot", "theta"];

    /// The unknown named `name`, or an error naming the field `solve`.
    pub fn parse(name: &str) -> Result<Self, ModelError> {
        match name {
            "spin" => Ok(Solve::Spin),
            "phi_dot" => Ok(Solve::PhiDot),
            "theta" => Ok(Solve::Theta),
            _ => Err(ModelError::invalid(
                "solve",
                Value::Choice(name.into()),
                format!("must be one of {}", Solve::NAMES.join(", ")),
            )),
        }
    }

    /// Its name.
    pub fn name(self) -> &'static str {
        Solve::NAMES[self as usize]
    }
}

/// Relative tolerance of the body-of-revolution checks.
const REVOLUTION_TOLERANCE: f64 = 1e-12;

/// Smallest sin θ of a tilted steady motion: closer to upright or inverted, the split of
/// the rates into φ̇ and ψ̇ is ill-defined (use "upright" or "inverted").
const MIN_SIN_THETA: f64 = 1e-6;

/// The body and law of a tilted family: the moments A, C, m g and κ.
#[derive(Debug, Clone, Copy)]
pub struct Relation {
    /// Transverse and axial moments of inertia about G [kg m²].
    pub big_a: f64,
    pub big_c: f64,
    /// Mass [kg] and m g [N].
    pub mass: f64,
    pub weight: f64,
    /// 0 frictionless, 1 rolling.
    pub kappa: f64,
}

/// The meridian geometry at tilt θ: where the contact point is, seen from G.
#[derive(Debug, Clone, Copy)]
pub struct Meridian {
    pub theta: f64,
    /// Contact point from G: along e (away from the axis, down-tilt side) and along k [m].
    pub u: f64,
    pub w: f64,
    /// du/dθ, dw/dθ [m/rad].
    pub du: f64,
    pub dw: f64,
}

impl Meridian {
    /// The horizontal offset s = dh/dθ of the contact point from G towards the lean [m].
    pub fn s(&self) -> f64 {
        let (st, ct) = self.theta.sin_cos();
        self.u * ct + self.w * st
    }
    /// The height h of G above the plane [m].
    pub fn h(&self) -> f64 {
        let (st, ct) = self.theta.sin_cos();
        self.u * st - self.w * ct
    }
    /// ds/dθ [m/rad].
    pub fn ds(&self) -> f64 {
        let (st, ct) = self.theta.sin_cos();
        self.du * ct - self.u * st + self.dw * st + self.w * ct
    }
}

impl Relation {
    /// F(θ, Ω, n) and its partial derivatives (F_θ, F_Ω, F_n) (module docs).
    pub fn evaluate(&self, geo: &Meridian, omega: f64, n: f64) -> [f64; 4] {
        let Relation {
            big_a,
            big_c,
            mass,
            weight,
            kappa,
        } = *self;
        let (st, ct) = geo.theta.sin_cos();
        let (u, w, h, s) = (geo.u, geo.w, geo.h(), geo.s());
        let f = omega * st * (big_c * n - big_a * omega * ct)
            + weight * s
            + kappa * mass * h * omega * (n * u + omega * w * st);
        let f_n = omega * (big_c * st + kappa * mass * h * u);
        let f_omega = n * (big_c * st + kappa * mass * h * u)
            + 2.0 * omega * st * (kappa * mass * h * w - big_a * ct);
        // h' = s (the contact point moves along the surface: u' sin θ = w' cos θ).
        let f_theta = omega * ct * (big_c * n - big_a * omega * ct)
            + big_a * omega * omega * st * st
            + weight * geo.ds()
            + kappa
                * mass
                * omega
                * (s * (n * u + omega * w * st)
                    + h * (n * geo.du + omega * (geo.dw * st + w * ct)));
        [f, f_theta, f_omega, f_n]
    }
}

/// ζ0 = (sin θ sin ψ, sin θ cos ψ, cos θ), world up in body axes.
pub fn zeta_at(theta: f64, psi: f64) -> Vector3<f64> {
    let (st, ct) = theta.sin_cos();
    let (sp, cp) = psi.sin_cos();
    Vector3::new(st * sp, st * cp, ct)
}

/// The meridian geometry of `body` at tilt θ and yaw ψ about its axis.
pub fn meridian(body: &Body, theta: f64, psi: f64) -> Meridian {
    let zeta = zeta_at(theta, psi);
    let k = Vector3::z();
    let (st, ct) = theta.sin_cos();
    let e = (k * ct - zeta) / st;
    let t_theta = (zeta * ct - k) / st;
    // ζ × ω = dζ/dθ for ω = t × ζ: the contact's ṙ = −H ζ̇ is then dr/dθ.
    let c = Contact::new(body, zeta, t_theta.cross(&zeta));
    Meridian {
        theta,
        u: c.r.dot(&e),
        w: c.r.z,
        du: c.r_dot_surface.dot(&e),
        dw: c.r_dot_surface.z,
    }
}

/// The relation's constants for `field`'s body under `family`, or why the family does
/// not apply: the body must be of revolution about its c axis, G and the contact spheres
/// on that axis; "precession" needs the frictionless law, "rolling-circle" a rolling one.
pub fn relation(field: &ReducedField, family: Family) -> Result<Relation, ModelError> {
    let body = field.body();
    check_revolution(body)?;
    let kappa = match (family, field) {
        (Family::Precession, ReducedField::Frictionless(_)) => 0.0,
        (Family::RollingCircle, ReducedField::Rolling(..)) => 1.0,
        (Family::Precession, _) => {
            return Err(ModelError::invalid(
                "contact.model",
                Value::Text("a rolling contact".into()),
                "the precession family (G fixed) is frictionless: use model = \"frictionless\", or the family \"rolling-circle\" for rolling",
            ));
        }
        _ => {
            return Err(ModelError::invalid(
                "contact.model",
                Value::Choice("frictionless".into()),
                "the rolling-circle family rolls without slip: use model = \"rolling\" or \"coulomb\", or the family \"precession\" without friction",
            ));
        }
    };
    let i = body.inertia();
    Ok(Relation {
        big_a: i[(0, 0)],
        big_c: i[(2, 2)],
        mass: body.mass(),
        weight: body.mass() * field.gravity(),
        kappa,
    })
}

/// A body of revolution about its c axis: a = b, inertia diag(A, A, C), G and the
/// contact spheres' centres on the axis.
fn check_revolution(body: &Body) -> Result<(), ModelError> {
    let tol = REVOLUTION_TOLERANCE;
    let ax = body.semi_axes();
    if (ax.x - ax.y).abs() > tol * ax.max() {
        return Err(ModelError::invalid(
            "body.b",
            ax.y,
            format!(
                "the tilted families need a body of revolution about its c axis: b must equal a = {}",
                number(ax.x)
            ),
        ));
    }
    let i = body.inertia();
    let scale = i.norm();
    if (i[(0, 0)] - i[(1, 1)]).abs() > tol * scale
        || i[(0, 1)].abs().max(i[(0, 2)].abs()).max(i[(1, 2)].abs()) > tol * scale
    {
        return Err(ModelError::invalid(
            "body.inertia",
            Value::Matrix(Box::new(*i), Digits::Plain),
            "the tilted families need a body of revolution about its c axis: inertia diag(A, A, C)",
        ));
    }
    let g = body.com_offset();
    if g.x.abs().max(g.y.abs()) > tol * ax.max() {
        return Err(ModelError::invalid(
            "body.com_offset",
            Value::Numbers {
                values: g.as_slice().to_vec(),
                digits: Digits::Plain,
                brackets: Brackets::Round,
            },
            "the tilted families need G on the body's c axis",
        ));
    }
    if let Some(sp) = body
        .spheres()
        .iter()
        .find(|sp| sp.center.x.abs().max(sp.center.y.abs()) > tol * ax.max())
    {
        return Err(ModelError::invalid(
            format!("body.spheres.{}.center", sp.name),
            Value::Numbers {
                values: sp.center.as_slice().to_vec(),
                digits: Digits::Plain,
                brackets: Brackets::Round,
            },
            "the tilted families need the contact spheres' centres on the body's c axis",
        ));
    }
    Ok(())
}

/// The spin n = ω·k of the steady motion of `rel` at tilt θ and precession rate Ω:
/// F is linear in n (module docs).
pub fn solve_spin(rel: &Relation, geo: &Meridian, omega: f64) -> Result<f64, ModelError> {
    let [f0, _, _, f_n] = rel.evaluate(geo, omega, 0.0);
    let n = -f0 / f_n;
    if !n.is_finite() {
        return Err(ModelError::invalid(
            "initial.phi_dot",
            omega,
            format!(
                "no steady motion at this precession rate and tilt θ = {} rad: the spin would be infinite (a tilted body without precession falls)",
                number(geo.theta)
            ),
        ));
    }
    Ok(n)
}

/// The precession rate Ω of the steady motion of `rel` at tilt θ and spin n nearest
/// `guess`: F is quadratic in Ω, a₂Ω² + a₁Ω + a₀ with a₂ = sin θ (κ m h w − A cos θ),
/// a₁ = n (C sin θ + κ m h u), a₀ = m g s (module docs).
pub fn solve_precession(
    rel: &Relation,
    geo: &Meridian,
    n: f64,
    guess: f64,
) -> Result<f64, ModelError> {
    let st = geo.theta.sin();
    let (h, u, w) = (geo.h(), geo.u, geo.w);
    let a2 = st * (rel.kappa * rel.mass * h * w - rel.big_a * geo.theta.cos());
    let b = rel.big_c * st + rel.kappa * rel.mass * h * u;
    let a1 = n * b;
    let a0 = rel.weight * geo.s();
    let disc = a1 * a1 - 4.0 * a2 * a0;
    let none = |why: String| {
        ModelError::invalid(
            "initial.psi_dot",
            n - guess * geo.theta.cos(),
            format!(
                "no steady precession at tilt θ = {} rad and spin n = {} rad/s: {why}",
                number(geo.theta),
                number(n)
            ),
        )
    };
    if disc < 0.0 {
        let n_min = (4.0 * a2 * a0).sqrt() / b.abs();
        return Err(none(format!(
            "the spin must be at least {} rad/s in magnitude",
            number(n_min)
        )));
    }
    // The roots without cancellation: q = −(a₁ + sign(a₁)√disc)/2, Ω = q/a₂ and a₀/q.
    let q = -0.5 * (a1 + a1.signum() * disc.sqrt());
    let roots = [q / a2, a0 / q];
    roots
        .into_iter()
        .filter(|r| r.is_finite() && *r != 0.0)
        .min_by(|x, y| (x - guess).abs().total_cmp(&(y - guess).abs()))
        .ok_or_else(|| none("the precession rate would be zero or infinite".into()))
}

/// The tilt θ of the steady motion of `rel` at precession rate Ω and spin n, by Newton
/// on F(θ) from `guess` (F_θ analytic), each step kept inside (0, π).
pub fn solve_tilt(
    rel: &Relation,
    body: &Body,
    psi: f64,
    omega: f64,
    n: f64,
    guess: f64,
) -> Result<f64, ModelError> {
    let mut theta = guess;
    for _ in 0..60 {
        let geo = meridian(body, theta, psi);
        let [f, f_theta, _, _] = rel.evaluate(&geo, omega, n);
        let mut step = -f / f_theta;
        if !step.is_finite() {
            break;
        }
        while !(theta + step > 0.0 && theta + step < std::f64::consts::PI) {
            step *= 0.5;
        }
        theta += step;
        // Newton converges quadratically: after a step of 1e-13, θ is at round-off.
        if step.abs() <= 1e-13 * theta {
            return Ok(theta);
        }
    }
    Err(ModelError::invalid(
        "initial.theta",
        guess,
        format!(
            "no tilted steady motion with precession rate {} rad/s and spin {} rad/s was found from this tilt",
            number(omega),
            number(n)
        ),
    ))
}

/// The steady motion of `family` at tilt θ, yaw ψ about the axis (a symmetry: it only
/// chooses the coordinates), precession rate Ω and spin n (which must satisfy F = 0;
/// checked on the simulator's field).
pub fn motion(
    field: &ReducedField,
    family: Family,
    rel: &Relation,
    (theta, psi): (f64, f64),
    omega: f64,
    n: f64,
) -> Result<SteadyMotion, ModelError> {
    let body = field.body();
    let geo = meridian(body, theta, psi);
    let [_, f_theta, f_omega, f_n] = rel.evaluate(&geo, omega, n);
    let k = Vector3::z();
    let zeta = zeta_at(theta, psi);
    let (st, ct) = theta.sin_cos();
    let psi_dot = n - omega * ct;
    let w0 = zeta * omega + k * psi_dot;
    check_derived_rate(body, field.gravity(), "angular velocity |ω0|", w0.norm())?;
    let at = join(&zeta, &w0);
    // In the frame turning about k at ν = −ψ̇ the motion is an equilibrium.
    let nu = -psi_dot;
    let turning = join(&k.cross(&zeta), &k.cross(&w0));
    let rate = field.rate(&at) - turning * nu;
    let scale_omega = w0
        .norm()
        .max((field.gravity() / body.semi_axes().max()).sqrt());
    let residual = rate.amax() / (scale_omega * scale_omega);
    if !(residual <= RESIDUAL_TOLERANCE) {
        return Err(ModelError::invalid(
            "initial",
            Value::Named {
                name: "|f(x0)|",
                value: residual,
                unit: "of the field's scale",
            },
            format!("the {} motion is not steady for this body", family.name()),
        ));
    }
    let force = field.force(&at);
    if !(force.z > 0.0) {
        return Err(ModelError::derived(
            "initial",
            "normal force N",
            force.z,
            format!(
                "the plane must push on the body in the {} steady motion",
                family.name()
            ),
        ));
    }
    super::families::check_lowest(body, &zeta, |rule| {
        ModelError::invalid("initial.theta", theta, rule)
    })?;
    // The family's tangents: the derivatives of x0 along the null space of ∇F.
    let t_theta = (zeta * ct - k) / st;
    let Some(tangents) = family_tangents([f_theta, f_omega, f_n], scale_omega) else {
        return Err(ModelError::invalid(
            "initial.theta",
            theta,
            format!(
                "the {} family is singular at this tilt: ∇F = 0, so its neighbours are not a surface through this motion",
                family.name()
            ),
        ));
    };
    let [d_theta, d_omega] = tangents.map(|[dt, dw, dn]| {
        join(
            &(t_theta * dt),
            &((t_theta * omega + k * (omega * st)) * dt + (zeta - k * ct) * dw + k * dn),
        )
    });
    // G's velocity −ω × r (rolling) is constant in the turning frame: G circles at
    // radius |v_G/Ω|, the contact point at |v_G/Ω + s| about the same vertical; at Ω = 0
    // G rests (frictionless) or goes straight on (rolling: radii infinite).
    let speed = rel.kappa * -(n * geo.u + omega * geo.w * st);
    let circles = if speed == 0.0 {
        Circles {
            center: 0.0,
            contact: geo.s().abs(),
        }
    } else {
        Circles {
            center: (speed / omega).abs(),
            contact: (speed / omega + geo.s()).abs(),
        }
    };
    Ok(SteadyMotion {
        family,
        surface: body.surface(),
        at,
        spin: n,
        theta,
        normal_force: force.z,
        cone_margin: field.friction().map(|mu| mu * force.z - force.xy().norm()),
        removed: vec![turning, d_theta, d_omega],
        frame_rate: nu,
        precession: Some(omega),
        circles: Some(circles),
        residual,
    })
}

/// Two directions (dθ, dΩ, dn) spanning the null space of ∇F = (F_θ, F_Ω, F_n): the
/// family's tangents, along which F stays 0 to first order. The component of ∇F largest
/// with the rates in units of `rate` [rad/s] (so that the three compare) is solved for,
/// each of the other two taken as 1 in turn. Where that is the spin (F_n), these are
/// d/dθ and d/dΩ with n following; at Ω = 0, where F_n = Ω (C sin θ + κ m h u)
/// vanishes, they are d/dn and a turn of θ and Ω together. None where ∇F = 0.
fn family_tangents(grad: [f64; 3], rate: f64) -> Option<[[f64; 3]; 2]> {
    let scaled = [grad[0], grad[1] * rate, grad[2] * rate];
    let pivot = (0..3).max_by(|&i, &j| scaled[i].abs().total_cmp(&scaled[j].abs()))?;
    if !(scaled[pivot].abs() > 0.0 && scaled.iter().all(|g| g.is_finite())) {
        return None;
    }
    let tangent = |j: usize| {
        let mut v = [0.0; 3];
        v[j] = 1.0;
        v[pivot] = -grad[j] / grad[pivot];
        v
    };
    let mut free = (0..3).filter(|&j| j != pivot);
    Some([tangent(free.next()?), tangent(free.next()?)])
}

/// Checks the tilt of a tilted family: strictly between upright and inverted.
pub fn check_tilt(theta: f64) -> Result<(), ModelError> {
    if !(theta.is_finite()
        && theta.sin() >= MIN_SIN_THETA
        && theta > 0.0
        && theta < std::f64::consts::PI)
    {
        return Err(ModelError::invalid(
            "initial.theta",
            theta,
            "a tilted family needs 0 < θ < π (sin θ ≥ 1e-6); θ = 0 and π are the families \"upright\" and \"inverted\"",
        ));
    }
    Ok(())
}

/// The steady motion of `family` that the scene's angles define: two of the tilt θ, the
/// precession rate Ω = φ̇ and the spin n = φ̇ cos θ + ψ̇ given, the one `solve` names
/// solved for; the yaw ψ about the axis only chooses the body axes.
pub fn from_angles(
    field: &ReducedField,
    family: Family,
    angles: &crate::state::EulerAngles,
    solve: Solve,
) -> Result<SteadyMotion, ModelError> {
    let rel = relation(field, family)?;
    check_tilt(angles.theta)?;
    let body = field.body();
    let (theta, psi) = (angles.theta, angles.psi);
    let spin = angles.phi_dot * theta.cos() + angles.psi_dot;
    // The given rates, before any is solved for.
    if solve != Solve::PhiDot {
        check_rate(body, field.gravity(), angles.phi_dot, |rule| {
            ModelError::invalid("initial.phi_dot", angles.phi_dot, rule)
        })?;
    }
    if solve != Solve::Spin {
        check_derived_rate(body, field.gravity(), "spin n", spin)?;
    }
    let (theta, omega, n) = match solve {
        Solve::Spin if angles.phi_dot == 0.0 => {
            // F = m g s(θ) does not depend on n: every spin is steady where s = 0.
            let s = meridian(body, theta, psi).s();
            if !(s.abs() <= REVOLUTION_TOLERANCE * body.semi_axes().max()) {
                return Err(ModelError::invalid(
                    "initial.theta",
                    theta,
                    format!(
                        "at phi_dot = 0 a {} motion is steady only where the contact point is straight below G, with the spin free; here it is {} m from G's vertical (solve = \"theta\" finds the tilt)",
                        family.name(),
                        number(s)
                    ),
                ));
            }
            check_derived_rate(body, field.gravity(), "spin n", spin)?;
            (theta, 0.0, spin)
        }
        Solve::Spin => {
            let n = solve_spin(&rel, &meridian(body, theta, psi), angles.phi_dot)?;
            (theta, angles.phi_dot, n)
        }
        Solve::PhiDot => {
            let geo = meridian(body, theta, psi);
            let omega = solve_precession(&rel, &geo, spin, angles.phi_dot)?;
            (theta, omega, spin)
        }
        Solve::Theta => {
            let theta = solve_tilt(&rel, body, psi, angles.phi_dot, spin, theta)?;
            check_tilt(theta)?;
            (theta, angles.phi_dot, spin)
        }
    };
    motion(field, family, &rel, (theta, psi), omega, n)
}
