//! `ellipsoid precision`: the quick grid runs on short scenes, writes the CSV and both
//! plots (atomically: no temporary is left), and every method's error falls as its
//! setting tightens — by at least the factor its order promises, with a margin.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const BIN: &str = env!("CARGO_BIN_EXE_ellipsoid");

fn scenario(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenarios")
        .join(name)
        .canonicalize()
        .expect("scenario exists")
}

fn ellipsoid(dir: &Path, args: &[&str]) -> Output {
    Command::new(BIN)
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the binary runs")
}

/// Header and rows of precision.csv.
fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).expect("precision.csv written");
    let mut lines = text.lines();
    let header = lines
        .next()
        .expect("header")
        .split(',')
        .map(str::to_owned)
        .collect();
    (
        header,
        lines
            .map(|l| l.split(',').map(str::to_owned).collect())
            .collect(),
    )
}

/// (method, error) for each row, in grid order.
fn errors(header: &[String], rows: &[Vec<String>]) -> Vec<(String, f64)> {
    let col = |n: &str| {
        header
            .iter()
            .position(|h| h == n)
            .unwrap_or_else(|| panic!("no column {n}"))
    };
    let (m, e) = (col("method"), col("error"));
    rows.iter()
        .map(|r| {
            (
                r[m].clone(),
                r[e].parse::<f64>()
                    .unwrap_or_else(|_| panic!("error = {:?}", r[e])),
            )
        })
        .collect()
}

/// Runs the quick grid on `name` and checks the files; returns the CSV.
fn quick(name: &str, t_end: &str) -> (Vec<String>, Vec<Vec<String>>, String) {
    let dir = tempfile::tempdir().unwrap();
    let out = ellipsoid(
        dir.path(),
        &[
            "precision",
            scenario(name).to_str().unwrap(),
            "--quick",
            "--t-end",
            t_end,
            "-o",
            "report",
            "-q",
        ],
    );
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert_eq!(
        out.status.code(),
        Some(0),
        "stdout:\n{stdout}\nstderr:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let report = dir.path().join("report");
    let mut names: Vec<String> = std::fs::read_dir(&report)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(
        names,
        [
            "error_vs_evaluations.svg",
            "error_vs_time.svg",
            "precision.csv"
        ],
        "exactly the three files, no temporaries"
    );
    for svg in ["error_vs_time.svg", "error_vs_evaluations.svg"] {
        let text = std::fs::read_to_string(report.join(svg)).unwrap();
        assert!(
            text.starts_with("<svg") && text.trim_end().ends_with("</svg>"),
            "{svg} is a whole SVG"
        );
        for label in ["rk4", "dopri5", "dop853", "paper: RK4, h = 1e-4 s"] {
            assert!(text.contains(label), "{svg} lacks {label:?}");
        }
    }
    let (header, rows) = read_csv(&report.join("precision.csv"));
    assert_eq!(rows.len(), 9, "three settings per method");
    (header, rows, stdout)
}

/// Each method's errors, in order of tightening settings, fall by at least `factor[m]`
/// per setting (the quick grid tightens h by 10 and rtol by 1000 per setting).
fn assert_converges(header: &[String], rows: &[Vec<String>], factor: &[(&str, f64)]) {
    let errs = errors(header, rows);
    for &(method, f) in factor {
        let e: Vec<f64> = errs
            .iter()
            .filter(|(m, _)| m == method)
            .map(|p| p.1)
            .collect();
        assert_eq!(e.len(), 3, "{method}");
        for w in e.windows(2) {
            assert!(w[0].is_finite() && w[1] > 0.0, "{method}: errors {e:?}");
            assert!(
                w[1] * f < w[0],
                "{method}: error {:e} -> {:e} falls by less than {f}: {e:?}",
                w[0],
                w[1]
            );
        }
    }
}

#[test]
fn precision_quick_on_nutation_measures_period_error_that_converges() {
    let (header, rows, stdout) = quick("nutation.toml", "0.5");
    let measure = header.iter().position(|h| h == "measure").unwrap();
    assert!(
        rows.iter().all(|r| r[measure] == "period"),
        "frictionless body of revolution: exact period reference"
    );
    // RK4 is 4th order: 10× smaller h gives ~1e4× smaller error; the adaptive methods
    // gain ~1000× per 1000× tighter rtol.
    assert_converges(
        &header,
        &rows,
        &[("rk4", 300.0), ("dopri5", 100.0), ("dop853", 100.0)],
    );
    assert!(
        stdout.contains("exact nutation period T = 0.0622092117608"),
        "{stdout}"
    );
    for target in ["1e-3:", "1e-6:", "1e-9:", "1e-12:"] {
        assert!(stdout.contains(target), "answer for {target} in\n{stdout}");
    }
}

#[test]
fn precision_quick_on_a_sliding_scene_measures_final_state_error_that_converges() {
    let (header, rows, stdout) = quick("paper-sliding.toml", "0.1");
    let measure = header.iter().position(|h| h == "measure").unwrap();
    assert!(rows.iter().all(|r| r[measure] == "final_state"));
    assert!(
        stdout.contains("final state of DOP853 at rtol = 1e-14"),
        "{stdout}"
    );
    assert_converges(
        &header,
        &rows,
        &[("rk4", 300.0), ("dopri5", 10.0), ("dop853", 10.0)],
    );
}

#[test]
fn precision_rejects_a_bad_end_time_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let out = ellipsoid(
        dir.path(),
        &[
            "precision",
            scenario("nutation.toml").to_str().unwrap(),
            "--t-end",
            "-1",
            "-o",
            "report",
        ],
    );
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("--t-end -1") && err.lines().count() == 1,
        "{err}"
    );
    assert!(!dir.path().join("report").exists());
}

