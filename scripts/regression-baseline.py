#!/usr/bin/env python3
"""Writes tests/data/regress/baseline.json: for every bundled scenario, a digest of the
CSV trajectory and the JSON summary that `ellipsoid run` produces, for the regression
test `regress_bundled_scenarios` (tests/regress.rs).

The baseline in the repository was made with the `ellipsoid` binary built from commit
f2009a6 (main before the run-loop rewrite of issue #12):

    cargo build --release -p ellipsoid-cli
    python3 scripts/regression-baseline.py target/release/ellipsoid

The digest of a CSV is the FNV-1a 64-bit hash of its text restricted to the columns in
`columns` (the columns f2009a6 wrote), rows joined with "\n", fields with ",", so columns
added later do not change it; each number is first rewritten in one canonical form, the
one f2009a6 wrote (Rust's `{:e}`: shortest round-trip digits, `1.5e-7`, `6e1`, `0e0`), so
the digest depends on the values, not on how a later version formats them (the CSV
writer moved to `zmij`'s `0.025` / `60.0` style in issue #18). The summary is kept whole except `wall_time_s`, `version`
and `units` (machine- and build-dependent, or grown with new columns).
"""
import decimal
import json
import pathlib
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parent.parent
COLUMNS = ["t", "x", "y", "z", "theta", "phi", "psi", "theta_dot", "phi_dot", "psi_dot",
           "omega_x", "omega_y", "omega_z", "vx", "vy", "vz", "energy", "normal_force",
           "slip_speed", "mode", "work"]
DROPPED = ["wall_time_s", "version", "units", "output"]


def fnv1a64(data: bytes) -> int:
    h = 0xCBF29CE484222325
    for b in data:
        h ^= b
        h = (h * 0x100000001B3) & 0xFFFFFFFFFFFFFFFF
    return h


def canonical(field: str) -> str:
    """`field` as Rust's `{:e}` writes the same f64 (a non-number is kept)."""
    try:
        x = float(field)
    except ValueError:
        return field
    sign, digit_tuple, exp = decimal.Decimal(repr(x)).as_tuple()  # repr: shortest digits
    all_digits = "".join(map(str, digit_tuple))
    digits = all_digits.rstrip("0")
    if not digits:
        return ("-" if sign else "") + "0e0"
    exp10 = exp + len(all_digits) - 1
    mantissa = digits[0] + ("." + digits[1:] if len(digits) > 1 else "")
    return ("-" if sign else "") + f"{mantissa}e{exp10}"


def digest(csv_text: str) -> dict:
    lines = csv_text.rstrip("\n").split("\n")
    header = lines[0].split(",")
    idx = [header.index(c) for c in COLUMNS]
    rows = [",".join(canonical(f[i]) for i in idx) for f in (line.split(",") for line in lines)]
    return {"rows": len(rows) - 1, "fnv1a64": format(fnv1a64("\n".join(rows).encode()), "016x")}


def main() -> None:
    exe = sys.argv[1]
    scenarios = sorted((ROOT / "scenarios").glob("*.toml")) + sorted((ROOT / "scenarios" / "paper").glob("*.toml"))
    out = {"columns": COLUMNS, "made_by": "scripts/regression-baseline.py with the binary of commit f2009a6", "scenarios": {}}
    with tempfile.TemporaryDirectory() as tmp:
        for sc in scenarios:
            rel = sc.relative_to(ROOT).as_posix()
            csv = pathlib.Path(tmp) / "out.csv"
            js = pathlib.Path(tmp) / "out.json"
            r = subprocess.run([exe, "run", rel, "-o", str(csv), "--summary", str(js), "-q"], cwd=ROOT)
            summary = json.loads(js.read_text())
            for k in DROPPED:
                summary.pop(k, None)
            out["scenarios"][rel] = {"exit": r.returncode, "csv": digest(csv.read_text()), "summary": summary}
    path = ROOT / "tests" / "data" / "regress" / "baseline.json"
    path.write_text(json.dumps(out, indent=1, sort_keys=True) + "\n")
    print(f"wrote {path} ({len(scenarios)} scenarios)")


if __name__ == "__main__":
    main()
