"""ellipsoid.precision and ellipsoid.check: the command-line tool's `precision` and
`check`, as data, from the same library code (crates/ellipsoid-study)."""

from __future__ import annotations

import csv
import math
import re
import subprocess
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import ellipsoid
from conftest import BUNDLED, INTERRUPT_MAIN, REPO, interrupt_inside, scenario_id

NUTATION = REPO / "scenarios" / "nutation.toml"
SLIDING = REPO / "scenarios" / "paper-sliding.toml"
# Columns that depend on the machine's speed (the timing budget sets the repeats).
TIMING = {"wall_time_median_s", "wall_time_min_s", "repeats"}


@pytest.fixture(scope="module")
def nutation_quick() -> ellipsoid.PrecisionTable:
    return ellipsoid.precision(NUTATION, quick=True, t_end=0.5)


# ----------------------------------------------------------------- precision


def test_precision_error_falls_as_dop853_tightens(nutation_quick: ellipsoid.PrecisionTable) -> None:
    t = nutation_quick
    assert len(t) == 9 and set(t.measure) == {"period"}
    dop853 = t.method == "dop853"
    rtol, error = t.rtol[dop853], t.error[dop853]
    assert list(rtol) == [1e-4, 1e-7, 1e-10]
    # 1000× tighter rtol: at least 100× smaller error each time (as tests/cli_precision.rs).
    assert np.all(error[1:] * 100 < error[:-1]), error
    assert np.all(t.period_error[dop853] <= error) and np.all(np.isnan(t.state_error))
    # RK4 rows have a step and no tolerances; the adaptive rows the reverse.
    rk4 = t.method == "rk4"
    assert list(t.h[rk4]) == [1e-2, 1e-3, 1e-4] and np.all(np.isnan(t.h[~rk4]))
    assert np.all(np.isnan(t.rtol[rk4])) and np.all(t.atol[~rk4] == t.rtol[~rk4] * 1e-2)
    assert np.all(t.status == "completed") and np.all(t.t_final == 0.5)
    assert t.rhs_evals.dtype == np.int64 and np.all(t.rhs_evals > 0)
    ref = t.reference
    assert ref["measure"] == "period" and ref["period"] == pytest.approx(0.062209211760876, abs=1e-15)
    assert "exact nutation period T = 0.0622092117608" in t.summary
    assert t.notes == []


def test_precision_columns_are_read_only_and_named_like_the_csv(nutation_quick: ellipsoid.PrecisionTable) -> None:
    t = nutation_quick
    header = (REPO / "docs" / "performance" / "nutation-precision.csv").read_text().splitlines()[0]
    assert t.columns == header.split(",") == list(t.to_dict())
    with pytest.raises(ValueError):
        t.error[0] = 0.0
    pd = pytest.importorskip("pandas")
    df = t.to_pandas()
    assert isinstance(df, pd.DataFrame) and list(df.columns) == t.columns and len(df) == len(t)
    np.testing.assert_array_equal(df["rhs_evals"].to_numpy(), t.rhs_evals)


def read_csv(path: Path) -> dict[str, list[str]]:
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    return {name: [r[i] for r in rows[1:]] for i, name in enumerate(rows[0])}


def assert_table_matches_csv(table: ellipsoid.PrecisionTable, cells: dict[str, list[str]]) -> None:
    """Every non-timing column equal to the CSV's cells exactly (empty cell = NaN)."""
    assert list(cells) == table.columns
    for name, values in cells.items():
        if name in TIMING:
            continue
        col = getattr(table, name)
        if col.dtype.kind == "U":
            assert col.tolist() == values, name
        elif col.dtype.kind == "i":
            assert col.tolist() == [int(v) for v in values], name
        else:
            expected = [float(v) if v else math.nan for v in values]
            np.testing.assert_array_equal(col, expected, err_msg=name)


