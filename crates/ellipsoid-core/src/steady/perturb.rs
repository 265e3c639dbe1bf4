//! A steady motion started as a scenario, displaced along one of its modes, so that a run
//! shows the mode grow or oscillate (docs/physics.md, "Steady motions and their
//! stability").

use crate::error::{Brackets, Digits, ModelError, Value};
use crate::scenario::{self, Scenario, ScenarioErrors};

use super::{Analysis, started_at};

/// Largest |ε| a perturbation takes \[rad of tilt\]: beyond it the linearisation says
/// little about the start.
pub const MAX_EPSILON: f64 = 0.1;

/// `scenario` started on the steady motion `an` displaced by ε along mode `k` (0-based,
/// `an.spectrum.modes` order; the displacement ε Re(v), [`Analysis::perturbation`]), as
/// a scenario of its own: the `[initial]` table replaced by the displaced attitude
/// (θ, φ = 0, ψ), body angular velocity, position, and the horizontal velocity of a
/// body at rest horizontally (frictionless and sliding; the rolling models take G's
/// velocity from the no-slip constraint), every other table as the scenario has it.
pub fn perturbed(
    scenario: &Scenario,
    an: &Analysis,
    k: usize,
    epsilon: f64,
) -> Result<Scenario, ScenarioErrors> {
    let modes = an.spectrum.modes.len();
    if k >= modes {
        return Err(scenario
            .locate(&ModelError::invalid(
                "mode",
                k + 1,
                format!(
                    "the {} motion has modes 1 to {modes}",
                    an.motion.family.name()
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
    let delta = an.perturbation(k, epsilon);
    let scene = started_at(&scenario.scene, &an.motion.at, &delta);
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
