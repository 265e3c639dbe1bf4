use std::path::Path;
use std::sync::Arc;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

use super::plan::Values;
use super::spec::{self, Naming};
use super::*;

const TOP: &str = include_str!("../../../../scenarios/tippe-top.toml");

fn plan(doc: &str) -> Result<Plan, String> {
    let base = Base {
        text: TOP.to_owned(),
        source: "tippe-top.toml".into(),
        overrides: vec!["output.t_end=0.05".into(), "output.dt=0.01".into()],
    };
    spec::parse(doc, "s.toml", None, Some(base), Naming::File).map_err(|e| e.to_string())
}

fn study(doc: &str) -> Result<Study, String> {
    Study::new(plan(doc)?).map_err(|e| e.to_string())
}

fn run_all(s: &Study) -> Vec<Vec<Cell>> {
    let r = execute(s, None, 2, &Arc::new(AtomicBool::new(false)), |_| {}).unwrap();
    s.rows(r)
}

/// The journal of study `s` at `j`, as `execute` opens it.
fn open_journal(s: &Study, j: &Path) -> Journal {
    let whom = journal::For {
        outcomes: &s.outcome_fingerprint(),
        plan: &s.plan_fingerprint(),
        cells: s.outcome_columns().len(),
        points: s.len(),
    };
    Journal::open(j, whom, &AtomicBool::new(false)).unwrap()
}

fn header(s: &Study) -> Vec<String> {
    s.columns.iter().map(Column::header).collect()
}

#[test]
fn a_grid_is_row_major_with_the_last_axis_fastest() {
    let s = study(
        "[[axis]]\nkey = \"contact.friction\"\nvalues = [0.2, 0.3]\n[[axis]]\nkey = \"initial.phi_dot\"\nlinspace = [100, 200, 3]\n",
    )
    .unwrap();
    assert_eq!(s.len(), 6);
    let rows = run_all(&s);
    let h = header(&s);
    assert_eq!(
        &h[..3],
        ["point", "contact.friction [1]", "initial.phi_dot [rad/s]"]
    );
    let pairs: Vec<(f64, f64)> = rows
        .iter()
        .map(|r| match (&r[1], &r[2]) {
            (Cell::Float(a), Cell::Float(b)) => (*a, *b),
            _ => panic!(),
        })
        .collect();
    assert_eq!(
        pairs,
        vec![
            (0.2, 100.0),
            (0.2, 150.0),
            (0.2, 200.0),
            (0.3, 100.0),
            (0.3, 150.0),
            (0.3, 200.0)
        ]
    );
    assert!(h.contains(&"drift.jellett [1]".to_owned()) && h.contains(&"wall_time [s]".to_owned()));
    let status = h.iter().position(|c| c == "status").unwrap();
    assert!(
        rows.iter()
            .all(|r| r[status] == Cell::Text("completed".into()))
    );
}

#[test]
fn the_same_scenario_has_the_same_key_and_a_changed_one_another() {
    let s = study("[[axis]]\nkey = \"contact.friction\"\nvalues = [0.3, 0.2, 0.3]\n").unwrap();
    let k: Vec<String> = (0..3).map(|i| s.resolve(i).unwrap().key).collect();
    assert_eq!(k[0], k[2]);
    assert_ne!(k[0], k[1]);
    assert_eq!(k[0].len(), 32);
    // The base at friction 0.3 written another way (the value given by the study's [set])
    // resolves to the same text, so the same key.
    let t = study("set = { \"contact.friction\" = 0.2 }\n[[axis]]\nkey = \"contact.friction\"\nvalues = [0.3]\n").unwrap();
    assert_eq!(t.resolve(0).unwrap().key, k[0]);
}

