//! `ellipsoid.steady` and `ellipsoid.linearize` (docs/physics.md, "Steady motions and
//! their stability"): the raw arrays; `python/ellipsoid/_steady.py` wraps them in the
//! `Steady` result.

use ellipsoid_core::body::Surface;
use ellipsoid_core::error::{ModelError, Value};
use ellipsoid_core::scenario::Scenario;
use ellipsoid_core::simulate::ContactModel;
use ellipsoid_core::steady::sweep::Row;
use ellipsoid_core::steady::viscous::ViscousSpin;
use ellipsoid_core::steady::{self, Analysis, COORDINATES, Family, Phase, Solve};
use numpy::{Complex64, PyArray1, PyArray2};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors;
use crate::run;
use crate::scenario::{PyScenario, resolve};

/// A model error placed at its scenario key, as ScenarioError.
fn located(py: Python<'_>, scenario: &Scenario, e: &ModelError) -> PyErr {
    errors::scenario_error(py, &scenario.locate(e))
}

/// What `steady_raw` returns of one value's analysis.
struct Summary {
    eigenvalues: Vec<Complex64>,
    names: Vec<&'static str>,
    /// (ζ, ω) in body axes.
    state: Vec<f64>,
    spin: f64,
    theta: f64,
    normal_force: f64,
    precession: Option<f64>,
    circles: Option<Vec<f64>>,
    max_real: f64,
    stable: bool,
    /// The surface the body rests on.
    surface: Surface,
}

impl From<&Analysis> for Summary {
    fn from(a: &Analysis) -> Summary {
        Summary {
            eigenvalues: complex(&a.spectrum.eigenvalues()),
            names: a.spectrum.modes.iter().map(|m| m.name).collect(),
            state: a.motion.at.iter().copied().collect(),
            spin: a.motion.spin,
            theta: a.motion.theta,
            normal_force: a.motion.normal_force,
            precession: a.motion.precession,
            circles: a.motion.circles.map(|c| vec![c.center, c.contact]),
            max_real: a.spectrum.max_real(),
            stable: a.spectrum.stable(),
            surface: a.motion.surface,
        }
    }
}

impl From<&ViscousSpin> for Summary {
    fn from(v: &ViscousSpin) -> Summary {
        Summary {
            eigenvalues: complex(&v.eigenvalues),
            names: v.mode_names(),
            state: v.at().iter().take(6).copied().collect(),
            spin: v.spin + 0.0,
            theta: v.zeta.xy().norm().atan2(v.zeta.z),
            normal_force: v.normal_force,
            precession: None,
            circles: None,
            max_real: v.max_real(),
            stable: v.stable(),
            // The viscous model takes no contact spheres (the scene refuses them).
            surface: Surface::Ellipsoid,
        }
    }
}

fn complex(z: &[nalgebra::Complex<f64>]) -> Vec<Complex64> {
    z.iter().map(|z| Complex64::new(z.re, z.im)).collect()
}

/// The summaries of a sweep's rows, or the first value without a steady motion as
/// ScenarioError.
fn summaries<'a, T: 'a>(
    py: Python<'_>,
    scenario: &Scenario,
    key: Option<&str>,
    values: &[f64],
    rows: &'a [Row<T>],
) -> PyResult<Vec<Summary>>
where
    Summary: From<&'a T>,
{
    rows.iter()
        .zip(values)
        .map(|(r, v)| match r {
            Ok(a) => Ok(Summary::from(a)),
            Err(e) => {
                let e = ModelError::invalid(
                    key.unwrap_or("initial"),
                    *v,
                    format!("no steady motion there: {e}"),
                );
                Err(located(py, scenario, &e))
            }
        })
        .collect()
}

