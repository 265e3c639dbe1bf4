"""Poincaré sections in Python: `Trajectory.sections` holds the points that `ellipsoid
run --sections` writes (the same numbers), each on its section; they survive pickling;
`plot_section` draws them and refuses bad arguments by name."""

from __future__ import annotations

import pickle
import subprocess
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import ellipsoid

from conftest import REPO

SCENARIOS = REPO / "scenarios"
SECTIONS = [
    {"name": "bottom", "column": "theta_dot", "crosses": 0.0, "direction": "up"},
    {"name": "tilt", "column": "theta", "crosses": 0.17},
]


def run() -> ellipsoid.Trajectory:
    return ellipsoid.simulate(SCENARIOS / "nutation.toml", output={"t_end": 3.0, "dt": 0.01}, section=SECTIONS)


def test_sections_hold_every_column_at_each_crossing() -> None:
    traj = run()
    assert set(traj.sections) == {"bottom", "tilt"}
    bottom = traj.sections["bottom"]
    assert list(bottom) == traj.columns
    n = len(bottom["t"])
    assert n >= 5
    assert all(len(v) == n for v in bottom.values())
    scale = np.abs(traj.theta_dot).max()
    assert np.all(np.abs(bottom["theta_dot"]) < 1e-10 * scale)
    assert np.all(np.abs(traj.sections["tilt"]["theta"] - 0.17) < 1e-10)
    assert np.all(np.diff(bottom["t"]) > 0)
    assert np.all(np.abs(bottom["energy"] - traj.energy[0]) < 1e-9 * abs(traj.energy[0]))
    assert set(bottom["mode"]) == {"frictionless"}


def test_sections_match_the_command_line_table(cli: Path, tmp_path: Path) -> None:
    traj = run()
    sets = "section=[" + ", ".join(
        "{ " + ", ".join(f"{k} = {v!r}".replace("'", '"') for k, v in s.items()) + " }" for s in SECTIONS
    ) + "]"
    out = tmp_path / "s.csv"
    subprocess.run(
        [cli, "run", SCENARIOS / "nutation.toml", "-q", "-o", tmp_path / "t.csv", "--set", "output.t_end=3",
         "--set", "output.dt=0.01", "--set", sets, "--sections", out],
        check=True,
    )
    table = pd.read_csv(out, comment="#")
    for name, points in traj.sections.items():
        rows = table[table["section"] == name]
        for column in traj.columns:
            if column != "mode":
                np.testing.assert_array_equal(rows[column].to_numpy(), points[column])


def test_sections_survive_pickling() -> None:
    traj = run()
    back = pickle.loads(pickle.dumps(traj))
    for name, points in traj.sections.items():
        for column, values in points.items():
            np.testing.assert_array_equal(back.sections[name][column], values)


def test_plot_section_draws_the_points_and_refuses_bad_arguments() -> None:
    pytest.importorskip("matplotlib")
    traj = run()
    ax = traj.plot_section("bottom", "phi", "theta")
    import matplotlib.pyplot as plt

    assert ax.figure is plt.gcf() and ax.figure.axes == [ax]
    fig, given = plt.subplots()
    assert traj.plot_section("bottom", "phi", "theta", ax=given) is given
    plt.close("all")
    x, y = ax.lines[0].get_data()
    np.testing.assert_array_equal(x, traj.sections["bottom"]["phi"])
    np.testing.assert_array_equal(y, traj.sections["bottom"]["theta"])
    assert ax.get_xlabel() == "phi (rad)"
    assert ax.get_ylabel() == "theta (rad)"
    # Issue 47: an angle drawn modulo 2π, in [0, 2π).
    ax = traj.plot_section("bottom", "phi", "theta", wrap="phi")
    x, y = ax.lines[0].get_data()
    phi = traj.sections["bottom"]["phi"]
    assert np.ptp(phi) > 4 * np.pi, "the run's φ turns more than twice, so the wrap is seen"
    assert np.all((0 <= x) & (x < 2 * np.pi))
    np.testing.assert_allclose(np.cos(x), np.cos(phi), atol=1e-12)
    np.testing.assert_allclose(np.sin(x), np.sin(phi), atol=1e-12)
    np.testing.assert_array_equal(y, traj.sections["bottom"]["theta"])
    assert ax.get_xlabel() == "phi (rad, modulo 2π)" and ax.get_ylabel() == "theta (rad)"
    plt.close("all")
    with pytest.raises(ellipsoid.ScenarioError, match="not an angle: its unit is rad/s"):
        traj.plot_section("bottom", "phi", "psi_dot", wrap=["phi", "psi_dot"])
    with pytest.raises(ellipsoid.ScenarioError, match="not a column of this plot"):
        traj.plot_section("bottom", "phi", "theta", wrap="psi")
    with pytest.raises(ellipsoid.ScenarioError, match="wrap"):
        traj.plot_section("bottom", "phi", "theta", wrap=3)
    with pytest.raises(ellipsoid.ScenarioError, match="not a section"):
        traj.plot_section("nowhere", "phi", "theta")
    with pytest.raises(ellipsoid.ScenarioError, match="not a numeric column"):
        traj.plot_section("bottom", "phi", "mode")