@pytest.mark.parametrize("path, t_end", [(NUTATION, "0.5"), (SLIDING, "0.1")], ids=["nutation", "paper-sliding"])
def test_precision_matches_the_command_line_tool(cli: Path, tmp_path: Path, path: Path, t_end: str) -> None:
    done = subprocess.run(
        [cli, "precision", path, "--quick", "--t-end", t_end, "-o", tmp_path / "cli", "-q"],
        capture_output=True, text=True, timeout=600,
    )
    assert done.returncode == 0, done.stderr
    table = ellipsoid.precision(path, quick=True, t_end=float(t_end), out=tmp_path / "py")
    assert_table_matches_csv(table, read_csv(tmp_path / "cli" / "precision.csv"))
    # `out` wrote the same three files; the table's own CSV is the one written.
    assert sorted(p.name for p in (tmp_path / "py").iterdir()) == ["error_vs_evaluations.svg", "error_vs_time.svg", "precision.csv"]
    assert_table_matches_csv(table, read_csv(tmp_path / "py" / "precision.csv"))
    table.to_csv(tmp_path / "again.csv")
    assert (tmp_path / "again.csv").read_bytes() == (tmp_path / "py" / "precision.csv").read_bytes()
    # Evaluations do not depend on timing: that plot is the command line's byte for byte.
    assert (tmp_path / "py" / "error_vs_evaluations.svg").read_bytes() == (tmp_path / "cli" / "error_vs_evaluations.svg").read_bytes()
    # The printed table, but for its timings (and the `wrote` line).
    number = re.compile(r"\d\.\d{3}e-?\d+")
    printed = done.stdout.rsplit("wrote ", 1)[0]
    if "cheapest" in printed:  # the cheapest setting is chosen by time: compare up to there
        printed, summary = printed.split("cheapest")[0], table.summary.split("cheapest")[0]
    assert number.sub("T", printed) == number.sub("T", summary)
    paths = table.write(tmp_path / "written")
    assert [p.name for p in paths] == ["precision.csv", "error_vs_time.svg", "error_vs_evaluations.svg"]


def test_precision_on_a_sliding_scene_measures_the_final_state() -> None:
    t = ellipsoid.precision(SLIDING, quick=True, t_end=0.05, repeats=1)
    assert set(t.measure) == {"final_state"} and np.all(np.isnan(t.period_error))
    np.testing.assert_array_equal(t.error, t.state_error)
    assert np.all(t.repeats >= 1)
    ref = t.reference
    assert ref["measure"] == "final_state" and ref["rtol"] == 1e-14 and 0 <= ref["uncertainty"] < 1e-10
    dop853 = t.method == "dop853"
    assert np.all(t.error[dop853][1:] * 10 < t.error[dop853][:-1]), t.error[dop853]


def test_precision_applies_changes_and_accepts_a_scenario() -> None:
    s = ellipsoid.load(SLIDING)
    changes: dict[str, Any] = {"contact.friction": 0.2}
    t = ellipsoid.precision(s, quick=True, t_end=0.05, **changes)
    u = ellipsoid.precision(s.replace(contact={"friction": 0.2}), quick=True, t_end=0.05)
    np.testing.assert_array_equal(t.error, u.error)
    assert repr(t).startswith('<ellipsoid.PrecisionTable "paper-sliding": 9 settings')


@pytest.mark.parametrize(
    "options, key, value, needles",
    [
        ({"t_end": 11.0}, "t_end", "11", ["t_end=11: ", "h = 1e-6 s would take 11000000 steps", "give t_end=10 or less, or use quick=True"]),
        ({"t_end": -1.0, "quick": True}, "t_end", "-1", ["t_end=-1: the end time must be positive and finite (s)"]),
        ({"t_end": math.inf, "quick": True}, "t_end", "inf", ["t_end=inf: the end time must be positive and finite"]),
        ({"t_end": "1", "quick": True}, "t_end", "'1'", ["t_end='1': expected a number"]),
        ({"quick": True, "t_end": 0.1, "repeats": 0}, "repeats", "0", ["repeats=0: give 1 to 1000 timed runs per setting"]),
        ({"quick": True, "t_end": 0.1, "repeats": -2}, "repeats", "-2", ["repeats=-2: give 1 to 1000"]),
        ({"quick": True, "t_end": 0.1, "repeats": 10**30}, "repeats", str(10**30), ["give 1 to 1000"]),
        ({"quick": True, "t_end": 0.1, "repeats": 2.0}, "repeats", "2.0", ["repeats=2.0: expected an int"]),
    ],
)
def test_precision_refuses_bad_options_before_running_and_writes_nothing(
    tmp_path: Path, options: dict[str, Any], key: str, value: str, needles: list[str]
) -> None:
    with pytest.raises(ellipsoid.ScenarioError) as info:
        ellipsoid.precision(SLIDING, out=tmp_path / "report", **options)
    e = info.value
    assert (e.kind, e.key, e.value) == ("invalid", key, value), str(e)
    assert str(e).endswith(e.rule)
    for n in needles:
        assert n in str(e), str(e)
    assert not (tmp_path / "report").exists()


