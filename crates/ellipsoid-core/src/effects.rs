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

use crate::body::Body;
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

/// Rolling resistance: torque −c_r N ω_h/|ω_h|, ω_h the horizontal part of ω,
/// regularised as ω_h / √(|ω_h|² + ε²) so that it vanishes smoothly at ω_h = 0.
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
        let zeta = kin.contact.zeta;
        let omega_h = kin.omega - zeta * kin.omega.dot(&zeta);
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
}
