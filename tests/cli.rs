//! Integration tests of the `ellipsoid` binary: every bundled scenario, the output files
//! and summary, and a table of malformed inputs (exit 2, one precise line, nothing
//! written, no panic text).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_json::{Value, json};

const BIN: &str = env!("CARGO_BIN_EXE_ellipsoid");

fn scenarios() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenarios")
        .canonicalize()
        .expect("scenarios/ exists")
}

/// Runs the binary in `dir`.
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

fn code(o: &Output) -> i32 {
    o.status.code().expect("exited, not killed")
}

fn assert_no_panic(o: &Output) {
    let text = format!("{}{}", String::from_utf8_lossy(&o.stdout), stderr(o));
    assert!(
        !text.contains("panicked") && !text.contains("RUST_BACKTRACE"),
        "panic text in output:\n{text}"
    );
}

fn read_json(path: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).expect("summary written"))
        .expect("summary is JSON")
}

/// Header and rows of a CSV trajectory (its `#` comment line skipped), numbers parsed.
fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).expect("trajectory written");
    let mut lines = text.lines().skip_while(|l| l.starts_with('#'));
    let header: Vec<String> = lines
        .next()
        .expect("header")
        .split(',')
        .map(str::to_owned)
        .collect();
    let rows: Vec<Vec<String>> = lines
        .map(|l| l.split(',').map(str::to_owned).collect())
        .collect();
    (header, rows)
}

/// The text column `name`.
fn column_text<'r>(header: &[String], rows: &'r [Vec<String>], name: &str) -> Vec<&'r str> {
    let i = header.iter().position(|h| h == name).unwrap();
    rows.iter().map(|r| r[i].as_str()).collect()
}

fn column(header: &[String], rows: &[Vec<String>], name: &str) -> Vec<f64> {
    let i = header
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("no column {name}"));
    rows.iter()
        .map(|r| {
            r[i].parse::<f64>()
                .unwrap_or_else(|_| panic!("{name} = {:?} is not a number", r[i]))
        })
        .collect()
}

/// The CSV header, exactly (docs/scenarios.md).
const HEADER: &str = "t,x,y,z,theta,phi,psi,theta_dot,phi_dot,psi_dot,omega_x,omega_y,omega_z,vx,vy,vz,energy,normal_force,slip_speed,mode,work,omega_world_x,omega_world_y,omega_world_z,contact_x,contact_y,drift,gap";

// ------------------------------------------------------------------ bundled scenarios

/// Runs a bundled scenario (shortened to `t_end` when given) and checks what every run
/// must satisfy: the exit status for its run status, a well-formed CSV that ends where
/// the summary says, and the scenario's `[check]` drift tolerances.
fn run_scenario(
    name: &str,
    t_end: Option<f64>,
    status: &str,
) -> (Value, Vec<String>, Vec<Vec<String>>) {
    let dir = tempfile::tempdir().unwrap();
    let file = scenarios().join(format!("{name}.toml"));
    let (csv, json) = (dir.path().join("out.csv"), dir.path().join("summary.json"));
    let set = t_end.map(|t| format!("output.t_end={t}"));
    let mut args = vec![
        "run",
        file.to_str().unwrap(),
        "-o",
        csv.to_str().unwrap(),
        "--summary",
        json.to_str().unwrap(),
        "-q",
    ];
    if let Some(s) = &set {
        args.extend(["--set", s]);
    }
    let out = ellipsoid(dir.path(), &args);
    assert_no_panic(&out);
    let expected_code = if status == "completed" { 0 } else { 3 };
    assert_eq!(code(&out), expected_code, "{name}: stderr {}", stderr(&out));
    let summary = read_json(&json);
    assert_eq!(summary["status"], status, "{name}: {}", summary["message"]);
    for (key, check) in summary["checks"].as_object().unwrap() {
        if key != "status" {
            assert_eq!(check["passed"], true, "{name}: [check] {key}: {check}");
        }
    }
    let (header, rows) = read_csv(&csv);
    // The fixed columns, then five per surface of a body with contact spheres.
    assert_eq!(
        header[..HEADER.split(',').count()].join(","),
        HEADER,
        "{name}: header"
    );
    for group in header[HEADER.split(',').count()..].chunks(5) {
        let surface = group[0]
            .strip_prefix("normal_force_")
            .expect("a surface's columns");
        let expected = [
            "normal_force",
            "slip_speed",
            "gap",
            "contact_x",
            "contact_y",
        ]
        .map(|q| format!("{q}_{surface}"));
        assert_eq!(group, expected, "{name}: header");
    }
    assert_eq!(
        rows.len() as u64,
        summary["samples"].as_u64().unwrap(),
        "{name}"
    );
    assert!(
        rows.iter().all(|r| r.len() == header.len()),
        "{name}: ragged rows"
    );
    let t = column(&header, &rows, "t");
    assert_eq!(t[0], 0.0);
    assert_eq!(
        *t.last().unwrap(),
        summary["final"]["t"].as_f64().unwrap(),
        "{name}: the trajectory ends where the run did"
    );
    assert!(t.windows(2).all(|w| w[1] > w[0]), "{name}: times increase");
    // Every numeric column (all but `mode`, which is not last: `work` follows it).
    let numeric: Vec<&String> = header.iter().filter(|h| *h != "mode").collect();
    assert_eq!(numeric.len(), header.len() - 1);
    for h in numeric {
        assert!(
            column(&header, &rows, h).iter().all(|v| v.is_finite()),
            "{name}: {h} finite"
        );
    }
    (summary, header, rows)
}

#[test]
fn every_bundled_scenario_has_a_test() {
    let tested = [
        "nutation",
        "paper-sliding",
        "paper-rolling",
        "tippe-top",
        "egg",
        "billiard",
        "disc",
        "rattleback",
        "rolling-resistance",
        "spin-friction",
        "air-drag",
        "tippe-top-disc",
        "egg-jump",
        "drop",
        "tippe-top-jump",
        "tippe-top-jump-stem",
        "tippe-top-stem",
        "top-on-peg",
        "top-falls-onto-rim",
        "coin",
        "euler-disk",
        "rolling-disc",
    ];
    for entry in std::fs::read_dir(scenarios()).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") {
            let stem = path.file_stem().unwrap().to_string_lossy().into_owned();
            assert!(
                tested.contains(&stem.as_str()),
                "scenarios/{stem}.toml has no test in tests/cli.rs"
            );
        }
    }
}

#[test]
fn scenario_nutation_conserves_its_invariants() {
    let (s, h, rows) = run_scenario("nutation", Some(2.0), "completed");
    for k in ["energy", "momentum", "angular_momentum_z", "axial_spin"] {
        assert!(
            s["drift"][k].as_f64().unwrap() < 1e-9,
            "{k}: {}",
            s["drift"][k]
        );
    }
    assert!(s["drift"]["jellett"].is_null(), "not a sphere");
    // θ nutates: it returns close to θ0 = 10° after dipping.
    let theta = column(&h, &rows, "theta");
    let (lo, hi) = theta
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), &v| (a.min(v), b.max(v)));
    assert!(
        lo < 0.16 && (hi - 10f64.to_radians()).abs() < 1e-6,
        "θ in [{lo}, {hi}]"
    );
}

#[test]
fn scenario_paper_sliding_rises_until_the_slip_stops() {
    let (s, h, rows) = run_scenario("paper-sliding", None, "slip_stopped");
    assert_eq!(s["events"][0]["kind"], "slip_stop");
    let theta = column(&h, &rows, "theta");
    assert!(
        theta.last().unwrap().to_degrees() > 135.0,
        "θ_final = {}°",
        theta.last().unwrap().to_degrees()
    );
}

#[test]
fn scenario_paper_rolling_conserves_energy() {
    let (s, h, rows) = run_scenario("paper-rolling", Some(2.0), "completed");
    assert!(s["drift"]["energy"].as_f64().unwrap() < 1e-9);
    assert!(
        column(&h, &rows, "slip_speed")
            .iter()
            .all(|v| v.abs() < 1e-12),
        "no slip while rolling"
    );
}

#[test]
fn scenario_tippe_top_turns_over() {
    let (s, h, rows) = run_scenario("tippe-top", None, "completed");
    let theta = column(&h, &rows, "theta");
    assert!(theta.iter().copied().fold(0.0, f64::max).to_degrees() > 120.0);
    assert!(s["drift"]["jellett"].as_f64().unwrap() < 1e-9);
}

