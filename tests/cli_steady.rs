//! `ellipsoid steady`: the printout, the CSV table and bad input, through the binary.
//! The physics is checked in tests/steady.rs; here the interface: the critical value the
//! command prints and the table it writes agree with the analytic critical spin of a
//! frictionless egg on its end, C²n_c² = 4 A m g (l − ρ).

use std::path::{Path, PathBuf};
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_ellipsoid");

/// A prolate egg (a = b = 0.02 m, c = 0.03 m, uniform, 0.06 kg) upright without friction.
const EGG: &str = r#"
[body]
a = 0.02
c = 0.03
mass = 0.06
inertia = "uniform"
[initial]
theta = 0.0
psi_dot = 100.0
[contact]
model = "frictionless"
[output]
t_end = 1.0
dt = 0.01
"#;

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("ellipsoid-cli-steady-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// The standard output of `cmd`, which must succeed (else the test fails with its error).
fn stdout_of(cmd: &mut Command) -> String {
    let out = cmd.output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

/// n_c = 2√(A m g (l − ρ))/C with A = m(a² + c²)/5, C = 2ma²/5, l = c, ρ = a²/c.
fn critical_spin() -> f64 {
    let (a, c, m, g): (f64, f64, f64, f64) = (0.02, 0.03, 0.06, 9.81);
    let (big_a, big_c) = (m * (a * a + c * c) / 5.0, 2.0 * m * a * a / 5.0);
    2.0 * (big_a * m * g * (c - a * a / c)).sqrt() / big_c
}

#[test]
fn steady_prints_the_critical_spin_and_writes_the_table() {
    let scene = scratch("egg.toml");
    std::fs::write(&scene, EGG).unwrap();
    let table = scratch("egg.csv");
    let text = stdout_of(
        Command::new(BIN)
            .args([
                "steady",
                scene.to_str().unwrap(),
                "--vary",
                "initial.psi_dot=40:160:7",
                "-o",
            ])
            .arg(&table),
    );
    let line = text
        .lines()
        .find(|l| l.starts_with("critical initial.psi_dot = "))
        .unwrap_or_else(|| panic!("{text}"));
    let value: f64 = line["critical initial.psi_dot = ".len()..]
        .split_whitespace()
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!((value / critical_spin() - 1.0).abs() < 1e-10, "{line}");
    assert!(line.contains("(collision; stable above"), "{line}");
    let csv = std::fs::read_to_string(&table).unwrap();
    let mut lines = csv.lines();
    assert_eq!(
        lines.next().unwrap(),
        "initial.psi_dot,spin,theta,normal_force,stable,max_real,lambda1_re,lambda1_im,mode1,lambda2_re,lambda2_im,mode2,lambda3_re,lambda3_im,mode3,lambda4_re,lambda4_im,mode4,error"
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 7);
    for row in rows {
        let n: f64 = row[0].parse().unwrap();
        assert_eq!(row[4], if n > critical_spin() { "true" } else { "false" });
        assert_eq!(row[8], "tilt");
    }
}

#[test]
fn bad_input_exits_2_and_writes_nothing() {
    let scene = scratch("egg-bad.toml");
    std::fs::write(&scene, EGG).unwrap();
    let table = scratch("never.csv");
    for (args, says) in [
        (vec!["--family", "sideways"], "--family = \"sideways\""),
        (vec!["--family", "precession"], "initial.theta = 0"),
        (
            vec!["--family", "rolling-circle", "--set", "initial.theta=0.5"],
            "contact.model",
        ),
        (
            vec![
                "--family",
                "precession",
                "--set",
                "initial.theta=0.5",
                "--set",
                "initial.phi_dot=1",
                "--vary",
                "initial.psi_dot=1:2:2",
            ],
            "solves for spin here",
        ),
        (vec!["--vary", "initial.psi_dot=1:2"], "KEY=a:b:n"),
        (vec!["--vary", "initial.psi_dot=1:2:0"], "from 1 to"),
        (
            vec![
                "--set",
                "contact.model=\"sliding\"",
                "--set",
                "contact.friction=0.3",
            ],
            "contact.model",
        ),
    ] {
        let out = Command::new(BIN)
            .arg("steady")
            .arg(&scene)
            .args(&args)
            .arg("-o")
            .arg(&table)
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(says), "{args:?}: {err}");
        assert!(!table.exists(), "{args:?}");
    }
}

/// A disc-like lens (a = 0.03 m, c = 0.004 m, uniform, 0.05 kg) rolling, tilted 1.7 rad.
const LENS: &str = r#"
[body]
a = 0.03
c = 0.004
mass = 0.05
inertia = "uniform"
[initial]
theta = 1.7
phi_dot = 1.0
[contact]
model = "rolling"
[output]
t_end = 1.0
dt = 0.01
"#;

/// The rolling-circle family: the printout names the solved spin, the precession rate and
/// the circles; a sweep of φ̇ finds where the circle loses stability (a real pair leaves
/// zero) and the table has the tilted family's columns and two eigenvalues per row.
#[test]
fn steady_rolling_circle_prints_the_motion_and_its_table() {
    let scene = scratch("lens.toml");
    std::fs::write(&scene, LENS).unwrap();
    let run = |args: &[&str]| {
        stdout_of(
            Command::new(BIN)
                .arg("steady")
                .arg(&scene)
                .args(["--family", "rolling-circle"])
                .args(args),
        )
    };
    let text = run(&[]);
    for want in [
        "family               rolling-circle",
        "(about the body's axis, solved for)",
        "precession phi_dot   1 rad/s (about the vertical)\n",
        "circles              G ",
        "verdict              stable",
        "  nutation ",
    ] {
        assert!(text.contains(want), "{want:?} in {text}");
    }
    let table = scratch("lens.csv");
    let text = run(&[
        "--vary",
        "initial.phi_dot=1:8:8",
        "-o",
        table.to_str().unwrap(),
    ]);
    assert!(
        text.contains("critical initial.phi_dot = ") && text.contains("(real; stable below"),
        "{text}"
    );
    let csv = std::fs::read_to_string(&table).unwrap();
    let mut lines = csv.lines();
    assert_eq!(
        lines.next().unwrap(),
        "initial.phi_dot,spin,theta,normal_force,phi_dot,radius_g,radius_contact,stable,max_real,lambda1_re,lambda1_im,mode1,lambda2_re,lambda2_im,mode2,error"
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 8);
    assert_eq!(rows[0][7], "true");
    assert_eq!(rows[2][7], "false");
    for row in &rows {
        assert_eq!(row.len(), 16);
        assert_eq!(row[0], row[4]);
        assert_eq!((row[11], row[14]), ("nutation", "nutation"));
    }
}

/// `--perturb`: the egg on its end below its critical spin (0.3 n_c), started by
/// `ellipsoid steady --perturb 1=1e-6` on its upright spin displaced along its unstable
/// mode and run by `ellipsoid run`, tilts at the rate the table predicts: the growth of θ
/// fitted over a decade (1e-5 to 1e-4 rad) is the first eigenvalue's real part within
/// 1 % (the nonlinear terms are ~θ² there). The scenario printed is the one written, the
/// mode is found by name too, and a bad spec is refused (exit 2) naming the rule.
#[test]
fn steady_perturb_starts_a_run_that_grows_at_the_predicted_rate() {
    let scene = scratch("egg-perturb.toml");
    std::fs::write(&scene, EGG).unwrap();
    let spin = format!("initial.psi_dot={}", 0.3 * critical_spin());
    let steady = |extra: &[&str]| {
        stdout_of(
            Command::new(BIN)
                .args(["steady", scene.to_str().unwrap(), "--set", &spin])
                .args(extra),
        )
    };
    let table = scratch("egg-perturb.csv");
    steady(&["-o", table.to_str().unwrap()]);
    let csv = std::fs::read_to_string(&table).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let row: Vec<&str> = lines.next().unwrap().split(',').collect();
    let at = |name: &str| row[header.iter().position(|h| *h == name).unwrap()];
    let rate: f64 = at("lambda1_re").parse().unwrap();
    assert!(rate > 0.0, "0.3 n_c is below the critical spin");

    let start = scratch("egg-start.toml");
    steady(&["--perturb", "1=1e-6", "-o", start.to_str().unwrap()]);
    let text = std::fs::read_to_string(&start).unwrap();
    assert_eq!(steady(&["--perturb", "1=1e-6"]), text);
    assert_eq!(
        steady(&["--perturb", &format!("{}=1e-6", at("mode1"))]),
        text
    );

    let run = scratch("egg-start.csv");
    let t_end = 16.0 / rate;
    stdout_of(
        Command::new(BIN)
            .args([
                "run",
                start.to_str().unwrap(),
                "-q",
                "-o",
                run.to_str().unwrap(),
            ])
            .args(["--set", &format!("output.t_end={t_end}")])
            .args(["--set", &format!("output.dt={}", t_end / 4000.0)]),
    );
    let csv = std::fs::read_to_string(&run).unwrap();
    let mut lines = csv.lines().skip_while(|l| l.starts_with('#'));
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let (t, theta) = (
        header.iter().position(|h| *h == "t").unwrap(),
        header.iter().position(|h| *h == "theta").unwrap(),
    );
    let rows: Vec<(f64, f64)> = lines
        .map(|l| {
            let v: Vec<&str> = l.split(',').collect();
            (v[t].parse().unwrap(), v[theta].parse().unwrap())
        })
        .collect();
    assert!(
        rows[0].1 < 2e-6,
        "the start is 1e-6 off the upright: θ = {}",
        rows[0].1
    );
    let reaching = |level: f64| {
        let w = rows
            .windows(2)
            .find(|w| w[0].1 < level && w[1].1 >= level)
            .expect("the tilt reaches the level");
        let (l0, l1) = (w[0].1.ln(), w[1].1.ln());
        w[0].0 + (level.ln() - l0) / (l1 - l0) * (w[1].0 - w[0].0)
    };
    let fitted = 10f64.ln() / (reaching(1e-4) - reaching(1e-5));
    eprintln!("perturbed egg: growth {fitted:.9} /s against Re λ = {rate:.9} /s");
    assert!(
        (fitted / rate - 1.0).abs() < 0.01,
        "growth {fitted} against Re λ = {rate}"
    );

    for (spec, rule) in [
        ("9=1e-6", "has modes 1 to 4"),
        ("1=0.5", "at most 0.1"),
        ("0=1e-6", "numbered from 1"),
        ("spin-up=1e-6", "has no mode"),
        ("1", "MODE=EPS"),
    ] {
        let out = Command::new(BIN)
            .args([
                "steady",
                scene.to_str().unwrap(),
                "--set",
                &spin,
                "--perturb",
                spec,
            ])
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{spec}: {err}");
        assert!(err.contains(rule), "{spec}: {err}");
    }
}

/// `--plot`: the egg's diagram against its spin in each format (SVG text with the panels'
/// titles, the critical value the printout gives, labelled where it is drawn, both
/// shadings; PNG and PDF by their signatures); without --vary, or with an unknown
/// extension, exit 2 with nothing written.
#[test]
fn steady_plot_draws_the_stability_diagram() {
    let scene = scratch("egg-plot.toml");
    std::fs::write(&scene, EGG).unwrap();
    let n_c = critical_spin();
    for ext in ["svg", "png", "pdf"] {
        let figure = scratch(&format!("egg.{ext}"));
        stdout_of(
            Command::new(BIN)
                .args([
                    "steady",
                    scene.to_str().unwrap(),
                    "--vary",
                    "initial.psi_dot=40:160:13",
                    "--plot",
                ])
                .arg(&figure),
        );
        let bytes = std::fs::read(&figure).unwrap();
        match ext {
            "png" => assert!(bytes.starts_with(b"\x89PNG")),
            "pdf" => assert!(bytes.starts_with(b"%PDF")),
            _ => {
                let svg = String::from_utf8(bytes).unwrap();
                for text in [
                    "Growth rates Re λ",
                    "Angular frequencies |Im λ|",
                    "initial.psi_dot (rad/s)",
                    &format!("{n_c:.4} (collision)"),
                    "fill=\"#D6F0D6\"",
                    "fill=\"#FAD6D6\"",
                ] {
                    assert!(svg.contains(text), "{text} not in the SVG");
                }
            }
        }
    }
    for (args, says) in [
        (vec!["--plot", "x.svg"], "give --vary"),
        (
            vec!["--vary", "initial.psi_dot=40:160:13", "--plot", "x.gif"],
            "unknown figure format",
        ),
        (
            vec!["--vary", "initial.psi_dot=40:160:10001", "--plot", "x.svg"],
            "at most 10000 values",
        ),
    ] {
        let out = Command::new(BIN)
            .current_dir(scratch(""))
            .arg("steady")
            .arg(&scene)
            .args(&args)
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(says), "{args:?}: {err}");
        assert!(!scratch(args[args.len() - 1]).exists(), "{args:?}");
    }
}

