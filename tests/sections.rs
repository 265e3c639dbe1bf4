//! Poincaré sections (`[[section]]`): the full state at each crossing, located on the
//! dense output. Each point lies on its section; a steady precession (periodic) gives one
//! repeating point; the direction filters the crossings; `max_points` bounds them and
//! ends the run (`section_full`); bad keys are refused at their line. Also: the φ and ψ
//! of an observed event are those of the dense output at its time (unwrapped against the
//! row before it, not a later one).

use std::f64::consts::TAU;
use std::ops::ControlFlow;

use ellipsoid_core::columns::{self, Layout};
use ellipsoid_core::integrate::Direction;
use ellipsoid_core::scenario::{self, Scenario};
use ellipsoid_core::simulate::{self, EventKind, Observe, Outcome, Sample, Section, Status};
use ellipsoid_core::steady::{self, Family, Phase};

/// The paper's oblate body, frictionless, tilted 10° and spinning at 60 rad/s: it nutates
/// (θ periodic) and precesses (φ grows).
const NUTATION: &str = r#"
[body]
a = 0.025
c = 0.0175
mass = 0.05
com_offset = 0.003
inertia = [9.3125e-6, 9.3125e-6, 1.25e-5]

[initial]
theta_deg = 10.0
psi_dot = 60.0

[contact]
model = "frictionless"

[solver]
rtol = 1e-11
atol = 1e-13

[output]
t_end = 6.0
dt = 1e-2
"#;

fn parse(text: &str) -> Scenario {
    scenario::parse(text, "x.toml", &[] as &[&str]).unwrap_or_else(|e| panic!("{e}"))
}

fn run(scene: &simulate::Scene) -> (Outcome, Vec<Sample>) {
    let mut rows = Vec::new();
    let out = simulate::simulate(scene, &mut |s| {
        rows.push(*s);
        ControlFlow::Continue(())
    })
    .unwrap();
    (out, rows)
}

/// `NUTATION` with `[[section]]` entries appended.
fn with_sections(sections: &str) -> Scenario {
    parse(&format!("{NUTATION}\n{sections}"))
}

/// The middle of θ's swing in `NUTATION` [rad], from a run without sections.
fn mid_theta() -> f64 {
    let (_, rows) = run(&parse(NUTATION).scene);
    let (lo, hi) = rows.iter().fold((f64::INFINITY, 0.0_f64), |(lo, hi), r| {
        (lo.min(r.angles.theta), hi.max(r.angles.theta))
    });
    assert!(hi - lo > 0.01, "θ swings from {lo} to {hi}");
    0.5 * (lo + hi)
}

fn value(s: &Sample, column: &str) -> f64 {
    columns::values(s)[columns::index(column).unwrap()]
}

/// Each point of a section on ω_world,x = 0.3 rad/s (a column the state does not hold:
/// it is R ω_b) lies on the section to 1e-10 of the column's scale, and θ through the middle
/// of its swing (a state angle) to 1e-10 rad; the points are in time order and each is the state at
/// its time (the energy, conserved, to 1e-9 relative).
#[test]
fn val_section_points_lie_on_the_section() {
    let mid = mid_theta();
    let s = with_sections(&format!(
        "[[section]]\nname = \"w\"\ncolumn = \"omega_world_x\"\ncrosses = 0.3\n\n\
         [[section]]\nname = \"tilt\"\ncolumn = \"theta\"\ncrosses = {mid:e}\n",
    ));
    let (out, rows) = run(&s.scene);
    assert_eq!(out.status, Status::Completed);
    assert_eq!(out.sections.len(), 2);
    let scale = rows
        .iter()
        .map(|r| value(r, "omega_world_x").abs())
        .fold(0.0, f64::max);
    for (k, (column, crosses, tol)) in
        [("omega_world_x", 0.3, 1e-10 * scale), ("theta", mid, 1e-10)]
            .into_iter()
            .enumerate()
    {
        let points = &out.sections[k];
        assert!(points.len() > 10, "{column}: {} points", points.len());
        for p in points {
            let off = (value(p, column) - crosses).abs();
            assert!(off < tol, "{column} = {} at t = {}", value(p, column), p.t);
            let e0 = rows[0].energy;
            assert!(
                (p.energy - e0).abs() < 1e-9 * e0.abs(),
                "energy {}",
                p.energy
            );
        }
        assert!(points.windows(2).all(|w| w[0].t < w[1].t));
    }
}

