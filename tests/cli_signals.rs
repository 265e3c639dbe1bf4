//! The crash test (issue #17): `ellipsoid run` interrupted by SIGINT or killed by SIGKILL
//! at random moments (a fixed seed, so every run of the test uses the same moments). The
//! target path never holds a partial file, an existing output survives byte-identical,
//! SIGINT exits 130 having removed its temporaries and the directories it made, and the
//! temporaries a SIGKILL leaves are named after their process and removed by the next run
//! into the same directory.

use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

const BIN: &str = env!("CARGO_BIN_EXE_ellipsoid");

fn nutation() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenarios/nutation.toml")
        .canonicalize()
        .unwrap()
}

/// A run of several minutes (10⁴ s simulated, 10⁶ rows) into `out`, with a summary.
fn long_run(dir: &Path, out: &str, summary: &str) -> Child {
    Command::new(BIN)
        .args([
            "run",
            nutation().to_str().unwrap(),
            "-o",
            out,
            "--summary",
            summary,
            "--set",
            "output.t_end=1e4",
            "--set",
            "output.dt=1e-2",
        ])
        .current_dir(dir)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary runs")
}

fn signal(child: &Child, sig: &str) {
    let ok = Command::new("sh")
        .args(["-c", &format!("kill -{sig} {}", child.id())])
        .status()
        .expect("sh runs")
        .success();
    assert!(ok, "kill -{sig}");
}

/// Every file under `dir` (relative paths), sorted.
fn tree(dir: &Path) -> Vec<String> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_owned()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap().flatten() {
            let p = e.path();
            out.push(p.strip_prefix(dir).unwrap().to_string_lossy().into_owned());
            if p.is_dir() {
                stack.push(p);
            }
        }
    }
    out.sort();
    out
}

/// Waits until a temporary of ours appears in `dir` (the run is writing).
fn wait_for_temporary(dir: &Path, child: &mut Child) {
    let start = Instant::now();
    while !tree(dir)
        .iter()
        .any(|n| n.contains(".ellipsoid-") && n.ends_with(".tmp"))
    {
        assert!(
            child.try_wait().unwrap().is_none(),
            "the run ended before writing"
        );
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "no temporary after 60 s"
        );
        std::thread::sleep(Duration::from_millis(5));
    }
}

#[test]
fn sigint_stops_the_run_removes_its_temporaries_and_directories_and_exits_130() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("summary.json"), "previous summary").unwrap();
    let before = tree(dir.path());
    let mut child = long_run(dir.path(), "new/deeper/traj.csv", "summary.json");
    wait_for_temporary(dir.path(), &mut child);
    std::thread::sleep(Duration::from_millis(200));
    signal(&child, "INT");
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(130), "{err}");
    assert!(
        err.starts_with("error: interrupted by SIGINT at t = ")
            && err.contains("nothing was written"),
        "{err}"
    );
    assert_eq!(
        tree(dir.path()),
        before,
        "temporaries and the directories made for the output are gone"
    );
    assert_eq!(
        std::fs::read_to_string(dir.path().join("summary.json")).unwrap(),
        "previous summary"
    );
}

#[test]
fn sigterm_too_exits_143_and_leaves_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let mut child = long_run(dir.path(), "traj.csv", "s.json");
    wait_for_temporary(dir.path(), &mut child);
    signal(&child, "TERM");
    let out = child.wait_with_output().unwrap();
    assert_eq!(
        out.status.code(),
        Some(143),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(tree(dir.path()), Vec::<String>::new());
}

