#!/usr/bin/env python3
"""Compares the results of every bundled scenario with tests/data/regress/baseline.json,
or re-blesses that baseline with a stated reason (the regression test tests/regress.rs
applies the same rule).

    cargo build --release -p ellipsoid-cli
    python3 scripts/regression-baseline.py target/release/ellipsoid
    python3 scripts/regression-baseline.py target/release/ellipsoid --bless "REASON"

Every scenario of scenarios/*.toml and scenarios/paper/*.toml is run with `BIN run
SCENARIO -o CSV --summary JSON -q` from the repository's root. Its record in the baseline
holds values, not hashes: the exit status, the summary's `status`, `events` and `final`
state, and a subsample of the CSV (`rows`: its row count, the indices of 21 evenly
spaced rows from the first to the last, and every column at those rows). The summary's
machine- or build-dependent fields (wall time, version, step statistics) are not kept.

A number moved when |a - b| > 1e-9 max(|a|, |b|) + floor, where the floor is 1e-9 s for
an event's time and otherwise 1e-9 times the largest magnitude the same field (the CSV
column, or the event or final field of that name) takes in the scenario's baseline
record, so that a value crossing zero is judged on its scale. Strings, booleans, row and
event counts must be equal. Without `--bless` the script prints every moved number and
exits 1 if there is one. With `--bless REASON` it rewrites every record from BIN and
appends to the baseline's `changes` list the reason and, per scenario that moved, its
largest relative move |a - b| / max(|a|, |b|, scale) and the fields that moved, so the
history of deliberate changes stays in the file with their reasons.
"""
import argparse
import json
import math
import pathlib
import re
import subprocess
import sys
import tempfile
from typing import Any

ROOT = pathlib.Path(__file__).resolve().parent.parent
BASELINE = ROOT / "tests" / "data" / "regress" / "baseline.json"
REL = 1e-9
EVENT_TIME_FLOOR = 1e-9  # s
SUBSAMPLE = 20
# (path, field, old value, new value, relative move or None for a non-number)
Move = tuple[str, str, Any, Any, float | None]
ABOUT = ("Results of every bundled scenario, written by scripts/regression-baseline.py --bless "
         "and compared by tests/regress.rs (see either for the rule); `changes` states why each "
         "re-blessing moved them.")


def scenarios() -> list[str]:
    files = sorted((ROOT / "scenarios").glob("*.toml")) + sorted((ROOT / "scenarios" / "paper").glob("*.toml"))
    return [f.relative_to(ROOT).as_posix() for f in files]


def number(field: str):
    """A CSV field as a float where it is a finite one (the `mode` column stays a string)."""
    try:
        x = float(field)
    except ValueError:
        return field
    return x if math.isfinite(x) else field


def run(exe: str, scenario: str) -> tuple[int, dict, list[str], list[str]]:
    """Exit status, summary, CSV header and CSV rows of one run."""
    with tempfile.TemporaryDirectory() as tmp:
        csv, js = pathlib.Path(tmp) / "out.csv", pathlib.Path(tmp) / "out.json"
        r = subprocess.run([exe, "run", scenario, "-o", str(csv), "--summary", str(js), "-q"],
                           cwd=ROOT, capture_output=True)
        if not js.exists():
            sys.exit(f"{scenario}: {exe} exited {r.returncode} without a summary:\n{r.stderr.decode()}")
        summary = json.loads(js.read_text())
        # the comment line (the scenario and its body) is not a row
        lines = [line for line in csv.read_text().rstrip("\n").split("\n") if not line.startswith("#")]
    return r.returncode, summary, lines[0].split(","), lines[1:]


