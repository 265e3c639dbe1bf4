//! `ellipsoid.steady` and `ellipsoid.linearize` (docs/physics.md, "Steady motions and
//! their stability"): the raw arrays; `python/ellipsoid/_steady.py` wraps them in the
//! `Steady` result.

use ellipsoid_core::error::{ModelError, Value};
use ellipsoid_core::scenario::Scenario;
use ellipsoid_core::steady::{self, Analysis, COORDINATES, Family, Phase, Solve};
use numpy::{Complex64, PyArray1, PyArray2};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors;
use crate::scenario::{PyScenario, resolve};

/// A model error placed at its scenario key, as ScenarioError.
fn located(py: Python<'_>, scenario: &Scenario, e: &ModelError) -> PyErr {
    errors::scenario_error(py, &scenario.locate(e))
}

/// The analyses of `family` for `scenario` (one, or one per value of `key`; a tilted
/// family solving for `solve`: "spin", "phi_dot" or "theta") as a dict of
/// numpy arrays and lists: values, eigenvalues (n × 4 complex; n × 2 for a tilted
/// family), names (likewise), states (n × 6: ζ, ω), spin, theta, normal_force, stable,
/// critical (list of dicts); for a tilted family also phi_dot and circles (n × 2: the
/// radii of G's and the contact point's circles), None otherwise.
#[pyfunction]
#[pyo3(signature = (scenario, family, key = None, values = None, solve = "spin"))]
pub fn steady_raw<'py>(
    py: Python<'py>,
    scenario: &Bound<'py, PyAny>,
    family: &str,
    key: Option<String>,
    values: Option<Vec<f64>>,
    solve: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let scenario = resolve(py, scenario, Vec::new())?.inner;
    let family = Family::parse(family).map_err(|e| located(py, &scenario, &e))?;
    let solve = Solve::parse(solve).map_err(|e| located(py, &scenario, &e))?;
    let (key, values, rows, critical) = match (key, values) {
        (Some(key), Some(values)) => {
            let sw = py
                .detach(|| steady::sweep_solving(&scenario, family, solve, &key, &values))
                .map_err(|e| located(py, &scenario, &e))?;
            (Some(key), sw.values, sw.rows, sw.critical)
        }
        _ => {
            let an = steady::analyse_solving(&scenario.scene, family, solve)
                .map_err(|e| located(py, &scenario, &e))?;
            (None, vec![an.motion.spin], vec![Ok(an)], Vec::new())
        }
    };
    let analyses: Vec<&Analysis> = rows
        .iter()
        .zip(&values)
        .map(|(r, v)| {
            r.as_ref().map_err(|e| {
                let e = ModelError::invalid(
                    key.as_deref().unwrap_or("initial"),
                    *v,
                    format!("no steady motion there: {e}"),
                );
                located(py, &scenario, &e)
            })
        })
        .collect::<PyResult<_>>()?;
    let eig: Vec<Vec<Complex64>> = analyses
        .iter()
        .map(|a| {
            a.spectrum
                .eigenvalues()
                .iter()
                .map(|z| Complex64::new(z.re, z.im))
                .collect()
        })
        .collect();
    let names: Vec<Vec<&str>> = analyses
        .iter()
        .map(|a| a.spectrum.modes.iter().map(|m| m.name).collect())
        .collect();
    let states: Vec<Vec<f64>> = analyses
        .iter()
        .map(|a| a.motion.at.iter().copied().collect())
        .collect();
    let column =
        |f: &dyn Fn(&Analysis) -> f64| -> Vec<f64> { analyses.iter().map(|a| f(a)).collect() };
    let out = PyDict::new(py);
    out.set_item("key", key)?;
    out.set_item("family", family.name())?;
    out.set_item("values", PyArray1::from_vec(py, values))?;
    out.set_item("eigenvalues", PyArray2::from_vec2(py, &eig)?)?;
    out.set_item("modes", names)?;
    out.set_item("states", PyArray2::from_vec2(py, &states)?)?;
    out.set_item("spin", PyArray1::from_vec(py, column(&|a| a.motion.spin)))?;
    out.set_item("theta", PyArray1::from_vec(py, column(&|a| a.motion.theta)))?;
    out.set_item(
        "normal_force",
        PyArray1::from_vec(py, column(&|a| a.motion.normal_force)),
    )?;
    let tilted = |f: &dyn Fn(&Analysis) -> Option<Vec<f64>>| -> Option<Vec<Vec<f64>>> {
        analyses.iter().map(|a| f(a)).collect()
    };
    let phi_dot = tilted(&|a| a.motion.precession.map(|p| vec![p]))
        .map(|v| PyArray1::from_vec(py, v.concat()));
    out.set_item("phi_dot", phi_dot)?;
    let circles = tilted(&|a| a.motion.circles.map(|c| vec![c.center, c.contact]))
        .map(|v| PyArray2::from_vec2(py, &v))
        .transpose()?;
    out.set_item("circles", circles)?;
    out.set_item(
        "max_real",
        PyArray1::from_vec(py, column(&|a| a.spectrum.max_real())),
    )?;
    let stable: Vec<bool> = analyses.iter().map(|a| a.spectrum.stable()).collect();
    out.set_item("stable", PyArray1::from_vec(py, stable))?;
    let crit = critical
        .iter()
        .map(|c| {
            let d = PyDict::new(py);
            d.set_item("value", c.value)?;
            d.set_item("kind", c.kind.name())?;
            d.set_item(
                "stable_side",
                if c.stable_above { "above" } else { "below" },
            )?;
            d.set_item(
                "eigenvalue",
                pyo3::types::PyComplex::from_doubles(py, c.eigenvalue.re, c.eigenvalue.im),
            )?;
            Ok(d)
        })
        .collect::<PyResult<Vec<_>>>()?;
    out.set_item("critical", crit)?;
    Ok(out)
}

