//! Optional effects beyond gravity and the contact law, composed at compile time.
//!
//! Each effect contributes a [`Wrench`]: a world-frame force on G, a body-frame torque
//! about G, and a body-frame torque *per unit normal force* (for contact-borne
//! resistance, which scales with N). A scene's effects are a tuple of [`Effect`]s; the
//! empty tuple `()` contributes nothing and compiles to nothing, so an effect a scene
//! does not name costs nothing at run time. The work they dissipate is accounted in the
//! model's power balance (see `model`).
//!
//! The effects a scenario may name are listed once, at the end of this file: each
//! entry's key in `[effects]`, type and `ellipsoid check` line give [`EffectSet`], its
//! report and the monomorphising dispatch. A new effect is its physics here, one entry
//! of that list, its keys (unit, kind, doc line) in `scenario::schema::SCHEMA` and its
//! reader in the scenario format (`scenario::format::read_effects`, which the compiler
//! holds to every field of [`EffectSet`]). The physics never reads the file format.

use nalgebra::Vector3;
use serde::Serialize;

use crate::body::{Body, Surface};
use crate::geometry::{self, FLAT_TILT};
use crate::kinematics::Kinematics;

/// Generalised load of the optional effects.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Wrench {
    /// Force on G, world frame \[N\].
    pub force: Vector3<f64>,
    /// Torque about G, body frame [N·m].
    pub torque: Vector3<f64>,
    /// Torque about G per newton of normal force, body frame \[m\].
    pub torque_per_normal: Vector3<f64>,
}

impl Wrench {
    /// No load.
    pub const ZERO: Wrench = Wrench {
        force: Vector3::new(0.0, 0.0, 0.0),
        torque: Vector3::new(0.0, 0.0, 0.0),
        torque_per_normal: Vector3::new(0.0, 0.0, 0.0),
    };
}

impl std::ops::Add for Wrench {
    type Output = Wrench;
    fn add(self, o: Wrench) -> Wrench {
        Wrench {
            force: self.force + o.force,
            torque: self.torque + o.torque,
            torque_per_normal: self.torque_per_normal + o.torque_per_normal,
        }
    }
}

/// One optional physical effect.
pub trait Effect {
    /// The load this effect applies in the given kinematic state.
    fn wrench(&self, body: &Body, kin: &Kinematics) -> Wrench;
}

impl Effect for () {
    #[inline(always)]
    fn wrench(&self, _: &Body, _: &Kinematics) -> Wrench {
        Wrench::ZERO
    }
}

impl<A: Effect, B: Effect> Effect for (A, B) {
    #[inline(always)]
    fn wrench(&self, body: &Body, kin: &Kinematics) -> Wrench {
        self.0.wrench(body, kin) + self.1.wrench(body, kin)
    }
}

/// Viscous air drag: force −k v_G \[N\] and torque −k_ω ω [N·m].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct AirDrag {
    /// k [kg/s].
    pub linear: f64,
    /// k_ω [kg·m²/s].
    pub angular: f64,
}

impl Effect for AirDrag {
    #[inline]
    fn wrench(&self, _: &Body, kin: &Kinematics) -> Wrench {
        Wrench {
            force: -self.linear * kin.v_g,
            torque: -self.angular * kin.omega,
            torque_per_normal: Vector3::zeros(),
        }
    }
}

/// Rolling resistance: a couple c_r N against the rolling angular velocity, torque
/// −c_r N ω_h/|ω_h|, ω_h the horizontal part of ω (power c_r N |ω_h|), regularised as
/// ω_h / √(|ω_h|² + ε²) so that it vanishes smoothly at ω_h = 0.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct RollingResistance {
    /// c_r \[m\].
    pub coefficient: f64,
    /// ε [rad/s].
    pub regularisation: f64,
}

impl Effect for RollingResistance {
    #[inline]
    fn wrench(&self, _: &Body, kin: &Kinematics) -> Wrench {
        let omega_h = rolling_part(kin);
        let scale = (omega_h.norm_squared() + self.regularisation * self.regularisation).sqrt();
        Wrench {
            force: Vector3::zeros(),
            torque: Vector3::zeros(),
            torque_per_normal: -self.coefficient * omega_h / scale,
        }
    }
}

/// Spin (drilling) friction: torque −c_s N sign(ω_z) e3, with sign regularised as
/// ω_z / √(ω_z² + ε²).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SpinFriction {
    /// c_s \[m\].
    pub coefficient: f64,
    /// ε [rad/s].
    pub regularisation: f64,
}

impl Effect for SpinFriction {
    #[inline]
    fn wrench(&self, _: &Body, kin: &Kinematics) -> Wrench {
        let zeta = kin.contact.zeta;
        let wz = kin.omega.dot(&zeta);
        let sign = wz / (wz * wz + self.regularisation * self.regularisation).sqrt();
        Wrench {
            force: Vector3::zeros(),
            torque: Vector3::zeros(),
            torque_per_normal: -self.coefficient * sign * zeta,
        }
    }
}

