//! `ellipsoid study` (issue #15): the kill test — a study killed by SIGKILL mid-way loses
//! only its runs in flight, never leaves a table behind, and its rerun completes with a
//! table identical to an uninterrupted run's (every column but the measured wall time) —
//! plus SIGINT, resuming, and the errors of a hostile study file.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

const BIN: &str = env!("CARGO_BIN_EXE_ellipsoid");

fn scenarios() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenarios")
        .canonicalize()
        .unwrap()
}

/// A study of 400 nutation runs of 1 s (a few ms each: about a second on 2 cores), with
/// every kind of outcome column.
fn write_study(dir: &Path) -> PathBuf {
    let path = dir.join("study.toml");
    let text = format!(
        "base = {:?}\n[set]\n\"output.t_end\" = 1.0\n\"output.dt\" = 0.01\nobserve = [{{ name = \"tilt\", column = \"theta\", crosses = 0.2, direction = \"up\" }}]\n\
         [[axis]]\nkey = \"initial.psi_dot\"\nlinspace = [20.0, 80.0, 20]\n\
         [[axis]]\nkey = \"initial.theta_deg\"\nlinspace = [5.0, 30.0, 20]\n\
         [outcomes]\nfinal = [\"theta\", \"mode\"]\nmin = [\"normal_force\"]\nmax = [\"theta\"]\n",
        scenarios().join("nutation.toml")
    );
    std::fs::write(&path, text).unwrap();
    path
}

fn study(dir: &Path, args: &[&str]) -> Output {
    Command::new(BIN)
        .arg("study")
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the binary runs")
}

/// The CSV table without its wall-time column (a measurement, different in every run).
fn table_without_wall_time(path: &Path) -> Vec<Vec<String>> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let wall = header.iter().position(|h| *h == "wall_time [s]").unwrap();
    std::iter::once(text.lines().next().unwrap())
        .chain(lines)
        .map(|l| {
            // The messages hold no commas in this study, so splitting is exact.
            l.split(',')
                .enumerate()
                .filter(|(i, _)| *i != wall)
                .map(|(_, c)| c.to_owned())
                .collect()
        })
        .collect()
}

fn journal_rows(path: &Path) -> usize {
    std::fs::read_to_string(path)
        .map(|t| t.lines().count().saturating_sub(1))
        .unwrap_or(0)
}

#[test]
fn a_study_killed_mid_way_resumes_to_the_table_of_an_uninterrupted_run() {
    let dir = tempfile::tempdir().unwrap();
    let spec = write_study(dir.path());
    let spec = spec.to_str().unwrap();

    let whole = study(dir.path(), &[spec, "-o", "whole.csv", "-q"]);
    assert!(
        whole.status.success(),
        "{}",
        String::from_utf8_lossy(&whole.stderr)
    );
    let expected = table_without_wall_time(&dir.path().join("whole.csv"));
    assert_eq!(expected.len(), 401);

    // Killed once the journal holds some rows but far from all.
    let mut child = Command::new(BIN)
        .args(["study", spec, "-o", "killed.csv", "-q"])
        .current_dir(dir.path())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let journal = dir.path().join("killed.csv.journal");
    let start = Instant::now();
    while journal_rows(&journal) < 40 {
        assert!(start.elapsed() < Duration::from_secs(60), "no progress");
        assert!(
            child.try_wait().unwrap().is_none(),
            "the study ended before it was killed"
        );
        std::thread::sleep(Duration::from_millis(5));
    }
    child.kill().unwrap(); // SIGKILL
    child.wait().unwrap();
    let kept = journal_rows(&journal);
    assert!(
        kept < 400,
        "killed too late to prove anything ({kept} rows)"
    );
    assert!(
        !dir.path().join("killed.csv").exists(),
        "no table before the study is complete"
    );

    let again = study(dir.path(), &[spec, "-o", "killed.csv"]);
    let stderr = String::from_utf8_lossy(&again.stderr);
    assert!(again.status.success(), "{stderr}");
    assert!(stderr.contains("from the journal"), "{stderr}");
    assert_eq!(
        table_without_wall_time(&dir.path().join("killed.csv")),
        expected
    );

    // A rerun of a finished study runs nothing and writes the same table again.
    let third = study(dir.path(), &[spec, "-o", "killed.csv"]);
    let stderr = String::from_utf8_lossy(&third.stderr);
    assert!(stderr.contains("(0 run now"), "{stderr}");
    assert_eq!(
        table_without_wall_time(&dir.path().join("killed.csv")),
        expected
    );
}