#[test]
fn scenario_egg_rises_then_stops_slipping() {
    let (_, h, rows) = run_scenario("egg", None, "slip_stopped");
    let theta = column(&h, &rows, "theta");
    assert!(
        theta[0].to_degrees() > 79.0 && theta.last().unwrap().to_degrees() < 25.0,
        "θ from {} to {}",
        theta[0],
        theta.last().unwrap()
    );
}

#[test]
fn scenario_billiard_matches_the_analytic_slip_time_and_rolling_speed() {
    let (s, h, rows) = run_scenario("billiard", None, "completed");
    let (v0, mu, g) = (2.0, 0.2, 9.81);
    let slip_stop = s["events"]
        .as_array()
        .unwrap()
        .iter()
        .find(|e| e["kind"] == "slip_stop")
        .expect("slip stops");
    let t_star = 2.0 * v0 / (7.0 * mu * g);
    assert!(
        (slip_stop["t"].as_f64().unwrap() - t_star).abs() < 1e-9,
        "t* = {} vs {t_star}",
        slip_stop["t"]
    );
    let vx = column(&h, &rows, "vx");
    assert!((vx.last().unwrap() - 5.0 * v0 / 7.0).abs() < 1e-9);
    assert_eq!(rows.last().unwrap()[19], "rolling");
}

#[test]
fn scenario_disc_rolls_with_constant_energy() {
    let (s, _, _) = run_scenario("disc", Some(2.0), "completed");
    assert!(s["drift"]["energy"].as_f64().unwrap() < 1e-9);
}

#[test]
fn scenario_rattleback_reverses_its_spin() {
    let (s, h, rows) = run_scenario("rattleback", Some(5.0), "completed");
    assert!(s["drift"]["energy"].as_f64().unwrap() < 1e-9);
    // ω3 starts at −5 rad/s and has changed sign by 5 s (first reversal ≈ 2.7 s).
    let wz = column(&h, &rows, "omega_z");
    assert_eq!(wz[0], -5.0);
    assert!(*wz.last().unwrap() > 1.0, "ω3 = {}", wz.last().unwrap());
}

/// The coin and Euler's disk spin down and land flat once (the event `flat`; the disc at
/// its `flat_tilt`, after its air boundary layer took over), then lie on their face to the end; the rolling disc keeps its lean on its circle.
#[test]
fn scenario_coin_and_euler_disk_land_flat_and_the_rolling_disc_keeps_its_lean() {
    for (name, at) in [("coin", 7.25), ("euler-disk", 61.65)] {
        let (s, h, rows) = run_scenario(name, None, "completed");
        let flats: Vec<f64> = (s["events"].as_array().unwrap().iter())
            .filter(|e| e["kind"] == "flat")
            .map(|e| e["t"].as_f64().unwrap())
            .collect();
        assert_eq!(flats.len(), 1, "{name}: {flats:?}");
        assert!((flats[0] - at).abs() < 0.01, "{name}: flat at {}", flats[0]);
        let k = h.iter().position(|c| c == "mode").unwrap();
        assert!(rows.last().unwrap()[k].starts_with("face@"), "{name}");
        assert!(
            s["drift"]["energy_plus_work"].as_f64().unwrap() < 1e-8,
            "{name}"
        );
    }
    let (s, h, rows) = run_scenario("rolling-disc", None, "completed");
    let theta = column(&h, &rows, "theta");
    let lean = 85f64.to_radians();
    assert!(theta.iter().all(|t| (t - lean).abs() < 1e-9));
    assert!(s["drift"]["energy"].as_f64().unwrap() < 1e-10);
}

#[test]
fn scenario_rolling_resistance_dissipates() {
    let (s, _, _) = run_scenario("rolling-resistance", Some(2.0), "completed");
    assert!(
        s["final_invariants"]["energy"].as_f64().unwrap()
            < s["initial_invariants"]["energy"].as_f64().unwrap()
    );
    assert!(
        s["drift"]["energy"].is_null(),
        "energy is not conserved with rolling resistance"
    );
}

#[test]
fn scenario_spin_friction_slows_the_spin() {
    let (s, h, rows) = run_scenario("spin-friction", Some(2.0), "completed");
    let wz = column(&h, &rows, "omega_z");
    assert!(wz.last().unwrap() < &(0.8 * wz[0]));
    assert!(s["final"]["work"].as_f64().unwrap() > 0.0);
}

/// The kinds of the summary's events, in order.
fn event_kinds(s: &Value) -> Vec<&str> {
    s["events"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| e["kind"].as_str().unwrap())
        .collect()
}

#[test]
fn scenario_egg_jump_flies_and_lands_again_and_again() {
    let (s, h, rows) = run_scenario("egg-jump", Some(2.3), "completed");
    let kinds = event_kinds(&s);
    let lifts = kinds.iter().filter(|k| **k == "lift_off").count();
    assert!(lifts >= 5, "{lifts} lift-offs");
    // the run may end in flight
    let downs = kinds.iter().filter(|k| **k == "touchdown").count();
    assert!(
        downs == lifts || downs + 1 == lifts,
        "{lifts} lift-offs, {downs} touchdowns"
    );
    let impact = s["events"]
        .as_array()
        .unwrap()
        .iter()
        .find(|e| e["kind"] == "impact")
        .unwrap();
    assert!(
        impact["energy_loss"].as_f64().unwrap() >= 0.0
            && impact["impulse"][2].as_f64().unwrap() > 0.0
    );
    let mode = h.iter().position(|c| c == "mode").unwrap();
    let gap = column(&h, &rows, "gap");
    let flying: Vec<usize> = (0..rows.len())
        .filter(|&i| rows[i][mode] == "flight")
        .collect();
    assert!(!flying.is_empty() && flying.iter().any(|&i| gap[i] > 0.0));
    assert!(s["drift"]["energy_plus_work"].as_f64().unwrap() < 1e-9);
}

#[test]
fn scenario_drop_bounces_and_settles() {
    let (s, h, rows) = run_scenario("drop", Some(1.0), "completed");
    let hits: Vec<&Value> = s["events"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|e| e["kind"] == "impact")
        .collect();
    assert!(
        hits.len() > 5 && hits.last().unwrap()["persistent"] == true,
        "{hits:?}"
    );
    let mode = h.iter().position(|c| c == "mode").unwrap();
    assert_eq!(rows[0][mode], "flight");
    assert_ne!(rows.last().unwrap()[mode], "flight");
}

#[test]
fn scenario_tippe_top_jump_hops_while_turning_over() {
    let (s, _, _) = run_scenario("tippe-top-jump", Some(1.0), "completed");
    let kinds = event_kinds(&s);
    assert!(kinds.iter().filter(|k| **k == "lift_off").count() >= 5);
    assert!(kinds.contains(&"observed"), "θ passes π/2");
    // A one-surface body's events name no surface.
    let events = s["events"].as_array().unwrap();
    assert!(events.iter().any(|e| e["kind"] == "touchdown"));
    assert!(events.iter().all(|e| e.get("surface").is_none()));
}

