//! A steady motion started as a scenario, displaced along one of its modes, so that a run
//! shows the mode grow or oscillate (docs/physics.md, "Steady motions and their
//! stability").

use crate::error::{Brackets, Digits, ModelError, Value};
use crate::scenario::{self, Scenario, ScenarioErrors};
use crate::simulate::Scene;

use super::families::Family;
use super::viscous::{self, ViscousSpin};
use super::{Analysis, started_at};

/// Largest |ε| a perturbation takes \[rad of tilt\]: beyond it the linearisation says
/// little about the start.
pub const MAX_EPSILON: f64 = 0.1;

/// A steady motion with modes, which a run can start displaced along one of them.
pub trait Start {
    /// The motion's family.
    fn family(&self) -> Family;
    /// What moves in each mode, in the order of the modes (the table's).
    fn mode_names(&self) -> Vec<&'static str>;
    /// `scene` started on the motion displaced by ε Re(v) along mode `k` (0-based).
    fn started(&self, scene: &Scene, k: usize, epsilon: f64) -> Scene;
}

impl Start for Analysis {
    fn family(&self) -> Family {
        self.motion.family
    }
    fn mode_names(&self) -> Vec<&'static str> {
        self.spectrum.modes.iter().map(|m| m.name).collect()
    }
    /// [`started_at`] the motion displaced by [`Analysis::perturbation`].
    fn started(&self, scene: &Scene, k: usize, epsilon: f64) -> Scene {
        started_at(scene, &self.motion.at, &self.perturbation(k, epsilon))
    }
}

impl Start for ViscousSpin {
    fn family(&self) -> Family {
        self.family
    }
    fn mode_names(&self) -> Vec<&'static str> {
        ViscousSpin::mode_names(self)
    }
    /// [`viscous::started_at`] the spin displaced by [`ViscousSpin::perturbation`]
    /// (G's horizontal velocity displaced too).
    fn started(&self, scene: &Scene, k: usize, epsilon: f64) -> Scene {
        viscous::started_at(scene, &self.at(), &self.perturbation(k, epsilon))
    }
}

/// `scenario` started on the steady motion `motion` displaced by ε along mode `k`
/// (0-based, in the order of [`Start::mode_names`]; the displacement ε Re(v)), as a
/// scenario of its own: the `[initial]` table replaced by the displaced attitude
/// (θ, φ = 0, ψ), body angular velocity, position, and G's horizontal velocity (at rest
/// horizontally without friction and sliding; displaced along the mode under the viscous
/// law; the rolling models take it from the no-slip constraint), every other table as
/// the scenario has it.
pub fn perturbed<M: Start>(
    scenario: &Scenario,
    motion: &M,
    k: usize,
    epsilon: f64,
) -> Result<Scenario, ScenarioErrors> {
    let modes = motion.mode_names().len();
    if k >= modes {
        return Err(scenario
            .locate(&ModelError::invalid(
                "mode",
                k + 1,
                format!(
                    "the {} motion has modes 1 to {modes}",
                    motion.family().name()
                ),
            ))
            .into());
    }
    if !(epsilon.is_finite() && epsilon.abs() <= MAX_EPSILON) {
        return Err(scenario
            .locate(&ModelError::invalid(
                "epsilon",
                Value::Numbers {
                    values: vec![epsilon],
                    digits: Digits::Plain,
                    brackets: Brackets::None,
                },
                format!("a perturbation is finite and at most {MAX_EPSILON} in size"),
            ))
            .into());
    }
    let scene = motion.started(&scenario.scene, k, epsilon);
    let init = &scene.initial;
    let list = |v: &[f64]| toml::Value::Array(v.iter().map(|&x| toml::Value::Float(x)).collect());
    let mut table = toml::Table::new();
    let a = &init.angles;
    table.insert("theta".into(), toml::Value::Float(a.theta));
    table.insert("phi".into(), toml::Value::Float(a.phi));
    table.insert("psi".into(), toml::Value::Float(a.psi));
    let omega = init.omega_body.expect("started_at gives ω in body axes");
    table.insert("omega_body".into(), list(omega.as_slice()));
    table.insert("position".into(), list(init.position.as_slice()));
    if let Some(v) = init.velocity {
        table.insert("velocity".into(), list(v.as_slice()));
    }
    let label = format!("initial=<mode {} displaced by {epsilon}>", k + 1);
    let mut draft = scenario.draft();
    draft.change("initial", &toml::Value::Table(table), &label)?;
    let text = draft.canonical().map_err(|e| {
        ScenarioErrors::from(scenario.locate(&ModelError::invalid(
            "initial",
            Value::Text("the perturbed state".into()),
            format!("cannot be written as TOML: {e}"),
        )))
    })?;
    scenario::parse_all(&text, &scenario.source, &[] as &[&str])
}
