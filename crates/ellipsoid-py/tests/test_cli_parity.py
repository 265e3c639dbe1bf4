"""regress_*: Python gives the command-line tool's output for the same run — the same CSV
bytes, the same numbers, the same summary."""

from __future__ import annotations

import csv
import json
import subprocess
from pathlib import Path

import numpy as np
import pytest

import ellipsoid
from conftest import BUNDLED, REPO, scenario_id

# Fields of the summary that legitimately differ between two runs of the same scenario.
VOLATILE = {"wall_time_s", "output"}


def run_cli(cli: Path, scenario: str, out: Path, *sets: str) -> dict:
    args = [str(cli), "run", scenario, "-o", str(out / "cli.csv"), "--summary", str(out / "cli.json"), "--quiet"]
    for s in sets:
        args += ["--set", s]
    done = subprocess.run(args, cwd=REPO, capture_output=True, text=True, timeout=300)
    assert done.returncode in (0, 3), done.stderr
    return json.loads((out / "cli.json").read_text())


def read_csv(path: Path) -> tuple[list[str], list[list[str]]]:
    """Header and rows of a CSV trajectory, its `#` comment line skipped."""
    with open(path, newline="") as f:
        rows = list(csv.reader(line for line in f if not line.startswith("#")))
    return rows[0], rows[1:]


@pytest.mark.parametrize("path", BUNDLED, ids=scenario_id)
def test_regress_bundled_scenario_matches_the_cli(cli: Path, path: Path, tmp_path: Path, monkeypatch) -> None:
    monkeypatch.chdir(REPO)
    rel = str(path.relative_to(REPO))
    summary_cli = run_cli(cli, rel, tmp_path)
    traj = ellipsoid.simulate(rel)
    traj.to_csv(tmp_path / "py.csv")
    assert (tmp_path / "py.csv").read_bytes() == (tmp_path / "cli.csv").read_bytes()

    header, rows = read_csv(tmp_path / "cli.csv")
    assert header == list(traj.columns) and header[: len(ellipsoid.COLUMNS)] == list(ellipsoid.COLUMNS)
    assert len(traj) == len(rows)
    for j, name in enumerate(header):
        column = [r[j] for r in rows]
        if name == "mode":
            assert traj.mode.tolist() == column
        else:
            values = traj[name]
            assert values.dtype == np.float64
            # Shortest round-trip formatting: equality is bit for bit.
            np.testing.assert_array_equal(values, np.array(column, dtype=np.float64), err_msg=name)

    summary_py = traj.summary
    assert {k: v for k, v in summary_py.items() if k not in VOLATILE} == {k: v for k, v in summary_cli.items() if k not in VOLATILE}
    assert summary_py["output"] is None
    assert traj.status == summary_cli["status"]
    assert traj.events == summary_cli["events"]


def test_regress_overrides_match_cli_set(cli: Path, tmp_path: Path, monkeypatch) -> None:
    monkeypatch.chdir(REPO)
    sets = ("output.t_end=0.25", "contact.model=coulomb", "contact.friction=0.2", "initial.position=[0.1, -0.2]")
    summary_cli = run_cli(cli, "scenarios/nutation.toml", tmp_path, *sets)
    traj = ellipsoid.simulate(
        "scenarios/nutation.toml",
        output={"t_end": 0.25},
        contact={"model": "coulomb", "friction": 0.2},
        **{"initial.position": [0.1, -0.2]},
    )
    traj.to_csv(tmp_path / "py.csv")
    assert (tmp_path / "py.csv").read_bytes() == (tmp_path / "cli.csv").read_bytes()
    py = traj.summary
    assert py["overrides"] == ["output.t_end=0.25", "contact.model=\"coulomb\"", "contact.friction=0.2", "initial.position=[0.1, -0.2]"]
    for key in ("status", "events", "stats", "final", "drift", "samples"):
        assert py[key] == summary_cli[key], key


def test_regress_save_picks_the_format_like_cli_output(tmp_path: Path) -> None:
    traj = ellipsoid.simulate(str(REPO / "scenarios" / "billiard.toml"), output={"t_end": 0.1})
    traj.save(tmp_path / "a.csv")
    traj.to_csv(tmp_path / "b.csv")
    assert (tmp_path / "a.csv").read_bytes() == (tmp_path / "b.csv").read_bytes()
    with pytest.raises(ellipsoid.OutputError, match=r"unknown output format \"txt\"; use \.csv or \.h5"):
        traj.save(tmp_path / "a.txt")
