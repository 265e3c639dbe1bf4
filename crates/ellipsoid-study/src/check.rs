//! What follows from a scenario without simulating it: the data `ellipsoid check` prints
//! and Python's `ellipsoid.check` returns (one function, [`derive`], builds it for both).
//!
//! The initial normal force, the initial contact regime and the list of tracked
//! invariants come from `simulate` itself, stopped at its first sample, so that they are
//! exactly what a run would use (and every check a run makes at t = 0 is made here).

use std::ops::ControlFlow;

use ellipsoid_core::body::{Body, Surface};
use ellipsoid_core::geometry::{self, Contact};
use ellipsoid_core::integrate::Method;
use ellipsoid_core::scenario::{Scenario, ScenarioError};
use ellipsoid_core::simulate::{self, ContactModel, EffectSet, Sample};
use nalgebra::{Matrix3, Vector3};
use serde::Serialize;

use crate::drift_entries;

/// Everything `ellipsoid check` prints, as data (SI units, radians; vectors in body axes
/// unless named `_world`). Serialises to the dict Python's `ellipsoid.check` returns.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Derived {
    /// The scenario file (or the name of its text).
    pub scenario: String,
    /// `--set` overrides applied, in order.
    pub overrides: Vec<String>,
    pub body: BodyData,
    /// g [m/s²].
    pub gravity: f64,
    pub contact: ContactData,
    /// The effects present (core's own declaration, serialised; None where absent).
    pub effects: EffectSet,
    pub initial: InitialData,
    /// The invariants the run tracks (conserved in this scene), in summary order.
    pub invariants: Vec<String>,
    pub solver: SolverData,
    pub output: OutputData,
    /// The scenario's `[check]` table.
    pub check: CheckData,
}

/// The body.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BodyData {
    /// a, b, c \[m\].
    pub semi_axes: [f64; 3],
    /// "sphere", "oblate spheroid", "prolate spheroid" or "triaxial ellipsoid".
    pub shape: &'static str,
    /// m \[kg\].
    pub mass: f64,
    /// Inertia tensor about G in body axes, by rows [kg m²].
    pub inertia: [[f64; 3]; 3],
    /// Its eigenvalues, ascending [kg m²].
    pub principal_moments: [f64; 3],
    /// G − C0 in body axes \[m\].
    pub com_offset: [f64; 3],
    /// gᵀA⁻²g (< 1: G inside the body).
    pub com_offset_radial: f64,
    /// m g \[N\].
    pub weight: f64,
    /// The contact spheres, in the body's order (empty: the ellipsoid alone touches).
    pub spheres: Vec<SphereData>,
    /// The rims, in the body's order.
    pub rims: Vec<RimData>,
    /// Whether the ellipsoid itself touches the plane (`body.ellipsoid_contact`).
    pub ellipsoid_contact: bool,
    /// The tilts θ* at which two surfaces touch the plane at once, lowest of all (a
    /// body of revolution with several surfaces; empty for one surface), by increasing
    /// θ; None for a body of several surfaces not of revolution about its c axis, whose
    /// θ* depends on the heading ψ.
    pub two_contact_tilts: Option<Vec<TwoContactTilt>>,
}

/// A tilt θ* at which two surfaces touch the plane at once (docs/physics.md, "Contact
/// spheres"): where their heights of G, h(ζ), are equal and no other surface is lower.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TwoContactTilt {
    /// The two surfaces' names, in the body's order.
    pub surfaces: [String; 2],
    /// θ* \[rad\] and in degrees.
    pub theta: f64,
    pub theta_deg: f64,
}

/// A contact sphere fixed in the body.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SphereData {
    /// Its name (its output columns and events name it).
    pub name: String,
    /// Its centre in body axes, from the ellipsoid's centre C0 \[m\].
    pub center: [f64; 3],
    /// Its radius \[m\].
    pub radius: f64,
}

/// A rim fixed in the body (docs/physics.md, "Rims").
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RimData {
    /// Its name (its output columns and events name it).
    pub name: String,
    /// The centre of its circle in body axes, from C0, on the z axis \[m\].
    pub center: [f64; 3],
    /// R, the radius of its circle \[m\].
    pub radius: f64,
    /// r, the radius of its rounded edge (0: sharp) \[m\].
    pub edge: f64,
}

/// The contact model.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ContactData {
    /// "frictionless", "sliding", "rolling" or "coulomb".
    pub model: &'static str,
    /// μ (sliding and coulomb), else None.
    pub friction: Option<f64>,
    /// μ_v [s/m] (viscous), else None.
    pub viscous_friction: Option<f64>,
    /// The contact disc (Coulomb–Contensou friction), None for a point contact.
    pub disc: Option<DiscData>,
}

