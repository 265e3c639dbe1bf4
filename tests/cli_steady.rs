//! `ellipsoid steady`: the printout, the CSV table and bad input, through the binary.
//! The physics is checked in tests/steady.rs; here the interface: the critical value the
//! command prints and the table it writes agree with the analytic critical spin of a
//! frictionless egg on its end, C²n_c² = 4 A m g (l − ρ).

use std::path::PathBuf;
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
    let out = Command::new(BIN)
        .args([
            "steady",
            scene.to_str().unwrap(),
            "--vary",
            "initial.psi_dot=40:160:7",
            "-o",
        ])
        .arg(&table)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
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
        let out = Command::new(BIN)
            .arg("steady")
            .arg(&scene)
            .args(["--family", "rolling-circle"])
            .args(args)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        String::from_utf8(out.stdout).unwrap()
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
