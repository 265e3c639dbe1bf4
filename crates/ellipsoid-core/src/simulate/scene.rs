//! What a run simulates: the scene's body, contact model, effects, initial state, solver
//! settings, output times and observables, and the checks no other layer makes.

use nalgebra::{Vector2, Vector3};

use crate::body::Body;
use crate::columns;
pub use crate::effects::EffectSet;
use crate::error::{Brackets, Digits, ModelError, Value, number};
use crate::geometry;
use crate::integrate::{self, Direction, Method};
use crate::model::ContactDisc;
use crate::state::EulerAngles;

/// The contact model a scene asks for.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ContactModel {
    /// F = N e3.
    Frictionless,
    /// Coulomb friction while slipping; stops when the slip does.
    Sliding { friction: f64 },
    /// No slip, unlimited friction.
    Rolling,
    /// Sliding and rolling with transitions; `friction` is μ.
    Coulomb { friction: f64 },
    /// Viscous sliding friction F_t = −μ_v N v_C (docs/physics.md, "Viscous sliding");
    /// `viscous_friction` is μ_v [s/m].
    Viscous { viscous_friction: f64 },
}

impl ContactModel {
    /// Every model, at placeholder parameters (μ = 0, μ_v = 0), in the order of
    /// [`ContactModel::NAMES`].
    pub const ALL: [ContactModel; 5] = [
        ContactModel::Frictionless,
        ContactModel::Sliding { friction: 0.0 },
        ContactModel::Rolling,
        ContactModel::Coulomb { friction: 0.0 },
        ContactModel::Viscous {
            viscous_friction: 0.0,
        },
    ];
    /// Their names in scenario files (`[contact] model`).
    pub const NAMES: [&'static str; 5] = [
        ContactModel::ALL[0].name(),
        ContactModel::ALL[1].name(),
        ContactModel::ALL[2].name(),
        ContactModel::ALL[3].name(),
        ContactModel::ALL[4].name(),
    ];

    /// Its name in scenario files (`[contact] model`).
    pub const fn name(&self) -> &'static str {
        match self {
            ContactModel::Frictionless => "frictionless",
            ContactModel::Sliding { .. } => "sliding",
            ContactModel::Rolling => "rolling",
            ContactModel::Coulomb { .. } => "coulomb",
            ContactModel::Viscous { .. } => "viscous",
        }
    }

    /// The model called `name` (one of [`ContactModel::NAMES`]) at placeholder parameters.
    pub fn named(name: &str) -> Option<ContactModel> {
        ContactModel::ALL.into_iter().find(|m| m.name() == name)
    }

    /// μ of the models with Coulomb friction.
    pub fn friction(&self) -> Option<f64> {
        match *self {
            ContactModel::Sliding { friction } | ContactModel::Coulomb { friction } => {
                Some(friction)
            }
            ContactModel::Frictionless | ContactModel::Rolling | ContactModel::Viscous { .. } => {
                None
            }
        }
    }
}

/// What happens when the normal force reaches zero (`[contact] on_lift_off`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LiftOff {
    /// The body flies, lands and goes on (docs/physics.md, "Flight").
    #[default]
    Fly,
    /// The run ends with status `lost_contact`.
    Stop,
}

impl LiftOff {
    /// The `on_lift_off` names, in declaration order.
    pub const NAMES: [&'static str; 2] = ["fly", "stop"];
}

/// Leaving and landing on the plane (`[contact] restitution`, `on_lift_off`, `flat_tilt`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Landing {
    /// Energetic coefficient of restitution e ∈ [0, 1] (docs/physics.md, "Impact at
    /// touchdown"); the default 0 (plastic) adds no bounce the scene did not ask for.
    pub restitution: f64,
    pub lift_off: LiftOff,
    /// The tilt sin α below which a rim lands on its face (docs/physics.md, "Rims": "The
    /// flat landing"), in [`geometry::FLAT_TILT`], [`Landing::MAX_FLAT_TILT`]: the far side
    /// of the face is then within 2R sin α of the plane.
    pub flat_tilt: f64,
}

impl Landing {
    /// The largest `flat_tilt`: a face 2R·1e-3 above the plane at its far side (75 µm on
    /// a 75 mm disc) is as rough as a landing is modelled.
    pub const MAX_FLAT_TILT: f64 = 1e-3;
}

