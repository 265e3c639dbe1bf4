//! Steady motions: the states that are equilibria of the reduced field, i.e. motions
//! steady up to the plane's symmetries (docs/physics.md, "Steady motions and their
//! stability", "Families").
//!
//! "upright" and "inverted": the body spins at n about the vertical in a rest attitude
//! ζ0, one where the contact point is directly below G (r ∥ ζ0, a critical point of
//! G's height h(ζ)), so ω0 = n ζ0. It is steady at every n exactly when ζ0 is a
//! principal axis of inertia (ω × Iω = n² ζ0 × Iζ0 = 0). "upright" is the rest attitude
//! nearest ζ = +e3 (the body's c axis up, the paper's θ = 0), "inverted" the one nearest
//! −e3 (θ = π). The family's parameter is n; x0(n) = (ζ0, n ζ0), so the family's
//! direction in reduced coordinates is (0, 0, ζ0).
//!
//! "precession" and "rolling-circle", the tilted motions of a body of revolution, are in
//! [`super::tilted`].

use nalgebra::{Matrix2, Vector2, Vector3};

use super::linearize::tangent_basis;
use super::reduce::{Phase, ReducedField, join};
use super::tilted::Solve;
use crate::body::{Body, Surface};
use crate::error::{Brackets, Digits, ModelError, Value, number};
use crate::geometry::{Contact, hessian};
use crate::simulate::{ContactModel, Scene};

/// A family of steady motions (`ellipsoid steady --family`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Family {
    /// Spinning about the vertical in the rest attitude nearest the c axis up.
    Upright,
    /// The same nearest the c axis down.
    Inverted,
    /// Frictionless precession of a tilted body of revolution (G fixed).
    Precession,
    /// Routh's steady rolling of a tilted body of revolution on a circle.
    RollingCircle,
}

impl Family {
    /// The names, as `--family` and Python's `family` take them.
    pub const NAMES: [&'static str; 4] = ["upright", "inverted", "precession", "rolling-circle"];

    /// The family named `name`, or an error naming the field `family`.
    pub fn parse(name: &str) -> Result<Self, ModelError> {
        match name {
            "upright" => Ok(Family::Upright),
            "inverted" => Ok(Family::Inverted),
            "precession" => Ok(Family::Precession),
            "rolling-circle" => Ok(Family::RollingCircle),
            _ => Err(ModelError::invalid(
                "family",
                Value::Choice(name.into()),
                format!("must be one of {}", Family::NAMES.join(", ")),
            )),
        }
    }

    /// Whether it is one of the tilted families of a body of revolution (`tilted`).
    pub fn tilted(self) -> bool {
        matches!(self, Family::Precession | Family::RollingCircle)
    }

    /// How many eigenvalues its spectrum has: 4 upright and inverted, 2 tilted (three
    /// more zeros removed: the axial turn and the family's two tangents).
    pub fn modes(self) -> usize {
        if self.tilted() { 2 } else { 4 }
    }

    /// Its name.
    pub fn name(self) -> &'static str {
        match self {
            Family::Upright => "upright",
            Family::Inverted => "inverted",
            Family::Precession => "precession",
            Family::RollingCircle => "rolling-circle",
        }
    }
}

/// The circles of a tilted steady motion, about a common vertical.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Circles {
    /// Radius of G's circle \[m\] (0: G fixed).
    pub center: f64,
    /// Radius of the contact point's circle on the plane \[m\].
    pub contact: f64,
}

/// One steady motion.
#[derive(Debug, Clone, PartialEq)]
pub struct SteadyMotion {
    pub family: Family,
    /// The surface the body rests on ([`Body::surface`] of the field's body).
    pub surface: Surface,
    /// (ζ0, ω0): world up and the angular velocity, body axes.
    pub at: Phase,
    /// The spin n [rad/s]: upright and inverted, about the upward vertical (ω0·ζ0);
    /// the tilted families, about the body's axis (ω0·k = φ̇ cos θ + ψ̇).
    pub spin: f64,
    /// Tilt θ of the body's c axis from the vertical \[rad\].
    pub theta: f64,
    /// Normal force N \[N\].
    pub normal_force: f64,
    /// Under the Coulomb model, the friction cone's margin μN − |F_h| \[N\]: the motion
    /// rolls (and the rolling analysis holds) only where it is positive.
    pub cone_margin: Option<f64>,
    /// The phase-space directions (δζ, δω) whose zero eigenvalues are not the motion's:
    /// the family's tangents, and for the tilted families the turn about the body's axis.
    pub removed: Vec<Phase>,
    /// ν [rad/s]: the motion is an equilibrium in the body frame turned about the body's
    /// c axis at ν (0 upright and inverted; −ψ̇ for the tilted families).
    pub frame_rate: f64,
    /// Ω = φ̇, the rate at which a tilted motion turns about the vertical [rad/s].
    pub precession: Option<f64>,
    /// A tilted motion's circles.
    pub circles: Option<Circles>,
    /// |f(x0)| relative to the field's scale: how far from steady the state is.
    pub residual: f64,
}