/// Rolling friction: a force μ_r N resisting the travel of the contact point, which moves
/// over the body at ṙ_C = −H ζ̇ (`geometry::Contact::r_dot_surface`; rolling, at the same
/// speed along the plane). The material contact point is at rest in rolling, so the force
/// acts as the couple whose power is μ_r N |ṙ_C|: −μ_r N (|ṙ_C|/|ω_h|) ω̂_h, ω_h the
/// rolling (horizontal) part of ω (|ζ̇| = |ω_h|), regularised as ω_h/√(|ω_h|² + ε²)
/// (docs/physics.md, "Dissipation of a rolling disc").
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct RollingFriction {
    /// μ_r \[1\].
    pub coefficient: f64,
    /// ε [rad/s].
    pub regularisation: f64,
}

impl Effect for RollingFriction {
    #[inline]
    fn wrench(&self, _: &Body, kin: &Kinematics) -> Wrench {
        let omega_h = rolling_part(kin);
        let w = omega_h.norm();
        let per_normal = if w > 0.0 {
            let travel = kin.contact.r_dot_surface.norm();
            -self.coefficient * travel / w * omega_h
                / (w * w + self.regularisation * self.regularisation).sqrt()
        } else {
            Vector3::zeros()
        };
        Wrench {
            force: Vector3::zeros(),
            torque: Vector3::zeros(),
            torque_per_normal: per_normal,
        }
    }
}

/// Moffatt's air film: the viscous air in the wedge under a disc touching the plane at
/// its rim, in the lubrication approximation (Moffatt, Nature 404 (2000) 833). The
/// Reynolds equation is linear in the rocking rate ω_h and the gap scales as a sin α, so
/// the film's load is the couple −(π/4) μ a³ ω_h / sin³α; its power (π/4) μ a³ Ω² cos²α /
/// sin α on the rolling disc (|ω_h| = Ω sin α cos α) is Moffatt's Φ, the constant that of
/// his t0 = α0³ M/(2π μ a) (docs/physics.md, "Dissipation of a rolling disc"). It acts on
/// a rim on the plane, a its radius R.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct AirFilm {
    /// μ, the air's dynamic viscosity [Pa·s].
    pub viscosity: f64,
}

impl Effect for AirFilm {
    #[inline]
    fn wrench(&self, body: &Body, kin: &Kinematics) -> Wrench {
        let torque = rocking_disc(body, kin).map_or(Vector3::zeros(), |(a, sin_alpha, w)| {
            -std::f64::consts::FRAC_PI_4 * self.viscosity * a.powi(3) / sin_alpha.powi(3) * w
        });
        Wrench {
            force: Vector3::zeros(),
            torque,
            torque_per_normal: Vector3::zeros(),
        }
    }
}

/// Bildsten's boundary layer: above the angle where the air's viscous diffusion across
/// the gap is slower than the precession, the shear is confined to a layer δ = √(2ν/Ω)
/// (ν = μ/ρ) and the power lost is √(μρ) a⁴ Ω^{5/2}/√2 (Bildsten, Phys. Rev. E 66 (2002)
/// 056309; docs/physics.md, "Dissipation of a rolling disc"). As a couple against the
/// rocking rate with Ω = |ω_h|/sin α: −√(μρ) a⁴ |ω_h|^{1/2} ω_h / (√2 sin^{5/2}α), on a rim
/// on the plane, a its radius R.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct AirBoundaryLayer {
    /// μ, the air's dynamic viscosity [Pa·s].
    pub viscosity: f64,
    /// ρ, the air's density [kg/m³].
    pub density: f64,
}

impl Effect for AirBoundaryLayer {
    #[inline]
    fn wrench(&self, body: &Body, kin: &Kinematics) -> Wrench {
        let torque = rocking_disc(body, kin).map_or(Vector3::zeros(), |(a, sin_alpha, w)| {
            let k = (self.viscosity * self.density).sqrt()
                * a.powi(4)
                * std::f64::consts::FRAC_1_SQRT_2;
            -k * w.norm().sqrt() / (sin_alpha * sin_alpha * sin_alpha.sqrt()) * w
        });
        Wrench {
            force: Vector3::zeros(),
            torque,
            torque_per_normal: Vector3::zeros(),
        }
    }
}

/// The rolling (horizontal) part of ω, ω_h = ω − ζ (ζ·ω), body axes [rad/s].
#[inline(always)]
fn rolling_part(kin: &Kinematics) -> Vector3<f64> {
    let zeta = kin.contact.zeta;
    kin.omega - zeta * kin.omega.dot(&zeta)
}