impl Default for Landing {
    fn default() -> Self {
        Landing {
            restitution: 0.0,
            lift_off: LiftOff::Fly,
            flat_tilt: geometry::FLAT_TILT,
        }
    }
}

/// Initial conditions.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InitialState {
    /// Euler angles and rates (paper eq. 1) [rad, rad/s].
    pub angles: EulerAngles,
    /// Body angular velocity [rad/s]; when given it replaces the Euler-angle rates.
    pub omega_body: Option<Vector3<f64>>,
    /// Horizontal position of G \[m\].
    pub position: Vector2<f64>,
    /// Horizontal velocity of G [m/s]. Must be `None` for rolling, where it is implied;
    /// `None` means zero for frictionless and sliding, and no slip (v_G = −ω × r) for
    /// Coulomb. A body that starts in flight may have any horizontal velocity.
    pub velocity: Option<Vector2<f64>>,
    /// Gap of the lowest point above the plane at t = 0 \[m\]; > 0 starts in flight.
    pub height: f64,
    /// Vertical velocity of G [m/s]; only for a body that starts in flight (`None` = 0).
    pub velocity_z: Option<f64>,
}

/// Integrator settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolverSettings {
    pub method: Method,
    pub rtol: f64,
    pub atol: f64,
    /// Initial step hint for the adaptive methods \[s\].
    pub initial_step: Option<f64>,
    pub max_steps: u64,
}

/// An event on an output column that the user asks for (`[[observe]]`): the times at
/// which `column` crosses the value `crosses` in `direction`, located on the dense output
/// like the contact events.
#[derive(Debug, Clone, PartialEq)]
pub struct Observe {
    /// The user's name for it, unique in the scene.
    pub name: String,
    /// Index of the column among the body's numeric columns (`columns::Layout`).
    pub column: usize,
    /// The value crossed, in the column's unit.
    pub crosses: f64,
    pub direction: Direction,
    /// Whether the run ends at the first crossing (status `observed`).
    pub terminal: bool,
}

/// A Poincaré section (`[[section]]`): the full state (every output column) at each
/// crossing of `crossing` (never terminal), located on the dense output like every event
/// (docs/physics.md, "Poincaré sections"). The run stops at the `max_points`-th point
/// (status `section_full`).
#[derive(Debug, Clone, PartialEq)]
pub struct Section {
    /// The column, value and direction crossed, and the section's name (unique among the
    /// scene's sections).
    pub crossing: Observe,
    /// Most points kept, 1 to [`MAX_SECTION_POINTS`]; the scene's sections together keep
    /// at most [`MAX_SECTION_POINTS`] (docs/scenarios.md, "Poincaré sections").
    pub max_points: u64,
}

/// Most sections a scene may name.
pub const MAX_SECTIONS: usize = 16;

/// Most points a section keeps, and most the sections of a scene keep together (the sum
/// of their `section.max_points`; docs/scenarios.md, "Poincaré sections"): 10⁶ rows of
/// every column, some 200–800 MB in memory and a sections table of up to about 500 MB.
pub const MAX_SECTION_POINTS: u64 = 1_000_000;

/// Highest start above the plane, in body sizes (largest semi-axis): a fall from
/// 10⁶ sizes lasts √(2·10⁶ L/g), ample for any experiment, and keeps z_G's round-off
/// (ε z_G) far below the body's size.
pub const MAX_HEIGHT_SIZES: f64 = 1e6;

/// Largest viscous friction coefficient μ_v [s/m]: with g = 9.81 m/s² the slip of a ball
/// relaxes in 1/(3.5 μ_v g) ≈ 3e-7 s at this bound, already a stiff scale for an explicit
/// integrator.
pub const MAX_VISCOUS_FRICTION: f64 = 1e5;

/// Most observables a scene may name.
pub const MAX_OBSERVE: usize = 64;

/// Largest dimensionless initial spin |ω|·√(L/g), L = max(a, b, c), that a run accepts:
/// ≈ 1/√ε (ε = 2.2e-16). Beyond it ω²L/g > 1/ε: g is below the round-off of the spin's
/// terms (ω × Iω and κ, ~ m L ω²) that the normal force balances it against
/// (docs/physics.md, model 1), so N and the motion it drives are noise, and the steps
/// collapse to round-off of t.
pub const MAX_DIMENSIONLESS_SPIN: f64 = 6.7e7;