def test_precision_bad_scenario_change_is_a_scenario_error() -> None:
    with pytest.raises(ellipsoid.ScenarioError, match="body.mass") as info:
        changes: dict[str, Any] = {"body.mass": -1}
        ellipsoid.precision(SLIDING, quick=True, **changes)
    assert info.value.key == "body.mass"


def test_precision_output_error_is_an_oserror(tmp_path: Path) -> None:
    (tmp_path / "file").write_text("x")
    with pytest.raises(ellipsoid.OutputError):
        ellipsoid.precision(SLIDING, quick=True, t_end=0.02, out=tmp_path / "file" / "sub")


def test_precision_without_an_exact_period_says_why_and_measures_the_final_state() -> None:
    # A frictionless triaxial body: no one-degree-of-freedom reduction, so no exact period.
    t = ellipsoid.precision(NUTATION, quick=True, t_end=0.2, body={"b": 0.02, "inertia": [9e-6, 8e-6, 1.2e-5]})
    assert set(t.measure) == {"final_state"}
    assert len(t.notes) == 1 and "no exact period reference (not a body of revolution" in t.notes[0]


def test_precision_without_a_clean_reference_is_a_simulation_error() -> None:
    # The needle of test_run.py: sliding with mu = 1 reaches a Painleve inconsistency at
    # t = 0.034 s, so the DOP853 reference run cannot finish.
    needle = ellipsoid.Scenario(
        body=dict(a=0.005, c=0.1, mass=0.1, inertia="uniform"),
        initial=dict(theta=0.3, velocity=[1.0, 0.0]),
        contact=dict(model="sliding", friction=1.0),
        output=dict(t_end=0.2, dt=1e-3),
    )
    with pytest.raises(ellipsoid.SimulationError, match=r"^no reference: the DOP853 reference run at rtol = 1e-14 did not finish cleanly \(painleve\)") as info:
        ellipsoid.precision(needle, quick=True, t_end=0.1)
    e = info.value
    assert e.status == "painleve" and e.trajectory.status == "painleve" and len(e.trajectory) == 0
    assert 0.03 < e.trajectory.summary["final"]["t"] < 0.04


def test_ctrl_c_interrupts_the_precision_study() -> None:
    # The full grid over 10 s takes minutes (RK4 alone makes 10^7 steps at h = 1e-6 s);
    # the interrupt comes once another thread sees it running (see conftest).
    interrupt_inside(INTERRUPT_MAIN, ellipsoid.precision, NUTATION)
    assert len(ellipsoid.precision(SLIDING, quick=True, t_end=0.02)) == 9


# ----------------------------------------------------------------- check

NUM = re.compile(r"(?<![\w^.\-])-?\d+(?:\.\d+)?(?:e-?\d+)?(?![\w.])")


def numbers(text: str) -> list[float]:
    """The numbers of a printed line (not the digits of units such as m^2 or A^-2)."""
    return [float(x) for x in NUM.findall(text)]


