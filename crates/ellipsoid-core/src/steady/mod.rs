//! Steady motions of the body on the plane and their linear stability
//! (docs/physics.md, "Steady motions and their stability").
//!
//! Layout: [`reduce`] (the closed dynamics of ζ = Rᵀe3 and ω that the plane's symmetries
//! and the contact constraint leave), [`families`] (the steady states), [`linearize`]
//! (the Jacobian in tangent coordinates), [`spectrum`] (eigenvalues with the family's
//! zeros removed, eigenvectors named by what moves), [`sweep`] (a family against a
//! parameter and its critical values), [`tilted`] (the tilted families of a body of
//! revolution: frictionless precession and Routh's rolling circles), [`viscous`] (the
//! upright and inverted spins under the viscous sliding law).

pub mod families;
pub mod linearize;
pub mod perturb;
pub mod reduce;
pub mod spectrum;
pub mod sweep;
pub mod tilted;
pub mod viscous;

pub use families::{Circles, Family, MAX_RATE_RATIO, SteadyMotion, started_at};
pub use linearize::{COORDINATES, Linearization, Reduced, linearize};
pub use perturb::perturbed;
pub use reduce::{Phase, ReducedField};
pub use spectrum::{Mode, STABLE_TOLERANCE, Shape, Spectrum};
pub use sweep::{Critical, CriticalKind, Sweep, sweep, sweep_solving};
pub use tilted::Solve;

use nalgebra::Vector3;

use crate::body::Body;
use crate::error::{ModelError, Value};
use crate::simulate::Scene;

/// A steady motion, its linearisation and its spectrum.
#[derive(Debug, Clone)]
pub struct Analysis {
    pub motion: SteadyMotion,
    pub linearization: Linearization,
    pub spectrum: Spectrum,
}

/// The steady motion of `family` that `scene` defines (its body, contact model and
/// initial spin, or for a tilted family its tilt and precession rate, the spin solved
/// for) and its stability. A body with contact spheres rests on the surface lowest where
/// the family starts ([`families::start_attitude`]).
pub fn analyse(scene: &Scene, family: Family) -> Result<Analysis, ModelError> {
    analyse_solving(scene, family, Solve::Spin)
}

/// [`analyse`], a tilted family solving for the unknown `solve` names (θ, φ̇ or the
/// spin; the scene gives the other two).
pub fn analyse_solving(
    scene: &Scene,
    family: Family,
    solve: Solve,
) -> Result<Analysis, ModelError> {
    let start = families::start_attitude(scene, family);
    let field =
        ReducedField::from_scene(scene)?.touching(reduce::resting_surface(&scene.body, &start));
    let motion = families::steady_motion(&field, scene, family, solve)?;
    analyse_motion(&field, motion)
}

/// The linearisation of `scene`'s reduced dynamics at `at` = (ζ, ω) (ζ normalised), or
/// at the scene's initial state (ζ = Rᵀe3 of the initial attitude, ω the initial body
/// angular velocity): the Jacobian in [`COORDINATES`], steady or not. Refused, as the
/// steady families' rates are (docs/physics.md, "Steady motions and their stability"):
/// a state that is not finite, a ζ whose squared length is not a normal float (it cannot
/// be normalised), |ω| above [`MAX_RATE_RATIO`] √(g/c_max), and a Jacobian that is not
/// finite.
pub fn linearize_scene(scene: &Scene, at: Option<Phase>) -> Result<Linearization, ModelError> {
    let field = ReducedField::from_scene(scene)?;
    let at = at.unwrap_or_else(|| {
        let init = &scene.initial;
        let rot = init.angles.rotation().to_rotation_matrix().into_inner();
        let zeta = Vector3::new(rot[(2, 0)], rot[(2, 1)], rot[(2, 2)]);
        reduce::join(
            &zeta,
            &init.omega_body.unwrap_or_else(|| init.angles.omega_body()),
        )
    });
    let (zeta, omega) = reduce::split(&at);
    let state = || Value::State(Box::new([zeta, omega]));
    if !(at.iter().all(|x| x.is_finite()) && zeta.norm() > 0.0) {
        return Err(ModelError::invalid(
            "state",
            state(),
            "the state (ζ1, ζ2, ζ3, ω1, ω2, ω3) must be finite with ζ ≠ 0",
        ));
    }
    let length = zeta.norm_squared();
    if !(length.is_finite() && length >= f64::MIN_POSITIVE) {
        return Err(ModelError::invalid(
            "state",
            state(),
            format!(
                "ζ is the direction of the vertical in body axes: its squared length |ζ|² = {length:e} must be a normal float ({:e} to {:e}) to be normalised",
                f64::MIN_POSITIVE,
                f64::MAX
            ),
        ));
    }
    families::check_rate(field.body(), field.gravity(), omega.norm(), |rule| {
        ModelError::invalid(
            "state",
            state(),
            format!("|ω| = {:e} rad/s: {rule}", omega.norm()),
        )
    })?;
    let field = field.touching(reduce::resting_surface(&scene.body, &zeta));
    let lin = linearize(&field, &at, None);
    if !lin.jacobian.iter().all(|x| x.is_finite()) {
        return Err(ModelError::invalid(
            "state",
            Value::State(Box::new([zeta, omega])),
            "the Jacobian at this state is not finite in double precision (the state is too large)",
        ));
    }
    Ok(lin)
}

