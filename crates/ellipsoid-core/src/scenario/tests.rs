//! Unit tests of the scenario parser.

use super::*;
use crate::effects::{AirDrag, RollingResistance, SpinFriction};

const PAPER: &str = r#"# the brief's example
[body]
a = 0.025
c = 0.0175
mass = 0.05
com_offset = 0.003
inertia = [3.8e-6, 3.8e-6, 6.25e-6]

[initial]
theta = 0.1745
psi_dot = 60.0

[contact]
model = "frictionless"

[solver]
method = "dopri5"
rtol = 1e-10
atol = 1e-12

[output]
t_end = 10.0
dt = 1e-3
"#;

fn ok(text: &str, sets: &[&str]) -> Scenario {
    parse(text, "x.toml", sets).unwrap_or_else(|e| panic!("{e}"))
}

fn err(text: &str, sets: &[&str]) -> String {
    parse(text, "x.toml", sets)
        .expect_err("should be rejected")
        .to_string()
}

/// `PAPER` with `old` replaced by `new` (which must occur).
fn edit(old: &str, new: &str) -> String {
    assert!(PAPER.contains(old), "{old}");
    PAPER.replacen(old, new, 1)
}

#[test]
fn reads_the_example_scene() {
    let s = ok(PAPER, &[]);
    let scene = &s.scene;
    assert_eq!(scene.body.semi_axes(), Vector3::new(0.025, 0.025, 0.0175));
    assert_eq!(scene.body.com_offset(), Vector3::new(0.0, 0.0, -0.003));
    assert_eq!(scene.body.inertia()[(2, 2)], 6.25e-6);
    assert_eq!(scene.gravity, DEFAULT_GRAVITY);
    assert_eq!(scene.contact, ContactModel::Frictionless);
    assert_eq!(scene.initial.angles.theta, 0.1745);
    assert_eq!(scene.initial.angles.psi_dot, 60.0);
    assert_eq!(scene.initial.velocity, None);
    assert_eq!(scene.solver.method, Method::Dopri5);
    assert_eq!(scene.sample_times.len(), 10_001);
    assert_eq!(scene.sample_times[1], 1e-3);
    assert_eq!(*scene.sample_times.last().unwrap(), 10.0);
    assert_eq!(s.stem(), "x");
    assert_eq!(s.check, Check::default());
}

#[test]
fn sampling_grid_ends_at_t_end() {
    assert_eq!(grid(0.3, 0.1).unwrap(), vec![0.0, 0.1, 0.2, 0.3]);
    assert_eq!(
        grid(1.0, 0.3).unwrap(),
        vec![0.0, 0.3, 0.6, 0.8999999999999999, 1.0]
    );
    assert_eq!(grid(0.5, 2.0).unwrap(), vec![0.0, 0.5]);
    assert!(grid(1.0, 1e-9).is_err());
}

/// A change of one of two exclusive keys replaces the other (issue 47): the degree twin,
/// the general form, the sampling; a file holding both is still refused.
#[test]
fn a_change_replaces_the_keys_twin() {
    let deg = edit("theta = 0.1745", "theta_deg = 10");
    assert_eq!(
        ok(&deg, &["initial.theta=0.2"]).scene.initial.angles.theta,
        0.2
    );
    assert_eq!(
        ok(PAPER, &["initial.theta_deg=5"])
            .scene
            .initial
            .angles
            .theta,
        5f64.to_radians()
    );
    let vector = ok(PAPER, &["body.com_offset_vector=[0.0, 0.0, -0.002]"]);
    let scalar = ok(PAPER, &["body.com_offset=0.002"]);
    assert_eq!(vector.scene, scalar.scene);
    let times = ok(PAPER, &["output.times=[0.0, 0.5, 1.0]"]);
    assert_eq!(times.scene.sample_times, [0.0, 0.5, 1.0]);
    assert_eq!(
        ok(PAPER, &["output.dt=0.5", "output.t_end=1.0"])
            .scene
            .sample_times,
        [0.0, 0.5, 1.0]
    );
    // Only the twin goes: the rest of the table stays.
    assert_eq!(
        ok(&deg, &["initial.theta=0.2"])
            .scene
            .initial
            .angles
            .psi_dot,
        60.0
    );
}

#[test]
fn degree_twins_convert_and_exclude_each_other() {
    let s = ok(
        &edit("theta = 0.1745", "theta_deg = 10\nphi_dot_deg = 180"),
        &[],
    );
    assert_eq!(s.scene.initial.angles.theta, 10f64.to_radians());
    assert_eq!(s.scene.initial.angles.phi_dot, std::f64::consts::PI);
    let msg = err(
        &edit("theta = 0.1745", "theta = 0.1745\ntheta_deg = 10"),
        &[],
    );
    assert_eq!(
        msg,
        "x.toml:11:1: initial.theta_deg = 10: give either initial.theta or initial.theta_deg, not both (radians or degrees)"
    );
}