#[test]
fn an_element_of_an_array_and_tied_keys_change_together() {
    let s = study(
        "[[axis]]\nkey = \"body.inertia[0]\"\nalso = [\"body.inertia[1]\"]\nvalues = [6e-7, 9e-7]\n",
    )
    .unwrap();
    let r = s.resolve(1).unwrap();
    assert!(
        r.draft
            .overrides
            .last()
            .unwrap()
            .starts_with("body.inertia=["),
        "{:?}",
        r.draft.overrides
    );
    let sc = s.scenario(&r).unwrap();
    let i = sc.scene.body.inertia();
    assert_eq!((i[(0, 0)], i[(1, 1)], i[(2, 2)]), (9e-7, 9e-7, 7e-7));
    let e = study("[[axis]]\nkey = \"body.inertia[3]\"\nvalues = [1e-7]\n").unwrap_err();
    assert!(e.contains("index 3 is out of range"), "{e}");
}

#[test]
fn a_bad_value_is_a_row_with_its_status_and_message() {
    let s = study("[[axis]]\nkey = \"contact.friction\"\nvalues = [0.3, -1.0]\n").unwrap();
    let rows = run_all(&s);
    let h = header(&s);
    let (st, msg, tf) = (
        h.iter().position(|c| c == "status").unwrap(),
        h.iter().position(|c| c == "message").unwrap(),
        h.iter().position(|c| c == "t_final [s]").unwrap(),
    );
    assert_eq!(rows[1][st], Cell::Text(RowStatus::Invalid.name().into()));
    match &rows[1][msg] {
        Cell::Text(m) => assert!(m.contains("contact.friction = -1"), "{m}"),
        other => panic!("{other:?}"),
    }
    assert_eq!(rows[1][tf], Cell::Null);
    assert_eq!(rows[0][st], Cell::Text("completed".into()));
}

#[test]
fn a_misspelt_key_is_an_error_of_the_study() {
    let e = study("[[axis]]\nkey = \"contact.fricton\"\nvalues = [0.3]\n").unwrap_err();
    assert!(
        e.contains("contact.fricton") && e.contains("did you mean"),
        "{e}"
    );
}

#[test]
fn hostile_study_files_fail_fast_naming_key_value_and_rule() {
    let cases = [
        (
            "[[axis]]\nkey = \"contact.friction\"\nlinspace = [0, 1, 1000000000]\n",
            "s.toml:3:19: axis[0].linspace = 1000000000: n must be an integer from 1 to 10000000",
        ),
        (
            "[[axis]]\nkey = \"contact.friction\"\nlinspace = [0.1, 1, 100000]\n[[axis]]\nkey = \"initial.phi_dot\"\nlinspace = [1, 2, 10000]\n",
            "combine = grid: 100000 × 10000 = 1e9 points; a study has at most 10000000",
        ),
        (
            "[[axis]]\nkey = \"contact.friction\"\nrandom = { low = 1, high = 0, n = 3 }\n",
            "axis[0].random.high = 0: low must be below high",
        ),
        (
            "[[axis]]\nkey = \"contact.friction\"\nlogspace = [0, 1, 3]\n",
            "start and stop must be > 0",
        ),
        (
            "[[axis]]\nkey = \"contact.friction\"\nvalues = [0.1]\nlinspace = [0, 1, 2]\n",
            "an axis has one generator",
        ),
        (
            "[[axis]]\nkey = \"a..b\"\nvalues = [0.1]\n",
            "axis[0].key = \"a..b\": a key is a dotted path",
        ),
        ("x = 1\n", "s.toml:1:1: x: unknown key in the study"),
        (
            &format!("a = {}1{}\n", "[".repeat(100_000), "]".repeat(100_000)),
            "TOML syntax error",
        ),
        (
            "[[axis]]\nkeys = [\"contact.friction\"]\nlatin_hypercube = { low = [0], high = [1, 2], n = 5 }\n",
            "one bound per key",
        ),
    ];
    for (doc, expected) in cases {
        let t = Instant::now();
        let e = study(doc).unwrap_err();
        assert!(
            t.elapsed().as_secs_f64() < 0.5,
            "{expected}: {:?}",
            t.elapsed()
        );
        assert!(e.contains(expected), "expected {expected:?} in {e:?}");
    }
}