/// The analyses of `family` for `scenario` (one, or one per value of `key`; a tilted
/// family solving for `solve`: "spin", "phi_dot" or "theta"; the viscous model's upright
/// and inverted spins by `steady::viscous`) as a dict of numpy arrays and lists: values,
/// eigenvalues (n × 4 complex; n × 2 for a tilted family, n × 6 under the viscous law),
/// names (likewise), states (n × 6: ζ, ω), spin, theta, normal_force, stable, critical
/// (list of dicts), surface (the name of the surface each motion rests on); for a
/// tilted family also phi_dot and circles (n × 2: the radii of G's
/// and the contact point's circles), None otherwise. Ctrl-C stops a sweep before its next
/// value and raises KeyboardInterrupt.
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
    crate::plausible::warn(py, &scenario)?;
    let family = Family::parse(family).map_err(|e| located(py, &scenario, &e))?;
    let solve = Solve::parse(solve).map_err(|e| located(py, &scenario, &e))?;
    let viscous = matches!(scenario.scene.contact, ContactModel::Viscous { .. });
    let k = key.as_deref();
    let (values, rows, critical) = match (&key, values, viscous) {
        (Some(key), Some(values), false) => {
            let (sw, interrupt) = run::detached(py, |cancel| {
                steady::sweep_solving(
                    &scenario,
                    family,
                    solve,
                    key,
                    &values,
                    Some(cancel.as_ref()),
                )
            })?;
            if let Some(e) = interrupt {
                return Err(e);
            }
            let sw = sw.map_err(|e| located(py, &scenario, &e))?;
            let rows = summaries(py, &scenario, k, &sw.values, &sw.rows)?;
            (sw.values, rows, sw.critical)
        }
        (Some(key), Some(values), true) => {
            let (sw, interrupt) = run::detached(py, |cancel| {
                steady::viscous::sweep(&scenario, family, key, &values, Some(cancel.as_ref()))
            })?;
            if let Some(e) = interrupt {
                return Err(e);
            }
            let sw = sw.map_err(|e| located(py, &scenario, &e))?;
            let rows = summaries(py, &scenario, k, &sw.values, &sw.rows)?;
            (sw.values, rows, sw.critical)
        }
        (_, _, false) => {
            let an = steady::analyse_solving(&scenario.scene, family, solve)
                .map_err(|e| located(py, &scenario, &e))?;
            (vec![an.motion.spin], vec![Summary::from(&an)], Vec::new())
        }
        (_, _, true) => {
            let spin = steady::viscous::analyse(&scenario.scene, family)
                .map_err(|e| located(py, &scenario, &e))?;
            let row = Summary::from(&spin);
            (vec![row.spin], vec![row], Vec::new())
        }
    };
    let eig: Vec<Vec<Complex64>> = rows.iter().map(|r| r.eigenvalues.clone()).collect();
    let names: Vec<Vec<&str>> = rows.iter().map(|r| r.names.clone()).collect();
    let states: Vec<Vec<f64>> = rows.iter().map(|r| r.state.clone()).collect();
    let column = |f: &dyn Fn(&Summary) -> f64| -> Vec<f64> { rows.iter().map(f).collect() };
    let out = PyDict::new(py);
    out.set_item("key", key)?;
    out.set_item("family", family.name())?;
    out.set_item("values", PyArray1::from_vec(py, values))?;
    out.set_item("eigenvalues", PyArray2::from_vec2(py, &eig)?)?;
    out.set_item("modes", names)?;
    out.set_item("states", PyArray2::from_vec2(py, &states)?)?;
    out.set_item("spin", PyArray1::from_vec(py, column(&|r| r.spin)))?;
    out.set_item("theta", PyArray1::from_vec(py, column(&|r| r.theta)))?;
    out.set_item(
        "normal_force",
        PyArray1::from_vec(py, column(&|r| r.normal_force)),
    )?;
    let phi_dot: Option<Vec<f64>> = rows.iter().map(|r| r.precession).collect();
    out.set_item("phi_dot", phi_dot.map(|v| PyArray1::from_vec(py, v)))?;
    let circles: Option<Vec<Vec<f64>>> = rows.iter().map(|r| r.circles.clone()).collect();
    let circles = circles.map(|v| PyArray2::from_vec2(py, &v)).transpose()?;
    out.set_item("circles", circles)?;
    out.set_item("max_real", PyArray1::from_vec(py, column(&|r| r.max_real)))?;
    let stable: Vec<bool> = rows.iter().map(|r| r.stable).collect();
    out.set_item("stable", PyArray1::from_vec(py, stable))?;
    let body = &scenario.scene.body;
    let surfaces: Vec<&str> = rows.iter().map(|r| body.surface_name(r.surface)).collect();
    out.set_item("surface", surfaces)?;
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
/// its column in the eigenvalues; a spin of the viscous model too): `steady::perturbed`,
/// as `ellipsoid steady --perturb`.
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
    let inner = if matches!(scenario.scene.contact, ContactModel::Viscous { .. }) {
        let spin = steady::viscous::analyse(&scenario.scene, family)
            .map_err(|e| located(py, &scenario, &e))?;
        steady::perturbed(&scenario, &spin, mode, epsilon)
    } else {
        let an = steady::analyse_solving(&scenario.scene, family, solve)
            .map_err(|e| located(py, &scenario, &e))?;
        steady::perturbed(&scenario, &an, mode, epsilon)
    }
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
    state: Option<&Bound<'py, PyAny>>,
) -> PyResult<(Bound<'py, PyArray2<f64>>, Vec<&'static str>)> {
    let scenario = resolve(py, scenario, Vec::new())?.inner;
    // Read by hand: pyo3's extraction would raise a plain TypeError.
    let state = match state.filter(|s| !s.is_none()) {
        None => None,
        Some(s) => Some(s.extract::<Vec<f64>>().map_err(|_| {
            errors::type_error(
                py,
                &scenario.source,
                Some("state"),
                None,
                format!(
                    "expected a sequence of 6 numbers (ζ1, ζ2, ζ3, ω1, ω2, ω3), found {}",
                    crate::args::type_name(s)
                ),
            )
        })?),
    };
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