#[test]
fn sigint_stops_the_study_keeping_its_rows_and_writing_no_table() {
    let dir = tempfile::tempdir().unwrap();
    let spec = write_study(dir.path());
    let child = Command::new(BIN)
        .args(["study", spec.to_str().unwrap(), "-o", "t.parquet"])
        .current_dir(dir.path())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let journal = dir.path().join("t.parquet.journal");
    let start = Instant::now();
    while journal_rows(&journal) < 10 {
        assert!(start.elapsed() < Duration::from_secs(60), "no progress");
        std::thread::sleep(Duration::from_millis(5));
    }
    Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    if out.status.code() == Some(0) {
        return; // it finished before the signal arrived (a fast machine): nothing to check
    }
    assert_eq!(out.status.code(), Some(130), "{stderr}");
    assert!(
        stderr.contains("interrupted by SIGINT after") && stderr.contains("rerun the same command"),
        "{stderr}"
    );
    assert!(!dir.path().join("t.parquet").exists());
    assert!(journal_rows(&journal) >= 10);
}

#[test]
fn a_hostile_study_file_is_refused_at_once_naming_key_value_and_rule() {
    let dir = tempfile::tempdir().unwrap();
    let base = scenarios().join("nutation.toml");
    let cases = [
        (
            format!(
                "base = {base:?}\n[[axis]]\nkey = \"initial.psi_dot\"\nlinspace = [1, 2, 1000000000]\n"
            ),
            "study.toml:4:19: axis[0].linspace = 1000000000: n must be an integer from 1 to 10000000",
        ),
        (
            format!(
                "base = {base:?}\n[[axis]]\nkey = \"initial.psi_dot\"\nlinspace = [1, 2, 100000]\n[[axis]]\nkey = \"initial.theta\"\nlinspace = [0.1, 0.2, 10000]\n"
            ),
            "combine = grid: 100000 × 10000 = 1e9 points; a study has at most 10000000",
        ),
        (
            format!(
                "base = {base:?}\nx = {}1{}\n",
                "[".repeat(50_000),
                "]".repeat(50_000)
            ),
            "TOML syntax error",
        ),
        (
            format!("base = {base:?}\n[[axis]]\nkey = \"initial.psi_dott\"\nvalues = [1.0]\n"),
            "did you mean",
        ),
        (
            "[[axis]]\nkey = \"a\"\nvalues = [1]\n".to_owned(),
            "base is missing",
        ),
    ];
    for (text, expected) in cases {
        std::fs::write(dir.path().join("study.toml"), &text).unwrap();
        let t = Instant::now();
        let out = study(dir.path(), &["study.toml", "-o", "t.csv"]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(
            t.elapsed() < Duration::from_secs(1),
            "{expected}: {:?}",
            t.elapsed()
        );
        assert_eq!(out.status.code(), Some(2), "{stderr}");
        assert!(
            stderr.starts_with("error: ") && stderr.contains(expected),
            "expected {expected:?} in {stderr}"
        );
        assert!(!dir.path().join("t.csv").exists());
    }
    let out = study(dir.path(), &["study.toml", "-o", "t.xlsx"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains(".csv, .parquet or .h5"));
}

/// `--trajectories RUNS.h5`: one group per table row, named by the row's key, each the
/// same trajectory `ellipsoid run` writes for that point (same values, bit for bit), with
/// the axis value and status as attributes; refused over a journal that holds rows
/// (unless --fresh) and above the size limit, leaving no file behind.
#[test]
fn trajectories_are_one_hdf5_group_per_row_named_by_its_key() {
    let dir = tempfile::tempdir().unwrap();
    let base = scenarios().join("nutation.toml");
    let text = format!(
        "base = {base:?}\n[set]\n\"output.t_end\" = 0.2\n\"output.dt\" = 0.01\n\
         [[axis]]\nkey = \"initial.psi_dot\"\nvalues = [20.0, 40.0, 60.0]\n"
    );
    std::fs::write(dir.path().join("study.toml"), &text).unwrap();
    let args = [
        "study.toml",
        "-o",
        "t.csv",
        "--trajectories",
        "runs/t.h5",
        "-q",
    ];
    let out = study(dir.path(), &args);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let h5 = dir.path().join("runs/t.h5");
    let table = std::fs::read_to_string(dir.path().join("t.csv")).unwrap();
    let header: Vec<&str> = table.lines().next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let rows: Vec<Vec<&str>> = table
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    assert_eq!(rows.len(), 3);
    // Numbers as people write them (issue 47): 60, not 6e1.
    let spins: Vec<&str> = rows
        .iter()
        .map(|r| r[col("initial.psi_dot [rad/s]")])
        .collect();
    assert_eq!(spins, ["20", "40", "60"]);
    let mut keys: Vec<String> = rows.iter().map(|r| r[col("key")].to_owned()).collect();
    keys.sort();
    assert_eq!(ellipsoid_io::hdf5::group_names(&h5).unwrap(), keys);
    for row in &rows {
        let key = row[col("key")];
        let g = ellipsoid_io::hdf5::read_group(&h5, key).unwrap();
        let spin: f64 = row[col("initial.psi_dot [rad/s]")].parse().unwrap();
        assert_eq!(g.numbers["initial.psi_dot"], spin);
        assert_eq!(
            g.numbers["point"],
            row[col("point")].parse::<f64>().unwrap()
        );
        assert_eq!(g.attributes["key"], key);
        assert_eq!(g.attributes["status"], row[col("status")]);
        assert_eq!(g.column("t").unwrap().len(), 21);
        // The same point through `ellipsoid run`.
        let single = dir.path().join(format!("single-{key}.h5"));
        let o = Command::new(BIN)
            .args(["run", base.to_str().unwrap(), "-q"])
            .args(["--set", "output.t_end=0.2", "--set", "output.dt=0.01"])
            .args(["--set", &format!("initial.psi_dot={spin:?}")])
            .arg("-o")
            .arg(&single)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let run = ellipsoid_io::hdf5::read(&single).unwrap();
        assert_eq!(g.columns, run.columns, "point {key}: columns and units");
        assert_eq!(g.modes, run.modes);
    }

    // A journal holding rows has no trajectories to give: refused, the file untouched.
    let before = std::fs::read(&h5).unwrap();
    let out = study(dir.path(), &args);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("already holds 3 finished runs") && stderr.contains("--fresh"),
        "{stderr}"
    );
    assert_eq!(std::fs::read(&h5).unwrap(), before);
    let out = study(dir.path(), &[&args[..], &["--fresh"]].concat());
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(ellipsoid_io::hdf5::group_names(&h5).unwrap(), keys);

    // Above the limit: 2000 runs × 100001 samples, refused before anything runs.
    std::fs::write(
        dir.path().join("big.toml"),
        format!(
            "base = {base:?}\n[set]\n\"output.t_end\" = 100.0\n\"output.dt\" = 0.001\n\
             [[axis]]\nkey = \"initial.psi_dot\"\nlinspace = [20.0, 80.0, 2000]\n"
        ),
    )
    .unwrap();
    let t = Instant::now();
    let out = study(
        dir.path(),
        &["big.toml", "-o", "big.csv", "--trajectories", "big.h5"],
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains(
            "2000 runs × 100001 samples = 200002000 trajectory rows, above the limit of 100000000"
        ),
        "{stderr}"
    );
    assert!(t.elapsed() < Duration::from_secs(2));
    assert!(!dir.path().join("big.h5").exists() && !dir.path().join("big.csv").exists());
    let out = study(
        dir.path(),
        &["study.toml", "-o", "x.csv", "--trajectories", "x.csv"],
    );
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains(".h5"));
}