/// The tippe top (a sphere, R = 15 mm, G 3 mm below its centre: α = 0.2; I1 = I2 =
/// 8e-7 kg m²) spinning upright at 180 rad/s under viscous sliding.
const VISCOUS_TOP: &str = r#"
[body]
a = 0.015
c = 0.015
mass = 6e-3
com_offset = 0.003
inertia = [8e-7, 8e-7, 7e-7]
[initial]
theta = 0.0
phi_dot = 180.0
[contact]
model = "viscous"
viscous_friction = 1.0
[output]
t_end = 1.0
dt = 0.01
"#;

/// The viscous law with --vary: a sweep of I3 finds where the upright spin destabilises
/// (inside the criterion 1 − α < I1/I3, near its end at this spin), and `ellipsoid
/// steady` of single scenarios just either side of it gives opposite verdicts; the table
/// has six modes per row.
#[test]
fn steady_vary_takes_the_viscous_law() {
    let scene = scratch("viscous-top.toml");
    std::fs::write(&scene, VISCOUS_TOP).unwrap();
    let table = scratch("viscous-top.csv");
    let stdout = stdout_of(
        Command::new(BIN)
            .args([
                "steady",
                scene.to_str().unwrap(),
                "--vary",
                "body.inertia[2]=6e-7:1.2e-6:13",
                "-o",
            ])
            .arg(&table),
    );
    let line = stdout
        .lines()
        .find(|l| l.starts_with("critical body.inertia[2] = "))
        .unwrap_or_else(|| panic!("{stdout}"));
    let i3: f64 = line["critical body.inertia[2] = ".len()..]
        .split_whitespace()
        .next()
        .unwrap()
        .parse()
        .unwrap();
    let ratio = 8e-7 / i3;
    assert!(ratio > 0.8 && ratio < 0.82, "I1/I3 = {ratio}");
    let verdict = |i3: f64| {
        let out = Command::new(BIN)
            .args([
                "steady",
                scene.to_str().unwrap(),
                "--set",
                &format!("body.inertia[2]={i3:e}"),
            ])
            .output()
            .unwrap();
        let text = String::from_utf8_lossy(&out.stdout).into_owned();
        text.lines()
            .find(|l| l.starts_with("verdict"))
            .unwrap()
            .ends_with(" stable")
    };
    assert!(verdict(i3 * (1.0 + 1e-6)) && !verdict(i3 * (1.0 - 1e-6)));
    let csv = std::fs::read_to_string(&table).unwrap();
    let header = csv.lines().next().unwrap();
    assert!(
        header.starts_with("body.inertia[2],spin,theta,normal_force,stable,max_real,lambda1_re")
    );
    assert!(
        header.ends_with("lambda6_re,lambda6_im,mode6,error"),
        "{header}"
    );
    assert_eq!(csv.lines().count(), 14);
}