#[test]
fn zip_and_latin_hypercube_make_one_point_per_value() {
    let s = study(
        "combine = \"zip\"\n[[axis]]\nkey = \"contact.friction\"\nrandom = { low = 0.1, high = 0.5, n = 4, seed = 3 }\n[[axis]]\nkeys = [\"initial.phi_dot\", \"initial.theta\"]\nlatin_hypercube = { low = [100, 0.05], high = [200, 0.2], n = 4, seed = 1 }\n",
    )
    .unwrap();
    assert_eq!(s.len(), 4);
    assert_eq!(s.columns[3].header(), "initial.theta [rad]");
    let mismatch = study("combine = \"zip\"\n[[axis]]\nkey = \"contact.friction\"\nvalues = [0.1, 0.2]\n[[axis]]\nkey = \"initial.theta\"\nvalues = [0.1]\n").unwrap_err();
    assert!(mismatch.contains("same number of values"), "{mismatch}");
    match &s.plan.axes[1].dims[0].values {
        Values::Floats(v) => assert!(v.iter().all(|x| (100.0..200.0).contains(x))),
        other => panic!("{other:?}"),
    }
}

#[test]
fn a_resumed_study_gives_the_table_of_an_uninterrupted_one() {
    let dir = tempfile::tempdir().unwrap();
    let doc = "[[axis]]\nkey = \"contact.friction\"\nlinspace = [0.1, 0.5, 6]\n[outcomes]\nmax = [\"theta\"]\nfinal = [\"theta\", \"mode\"]\n";
    let s = study(doc).unwrap();
    let full = run_all(&s);
    // Half the rows already in the journal, as an interrupted study leaves them.
    let j = dir.path().join("j");
    let mut journal = open_journal(&s, &j);
    for i in [0, 2, 5] {
        journal.append(&s.run_point(i, None).unwrap()).unwrap();
    }
    drop(journal);
    let mut seen = Tally::default();
    s.resolves.store(0, std::sync::atomic::Ordering::Relaxed);
    let r = execute(&s, Some(&j), 2, &Arc::new(AtomicBool::new(false)), |t| {
        seen = *t
    })
    .unwrap();
    assert_eq!((seen.done, seen.resumed, seen.total), (6, 3, 6));
    // The journal is this plan's: its points are skipped by index, never resolved; only
    // the three that run are.
    assert_eq!(s.resolves.load(std::sync::atomic::Ordering::Relaxed), 3);
    let resumed = s.rows(r);
    let wall = s
        .columns
        .iter()
        .position(|c| c.name == "wall_time")
        .unwrap();
    let strip = |rows: &[Vec<Cell>]| -> Vec<Vec<Cell>> {
        rows.iter()
            .map(|r| {
                r.iter()
                    .enumerate()
                    .filter(|(i, _)| *i != wall)
                    .map(|(_, c)| c.clone())
                    .collect()
            })
            .collect()
    };
    assert_eq!(strip(&resumed), strip(&full));
    // And the table writes.
    let csv = dir.path().join("t.csv");
    table::write(&csv, &s.columns, &resumed, "s.toml").unwrap();
    let text = std::fs::read_to_string(&csv).unwrap();
    assert!(
        text.starts_with("point,contact.friction [1],status,message,t_final [s],"),
        "{text}"
    );
    assert_eq!(text.lines().count(), 7);
    assert!(Path::new(&csv).exists());
}

#[test]
fn a_plan_travels_as_json_without_changing_a_bit() {
    let s = study("[[axis]]\nkey = \"body.inertia[0]\"\nalso = [\"body.inertia[1]\"]\nlinspace = [3.85e-7, 1.12e-6, 40]\n[[axis]]\nkey = \"contact.friction\"\nrandom = { low = 0.1, high = 0.5, n = 7, seed = 9 }\n").unwrap();
    let json = serde_json::to_string(&s.plan).unwrap();
    let back = Study::new(serde_json::from_str(&json).unwrap()).unwrap();
    assert_eq!(back.plan, s.plan);
    for i in 0..s.len() {
        assert_eq!(back.resolve(i).unwrap().key, s.resolve(i).unwrap().key);
    }
}