/// A frictionless steady precession (`steady`'s precession family: G fixed, θ, φ̇ and ψ̇
/// constant) is periodic in everything but φ and ψ: its section on ω_world,x = 0 (up),
/// crossed once per turn of the axis about the vertical, is one point repeated, θ, the
/// rates and G's position to 1e-10 (relative for the rates), φ to 1e-9 modulo 2π, and
/// the crossings one precession period 2π/φ̇ apart to 1e-9 relative.
#[test]
fn val_a_steady_precession_gives_one_repeating_point() {
    let s = parse(&NUTATION.replace(
        "theta_deg = 10.0\npsi_dot = 60.0",
        "theta = 0.3\nphi_dot = 2.0",
    ));
    let an = steady::analyse(&s.scene, Family::Precession).unwrap();
    let mut scene = steady::started_at(&s.scene, &an.motion.at, &Phase::zeros());
    scene.t_end = 20.0;
    scene.sample_times = (0..=2000).map(|i| i as f64 * 1e-2).collect();
    let layout = Layout::of(&scene.body);
    scene.sections.push(Section {
        crossing: Observe {
            name: "w".into(),
            column: layout.index("omega_world_x").unwrap(),
            crosses: 0.0,
            direction: Direction::Rising,
            terminal: false,
        },
        max_points: 1000,
    });
    let (out, _) = run(&scene);
    assert_eq!(out.status, Status::Completed);
    let points = &out.sections[0];
    assert!(points.len() >= 5, "{} points", points.len());
    let first = &points[0];
    let rate = first.angles.phi_dot;
    assert!((rate - 2.0).abs() < 1e-8, "φ̇ = {rate}");
    let spin = first.omega.norm();
    for p in &points[1..] {
        let (a, b) = (&p.angles, &first.angles);
        assert!(
            (a.theta - b.theta).abs() < 1e-10,
            "θ {} vs {}",
            a.theta,
            b.theta
        );
        for (x, y) in [
            (a.theta_dot, b.theta_dot),
            (a.phi_dot, b.phi_dot),
            (a.psi_dot, b.psi_dot),
            (p.omega_world.y, first.omega_world.y),
            (p.omega_world.z, first.omega_world.z),
        ] {
            assert!((x - y).abs() < 1e-10 * spin, "{x} vs {y} at t = {}", p.t);
        }
        assert!((p.position - first.position).norm() < 1e-10 * 0.025);
        let turns = (a.phi - b.phi) / TAU;
        assert!(
            (turns - turns.round()).abs() * TAU < 1e-9,
            "φ {} vs {}",
            a.phi,
            b.phi
        );
    }
    let period = TAU / rate;
    for w in points.windows(2) {
        let dt = w[1].t - w[0].t;
        assert!((dt - period).abs() < 1e-9 * period, "{dt} vs {period}");
    }
}

/// `direction` filters the crossings: on θ through the middle of its swing, "up" and
/// "down" alternate, together they are "either" (the same times, to the last bit), and
/// θ̇ is positive at every up point and negative at every down one.
#[test]
fn section_direction_filters_the_crossings() {
    let mid = mid_theta();
    let entry = |name: &str, dir: &str| {
        format!(
            "[[section]]\nname = \"{name}\"\ncolumn = \"theta\"\ncrosses = {mid:e}\ndirection = \"{dir}\"\n"
        )
    };
    let s = with_sections(&[entry("u", "up"), entry("d", "down"), entry("e", "either")].concat());
    let (out, _) = run(&s.scene);
    let [up, down, either] = [0, 1, 2].map(|k| &out.sections[k]);
    assert!(up.len() > 5 && down.len() > 5);
    assert!(up.len().abs_diff(down.len()) <= 1);
    assert!(up.iter().all(|p| p.angles.theta_dot > 0.0));
    assert!(down.iter().all(|p| p.angles.theta_dot < 0.0));
    let mut merged: Vec<f64> = up.iter().chain(down.iter()).map(|p| p.t).collect();
    merged.sort_by(f64::total_cmp);
    let all: Vec<f64> = either.iter().map(|p| p.t).collect();
    assert_eq!(merged, all);
    for w in all.windows(2) {
        let a = up.iter().any(|p| p.t == w[0]);
        let b = up.iter().any(|p| p.t == w[1]);
        assert_ne!(a, b, "up and down alternate at {} and {}", w[0], w[1]);
    }
}