/// A contact disc: `radius` [m] and `law` ("exact", "pade" or "ellipse").
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct DiscData {
    pub radius: f64,
    pub law: &'static str,
}

/// The initial state and what follows from it at t = 0.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct InitialData {
    /// z-x-z Euler angles \[rad\].
    pub theta: f64,
    pub phi: f64,
    pub psi: f64,
    /// θ in degrees.
    pub theta_deg: f64,
    /// The Euler-angle rates [rad/s]; None when `omega_body` was given instead.
    pub rates: Option<Rates>,
    /// Body angular velocity [rad/s] (given, or from the rates).
    pub omega_body: [f64; 3],
    /// Whether `omega_body` was given in the scenario.
    pub omega_body_given: bool,
    /// Contact point C relative to C0, body axes \[m\].
    pub contact_point: [f64; 3],
    /// Contact point in the world frame (z = 0 on the plane, to round-off) \[m\].
    pub contact_point_world: [f64; 3],
    /// Height of G above the plane \[m\].
    pub height: f64,
    /// The first sample of a run (None if the run produced none at t = 0).
    pub mode: Option<&'static str>,
    /// N \[N\].
    pub normal_force: Option<f64>,
    /// E \[J\].
    pub energy: Option<f64>,
    /// Speed of the contact point [m/s].
    pub slip_speed: Option<f64>,
    /// Velocity of G as the run starts it [m/s] (world axes): the given `velocity`, else
    /// what the contact model makes of its absence.
    pub velocity: Option<[f64; 3]>,
    /// Whether `[initial] velocity` was given in the scenario.
    pub velocity_given: bool,
}

/// θ̇, φ̇, ψ̇ [rad/s].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Rates {
    pub theta_dot: f64,
    pub phi_dot: f64,
    pub psi_dot: f64,
}

/// The solver settings.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SolverData {
    /// "rk4", "dopri5" or "dop853".
    pub method: &'static str,
    /// RK4's fixed step \[s\]; None for the adaptive methods.
    pub step: Option<f64>,
    /// rtol and atol of the adaptive methods; None for RK4.
    pub rtol: Option<f64>,
    pub atol: Option<f64>,
    /// Initial step hint of the adaptive methods \[s\].
    pub initial_step: Option<f64>,
}

/// The sampling.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct OutputData {
    /// \[s\].
    pub t_end: f64,
    /// Number of output times.
    pub samples: usize,
}

/// The `[check]` table.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CheckData {
    /// Expected status.
    pub status: Option<String>,
    /// Invariant name → largest allowed relative drift, in name order.
    pub drift: std::collections::BTreeMap<String, f64>,
}