#[test]
fn worker_threads_are_bounded_by_the_cap_and_the_runs() {
    let max = max_threads();
    assert!(max >= 8);
    assert_eq!(worker_threads(5, 2), 2);
    assert_eq!(worker_threads(3, 0), 1);
    assert_eq!(worker_threads(1_000_000_000, 1_000_000_000), max);
    assert!(worker_threads(0, 3) <= 3);
    assert_eq!(worker_threads(1, 100), 1);
}

/// The grid's size is known from the generators' `n` before any value is made: 32 axes
/// of 10⁷ values used to make 2.5 GB of values before the count was checked.
#[test]
fn the_point_count_is_checked_before_any_value_is_made() {
    let axis = "[[axis]]\nkey = \"contact.friction\"\nlinspace = [0.1, 1, 10000000]\n";
    let e = plan(&axis.repeat(32)).unwrap_err();
    assert!(
        e.starts_with("s.toml:1:1: combine = grid: 10000000 × 10000000 × "),
        "{e}"
    );
    assert!(
        e.contains("= 1e224 points; a study has at most 10000000"),
        "{e}"
    );
    let e = plan("[[axis]]\nkey = \"contact.friction\"\nvalues = [0.1, 0.2]\n[[axis]]\nkey = \"initial.phi_dot\"\nrandom = { low = 0, high = 1, n = 6000000 }\n").unwrap_err();
    assert!(e.contains("2 × 6000000 = 1.2e7 points"), "{e}");
}

/// Generator ranges whose width overflows are refused: they made NaN and inf values,
/// which then reached the scenario as the string "NaN".
#[test]
fn generators_make_only_finite_values() {
    for (doc, key) in [
        ("linspace = [-1e308, 1e308, 3]", "axis[0].linspace"),
        ("logspace = [1e-300, 1.7e308, 3]", ""),
        (
            "random = { low = -1.7e308, high = 1.7e308, n = 3 }",
            "axis[0].random.high",
        ),
    ] {
        let text = format!("[[axis]]\nkey = \"contact.friction\"\n{doc}\n");
        match plan(&text) {
            Err(e) => assert!(
                !key.is_empty() && e.contains(key) && e.contains("too far apart"),
                "{doc}: {e}"
            ),
            Ok(p) => {
                assert!(key.is_empty(), "{doc} accepted");
                match &p.axes[0].dims[0].values {
                    Values::Floats(v) => assert!(v.iter().all(|x| x.is_finite()), "{v:?}"),
                    other => panic!("{other:?}"),
                }
            }
        }
    }
    let e = plan("[[axis]]\nkeys = [\"contact.friction\"]\nlatin_hypercube = { low = [-1e308], high = [1e308], n = 5 }\n").unwrap_err();
    assert!(
        e.contains("axis[0].latin_hypercube.high") && e.contains("too far apart"),
        "{e}"
    );
}

/// Study-file messages name the right field and place: `final = ["all"]` is the documented
/// "all"; a misspelt `also` key is reported on `also`; a non-UTF-8 file gets line:column.
#[test]
fn study_file_messages_name_the_field_and_place() {
    let all = study(
        "[[axis]]\nkey = \"contact.friction\"\nvalues = [0.3]\n[outcomes]\nfinal = [\"all\"]\n",
    )
    .unwrap();
    let word = study(
        "[[axis]]\nkey = \"contact.friction\"\nvalues = [0.3]\n[outcomes]\nfinal = \"all\"\n",
    )
    .unwrap();
    assert_eq!(header(&all), header(&word));
    assert!(header(&all).iter().any(|h| h.starts_with("final.mode")));
    let e = study("[[axis]]\nkey = \"contact.friction\"\nalso = [\"initial.omega_body[7]\"]\nvalues = [0.3]\n").unwrap_err();
    assert!(
        e.contains("axis[contact.friction].also = \"initial.omega_body[7]\""),
        "{e}"
    );
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("s.toml");
    std::fs::write(&path, b"combine = \"grid\"\nx = \"ab\xff\"\n").unwrap();
    let e = spec::load(&path).unwrap_err().to_string();
    assert!(e.contains("s.toml:2:8: ") && e.contains("byte 0xff"), "{e}");
}