/// Largest accepted residual |f(x0)| of a steady state, relative to the field's scale.
pub(super) const RESIDUAL_TOLERANCE: f64 = 1e-9;

/// Largest rate of a steady motion analysed, in units of the body's own rate √(g/c_max).
/// The round-off in the eigenvalues' real parts grows with the rate: measured, at most
/// 6e-16 (|ω|/√(g/c_max)) of max |λ| (the thin rolling lens, the worst of the bundled and
/// test bodies; 1e-21 for an egg on its end), so at this bound it is 6e-11 of max |λ|,
/// a sixteenth of the stability tolerance ([`super::STABLE_TOLERANCE`]); the weight m g is
/// then 1e-10 of the spin's terms m |ω|² c_max. Beyond, the verdict would be round-off
/// (an egg spinning at 1e30 rad/s came out "unstable" with Re λ = 1e23 /s, at 1e150 the
/// decomposition did not converge).
pub const MAX_RATE_RATIO: f64 = 1e5;

/// Refuses a rate [rad/s] above [`MAX_RATE_RATIO`] √(g/c_max) of `body` under gravity
/// `g`, or one that is not finite: the error is `at_fault` of the rule (which names the
/// field and value).
pub(super) fn check_rate(
    body: &Body,
    gravity: f64,
    rate: f64,
    at_fault: impl FnOnce(String) -> ModelError,
) -> Result<(), ModelError> {
    let natural = (gravity / body.semi_axes().max()).sqrt();
    let bound = MAX_RATE_RATIO * natural;
    if !(rate.abs() <= bound) {
        return Err(at_fault(format!(
            "a steady motion is analysed up to {} √(g/c_max) = {bound:.4e} rad/s (g = {} m/s^2, c_max = {} m): beyond, its eigenvalues in double precision are round-off (docs/physics.md, \"Steady motions and their stability\")",
            number(MAX_RATE_RATIO),
            number(gravity),
            number(body.semi_axes().max())
        )));
    }
    Ok(())
}

/// [`check_rate`] of a rate derived from the `[initial]` table, named `quantity`.
pub(super) fn check_derived_rate(
    body: &Body,
    gravity: f64,
    quantity: &'static str,
    rate: f64,
) -> Result<(), ModelError> {
    check_rate(body, gravity, rate, |rule| {
        ModelError::derived("initial", quantity, Value::Number(rate, "rad/s"), rule)
    })
}

/// The steady motion of `family` that the scene defines: upright and inverted, the spin
/// about the vertical is the scene's initial ω·ζ0 (`initial.omega_body`, or the Euler
/// rates: at θ = 0, n = φ̇ + ψ̇); the tilted families, the scene's θ and φ̇ (and ψ, which
/// only chooses the coordinates) with the spin solved for (`tilted`), or two of θ, φ̇ and
/// the spin φ̇ cos θ + ψ̇ with the third solved for, as `solve` says.
pub fn steady_motion(
    field: &ReducedField,
    scene: &Scene,
    family: Family,
    solve: Solve,
) -> Result<SteadyMotion, ModelError> {
    if solve != Solve::Spin && !family.tilted() {
        return Err(ModelError::invalid(
            "solve",
            Value::Choice(solve.name().into()),
            format!(
                "the {} family has only its spin: solve applies to the tilted families (precession, rolling-circle)",
                family.name()
            ),
        ));
    }
    let start = match family {
        Family::Upright | Family::Inverted => start_attitude(scene, family),
        Family::Precession | Family::RollingCircle => {
            if let Some(w) = scene.initial.omega_body {
                return Err(ModelError::invalid(
                    "initial.omega_body",
                    Value::Numbers {
                        values: w.as_slice().to_vec(),
                        digits: Digits::Plain,
                        brackets: Brackets::Square,
                    },
                    format!(
                        "the {} family takes its tilt and precession rate from initial.theta and initial.phi_dot: give the Euler rates instead",
                        family.name()
                    ),
                ));
            }
            return super::tilted::from_angles(field, family, &scene.initial.angles, solve);
        }
    };
    let body = field.body();
    check_not_flat(body, family)?;
    let zeta = rest_attitude(body, start)?;
    check_principal(body, family, &zeta)?;
    let init = &scene.initial;
    let omega_init = init.omega_body.unwrap_or_else(|| init.angles.omega_body());
    let spin = omega_init.dot(&zeta);
    check_derived_rate(body, field.gravity(), "spin n", spin)?;
    upright_motion(field, family, zeta, spin)
}