/// `max_points` bounds a section: the run ends at its last point with status
/// `section_full`, the final row is that point, and the points are the unbounded run's
/// first ones (bit for bit).
#[test]
fn a_full_section_ends_the_run() {
    let mid = mid_theta();
    let entry = |max: &str| {
        format!("[[section]]\nname = \"tilt\"\ncolumn = \"theta\"\ncrosses = {mid:e}\n{max}")
    };
    let (free, _) = run(&with_sections(&entry("")).scene);
    let (full, rows) = run(&with_sections(&entry("max_points = 4\n")).scene);
    assert_eq!(full.status, Status::SectionFull { index: 0 });
    assert_eq!(full.status.name(), "section_full");
    assert!(full.status.finished());
    assert_eq!(full.sections[0].len(), 4);
    assert_eq!(full.sections[0][..], free.sections[0][..4]);
    let last = &full.sections[0][3];
    assert_eq!(full.final_sample.t, last.t);
    assert_eq!(rows.last().unwrap().t, last.t);
    assert!(last.t < 6.0);
}

/// Bad `[[section]]` keys are refused at their line, naming the key and the rule.
#[test]
fn bad_section_keys_are_refused_at_their_line() {
    let cases = [
        ("column = \"theta\"\ncrosses = 0.1\n", "name"),
        (
            "name = \"s\"\ncolumn = \"thetaa\"\ncrosses = 0.1\n",
            "column",
        ),
        ("name = \"s\"\ncolumn = \"theta\"\n", "crosses"),
        (
            "name = \"s\"\ncolumn = \"theta\"\ncrosses = 0.1\nmax_points = 0\n",
            "max_points",
        ),
        (
            "name = \"s\"\ncolumn = \"theta\"\ncrosses = 0.1\nmax_points = 2000000\n",
            "max_points",
        ),
        (
            "name = \"s\"\ncolumn = \"theta\"\ncrosses = 0.1\nmax_points = 2.5\n",
            "max_points",
        ),
        (
            "name = \"s\"\ncolumn = \"theta\"\ncrosses = 0.1\ndirection = \"sideways\"\n",
            "direction",
        ),
        (
            "name = \"s\"\ncolumn = \"theta\"\ncrosses = 0.1\nterminal = true\n",
            "terminal",
        ),
    ];
    let header = NUTATION.lines().count() + 2; // the [[section]] line
    for (body, key) in cases {
        let text = format!("{NUTATION}\n[[section]]\n{body}");
        let e = scenario::parse(&text, "x.toml", &[] as &[&str])
            .expect_err(body)
            .to_string();
        assert!(e.starts_with("x.toml:"), "{e}");
        let line: usize = e.split(':').nth(1).unwrap().parse().unwrap();
        assert!(
            line >= header,
            "{e} (line {line}, the table starts at {header})"
        );
        assert!(e.contains(key), "{e} does not name {key}");
    }
    let twice = format!(
        "{NUTATION}\n[[section]]\nname = \"s\"\ncolumn = \"theta\"\ncrosses = 0.1\n\n\
         [[section]]\nname = \"s\"\ncolumn = \"phi\"\ncrosses = 0.1\n"
    );
    let e = scenario::parse(&twice, "x.toml", &[] as &[&str])
        .expect_err("a repeated name")
        .to_string();
    assert!(e.contains("unique"), "{e}");
}

