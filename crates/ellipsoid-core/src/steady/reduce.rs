//! The reduced dynamics of a body touching the plane: world-up seen in body axes,
//! ζ = Rᵀe3, and the body angular velocity ω (docs/physics.md, "Steady motions and their
//! stability", "The reduction").
//!
//! ```text
//!   ζ̇ = ζ × ω,     ω̇ = the contact law's angular acceleration at (ζ, ω)
//! ```
//! Under the frictionless and the rolling laws without effects, ω̇ depends on the state
//! only through ζ and ω: the yaw about the vertical and the position of G drop out (the
//! plane's symmetries), v_G is constant (frictionless: no horizontal force, a Galilean
//! symmetry) or slaved to ω (rolling: v_G = −ω × r), and z_G, v_Gz follow from ζ, ω
//! (the contact constraint). So (ζ, ω) on S² × R³ is a closed system of dimension 5.

use nalgebra::{Vector3, Vector6};

use crate::body::{Body, Surface};
use crate::error::{ModelError, Value};
use crate::geometry::Contact;
use crate::model::{ContactLaw, Frictionless, Rolling, System};
use crate::simulate::{ContactModel, Scene};
use crate::state::{self, EulerAngles, State};

/// A point of the reduced phase space: (ζ, ω) stacked, ζ dimensionless, ω in rad/s.
pub type Phase = Vector6<f64>;

/// The reduced vector field of a scene's body under its contact law.
#[derive(Debug, Clone)]
pub enum ReducedField {
    /// F = N e3.
    Frictionless(System<Frictionless, ()>),
    /// No slip; under the Coulomb model also the friction coefficient, whose cone the
    /// steady motion must respect to stay rolling.
    Rolling(System<Rolling, ()>, Option<f64>),
}

impl ReducedField {
    /// The reduced field of `scene`, or why the scene has none: effects, a contact
    /// disc, and the pure sliding model (which stops where the slip does, so it has no
    /// motion without slip to linearise about) are refused.
    pub fn from_scene(scene: &Scene) -> Result<Self, ModelError> {
        plain(scene)?;
        let body = scene.body.clone();
        let gravity = scene.gravity;
        Ok(match scene.contact {
            ContactModel::Frictionless => ReducedField::Frictionless(System {
                body,
                gravity,
                contact: Frictionless,
                effects: (),
            }),
            ContactModel::Rolling => ReducedField::Rolling(
                System {
                    body,
                    gravity,
                    contact: Rolling,
                    effects: (),
                },
                None,
            ),
            ContactModel::Coulomb { friction } => ReducedField::Rolling(
                System {
                    body,
                    gravity,
                    contact: Rolling,
                    effects: (),
                },
                Some(friction),
            ),
            ContactModel::Viscous { .. } => {
                return Err(ModelError::invalid(
                    "contact.model",
                    Value::Choice("viscous".into()),
                    "the viscous model's upright and inverted spins are analysed by `ellipsoid steady` and ellipsoid.steady (Rust: steady::viscous); the tilted families, the linearisation in these coordinates and --perturb do not take it",
                ));
            }
            ContactModel::Sliding { .. } => {
                return Err(ModelError::invalid(
                    "contact.model",
                    Value::Choice("sliding".into()),
                    "a steady motion has no slip, where the sliding model stops: use \"coulomb\" (whose rolling phase is analysed, within its friction cone) or \"rolling\"",
                ));
            }
        })
    }

    /// The same field, the body touching the plane with `surface` (its contact geometry:
    /// [`Body::touching`]).
    pub fn touching(self, surface: Surface) -> Self {
        match self {
            ReducedField::Frictionless(mut s) => {
                s.body = s.body.touching(surface);
                ReducedField::Frictionless(s)
            }
            ReducedField::Rolling(mut s, mu) => {
                s.body = s.body.touching(surface);
                ReducedField::Rolling(s, mu)
            }
        }
    }

    /// The body.
    pub fn body(&self) -> &Body {
        match self {
            ReducedField::Frictionless(s) => &s.body,
            ReducedField::Rolling(s, _) => &s.body,
        }
    }

    /// g [m/s²].
    pub fn gravity(&self) -> f64 {
        match self {
            ReducedField::Frictionless(s) => s.gravity,
            ReducedField::Rolling(s, _) => s.gravity,
        }
    }