/// The bundled rattleback run for 5 s with two Poincaré sections (θ̇ = 0 falling, and
/// ω_z = 0 in either direction under a name a CSV field must quote).
fn rattleback_with_sections() -> PathBuf {
    let root = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../scenarios/rattleback.toml"
    );
    let mut text = std::fs::read_to_string(root).unwrap();
    text.push_str(
        r#"
[[section]]
name = "tilt_max"
column = "theta_dot"
crosses = 0.0
direction = "down"

[[section]]
name = "spin, \"reversal\""
column = "omega_z"
crosses = 0.0
"#,
    );
    let scene = scratch("rattleback-sections.toml");
    std::fs::write(&scene, text).unwrap();
    scene
}

/// Issue 47: a body with contact spheres is analysed on the surface it rests on, and the
/// report says which: the inverted tippe top of scenarios/tippe-top-stem.toml stands on
/// its stem (stable at 120 rad/s, above its critical 85.67), upright on its ball; the
/// paper's body, one surface, has no such line.
#[test]
fn steady_names_the_surface_a_body_with_spheres_rests_on() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios");
    let stem = root.join("tippe-top-stem.toml");
    let report = |path: &Path, args: &[&str]| {
        stdout_of(Command::new(BIN).arg("steady").arg(path).args(args))
    };
    let point = "contact.contact_radius=0";
    let down = report(
        &stem,
        &[
            "--family",
            "inverted",
            "--set",
            point,
            "--set",
            "initial.psi_dot=-120",
        ],
    );
    assert!(down.contains("resting on           stem"), "{down}");
    assert!(down.contains("spin n               120 rad/s"), "{down}");
    assert!(down.contains("verdict              stable"), "{down}");
    let up = report(&stem, &["--set", point, "--set", "initial.theta=0"]);
    assert!(up.contains("resting on           ellipsoid"), "{up}");
    let plain = report(
        &root.join("egg.toml"),
        &["--set", "contact.model=\"coulomb\""],
    );
    assert!(!plain.contains("resting on"), "{plain}");
}