#[test]
fn killed_at_random_moments_the_target_is_never_partial_and_an_old_output_survives() {
    let dir = tempfile::tempdir().unwrap();
    let (old_traj, old_summary) = ("an earlier trajectory\n", "{\"an\": \"earlier summary\"}\n");
    std::fs::write(dir.path().join("traj.csv"), old_traj).unwrap();
    std::fs::write(dir.path().join("s.json"), old_summary).unwrap();
    let mut rng: u64 = 0x9e37_79b9_7f4a_7c15;
    let mut killed = Vec::new();
    for round in 0..8 {
        rng ^= rng << 13;
        rng ^= rng >> 7;
        rng ^= rng << 17;
        // Anywhere from before the scenario is read to well into the writing.
        let delay = Duration::from_millis(rng % 1200);
        let sig = if round % 3 == 2 { "INT" } else { "KILL" };
        let mut child = long_run(dir.path(), "traj.csv", "s.json");
        std::thread::sleep(delay);
        signal(&child, sig);
        let pid = child.id();
        let status = child.wait().unwrap();
        match sig {
            "INT" => assert!(
                status.code() == Some(130) || status.code().is_none(),
                "round {round}: {status:?}"
            ),
            _ => assert_eq!(status.code(), None, "round {round}: killed"),
        }
        assert_eq!(
            std::fs::read_to_string(dir.path().join("traj.csv")).unwrap(),
            old_traj,
            "round {round} ({sig} after {delay:?})"
        );
        assert_eq!(
            std::fs::read_to_string(dir.path().join("s.json")).unwrap(),
            old_summary,
            "round {round}"
        );
        for name in tree(dir.path()) {
            let ours =
                name.starts_with(".traj.csv.ellipsoid-") || name.starts_with(".s.json.ellipsoid-");
            assert!(
                name == "traj.csv" || name == "s.json" || (ours && name.ends_with(".tmp")),
                "round {round}: unexpected {name}"
            );
            // A leftover names the process that left it: one killed by SIGKILL.
            if ours {
                let leftover_pid: u32 = name
                    .split(".ellipsoid-")
                    .nth(1)
                    .unwrap()
                    .split('-')
                    .next()
                    .unwrap()
                    .parse()
                    .unwrap();
                assert!(
                    killed.contains(&leftover_pid) || (sig == "KILL" && leftover_pid == pid),
                    "round {round}: {name} from pid {leftover_pid}"
                );
            }
        }
        if sig == "KILL" {
            killed.push(pid);
        }
    }
    // The next complete run in the directory removes the leftovers and replaces the files.
    let out = Command::new(BIN)
        .args([
            "run",
            nutation().to_str().unwrap(),
            "-o",
            "traj.csv",
            "--summary",
            "s.json",
            "--set",
            "output.t_end=0.1",
            "-q",
        ])
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(tree(dir.path()), ["s.json", "traj.csv"]);
    assert!(
        std::fs::read_to_string(dir.path().join("traj.csv"))
            .unwrap()
            .lines()
            .find(|l| !l.starts_with('#')) // past the comment line naming the body
            .is_some_and(|header| header.starts_with("t,x,y"))
    );
}