def printed_check(cli: Path, path: Path, *sets: str) -> dict[str, str]:
    args: list[str | Path] = [cli, "check", path]
    for s in sets:
        args += ["--set", s]
    done = subprocess.run(args, capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr
    out: dict[str, str] = {}
    last = ""
    for line in done.stdout.splitlines():
        label, text = line[:21].strip(), line[22:]
        if line.startswith("[check] ") and not line[21:22] == " ":
            label, text = line.split(" relative")[0], "relative" + line.split(" relative", 1)[1]
        if not label:  # a continuation line (the world contact point)
            label = last + " (world)"
        out[label] = text
        last = label
    return out


def assert_check_equals_printed(d: dict[str, Any], p: dict[str, str]) -> None:
    body, init, solver = d["body"], d["initial"], d["solver"]
    overrides = f" (--set {', --set '.join(d['overrides'])})" if d["overrides"] else ""
    assert p["scenario"] == d["scenario"] + overrides
    assert numbers(p["semi-axes a, b, c"]) == body["semi_axes"] and f"({body['shape']})" in p["semi-axes a, b, c"]
    assert numbers(p["mass"]) == [body["mass"]]
    assert numbers(p["inertia about G"]) == [x for row in body["inertia"] for x in row]
    assert numbers(p["principal moments"]) == body["principal_moments"]
    com = numbers(p["CM offset G - C0"])
    assert com[:3] == body["com_offset"] and f"= {body['com_offset_radial']:.4f}," in p["CM offset G - C0"]
    assert numbers(p["gravity"]) == [d["gravity"]]
    contact = p["contact model"]
    assert contact.split()[0] == d["contact"]["model"]
    friction = d["contact"]["friction"]
    assert numbers(contact) == ([] if friction is None else [friction])
    effects = list(d["effects"].values())  # every optional effect, in the printed order
    expected_effects = [v for e in effects if e for v in e.values()]
    assert numbers(p["effects"]) == expected_effects and (p["effects"] == "none") == (not expected_effects)
    angles = numbers(p["initial angles"])
    assert [angles[0], angles[2], angles[3]] == [init["theta"], init["phi"], init["psi"]]
    assert f"({init['theta_deg']:.4f} deg)" in p["initial angles"]
    if init["rates"] is None:
        assert init["omega_body_given"] and "initial rates" not in p and p["initial omega (body)"].endswith("(given)")
    else:
        assert numbers(p["initial rates"]) == [init["rates"][k] for k in ("theta_dot", "phi_dot", "psi_dot")]
    assert numbers(p["initial omega (body)"]) == init["omega_body"]
    assert numbers(p["contact point C"]) == init["contact_point"]
    assert numbers(p["contact point C (world)"])[:3] == init["contact_point_world"]
    assert numbers(p["height of G"]) == [init["height"]]
    assert p["initial mode"] == init["mode"]
    assert numbers(p["initial N"]) == [init["normal_force"], body["weight"]]
    assert numbers(p["initial energy"]) == [init["energy"]]
    assert numbers(p["initial slip speed"]) == [init["slip_speed"]]
    assert p["invariants checked"].split(", ") == d["invariants"]
    s = p["solver"]
    assert s.split(",")[0] == solver["method"]
    if solver["step"] is not None:
        assert numbers(s) == [solver["step"]] and solver["rtol"] is None
    else:
        expected = [solver["rtol"], solver["atol"]] + ([solver["initial_step"]] if solver["initial_step"] else [])
        assert numbers(s) == expected
    assert numbers(p["output"]) == [d["output"]["t_end"], d["output"]["samples"]]
    tilts = body["two_contact_tilts"]
    if tilts:  # the printed line is the last θ*'s (a label repeats)
        assert numbers(p["two contacts"])[0] == tilts[-1]["theta"]
        assert p["two contacts"].startswith(" and ".join(tilts[-1]["surfaces"]) + " at theta* = ")
    elif tilts is None:
        assert "not of revolution" in p["two contacts"]
    assert p.get("[check] status") == d["check"]["status"]
    drifts = {k[len("[check] "):]: numbers(v)[0] for k, v in p.items() if k.startswith("[check] ") and k != "[check] status"}
    assert drifts == d["check"]["drift"]


@pytest.mark.parametrize("path", BUNDLED, ids=scenario_id)
def test_check_returns_what_the_command_line_prints(cli: Path, path: Path) -> None:
    assert_check_equals_printed(ellipsoid.check(path), printed_check(cli, path))


@pytest.mark.parametrize(
    "path, sets, changes",
    [
        (NUTATION, ["initial.theta_deg=30"], {"initial.theta_deg": 30}),
        (NUTATION, ["solver.method=rk4", "solver.step=1e-3"], {"solver": {"method": "rk4", "step": 1e-3}}),
        (
            REPO / "scenarios" / "air-drag.toml",
            ["effects.rolling_resistance=1e-4", "effects.spin_friction={ coefficient = 2e-4, regularisation = 1e-2 }"],
            {"effects": {"rolling_resistance": 1e-4, "spin_friction": {"coefficient": 2e-4, "regularisation": 1e-2}}},
        ),
    ],
    ids=["tilted", "rk4", "all-effects"],
)
def test_check_with_changes_returns_what_the_command_line_prints(cli: Path, path: Path, sets: list[str], changes: dict[str, Any]) -> None:
    d = ellipsoid.check(path, **changes)
    p = printed_check(cli, path, *sets)
    p.pop("scenario")  # the overrides are spelled differently
    d["overrides"] = []
    assert_check_equals_printed(d, {"scenario": d["scenario"], **p})


def test_check_of_a_given_omega_returns_what_the_command_line_prints(cli: Path, tmp_path: Path) -> None:
    path = tmp_path / "spun.toml"
    path.write_text(NUTATION.read_text().replace("psi_dot = 60.0", "omega_body = [1.0, 2.0, 60.0]"))
    d = ellipsoid.check(path)
    assert d["initial"]["omega_body_given"] and d["initial"]["rates"] is None
    assert_check_equals_printed(d, printed_check(cli, path))


def test_check_is_data() -> None:
    d = ellipsoid.check(NUTATION, output={"t_end": 2.0})
    assert d["output"] == {"t_end": 2.0, "samples": 2001}
    assert d["overrides"] and d["body"]["shape"] == "oblate spheroid"
    assert d["initial"]["mode"] == "frictionless" and 0 < d["initial"]["normal_force"] < d["body"]["weight"]
    assert d["effects"] == {"rolling_resistance": None, "spin_friction": None, "air_drag": None,
                            "rolling_friction": None, "air_film": None, "air_boundary_layer": None}
    # The same values a run starts from.
    traj = ellipsoid.simulate(NUTATION, output={"t_end": 0.01})
    assert traj.normal_force[0] == d["initial"]["normal_force"] and traj.energy[0] == d["initial"]["energy"]
    assert traj.z[0] == d["initial"]["height"]
    assert d["invariants"] == [k for k, v in traj.summary["drift"].items() if v is not None]


def test_check_gives_the_tilt_at_which_two_surfaces_touch(tmp_path: Path) -> None:
    """Issue 47: θ* of the tippe top with its stem, against its closed form: the ball
    (r1 = 15 mm, about C0) and the stem (r2 = 5 mm, centre 13 mm up the axis) touch at
    once where r1 = r2 − 13 mm cos θ (docs/physics.md, "Contact spheres")."""
    stem = REPO / "scenarios" / "tippe-top-stem.toml"
    (tilt,) = ellipsoid.check(stem)["body"]["two_contact_tilts"]
    assert tilt["surfaces"] == ["ellipsoid", "stem"]
    assert tilt["theta"] == pytest.approx(math.acos((0.005 - 0.015) / 0.013), rel=1e-14, abs=0)
    assert tilt["theta_deg"] == pytest.approx(140.28, abs=0.005)
    assert ellipsoid.check(NUTATION)["body"]["two_contact_tilts"] == []
    # An off-axis sphere: θ* depends on the heading, and is not given.
    off = tmp_path / "off.toml"
    off.write_text(stem.read_text().replace("center = [0.0, 0.0, 0.013]", "center = [0.002, 0.0, 0.013]"))
    assert ellipsoid.check(off)["body"]["two_contact_tilts"] is None


def test_check_refuses_a_bad_scenario_like_the_command_line() -> None:
    with pytest.raises(ellipsoid.ScenarioError, match="body.mass = 0: the mass must be positive") as info:
        ellipsoid.check(NUTATION, **{"body.mass": 0})
    assert info.value.key == "body.mass"
    with pytest.raises(TypeError):
        ellipsoid.check(42)  # type: ignore[arg-type]