/// The disc of the air laws: while a rim is on the plane (gap 0) and tilted α above
/// [`FLAT_TILT`], its radius a = R \[m\], sin α = |Pζ| and the rocking rate ω_h (body
/// axes) [rad/s]; `None` otherwise (another surface touching, flight, lying flat).
#[inline]
fn rocking_disc(body: &Body, kin: &Kinematics) -> Option<(f64, f64, Vector3<f64>)> {
    let Surface::Rim(k) = kin.contact.surface else {
        return None;
    };
    let (_, sin_alpha) = geometry::ring_direction(kin.contact.zeta);
    (kin.gap == 0.0 && sin_alpha > FLAT_TILT)
        .then(|| (body.rims()[k].radius, sin_alpha, rolling_part(kin)))
}

/// What runs with a scene's effects: [`EffectSet::dispatch`] calls `run` with exactly the
/// effects present, as a tuple monomorphised over them (an absent effect is left out and
/// costs nothing).
pub(crate) trait WithEffects {
    type Output;
    fn run<E: Effect + Copy + 'static>(self, effects: E) -> Self::Output;
}

/// Declares [`EffectSet`] from the list of effects below (`key: Type { report }`).
macro_rules! effect_set {
    (@dispatch $set:ident, $run:ident, $acc:expr;) => {
        $run.run($acc)
    };
    (@dispatch $set:ident, $run:ident, $acc:expr; $key:ident $($rest:ident)*) => {
        match $set.$key {
            Some(effect) => effect_set!(@dispatch $set, $run, ($acc, effect); $($rest)*),
            None => effect_set!(@dispatch $set, $run, $acc; $($rest)*),
        }
    };
    ($(
        $(#[$doc:meta])*
        $key:ident: $ty:ident {
            report: $report:expr $(,)?
        }
    ),* $(,)?) => {
        /// The optional effects a scene names (absent = not simulated, no cost). Serialised
        /// as `ellipsoid check` reports them (Python's `check(...)["effects"]`), `None`
        /// where absent.
        #[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
        pub struct EffectSet {
            $($(#[$doc])* pub $key: Option<$ty>,)*
        }

        impl EffectSet {
            /// The keys of `[effects]` that name an effect (its field here), in order.
            pub const KEYS: &[&str] = &[$(stringify!($key)),*];

            /// Whether any effect is present.
            pub fn any(&self) -> bool {
                false $(|| self.$key.is_some())*
            }

            /// One line per effect present, as `ellipsoid check` reports it.
            pub fn report(&self) -> Vec<String> {
                let mut out = Vec::new();
                $(if let Some(effect) = &self.$key {
                    let report: fn(&$ty) -> String = $report;
                    out.push(report(effect));
                })*
                out
            }

            /// `run` with the effects present (see [`WithEffects`]): each level of the
            /// expansion doubles the variants.
            pub(crate) fn dispatch<R: WithEffects>(&self, run: R) -> R::Output {
                let set = self;
                effect_set!(@dispatch set, run, (); $($key)*)
            }
        }
    };
}

// The effects, each once: its key in `[effects]` (its keys, units and doc lines are in
// `scenario::schema::SCHEMA`, its reader in the scenario format), its type above and how
// `ellipsoid check` reports it. The order is that of the key reference, of `check`'s report and of the
// effects' sum in the right-hand side.
effect_set! {
    /// Rolling resistance ([`RollingResistance`]).
    rolling_resistance: RollingResistance {
        report: |e| {
            format!(
                "rolling resistance c_r = {} m (eps = {} rad/s)",
                e.coefficient, e.regularisation
            )
        },
    },
    /// Spin friction ([`SpinFriction`]).
    spin_friction: SpinFriction {
        report: |e| {
            format!(
                "spin friction c_s = {} m (eps = {} rad/s)",
                e.coefficient, e.regularisation
            )
        },
    },
    /// Air drag ([`AirDrag`]).
    air_drag: AirDrag {
        report: |e| format!("air drag k = {} kg/s, k_w = {} kg m^2/s", e.linear, e.angular),
    },
    /// Rolling friction ([`RollingFriction`]).
    rolling_friction: RollingFriction {
        report: |e| {
            format!(
                "rolling friction mu_r = {} (eps = {} rad/s)",
                e.coefficient, e.regularisation
            )
        },
    },
    /// Moffatt's air film ([`AirFilm`]).
    air_film: AirFilm {
        report: |e| format!("air film (Moffatt) mu = {} Pa s", e.viscosity),
    },
    /// Bildsten's boundary layer ([`AirBoundaryLayer`]).
    air_boundary_layer: AirBoundaryLayer {
        report: |e| {
            format!(
                "air boundary layer (Bildsten) mu = {} Pa s, rho = {} kg/m^3",
                e.viscosity, e.density
            )
        },
    },
}