/// Runs `args` in `dir`, ending it (and failing) if it has not finished within `limit`:
/// an input that blocks or never ends must be refused, not waited on.
fn finishes_within(dir: &Path, args: &[&str], limit: Duration) -> std::process::Output {
    let mut child = Command::new(BIN)
        .args(args)
        .current_dir(dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary runs");
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > limit {
            let _ = child.kill();
            let out = child.wait_with_output().unwrap();
            panic!(
                "`ellipsoid {}` still running after {limit:?}: {}",
                args.join(" "),
                String::from_utf8_lossy(&out.stderr)
            );
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

fn mkfifo(path: &Path) {
    let ok = Command::new("mkfifo")
        .arg(path)
        .status()
        .expect("mkfifo runs")
        .success();
    assert!(ok, "mkfifo {}", path.display());
}

/// A scenario, study file, `base` or journal that is a FIFO (which would block with no
/// writer, and where SIGTERM used to wait forever), or an endless device such as
/// /dev/zero (read until memory ran out): refused at once as not a regular file, exit 2.
#[test]
fn pipes_and_endless_devices_are_refused_as_inputs_at_once() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    mkfifo(&d.join("fifo.toml"));
    let nutation = nutation();
    let nutation = nutation.to_str().unwrap();
    std::fs::write(
        d.join("zero-base.toml"),
        "base = \"/dev/zero\"\n[[axis]]\nkey = \"initial.psi_dot\"\nvalues = [1.0]\n",
    )
    .unwrap();
    std::fs::write(
        d.join("s.toml"),
        format!("base = {nutation:?}\n[[axis]]\nkey = \"initial.psi_dot\"\nvalues = [20.0]\n"),
    )
    .unwrap();
    mkfifo(&d.join("t.csv.journal"));
    let cases: [(&[&str], &str); 6] = [
        (&["run", "fifo.toml", "-o", "o.csv"], "fifo.toml"),
        (&["run", "/dev/zero", "-o", "o.csv"], "/dev/zero"),
        (&["check", "/dev/urandom"], "/dev/urandom"),
        (&["study", "fifo.toml", "-o", "o.csv"], "fifo.toml"),
        (&["study", "zero-base.toml", "-o", "o.csv"], "/dev/zero"),
        (&["study", "s.toml", "-o", "t.csv"], "t.csv.journal"),
    ];
    for (args, named) in cases {
        let out = finishes_within(d, args, Duration::from_secs(5));
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(
            stderr.contains(named) && stderr.contains("not a regular file"),
            "{args:?}: {stderr}"
        );
    }
    assert!(!d.join("o.csv").exists() && !d.join("t.csv").exists());
}

/// Waits (at most `limit`) for `child` to exit; its exit code, or a panic naming `what`.
fn exits_within(child: &mut Child, limit: Duration, what: &str) -> Option<i32> {
    let start = Instant::now();
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            return status.code();
        }
        if start.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            panic!("{what}: still running {limit:?} after the signal");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// A rerun of a 10⁷-point study whose journal holds finished rows used to compute every
/// point's key to find what is done (a minute of CPU for 10⁷ points) and honour SIGTERM
/// only after it. Now a journal of the same study file skips its points by index: SIGTERM
/// one second into the rerun exits 143 at once, the journal's earlier rows kept as they
/// were (rows the rerun finished before the signal follow them). After the study file is
/// edited the rows are matched by key, a chunk of points resolved at a time with the
/// cancel flag read between chunks: SIGTERM exits at once too, the rows kept.
#[test]
fn sigterm_while_a_resumed_study_prepares_exits_at_once() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(
        d.join("big.toml"),
        format!(
            "base = {:?}\n[set]\n\"output.t_end\" = 0.01\n\
             [[axis]]\nkey = \"initial.theta_deg\"\nlinspace = [5.0, 20.0, 1000]\n\
             [[axis]]\nkey = \"initial.psi_dot\"\nlinspace = [20.0, 80.0, 10000]\n",
            nutation()
        ),
    )
    .unwrap();
    let start = || {
        Command::new(BIN)
            .args(["study", "big.toml", "-o", "big.csv", "-q", "-j", "2"])
            .current_dir(d)
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .expect("the binary runs")
    };
    // A first run, interrupted once the journal holds rows.
    let journal = d.join("big.csv.journal");
    let mut first = start();
    let begun = Instant::now();
    while std::fs::read_to_string(&journal).map_or(0, |t| t.lines().count()) < 3 {
        assert!(
            begun.elapsed() < Duration::from_secs(60),
            "no rows journaled"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    signal(&first, "INT");
    assert_eq!(
        exits_within(&mut first, Duration::from_secs(10), "the first run"),
        Some(130)
    );
    let rows = std::fs::read_to_string(&journal).unwrap().lines().count() - 1;
    assert!(rows >= 2);

    let before = std::fs::read_to_string(&journal).unwrap();
    let mut rerun = start();
    std::thread::sleep(Duration::from_secs(1));
    signal(&rerun, "TERM");
    let code = exits_within(&mut rerun, Duration::from_secs(5), "the resumed study");
    let out = rerun.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(code, Some(143), "{stderr}");
    assert!(stderr.contains("interrupted by SIGTERM"), "{stderr}");
    assert!(!d.join("big.csv").exists());
    let after = std::fs::read_to_string(&journal).unwrap();
    assert!(
        after.starts_with(&before) && after.lines().count() > rows,
        "the journal's rows are kept as they were"
    );

    // The study file edited (one axis stretched): matched by key, resolving every point.
    let text = std::fs::read_to_string(d.join("big.toml")).unwrap();
    std::fs::write(
        d.join("big.toml"),
        text.replace("80.0, 10000", "81.0, 10000"),
    )
    .unwrap();
    let kept = after.lines().count() - 1;
    let mut edited = start();
    std::thread::sleep(Duration::from_secs(1));
    signal(&edited, "TERM");
    let code = exits_within(&mut edited, Duration::from_secs(5), "the edited study");
    let out = edited.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(code, Some(143), "{stderr}");
    assert!(!d.join("big.csv").exists());
    let rewritten = std::fs::read_to_string(&journal).unwrap();
    assert!(
        rewritten.lines().count() > kept,
        "the rows are kept, now by key"
    );
}

/// Issue 48: Ctrl-C was ignored by `steady --vary` and `animate`: both ran to the end,
/// exited 0 and overwrote their output. Now, as `run` and `study`, SIGINT stops them
/// within a second with exit 130, the existing output untouched and no temporary left.
#[test]
fn sigint_stops_steady_vary_and_animate_with_130_and_the_old_output_kept() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("table.csv"), "an earlier table\n").unwrap();
    std::fs::write(d.join("anim.gif"), "an earlier animation").unwrap();
    // A trajectory to animate: 20 s of the nutation scene at 1 ms.
    let out = Command::new(BIN)
        .args(["run", nutation().to_str().unwrap(), "-o", "traj.csv", "-q"])
        .args(["--summary", "traj.json"])
        .args(["--set", "output.t_end=20", "--set", "output.dt=1e-3"])
        .current_dir(d)
        .output()
        .unwrap();
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let scene = nutation();
    let long: [&[&str]; 2] = [
        // 10⁵ spins of the nutation body, with their critical values: about 8 s.
        &[
            "steady",
            scene.to_str().unwrap(),
            "--vary",
            "initial.psi_dot=-200:200:100000",
            "-o",
            "table.csv",
        ],
        // 1981 frames of 2000 × 2000 px (the whole 20 s at 100 fps and 1.01 simulated
        // seconds per second; an animation has at most 2000): minutes.
        &[
            "animate",
            "traj.csv",
            "--summary",
            "traj.json",
            "-o",
            "anim.gif",
            "--width",
            "2000",
            "--height",
            "2000",
            "--fps",
            "100",
            "--speed",
            "1.01",
        ],
    ];
    for args in long {
        let mut child = Command::new(BIN)
            .args(args)
            .current_dir(d)
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        std::thread::sleep(Duration::from_millis(1500));
        assert!(child.try_wait().unwrap().is_none(), "{args:?} ended early");
        signal(&child, "INT");
        let code = exits_within(&mut child, Duration::from_secs(1), args[0]);
        let out = child.wait_with_output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(code, Some(130), "{args:?}: {err}");
        assert!(err.contains("interrupted by SIGINT"), "{err}");
    }
    assert_eq!(
        std::fs::read_to_string(d.join("table.csv")).unwrap(),
        "an earlier table\n"
    );
    assert_eq!(
        std::fs::read_to_string(d.join("anim.gif")).unwrap(),
        "an earlier animation"
    );
    assert_eq!(
        tree(d),
        ["anim.gif", "table.csv", "traj.csv", "traj.json"],
        "no temporary left"
    );
}
