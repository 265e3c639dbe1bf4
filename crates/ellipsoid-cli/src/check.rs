//! `ellipsoid check`: validate a scenario and print what follows from it, without
//! simulating. The data come from `ellipsoid_study::check::derive`, which Python's
//! `ellipsoid.check` returns as a dict; this module only lays them out.

use std::fmt::Write as _;
use std::process::ExitCode;

use ellipsoid_study::check::{self, Derived};

use crate::cli::CheckArgs;
use crate::error::CliError;

/// Width of the label column of the printout.
const LABEL_WIDTH: usize = 22;

pub fn check(args: &CheckArgs) -> Result<ExitCode, CliError> {
    let scenario = crate::plausible::load(&args.scenario, &args.set, args.quiet_plausibility)?;
    let derived = check::derive(&scenario).map_err(|e| CliError::from(*e))?;
    print!("{}", describe(&derived));
    Ok(ExitCode::SUCCESS)
}

fn describe(d: &Derived) -> String {
    let body = &d.body;
    let mut o = String::new();
    // Labels are padded to a column of LABEL_WIDTH; a longer one still gets a space.
    // Numbers printed short (a subnormal semi-axis is not spelt out in 330 digits).
    let mut line = |label: &str, text: String| {
        let text = ellipsoid_core::error::shorten_numbers(&text);
        let _ = writeln!(o, "{label:<width$} {text}", width = LABEL_WIDTH - 1);
    };
    line(
        "scenario",
        format!(
            "{}{}",
            d.scenario,
            if d.overrides.is_empty() {
                String::new()
            } else {
                format!(" (--set {})", d.overrides.join(", --set "))
            }
        ),
    );
    line(
        "semi-axes a, b, c",
        format!("{} m ({})", vec3(&body.semi_axes), body.shape),
    );
    line("mass", format!("{} kg", body.mass));
    line(
        "inertia about G",
        format!("{} kg m^2 (body axes)", mat3(&body.inertia)),
    );
    let m = &body.principal_moments;
    line(
        "principal moments",
        format!("[{:e}, {:e}, {:e}] kg m^2", m[0], m[1], m[2]),
    );
    line(
        "CM offset G - C0",
        format!(
            "{} m (body axes; g^T A^-2 g = {:.4}, < 1 inside the body)",
            vec3(&body.com_offset),
            body.com_offset_radial
        ),
    );
    for sp in &body.spheres {
        line(
            "contact sphere",
            format!(
                "{}: radius {} m, centre {} m (body axes, from C0)",
                sp.name,
                sp.radius,
                vec3(&sp.center)
            ),
        );
    }
    for rim in &body.rims {
        line(
            "rim",
            format!(
                "{}: radius {} m, edge {} m, centre {} m (body axes, from C0)",
                rim.name,
                rim.radius,
                rim.edge,
                vec3(&rim.center)
            ),
        );
    }
    if !body.ellipsoid_contact {
        line(
            "ellipsoid",
            "does not touch (ellipsoid_contact = false)".to_owned(),
        );
    }
    match &body.two_contact_tilts {
        Some(tilts) => {
            for t in tilts {
                line(
                    "two contacts",
                    format!(
                        "{} and {} at theta* = {} rad ({:.2} deg)",
                        t.surfaces[0], t.surfaces[1], t.theta, t.theta_deg
                    ),
                );
            }
        }
        None => line(
            "two contacts",
            "theta* not given: the body is not of revolution about its c axis, so it depends on the heading psi".to_owned(),
        ),
    }
    line("gravity", format!("{} m/s^2", d.gravity));
    line(
        "contact model",
        match (d.contact.model, d.contact.friction) {
            ("sliding", Some(mu)) => {
                format!("sliding (Coulomb, mu = {mu}; stops when the slip does)")
            }
            ("rolling", _) => "rolling without slipping".to_owned(),
            ("viscous", _) => match d.contact.viscous_friction {
                Some(mu_v) => format!("viscous (F_t = -mu_v N v_C, mu_v = {mu_v} s/m)"),
                None => "viscous".to_owned(),
            },
            ("coulomb", Some(mu)) => {
                format!("coulomb (sliding and rolling with transitions, mu = {mu})")
            }
            (model, _) => model.to_owned(),
        },
    );
    if let Some(disc) = d.contact.disc {
        line(
            "contact disc",
            format!(
                "R = {} m, law {} (Coulomb–Contensou friction and drilling torque)",
                disc.radius, disc.law
            ),
        );
    }
    let effects = d.effects.report();
    line(
        "effects",
        if effects.is_empty() {
            "none".to_owned()
        } else {
            effects.join("; ")
        },
    );

    let init = &d.initial;
    line(
        "initial angles",
        format!(
            "theta = {} rad ({:.4} deg), phi = {} rad, psi = {} rad",
            init.theta, init.theta_deg, init.phi, init.psi
        ),
    );
    match init.rates {
        None => line(
            "initial omega (body)",
            format!("{} rad/s (given)", vec3(&init.omega_body)),
        ),
        Some(r) => {
            line(
                "initial rates",
                format!(
                    "theta_dot = {}, phi_dot = {}, psi_dot = {} rad/s",
                    r.theta_dot, r.phi_dot, r.psi_dot
                ),
            );
            line(
                "initial omega (body)",
                format!("{} rad/s", vec3(&init.omega_body)),
            );
        }
    }
    line(
        "contact point C",
        format!("{} m from C0 (body axes)", vec3(&init.contact_point)),
    );
    line(
        "",
        format!(
            "{} m (world; z = 0 on the plane)",
            vec3(&init.contact_point_world)
        ),
    );
    line("height of G", format!("{} m", init.height));
    match (
        init.mode,
        init.normal_force,
        init.energy,
        init.slip_speed,
        init.velocity,
    ) {
        (Some(mode), Some(n), Some(energy), Some(slip), Some(v)) => {
            line("initial mode", mode.to_owned());
            line("initial N", format!("{n} N (m g = {} N)", body.weight));
            line("initial energy", format!("{energy} J"));
            line(
                "initial v_G",
                format!(
                    "{} m/s (world; {})",
                    vec3(&v),
                    if init.velocity_given {
                        "given"
                    } else {
                        "velocity not given"
                    }
                ),
            );
            line("initial slip speed", format!("{slip} m/s"));
        }
        _ => line(
            "initial N",
            "not available (the run produced no sample at t = 0)".to_owned(),
        ),
    }
    line("invariants checked", d.invariants.join(", "));
    let s = &d.solver;
    let method = match (s.step, s.rtol, s.atol) {
        (Some(h), _, _) => format!("{}, fixed step {h} s", s.method),
        (None, Some(rtol), Some(atol)) => format!(
            "{}, rtol = {rtol:e}, atol = {atol:e}{}",
            s.method,
            s.initial_step
                .map_or(String::new(), |h| format!(", initial step {h} s"))
        ),
        _ => s.method.to_owned(),
    };
    line("solver", method);
    line(
        "output",
        format!("t_end = {} s, {} samples", d.output.t_end, d.output.samples),
    );
    if let Some(status) = &d.check.status {
        line("[check] status", status.clone());
    }
    for (name, tol) in &d.check.drift {
        line(
            &format!("[check] {name}"),
            format!("relative drift <= {tol:e}"),
        );
    }
    o
}

fn vec3(v: &[f64; 3]) -> String {
    format!("[{}, {}, {}]", v[0], v[1], v[2])
}

fn mat3(m: &[[f64; 3]; 3]) -> String {
    let row = |r: &[f64; 3]| format!("[{:e}, {:e}, {:e}]", r[0], r[1], r[2]);
    format!("[{}, {}, {}]", row(&m[0]), row(&m[1]), row(&m[2]))
}