/// `ellipsoid plot --section` draws one marker per row of the section table, in the
/// colour of its section, whichever output format; a column the table lacks, a
/// non-numeric column and a missing --y are refused naming them, and nothing is written.
#[test]
fn plot_section_draws_one_marker_per_crossing() {
    let scene = rattleback_with_sections();
    let (run, sections) = (scratch("rb-run.csv"), scratch("rb-sections.csv"));
    stdout_of(
        Command::new(BIN)
            .arg("run")
            .arg(&scene)
            .args(["--set", "output.t_end=5", "-q", "-o"])
            .arg(&run)
            .arg("--sections")
            .arg(&sections),
    );
    let table = std::fs::read_to_string(&sections).unwrap();
    let rows: Vec<&str> = table
        .lines()
        .filter(|l| !l.starts_with('#'))
        .skip(1)
        .collect();
    let spin_rows = rows.iter().filter(|r| r.starts_with('"')).count();
    assert!(
        rows.len() - spin_rows > 20 && spin_rows > 0,
        "{} rows, {spin_rows} of the spin section",
        rows.len()
    );
    let svg = scratch("rb-section.svg");
    stdout_of(
        Command::new(BIN)
            .arg("plot")
            .arg(&sections)
            .args(["--section", "--x", "psi", "--y", "omega_z", "-q", "-o"])
            .arg(&svg),
    );
    let text = std::fs::read_to_string(&svg).unwrap();
    assert_eq!(text.matches("<circle").count(), rows.len());
    // Two colours, as many markers of the spin section's as it has rows.
    assert_eq!(text.matches(r##"fill="#D62728""##).count(), spin_rows + 1);
    assert!(text.contains("psi (rad)") && text.contains("omega_z (rad/s)"));
    assert!(text.contains("spin, &quot;reversal&quot;") || text.contains("spin, \"reversal\""));
    // Issue 47: ψ modulo 2π (the run's ψ reaches several turns).
    let wrapped = scratch("rb-section-wrapped.svg");
    stdout_of(
        Command::new(BIN)
            .arg("plot")
            .arg(&sections)
            .args(["--section", "--x", "psi", "--y", "omega_z", "--wrap", "psi"])
            .args(["-q", "-o"])
            .arg(&wrapped),
    );
    let text = std::fs::read_to_string(&wrapped).unwrap();
    assert!(text.contains("psi (rad, modulo 2π)"), "the axis says so");
    assert_eq!(text.matches("<circle").count(), rows.len());
    for ext in ["png", "pdf"] {
        let fig = scratch(&format!("rb-section.{ext}"));
        stdout_of(
            Command::new(BIN)
                .arg("plot")
                .arg(&sections)
                .args(["--section", "--x", "t", "--y", "theta", "-q", "-o"])
                .arg(&fig),
        );
        let bytes = std::fs::read(&fig).unwrap();
        let magic: &[u8] = if ext == "png" { b"\x89PNG" } else { b"%PDF" };
        assert!(bytes.starts_with(magic), "{ext}");
    }
    // Issue 47: --dpi scales a PNG's pixels (the IHDR's width and height, bytes 16–24).
    let size = |dpi: Option<&str>| {
        let fig = scratch(&format!("rb-section-{}.png", dpi.unwrap_or("default")));
        let mut cmd = Command::new(BIN);
        cmd.arg("plot")
            .arg(&sections)
            .args(["--section", "--x", "t", "--y", "theta", "-q", "-o"])
            .arg(&fig);
        if let Some(d) = dpi {
            cmd.args(["--dpi", d]);
        }
        stdout_of(&mut cmd);
        let b = std::fs::read(&fig).unwrap();
        let be = |k: usize| u32::from_be_bytes([b[k], b[k + 1], b[k + 2], b[k + 3]]);
        (be(16), be(20))
    };
    let (w, h) = size(None);
    assert_eq!(size(Some("96")), (w, h));
    assert_eq!(size(Some("192")), (2 * w, 2 * h));
    let never = scratch("never-section.svg");
    for (args, says) in [
        (
            vec!["--x", "psi", "--y", "omega_z", "--wrap", "omega_z"],
            "--wrap \"omega_z\": not an angle: its unit is rad/s",
        ),
        (
            vec!["--x", "psi", "--y", "omega_z", "--wrap", "theta"],
            "--wrap \"theta\": not a column of this plot",
        ),
        (
            vec!["--x", "psi", "--y", "omega_z", "--dpi", "200"],
            "--dpi 200: a resolution applies to PNG figures only",
        ),
        (vec!["--x", "psi", "--y", "spin"], "--y \"spin\""),
        (vec!["--x", "section", "--y", "psi"], "--x \"section\""),
        (
            vec!["--x", "mode", "--y", "psi"],
            "column `mode` = \"rolling\"",
        ),
        (vec!["--x", "psi"], "--y"),
    ] {
        let out = Command::new(BIN)
            .arg("plot")
            .arg(&sections)
            .arg("--section")
            .args(&args)
            .arg("-o")
            .arg(&never)
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(says), "{args:?}: {err}");
        assert!(!never.exists(), "{args:?}");
    }
    // A trajectory is not a section table.
    let out = Command::new(BIN)
        .arg("plot")
        .arg(&run)
        .args(["--section", "--x", "t", "--y", "theta", "-o"])
        .arg(&never)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("not `section`"));
}