/// A small study of `values` of `initial.psi_dot` (0.2 s runs).
fn write_small_study(dir: &Path, values: &str) {
    let base = scenarios().join("nutation.toml");
    let text = format!(
        "base = {base:?}\n[set]\n\"output.t_end\" = 0.2\n\"output.dt\" = 0.01\n\
         [[axis]]\nkey = \"initial.psi_dot\"\nvalues = [{values}]\n"
    );
    std::fs::write(dir.join("study.toml"), text).unwrap();
}

/// `-j` is bounded like Python's `workers` (4 per CPU, at least 8): 100000 threads used to
/// take minutes to start and end in a failed stack guard page.
#[test]
fn jobs_beyond_four_per_cpu_are_refused_at_once() {
    let dir = tempfile::tempdir().unwrap();
    write_small_study(dir.path(), "20.0, 40.0");
    for jobs in ["0", "100000", "1000000000"] {
        let t = Instant::now();
        let out = study(dir.path(), &["study.toml", "-o", "t.csv", "-j", jobs, "-q"]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "-j {jobs}: {stderr}");
        assert!(
            stderr.contains(&format!("--jobs {jobs}: give 1 to ")) && stderr.contains("4 per CPU"),
            "{stderr}"
        );
        assert!(t.elapsed() < Duration::from_secs(1), "{:?}", t.elapsed());
        assert!(!dir.path().join("t.csv").exists());
    }
    let out = study(dir.path(), &["study.toml", "-o", "t.csv", "-j", "8", "-q"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Issue 47: a study prints its points' plausibility warnings before it runs, each
/// distinct one once (ψ̇ typed in rpm at two points, 1600 twice), and
/// `--quiet-plausibility` and `-q` silence them; a plausible study prints none.
#[test]
fn a_study_prints_each_plausibility_warning_once() {
    let dir = tempfile::tempdir().unwrap();
    write_small_study(dir.path(), "20.0, 1600.0, 1600.0, 2000.0");
    let out = study(dir.path(), &["study.toml", "-o", "t.csv"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    let warnings: Vec<&str> = stderr
        .lines()
        .filter(|l| l.contains(": warning: "))
        .collect();
    assert_eq!(warnings.len(), 2, "{stderr}");
    assert!(warnings[0].contains("initial.psi_dot = 1600") && warnings[0].contains("rpm"));
    assert!(warnings[1].contains("initial.psi_dot = 2000"), "{stderr}");
    for quiet in ["--quiet-plausibility", "-q"] {
        let out = study(dir.path(), &["study.toml", "-o", "t.csv", quiet]);
        assert!(!String::from_utf8_lossy(&out.stderr).contains("warning"));
    }
    write_small_study(dir.path(), "20.0, 40.0");
    let out = study(dir.path(), &["study.toml", "-o", "t.csv", "--fresh"]);
    assert!(!String::from_utf8_lossy(&out.stderr).contains("warning"));
}

/// Points that run the same scenario (a repeated value) share a key: one group for them,
/// where a second group of the same name used to fail the whole study.
#[test]
fn trajectories_of_points_running_the_same_scenario_share_one_group() {
    let dir = tempfile::tempdir().unwrap();
    write_small_study(dir.path(), "20.0, 40.0, 20.0");
    let out = study(
        dir.path(),
        &["study.toml", "-o", "t.csv", "--trajectories", "t.h5", "-q"],
    );
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let table = std::fs::read_to_string(dir.path().join("t.csv")).unwrap();
    let header: Vec<&str> = table.lines().next().unwrap().split(',').collect();
    let key = header.iter().position(|h| *h == "key").unwrap();
    let keys: Vec<String> = table
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(key).unwrap().to_owned())
        .collect();
    assert_eq!(keys.len(), 3);
    assert_eq!(keys[0], keys[2]);
    let mut distinct = vec![keys[0].clone(), keys[1].clone()];
    distinct.sort();
    let h5 = dir.path().join("t.h5");
    assert_eq!(ellipsoid_io::hdf5::group_names(&h5).unwrap(), distinct);
    let g = ellipsoid_io::hdf5::read_group(&h5, &keys[0]).unwrap();
    assert_eq!(g.numbers["initial.psi_dot"], 20.0);
    assert_eq!(g.column("t").unwrap().len(), 21);
}

/// A body with contact spheres: the study's outcomes and trajectories follow its column
/// list (`gap_stem`, `normal_force_stem`, …, and its mode labels), bit for bit as
/// `ellipsoid run` writes the same point; a column the body lacks is refused, named.
#[test]
fn outcomes_and_trajectories_follow_the_columns_of_a_body_with_spheres() {
    let dir = tempfile::tempdir().unwrap();
    let base = scenarios().join("tippe-top-stem.toml");
    let study_text = |outcomes: &str| {
        format!(
            "base = {base:?}\n[set]\n\"output.t_end\" = 0.2\n\"output.dt\" = 0.01\n\
             [[axis]]\nkey = \"initial.theta\"\nvalues = [0.1, 1.2]\n\
             [outcomes]\nwall_time = false\n{outcomes}\n"
        )
    };
    std::fs::write(
        dir.path().join("stem.toml"),
        study_text(
            "final = [\"gap_stem\", \"normal_force_stem\", \"mode\", \"theta\"]\nmin = [\"gap_stem\"]\nmax = [\"slip_speed_ellipsoid\"]",
        ),
    )
    .unwrap();
    let out = study(
        dir.path(),
        &["stem.toml", "-o", "t.csv", "--trajectories", "t.h5", "-q"],
    );
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let table = std::fs::read_to_string(dir.path().join("t.csv")).unwrap();
    let header: Vec<&str> = table.lines().next().unwrap().split(',').collect();
    for h in [
        "final.gap_stem [m]",
        "final.normal_force_stem [N]",
        "min.gap_stem [m]",
        "max.slip_speed_ellipsoid [m/s]",
    ] {
        assert!(header.contains(&h), "{header:?}");
    }
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let h5 = dir.path().join("t.h5");
    for line in table.lines().skip(1) {
        let row: Vec<&str> = line.split(',').collect();
        let cell = |name: &str| row[col(name)].parse::<f64>().unwrap();
        let theta = cell("initial.theta [rad]");
        let single = dir.path().join(format!("single-{theta}.h5"));
        let o = Command::new(BIN)
            .args(["run", base.to_str().unwrap(), "-q"])
            .args(["--set", "output.t_end=0.2", "--set", "output.dt=0.01"])
            .args(["--set", &format!("initial.theta={theta:?}")])
            .arg("-o")
            .arg(&single)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let run = ellipsoid_io::hdf5::read(&single).unwrap();
        let column = |name: &str| run.column(name).unwrap();
        let last = |name: &str| *column(name).last().unwrap();
        assert_eq!(row[col("status")], "completed");
        assert_eq!(
            cell("final.gap_stem [m]").to_bits(),
            last("gap_stem").to_bits()
        );
        assert_eq!(
            cell("final.normal_force_stem [N]").to_bits(),
            last("normal_force_stem").to_bits()
        );
        assert_eq!(cell("final.theta [rad]").to_bits(), last("theta").to_bits());
        assert_eq!(row[col("final.mode")], run.modes.last().unwrap());
        assert!(run.modes.last().unwrap().contains('@'), "{:?}", run.modes);
        let min = column("gap_stem")
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min);
        assert_eq!(cell("min.gap_stem [m]").to_bits(), min.to_bits());
        assert!(min > 0.0, "the stem stays clear of the plane in 0.2 s");
        let max = column("slip_speed_ellipsoid")
            .iter()
            .copied()
            .fold(f64::NEG_INFINITY, f64::max);
        assert_eq!(
            cell("max.slip_speed_ellipsoid [m/s]").to_bits(),
            max.to_bits()
        );
        // The trajectory's group: every column of the run, per-surface ones included.
        let g = ellipsoid_io::hdf5::read_group(&h5, row[col("key")]).unwrap();
        assert!(g.column("normal_force_stem").is_some());
        assert_eq!(g.columns, run.columns, "theta {theta}: columns and units");
        assert_eq!(g.modes, run.modes);
    }

    // A column this body lacks: refused at once, named, with the body's columns.
    std::fs::write(
        dir.path().join("bad.toml"),
        study_text("final = [\"gap_peg\"]"),
    )
    .unwrap();
    let out = study(dir.path(), &["bad.toml", "-o", "bad.csv", "-q"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("outcomes.final")
            && stderr.contains("\"gap_peg\"")
            && stderr.contains("gap_stem"),
        "{stderr}"
    );
    assert!(!dir.path().join("bad.csv").exists());
}