/// The derived quantities of `scenario`: validates it, including every check a run
/// makes at t = 0 (a failing one is the error, placed in the scenario file).
pub fn derive(scenario: &Scenario) -> Result<Derived, Box<ScenarioError>> {
    let scene = &scenario.scene;
    let mut first_scene = scene.clone();
    first_scene.sample_times = vec![0.0];
    let mut first: Option<Sample> = None;
    let outcome = simulate::simulate(&first_scene, &mut |s| {
        first.get_or_insert(*s);
        ControlFlow::Break(())
    })
    .map_err(|e| Box::new(scenario.locate(&e)))?;

    let body = &scene.body;
    let (ax, i, g) = (body.semi_axes(), body.inertia(), body.com_offset());
    let mut moments: Vec<f64> = i.symmetric_eigenvalues().iter().copied().collect();
    moments.sort_by(f64::total_cmp);
    let radial = g.component_div(&ax).norm();
    let (model, friction) = (scene.contact.name(), scene.contact.friction());
    let init = &scene.initial;
    let a = &init.angles;
    let omega = init.omega_body.unwrap_or_else(|| a.omega_body());
    let rot = a.rotation().to_rotation_matrix().into_inner();
    let zeta = Vector3::new(rot[(2, 0)], rot[(2, 1)], rot[(2, 2)]);
    let contact = Contact::new(body, zeta, omega);
    let world_c = Vector3::new(init.position.x, init.position.y, contact.height) + rot * contact.r;
    let s = &scene.solver;
    let (step, rtol, atol, initial_step) = match s.method {
        Method::Rk4 { h } => (Some(h), None, None, None),
        _ => (None, Some(s.rtol), Some(s.atol), s.initial_step),
    };
    Ok(Derived {
        scenario: scenario.source.clone(),
        overrides: scenario.overrides.clone(),
        body: BodyData {
            semi_axes: arr(&ax),
            shape: shape(&ax),
            mass: body.mass(),
            inertia: rows(i),
            principal_moments: [moments[0], moments[1], moments[2]],
            com_offset: arr(&g),
            com_offset_radial: radial * radial,
            weight: body.mass() * scene.gravity,
            spheres: body
                .spheres()
                .iter()
                .map(|sp| SphereData {
                    name: sp.name.clone(),
                    center: arr(&sp.center),
                    radius: sp.radius,
                })
                .collect(),
            rims: (body.rims().iter())
                .map(|rim| RimData {
                    name: rim.name.clone(),
                    center: arr(&rim.center),
                    radius: rim.radius,
                    edge: rim.edge,
                })
                .collect(),
            ellipsoid_contact: body.ellipsoid_contact(),
            two_contact_tilts: two_contact_tilts(body),
        },
        gravity: scene.gravity,
        contact: ContactData {
            model,
            friction,
            viscous_friction: match scene.contact {
                ContactModel::Viscous { viscous_friction } => Some(viscous_friction),
                _ => None,
            },
            disc: scene.disc.map(|d| DiscData {
                radius: d.radius,
                law: d.law.name(),
            }),
        },
        effects: scene.effects,
        initial: InitialData {
            theta: a.theta,
            phi: a.phi,
            psi: a.psi,
            theta_deg: a.theta.to_degrees(),
            rates: match init.omega_body {
                Some(_) => None,
                None => Some(Rates {
                    theta_dot: a.theta_dot,
                    phi_dot: a.phi_dot,
                    psi_dot: a.psi_dot,
                }),
            },
            omega_body: arr(&omega),
            omega_body_given: init.omega_body.is_some(),
            contact_point: arr(&contact.p_c),
            contact_point_world: arr(&world_c),
            height: contact.height,
            mode: first.map(|s| s.mode.name()),
            normal_force: first.map(|s| s.normal_force),
            energy: first.map(|s| s.energy),
            slip_speed: first.map(|s| s.slip_speed),
            velocity: first.map(|s| arr(&s.velocity)),
            velocity_given: init.velocity.is_some(),
        },
        invariants: drift_entries(&outcome.drift)
            .into_iter()
            .filter(|(_, v)| v.is_some())
            .map(|(k, _)| k.to_owned())
            .collect(),
        solver: SolverData {
            method: s.method.name(),
            step,
            rtol,
            atol,
            initial_step,
        },
        output: OutputData {
            t_end: scene.t_end,
            samples: scene.sample_times.len(),
        },
        check: CheckData {
            status: scenario.check.status.clone(),
            drift: scenario.check.drift.clone(),
        },
    })
}

/// Intervals of θ over [0, π] searched for a change of sign of h1 − h2 (a pair of roots
/// closer than π/3600 = 0.05° would be missed).
const TILT_GRID: usize = 3600;