/// The hopping top with its stem: it hops on its ball before the stem first touches, the
/// stem touches with the ball on the plane, at θ* = arccos((r2 − r1)/13 mm), and the
/// rocking between ball and stem ends where both rest on the plane, where the top stays:
/// θ = θ* and G at r1 + 7 mm·10/13 (docs/physics.md, "Contact spheres"), each surface's
/// gap zero, at t_end.
#[test]
fn scenario_tippe_top_jump_stem_hops_then_rocks_between_ball_and_stem() {
    let (s, _, _) = run_scenario("tippe-top-jump-stem", None, "completed");
    let events = s["events"].as_array().unwrap();
    let first = events
        .iter()
        .position(|e| e["kind"] == "contact_surface")
        .expect("the stem touches");
    assert_eq!(events[first]["to"], "stem");
    let hops = events[..first]
        .iter()
        .filter(|e| e["kind"] == "lift_off")
        .count();
    assert!(hops >= 5, "{hops} hops before the stem touches");
    // Once on both surfaces, the stem's contact sticks and later slides again (a hold
    // released), and the ball's sticks (docs/physics.md, "Several contacts").
    let grips: Vec<(&str, bool)> = (events.iter())
        .filter(|e| e["kind"] == "grip")
        .map(|e| {
            (
                e["surface"].as_str().unwrap(),
                e["sticks"].as_bool().unwrap(),
            )
        })
        .collect();
    assert_eq!(
        grips,
        [("stem", true), ("stem", false), ("ellipsoid", true)],
        "{grips:?}"
    );
    // Thereafter every touchdown is on the surface the contact moves to, the other one.
    let landed: Vec<&str> = events[first..]
        .iter()
        .filter(|e| e["kind"] == "touchdown")
        .map(|e| e["surface"].as_str().unwrap())
        .collect();
    assert!(landed.len() > 20, "{landed:?}");
    assert!(
        landed.windows(2).filter(|w| w[0] == w[1]).count() <= 2,
        "{landed:?}"
    );
    let theta_star = ((0.005_f64 - 0.015) / 0.013).acos();
    let f = &s["final"];
    let theta = f["theta"].as_f64().unwrap();
    let z = f["z"].as_f64().unwrap();
    assert!((theta - theta_star).abs() < 1e-9, "θ = {theta}");
    assert!(
        (z - (0.015 + 0.007 * 10.0 / 13.0)).abs() < 1e-12,
        "z_G = {z}"
    );
    for gap in ["gap_ellipsoid", "gap_stem"] {
        assert!(f[gap].as_f64().unwrap().abs() < 1e-12, "{gap}: {}", f[gap]);
    }
}

/// The stem touches down after the top passes π/2, the summary names the surfaces, the
/// top rises on its stem towards θ = π, and later rests on ball and stem at θ*
/// (docs/physics.md, "Contact spheres").
#[test]
fn scenario_tippe_top_stem_rises_on_its_stem_and_rests_on_two_contacts() {
    let (s, h, rows) = run_scenario("tippe-top-stem", None, "completed");
    let events = s["events"].as_array().unwrap();
    let first = events
        .iter()
        .find(|e| e["kind"] == "contact_surface")
        .expect("the stem touches");
    assert_eq!(
        (&first["from"], &first["to"]),
        (&json!("ellipsoid"), &json!("stem"))
    );
    let inverted = events.iter().find(|e| e["kind"] == "observed").unwrap();
    assert!(inverted["t"].as_f64().unwrap() < first["t"].as_f64().unwrap());
    // Touchdowns and impacts name the surface struck: where a touchdown moves the
    // contact, the touchdown just before the change of surface and the impact just after
    // it name the surface it moves to (a surface that rebounds while the other stays
    // pressed moves nothing; a surface leaving two contacts moves it with no touchdown).
    let mut struck = 0;
    for (k, e) in events.iter().enumerate() {
        if e["kind"] == "touchdown" || e["kind"] == "impact" {
            assert!(e["surface"] == "ellipsoid" || e["surface"] == "stem", "{e}");
        }
        if e["kind"] == "contact_surface" && k > 0 && events[k - 1]["kind"] == "touchdown" {
            let (touchdown, impact) = (&events[k - 1], &events[k + 1]);
            assert_eq!(impact["kind"], "impact", "{impact}");
            assert_eq!(touchdown["surface"], e["to"], "{touchdown}");
            assert_eq!(impact["surface"], e["to"], "{impact}");
            struck += 1;
        }
    }
    assert!(struck > 100, "{struck}");
    let (theta, mode) = (
        h.iter().position(|c| c == "theta").unwrap(),
        h.iter().position(|c| c == "mode").unwrap(),
    );
    let highest = rows
        .iter()
        .map(|r| r[theta].parse::<f64>().unwrap())
        .fold(0.0, f64::max);
    assert!(highest > 3.1, "θ rose to {highest}");
    let theta_star = ((0.005_f64 - 0.015) / 0.013).acos();
    let both: Vec<f64> = rows
        .iter()
        .filter(|r| r[mode] == "two_contacts@ellipsoid+stem")
        .map(|r| r[theta].parse().unwrap())
        .collect();
    assert!(both.len() > 100);
    assert!(both.iter().all(|t| (t - theta_star).abs() < 1e-12));

    // The per-surface columns: the surface the mode names is on the plane and carries the
    // normal force; the other is open, carries none, and its gap is its support height.
    let col = |n: &str| h.iter().position(|c| c == n).unwrap();
    let v = |r: &Vec<String>, n: &str| r[col(n)].parse::<f64>().unwrap();
    let mut seen = [0; 3];
    for r in &rows {
        let (n, slip, cx) = (v(r, "normal_force"), v(r, "slip_speed"), v(r, "contact_x"));
        match r[mode].as_str() {
            "sliding@ellipsoid" => {
                seen[0] += 1;
                assert_eq!(v(r, "normal_force_ellipsoid"), n);
                assert_eq!(
                    (v(r, "gap_ellipsoid"), v(r, "normal_force_stem")),
                    (0.0, 0.0)
                );
                assert!(v(r, "gap_stem") > 0.0);
                assert!((v(r, "slip_speed_ellipsoid") - slip).abs() <= 1e-12 * (1.0 + slip));
                assert!((v(r, "contact_x_ellipsoid") - cx).abs() <= 1e-12);
            }
            "sliding@stem" => {
                seen[1] += 1;
                assert_eq!(v(r, "normal_force_stem"), n);
                assert_eq!(
                    (v(r, "gap_stem"), v(r, "normal_force_ellipsoid")),
                    (0.0, 0.0)
                );
                assert!(v(r, "gap_ellipsoid") > 0.0);
                assert!((v(r, "slip_speed_stem") - slip).abs() <= 1e-12 * (1.0 + slip));
                assert!((v(r, "contact_x_stem") - cx).abs() <= 1e-12);
            }
            "two_contacts@ellipsoid+stem" => {
                seen[2] += 1;
                let (n1, n2) = (v(r, "normal_force_ellipsoid"), v(r, "normal_force_stem"));
                assert!(n1 > 0.0 && n2 > 0.0, "{n1} {n2}");
                assert!((n1 + n2 - n).abs() <= 1e-12 * n);
                assert_eq!((v(r, "gap_ellipsoid"), v(r, "gap_stem")), (0.0, 0.0));
            }
            other => panic!("mode {other}"),
        }
    }
    assert!(seen.iter().all(|&k| k > 100), "{seen:?}");
}

/// The top on its peg spun at 200 rad/s sleeps: its tilt stays within 0.044..0.055 rad
/// and only the peg touches.
#[test]
fn scenario_top_on_peg_sleeps() {
    let (s, h, rows) = run_scenario("top-on-peg", None, "completed");
    let theta = h.iter().position(|c| c == "theta").unwrap();
    for row in &rows {
        let t: f64 = row[theta].parse().unwrap();
        assert!((0.044..0.055).contains(&t), "θ = {t}");
    }
    assert!(event_kinds(&s).iter().all(|k| *k != "contact_surface"));
    // It stands on its peg throughout: the disc (the ellipsoid) is open and unloaded.
    let mode = column_text(&h, &rows, "mode");
    assert!(
        mode.iter().all(|m| m.ends_with("@peg")),
        "{:?}",
        mode.first()
    );
    let n = column(&h, &rows, "normal_force");
    assert_eq!(column(&h, &rows, "normal_force_peg"), n);
    assert!(
        column(&h, &rows, "normal_force_ellipsoid")
            .iter()
            .all(|v| *v == 0.0)
    );
    assert!(column(&h, &rows, "gap_ellipsoid").iter().all(|v| *v > 0.01));
    assert!(column(&h, &rows, "gap_peg").iter().all(|v| *v == 0.0));
}

