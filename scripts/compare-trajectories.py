#!/usr/bin/env python3
"""Runs two `ellipsoid` binaries on every bundled scenario and compares their CSV
trajectories value by value: whether every number is bit-identical, else the largest
difference relative to each column's scale (max |x| over the run, at least 1e-300) and
where. For performance work whose promise is "results bit-identical, or within 1e-14 and
stated" (issue #18): the numbers are compared after parsing, so a change of number style
(e.g. `6e1` against `60.0`) is no difference.

    python3 scripts/compare-trajectories.py OLD_BINARY NEW_BINARY [SCENARIO ...]

Exit status 0 when every scenario's exit status, row count and columns agree to the bit,
1 otherwise (the report says what differs).
"""
import csv
import pathlib
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parent.parent


def run(binary: str, scenario: pathlib.Path, out: pathlib.Path) -> tuple[int, list[str], list[list[str]]]:
    r = subprocess.run([binary, "run", str(scenario), "-o", str(out), "-q"], cwd=ROOT, stderr=subprocess.DEVNULL)
    with open(out, newline="") as f:  # the `#` comment line (scenario, body) is not compared
        rows = list(csv.reader(line for line in f if not line.startswith("#")))
    return r.returncode, rows[0], rows[1:]


def compare(old: tuple, new: tuple) -> tuple[bool, str]:
    (code_a, head_a, rows_a), (code_b, head_b, rows_b) = old, new
    if code_a != code_b or len(rows_a) != len(rows_b):
        return False, f"exit {code_a} -> {code_b}, rows {len(rows_a)} -> {len(rows_b)}"
    worst, where = 0.0, ""
    for name in head_a:
        if name not in head_b:
            return False, f"column {name} is gone"
        i, j = head_a.index(name), head_b.index(name)
        a = [r[i] for r in rows_a]
        b = [r[j] for r in rows_b]
        if name == "mode":
            if a != b:
                return False, "mode differs"
            continue
        x, y = [float(v) for v in a], [float(v) for v in b]
        scale = max(max(map(abs, x)), 1e-300)
        for k, (p, q) in enumerate(zip(x, y)):
            d = abs(p - q) / scale
            if d > worst or (p != q and not where):
                worst, where = d, f"{name} row {k}"
    if not where:
        return True, "bit-identical"
    return False, f"largest difference {worst:.1e} (of the column's scale) at {where}"


def main() -> int:
    old_bin, new_bin, *names = sys.argv[1:]
    scenarios = [pathlib.Path(n) for n in names] or (
        sorted((ROOT / "scenarios").glob("*.toml")) + sorted((ROOT / "scenarios" / "paper").glob("*.toml"))
    )
    same = True
    with tempfile.TemporaryDirectory() as tmp:
        for sc in scenarios:
            a = run(old_bin, sc, pathlib.Path(tmp) / "a.csv")
            b = run(new_bin, sc, pathlib.Path(tmp) / "b.csv")
            ok, what = compare(a, b)
            same &= ok
            print(f"{sc.relative_to(ROOT) if sc.is_absolute() else sc}: {what}")
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main())