/// Largest ratio of the largest to the smallest semi-axis a run accepts: 1/√ε
/// (ε = 2.2e-16). The contact geometry adds the squares a²n₁², b²n₂², c²n₃² (the support
/// function); beyond this ratio the smallest one's term is below the round-off of the
/// largest's at tilts past 45°, and at smaller tilts the more the ratio grows, so the
/// height and the contact point are noise and the steps collapse (a 20,000 km disc
/// 3 cm thick).
pub const MAX_ASPECT_RATIO: f64 = 6.7e7;

/// Everything a run needs.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    pub body: Body,
    /// g [m/s²].
    pub gravity: f64,
    pub contact: ContactModel,
    /// A flat contact disc under the friction models (Coulomb–Contensou friction,
    /// `model::contensou`); `None` is a point contact.
    pub disc: Option<ContactDisc>,
    /// Leaving and landing on the plane.
    pub landing: Landing,
    pub effects: EffectSet,
    pub initial: InitialState,
    pub solver: SolverSettings,
    /// End time \[s\].
    pub t_end: f64,
    /// Output times, sorted, within [0, t_end] \[s\].
    pub sample_times: Vec<f64>,
    /// Events on output columns to locate and report.
    pub observe: Vec<Observe>,
    /// Poincaré sections to record.
    pub sections: Vec<Section>,
}

impl Scene {
    /// Checks the settings that the body and the integrator do not check themselves.
    pub fn validate(&self) -> Result<(), ModelError> {
        if !(self.t_end.is_finite() && self.t_end > 0.0) {
            return Err(ModelError::invalid(
                "output.t_end",
                self.t_end,
                "the end time must be positive and finite (s)",
            ));
        }
        if !(self.gravity.is_finite() && self.gravity >= 0.0) {
            return Err(ModelError::invalid(
                "effects.gravity",
                self.gravity,
                "g must be finite and non-negative (m/s^2)",
            ));
        }
        if let Some(friction) = self.contact.friction()
            && !(friction.is_finite() && friction >= 0.0)
        {
            return Err(ModelError::invalid(
                "contact.friction",
                friction,
                "the Coulomb coefficient must be finite and non-negative",
            ));
        }
        if let ContactModel::Viscous { viscous_friction } = self.contact {
            self.validate_viscous(viscous_friction)?;
        }
        if let Some(disc) = &self.disc {
            self.validate_disc(disc)?;
        }
        if let Some(bad) = self
            .sample_times
            .iter()
            .find(|t| !(t.is_finite() && **t >= 0.0 && **t <= self.t_end))
        {
            return Err(ModelError::invalid(
                "output.times",
                *bad,
                format!(
                    "output times must lie within [0, t_end = {}] s",
                    number(self.t_end)
                ),
            ));
        }
        if let Some(w) = self.sample_times.windows(2).find(|w| w[1] <= w[0]) {
            return Err(ModelError::invalid(
                "output.times",
                Value::After {
                    later: w[1],
                    earlier: w[0],
                },
                "output times must be strictly increasing",
            ));
        }
        if let Method::Rk4 { h } = self.solver.method {
            if h > self.t_end {
                return Err(ModelError::invalid(
                    "solver.step",
                    h,
                    format!(
                        "the fixed step must not exceed output.t_end = {} s",
                        number(self.t_end)
                    ),
                ));
            }
            let steps = (self.t_end / h - (integrate::RK4_LAST_STRETCH - 1.0)).ceil();
            if steps > self.solver.max_steps as f64 {
                return Err(ModelError::invalid(
                    "solver.step",
                    h,
                    format!(
                        "rk4 would take {} steps to t_end = {} s, more than solver.max_steps = {} (raise the step or max_steps)",
                        number(steps),
                        number(self.t_end),
                        self.solver.max_steps
                    ),
                ));
            }
        }
        let e = self.landing.restitution;
        if !(0.0..=1.0).contains(&e) {
            return Err(ModelError::invalid(
                "contact.restitution",
                e,
                "the coefficient of restitution must lie in [0, 1]",
            ));
        }
        let init = &self.initial;
        let size = self.body.semi_axes().max();
        if !(init.height.is_finite() && (0.0..=MAX_HEIGHT_SIZES * size).contains(&init.height)) {
            return Err(ModelError::invalid(
                "initial.height",
                init.height,
                format!(
                    "the gap above the plane must be finite, ≥ 0 and at most {MAX_HEIGHT_SIZES:e} body sizes ({} m)",
                    number(MAX_HEIGHT_SIZES * size)
                ),
            ));
        }
        if let Some(vz) = init.velocity_z {
            if init.height == 0.0 {
                return Err(ModelError::invalid(
                    "initial.velocity",
                    vz,
                    "a vertical velocity (third component) needs a body that starts in flight (initial.height > 0); touching, v_Gz follows from the contact",
                ));
            }
            if !vz.is_finite() {
                return Err(ModelError::invalid(
                    "initial.velocity",
                    vz,
                    "every component must be finite",
                ));
            }
        }
        let vectors = [
            ("initial.position", init.position.as_slice().to_vec()),
            (
                "initial.velocity",
                init.velocity.map_or(vec![], |v| v.as_slice().to_vec()),
            ),
            (
                "initial.omega_body",
                init.omega_body.map_or(vec![], |w| w.as_slice().to_vec()),
            ),
        ];
        for (name, v) in vectors {
            if v.iter().any(|x| !x.is_finite()) {
                return Err(ModelError::invalid(
                    name,
                    Value::Numbers {
                        values: v,
                        digits: Digits::Debug,
                        brackets: Brackets::Square,
                    },
                    "every component must be finite",
                ));
            }
        }
        let a = &self.initial.angles;
        for (name, v) in [
            ("theta", a.theta),
            ("phi", a.phi),
            ("psi", a.psi),
            ("theta_dot", a.theta_dot),
            ("phi_dot", a.phi_dot),
            ("psi_dot", a.psi_dot),
        ] {
            if !v.is_finite() {
                return Err(ModelError::invalid(
                    format!("initial.{name}"),
                    v,
                    "must be finite",
                ));
            }
        }
        self.validate_shape()?;
        self.validate_arms()?;
        self.validate_disc_laws()?;
        self.validate_observe()
    }