/// The tilts θ* of a body of revolution about its c axis (a = b, sphere centres and G
/// on the axis, to 1e-12 of its size) at which two of its surfaces touch at once
/// ([`TwoContactTilt`]): the roots in [0, π] of h1(θ) − h2(θ) along the meridian ψ = 0,
/// bracketed on a grid of [`TILT_GRID`] intervals and bisected to round-off, kept where
/// no third surface is lower. Empty for a body of one surface; None when a body of
/// several is not of revolution.
fn two_contact_tilts(body: &Body) -> Option<Vec<TwoContactTilt>> {
    let surfaces: Vec<Surface> = body.surfaces().collect();
    if surfaces.len() < 2 {
        return Some(Vec::new());
    }
    let ax = body.semi_axes();
    let tol = 1e-12 * ax.max();
    let on_axis = |c: &Vector3<f64>| c.x.abs().max(c.y.abs()) <= tol;
    if (ax.x - ax.y).abs() > tol
        || !on_axis(&body.com_offset())
        || !body.spheres().iter().all(|sp| on_axis(&sp.center))
    {
        return None;
    }
    let zeta = |theta: f64| Vector3::new(0.0, theta.sin(), theta.cos());
    let h = |s: Surface, theta: f64| geometry::height(body, s, zeta(theta));
    let mut tilts = Vec::new();
    for (i, &s1) in surfaces.iter().enumerate() {
        for &s2 in &surfaces[i + 1..] {
            let f = |theta: f64| h(s1, theta) - h(s2, theta);
            let step = std::f64::consts::PI / TILT_GRID as f64;
            for k in 0..TILT_GRID {
                let (mut lo, mut hi) = (k as f64 * step, (k + 1) as f64 * step);
                let (f_lo, f_hi) = (f(lo), f(hi));
                if !(f_lo < 0.0 && f_hi >= 0.0 || f_lo > 0.0 && f_hi <= 0.0) {
                    continue;
                }
                for _ in 0..200 {
                    let mid = 0.5 * (lo + hi);
                    if mid <= lo || mid >= hi {
                        break;
                    }
                    if (f(mid) > 0.0) == (f_lo > 0.0) {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                let theta = 0.5 * (lo + hi);
                let both = h(s1, theta).max(h(s2, theta));
                if surfaces
                    .iter()
                    .all(|&s| s == s1 || s == s2 || h(s, theta) < both - tol)
                {
                    tilts.push(TwoContactTilt {
                        surfaces: [
                            body.surface_name(s1).to_owned(),
                            body.surface_name(s2).to_owned(),
                        ],
                        theta,
                        theta_deg: theta.to_degrees(),
                    });
                }
            }
        }
    }
    tilts.sort_by(|a, b| a.theta.total_cmp(&b.theta));
    Some(tilts)
}

fn shape(ax: &Vector3<f64>) -> &'static str {
    if ax.x == ax.y && ax.y == ax.z {
        "sphere"
    } else if ax.x == ax.y {
        if ax.z < ax.x {
            "oblate spheroid"
        } else {
            "prolate spheroid"
        }
    } else {
        "triaxial ellipsoid"
    }
}

fn arr(v: &Vector3<f64>) -> [f64; 3] {
    [v.x, v.y, v.z]
}

fn rows(m: &Matrix3<f64>) -> [[f64; 3]; 3] {
    [0, 1, 2].map(|i| [m[(i, 0)], m[(i, 1)], m[(i, 2)]])
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn load(name: &str, set: &[&str]) -> Scenario {
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../scenarios")
            .join(name);
        ellipsoid_core::scenario::load(&path, set).unwrap()
    }

    #[test]
    fn nutation_derives_its_body_contact_and_first_sample() {
        let d = derive(&load("nutation.toml", &[])).unwrap();
        assert_eq!(d.body.shape, "oblate spheroid");
        assert_eq!(d.body.principal_moments, [9.3125e-6, 9.3125e-6, 1.25e-5]);
        assert_eq!(d.contact.model, "frictionless");
        assert_eq!(d.initial.mode, Some("frictionless"));
        // N < m g: the body is tilted and G accelerates downwards at t = 0.
        let n = d.initial.normal_force.unwrap();
        assert!(n > 0.0 && n < d.body.weight, "{n}");
        assert!(d.initial.contact_point_world[2].abs() < 1e-15);
        assert_eq!(
            d.invariants,
            [
                "energy",
                "energy_plus_work",
                "momentum",
                "angular_momentum_z",
                "axial_spin"
            ]
        );
        assert_eq!((d.solver.method, d.solver.step), ("dop853", None));
        assert_eq!(d.output.samples, 10001);
        assert!(d.body.spheres.is_empty() && d.contact.viscous_friction.is_none());
    }

    /// Euler's disk lists its two rims, and that its ellipsoid does not touch.
    #[test]
    fn rims_are_reported() {
        let scenario = load("euler-disk.toml", &[]);
        let d = derive(&scenario).unwrap();
        let rims = scenario.scene.body.rims();
        assert_eq!(d.body.rims.len(), 2);
        for (got, rim) in d.body.rims.iter().zip(rims) {
            assert_eq!(
                (&got.name, got.radius, got.edge),
                (&rim.name, rim.radius, rim.edge)
            );
            assert_eq!(got.center, [rim.center.x, rim.center.y, rim.center.z]);
        }
        assert!(!d.body.ellipsoid_contact);
    }

    /// A tippe top's stem is listed with the body, as the scenario gives it.
    #[test]
    fn contact_spheres_are_reported() {
        let d = derive(&load("tippe-top-stem.toml", &[])).unwrap();
        let scenario = load("tippe-top-stem.toml", &[]);
        let spheres = scenario.scene.body.spheres();
        assert_eq!(d.body.spheres.len(), spheres.len());
        assert!(!spheres.is_empty());
        for (got, sp) in d.body.spheres.iter().zip(spheres) {
            assert_eq!(
                (got.name.as_str(), got.radius),
                (sp.name.as_str(), sp.radius)
            );
            assert_eq!(got.center, arr(&sp.center));
        }
    }

    #[test]
    fn friction_effects_and_a_fixed_step_are_reported() {
        let d = derive(&load(
            "spin-friction.toml",
            &["solver.method=\"rk4\"", "solver.step=1e-4"],
        ))
        .unwrap();
        assert_eq!(d.contact.model, "coulomb");
        assert!(d.contact.friction.is_some_and(|mu| mu > 0.0));
        let s = d.effects.spin_friction.expect("spin friction");
        assert_eq!(s.coefficient, 3e-4);
        assert!(d.effects.rolling_resistance.is_none() && d.effects.air_drag.is_none());
        assert_eq!(
            (d.solver.method, d.solver.step, d.solver.rtol),
            ("rk4", Some(1e-4), None)
        );
        assert!(d.invariants.contains(&"energy_plus_work".to_owned()));
        assert!(!d.invariants.contains(&"energy".to_owned()));
    }
}