/// The attitude ζ at which `family`'s motion of `scene` is sought: the c axis up
/// (upright), down (inverted), or the scene's tilt θ and yaw ψ (the tilted families).
/// The surface lowest there is the one the motion rests on
/// ([`super::reduce::resting_surface`]).
pub fn start_attitude(scene: &Scene, family: Family) -> Vector3<f64> {
    match family {
        Family::Upright => Vector3::z(),
        Family::Inverted => -Vector3::z(),
        Family::Precession | Family::RollingCircle => {
            let angles = &scene.initial.angles;
            super::tilted::zeta_at(angles.theta, angles.psi)
        }
    }
}

/// Refuses an upright or inverted spin on a rim: with its axis vertical the whole circle
/// touches (the body lies on its face, docs/physics.md, "Rims", "The flat landing"), so
/// there is no contact point to linearise about. A disc on its edge is a tilted motion.
fn check_not_flat(body: &Body, family: Family) -> Result<(), ModelError> {
    if let Surface::Rim(_) = body.surface() {
        return Err(ModelError::invalid(
            "body.rim",
            Value::Name(body.surface_name(body.surface()).into()),
            format!(
                "the {} spin rests on this rim with its axis vertical, that is flat on its face, where no single point touches: a disc on its edge is analysed by the tilted families (rolling-circle, precession; at phi_dot = 0 rolling straight on or spinning in place)",
                family.name()
            ),
        ));
    }
    Ok(())
}

/// Refuses a motion at ζ0 on a surface that is not the body's lowest there: another
/// surface would be below the plane, so the body does not rest on this one.
pub(super) fn check_lowest(
    body: &Body,
    zeta: &Vector3<f64>,
    at_fault: impl FnOnce(String) -> ModelError,
) -> Result<(), ModelError> {
    let lowest = super::reduce::resting_surface(body, zeta);
    if lowest != body.surface() {
        return Err(at_fault(format!(
            "at its attitude the body would rest on {}, which is lower than {}, the surface it is analysed on",
            body.surface_name(lowest),
            body.surface_name(body.surface())
        )));
    }
    Ok(())
}

/// Refuses a rest attitude ζ0 that is not a principal axis of inertia: spinning about the
/// vertical there is not steady (the gyroscopic torque n² ζ0 × Iζ0 ≠ 0).
pub(super) fn check_principal(
    body: &Body,
    family: Family,
    zeta: &Vector3<f64>,
) -> Result<(), ModelError> {
    let inertia = body.inertia();
    let gyro = zeta.cross(&(inertia * zeta)).norm();
    if gyro > 1e-12 * inertia.norm() {
        return Err(ModelError::invalid(
            "body.inertia",
            Value::Named {
                name: "|ζ0 × I ζ0|",
                value: gyro,
                unit: "kg m^2",
            },
            format!(
                "the {} rest attitude ζ0 = ({:.6}, {:.6}, {:.6}) is not a principal axis of inertia, so spinning about the vertical there is not a steady motion",
                family.name(),
                zeta.x,
                zeta.y,
                zeta.z
            ),
        ));
    }
    Ok(())
}

