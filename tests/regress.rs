//! `regress_*`: every bundled scenario gives the results recorded in
//! `tests/data/regress/baseline.json`, to 1e-9 relative.
//!
//! Each scenario of `scenarios/*.toml` and `scenarios/paper/*.toml` is run with the
//! `ellipsoid` binary (`ellipsoid run SCENARIO -o CSV --summary JSON -q`, from the
//! repository's root). Its record in the baseline holds values: the exit status, the
//! summary's `status`, `events` and `final` state, and a subsample of the CSV (`rows`: the
//! row count, the indices of 21 evenly spaced rows, every column at those rows). The
//! summary's machine- and build-dependent fields (wall time, version, step statistics)
//! are not recorded.
//!
//! A number moved when |a − b| > 1e-9 max(|a|, |b|) + floor, the floor being 1e-9 s for an
//! event's time and otherwise 1e-9 times the largest magnitude the same field (the CSV
//! column, or the event or final field of that name) takes in the scenario's baseline
//! record, so a value that crosses zero is judged on its scale. Strings, booleans, row and
//! event counts must be equal. There are no per-scenario exceptions: the test fails
//! listing every moved number.
//!
//! A deliberate change is recorded by re-blessing the baseline with its reason:
//!
//! ```text
//! cargo build --release -p ellipsoid-cli
//! python3 scripts/regression-baseline.py target/release/ellipsoid              # what moved
//! python3 scripts/regression-baseline.py target/release/ellipsoid --bless "REASON"
//! ```
//!
//! The script applies the same rule, rewrites every record and appends the reason, with
//! each moved scenario's largest relative move and moved fields, to the baseline's
//! `changes` list, the history of every deliberate change.

use std::collections::{BTreeSet, HashMap};
use std::path::Path;
use std::process::Command;

use serde_json::{Map, Value, json};

const BIN: &str = env!("CARGO_BIN_EXE_ellipsoid");
/// Relative tolerance of every number, and of its floor's scale.
const REL: f64 = 1e-9;
/// Absolute floor on an event's time [s].
const EVENT_TIME_FLOOR: f64 = 1e-9;

fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
}

/// The bundled scenarios, as paths from the repository's root.
fn bundled() -> BTreeSet<String> {
    ["scenarios", "scenarios/paper"]
        .iter()
        .flat_map(|dir| {
            std::fs::read_dir(root().join(dir))
                .unwrap()
                .map(|e| e.unwrap().file_name().into_string().unwrap())
                .filter(|f| f.ends_with(".toml"))
                .map(move |f| format!("{dir}/{f}"))
        })
        .collect()
}

/// A CSV field as a JSON number where it is a finite one (`mode` stays a string).
fn field(text: &str) -> Value {
    text.parse::<f64>()
        .ok()
        .and_then(serde_json::Number::from_f64)
        .map_or_else(|| Value::String(text.to_owned()), Value::Number)
}

/// The record of one run of `name`, its CSV sampled at the rows `index`.
fn record(name: &str, index: &[usize], dir: &Path) -> Value {
    let (csv, json) = (dir.join("out.csv"), dir.join("out.json"));
    let out = Command::new(BIN)
        .current_dir(root())
        .args(["run", name, "-o", csv.to_str().unwrap()])
        .args(["--summary", json.to_str().unwrap(), "-q"])
        .output()
        .unwrap();
    let summary = std::fs::read_to_string(&json).unwrap_or_else(|_| {
        let stderr = String::from_utf8_lossy(&out.stderr);
        panic!(
            "{name}: exited {:?} without a summary:\n{stderr}",
            out.status.code()
        )
    });
    let summary: Value = serde_json::from_str(&summary).unwrap();
    let text = std::fs::read_to_string(&csv).unwrap();
    // The comment line (the scenario and its body) is not a row.
    let mut lines = text
        .trim_end_matches('\n')
        .split('\n')
        .skip_while(|l| l.starts_with('#'));
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let body: Vec<&str> = lines.collect();
    let picked: Vec<Vec<&str>> = index
        .iter()
        .filter_map(|&i| body.get(i).map(|row| row.split(',').collect()))
        .collect();
    let columns: Map<String, Value> = header
        .iter()
        .enumerate()
        .map(|(j, c)| {
            let values = picked.iter().map(|row| field(row[j])).collect();
            ((*c).to_owned(), Value::Array(values))
        })
        .collect();
    json!({
        "exit": out.status.code().unwrap_or(-1),
        "status": summary["status"],
        "events": summary["events"],
        "final": summary["final"],
        "rows": {"count": body.len(), "index": index, "columns": columns},
    })
}

