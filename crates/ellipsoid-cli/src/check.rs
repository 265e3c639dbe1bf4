//! `ellipsoid check`: validate a scenario and print what follows from it, without
//! simulating.
//!
//! The initial normal force, the initial contact regime and the list of tracked
//! invariants come from `simulate` itself, stopped at its first sample, so that they are
//! exactly what a run would use (and every check a run makes at t = 0 is made here).

use std::fmt::Write as _;
use std::ops::ControlFlow;
use std::process::ExitCode;

use ellipsoid_core::geometry::Contact;
use ellipsoid_core::integrate::Method;
use ellipsoid_core::scenario::{self, Scenario};
use ellipsoid_core::simulate::{self, ContactModel, Outcome, Sample};
use nalgebra::{Matrix3, Vector3};

use crate::cli::CheckArgs;
use crate::error::CliError;

/// Width of the label column of the printout.
const LABEL_WIDTH: usize = 22;

pub fn check(args: &CheckArgs) -> Result<ExitCode, CliError> {
    let scenario = scenario::load(&args.scenario, &args.set)?;
    let (first, outcome) = first_sample(&scenario)?;
    print!("{}", describe(&scenario, first.as_ref(), &outcome));
    Ok(ExitCode::SUCCESS)
}

/// Runs the scene up to its first sample at t = 0.
fn first_sample(scenario: &Scenario) -> Result<(Option<Sample>, Outcome), CliError> {
    let mut scene = scenario.scene.clone();
    scene.sample_times = vec![0.0];
    let mut first = None;
    let outcome = simulate::simulate(&scene, &mut |s| {
        first.get_or_insert(*s);
        ControlFlow::Break(())
    })
    .map_err(|e| scenario.locate(&e))?;
    Ok((first, outcome))
}