/// The top on its peg spun at 60 rad/s from 0.3 rad falls onto its rim: the rim strikes
/// while the peg is pressed (one impact at both), the top slides on both until each slip
/// stops, and from then on it rolls about the line through both contacts (docs/physics.md,
/// "Several contacts"). That roll fixes the tilt where both gaps vanish, holds G's height (so
/// N_rim + N_peg = m g), turns ω horizontal (φ̇ = −ψ̇ cos θ) and, with no slip, keeps the
/// energy and the precession rate.
#[test]
fn scenario_top_falls_onto_rim_and_rolls() {
    let (s, h, rows) = run_scenario("top-falls-onto-rim", None, "completed");
    let events = s["events"].as_array().unwrap();
    let of = |kind: &'static str| events.iter().filter(move |e| e["kind"] == kind);
    let strike = of("touchdown").next().expect("the rim touches down");
    assert_eq!(strike["surface"], "ellipsoid");
    let struck: Vec<_> = of("impact")
        .map(|e| e["surface"].as_str().unwrap())
        .collect();
    assert_eq!(struck, ["ellipsoid", "peg"], "one impact at both contacts");
    let grips: Vec<_> = of("grip").collect();
    assert!(grips.iter().all(|g| g["sticks"] == true), "{grips:?}");
    let mut gripped: Vec<_> = grips
        .iter()
        .map(|g| g["surface"].as_str().unwrap())
        .collect();
    gripped.sort();
    assert_eq!(gripped, ["ellipsoid", "peg"]);
    let t_roll = grips
        .iter()
        .map(|g| g["t"].as_f64().unwrap())
        .fold(0.0, f64::max);
    let t_strike = strike["t"].as_f64().unwrap();
    assert!(t_strike < t_roll && t_roll < 2.0, "{t_strike} {t_roll}");

    let t = column(&h, &rows, "t");
    let mode = column_text(&h, &rows, "mode");
    for (ti, m) in t.iter().zip(&mode) {
        if *ti < t_strike {
            assert!(m.ends_with("@peg"), "{ti}: {m}");
        } else if *ti > t_strike {
            assert_eq!(*m, "two_contacts@ellipsoid+peg", "{ti}");
        }
    }
    let rolling: Vec<usize> = (0..t.len()).filter(|&i| t[i] > t_roll).collect();
    assert!(rolling.len() > 500);
    let [
        theta,
        phi_dot,
        psi_dot,
        energy,
        work,
        n_rim,
        n_peg,
        slip_rim,
        slip_peg,
        gap_rim,
    ] = [
        "theta",
        "phi_dot",
        "psi_dot",
        "energy",
        "work",
        "normal_force_ellipsoid",
        "normal_force_peg",
        "slip_speed_ellipsoid",
        "slip_speed_peg",
        "gap_ellipsoid",
    ]
    .map(|name| column(&h, &rows, name));
    let first = rolling[0];
    let weight = 0.1 * 9.81;
    for &i in &rolling {
        assert!((theta[i] - theta[first]).abs() < 1e-12, "θ at {}", t[i]);
        assert!(
            (phi_dot[i] / phi_dot[first] - 1.0).abs() < 1e-9,
            "φ̇ at {}",
            t[i]
        );
        let horizontal = phi_dot[i] + psi_dot[i] * theta[i].cos();
        assert!(
            horizontal.abs() < 1e-9 * phi_dot[i].abs(),
            "ω_z at {}",
            t[i]
        );
        assert!((energy[i] - energy[first]).abs() < 1e-12, "E at {}", t[i]);
        assert_eq!(work[i], work[first], "W at {}", t[i]);
        assert!((n_rim[i] + n_peg[i] - weight).abs() < 1e-9 * weight);
        assert!(n_rim[i] > 0.1 && n_peg[i] > 0.1, "both pressed at {}", t[i]);
        assert!(
            slip_rim[i] < 1e-12 && slip_peg[i] < 1e-12,
            "slip at {}",
            t[i]
        );
        assert_eq!(gap_rim[i], 0.0);
    }
    // The tilt is the one where the rim and the peg touch the plane together: the disc's
    // lowest point lies √(a² sin²θ + c² cos²θ) below its centre G, the peg's d cos θ + r.
    let (a, c, d, r) = (0.03_f64, 0.005_f64, 0.04_f64, 0.001_f64);
    let gap =
        |th: f64| (a * a * th.sin().powi(2) + c * c * th.cos().powi(2)).sqrt() - d * th.cos() - r;
    let (mut lo, mut hi) = (0.0, 1.5);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if gap(mid) < 0.0 { lo = mid } else { hi = mid }
    }
    assert!(
        (theta[first] - lo).abs() < 1e-12,
        "θ {} vs {lo}",
        theta[first]
    );
}

#[test]
fn scenario_tippe_top_disc_turns_over() {
    let (s, h, rows) = run_scenario("tippe-top-disc", Some(2.0), "completed");
    let inverted = s["events"]
        .as_array()
        .unwrap()
        .iter()
        .find(|e| e["kind"] == "observed" && e["name"] == "inverted")
        .expect("θ passes π/2");
    let t = inverted["t"].as_f64().unwrap();
    assert!((t - 0.97787).abs() < 1e-5, "{t}");
    let theta = column(&h, &rows, "theta");
    assert!(theta.last().unwrap() > &2.448);
    assert!(s["drift"]["energy_plus_work"].as_f64().unwrap() < 1e-9);
    assert!(
        s["drift"]["jellett"].is_null(),
        "the drilling torque changes J"
    );
    let modes: Vec<&str> = rows
        .iter()
        .map(|r| r[h.iter().position(|c| c == "mode").unwrap()].as_str())
        .collect();
    assert!(
        modes.iter().all(|m| *m == "sliding"),
        "a spinning disc does not stick"
    );
}

#[test]
fn scenario_air_drag_slows_the_body() {
    let (s, h, rows) = run_scenario("air-drag", Some(2.0), "completed");
    let vx = column(&h, &rows, "vx");
    assert!(vx.last().unwrap() < &0.5 && vx.last().unwrap() > &0.45);
    assert!(s["drift"]["energy_plus_work"].as_f64().unwrap() < 1e-9);
}

// ------------------------------------------------------------------ outputs

#[test]
fn summary_has_every_documented_field_and_goes_to_stdout() {
    let dir = tempfile::tempdir().unwrap();
    let file = scenarios().join("nutation.toml");
    let out = ellipsoid(
        dir.path(),
        &[
            "run",
            file.to_str().unwrap(),
            "--set",
            "output.t_end=0.1",
            "--summary",
            "-",
        ],
    );
    assert_eq!(code(&out), 0, "{}", stderr(&out));
    let s: Value = serde_json::from_slice(&out.stdout).expect("stdout is the JSON summary alone");
    for key in [
        "status",
        "message",
        "events",
        "stats",
        "wall_time_s",
        "final",
        "drift",
        "initial_invariants",
        "final_invariants",
        "warnings",
        "units",
        "scenario",
        "version",
    ] {
        assert!(s.get(key).is_some(), "summary lacks {key}");
    }
    for key in ["accepted", "rejected", "rhs_evals", "events"] {
        assert!(s["stats"][key].is_u64(), "stats.{key}");
    }
    for col in HEADER.split(',') {
        assert!(
            s["final"].get(col).is_some() && s["units"].get(col).is_some(),
            "final/units lack {col}"
        );
    }
    assert_eq!(s["units"]["theta_dot"], "rad/s");
    assert_eq!(s["version"], env!("CARGO_PKG_VERSION"));
    assert_eq!(s["overrides"][0], "output.t_end=0.1");
    // The default trajectory path is out/<stem>.csv, relative to the working directory.
    assert!(dir.path().join("out/nutation.csv").is_file());
    assert!(
        stderr(&out).contains("completed at t = 0.1 s"),
        "{}",
        stderr(&out)
    );
}