    /// The semi-axes must stay within [`MAX_ASPECT_RATIO`] of each other.
    fn validate_shape(&self) -> Result<(), ModelError> {
        let axes = self.body.semi_axes();
        let named = ["a", "b", "c"].into_iter().zip(axes.iter().copied());
        let (large, max) = named
            .clone()
            .fold(("a", 0.0), |m, x| if x.1 > m.1 { x } else { m });
        let (small, min) = named.fold(("a", f64::INFINITY), |m, x| if x.1 < m.1 { x } else { m });
        let ratio = max / min;
        if ratio > MAX_ASPECT_RATIO {
            return Err(ModelError::invalid(
                format!("body.{large}"),
                max,
                format!(
                    "the semi-axes span {ratio:.3e} (body.{large} = {} m over body.{small} = {} m), more than {MAX_ASPECT_RATIO:e} ≈ 1/√ε: \
                     the contact geometry adds their squares, so {small}'s is below the round-off of {large}'s and the body's shape is lost",
                    number(max),
                    number(min)
                ),
            ));
        }
        Ok(())
    }

    /// The air laws act under a rim's face: the body needs a rim. Rolling friction's
    /// μ_r is a coefficient of resistance, at most 1 (measured ones are ~1e-4).
    fn validate_disc_laws(&self) -> Result<(), ModelError> {
        let e = &self.effects;
        for (key, mu) in [
            (
                "effects.air_film.viscosity",
                e.air_film.map(|f| f.viscosity),
            ),
            (
                "effects.air_boundary_layer.viscosity",
                e.air_boundary_layer.map(|b| b.viscosity),
            ),
        ] {
            if let Some(mu) = mu.filter(|_| self.body.rims().is_empty()) {
                return Err(ModelError::invalid(
                    key,
                    mu,
                    "the air laws act in the gap under a rim's face (docs/physics.md, \"Dissipation of a rolling disc\"): the body has no [[body.rim]]",
                ));
            }
        }
        if let Some(f) = e.rolling_friction.filter(|f| f.coefficient > 1.0) {
            return Err(ModelError::invalid(
                "effects.rolling_friction",
                f.coefficient,
                "the rolling-friction coefficient μ_r must be at most 1 (measured: ~1e-4)",
            ));
        }
        Ok(())
    }