/// The largest magnitude of every field name in `value` (an array takes its key's name).
fn scales(value: &Value, label: &str, out: &mut HashMap<String, f64>) {
    match value {
        Value::Object(map) => map.iter().for_each(|(k, v)| scales(v, k, out)),
        Value::Array(items) => items.iter().for_each(|v| scales(v, label, out)),
        Value::Number(n) => {
            let s = out.entry(label.to_owned()).or_insert(0.0);
            *s = s.max(n.as_f64().unwrap().abs());
        }
        _ => {}
    }
}

/// Where a number sits in a record and what judges it.
struct At<'a> {
    path: String,
    label: &'a str,
    in_events: bool,
}

/// Appends every difference of `new` from the baseline `old` on the fields `old` has.
fn compare(old: &Value, new: &Value, at: &At, scale: &HashMap<String, f64>, out: &mut Vec<String>) {
    let path = &at.path;
    match (old, new) {
        (Value::Object(o), Value::Object(n)) => {
            for (k, v) in o {
                let sub = At {
                    path: format!("{path}.{k}"),
                    label: k,
                    in_events: at.in_events || k == "events",
                };
                match n.get(k) {
                    Some(w) => compare(v, w, &sub, scale, out),
                    None => out.push(format!("{}: {v} -> missing", sub.path)),
                }
            }
        }
        (Value::Array(o), Value::Array(n)) => {
            if o.len() != n.len() {
                out.push(format!("{path} (length): {} -> {}", o.len(), n.len()));
            }
            for (k, (v, w)) in o.iter().zip(n).enumerate() {
                let sub = At {
                    path: format!("{path}[{k}]"),
                    ..*at
                };
                compare(v, w, &sub, scale, out);
            }
        }
        (Value::Number(a), Value::Number(b)) => {
            let (a, b) = (a.as_f64().unwrap(), b.as_f64().unwrap());
            let unit = if at.in_events && at.label == "t" {
                EVENT_TIME_FLOOR / REL
            } else {
                scale.get(at.label).copied().unwrap_or(0.0)
            };
            let diff = (a - b).abs();
            if diff > REL * (a.abs().max(b.abs()) + unit) {
                let rel = diff / a.abs().max(b.abs()).max(unit);
                out.push(format!("{path}: {a:e} -> {b:e} (relative move {rel:.2e})"));
            }
        }
        _ if old != new => out.push(format!("{path}: {old} -> {new}")),
        _ => {}
    }
}

#[test]
fn regress_bundled_scenarios_match_the_baseline() {
    let text = std::fs::read_to_string(root().join("tests/data/regress/baseline.json")).unwrap();
    let baseline: Value = serde_json::from_str(&text).unwrap();
    let records = baseline["scenarios"].as_object().unwrap();
    let dir = tempfile::tempdir().unwrap();
    let mut moved = Vec::new();
    let (bundled, recorded) = (bundled(), records.keys().cloned().collect());
    for name in bundled.difference(&recorded) {
        moved.push(format!("{name}: a bundled scenario the baseline lacks"));
    }
    for name in recorded.difference(&bundled) {
        moved.push(format!("{name}: in the baseline but no longer bundled"));
    }
    for (name, old) in records.iter().filter(|(n, _)| bundled.contains(*n)) {
        let index: Vec<usize> = serde_json::from_value(old["rows"]["index"].clone()).unwrap();
        let new = record(name, &index, dir.path());
        let mut scale = HashMap::new();
        scales(old, "", &mut scale);
        let mut out = Vec::new();
        let at = At {
            path: String::new(),
            label: "",
            in_events: false,
        };
        compare(old, &new, &at, &scale, &mut out);
        moved.extend(
            out.iter()
                .map(|m| format!("{name}: {}", m.trim_start_matches('.'))),
        );
    }
    assert!(
        moved.is_empty(),
        "{} values moved from tests/data/regress/baseline.json (more than 1e-9 relative):\n{}\n\
         If the change is deliberate, re-bless the baseline with its reason:\n  \
         cargo build --release -p ellipsoid-cli\n  \
         python3 scripts/regression-baseline.py target/release/ellipsoid --bless \"REASON\"",
        moved.len(),
        moved.join("\n")
    );
}