/// The run's report names each observable that crossed and when (issue 47): the times
/// of the summary's `observed` events.
#[test]
fn the_report_names_the_observables_crossings() {
    let dir = tempfile::tempdir().unwrap();
    let file = scenarios().join("tippe-top-disc.toml");
    let json = dir.path().join("s.json");
    let out = ellipsoid(
        dir.path(),
        &[
            "run",
            file.to_str().unwrap(),
            "-o",
            "t.csv",
            "--summary",
            json.to_str().unwrap(),
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let times: Vec<f64> = s["events"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|e| e["kind"] == "observed" && e["name"] == "inverted")
        .map(|e| e["t"].as_f64().unwrap())
        .collect();
    // θ passes π/2 upwards twice (it nutates about it as it turns over).
    let expected = match times.as_slice() {
        [t] => format!("ellipsoid: observed: inverted at t = {t} s"),
        [first, .., last] => format!(
            "ellipsoid: observed: inverted {} times, t = {first} s to {last} s",
            times.len()
        ),
        [] => panic!("no crossing in the summary: {}", s["events"]),
    };
    assert!(
        stderr(&out).lines().any(|l| l == expected),
        "{expected:?} not in {}",
        stderr(&out)
    );
    // A run whose observables do not cross says nothing of them.
    let short = ellipsoid(
        dir.path(),
        &[
            "run",
            file.to_str().unwrap(),
            "-o",
            "u.csv",
            "--set",
            "output.t_end=0.1",
        ],
    );
    assert!(!stderr(&short).contains("observed"), "{}", stderr(&short));
}

#[test]
fn csv_numbers_round_trip_exactly() {
    let dir = tempfile::tempdir().unwrap();
    let file = scenarios().join("paper-rolling.toml");
    let csv = dir.path().join("r.csv");
    let json = dir.path().join("r.json");
    let out = ellipsoid(
        dir.path(),
        &[
            "run",
            file.to_str().unwrap(),
            "--set",
            "output.t_end=0.05",
            "-o",
            csv.to_str().unwrap(),
            "--summary",
            json.to_str().unwrap(),
        ],
    );
    assert_eq!(code(&out), 0, "{}", stderr(&out));
    let s = read_json(&json);
    let (header, rows) = read_csv(&csv);
    for (i, name) in header.iter().enumerate() {
        if name == "mode" {
            assert_eq!(
                rows.last().unwrap()[i],
                s["final"]["mode"].as_str().unwrap()
            );
        } else {
            let v: f64 = rows.last().unwrap()[i].parse().unwrap();
            assert_eq!(
                v.to_bits(),
                s["final"][name].as_f64().unwrap().to_bits(),
                "{name}"
            );
        }
    }
}

#[test]
fn quiet_run_prints_nothing_and_no_progress_bar_off_a_terminal() {
    let dir = tempfile::tempdir().unwrap();
    let file = scenarios().join("nutation.toml");
    let out = ellipsoid(
        dir.path(),
        &[
            "run",
            file.to_str().unwrap(),
            "-q",
            "--set",
            "output.t_end=0.5",
        ],
    );
    assert_eq!(code(&out), 0);
    assert!(
        out.stderr.is_empty() && out.stdout.is_empty(),
        "{}",
        stderr(&out)
    );
}

#[test]
fn check_prints_numbers_short() {
    // `{}` spelt a subnormal out in 330 digits.
    let dir = tempfile::tempdir().unwrap();
    let file = scenarios().join("nutation.toml");
    let out = ellipsoid(
        dir.path(),
        &[
            "check",
            file.to_str().unwrap(),
            "--set",
            "effects.rolling_resistance=5e-324",
        ],
    );
    assert_eq!(code(&out), 0, "{}", stderr(&out));
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("rolling resistance c_r = 5e-324 m"), "{text}");
    assert!(text.lines().all(|l| l.len() < 200), "{text}");
}

#[test]
fn check_prints_derived_quantities_without_writing() {
    let dir = tempfile::tempdir().unwrap();
    let file = scenarios().join("nutation.toml");
    let out = ellipsoid(dir.path(), &["check", file.to_str().unwrap()]);
    assert_eq!(code(&out), 0, "{}", stderr(&out));
    let text = String::from_utf8(out.stdout).unwrap();
    for needle in [
        "principal moments     [9.3125e-6, 9.3125e-6, 1.25e-5] kg m^2",
        "CM offset G - C0      [0, 0, -0.003] m",
        "contact point C",
        "initial mode          frictionless",
        "initial N             0.4587879811700",
        "invariants checked    energy, energy_plus_work, momentum, angular_momentum_z, axial_spin",
        "output                t_end = 10 s, 10001 samples",
    ] {
        assert!(text.contains(needle), "missing {needle:?} in\n{text}");
    }
    // Every label is separated from its value, however long (the [check] drift keys).
    assert!(
        text.contains("\n[check] angular_momentum_z relative drift <= 1e-9\n"),
        "{text}"
    );
    for l in text.lines() {
        let padded = l.as_bytes().get(21) == Some(&b' ');
        let long_check_label = l
            .strip_prefix("[check] ")
            .and_then(|r| r.split_once(' '))
            .is_some_and(|(_, v)| v.starts_with("relative drift <= "));
        assert!(
            padded || long_check_label,
            "label run into its value: {l:?}"
        );
    }
    assert_eq!(
        std::fs::read_dir(dir.path()).unwrap().count(),
        0,
        "check writes nothing"
    );
    let out = ellipsoid(
        dir.path(),
        &["check", file.to_str().unwrap(), "--set", "body.mass=0"],
    );
    assert_eq!(code(&out), 2);
    assert!(
        stderr(&out).contains("--set body.mass=0: body.mass = 0: the mass must be positive"),
        "{}",
        stderr(&out)
    );
}

/// File names in `dir`, sorted.
fn listing(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

#[test]
fn an_unwritable_summary_exits_1_and_writes_nothing_new() {
    let dir = tempfile::tempdir().unwrap();
    let file = scenarios().join("nutation.toml");
    std::fs::write(dir.path().join("keep.csv"), "keep").unwrap();
    std::fs::create_dir(dir.path().join("d")).unwrap();
    let mut summaries = vec!["d"]; // a directory
    if Path::new("/proc/self").is_dir() {
        summaries.push("/proc/s.json"); // no file can be created there
    }
    for summary in summaries {
        for output in ["keep.csv", "made/new.csv"] {
            let out = ellipsoid(
                dir.path(),
                &[
                    "run",
                    file.to_str().unwrap(),
                    "-q",
                    "--set",
                    "output.t_end=0.1",
                    "-o",
                    output,
                    "--summary",
                    summary,
                ],
            );
            assert_no_panic(&out);
            let err = stderr(&out);
            assert_eq!(code(&out), 1, "-o {output} --summary {summary}: {err}");
            assert!(
                err.starts_with(&format!("error: {summary}: ")) && err.lines().count() == 1,
                "{err}"
            );
            // The OS's reason is given once, not repeated by the error chain.
            let reason = err.trim_end().rsplit(": ").next().unwrap();
            assert_eq!(err.matches(reason).count(), 1, "{err}");
            assert_eq!(
                listing(dir.path()),
                ["d", "keep.csv"],
                "-o {output} --summary {summary}: nothing new, no directory made"
            );
            assert_eq!(
                std::fs::read_to_string(dir.path().join("keep.csv")).unwrap(),
                "keep"
            );
            assert!(listing(&dir.path().join("d")).is_empty());
        }
    }
}

#[test]
fn outputs_that_are_the_same_file_as_each_other_or_the_scenario_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(scenarios().join("nutation.toml")).unwrap();
    std::fs::write(dir.path().join("v.toml"), &text).unwrap();
    std::fs::write(dir.path().join("v.csv"), &text).unwrap(); // a scenario by any other name
    std::fs::write(dir.path().join("keep.csv"), "keep").unwrap();
    let abs = dir.path().canonicalize().unwrap();
    let abs_v = abs.join("v.toml").to_string_lossy().into_owned();
    let abs_names = format!("the scenario file {abs_v} and --summary v.toml");
    let cases: [(&[&str], &str, &str); 6] = [
        (
            &["v.toml", "-o", "x.csv", "--summary", "x.csv"],
            "-o x.csv and --summary x.csv",
            "x.csv",
        ),
        (
            &["v.toml", "-o", "keep.csv", "--summary", "./keep.csv"],
            "-o keep.csv and --summary ./keep.csv",
            "keep.csv",
        ),
        (
            &["v.toml", "-o", "sub/../x.csv", "--summary", "x.csv"],
            "-o sub/../x.csv and --summary x.csv",
            "x.csv",
        ),
        (
            &["v.toml", "-o", "w.csv", "--summary", "v.toml"],
            "the scenario file v.toml and --summary v.toml",
            "v.toml",
        ),
        (
            &["v.csv", "-o", "out/../v.csv", "--summary", "s.json"],
            "the scenario file v.csv and -o out/../v.csv",
            "v.csv",
        ),
        (&[&abs_v, "--summary", "v.toml"], &abs_names, "v.toml"),
    ];
    for (extra, names, file) in cases {
        let mut args = vec!["run", "-q", "--set", "output.t_end=0.1"];
        args.extend(extra);
        let out = ellipsoid(dir.path(), &args);
        assert_no_panic(&out);
        let err = stderr(&out);
        assert_eq!(code(&out), 2, "{extra:?}: {err}");
        let expected = format!(
            "error: {names} are the same file ({})",
            abs.join(file).display()
        );
        assert!(
            err.starts_with(&expected) && err.lines().count() == 1,
            "{extra:?}: {err}\nexpected {expected}"
        );
        assert_eq!(
            listing(dir.path()),
            ["keep.csv", "v.csv", "v.toml"],
            "{extra:?}: nothing written"
        );
        assert_eq!(
            std::fs::read_to_string(dir.path().join("v.toml")).unwrap(),
            text
        );
        assert_eq!(
            std::fs::read_to_string(dir.path().join("v.csv")).unwrap(),
            text
        );
        assert_eq!(
            std::fs::read_to_string(dir.path().join("keep.csv")).unwrap(),
            "keep"
        );
    }
}

#[test]
fn an_input_error_does_not_touch_an_existing_output() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("keep.csv"), "keep").unwrap();
    let file = scenarios().join("nutation.toml");
    let out = ellipsoid(
        dir.path(),
        &[
            "run",
            file.to_str().unwrap(),
            "-o",
            "keep.csv",
            "--set",
            "body.mass=-1",
        ],
    );
    assert_eq!(code(&out), 2);
    assert_eq!(
        std::fs::read_to_string(dir.path().join("keep.csv")).unwrap(),
        "keep"
    );
    assert_eq!(
        std::fs::read_dir(dir.path()).unwrap().count(),
        1,
        "no temporary left behind"
    );
}