#[test]
fn errors_name_file_line_column_key_value_and_rule() {
    let cases = [
        (
            edit("mass = 0.05", "mass = -0.05"),
            "x.toml:5:1: body.mass = -0.05: the mass must be positive and finite (kg)",
        ),
        (
            edit("mass = 0.05", "mass = \"heavy\""),
            "x.toml:5:1: body.mass = \"heavy\": expected a number: the mass (kg), found a string",
        ),
        (
            edit("mass = 0.05\n", ""),
            "x.toml:2:1: body.mass is missing: give the mass (kg)",
        ),
        (
            edit("mass = 0.05", "mas = 0.05"),
            "x.toml:5:1: body.mas = 0.05: unknown key in [body]; did you mean `mass`?",
        ),
        (
            edit("[solver]", "[solvr]"),
            "x.toml:16:2: solvr: unknown table at the top level; did you mean `solver`?",
        ),
        (
            edit("\"frictionless\"", "\"frictionles\""),
            "x.toml:14:1: contact.model = \"frictionles\": expected one of \"frictionless\", \"sliding\", \"rolling\", \"coulomb\", \"viscous\"; did you mean \"frictionless\"?",
        ),
        (
            edit("\"frictionless\"", "\"sliding\""),
            "x.toml:13:1: contact.friction is missing: the sliding model needs μ, the Coulomb friction coefficient (e.g. friction = 0.3)",
        ),
        (
            edit("t_end = 10.0", "t_end = 0"),
            "x.toml:22:1: output.t_end = 0: the end time must be positive and finite (s)",
        ),
        (
            edit("com_offset = 0.003", "com_offset = 0.02"),
            "x.toml:6:1: body.com_offset = [0, 0, -0.02]: the centre of mass must lie inside the ellipsoid (g^T A^-2 g = 1.306122 must be < 1)",
        ),
        (
            edit("3.8e-6, 3.8e-6", "1e-6, 1e-6"),
            "x.toml:7:1: body.inertia = [1e-6, 1e-6, 6.25e-6]: principal moments must satisfy the triangle inequality (each at most the sum of the other two)",
        ),
        (
            edit(
                "inertia = [3.8e-6, 3.8e-6, 6.25e-6]",
                "inertia = \"uniform\"",
            ),
            "x.toml:7:1: body.inertia = \"uniform\": \"uniform\" is a homogeneous body, whose centre of mass is the geometric centre; with a centre-of-mass offset give the moments about G",
        ),
        (
            edit("method = \"dopri5\"", "method = \"rk4\""),
            "x.toml:16:1: solver.step is missing: the rk4 method needs its fixed step (s), e.g. step = 1e-4",
        ),
        (
            edit("psi_dot = 60.0", "psi_dot = 60.0\nvelocity = [1, 0]"),
            "x.toml:12:1: initial.velocity = [1, 0]: not allowed for the rolling model on the plane, where the velocity of G is implied by ω (v_G = −ω × r); remove it (or start in flight, initial.height > 0)",
        ),
        (
            edit("dt = 1e-3", "dt = 1e-3\ntimes = [1.0]"),
            "x.toml:24:1: output.times = [1.0]: give either output.dt or output.times, not both (a sampling interval or explicit output times)",
        ),
        (
            edit("t_end = 10.0", "t_end = 10.0.0"),
            "x.toml:22:13: TOML syntax error: invalid float, expected nothing",
        ),
    ];
    let mut failures = Vec::new();
    for (i, (text, expected)) in cases.iter().enumerate() {
        let text = if expected.contains("rolling model") {
            text.replace("\"frictionless\"", "\"rolling\"")
        } else {
            text.clone()
        };
        let got = err(&text, &[]);
        if &got != expected {
            failures.push(format!(
                "case {i}:\n  got      {got}\n  expected {expected}"
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn overrides_apply_before_validation() {
    let s = ok(
        PAPER,
        &[
            "output.t_end=0.5",
            "contact.model=rolling",
            "effects.gravity = 1.62",
            "initial.position=[1, 2]",
        ],
    );
    assert_eq!(s.scene.t_end, 0.5);
    assert_eq!(*s.scene.sample_times.last().unwrap(), 0.5);
    assert_eq!(s.scene.contact, ContactModel::Rolling);
    assert_eq!(s.scene.gravity, 1.62);
    assert_eq!(s.scene.initial.position, Vector2::new(1.0, 2.0));
    assert_eq!(s.text, PAPER);
    assert_eq!(
        err(PAPER, &["body.mass=-1"]),
        "x.toml: --set body.mass=-1: body.mass = -1: the mass must be positive and finite (kg)"
    );
    assert_eq!(
        err(PAPER, &["body.mas=1"]),
        "x.toml: --set body.mas=1: body.mas = 1: unknown key in [body]; did you mean `mass`?"
    );
    assert_eq!(
        err(PAPER, &["body.mass"]),
        "x.toml: --set body.mass: an override must have the form key=value, e.g. --set output.t_end=1.0"
    );
    assert_eq!(
        err(PAPER, &["body.mass.x=1"]),
        "x.toml: --set body.mass.x=1: body.mass: is not a table, so body.mass.x cannot be set"
    );
    assert!(
        err(PAPER, &["body.mass=[1,"])
            .starts_with("x.toml: --set body.mass=[1,: body.mass = [1,: not a TOML value")
    );
}

/// `--set` takes the key paths of studies and Python: `[i]` picks an element of an array
/// (of numbers or of tables); the change, and a bad value, are placed at the override.
#[test]
fn overrides_name_elements_of_arrays_by_index() {
    let s = ok(
        PAPER,
        &[
            "body.inertia[2]=7e-6",
            "initial.position=[1, 2]",
            "initial.position[1]=5",
        ],
    );
    assert_eq!(s.scene.body.inertia()[(2, 2)], 7e-6);
    assert_eq!(s.scene.body.inertia()[(0, 0)], 3.8e-6);
    assert_eq!(s.scene.initial.position, Vector2::new(1.0, 5.0));
    let observed =
        format!("{PAPER}\n[[observe]]\nname = \"up\"\ncolumn = \"theta\"\ncrosses = 0.5\n");
    let s = ok(
        &observed,
        &["observe[0].crosses=0.25", "observe[0].direction=down"],
    );
    assert_eq!(s.scene.observe[0].crosses, 0.25);
    assert_eq!(s.scene.observe[0].direction, Direction::Falling);
    assert_eq!(
        err(PAPER, &["body.inertia[1]=-1"]),
        "x.toml: --set body.inertia[1]=-1: body.inertia = [3.8e-6, -1, 6.25e-6]: principal moments of inertia must be positive"
    );
    assert_eq!(
        err(PAPER, &["body.inertia[3]=1"]),
        "x.toml: --set body.inertia[3]=1: body.inertia: has 3 element(s), no index 3, so body.inertia[3] cannot be set"
    );
    assert_eq!(
        err(PAPER, &["body.mass[0]=1"]),
        "x.toml: --set body.mass[0]=1: body.mass: is not an array, so body.mass[0] cannot be set"
    );
    assert_eq!(
        err(PAPER, &["observe[0].crosses=1"]),
        "x.toml: --set observe[0].crosses=1: observe: has 0 element(s), no index 0, so observe[0].crosses cannot be set"
    );
    assert_eq!(
        err(PAPER, &["body.inertia[x]=1"]),
        format!("x.toml: --set body.inertia[x]=1: body.inertia[x]: {KEY_RULE}")
    );
}

#[test]
fn inertia_forms() {
    let full = ok(
        &edit(
            "[3.8e-6, 3.8e-6, 6.25e-6]",
            "[[3.8e-6, 1e-7, 0], [1e-7, 3.8e-6, 0], [0, 0, 6.25e-6]]",
        ),
        &[],
    );
    assert_eq!(full.scene.body.inertia()[(0, 1)], 1e-7);
    let uniform = ok(
        &edit(
            "com_offset = 0.003\ninertia = [3.8e-6, 3.8e-6, 6.25e-6]",
            "inertia = \"uniform\"",
        ),
        &[],
    );
    assert_eq!(
        *uniform.scene.body.inertia(),
        uniform_inertia(Vector3::new(0.025, 0.025, 0.0175), 0.05)
    );
    let vector = ok(
        &edit(
            "com_offset = 0.003",
            "com_offset_vector = [0.001, 0, -0.003]",
        ),
        &[],
    );
    assert_eq!(
        vector.scene.body.com_offset(),
        Vector3::new(0.001, 0.0, -0.003)
    );
}

#[test]
fn rotation_composes_left_to_right() {
    let s = ok(
        &edit(
            "theta = 0.1745",
            "rotation = [{ axis = \"x\", angle_deg = 0.5 }, { axis = \"y\", angle = 0.01 }]",
        ),
        &[],
    );
    let expected = UnitQuaternion::from_axis_angle(&Vector3::x_axis(), 0.5f64.to_radians())
        * UnitQuaternion::from_axis_angle(&Vector3::y_axis(), 0.01);
    assert!(s.scene.initial.angles.rotation().angle_to(&expected) < 1e-14);
    let msg = err(&edit("theta = 0.1745", "theta = 0.1\nrotation = []"), &[]);
    assert!(
        msg.starts_with(
            "x.toml:11:1: initial.rotation = []: give either initial.rotation or the Euler angles"
        ),
        "{msg}"
    );
    let msg = err(
        &edit("theta = 0.1745", "rotation = [{ axis = \"w\", angle = 1 }]"),
        &[],
    );
    assert!(
        msg.starts_with(
            "x.toml:10:15: initial.rotation[0].axis = \"w\": expected one of \"x\", \"y\", \"z\""
        ),
        "{msg}"
    );
}

#[test]
fn effects_and_check_tables() {
    let s = ok(
        &format!(
            "{PAPER}\n[effects]\ngravity = 9.8\nrolling_resistance = 1e-4\nspin_friction = {{ coefficient = 2e-4, regularisation = 1e-2 }}\nair_drag = {{ linear = 0.1 }}\n[check]\nstatus = \"completed\"\nenergy = 1e-9\n"
        ),
        &[],
    );
    let e = s.scene.effects;
    assert_eq!(s.scene.gravity, 9.8);
    assert_eq!(
        e.rolling_resistance,
        Some(RollingResistance {
            coefficient: 1e-4,
            regularisation: DEFAULT_REGULARISATION
        })
    );
    assert_eq!(
        e.spin_friction,
        Some(SpinFriction {
            coefficient: 2e-4,
            regularisation: 1e-2
        })
    );
    assert_eq!(
        e.air_drag,
        Some(AirDrag {
            linear: 0.1,
            angular: 0.0
        })
    );
    assert_eq!(s.check.status.as_deref(), Some("completed"));
    assert_eq!(s.check.drift.get("energy"), Some(&1e-9));
    let msg = err(
        &format!("{PAPER}\n[effects]\nspin_friction = {{ coefficent = 1 }}\n"),
        &[],
    );
    assert_eq!(
        msg,
        "x.toml:26:19: effects.spin_friction.coefficent = 1: unknown key in [effects.spin_friction]; did you mean `coefficient`?"
    );
}

#[test]
fn physics_errors_found_later_are_located() {
    let s = ok(PAPER, &[]);
    let e = s.locate(&ModelError::derived(
        "initial",
        "initial state",
        crate::error::Value::Named {
            name: "N",
            value: -1.0,
            unit: "N",
        },
        "the plane must push",
    ));
    assert_eq!(
        e.to_string(),
        "x.toml:9:2: initial state = N = -1 N: the plane must push"
    );
    let e = s.locate(&ModelError::invalid("contact.friction", 0.3, "r"));
    assert_eq!(e.location.line, Some(13), "falls back to the table");
}

#[test]
fn unreadable_file_is_an_io_error() {
    let e = load(Path::new("/nonexistent/x.toml"), &[] as &[&str]).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Io);
    assert!(
        e.to_string()
            .starts_with("/nonexistent/x.toml: cannot read the scenario file: "),
        "{e}"
    );
}

#[test]
fn suggestions_need_a_small_edit_distance() {
    assert_eq!(levenshtein("kitten", "sitting"), 3);
    assert_eq!(suggest("gravty", &keys("effects")), Some("gravity"));
    assert_eq!(suggest("zzz", &keys("effects")), None);
}

#[test]
fn overflowing_initial_state_is_rejected_by_name() {
    let cases = [
        ("body.mass=1e308", "the normal force N = NaN N"),
        ("initial.velocity=[1e200, 0]", "the energy E = inf J"),
        // (body.a = 1e300 overflowed here; it is now refused by the parser, its square not
        // being a float: semi_axes_whose_squares_are_not_normal_floats_are_refused)
        ("initial.psi_dot=1e200", "the normal force N = NaN N"),
    ];
    for (set, what) in cases {
        let s = ok(PAPER, &[set]);
        let e = s.scene.initial_state().expect_err(set).to_string();
        assert!(
            e.starts_with(&format!("initial state = {what}: ")) && e.contains("must be finite"),
            "{set}: {e}"
        );
        let located = s.locate(&s.scene.initial_state().unwrap_err()).to_string();
        assert!(
            located.starts_with("x.toml:9:2: initial state = ")
                && located.ends_with(&format!("(in the scenario as changed by --set {set})")),
            "{located}"
        );
    }
    assert!(ok(PAPER, &[]).scene.initial_state().is_ok());
}

#[test]
fn solver_settings_are_bounded() {
    let e = err(PAPER, &["solver.rtol=0.5"]);
    assert!(e.contains("solver.rtol = 0.5") && e.contains("1e-2"), "{e}");
    assert!(ok(PAPER, &["solver.rtol=1e-2"]).scene.solver.rtol == 1e-2);
    let e = err(PAPER, &["solver.method=\"rk4\"", "solver.step=20.0"]);
    assert!(
        e.contains("solver.step = 20") && e.contains("must not exceed output.t_end = 10 s"),
        "{e}"
    );
    let e = err(PAPER, &["solver.method=\"rk4\"", "solver.step=1e-300"]);
    assert!(
        e.contains("solver.step = 1e-300") && e.contains("more than solver.max_steps = 10000000"),
        "{e}"
    );
    // exactly max_steps steps is allowed
    assert!(
        ok(
            PAPER,
            &[
                "solver.method=\"rk4\"",
                "solver.step=1e-3",
                "solver.max_steps=10000"
            ]
        )
        .scene
        .solver
        .max_steps
            == 10_000
    );
    // 0.07/0.01 = 7.000000000000001: the last step's stretch absorbs it (7 steps)
    assert!(
        ok(
            PAPER,
            &[
                "output.t_end=0.07",
                "solver.method=\"rk4\"",
                "solver.step=0.01",
                "solver.max_steps=7"
            ]
        )
        .scene
        .t_end
            == 0.07
    );
    let e = err(
        PAPER,
        &[
            "solver.method=\"rk4\"",
            "solver.step=1e-3",
            "solver.max_steps=9999",
        ],
    );
    assert!(e.contains("rk4 would take 10000 steps"), "{e}");
    let e = err(PAPER, &["solver.max_steps=99999999999999999999"]);
    assert!(
        e.contains("solver.max_steps = 99999999999999999999: integer out of TOML's range"),
        "{e}"
    );
    let e = err(PAPER, &["solver.max_steps=1e20"]);
    assert!(
        e.contains("solver.max_steps = 1e20: must be a whole number, at least 1 and below 2^64"),
        "{e}"
    );
}

#[test]
fn output_times_messages_are_exact() {
    let e = err(&edit("dt = 1e-3", "dt = 1e-6"), &[]);
    assert!(
        e.contains("asks for 10000001 samples; at most 10000000"),
        "{e}"
    );
    let e = err(&edit("dt = 1e-3", "times = [0.5, 0.5]"), &[]);
    assert!(
        e.contains("0.5 after 0.5") && e.contains("strictly increasing"),
        "{e}"
    );
    let e = err(&edit("dt = 1e-3", "times = [\"a\"]"), &[]);
    assert!(e.contains("every output time must be a number (s)"), "{e}");
    let e = err(&edit("dt = 1e-3", "dt = 1e-3\ntimes = [0.1]"), &[]).to_string();
    assert!(e.contains("not both"), "{e}");
    let e = err(PAPER, &["output.t_end=-1e-300"]);
    assert!(e.contains("output.t_end = -1e-300"), "{e}");
}

fn all(text: &str, sets: &[&str]) -> Vec<String> {
    parse_all(text, "x.toml", sets)
        .expect_err("should be rejected")
        .0
        .iter()
        .map(ToString::to_string)
        .collect()
}

/// A body that fails is not followed by an error about an observable of one of its
/// surfaces' columns (issue 47): that column is unknown only because the body failed.
#[test]
fn an_observable_of_a_failed_body_surface_is_no_second_error() {
    let stem = "[[body.sphere]]\nname = \"stem\"\ncenter = [0.0, 0.0, 0.013]\nradius = 0.005\n";
    let observe = "[[observe]]\nname = \"n\"\ncolumn = \"normal_force_stem\"\ncrosses = 0.1\n";
    ok(&format!("{PAPER}\n{stem}\n{observe}"), &[]);
    let broken = edit("mass = 0.05", "mass = -1.0");
    let got = all(&format!("{broken}\n{stem}\n{observe}"), &[]);
    assert_eq!(got.len(), 1, "{got:?}");
    assert!(got[0].contains("body.mass = -1: "), "{got:?}");
    // With the body read, an unknown column is still an error.
    let typo = observe.replace("normal_force_stem", "normal_force_stm");
    let got = all(&format!("{broken}\n{stem}\n{typo}"), &[]);
    assert_eq!(got.len(), 1, "{got:?}");
    let got = all(&format!("{PAPER}\n{stem}\n{typo}"), &[]);
    assert!(got[0].contains("observe[0].column"), "{got:?}");
}

#[test]
fn every_independent_error_is_reported_in_file_order() {
    // Two typos in different tables, the later table read first by the parser, and a bad
    // value in a third: all three, in file order.
    let text = edit("mass = 0.05", "mas = 0.05")
        .replace("psi_dot = 60.0", "psi_dott = 60.0")
        .replace("t_end = 10.0", "t_end = -1");
    let got = all(&text, &[]);
    assert_eq!(
        got,
        [
            "x.toml:5:1: body.mas = 0.05: unknown key in [body]; did you mean `mass`?",
            "x.toml:11:1: initial.psi_dott = 60.0: unknown key in [initial]; did you mean `psi_dot`?",
            "x.toml:22:1: output.t_end = -1: the end time must be positive and finite (s)",
        ]
    );
    assert_eq!(err(&text, &[]), got[0]);
    // `parse` gives the first in the file: [initial] (line 11) before [contact] (line 14),
    // though [contact] is read first (before, its error was the one reported).
    let text = edit("psi_dot = 60.0", "psi_dott = 60.0")
        .replace("model = \"frictionless\"", "modl = \"frictionless\"");
    assert!(
        err(&text, &[]).starts_with("x.toml:11:1: initial.psi_dott"),
        "{}",
        err(&text, &[])
    );
    assert_eq!(
        all(&text, &[]).len(),
        2,
        "psi_dott and modl ([contact] then misses model: a consequence)"
    );
    // Several unknown keys in one table, and a value error after them in the same table.
    let text = edit("c = 0.0175", "cc = 0.0175\nd = 1").replace("mass = 0.05", "mass = -1");
    let got = all(&text, &[]);
    // With the unknown keys gone, [body] misses `c`: most likely `cc`, so not reported
    // (and the reader stops there, before the mass).
    assert_eq!(got.len(), 2, "{got:#?}");
    assert!(
        got[0].starts_with("x.toml:4:1: body.cc = 0.0175: unknown key")
            && got[1].starts_with("x.toml:5:1: body.d = 1: unknown key"),
        "{got:#?}"
    );
}

#[test]
fn errors_are_capped() {
    let mut text = PAPER.to_owned();
    for i in 0..50 {
        text = text.replace("[contact]", &format!("typo{i} = 1\n[contact]"));
    }
    let got = all(&text, &[]);
    assert_eq!(got.len(), MAX_ERRORS);
    assert!(
        got[0].contains("initial.typo0 = 1: unknown key") && got[1].contains("initial.typo1"),
        "{got:#?}"
    );
}

#[test]
fn a_file_that_is_not_utf8_is_located_at_its_first_bad_byte() {
    let dir = std::env::temp_dir().join(format!("ellipsoid-utf8-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("latin1.toml");
    let mut bytes = PAPER.as_bytes().to_vec();
    // "# μ" in Latin-1 after `mass = 0.05 ` on line 5: é is 0xe9
    let at = PAPER.find("mass = 0.05").unwrap() + "mass = 0.05".len();
    bytes.splice(at..at, b" # caf\xe9".iter().copied());
    std::fs::write(&path, &bytes).unwrap();
    let e = load(&path, &[] as &[&str]).unwrap_err();
    std::fs::remove_dir_all(&dir).unwrap();
    assert_eq!(
        (e.kind, e.location.line, e.location.column),
        (ErrorKind::Syntax, Some(5), Some(18)),
        "{e}"
    );
    assert!(
        e.to_string()
            .contains(":5:18: the file is not UTF-8 text, as TOML must be: byte 0xe9 at offset"),
        "{e}"
    );
}

#[test]
fn integers_beyond_64_bits_are_rejected_as_toml_says() {
    let e = err(&edit("dt = 1e-3", "dt = 9223372036854775808"), &[]);
    assert_eq!(
        e,
        "x.toml:23:6: 9223372036854775808: integer out of TOML's range (-2^63 to 2^63 - 1, about ±9.2e18); write it as a float, e.g. 9.3e18"
    );
    assert!(
        err(&edit("dt = 1e-3", "dt = [1, -9223372036854775809]"), &[])
            .contains("-9223372036854775809: integer out of TOML's range")
    );
    let e = err(PAPER, &["output.dt=9223372036854775808"]);
    assert!(e.starts_with("x.toml: --set output.dt=9223372036854775808: output.dt = 9223372036854775808: integer out of TOML's range"), "{e}");
    // The largest integer is an integer (and a valid, if long, sampling interval).
    assert_eq!(
        ok(&edit("dt = 1e-3", "dt = 9223372036854775807"), &[])
            .scene
            .sample_times,
        [0.0, 10.0]
    );
}

#[test]
fn long_keys_are_cut_in_messages_and_not_compared_for_suggestions() {
    let key = "k".repeat(5_000_000);
    let e = err(&edit("mass = 0.05", &format!("{key} = 1")), &[]);
    assert!(e.len() < 300, "{} characters", e.len());
    assert!(
        e.starts_with("x.toml:5:1: body.kkkk")
            && e.contains("…")
            && e.contains("unknown key in [body]; expected one of: a, b"),
        "{e}"
    );
    let e = err(PAPER, &[&format!("body.{key}=1")]);
    assert!(e.len() < 300, "{} characters", e.len());
}

#[test]
fn numbers_in_messages_are_short() {
    // The physics layer's value (not the file's text): printed with `{}` it was 330 characters.
    let e = err(&edit("a = 0.025", "a = -5e-324"), &[]);
    assert_eq!(
        e,
        "x.toml:3:1: body.a = -5e-324: a semi-axis must be a positive, finite length in metres"
    );
}

/// A subnormal semi-axis (5e-324 m) used to be accepted and "complete"; semi-axes whose
/// squares leave the normal floats are refused, naming the range.
#[test]
fn semi_axes_whose_squares_are_not_normal_floats_are_refused() {
    for (bad, shown) in [
        ("5e-324", "5e-324"),
        ("1e-160", "1e-160"),
        ("1e155", "1e155"),
    ] {
        let e = err(&edit("a = 0.025", &format!("a = {bad}")), &[]);
        assert_eq!(
            e,
            format!(
                "x.toml:3:1: body.a = {shown}: a semi-axis must be from 1.5e-154 to 1.3e154 m, so that its square is a normal float"
            )
        );
    }
}

/// `[contact] contact_radius` and `contact_law` (issue #14): read into `Scene::disc`, and
/// every bad value named with its key, value and rule.
#[test]
fn contact_disc_keys_and_their_errors() {
    use crate::model::contensou::Law;
    let sliding = |extra: &str| {
        edit(
            "model = \"frictionless\"",
            &format!("model = \"coulomb\"\nfriction = 0.3\n{extra}"),
        )
    };
    let s = ok(&sliding("contact_radius = 5e-4"), &[]);
    let disc = s.scene.disc.expect("a disc");
    assert_eq!((disc.radius, disc.law), (5e-4, Law::Exact));
    let s = ok(
        &sliding("contact_radius = 1e-3\ncontact_law = \"pade\""),
        &[],
    );
    assert_eq!(s.scene.disc.unwrap().law, Law::Pade);
    let s = ok(
        &sliding(""),
        &["contact.contact_law=ellipse", "contact.contact_radius=2e-4"],
    );
    assert_eq!(s.scene.disc.unwrap().law, Law::Ellipse);
    // R = 0 is the point contact, with or without a law.
    assert_eq!(ok(&sliding("contact_radius = 0.0"), &[]).scene.disc, None);
    assert_eq!(ok(&sliding("contact_law = \"pade\""), &[]).scene.disc, None);
    assert_eq!(ok(PAPER, &[]).scene.disc, None);

    const NONNEG: &str =
        "the contact radius must be finite and non-negative (m); 0 is a point contact";
    let cases = [
        (
            sliding("contact_radius = -1e-3"),
            format!("x.toml:16:1: contact.contact_radius = -1e-3: {NONNEG}"),
        ),
        (
            sliding("contact_radius = nan"),
            format!("x.toml:16:1: contact.contact_radius = nan: {NONNEG}"),
        ),
        (
            sliding("contact_radius = inf"),
            format!("x.toml:16:1: contact.contact_radius = inf: {NONNEG}"),
        ),
        (
            sliding("contact_radius = \"small\""),
            "x.toml:16:1: contact.contact_radius = \"small\": expected a number: R, the radius of the contact disc (m), found a string".to_owned(),
        ),
        (
            sliding("contact_radius = 1e300"),
            "x.toml:16:1: contact.contact_radius = 1e300: the contact disc must be smaller than the body: R < min(a, b, c) = 0.0175 m".to_owned(),
        ),
        (
            sliding("contact_radius = 0.02"),
            "x.toml:16:1: contact.contact_radius = 0.02: the contact disc must be smaller than the body: R < min(a, b, c) = 0.0175 m".to_owned(),
        ),
        (
            sliding("contact_radius = 1e-3\ncontact_law = \"exakt\""),
            "x.toml:17:1: contact.contact_law = \"exakt\": expected one of \"exact\", \"pade\", \"ellipse\"; did you mean \"exact\"?".to_owned(),
        ),
        (
            sliding("contact_radius = 1e-3\ncontact_law = 1"),
            "x.toml:17:1: contact.contact_law = 1: expected a string, one of \"exact\", \"pade\", \"ellipse\"".to_owned(),
        ),
        (
            edit("model = \"frictionless\"", "model = \"frictionless\"\ncontact_radius = 1e-3"),
            "x.toml:15:1: contact.contact_radius = 0.001: a contact disc carries friction: it needs model = \"sliding\" or \"coulomb\" (or contact_radius = 0)".to_owned(),
        ),
        (
            edit("model = \"frictionless\"", "model = \"rolling\"\ncontact_law = \"pade\""),
            "x.toml:15:1: contact.contact_law = \"pade\": the contact law is the friction law of a contact disc: it needs model = \"sliding\" or \"coulomb\" and contact_radius > 0".to_owned(),
        ),
        (
            sliding("contact_radius = 1e-3\n[effects]\nspin_friction = 3e-4"),
            "x.toml:18:1: effects.spin_friction = 0.0003: the contact disc (contact.contact_radius = 0.001 m) already carries the drilling friction; use one or the other".to_owned(),
        ),
    ];
    for (text, expected) in cases {
        let got = err(&text, &[]);
        assert!(
            got.starts_with(&expected),
            "got      {got}\nexpected {expected}"
        );
    }
    let got = err(&sliding(""), &["contact.contact_radius=-2"]);
    assert!(
        got.contains("--set contact.contact_radius=-2") && got.contains(NONNEG),
        "{got}"
    );
}

/// An effect's torque arm c (torque c N) is at most the body's largest semi-axis: the
/// normal force acts within the contact, inside the body (docs/scenarios.md).
#[test]
fn an_effect_arm_longer_than_the_body_is_rejected() {
    const RULE: &str = "the torque arm c (torque c N) must not exceed the body's largest semi-axis max(a, b, c) = 0.025 m";
    let effects = |line: &str| format!("{PAPER}[effects]\n{line}\n");
    for (line, expected) in [
        (
            "rolling_resistance = 0.03",
            format!("x.toml:25:1: effects.rolling_resistance = 0.03: {RULE}"),
        ),
        (
            "spin_friction = { coefficient = 1e15, regularisation = 1e-2 }",
            format!("x.toml:25:1: effects.spin_friction = 1e15: {RULE}"),
        ),
    ] {
        let got = err(&effects(line), &[]);
        assert!(
            got.starts_with(&expected),
            "got      {got}\nexpected {expected}"
        );
    }
    // at the limit, and as an override
    ok(
        &effects("rolling_resistance = 0.025\nspin_friction = 0.025"),
        &[],
    );
    let got = err(PAPER, &["effects.spin_friction=1"]);
    assert!(
        got.contains("--set effects.spin_friction=1") && got.contains(RULE),
        "{got}"
    );
}

/// The initial spin in units of √(g/L), L = max(a, b, c), is at most ≈ 1/√ε: beyond it
/// gravity is below the round-off of the spin's own terms (docs/scenarios.md). Checked
/// with the initial state, after its overflow checks.
#[test]
fn a_spin_beyond_double_precision_is_rejected() {
    let rule = "in units of √(g/L) (L = max(a, b, c) = 0.025 m, g = 9.81 m/s^2), more than 6.7e7";
    let start = |text: &str| {
        let s = ok(text, &[]);
        s.scene
            .initial_state()
            .map_err(|e| s.locate(&e).to_string())
            .err()
    };
    let got = start(&edit("psi_dot = 60.0", "psi_dot = 1e18")).expect("rejected");
    assert!(
        got.starts_with(
            "x.toml:11:1: initial.psi_dot = 1e18: the spin |ω| = 1.000e18 rad/s is 5.048e16 "
        ) && got.contains(rule),
        "{got}"
    );
    let got = start(&edit("psi_dot = 60.0", "omega_body = [0.0, 0.0, 1e18]")).expect("rejected");
    assert!(
        got.starts_with("x.toml:11:1: initial.omega_body = [0, 0, 1e18]: the spin"),
        "{got}"
    );
    // √(g/L) = 19.81 rad/s: 7e7 of them is rejected, 6e7 is not (whatever else its
    // initial state may violate), nor is any spin without gravity
    let units = (9.81f64 / 0.025).sqrt();
    let spin = |k: f64| edit("psi_dot = 60.0", &format!("psi_dot = {}", k * units));
    assert!(start(&spin(7e7)).is_some_and(|e| e.contains(rule)));
    assert!(start(&spin(6e7)).is_none_or(|e| !e.contains(rule)));
    let weightless = format!("{}[effects]\ngravity = 0\n", spin(1e12));
    assert!(start(&weightless).is_none_or(|e| !e.contains("√(g/L)")));
}

/// `[[body.sphere]]`: contact spheres, and each error located at its line and column with
/// the field, the value and the rule.
#[test]
fn contact_sphere_keys_and_their_errors() {
    let with = |spheres: &str| format!("{PAPER}\n{spheres}");
    let stem = "[[body.sphere]]\nname = \"stem\"\ncenter = [0.0, 0.0, 0.013]\nradius = 0.005\n";
    let s = ok(&with(stem), &[]);
    let spheres = s.scene.body.spheres();
    assert_eq!(spheres.len(), 1);
    assert_eq!(spheres[0].name, "stem");
    assert_eq!(spheres[0].center, Vector3::new(0.0, 0.0, 0.013));
    assert_eq!(spheres[0].radius, 0.005);
    // The same as an inline array of tables (what Python's dicts become).
    let inline = PAPER.replace(
        "inertia = [3.8e-6, 3.8e-6, 6.25e-6]",
        "inertia = [3.8e-6, 3.8e-6, 6.25e-6]\nsphere = [{ name = \"stem\", center = [0.0, 0.0, 0.013], radius = 0.005 }]",
    );
    assert_eq!(ok(&inline, &[]).scene.body, s.scene.body);
    let line = PAPER.lines().count() + 2;
    let cases = [
        (
            with(&stem.replace("radius = 0.005", "radius = -0.005")),
            format!(
                "x.toml:{}:1: body.sphere[0].radius = -0.005: a radius must be positive and finite (m)",
                line + 3
            ),
        ),
        (
            with(&stem.replace("radius = 0.005\n", "")),
            format!(
                "x.toml:{line}:1: body.sphere[0].radius is missing: give the sphere's radius (m)"
            ),
        ),
        (
            with(&format!("{stem}{stem}")),
            format!(
                "x.toml:{}:1: body.sphere[1].name = \"stem\": sphere names must be unique among spheres and rims and not \"ellipsoid\" (the body's own surface)",
                line + 5
            ),
        ),
        (
            with(&stem.replace("radius", "radiu")),
            format!(
                "x.toml:{}:1: body.sphere[0].radiu = 0.005: unknown key in [body.sphere[0]]; did you mean `radius`?",
                line + 3
            ),
        ),
        (
            with(&stem.repeat(9).replace("\"stem\"", "\"s\"")),
            "body.sphere".to_owned(),
        ),
    ];
    for (text, expected) in cases {
        let e = err(&text, &[]);
        assert!(
            e.starts_with(&expected) || e.contains(&expected),
            "{e}\nexpected: {expected}"
        );
    }
    let nine = err(&with(&stem.repeat(9)), &[]);
    assert!(nine.contains("at most 8 contact spheres"), "{nine}");
}