/// (arguments, what the one error line must contain): end times the grid's finest RK4
/// step cannot reach within the report's step budget, non-finite ones, and repeats out
/// of range.
#[test]
fn precision_rejects_an_end_time_or_repeats_it_cannot_run_quickly_and_writes_nothing() {
    let cases: [(&[&str], &[&str]); 6] = [
        (
            &["--quick", "--t-end", "1e300"],
            &[
                "--t-end 1e300: ",
                "h = 0.0001 s would take 1.0e304 steps, more than the report allows (10000000); give --t-end 1000 or less",
            ],
        ),
        (
            &["--quick", "--t-end", "1e6"],
            &["--t-end 1000000: ", "give --t-end 1000 or less"],
        ),
        (
            &["--t-end", "11"],
            &[
                "--t-end 11: ",
                "h = 1e-6 s would take 11000000 steps",
                "give --t-end 10 or less, or use --quick",
            ],
        ),
        (
            &["--quick", "--t-end", "inf"],
            &["--t-end inf: the end time must be positive and finite (s)"],
        ),
        (
            &["--quick", "--t-end", "0.1", "--repeats", "0"],
            &["--repeats 0: give 1 to 1000 timed runs per setting"],
        ),
        (
            &["--quick", "--t-end", "0.1", "--repeats", "1000000000"],
            &["--repeats 1000000000: give 1 to 1000"],
        ),
    ];
    for (extra, needles) in cases {
        let dir = tempfile::tempdir().unwrap();
        let mut args: Vec<String> = vec![
            "precision".into(),
            scenario("paper-sliding.toml").to_str().unwrap().to_owned(),
            "-o".into(),
            "report".into(),
            "-q".into(),
        ];
        args.extend(extra.iter().map(|s| s.to_string()));
        let started = std::time::Instant::now();
        let out = Command::new(BIN)
            .args(&args)
            .current_dir(dir.path())
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{extra:?}: {err}");
        assert!(
            started.elapsed().as_secs_f64() < 5.0,
            "{extra:?}: refused at once, not after running"
        );
        assert!(
            err.starts_with("error: ") && err.lines().count() == 1,
            "{extra:?}: {err}"
        );
        for n in needles {
            assert!(err.contains(n), "{extra:?}: {n:?} not in {err}");
        }
        assert!(!err.contains("panicked"), "{err}");
        assert_eq!(
            std::fs::read_dir(dir.path()).unwrap().count(),
            0,
            "{extra:?}: nothing written"
        );
    }
}

/// A run shorter than the grid's longest RK4 step drops the settings it cannot take, and
/// the scenario's own solver (here an RK4 step of 0.01 s, longer than the run) does not
/// matter: the grid replaces it.
#[test]
fn precision_on_a_short_run_drops_steps_longer_than_it_and_ignores_the_scenarios_solver() {
    let dir = tempfile::tempdir().unwrap();
    let path = scenario("paper-sliding.toml");
    let args = [
        "precision",
        path.to_str().unwrap(),
        "-o",
        "report",
        "-q",
        "--quick",
        "--t-end",
        "0.005",
        "--set",
        "solver.method=\"rk4\"",
        "--set",
        "solver.step=0.01",
    ];
    let out = Command::new(BIN)
        .args(args)
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let csv = std::fs::read_to_string(dir.path().join("report/precision.csv")).unwrap();
    let settings: Vec<&str> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(4).unwrap())
        .collect();
    assert!(
        !settings.contains(&"h=1e-2")
            && settings.contains(&"h=1e-3")
            && settings.contains(&"h=1e-4"),
        "{settings:?}"
    );
    assert_eq!(
        settings.len(),
        8,
        "2 RK4 + 3 DOPRI5 + 3 DOP853 settings: {settings:?}"
    );
}