#[cfg(feature = "hdf5")]
#[test]
fn hdf5_round_trip_matches_the_csv() {
    let dir = tempfile::tempdir().unwrap();
    let file = scenarios().join("billiard.toml");
    let (h5, csv) = (dir.path().join("b.h5"), dir.path().join("b.csv"));
    for out in [&h5, &csv] {
        let o = ellipsoid(
            dir.path(),
            &[
                "run",
                file.to_str().unwrap(),
                "-q",
                "--set",
                "output.t_end=0.5",
                "-o",
                out.to_str().unwrap(),
            ],
        );
        assert_eq!(code(&o), 0, "{}", stderr(&o));
    }
    let traj = ellipsoid_io::hdf5::read(&h5).expect("readable HDF5");
    let (header, rows) = read_csv(&csv);
    for name in header.iter().filter(|h| *h != "mode") {
        let from_csv = column(&header, &rows, name);
        let from_h5 = traj
            .column(name)
            .unwrap_or_else(|| panic!("no dataset {name}"));
        assert_eq!(from_csv, from_h5, "{name}");
    }
    let modes: Vec<&str> = rows.iter().map(|r| r[19].as_str()).collect();
    assert_eq!(traj.modes, modes);
    assert_eq!(
        traj.columns.iter().find(|c| c.0 == "theta").unwrap().1,
        "rad"
    );
    assert_eq!(
        traj.attributes["scenario"],
        std::fs::read_to_string(&file).unwrap()
    );
    assert_eq!(traj.attributes["version"], env!("CARGO_PKG_VERSION"));
    assert_eq!(traj.attributes["status"], "completed");
    let summary: Value = serde_json::from_str(&traj.attributes["summary"]).unwrap();
    assert_eq!(summary["events"][0]["kind"], "slip_stop");
}

#[cfg(not(feature = "hdf5"))]
#[test]
fn hdf5_without_the_feature_says_how_to_get_it() {
    let dir = tempfile::tempdir().unwrap();
    let file = scenarios().join("nutation.toml");
    let out = ellipsoid(dir.path(), &["run", file.to_str().unwrap(), "-o", "x.h5"]);
    assert_eq!(code(&out), 2);
    let err = stderr(&out);
    assert!(err.starts_with("error: x.h5: this ellipsoid was built without HDF5 support") && err.contains("install the default build, which includes it: `cargo install --path crates/ellipsoid-cli`"), "{err}");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}

// ------------------------------------------------------------------ malformed input

/// A valid scenario; each malformed case edits one line.
const BASE: &str = r#"[body]
a = 0.025
c = 0.0175
mass = 0.05
com_offset = 0.003
inertia = [9.3125e-6, 9.3125e-6, 1.25e-5]

[initial]
theta = 0.1745
psi_dot = 60.0

[contact]
model = "frictionless"

[output]
t_end = 0.1
dt = 1e-2
"#;

fn edit(old: &str, new: &str) -> String {
    assert!(BASE.contains(old), "{old}");
    BASE.replacen(old, new, 1)
}