/// The scenario started on the steady motion of `family` that `scenario` defines (with
/// `key` set to `value`, if given), displaced by `epsilon` along mode `mode` (0-based,
/// its column in the eigenvalues): `steady::perturbed`, as `ellipsoid steady --perturb`.
#[pyfunction]
#[pyo3(signature = (scenario, family, mode, epsilon, key = None, value = None, solve = "spin"))]
#[allow(clippy::too_many_arguments)]
pub fn steady_start(
    py: Python<'_>,
    scenario: &Bound<'_, PyAny>,
    family: &str,
    mode: usize,
    epsilon: f64,
    key: Option<String>,
    value: Option<f64>,
    solve: &str,
) -> PyResult<PyScenario> {
    let mut scenario = resolve(py, scenario, Vec::new())?.inner;
    let family = Family::parse(family).map_err(|e| located(py, &scenario, &e))?;
    let solve = Solve::parse(solve).map_err(|e| located(py, &scenario, &e))?;
    if let (Some(key), Some(value)) = (key, value) {
        let mut draft = scenario.draft();
        draft
            .change(&key, &toml::Value::Float(value), &format!("{key}={value}"))
            .map_err(|e| errors::scenario_error(py, &e))?;
        scenario = draft.build().map_err(|e| errors::scenario_errors(py, &e))?;
    }
    let an = steady::analyse_solving(&scenario.scene, family, solve)
        .map_err(|e| located(py, &scenario, &e))?;
    let inner = steady::perturbed(&scenario, &an, mode, epsilon)
        .map_err(|e| errors::scenario_errors(py, &e))?;
    Ok(PyScenario { inner })
}

/// The Jacobian (5 × 5) of the reduced dynamics of `scenario` at `state` = (ζ1, ζ2, ζ3,
/// ω1, ω2, ω3), or at the scenario's initial state, and its coordinates' names.
#[pyfunction]
#[pyo3(signature = (scenario, state = None))]
pub fn linearize<'py>(
    py: Python<'py>,
    scenario: &Bound<'py, PyAny>,
    state: Option<Vec<f64>>,
) -> PyResult<(Bound<'py, PyArray2<f64>>, Vec<&'static str>)> {
    let scenario = resolve(py, scenario, Vec::new())?.inner;
    let at = match state {
        None => None,
        Some(s) if s.len() == 6 => Some(Phase::from_column_slice(&s)),
        Some(s) => {
            let e = ModelError::invalid(
                "state",
                Value::Count(s.len() as u64, "numbers"),
                "the state is (ζ1, ζ2, ζ3, ω1, ω2, ω3): 6 numbers",
            );
            return Err(located(py, &scenario, &e));
        }
    };
    let lin =
        steady::linearize_scene(&scenario.scene, at).map_err(|e| located(py, &scenario, &e))?;
    let rows: Vec<Vec<f64>> = (0..5)
        .map(|i| (0..5).map(|j| lin.jacobian[(i, j)]).collect())
        .collect();
    Ok((PyArray2::from_vec2(py, &rows)?, COORDINATES.to_vec()))
}