def record(result: tuple, index: list[int] | None) -> dict:
    """The record of a run at the rows `index`, or at 21 evenly spaced rows if None."""
    code, summary, header, body = result
    if index is None:
        index = sorted({k * (len(body) - 1) // SUBSAMPLE for k in range(SUBSAMPLE + 1)})
    picked = [body[i].split(",") for i in index if i < len(body)]
    return {
        "exit": code,
        "status": summary["status"],
        "events": summary["events"],
        "final": summary["final"],
        "rows": {"count": len(body), "index": index,
                 "columns": {c: [number(row[j]) for row in picked] for j, c in enumerate(header)}},
    }


def is_number(v) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def scales(record, label="", out=None) -> dict:
    """The largest magnitude of every field name in `record` (an array takes its key's name)."""
    out = {} if out is None else out
    if isinstance(record, dict):
        for k, v in record.items():
            scales(v, k, out)
    elif isinstance(record, list):
        for v in record:
            scales(v, label, out)
    elif is_number(record):
        out[label] = max(out.get(label, 0.0), abs(record))
    return out


def compare(old, new, scale: dict, path="", label="", in_events=False, moves: list[Move] | None = None) -> list[Move]:
    """Every difference of `new` from the baseline `old` on the fields `old` has."""
    moves = [] if moves is None else moves
    if isinstance(old, dict) and isinstance(new, dict):
        for k, v in old.items():
            if k not in new:
                moves.append((f"{path}.{k}", field_name(f"{path}.{k}"), v, "missing", None))
            else:
                compare(v, new[k], scale, f"{path}.{k}", k, in_events or k == "events", moves)
    elif isinstance(old, list) and isinstance(new, list):
        if len(old) != len(new):
            moves.append((f"{path} (length)", field_name(f"{path} (length)"), len(old), len(new), None))
        for k, (v, w) in enumerate(zip(old, new)):
            compare(v, w, scale, f"{path}[{k}]", label, in_events, moves)
    elif is_number(old) and is_number(new):
        unit = EVENT_TIME_FLOOR / REL if in_events and label == "t" else scale.get(label, 0.0)
        diff = abs(old - new)
        if diff > REL * (max(abs(old), abs(new)) + unit):
            moves.append((path, field_name(path), old, new, diff / max(abs(old), abs(new), unit)))
    elif old != new:
        moves.append((path, field_name(path), old, new, None))
    return moves


def field_name(path: str) -> str:
    """`.rows.columns.theta[3]` -> `rows.theta`; `.events[2].impulse[0]` -> `events.impulse`."""
    return re.sub(r"\[\d+\]", "", path).replace(".columns", "").lstrip(".")


def dumps(data: dict) -> str:
    """JSON with every array of plain values on one line (a row of the CSV per line)."""
    text = json.dumps(data, indent=1)
    text = re.sub(r"\[\n\s+([^\[\]{}]*?)\n\s+\]",
                  lambda m: "[" + re.sub(r",\n\s+", ", ", m.group(1)) + "]", text)
    assert json.loads(text) == data
    return text + "\n"


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("bin", help="the ellipsoid binary to run")
    ap.add_argument("--bless", metavar="REASON", help="rewrite the baseline from BIN, stating why")
    args = ap.parse_args()
    exe = str(pathlib.Path(args.bin).resolve())
    baseline = json.loads(BASELINE.read_text())
    old_records = baseline["scenarios"]
    records: dict[str, dict] = {}
    moved: dict[str, list[Move]] = {}
    for name in scenarios():
        old = old_records.get(name)
        index = old["rows"]["index"] if old else None
        result = run(exe, name)
        records[name] = record(result, None if args.bless else index)
        if old is None:
            moved[name] = [("", "new scenario", None, None, None)]
            continue
        moves = compare(old, record(result, index), scales(old))
        if moves:
            moved[name] = moves
    moved.update({name: [("", "scenario removed", None, None, None)] for name in old_records if name not in records})
    for name, moves in moved.items():
        for path, field, a, b, rel in moves:
            if not path:
                print(f"{name}: {field}")
            else:
                print(f"{name}: {path.lstrip('.')}: {a} -> {b}" + (f" (relative move {rel:.2e})" if rel is not None else ""))
    if not args.bless:
        print(f"{sum(map(len, moved.values()))} values moved in {len(moved)} of {len(records)} scenarios")
        return 1 if moved else 0
    entry = {"reason": args.bless, "scenarios": {}}
    for name, moves in moved.items():
        rels = [m[4] for m in moves if m[4] is not None]
        entry["scenarios"][name] = {"largest_relative_move": max(rels) if rels else None,
                                    "fields": sorted({m[1] for m in moves})}
    changes = baseline.get("changes", []) + [entry]
    BASELINE.write_text(dumps({"about": ABOUT, "changes": changes, "scenarios": records}))
    print(f"blessed {len(records)} scenarios ({len(moved)} moved) into {BASELINE.relative_to(ROOT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