/// Points that run the same scenario (a repeated axis value) all resume from its one
/// journal row when rows are matched by key (a journal of an edited study); a cancel flag already set when a resumed study prepares stops it before
/// any run, with nothing appended.
#[test]
fn repeated_points_resume_from_one_row_and_a_cancelled_prepare_runs_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let s = study("[[axis]]\nkey = \"contact.friction\"\nvalues = [0.2, 0.3, 0.2, 0.2]\n").unwrap();
    let j = dir.path().join("j");
    // A journal of another plan (an edited study file): matched by key.
    let whom = journal::For {
        outcomes: &s.outcome_fingerprint(),
        plan: "edited",
        cells: s.outcome_columns().len(),
        points: s.len(),
    };
    let mut journal = Journal::open(&j, whom, &AtomicBool::new(false)).unwrap();
    journal.append(&s.run_point(0, None).unwrap()).unwrap();
    drop(journal);
    let before = std::fs::read(&j).unwrap();
    let cancelled = execute(&s, Some(&j), 1, &Arc::new(AtomicBool::new(true)), |_| {});
    assert!(
        matches!(cancelled, Err(ExecError::Interrupted { done: 0, total: 4 })),
        "{cancelled:?}"
    );
    assert_eq!(std::fs::read(&j).unwrap(), before);
    let mut seen = Tally::default();
    let r = execute(&s, Some(&j), 1, &Arc::new(AtomicBool::new(false)), |t| {
        seen = *t
    })
    .unwrap();
    assert_eq!((seen.done, seen.resumed), (4, 3));
    let rows = s.rows(r);
    assert_eq!(rows[0][2..], rows[2][2..]);
    assert_eq!(rows[0][2..], rows[3][2..]);
}

/// Every rejection of a hand-written study file is placed at its line and column in the
/// study file: errors found when the study is prepared (a `[set]` value the scenario
/// refuses, a key that does not reach into the base, a misspelt `also` key, zipped axes
/// of different lengths, an outcome column that does not exist) as well as those of
/// reading it. A `[set]` error used to be reported against the base scenario's
/// `--set`, a misspelt `also` key as an "axis key", and the rest without a place.
#[test]
fn every_rejected_study_file_names_its_line_and_column() {
    let axis = "[[axis]]\nkey = \"initial.phi_dot\"\nvalues = [100.0]\n";
    let cases = [
        (
            format!("[set]\n\"contact.friction\" = -1\n{axis}"),
            "s.toml:2:22: set.contact.friction = -1: the Coulomb coefficient",
        ),
        (
            format!("[set]\nbody = {{ mass = \"heavy\" }}\n{axis}"),
            "s.toml:2:17: set.body.mass = \"heavy\": expected a number",
        ),
        (
            format!("[set]\n\"body.bogus\" = 1\n{axis}"),
            "s.toml:2:16: set.body.bogus = 1: unknown key in [body]",
        ),
        (
            "[[axis]]\nkey = \"initial.phi_dot\"\nalso = [\"initial.psi_dott\"]\nvalues = [1.0]\n"
                .into(),
            "s.toml:3:8: axis[initial.phi_dot].also = \"initial.psi_dott\": unknown key in [initial]",
        ),
        (
            "[[axis]]\nkey = \"initial.phi_dot\"\nalso = [\"body.inertia[7]\"]\nvalues = [1.0]\n"
                .into(),
            "s.toml:3:8: axis[initial.phi_dot].also = \"body.inertia[7]\": inertia has 3 elements",
        ),
        (
            "[[axis]]\nkey = \"initial.phi_dott\"\nvalues = [1.0]\n".into(),
            "s.toml:2:7: axis[initial.phi_dott].key = \"initial.phi_dott\": unknown key in [initial]",
        ),
        (
            "[[axis]]\nkey = \"initial.phi_dot.x\"\nvalues = [1.0]\n".into(),
            "s.toml:2:7: axis[initial.phi_dot.x].key",
        ),
        (
            format!(
                "combine = \"zip\"\n{axis}[[axis]]\nkey = \"initial.theta\"\nvalues = [0.1, 0.2]\n"
            ),
            "s.toml:1:11: combine = \"zip\": zipped axes must all have the same number of values",
        ),
        (
            format!("{axis}[outcomes]\nfinal = [\"thetaa\"]\n"),
            "s.toml:5:9: outcomes.final = \"thetaa\"",
        ),
        (
            format!("{axis}[outcomes]\nmin = [\"mode\"]\n"),
            "s.toml:5:7: outcomes.min = \"mode\"",
        ),
    ];
    for (doc, expected) in cases {
        let e = study(&doc).unwrap_err();
        assert!(e.contains(expected), "expected {expected:?} in {e:?}");
    }
}