/// How a case's one line of standard error must look.
enum Expect {
    Exact(&'static str),
    Parts(&'static str, &'static str),
}

/// (name, file content or None for no file, extra arguments, expected error line).
type Case = (&'static str, Option<Vec<u8>>, Vec<&'static str>, Expect);

#[test]
fn malformed_inputs_exit_2_with_one_precise_line_and_write_nothing() {
    let cases: Vec<Case> = vec![
        (
            "missing key",
            Some(edit("mass = 0.05\n", "").into()),
            vec![],
            Expect::Exact("error: bad.toml:1:1: body.mass is missing: give the mass (kg)"),
        ),
        (
            "wrong type",
            Some(edit("mass = 0.05", "mass = \"heavy\"").into()),
            vec![],
            Expect::Exact(
                "error: bad.toml:4:1: body.mass = \"heavy\": expected a number: the mass (kg), found a string",
            ),
        ),
        (
            "negative mass",
            Some(edit("mass = 0.05", "mass = -0.05").into()),
            vec![],
            Expect::Exact(
                "error: bad.toml:4:1: body.mass = -0.05: the mass must be positive and finite (kg)",
            ),
        ),
        (
            "unknown model",
            Some(edit("\"frictionless\"", "\"roling\"").into()),
            vec![],
            Expect::Exact(
                "error: bad.toml:13:1: contact.model = \"roling\": expected one of \"frictionless\", \"sliding\", \"rolling\", \"coulomb\", \"viscous\"; did you mean \"rolling\"?",
            ),
        ),
        (
            "friction missing for sliding",
            Some(edit("\"frictionless\"", "\"sliding\"").into()),
            vec![],
            Expect::Exact(
                "error: bad.toml:12:1: contact.friction is missing: the sliding model needs μ, the Coulomb friction coefficient (e.g. friction = 0.3)",
            ),
        ),
        (
            "friction given for rolling",
            Some(edit("\"frictionless\"", "\"rolling\"\nfriction = 0.3").into()),
            vec![],
            Expect::Exact(
                "error: bad.toml:14:1: contact.friction = 0.3: the rolling model takes no friction coefficient (rolling assumes unlimited friction); remove it, or use model = \"coulomb\"",
            ),
        ),
        (
            "inertia violating the triangle inequality",
            Some(edit("[9.3125e-6, 9.3125e-6, 1.25e-5]", "[1e-6, 1e-6, 1.25e-5]").into()),
            vec![],
            Expect::Parts(
                "error: bad.toml:6:1: body.inertia = [",
                "]: principal moments must satisfy the triangle inequality (each at most the sum of the other two)",
            ),
        ),
        (
            "centre of mass outside the body",
            Some(edit("com_offset = 0.003", "com_offset = 0.02").into()),
            vec![],
            Expect::Exact(
                "error: bad.toml:5:1: body.com_offset = [0, 0, -0.02]: the centre of mass must lie inside the ellipsoid (g^T A^-2 g = 1.306122 must be < 1)",
            ),
        ),
        (
            "t_end zero",
            Some(edit("t_end = 0.1", "t_end = 0.0").into()),
            vec![],
            Expect::Exact(
                "error: bad.toml:16:1: output.t_end = 0.0: the end time must be positive and finite (s)",
            ),
        ),
        (
            "t_end negative",
            Some(edit("t_end = 0.1", "t_end = -1").into()),
            vec![],
            Expect::Exact(
                "error: bad.toml:16:1: output.t_end = -1: the end time must be positive and finite (s)",
            ),
        ),
        (
            "unknown key",
            Some(edit("theta = 0.1745", "thetta = 0.1745").into()),
            vec![],
            Expect::Exact(
                "error: bad.toml:9:1: initial.thetta = 0.1745: unknown key in [initial]; did you mean `theta`?",
            ),
        ),
        (
            "unknown table",
            Some(edit("[contact]", "[contakt]").into()),
            vec![],
            Expect::Exact(
                "error: bad.toml:12:2: contakt: unknown table at the top level; did you mean `contact`?",
            ),
        ),
        (
            "both degree twins",
            Some(edit("theta = 0.1745", "theta = 0.1745\ntheta_deg = 10").into()),
            vec![],
            Expect::Exact(
                "error: bad.toml:10:1: initial.theta_deg = 10: give either initial.theta or initial.theta_deg, not both (radians or degrees)",
            ),
        ),
        (
            "velocity for rolling",
            Some(
                edit("\"frictionless\"", "\"rolling\"")
                    .replace("psi_dot = 60.0", "psi_dot = 60.0\nvelocity = [1.0, 0.0]")
                    .into_bytes(),
            ),
            vec![],
            Expect::Exact(
                "error: bad.toml:11:1: initial.velocity = [1.0, 0.0]: not allowed for the rolling model on the plane, where the velocity of G is implied by ω (v_G = −ω × r); remove it (or start in flight, initial.height > 0)",
            ),
        ),
        (
            "body leaves the plane at t = 0 (found by simulate)",
            Some(
                edit(
                    "theta = 0.1745\npsi_dot = 60.0",
                    // 300 rad/s: fast enough to lift the body, below the plausibility
                    // warning's spin (which would add a line).
                    "theta = 1.2\nphi_dot = 300.0",
                )
                .replace(
                    "model = \"frictionless\"",
                    "model = \"frictionless\"\non_lift_off = \"stop\"",
                )
                .into(),
            ),
            vec![],
            Expect::Parts(
                "error: bad.toml:8:2: initial normal force N = -",
                "the plane must push on the body at t = 0 (N > 0) when contact.on_lift_off = \"stop\"; with these angles and rates the body would leave the plane at once",
            ),
        ),
        (
            "TOML syntax",
            Some(edit("mass = 0.05", "mass = 0.05.0").into()),
            vec![],
            Expect::Parts("error: bad.toml:4:12: TOML syntax error: ", ""),
        ),
        (
            "empty file",
            Some(Vec::new()),
            vec![],
            Expect::Exact(
                "error: bad.toml:1:1: body is missing: a scenario needs a [body] table (semi-axes a and c, mass, inertia)\n\
                 error: bad.toml:1:1: contact is missing: a scenario needs a [contact] table with model = \"frictionless\", \"sliding\", \"rolling\", \"coulomb\", \"viscous\"\n\
                 error: bad.toml:1:1: output is missing: a scenario needs an [output] table with t_end and dt (or times)",
            ),
        ),
        (
            "not UTF-8",
            Some(b"[body]\na = 0.025 # \xb5m\n".to_vec()),
            vec![],
            Expect::Exact(
                "error: bad.toml:2:13: the file is not UTF-8 text, as TOML must be: byte 0xb5 at offset 19 does not begin a UTF-8 character (save the file as UTF-8)",
            ),
        ),
        (
            "two typos, reported in file order",
            Some(
                edit("psi_dot = 60.0", "psi_dott = 60.0")
                    .replace("model = \"frictionless\"", "modl = \"frictionless\"")
                    .into_bytes(),
            ),
            vec![],
            Expect::Exact(
                "error: bad.toml:10:1: initial.psi_dott = 60.0: unknown key in [initial]; did you mean `psi_dot`?\n\
                 error: bad.toml:13:1: contact.modl = \"frictionless\": unknown key in [contact]; did you mean `model`?",
            ),
        ),
        (
            "unreadable file",
            None,
            vec![],
            Expect::Exact(
                "error: bad.toml: cannot read the scenario file: No such file or directory (os error 2)",
            ),
        ),
        (
            "override without =",
            Some(BASE.into()),
            vec!["--set", "output.t_end"],
            Expect::Exact(
                "error: bad.toml: --set output.t_end: an override must have the form key=value, e.g. --set output.t_end=1.0",
            ),
        ),
        (
            "override breaking a rule",
            Some(BASE.into()),
            vec!["--set", "body.mass=-1"],
            Expect::Exact(
                "error: bad.toml: --set body.mass=-1: body.mass = -1: the mass must be positive and finite (kg)",
            ),
        ),
        (
            "unknown output format",
            Some(BASE.into()),
            vec!["-o", "out/x.txt"],
            Expect::Exact("error: out/x.txt: unknown output format \"txt\"; use .csv or .h5"),
        ),
    ];
    let mut failures = Vec::new();
    for (name, content, extra, expect) in cases {
        let dir = tempfile::tempdir().unwrap();
        if let Some(c) = &content {
            std::fs::write(dir.path().join("bad.toml"), c).unwrap();
        }
        let mut args = vec!["run", "bad.toml", "--summary", "summary.json"];
        args.extend(extra);
        let out = ellipsoid(dir.path(), &args);
        assert_no_panic(&out);
        let err = stderr(&out);
        let line = err.trim_end_matches('\n');
        let ok_line = match expect {
            Expect::Exact(e) => line == e,
            Expect::Parts(start, end) => line.starts_with(start) && line.ends_with(end),
        };
        let left: Vec<String> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| n != "bad.toml")
            .collect();
        let lines_expected = match expect {
            Expect::Exact(e) => e.lines().count(),
            Expect::Parts(..) => 1,
        };
        if code(&out) != 2
            || !ok_line
            || line.lines().count() != lines_expected
            || !left.is_empty()
            || !out.stdout.is_empty()
        {
            failures.push(format!(
                "{name}: exit {}, left {left:?}, stderr:\n{err}",
                code(&out)
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn usage_errors_exit_2_without_panic() {
    let dir = tempfile::tempdir().unwrap();
    for args in [
        vec![],
        vec!["run"],
        vec!["frobnicate"],
        vec!["run", "x.toml", "--bogus"],
    ] {
        let out = ellipsoid(dir.path(), &args);
        assert_no_panic(&out);
        assert_eq!(code(&out), 2, "{args:?}");
    }
}

/// Issue #17: a DOPRI5 stick–slip scene raised 34 "looks stiff" warnings; the summary
/// (JSON `warnings` and standard error) says them once, with their count and span.
#[test]
fn repeated_stiffness_warnings_are_said_once_with_their_count() {
    use ellipsoid_core::simulate::{Mode, RunWarning};
    let warnings: Vec<RunWarning> = (0..34)
        .map(|k| RunWarning::Stiff {
            t: k as f64 / 100.0,
            mode: Mode::Sliding,
        })
        .collect();
    let said = ellipsoid_io::summary::warning_messages(&warnings);
    assert_eq!(said.len(), 1, "{said:?}");
    assert!(
        said[0].contains("34 times") && said[0].contains("from t = 0 s to t = 0.33 s"),
        "{said:?}"
    );
}

/// `--sections` writes the scenario's Poincaré sections as one table: the comment line
/// with each column's SI unit, the header `section,` + the trajectory's, rows naming
/// their section; each point on its section (θ̇ = 0 rising: the bottom of each nutation
/// swing, θ̇ to 1e-10 of its scale, θ the same least tilt at each) with the energy of the
/// run. Without `[[section]]`,
/// `--sections` is refused and nothing is written.
#[test]
fn run_writes_the_poincare_sections_table() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scenarios().join("nutation.toml");
    let scene = scene.to_str().unwrap();
    let set = "section=[{ name = \"bottom\", column = \"theta_dot\", crosses = 0, direction = \"up\" }, { name = \"half\", column = \"theta\", crosses = 0.17 }]";
    let o = ellipsoid(
        dir.path(),
        &[
            "run",
            scene,
            "-q",
            "-o",
            "t.csv",
            "--set",
            set,
            "--set",
            "output.t_end=3",
            "--sections",
            "out/s.csv",
        ],
    );
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let path = dir.path().join("out/s.csv");
    let text = std::fs::read_to_string(&path).unwrap();
    let comment = text.lines().next().unwrap();
    let head: Value = serde_json::from_str(comment.strip_prefix("# ellipsoid ").unwrap()).unwrap();
    assert_eq!(head["units"]["t"], "s");
    assert_eq!(head["units"]["theta_dot"], "rad/s");
    assert_eq!(head["units"]["energy"], "J");
    let (header, rows) = read_csv(&path);
    assert_eq!(header.join(","), format!("section,{HEADER}"));
    let names = column_text(&header, &rows, "section");
    let bottom: Vec<usize> = (0..rows.len()).filter(|&i| names[i] == "bottom").collect();
    assert!(bottom.len() >= 5, "{} points", bottom.len());
    assert!(names.iter().all(|n| *n == "bottom" || *n == "half"));
    assert!(names.contains(&"half"));
    let (traj_header, traj) = read_csv(&dir.path().join("t.csv"));
    let rates = column(&traj_header, &traj, "theta_dot");
    let scale = rates.iter().fold(0.0_f64, |m, r| m.max(r.abs()));
    let e0 = column(&traj_header, &traj, "energy")[0];
    let theta_dot = column(&header, &rows, "theta_dot");
    let energy = column(&header, &rows, "energy");
    let theta = column(&header, &rows, "theta");
    let least = theta[bottom[0]];
    assert!(
        least < 0.16,
        "the bottom of the swing is its least tilt: {least}"
    );
    for &i in &bottom {
        assert!(theta_dot[i].abs() < 1e-10 * scale, "θ̇ = {}", theta_dot[i]);
        assert!((energy[i] - e0).abs() < 1e-9 * e0.abs());
        assert!(
            (theta[i] - least).abs() < 1e-8,
            "θ = {} vs {least}",
            theta[i]
        );
    }

    let o = ellipsoid(
        dir.path(),
        &["run", scene, "-q", "-o", "u.csv", "--sections", "none.csv"],
    );
    assert_ne!(code(&o), 0);
    assert!(
        stderr(&o).contains("--sections none.csv: the scenario has no [[section]]"),
        "{}",
        stderr(&o)
    );
    assert_no_panic(&o);
    assert!(!dir.path().join("none.csv").exists());
    assert!(!dir.path().join("u.csv").exists());
}

/// The rolling top on its peg (tests/data/spheres/top-on-peg-rolling.toml) thrown down at
/// θ̇0 = 5 rad/s from θ0 = 0.6: at t ≈ 0.974 s the peg touches down while the rim rolls, and
/// no set of the two contacts is consistent under unbounded friction — the run stops
/// `several_contacts` (exit 3), naming both surfaces, and its message names the remedy.
/// The remedy holds: the same top under Coulomb friction, μ = 0.3 and 0.8, runs to t_end
/// with E + W kept to 1e-10 of E(0) (from μ ≈ 1 on, sliding on the peg at the start is
/// itself inconsistent, Painlevé's paradox, and the scene is refused).
#[test]
fn several_contacts_under_rolling_names_coulomb_friction_which_resolves_it() {
    let dir = tempfile::tempdir().unwrap();
    let file = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/data/spheres/top-on-peg-rolling.toml");
    let json = dir.path().join("summary.json");
    let run = |set: &[&str]| {
        let mut args = vec![
            "run",
            file.to_str().unwrap(),
            "-o",
            "out.csv",
            "--summary",
            json.to_str().unwrap(),
            "-q",
            "--set",
            "initial.theta=0.6",
            "--set",
            "initial.theta_dot=5",
        ];
        for s in set {
            args.extend(["--set", s]);
        }
        let out = ellipsoid(dir.path(), &args);
        assert_no_panic(&out);
        (code(&out), read_json(&json))
    };
    let (exit, summary) = run(&[]);
    let message = summary["message"].as_str().unwrap();
    assert_eq!(
        (exit, summary["status"].as_str()),
        (3, Some("several_contacts")),
        "{message}"
    );
    assert!(
        message.contains("the peg") && message.contains("the ellipsoid"),
        "{message}"
    );
    assert!(
        message.contains("rolling model") && message.contains("model = \"coulomb\""),
        "{message}"
    );
    for mu in ["0.3", "0.8"] {
        let (exit, summary) = run(&[
            "contact.model=\"coulomb\"",
            &format!("contact.friction={mu}"),
        ]);
        assert_eq!(exit, 0, "μ = {mu}: {}", summary["message"]);
        let balance = summary["drift"]["energy_plus_work"].as_f64().unwrap();
        assert!(balance.abs() < 1e-10, "μ = {mu}: E + W {balance:e}");
    }
}

/// `ellipsoid power-law`: the thin disc under rolling friction alone approaches its flat
/// landing as α ∝ (t0 − t)^{2/3} and Ω ∝ (t0 − t)^{−1/3} (docs/physics.md, "Dissipation of
/// a rolling disc"), t0 the located landing or fitted in a bracket; bad requests exit 2
/// with one line naming the option.
#[test]
fn power_law_measures_the_disc_approach_and_refuses_bad_requests() {
    let dir = tempfile::tempdir().unwrap();
    let (g, a, m, alpha0) = (9.81f64, 0.0375f64, 0.445, 0.05f64);
    let omega = (4.0 * g / (a * alpha0.sin())).sqrt();
    let toml = format!(
        "[body]\na = {a}\nc = {}\nmass = {m}\ninertia = [{i_t}, {i_t}, {i_a}]\nellipsoid_contact = false\n\
         [[body.rim]]\nname = \"edge\"\ncenter = [0.0, 0.0, 0.0]\nradius = {a}\nedge = 0.0\n\
         [initial]\ntheta = {alpha0}\nphi_dot = {omega}\npsi_dot = {}\n[contact]\nmodel = \"rolling\"\n\
         [effects]\ngravity = {g}\nrolling_friction = 1e-4\n[output]\nt_end = 4.0\ndt = 1e-3\n",
        a / 10.0,
        -omega * alpha0.cos(),
        i_t = m * a * a / 4.0,
        i_a = m * a * a / 2.0,
    );
    std::fs::write(dir.path().join("disc.toml"), toml).unwrap();
    let fit = |args: &[&str]| {
        let mut all = vec!["power-law", "disc.toml", "--window", "0.03,3"];
        all.extend(args);
        let out = ellipsoid(dir.path(), &all);
        assert_no_panic(&out);
        assert_eq!(code(&out), 0, "{}", stderr(&out));
        serde_json::from_slice::<Value>(&out.stdout).expect("JSON on stdout")
    };
    let t0 = alpha0.powf(1.5) / (2.0 * 1e-4 * (g / a).sqrt());
    let tilt = fit(&["--column", "theta"]);
    assert_eq!(tilt["t0_from"], "landing");
    assert!(
        (tilt["t0"].as_f64().unwrap() / t0 - 1.0).abs() < 0.01,
        "{tilt}"
    );
    assert!(
        (tilt["exponent"].as_f64().unwrap() * 1.5 - 1.0).abs() < 0.02,
        "{tilt}"
    );
    let rate = fit(&[
        "--column",
        "phi_dot",
        "--t0",
        &format!("{},{}", 0.95 * t0, 1.05 * t0),
    ]);
    assert_eq!(rate["t0_from"], "fitted");
    assert!(
        (rate["exponent"].as_f64().unwrap() * -3.0 - 1.0).abs() < 0.03,
        "{rate}"
    );
    for (args, says) in [
        (
            vec!["--column", "tilt", "--window", "0.03,3"],
            "--column tilt: not a numeric output column",
        ),
        (
            vec!["--column", "theta", "--window", "3,0.03"],
            "0 < lo < hi",
        ),
        (
            vec!["--column", "theta", "--window", "0.03"],
            "--window 0.03: expected two numbers",
        ),
        (
            vec!["--column", "theta", "--window", "0.03,3", "--t0", "soon"],
            "--t0 soon: expected two numbers",
        ),
        (
            vec!["--column", "theta", "--window", "10,20", "--t0", "3.0"],
            "at least 3",
        ),
    ] {
        let mut all = vec!["power-law", "disc.toml"];
        all.extend(args);
        let out = ellipsoid(dir.path(), &all);
        assert_no_panic(&out);
        assert_eq!(code(&out), 2, "{all:?}");
        let err = stderr(&out);
        assert!(
            err.lines().count() == 1 && err.contains(says),
            "{all:?}: {err}"
        );
    }
}
