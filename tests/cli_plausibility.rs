//! The plausibility warnings of the command-line tool (issue 47 item 3): a valid value
//! that is likely a unit slip is reported on standard error as one `warning:` line, the
//! command goes on (exit 0, its output written), and `--quiet-plausibility` (or run's
//! `--quiet`) silences it. No bundled scenario warns.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const BIN: &str = env!("CARGO_BIN_EXE_ellipsoid");

fn scenarios() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenarios")
        .canonicalize()
        .expect("scenarios/ exists")
}

fn ellipsoid(dir: &Path, args: &[&str]) -> Output {
    Command::new(BIN)
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the binary runs")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// nutation.toml with ψ0 = 80 (degrees typed in the radian key), a short run.
const SLIP: [&str; 4] = ["--set", "initial.psi=80", "--set", "output.t_end=0.01"];

#[test]
fn run_warns_of_an_angle_beyond_a_turn_and_runs_and_the_flag_silences_it() {
    let dir = tempfile::tempdir().unwrap();
    let file = scenarios().join("nutation.toml");
    let file = file.to_str().unwrap();
    let mut args = vec!["run", file, "-o", "t.csv"];
    args.extend(SLIP);
    let out = ellipsoid(dir.path(), &args);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(dir.path().join("t.csv").exists());
    let err = stderr(&out);
    let line = err
        .lines()
        .find(|l| l.contains("warning:"))
        .unwrap_or_else(|| panic!("no warning in\n{err}"));
    assert!(
        line.ends_with(": --set initial.psi=80: warning: initial.psi = 80: 80 rad is more than 2π (12.7 turns): degrees? use psi_deg = 80"),
        "{line}"
    );
    assert_eq!(err.matches("warning:").count(), 1, "{err}");
    for quiet in ["--quiet-plausibility", "--quiet"] {
        let mut args = args.clone();
        args.push(quiet);
        let out = ellipsoid(dir.path(), &args);
        assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
        assert!(
            !stderr(&out).contains("warning"),
            "{quiet}: {}",
            stderr(&out)
        );
    }
    // The progress lines stay with --quiet-plausibility alone.
    let mut quiet = args.clone();
    quiet.push("--quiet-plausibility");
    let plain = stderr(&ellipsoid(dir.path(), &quiet));
    assert_eq!(
        plain,
        err.lines()
            .filter(|l| !l.contains("warning:"))
            .map(|l| format!("{l}\n"))
            .collect::<String>()
    );
}

#[test]
fn check_warns_of_a_mass_in_grams_and_prints_and_the_flag_silences_it() {
    let dir = tempfile::tempdir().unwrap();
    let file = scenarios().join("nutation.toml");
    let file = file.to_str().unwrap();
    let args = ["check", file, "--set", "body.mass=50"];
    let out = ellipsoid(dir.path(), &args);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(String::from_utf8_lossy(&out.stdout).contains("initial mode"));
    let err = stderr(&out);
    assert!(
        err.contains("warning: body.mass = 50: the density mass / ((4/3)π a b c) is 1.09e6 kg/m³, and solids have 10 to 30000 kg/m³, foam to osmium: grams? 50 g is mass = 0.05 (1091 kg/m³)\n"),
        "{err}"
    );
    let mut quiet = args.to_vec();
    quiet.push("--quiet-plausibility");
    let out = ellipsoid(dir.path(), &quiet);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(stderr(&out), "");
}

/// `check` (which loads a scenario as every command does) of every bundled scenario
/// prints no warning.
#[test]
fn no_bundled_scenario_warns() {
    let dir = tempfile::tempdir().unwrap();
    let root = scenarios();
    let mut n = 0;
    for d in [root.clone(), root.join("paper")] {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.extension().is_none_or(|x| x != "toml") {
                continue;
            }
            let out = ellipsoid(dir.path(), &["check", p.to_str().unwrap()]);
            assert_eq!(
                out.status.code(),
                Some(0),
                "{}: {}",
                p.display(),
                stderr(&out)
            );
            assert!(
                !stderr(&out).contains("warning"),
                "{}: {}",
                p.display(),
                stderr(&out)
            );
            n += 1;
        }
    }
    assert!(n >= 30, "{n} scenarios");
}