    /// An effect's torque arm must not be longer than the body.
    fn validate_arms(&self) -> Result<(), ModelError> {
        let size = self.body.semi_axes().max();
        let e = &self.effects;
        for (key, arm) in [
            (
                "effects.rolling_resistance",
                e.rolling_resistance.map(|r| r.coefficient),
            ),
            (
                "effects.spin_friction",
                e.spin_friction.map(|s| s.coefficient),
            ),
        ] {
            if let Some(c) = arm.filter(|&c| c > size) {
                return Err(ModelError::invalid(
                    key,
                    c,
                    format!(
                        "the torque arm c (torque c N) must not exceed the body's largest semi-axis max(a, b, c) = {} m: \
                         the normal force acts within the contact, inside the body",
                        number(size)
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The time scale of the motion under gravity, √(L/g) with L = max(a, b, c) \[s\]
    /// (`None` without gravity): the unit of [`MAX_DIMENSIONLESS_SPIN`], and the
    /// integrator's `Options::time_scale`, against which a run's pace is judged.
    pub fn gravity_time(&self) -> Option<f64> {
        (self.gravity > 0.0).then(|| (self.body.semi_axes().max() / self.gravity).sqrt())
    }

    /// The initial spin must stay within [`MAX_DIMENSIONLESS_SPIN`] (with g > 0). Checked
    /// with the initial state (`start`), after its overflow checks, which name the
    /// quantity that overflows.
    pub(super) fn validate_spin(&self) -> Result<(), ModelError> {
        let Some(time_scale) = self.gravity_time() else {
            return Ok(());
        };
        let size = self.body.semi_axes().max();
        let init = &self.initial;
        let spin = init
            .omega_body
            .unwrap_or_else(|| init.angles.omega_body())
            .norm();
        let dimensionless = spin * time_scale;
        if dimensionless > MAX_DIMENSIONLESS_SPIN {
            let a = &init.angles;
            let (key, value) = match init.omega_body {
                Some(w) => ("initial.omega_body", Value::vector(&w)),
                None => [
                    ("initial.theta_dot", a.theta_dot),
                    ("initial.phi_dot", a.phi_dot),
                    ("initial.psi_dot", a.psi_dot),
                ]
                .into_iter()
                .max_by(|x, y| x.1.abs().total_cmp(&y.1.abs()))
                .map(|(k, v)| (k, Value::from(v)))
                .expect("three rates"),
            };
            return Err(ModelError::invalid(
                key,
                value,
                format!(
                    "the spin |ω| = {spin:.3e} rad/s is {dimensionless:.3e} in units of √(g/L) (L = max(a, b, c) = {} m, g = {} m/s^2), \
                     more than {MAX_DIMENSIONLESS_SPIN:e} ≈ 1/√ε: ω²L/g > 1/ε puts gravity below the round-off of the spin's own terms",
                    number(size),
                    number(self.gravity)
                ),
            ));
        }
        Ok(())
    }

    /// The viscous model: μ_v finite, in [0, [`MAX_VISCOUS_FRICTION`]], on a body without
    /// contact spheres (contact on two surfaces is simulated with Coulomb friction only).
    fn validate_viscous(&self, viscous_friction: f64) -> Result<(), ModelError> {
        if !(viscous_friction.is_finite()
            && (0.0..=MAX_VISCOUS_FRICTION).contains(&viscous_friction))
        {
            return Err(ModelError::invalid(
                "contact.viscous_friction",
                viscous_friction,
                format!(
                    "the viscous coefficient μ_v must be finite and within [0, {}] s/m \
                     (the slip relaxes at a rate ~ μ_v g: beyond that bound its time is below a microsecond)",
                    number(MAX_VISCOUS_FRICTION)
                ),
            ));
        }
        if !self.body.plain() {
            return Err(ModelError::invalid(
                "contact.model",
                Value::Choice("viscous".into()),
                "the viscous model is simulated with one contact: a body with contact spheres or rims needs model = \"sliding\" or \"coulomb\"",
            ));
        }
        Ok(())
    }

    /// A contact disc: R finite and positive, smaller than the body, under a friction
    /// model, and not doubled by the regularised spin friction.
    fn validate_disc(&self, disc: &ContactDisc) -> Result<(), ModelError> {
        const KEY: &str = "contact.contact_radius";
        let r = disc.radius;
        if !(r.is_finite() && r > 0.0) {
            return Err(ModelError::invalid(
                KEY,
                r,
                "the contact radius must be finite and non-negative (m); 0 is a point contact",
            ));
        }
        if self.contact.friction().is_none() {
            return Err(ModelError::invalid(
                KEY,
                r,
                "a contact disc carries friction: it needs model = \"sliding\" or \"coulomb\" (or contact_radius = 0)",
            ));
        }
        let smallest = self.body.semi_axes().min();
        if !(r < smallest) {
            return Err(ModelError::invalid(
                KEY,
                r,
                format!(
                    "the contact disc must be smaller than the body: R < min(a, b, c) = {} m",
                    number(smallest)
                ),
            ));
        }
        if let Some(s) = self.effects.spin_friction {
            return Err(ModelError::invalid(
                "effects.spin_friction",
                s.coefficient,
                format!(
                    "the contact disc (contact.contact_radius = {} m) already carries the drilling friction; use one or the other",
                    number(r)
                ),
            ));
        }
        Ok(())
    }

    fn validate_observe(&self) -> Result<(), ModelError> {
        validate_crossings(
            &self.body,
            "observe",
            "observable",
            MAX_OBSERVE,
            self.observe.iter(),
        )?;
        validate_crossings(
            &self.body,
            "section",
            "section",
            MAX_SECTIONS,
            self.sections.iter().map(|s| &s.crossing),
        )?;
        for s in &self.sections {
            if !(1..=MAX_SECTION_POINTS).contains(&s.max_points) {
                return Err(ModelError::invalid(
                    "section.max_points",
                    s.max_points,
                    format!("a section keeps 1 to {MAX_SECTION_POINTS} points"),
                ));
            }
            if s.crossing.terminal {
                return Err(ModelError::invalid(
                    "section.terminal",
                    Value::Text("true".into()),
                    "a section's crossings never end the run (max_points bounds it)",
                ));
            }
        }
        let total = (self.sections.iter()).fold(0u64, |n, s| n.saturating_add(s.max_points));
        if total > MAX_SECTION_POINTS {
            return Err(ModelError::invalid(
                "section.max_points",
                Value::Count(total, "points in all"),
                format!(
                    "the sections together keep at most {MAX_SECTION_POINTS} points (the sum of their max_points)"
                ),
            ));
        }
        Ok(())
    }
}

/// Checks the crossings of `[[observe]]` or `[[section]]` entries (`table`; each a `what`):
/// at most `max`, unique names of 1 to 100 bytes, numeric columns, finite values.
fn validate_crossings<'a>(
    body: &Body,
    table: &str,
    what: &str,
    max: usize,
    list: impl ExactSizeIterator<Item = &'a Observe> + Clone,
) -> Result<(), ModelError> {
    if list.len() > max {
        return Err(ModelError::invalid(
            table,
            Value::Count(list.len() as u64, "entries"),
            format!("at most {max} entries"),
        ));
    }
    let field = |key: &str| format!("{table}.{key}");
    for (k, o) in list.clone().enumerate() {
        if o.name.is_empty() || o.name.len() > 100 {
            return Err(ModelError::invalid(
                field("name"),
                Value::Name(o.name.clone()),
                format!("a {what} needs a name of 1 to 100 bytes"),
            ));
        }
        if list.clone().take(k).any(|p| p.name == o.name) {
            return Err(ModelError::invalid(
                field("name"),
                Value::Name(o.name.clone()),
                format!("{what} names must be unique"),
            ));
        }
        let layout = columns::Layout::of(body);
        if o.column >= layout.numeric() {
            let names: Vec<String> = layout
                .numeric_columns()
                .into_iter()
                .map(|c| c.0.into_owned())
                .collect();
            return Err(ModelError::invalid(
                field("column"),
                o.column,
                format!("not a numeric column (one of {})", names.join(", ")),
            ));
        }
        if !o.crosses.is_finite() {
            return Err(ModelError::invalid(
                field("crosses"),
                o.crosses,
                "the value crossed must be finite",
            ));
        }
    }
    Ok(())
}