/// The steady spin at `spin` in the rest attitude `zeta` (see the module docs).
pub fn upright_motion(
    field: &ReducedField,
    family: Family,
    zeta: Vector3<f64>,
    spin: f64,
) -> Result<SteadyMotion, ModelError> {
    let at = join(&zeta, &(zeta * spin));
    let body = field.body();
    check_lowest(body, &zeta, |rule| {
        ModelError::invalid(
            "body",
            Value::Name(body.surface_name(body.surface()).into()),
            format!("the {} rest attitude: {rule}", family.name()),
        )
    })?;
    let scale_omega = spin
        .abs()
        .max((field.gravity() / body.semi_axes().max()).sqrt());
    let residual = field.rate(&at).amax() / (scale_omega * scale_omega);
    if !(residual <= RESIDUAL_TOLERANCE) {
        return Err(ModelError::invalid(
            "initial",
            Value::Named {
                name: "|f(x0)|",
                value: residual,
                unit: "of the field's scale",
            },
            format!("the {} spin is not steady for this body", family.name()),
        ));
    }
    let force = field.force(&at);
    let normal_force = force.z;
    if !(normal_force > 0.0) {
        return Err(ModelError::derived(
            "initial",
            "normal force N",
            normal_force,
            format!(
                "the plane must push on the body in the {} steady spin",
                family.name()
            ),
        ));
    }
    let cone_margin = field
        .friction()
        .map(|mu| mu * normal_force - force.xy().norm());
    Ok(SteadyMotion {
        family,
        surface: body.surface(),
        at,
        spin,
        theta: zeta.xy().norm().atan2(zeta.z),
        normal_force,
        cone_margin,
        removed: vec![join(&Vector3::zeros(), &zeta)],
        frame_rate: 0.0,
        precession: None,
        circles: None,
        residual,
    })
}

/// The rest attitude nearest `start`: the unit ζ at which the lever arm r(ζ) = C − G is
/// parallel to ζ (G straight above C; ∇h = −r has no tangential part). Newton on the
/// sphere with the Riemannian Hessian P(H + (ζ·r) 𝟙)P of h (`geometry`).
pub fn rest_attitude(body: &Body, start: Vector3<f64>) -> Result<Vector3<f64>, ModelError> {
    let mut zeta = start.normalize();
    for _ in 0..50 {
        let r = Contact::new(body, zeta, Vector3::zeros()).r;
        let [t1, t2] = tangent_basis(&zeta);
        // Tangential gradient of h: −(r·t1, r·t2).
        let grad = Vector2::new(-r.dot(&t1), -r.dot(&t2));
        if grad.norm() <= 1e-15 * body.semi_axes().max() {
            return Ok(zeta);
        }
        let h = hessian(body, zeta) + nalgebra::Matrix3::identity() * zeta.dot(&r);
        let hess = Matrix2::new(
            t1.dot(&(h * t1)),
            t1.dot(&(h * t2)),
            t2.dot(&(h * t1)),
            t2.dot(&(h * t2)),
        );
        let Some(step) = hess.lu().solve(&-grad) else {
            break;
        };
        zeta = (zeta + t1 * step.x + t2 * step.y).normalize();
    }
    Err(ModelError::invalid(
        "body.com_offset",
        Value::Numbers {
            values: start.as_slice().to_vec(),
            digits: Digits::Fixed6,
            brackets: Brackets::Round,
        },
        "no rest attitude (G straight above the contact point) was found near this orientation",
    ))
}

/// The scene started on `at` displaced by `delta` (a phase-space direction, `ζ` part
/// tangent): attitude from ζ (φ = 0), ω given in body axes, G where the scene puts it,
/// at rest horizontally (frictionless) or rolling. The body touches the plane.
pub fn started_at(scene: &Scene, at: &Phase, delta: &Phase) -> Scene {
    let x = at + delta;
    let (zeta, omega) = super::reduce::split(&x);
    let mut scene = scene.clone();
    let init = &mut scene.initial;
    init.angles = super::reduce::attitude(&zeta);
    init.omega_body = Some(omega);
    init.height = 0.0;
    init.velocity_z = None;
    init.velocity = match scene.contact {
        ContactModel::Frictionless
        | ContactModel::Sliding { .. }
        | ContactModel::Viscous { .. } => Some(nalgebra::Vector2::zeros()),
        ContactModel::Rolling | ContactModel::Coulomb { .. } => None,
    };
    scene
}