fn describe(scenario: &Scenario, first: Option<&Sample>, outcome: &Outcome) -> String {
    let scene = &scenario.scene;
    let body = &scene.body;
    let (ax, i, g) = (body.semi_axes(), body.inertia(), body.com_offset());
    let mut o = String::new();
    // Labels are padded to a column of LABEL_WIDTH; a longer one still gets a space.
    let mut line = |label: &str, text: String| {
        let _ = writeln!(o, "{label:<width$} {text}", width = LABEL_WIDTH - 1);
    };
    line(
        "scenario",
        format!(
            "{}{}",
            scenario.source,
            if scenario.overrides.is_empty() {
                String::new()
            } else {
                format!(" (--set {})", scenario.overrides.join(", --set "))
            }
        ),
    );
    line(
        "semi-axes a, b, c",
        format!("{} m ({})", vec3(&ax), shape(&ax)),
    );
    line("mass", format!("{} kg", body.mass()));
    line("inertia about G", format!("{} kg m^2 (body axes)", mat3(i)));
    let moments = i.symmetric_eigenvalues();
    let mut sorted: Vec<f64> = moments.iter().copied().collect();
    sorted.sort_by(f64::total_cmp);
    line(
        "principal moments",
        format!("[{:e}, {:e}, {:e}] kg m^2", sorted[0], sorted[1], sorted[2]),
    );
    let radial = g.component_div(&ax).norm();
    line(
        "CM offset G - C0",
        format!(
            "{} m (body axes; g^T A^-2 g = {:.4}, < 1 inside the body)",
            vec3(&g),
            radial * radial
        ),
    );
    line("gravity", format!("{} m/s^2", scene.gravity));
    line(
        "contact model",
        match scene.contact {
            ContactModel::Frictionless => "frictionless".to_owned(),
            ContactModel::Sliding { friction } => {
                format!("sliding (Coulomb, mu = {friction}; stops when the slip does)")
            }
            ContactModel::Rolling => "rolling without slipping".to_owned(),
            ContactModel::Coulomb { friction } => {
                format!("coulomb (sliding and rolling with transitions, mu = {friction})")
            }
        },
    );
    let e = &scene.effects;
    let mut effects = Vec::new();
    if let Some(r) = e.rolling_resistance {
        effects.push(format!(
            "rolling resistance c_r = {} m (eps = {} rad/s)",
            r.coefficient, r.regularisation
        ));
    }
    if let Some(s) = e.spin_friction {
        effects.push(format!(
            "spin friction c_s = {} m (eps = {} rad/s)",
            s.coefficient, s.regularisation
        ));
    }
    if let Some(d) = e.air_drag {
        effects.push(format!(
            "air drag k = {} kg/s, k_w = {} kg m^2/s",
            d.linear, d.angular
        ));
    }
    line(
        "effects",
        if effects.is_empty() {
            "none".to_owned()
        } else {
            effects.join("; ")
        },
    );

    let init = &scene.initial;
    let a = &init.angles;
    line(
        "initial angles",
        format!(
            "theta = {} rad ({:.4} deg), phi = {} rad, psi = {} rad",
            a.theta,
            a.theta.to_degrees(),
            a.phi,
            a.psi
        ),
    );
    let omega = init.omega_body.unwrap_or_else(|| a.omega_body());
    match init.omega_body {
        Some(_) => line(
            "initial omega (body)",
            format!("{} rad/s (given)", vec3(&omega)),
        ),
        None => {
            line(
                "initial rates",
                format!(
                    "theta_dot = {}, phi_dot = {}, psi_dot = {} rad/s",
                    a.theta_dot, a.phi_dot, a.psi_dot
                ),
            );
            line("initial omega (body)", format!("{} rad/s", vec3(&omega)));
        }
    }
    let rot = a.rotation().to_rotation_matrix().into_inner();
    let zeta = Vector3::new(rot[(2, 0)], rot[(2, 1)], rot[(2, 2)]);
    let contact = Contact::new(body, zeta, omega);
    line(
        "contact point C",
        format!("{} m from C0 (body axes)", vec3(&contact.p_c)),
    );
    let world_c = Vector3::new(init.position.x, init.position.y, contact.height) + rot * contact.r;
    line(
        "",
        format!("{} m (world; z = 0 on the plane)", vec3(&world_c)),
    );
    line("height of G", format!("{} m", contact.height));
    match first {
        Some(s) => {
            line("initial mode", s.mode.name().to_owned());
            line(
                "initial N",
                format!(
                    "{} N (m g = {} N)",
                    s.normal_force,
                    body.mass() * scene.gravity
                ),
            );
            line("initial energy", format!("{} J", s.energy));
            line("initial slip speed", format!("{} m/s", s.slip_speed));
        }
        None => line(
            "initial N",
            "not available (the run produced no sample at t = 0)".to_owned(),
        ),
    }
    let d = serde_json::to_value(outcome.drift)
        .ok()
        .and_then(|v| v.as_object().cloned())
        .unwrap_or_default();
    let tracked: Vec<&str> = d
        .iter()
        .filter(|(_, v)| !v.is_null())
        .map(|(k, _)| k.as_str())
        .collect();
    line("invariants checked", tracked.join(", "));
    let s = &scene.solver;
    let method = match s.method {
        Method::Rk4 { h } => format!("rk4, fixed step {h} s"),
        m => format!(
            "{}, rtol = {:e}, atol = {:e}{}",
            m.name(),
            s.rtol,
            s.atol,
            s.initial_step
                .map_or(String::new(), |h| format!(", initial step {h} s"))
        ),
    };
    line("solver", method);
    line(
        "output",
        format!(
            "t_end = {} s, {} samples",
            scene.t_end,
            scene.sample_times.len()
        ),
    );
    if let Some(status) = &scenario.check.status {
        line("[check] status", status.clone());
    }
    for (name, tol) in &scenario.check.drift {
        line(
            &format!("[check] {name}"),
            format!("relative drift <= {tol:e}"),
        );
    }
    o
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

fn vec3(v: &Vector3<f64>) -> String {
    format!("[{}, {}, {}]", v.x, v.y, v.z)
}

fn mat3(m: &Matrix3<f64>) -> String {
    let row = |i: usize| format!("[{:e}, {:e}, {:e}]", m[(i, 0)], m[(i, 1)], m[(i, 2)]);
    format!("[{}, {}, {}]", row(0), row(1), row(2))
}
