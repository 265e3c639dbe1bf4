//! Pickling a `Trajectory` (joblib, multiprocessing): its samples travel as the float64
//! values of the numeric columns (one row per sample) and the mode names, its summary as
//! the summary JSON; both are read back here into the very values the run produced, so an
//! unpickled trajectory writes the same files and shows the same columns.

use ellipsoid_core::body::Surface;
use ellipsoid_core::columns::{Layout, NUMERIC, SURFACE_COLUMNS};
use ellipsoid_core::integrate::Stats;
use ellipsoid_core::invariants::{Drift, Invariant, Invariants};
use ellipsoid_core::simulate::{Mode, Sample, Status};
use ellipsoid_core::state::EulerAngles;
use ellipsoid_io::Summary;
use ellipsoid_io::summary::CheckResult;
use nalgebra::{Vector2, Vector3};
use serde_json::{Map, Value};

/// The sample whose numeric columns (`layout`'s order) are `v`, its mode label `label`:
/// the inverse of `columns::values` and `Layout::{surface_values, mode}` (`None` for a
/// label the layout cannot write).
pub fn sample(layout: &Layout, v: &[f64], label: &str) -> Option<Sample> {
    let (mode, surfaces) = layout.parse_mode(label)?;
    // The normal force of a surface in contact: its column (a body with contact
    // spheres), or the one contact's.
    let normal = |surface: Surface| match surface {
        _ if layout.extra() == 0 => v[17],
        Surface::Ellipsoid => v[NUMERIC],
        Surface::Sphere(k) => v[NUMERIC + SURFACE_COLUMNS.len() * (k + 1)],
    };
    let touching = match (mode, surfaces.as_slice()) {
        (Mode::Flight, _) => [None, None],
        (_, []) => [Some((Surface::Ellipsoid, v[17])), None],
        (_, [a]) => [Some((*a, normal(*a))), None],
        (_, [a, b, ..]) => [Some((*a, normal(*a))), Some((*b, normal(*b)))],
    };
    Some(Sample {
        t: v[0],
        position: Vector3::new(v[1], v[2], v[3]),
        angles: EulerAngles {
            theta: v[4],
            phi: v[5],
            psi: v[6],
            theta_dot: v[7],
            phi_dot: v[8],
            psi_dot: v[9],
        },
        omega: Vector3::new(v[10], v[11], v[12]),
        velocity: Vector3::new(v[13], v[14], v[15]),
        energy: v[16],
        normal_force: v[17],
        slip_speed: v[18],
        work: v[19],
        omega_world: Vector3::new(v[20], v[21], v[22]),
        contact: Vector2::new(v[23], v[24]),
        drift: v[25],
        gap: v[26],
        mode,
        touching,
    })
}

/// The summary whose JSON (`Summary::to_json`) is `json`: every field read back.
pub fn summary(json: &str) -> Result<Summary, String> {
    let v: Value = serde_json::from_str(json).map_err(|e| e.to_string())?;
    let get = |k: &str| v.get(k).ok_or_else(|| format!("the summary has no `{k}`"));
    let text = |k: &str| -> Result<String, String> {
        get(k)?
            .as_str()
            .map(str::to_owned)
            .ok_or_else(|| format!("summary `{k}` is not a string"))
    };
    let object = |k: &str| -> Result<Map<String, Value>, String> {
        get(k)?
            .as_object()
            .cloned()
            .ok_or_else(|| format!("summary `{k}` is not an object"))
    };
    let strings = |k: &str| -> Result<Vec<String>, String> {
        serde_json::from_value(get(k)?.clone()).map_err(|e| format!("summary `{k}`: {e}"))
    };
    let status_name = text("status")?;
    let status = Status::NAMES
        .iter()
        .find(|n| **n == status_name)
        .ok_or_else(|| format!("unknown status {status_name:?}"))?;
    let stats = object("stats")?;
    let count = |k: &str| stats.get(k).and_then(Value::as_u64).unwrap_or(0);
    let st = Stats {
        accepted: count("accepted"),
        rejected: count("rejected"),
        rhs_evals: count("rhs_evals"),
        events: count("events"),
        min_step: stats
            .get("min_step")
            .and_then(Value::as_f64)
            .unwrap_or(f64::INFINITY),
    };
    let drifts = object("drift")?;
    let drift = Drift(Invariant::ALL.map(|i| drifts.get(i.name()).and_then(Value::as_f64)));
    let checks = object("checks")?
        .into_iter()
        .map(|(k, c)| {
            let passed = c.get("passed").and_then(Value::as_bool).unwrap_or(false);
            let field = |f: &str| c.get(f).cloned().unwrap_or(Value::Null);
            (
                k,
                CheckResult {
                    expected: field("expected"),
                    actual: field("actual"),
                    passed,
                },
            )
        })
        .collect();
    Ok(Summary {
        status,
        message: text("message")?,
        events: serde_json::from_value(get("events")?.clone()).map_err(|e| e.to_string())?,
        stats: st,
        wall_time_s: get("wall_time_s")?.as_f64().unwrap_or(0.0),
        samples: get("samples")?.as_u64().unwrap_or(0),
        final_state: object("final")?,
        drift,
        initial_invariants: invariants(get("initial_invariants")?)?,
        final_invariants: invariants(get("final_invariants")?)?,
        warnings: strings("warnings")?,
        checks,
        units: object("units")?,
        scenario: text("scenario")?,
        overrides: strings("overrides")?,
        output: get("output")?.as_str().map(str::to_owned),
        version: text("version")?,
    })
}

fn invariants(v: &Value) -> Result<Invariants, String> {
    let f = |k: &str| {
        v.get(k)
            .and_then(Value::as_f64)
            .ok_or_else(|| format!("invariant `{k}` missing"))
    };
    let p = v
        .get("momentum")
        .and_then(Value::as_array)
        .filter(|a| a.len() == 2)
        .and_then(|a| Some([a[0].as_f64()?, a[1].as_f64()?]))
        .ok_or("invariant `momentum` missing")?;
    Ok(Invariants {
        energy: f("energy")?,
        energy_plus_work: f("energy_plus_work")?,
        momentum: p,
        angular_momentum_z: f("angular_momentum_z")?,
        axial_spin: f("axial_spin")?,
        jellett: f("jellett")?,
    })
}