/// The linearisation and spectrum of a steady `motion` of `field`: the Jacobian in the
/// frame in which the motion is an equilibrium (turned about the body's c axis at the
/// motion's `frame_rate`), the zeros of `motion.removed` taken out of its spectrum. An
/// error if its angular velocity is beyond what doubles resolve
/// ([`families::check_rate`]) or its Jacobian has no spectrum.
pub fn analyse_motion(field: &ReducedField, motion: SteadyMotion) -> Result<Analysis, ModelError> {
    let (_, omega) = reduce::split(&motion.at);
    families::check_derived_rate(
        field.body(),
        field.gravity(),
        "angular velocity |ω0|",
        omega.norm(),
    )?;
    let generator = (motion.frame_rate != 0.0).then_some((Vector3::z(), motion.frame_rate));
    let linearization = linearize(field, &motion.at, generator);
    let (zeta, _) = reduce::split(&linearization.at);
    let removed: Vec<Reduced> = motion
        .removed
        .iter()
        .map(|d| linearization.reduced(d))
        .collect();
    let mut shape = shape(field.body(), zeta);
    shape.tilted = motion.family.tilted();
    let floor = if shape.tilted {
        let axes = field.body().semi_axes();
        omega.norm().max((field.gravity() / axes.max()).sqrt())
    } else {
        0.0
    };
    let spectrum = spectrum::spectrum(&linearization, &removed, &shape, floor)?;
    Ok(Analysis {
        motion,
        linearization,
        spectrum,
    })
}

impl Analysis {
    /// The phase-space displacement ε Re(v) along mode `k` (its tilt ε rad).
    pub fn perturbation(&self, k: usize, epsilon: f64) -> Phase {
        let v = self.spectrum.modes[k].vector.map(|c| c.re * epsilon);
        self.linearization.direction(&v)
    }
}

/// How the body looks from above at attitude ζ0, for naming modes.
fn shape(body: &Body, zeta: Vector3<f64>) -> Shape {
    let axes = body.semi_axes();
    let i = body.inertia();
    // The body axis most nearly vertical, and the other two by length.
    let vertical = zeta.iamax();
    let (p, q) = match vertical {
        0 => (1, 2),
        1 => (0, 2),
        _ => (0, 1),
    };
    let (long, short) = if axes[p] >= axes[q] { (p, q) } else { (q, p) };
    let unit = |k: usize| Vector3::from_fn(|j, _| if j == k { 1.0 } else { 0.0 });
    let tol = 1e-12;
    let g = body.com_offset();
    let on_axis = |c: &Vector3<f64>| c[p].abs().max(c[q].abs()) <= tol * axes.max();
    let revolution = (axes[p] - axes[q]).abs() <= tol * axes.max()
        && body.spheres().iter().all(|sp| on_axis(&sp.center))
        && (i[(p, p)] - i[(q, q)]).abs() <= tol * i.norm()
        && i[(p, q)].abs() <= tol * i.norm()
        && i[(p, vertical)].abs() <= tol * i.norm()
        && i[(q, vertical)].abs() <= tol * i.norm()
        && on_axis(&g)
        && (zeta.abs()[vertical] - 1.0).abs() <= tol;
    Shape {
        zeta,
        long: unit(long),
        short: unit(short),
        revolution,
        tilted: false,
    }
}