/// `--perturb` under the viscous law: a mode by number or by name gives the same start,
/// which carries G's horizontal velocity; a run of it tilts from 1e-5 to 1e-4 rad at the
/// Re λ of the table's first mode within 1 % (tests/steady.rs checks the frequencies).
#[test]
fn steady_perturb_takes_the_viscous_law() {
    let scene = scratch("viscous-perturb.toml");
    std::fs::write(&scene, VISCOUS_TOP).unwrap();
    let steady = |extra: &[&str]| {
        stdout_of(
            Command::new(BIN)
                .args(["steady", scene.to_str().unwrap()])
                .args(extra),
        )
    };
    let table = scratch("viscous-perturb.csv");
    let text = steady(&["-o", table.to_str().unwrap()]);
    assert!(
        text.contains("  tilt ") && text.contains("  slip "),
        "{text}"
    );
    let csv = std::fs::read_to_string(&table).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let row: Vec<&str> = lines.next().unwrap().split(',').collect();
    let at = |name: &str| row[header.iter().position(|h| *h == name).unwrap()];
    let rate: f64 = at("lambda1_re").parse().unwrap();
    assert!(rate > 0.0 && at("mode1") == "tilt", "{csv}");

    let start = scratch("viscous-start.toml");
    steady(&["--perturb", "1=1e-6", "-o", start.to_str().unwrap()]);
    let text = std::fs::read_to_string(&start).unwrap();
    assert!(text.contains("velocity = ["), "{text}");
    assert_eq!(steady(&["--perturb", "tilt=1e-6"]), text);
    assert_ne!(steady(&["--perturb", "slip=1e-6"]), text);

    let run = scratch("viscous-start.csv");
    let t_end = 16.0 / rate;
    stdout_of(
        Command::new(BIN)
            .args(["run", start.to_str().unwrap(), "-q", "-o"])
            .arg(&run)
            .args(["--set", &format!("output.t_end={t_end}")])
            .args(["--set", &format!("output.dt={}", t_end / 4000.0)]),
    );
    let csv = std::fs::read_to_string(&run).unwrap();
    let mut lines = csv.lines().skip_while(|l| l.starts_with('#'));
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let (t, theta) = (
        header.iter().position(|h| *h == "t").unwrap(),
        header.iter().position(|h| *h == "theta").unwrap(),
    );
    let rows: Vec<(f64, f64)> = lines
        .map(|l| {
            let v: Vec<&str> = l.split(',').collect();
            (v[t].parse().unwrap(), v[theta].parse().unwrap())
        })
        .collect();
    let reaching = |level: f64| {
        let w = rows
            .windows(2)
            .find(|w| w[0].1 < level && w[1].1 >= level)
            .expect("the tilt reaches the level");
        let (l0, l1) = (w[0].1.ln(), w[1].1.ln());
        w[0].0 + (level.ln() - l0) / (l1 - l0) * (w[1].0 - w[0].0)
    };
    let fitted = 10f64.ln() / (reaching(1e-4) - reaching(1e-5));
    eprintln!("perturbed viscous top: growth {fitted:.9} /s against Re λ = {rate:.9} /s");
    assert!(
        (fitted / rate - 1.0).abs() < 0.01,
        "growth {fitted} against Re λ = {rate}"
    );
}