/// The φ and ψ of an observed event are the dense output's at its time: unwrapped
/// against the row before the event, they differ from that row's by less than the
/// angles move in one output interval (the precession φ̇ ≈ 1 rad/s here: < 0.1 rad at
/// dt = 0.01 s; a later row would put them whole turns away).
#[test]
fn observed_angles_are_unwrapped_against_the_row_before_the_event() {
    let mid = mid_theta();
    let s = parse(&format!(
        "{NUTATION}\n[[observe]]\nname = \"tilt\"\ncolumn = \"theta\"\ncrosses = {mid:e}\n"
    ));
    let (out, rows) = run(&s.scene);
    let events: Vec<&Sample> = out
        .events
        .iter()
        .filter_map(|e| match &e.kind {
            EventKind::Observed { sample, .. } => Some(&**sample),
            _ => None,
        })
        .collect();
    assert!(events.len() > 10);
    assert!(
        rows.last().unwrap().angles.psi > 100.0,
        "ψ turns many times"
    );
    for e in events {
        let before = rows.iter().rev().find(|r| r.t <= e.t).unwrap();
        let dt = e.t - before.t;
        assert!(dt <= 1e-2 + 1e-12);
        for (a, b, rate) in [
            (e.angles.phi, before.angles.phi, e.angles.phi_dot),
            (e.angles.psi, before.angles.psi, e.angles.psi_dot),
        ] {
            assert!(
                (a - b).abs() <= 2.0 * rate.abs() * 1e-2 + 1e-9,
                "at t = {}: {a} vs the row at {}: {b}",
                e.t,
                before.t
            );
        }
    }
}

/// The sections of a scene keep at most 10⁶ points together (issue 48: sixteen sections of
/// 10⁶ points each were accepted, some 13 GB of memory from a 1 kB file): the sum of their
/// `max_points` is bounded, a section without `max_points` keeps an equal share, and a
/// scenario asking for more is refused at the entry that passes the bound, with its file,
/// line and column, the key, the value and the rule naming the sum.
#[test]
fn the_sections_together_keep_at_most_a_million_points() {
    let entry = |k: usize, max: &str| {
        format!("[[section]]\nname = \"s{k}\"\ncolumn = \"theta\"\ncrosses = 0.1\n{max}\n")
    };
    let parse = |entries: &str| {
        scenario::parse(&format!("{NUTATION}\n{entries}"), "x.toml", &[] as &[&str])
            .map_err(|e| e.to_string())
    };
    // Sixteen sections of 10⁶ points: refused at the second's max_points.
    let sixteen: String = (0..16).map(|k| entry(k, "max_points = 1000000")).collect();
    let e = parse(&sixteen).expect_err("16 × 10⁶ points").to_string();
    let text = format!("{NUTATION}\n{sixteen}");
    let at = text.match_indices("max_points").nth(1).unwrap().0;
    let second = text[..at].matches('\n').count() + 1; // the second entry's max_points line
    assert!(
        e.starts_with(&format!("x.toml:{second}:")),
        "{e} (expected line {second})"
    );
    assert!(e.contains("section[1].max_points = 1000000"), "{e}");
    assert!(
        e.contains("together keep at most 1000000 points") && e.contains("sum to 2000000"),
        "{e}"
    );
    // Without max_points, each of n sections keeps 10⁶ / n.
    let defaults: String = (0..3).map(|k| entry(k, "")).collect();
    let s = parse(&defaults).unwrap_or_else(|e| panic!("{e}"));
    assert!(s.scene.sections.iter().all(|s| s.max_points == 333_333));
    let one = parse(&entry(0, "")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(one.scene.sections[0].max_points, 1_000_000);
    // Explicit values summing to 10⁶ are allowed; a default share that passes it is
    // refused at its entry, naming the default.
    let exact = format!(
        "{}{}",
        entry(0, "max_points = 400000"),
        entry(1, "max_points = 600000")
    );
    assert!(parse(&exact).is_ok());
    let over = format!("{}{}", entry(0, "max_points = 900000"), entry(1, ""));
    let e = parse(&over).expect_err("900000 + 500000").to_string();
    assert!(
        e.contains("section[1].max_points = 500000 (the default)"),
        "{e}"
    );
    assert!(e.contains("sum to 1400000"), "{e}");
    // The scene's own validation holds the bound too (a scene built in code).
    let mut scene = one.scene.clone();
    scene.sections.push(Section {
        max_points: 1,
        ..scene.sections[0].clone()
    });
    scene.sections[1].crossing.name = "other".into();
    let e = scene.validate().expect_err("1000001 points").to_string();
    assert!(
        e.contains("section.max_points") && e.contains("together"),
        "{e}"
    );
}