/// An axis column's unit is the scenario schema's, for every key the format has.
#[test]
fn axis_columns_take_their_units_from_the_scenario_schema() {
    let s = study(
        "combine = \"zip\"\n\
         [[axis]]\nkey = \"contact.contact_radius\"\nvalues = [0.0]\n\
         [[axis]]\nkey = \"contact.restitution\"\nvalues = [0.5]\n\
         [[axis]]\nkey = \"initial.height\"\nvalues = [0.0]\n",
    )
    .unwrap();
    assert_eq!(
        &header(&s)[1..4],
        [
            "contact.contact_radius [m]",
            "contact.restitution [1]",
            "initial.height [m]"
        ]
    );
}

/// The row keys of studies run before the values were set on the parsed document (by
/// `--set` text): the same, so their journals resume. The keys were written by that
/// implementation for this study (an index axis with its `also` key, and a string axis).
#[test]
fn row_keys_are_those_of_existing_journals() {
    let s = study(
        "[[axis]]\nkey = \"body.inertia[0]\"\nalso = [\"body.inertia[1]\"]\nvalues = [6e-7, 9e-7]\n\
         [[axis]]\nkey = \"contact.model\"\nvalues = [\"coulomb\", \"sliding\"]\n",
    )
    .unwrap();
    let keys: Vec<String> = (0..4).map(|i| s.resolve(i).unwrap().key).collect();
    assert_eq!(
        keys,
        [
            "30fe60aa2b2b8739af55f22a4768fe9a",
            "12afb2bd4621d9cf28ceabcc8219d493",
            "c427a48a1ffea43b492caae4e63ecdb9",
            "5dc80532da170c32b296bfe348a5a25e"
        ]
    );
}

/// The table of `s` run uninterrupted, as CSV text, and the journal-streamed table of a
/// study resumed from `journal` (whatever its rows), as CSV text, with the resumed
/// tally. Wall times are left out of the study (they differ from run to run).
fn fresh_and_resumed(s: &Study, j: &Path, dir: &Path) -> (String, String, Tally) {
    let fresh = dir.join("fresh.csv");
    table::write(&fresh, &s.columns, &run_all(s), "s.toml").unwrap();
    let mut seen = Tally::default();
    let mut f = execute_with(s, j, 2, &Arc::new(AtomicBool::new(false)), None, |t| {
        seen = *t
    })
    .unwrap();
    let resumed = dir.join("resumed.csv");
    f.write_table(s, &resumed).unwrap();
    (
        std::fs::read_to_string(fresh).unwrap(),
        std::fs::read_to_string(resumed).unwrap(),
        seen,
    )
}

const FRICTION: &str = "[[axis]]\nkey = \"contact.friction\"\nvalues = [0.1, 0.2, 0.3, 0.4, 0.5]\n[outcomes]\nwall_time = false\nfinal = [\"theta\", \"mode\"]\n";