/// Runs `ellipsoid steady SCENE ARGS`, failing if it takes more than `limit` (an input
/// that never ends must be refused, not waited on).
fn steady_within(scene: &std::path::Path, args: &[&str], limit: f64) -> std::process::Output {
    let mut child = Command::new(BIN)
        .arg("steady")
        .arg(scene)
        .args(args)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let start = std::time::Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed().as_secs_f64() > limit {
            let _ = child.kill();
            panic!("`steady {args:?}` still running after {limit} s");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

/// Issue 48: the rolling-circle and precession families solved for θ at φ̇ = 0 panicked
/// (exit 101, "Singular value was NaN"), and one such value killed a whole sweep. Issue
/// 44: φ̇ = 0 has its motion, the lens on its edge (θ = π/2) rolling straight on (its
/// circles none, `inf` in the table) or spinning in place (G fixed, radius 0); a sweep
/// through it has three rows, none of them an error.
#[test]
fn steady_at_zero_precession_stands_the_lens_on_its_edge() {
    let scene = scratch("lens-still.toml");
    std::fs::write(&scene, LENS).unwrap();
    for (family, model) in [
        ("rolling-circle", "contact.model=\"rolling\""),
        ("precession", "contact.model=\"frictionless\""),
    ] {
        let base = ["--family", family, "--solve", "theta", "--set", model];
        let out = steady_within(
            &scene,
            &[
                &base[..],
                &["--set", "initial.phi_dot=0", "--set", "initial.psi_dot=10"],
            ]
            .concat(),
            10.0,
        );
        let text = String::from_utf8_lossy(&out.stdout);
        assert_eq!(
            out.status.code(),
            Some(0),
            "{family}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let theta: f64 = text
            .lines()
            .find_map(|l| l.strip_prefix("tilt theta"))
            .and_then(|l| l.split_whitespace().next())
            .and_then(|v| v.parse().ok())
            .unwrap_or_else(|| panic!("{text}"));
        assert!(
            (theta - std::f64::consts::FRAC_PI_2).abs() < 1e-12,
            "{text}"
        );
        let circles = if family == "rolling-circle" {
            "circles              none: G and the contact point go straight on (phi_dot = 0)"
        } else {
            "circles              G 0 m, contact point "
        };
        assert!(text.contains(circles), "{family}: {text}");
        let table = scratch(&format!("still-{family}.csv"));
        let out = steady_within(
            &scene,
            &[
                &base[..],
                &[
                    "--set",
                    "initial.psi_dot=10",
                    "--vary",
                    "initial.phi_dot=-1:1:3",
                    "-o",
                ],
                &[table.to_str().unwrap()],
            ]
            .concat(),
            10.0,
        );
        assert_eq!(
            out.status.code(),
            Some(0),
            "{family}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let csv = std::fs::read_to_string(&table).unwrap();
        let rows: Vec<&str> = csv.lines().skip(1).collect();
        assert_eq!(rows.len(), 3, "{csv}");
        assert!(rows.iter().all(|r| r.ends_with(',')), "{csv}");
        assert!(rows[1].starts_with("0,"), "{csv}");
        if family == "rolling-circle" {
            assert!(rows[1].contains(",inf,inf,"), "{csv}");
        }
    }
}

/// Issue 48: spins of 1e80 rad/s and up never returned, and at 1e40 the verdict was
/// round-off. Now refused at once (exit 2) naming the quantity, its value and the rule,
/// in a single analysis; in a sweep such values are rows without a steady motion.
#[test]
fn steady_refuses_rates_beyond_what_doubles_resolve_at_once() {
    let scene = scratch("egg-fast.toml");
    std::fs::write(&scene, EGG).unwrap();
    for spin in ["1e40", "1e80", "1e200"] {
        let set = format!("initial.psi_dot={spin}");
        let out = steady_within(&scene, &["--set", &set], 5.0);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{spin}: {err}");
        assert!(
            err.contains(&format!(
                "spin n = {spin} rad/s: a steady motion is analysed up to 100000 √(g/c_max)"
            )),
            "{err}"
        );
    }
    let out = steady_within(&scene, &["--vary", "initial.psi_dot=100:1e200:3"], 5.0);
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(
        text.matches("no steady motion: spin n = ").count(),
        2,
        "{text}"
    );
}

/// Issue 48: `--vary` over an unknown, a non-numeric or an out-of-range key exited 0 with
/// a table of error rows. Now exit 2 naming the key and the rule, nothing written.
#[test]
fn vary_over_a_key_the_scenario_refuses_exits_2_and_writes_nothing() {
    let scene = scratch("egg-vary.toml");
    std::fs::write(&scene, EGG).unwrap();
    let table = scratch("vary-never.csv");
    for (vary, says) in [
        ("body.colour=1:2:3", "unknown key"),
        ("contact.model=1:2:3", "expected a string"),
        ("body.mass=-1:1:3", "the mass must be positive"),
    ] {
        let out = steady_within(
            &scene,
            &["--vary", vary, "-o", table.to_str().unwrap()],
            10.0,
        );
        let err = String::from_utf8_lossy(&out.stderr);
        let key = vary.split('=').next().unwrap();
        assert_eq!(out.status.code(), Some(2), "{vary}: {err}");
        assert!(
            err.contains(&format!("{key} = "))
                && err.contains("the scenario refuses this value")
                && err.contains(says),
            "{vary}: {err}"
        );
        assert!(out.stdout.is_empty(), "{vary}: nothing printed");
        assert!(!table.exists(), "{vary}");
    }
}

/// Issue 48: `steady --plot X -o X` left the table's CSV text in the figure while saying
/// "wrote X", and `-o x.h5` or `-o x.toml` got CSV. `-o` takes .csv or .parquet (with
/// --perturb, .toml), and never the path of --plot: anything else is refused before the
/// analysis (exit 2, the message naming the option and the rule, nothing written).
#[test]
fn steady_refuses_an_output_it_does_not_write_or_the_plot_s_path() {
    let scene = scratch("egg-outputs.toml");
    std::fs::write(&scene, EGG).unwrap();
    let vary = ["--vary", "initial.psi_dot=10:200:5"];
    let png = scratch("same.png");
    let png_dot = format!("{}/./same.png", png.parent().unwrap().display());
    let cases: Vec<(Vec<String>, &str, Vec<PathBuf>)> = vec![
        (
            vec![
                "--plot".into(),
                png.display().to_string(),
                "-o".into(),
                png.display().to_string(),
            ],
            "give them different paths",
            vec![png.clone()],
        ),
        (
            vec![
                "--plot".into(),
                png.display().to_string(),
                "-o".into(),
                png_dot,
            ],
            "give them different paths",
            vec![png.clone()],
        ),
        (
            vec!["-o".into(), scratch("t.h5").display().to_string()],
            "-o writes the table as .csv or .parquet",
            vec![scratch("t.h5")],
        ),
        (
            vec!["-o".into(), scratch("t.toml").display().to_string()],
            "-o writes the table as .csv or .parquet",
            vec![scratch("t.toml")],
        ),
        (
            vec!["-o".into(), scratch("t").display().to_string()],
            "-o writes the table as .csv or .parquet",
            vec![scratch("t")],
        ),
    ];
    for (args, says, never) in cases {
        let out = Command::new(BIN)
            .arg("steady")
            .arg(&scene)
            .args(vary)
            .args(&args)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(says) && err.contains("-o "), "{args:?}: {err}");
        for p in never {
            assert!(!p.exists(), "{args:?} wrote {}", p.display());
        }
    }
    // --perturb writes TOML, and only TOML.
    let csv = scratch("start.csv");
    let out = Command::new(BIN)
        .arg("steady")
        .arg(&scene)
        .args(["--perturb", "1=1e-6", "-o"])
        .arg(&csv)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.contains("with --perturb, -o writes the started scenario as .toml"),
        "{err}"
    );
    assert!(!csv.exists());
    let toml = scratch("start.toml");
    stdout_of(
        Command::new(BIN)
            .arg("steady")
            .arg(&scene)
            .args(["--perturb", "1=1e-6", "-o"])
            .arg(&toml),
    );
    assert!(
        std::fs::read_to_string(&toml)
            .unwrap()
            .contains("[initial]")
    );
}

/// Issue 48: `plot --section` of a table of 10⁶ points wrote a 92 MB SVG, and the PNG
/// failed ("nodes limit reached"). Beyond 20 000 points the figure is drawn on a grid of
/// marker-sized cells: 10⁶ points of two sections give an SVG under 4 MB and a PNG, the
/// legend counting every point, and stderr saying how many markers were drawn.
#[test]
fn plot_section_of_a_million_points_stays_small() {
    use std::io::Write;
    let table = scratch("million-sections.csv");
    {
        let mut w = std::io::BufWriter::new(std::fs::File::create(&table).unwrap());
        w.write_all(b"section,t,psi,omega_z\n").unwrap();
        for k in 0..1_000_000u64 {
            // Two sections filling a square densely (a chaotic section looks so).
            let (x, y) = (
                (k * 7919 % 1_000_003) as f64,
                (k * 104_729 % 999_983) as f64,
            );
            let name = if k % 2 == 0 { "a" } else { "b" };
            writeln!(w, "{name},{k},{x},{y}").unwrap();
        }
        w.flush().unwrap();
    }
    for ext in ["svg", "png"] {
        let fig = scratch(&format!("million.{ext}"));
        let out = Command::new(BIN)
            .arg("plot")
            .arg(&table)
            .args(["--section", "--x", "psi", "--y", "omega_z", "-o"])
            .arg(&fig)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{ext}: {err}");
        assert!(
            err.contains("1000000 points of 2 sections") && err.contains("markers"),
            "{err}"
        );
        let size = std::fs::metadata(&fig).unwrap().len();
        assert!(size < 4_000_000, "{ext}: {size} bytes");
        if ext == "svg" {
            let text = std::fs::read_to_string(&fig).unwrap();
            assert!(text.matches("<circle").count() <= 225 * 175);
            assert!(text.contains("a (500000 points)") && text.contains("b (500000 points)"));
        }
    }
}