    /// μ of the Coulomb model, whose cone a rolling steady motion must respect.
    pub fn friction(&self) -> Option<f64> {
        match self {
            ReducedField::Frictionless(_) => None,
            ReducedField::Rolling(_, mu) => *mu,
        }
    }

    /// (ζ̇, ω̇) at `x`: ζ̇ = ζ × ω with ζ as given, ω̇ from the contact law at ζ/|ζ|.
    #[inline]
    pub fn rate(&self, x: &Phase) -> Phase {
        let (zeta, omega) = split(x);
        let omega_dot = match self {
            ReducedField::Frictionless(s) => response(s, &zeta, &omega).omega_dot,
            ReducedField::Rolling(s, _) => response(s, &zeta, &omega).omega_dot,
        };
        join(&zeta.cross(&omega), &omega_dot)
    }

    /// The contact force at `x`, world frame with the body's yaw set to zero (see
    /// [`full_state`]) \[N\].
    pub fn force(&self, x: &Phase) -> Vector3<f64> {
        let (zeta, omega) = split(x);
        match self {
            ReducedField::Frictionless(s) => response(s, &zeta, &omega).force,
            ReducedField::Rolling(s, _) => response(s, &zeta, &omega).force,
        }
    }
}

/// The surface of `body` lowest at attitude ζ (`Contact::lowest`): the one the body rests
/// on there, and so the contact of a steady motion at ζ (docs/physics.md, "Steady
/// motions and their stability", "Bodies with contact spheres").
pub fn resting_surface(body: &Body, zeta: &Vector3<f64>) -> Surface {
    Contact::lowest(body, *zeta, Vector3::zeros()).surface
}

/// Refuses what no steady analysis takes: effects and a contact disc.
pub(super) fn plain(scene: &Scene) -> Result<(), ModelError> {
    if scene.effects.any() {
        // The effects are the keys of [effects] but gravity, named in alphabetical order.
        let mut effects = crate::scenario::schema::keys("effects");
        effects.retain(|k| *k != "gravity");
        effects.sort_unstable();
        return Err(ModelError::invalid(
            "effects",
            Value::Text("present".into()),
            format!(
                "steady motions are analysed without effects ({}): remove them",
                effects.join(", ")
            ),
        ));
    }
    if let Some(disc) = &scene.disc {
        return Err(ModelError::invalid(
            "contact.contact_radius",
            disc.radius,
            "steady motions are analysed with a point contact (contact_radius = 0)",
        ));
    }
    Ok(())
}

/// The contact law's response at (ζ, ω).
#[inline]
fn response<C: ContactLaw>(
    system: &System<C, ()>,
    zeta: &Vector3<f64>,
    omega: &Vector3<f64>,
) -> crate::model::Response {
    system.evaluate(&full_state(zeta, omega)).response
}

/// A full integration state with attitude ζ (normalised) and body angular velocity ω:
/// the Euler angles θ = atan2(|ζ_h|, ζ3), ψ = atan2(ζ1, ζ2), φ = 0 (docs/physics.md,
/// "Body, frames, conventions": ζ = (sin θ sin ψ, sin θ cos ψ, cos θ)), G at the origin
/// and at rest horizontally (the rolling law replaces v_G by −ω × r).
pub fn full_state(zeta: &Vector3<f64>, omega: &Vector3<f64>) -> State {
    let mut y = State::zeros();
    state::set_quaternion(&mut y, &attitude(zeta).rotation());
    for i in 0..3 {
        y[state::OMEGA + i] = omega[i];
    }
    y
}

/// Euler angles (rates zero) whose rotation has Rᵀe3 = ζ/|ζ|, with φ = 0. θ comes from
/// atan2, not acos, so a small tilt keeps its relative precision.
pub fn attitude(zeta: &Vector3<f64>) -> EulerAngles {
    EulerAngles {
        theta: zeta.xy().norm().atan2(zeta.z),
        psi: zeta.x.atan2(zeta.y),
        ..Default::default()
    }
}

/// (ζ, ω) of a phase point.
#[inline]
pub fn split(x: &Phase) -> (Vector3<f64>, Vector3<f64>) {
    (x.fixed_rows::<3>(0).into(), x.fixed_rows::<3>(3).into())
}

/// The phase point (ζ, ω).
#[inline]
pub fn join(zeta: &Vector3<f64>, omega: &Vector3<f64>) -> Phase {
    Phase::new(zeta.x, zeta.y, zeta.z, omega.x, omega.y, omega.z)
}