/// A journal written for a study whose file was then edited (the same axis, its values
/// reversed: point i now runs what point 4 − i ran) is not trusted by index: its rows
/// are matched by key, every point is resolved, and the table is that of the edited
/// study run from scratch (trusting the indexes would put each row at the wrong point).
#[test]
fn a_journal_of_an_edited_study_is_matched_by_key_not_index() {
    let dir = tempfile::tempdir().unwrap();
    let j = dir.path().join("j");
    let before = study(FRICTION).unwrap();
    let mut journal = open_journal(&before, &j);
    for i in 0..4 {
        journal.append(&before.run_point(i, None).unwrap()).unwrap();
    }
    drop(journal);
    let edited =
        study(&FRICTION.replace("0.1, 0.2, 0.3, 0.4, 0.5", "0.5, 0.4, 0.3, 0.2, 0.1")).unwrap();
    assert_ne!(before.plan_fingerprint(), edited.plan_fingerprint());
    assert_eq!(before.outcome_fingerprint(), edited.outcome_fingerprint());
    let (fresh, resumed, seen) = fresh_and_resumed(&edited, &j, dir.path());
    assert_eq!(resumed, fresh);
    // Points 1..=4 of the edited study are points 3..=0 of the first: found by key.
    assert_eq!((seen.done, seen.resumed), (5, 4));
    // Rewritten for the edited plan with every point indexed: resumed again by index.
    edited
        .resolves
        .store(0, std::sync::atomic::Ordering::Relaxed);
    let (_, again, seen) = fresh_and_resumed(&edited, &j, dir.path());
    assert_eq!(again, fresh);
    assert_eq!(seen.resumed, 5);
    // Only the fresh run's five resolves: the resumed study resolved none.
    assert_eq!(
        edited.resolves.load(std::sync::atomic::Ordering::Relaxed),
        5
    );
}

/// A journal of the first format (rows by key, no point index: `<key>\t<cells>\t<crc>`
/// under `ellipsoid-study-journal 1 <outcome fingerprint>`) still resumes, by key, to the
/// table of an uninterrupted study.
#[test]
fn a_journal_of_the_first_format_still_resumes() {
    let dir = tempfile::tempdir().unwrap();
    let j = dir.path().join("j");
    let s = study(FRICTION).unwrap();
    let mut text = format!("ellipsoid-study-journal 1 {}\n", s.outcome_fingerprint());
    for i in [4, 1, 2] {
        let r = s.run_point(i, None).unwrap();
        let mut line = String::new();
        journal::encode(&mut line, None, &r.key, &r.cells);
        let body = line
            .strip_prefix("-\t")
            .unwrap()
            .rsplit_once('\t')
            .unwrap()
            .0;
        text.push_str(&format!(
            "{body}\t{:08x}\n",
            crc32fast::hash(body.as_bytes())
        ));
    }
    std::fs::write(&j, text).unwrap();
    let (fresh, resumed, seen) = fresh_and_resumed(&s, &j, dir.path());
    assert_eq!(resumed, fresh);
    assert_eq!((seen.done, seen.resumed), (5, 3));
    assert!(
        std::fs::read_to_string(&j)
            .unwrap()
            .starts_with("ellipsoid-study-journal 2 ")
    );
}

#[test]
fn the_tally_counts_as_failed_exactly_the_rows_whose_run_did_not_finish() {
    use ellipsoid_core::simulate::StatusKind;
    // Every core status reads back from its cell, and fails the tally exactly when the
    // core says the run did not end where the scene asked (section_full included).
    for kind in StatusKind::ALL {
        let cells = [Cell::Text(RowStatus::Ran(kind).name().into())];
        let status = RowStatus::of(&cells).unwrap();
        assert_eq!(status, RowStatus::Ran(kind));
        assert_eq!(status.failed(), !kind.finished(), "{}", kind.name());
    }
    for st in [RowStatus::Invalid, RowStatus::InternalError] {
        assert_eq!(RowStatus::named(st.name()), Some(st));
        assert!(st.failed());
    }
    assert_eq!(RowStatus::names().count(), StatusKind::ALL.len() + 2);
    // A cell that names no status (an edited journal) is refused, its text given back.
    assert_eq!(
        RowStatus::of(&[Cell::Text("done".into())]),
        Err("\"done\"".into())
    );
    assert_eq!(RowStatus::of(&[Cell::Null]), Err("~".into()));
}

/// A journal row whose status cell names no status (its CRC recomputed, as an edit that
/// knows the format would) is refused when the study resumes: the error names the
/// journal, the line and the value, and the journal is left as it was.
#[test]
fn an_unknown_status_in_a_journal_row_is_an_error_naming_the_journal_line_and_value() {
    let dir = tempfile::tempdir().unwrap();
    let j = dir.path().join("j");
    let s = study(FRICTION).unwrap();
    let mut journal = open_journal(&s, &j);
    for i in [3, 0] {
        journal.append(&s.run_point(i, None).unwrap()).unwrap();
    }
    drop(journal);
    let text = std::fs::read_to_string(&j).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let body = lines[2].rsplit_once('\t').unwrap().0;
    assert!(body.contains("\ts\"completed\"\t"), "{body}");
    let body = body.replace("\ts\"completed\"\t", "\ts\"finished\"\t");
    let edited = format!(
        "{}\n{}\n{body}\t{:08x}\n",
        lines[0],
        lines[1],
        crc32fast::hash(body.as_bytes())
    );
    std::fs::write(&j, &edited).unwrap();
    let cancel = Arc::new(AtomicBool::new(false));
    let e = execute(&s, Some(&j), 1, &cancel, |_| {})
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with(&format!(
            "{}:3: the row's status \"finished\" is not one of completed, observed, ",
            j.display()
        )),
        "{e}"
    );
    assert!(e.contains(", invalid, internal_error; "), "{e}");
    assert_eq!(std::fs::read_to_string(&j).unwrap(), edited);
}

/// Issue 48: an `also` list of more than 64 keys was refused with "at most 64 values",
/// the rule of an axis's values, while the bound is on the keys one axis sets (64, as
/// for `[set]` and the outcome lists: docs/studies.md, "Limits"). The message now names
/// that rule, as do those of an outcome list (columns) and a Latin hypercube's keys; 64
/// keys are allowed.
#[test]
fn an_also_list_too_long_names_the_rule_of_keys() {
    let keys = |n: usize| {
        (0..n)
            .map(|_| "\"initial.theta\"")
            .collect::<Vec<_>>()
            .join(", ")
    };
    let e = study(&format!(
        "[[axis]]\nkey = \"contact.friction\"\nalso = [{}]\nvalues = [0.3]\n",
        keys(65)
    ))
    .unwrap_err();
    assert!(
        e.contains("axis[0].also = an array of 65 values: an axis sets at most 64 more keys to its value (also)"),
        "{e}"
    );
    assert!(!e.contains("at most 64 values"), "{e}");
    study(&format!(
        "[[axis]]\nkey = \"contact.friction\"\nalso = [{}]\nvalues = [0.3]\n",
        keys(64)
    ))
    .unwrap();
    let columns = (0..65).map(|_| "\"theta\"").collect::<Vec<_>>().join(", ");
    let e = study(&format!(
        "[[axis]]\nkey = \"contact.friction\"\nvalues = [0.3]\n[outcomes]\nfinal = [{columns}]\n"
    ))
    .unwrap_err();
    assert!(
        e.contains("an outcome list names at most 64 columns"),
        "{e}"
    );
}

/// No point of a bundled study (`studies/*.toml`, every point of its axes) is a scenario
/// with a plausibility warning (`ellipsoid_core::scenario::plausibility`).
#[test]
fn no_point_of_a_bundled_study_warns() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../studies");
    let mut files = 0;
    for e in std::fs::read_dir(&dir).expect("studies/") {
        let path = e.expect("an entry").path();
        if path.extension().is_none_or(|x| x != "toml") {
            continue;
        }
        files += 1;
        let plan = spec::load(&path).unwrap_or_else(|e| panic!("{e}"));
        let study = Study::new(plan).unwrap_or_else(|e| panic!("{e}"));
        assert!(!study.is_empty());
        for i in 0..study.len() {
            let r = study
                .resolve(i)
                .unwrap_or_else(|e| panic!("{}: point {i}: {e:?}", path.display()));
            let s = study
                .scenario(&r)
                .unwrap_or_else(|e| panic!("{}: point {i}: {e}", path.display()));
            let w = ellipsoid_core::scenario::warnings(&s);
            assert!(w.is_empty(), "{}: point {i}: {}", path.display(), w[0]);
        }
    }
    assert!(files >= 3, "{files} studies");
}
