"""`Steady.scenario(mode, eps, index)`: a steady motion started as a scenario, displaced
along one of its modes; a run of it grows at the predicted rate (the egg on its end
below its critical spin), and bad modes, sizes and rows are refused by name. And
`ellipsoid steady -o OUT.parquet`: read back with pyarrow, the table of the CSV."""

from __future__ import annotations

import math
import subprocess
from pathlib import Path

import numpy as np
import pytest

import ellipsoid

EGG = {
    "body": {"a": 0.02, "c": 0.03, "mass": 0.06, "inertia": "uniform"},
    "initial": {"theta": 0.0, "psi_dot": 100.0},
    "contact": {"model": "frictionless"},
    "output": {"t_end": 1.0, "dt": 0.01},
}


def critical_spin() -> float:
    """n_c = 2√(A m g (l − ρ))/C, A = m(a² + c²)/5, C = 2ma²/5, l = c, ρ = a²/c."""
    a, c, m, g = 0.02, 0.03, 0.06, 9.81
    big_a, big_c = m * (a * a + c * c) / 5.0, 2.0 * m * a * a / 5.0
    return 2.0 * math.sqrt(big_a * m * g * (c - a * a / c)) / big_c


def reaching(t: np.ndarray, theta: np.ndarray, level: float) -> float:
    """When θ first reaches `level`, interpolated in log θ."""
    k = int(np.argmax(theta >= level))
    assert k > 0 and theta[k - 1] < level
    l0, l1 = math.log(theta[k - 1]), math.log(theta[k])
    return float(t[k - 1] + (math.log(level) - l0) / (l1 - l0) * (t[k] - t[k - 1]))


def test_a_perturbed_steady_motion_grows_at_the_predicted_rate() -> None:
    scn = ellipsoid.Scenario(**EGG)
    spins = [0.3 * critical_spin(), 0.8 * critical_spin()]
    res = ellipsoid.steady(scn, "upright", vary={"initial.psi_dot": spins})
    for index in range(2):
        rate = float(res.eigenvalues[index, 0].real)
        assert rate > 0
        start = res.scenario(0, 1e-6, index=index)
        assert isinstance(start, ellipsoid.Scenario)
        assert res.scenario(res.modes[index][0], 1e-6, index=index) == start
        t_end = 16.0 / rate
        traj = ellipsoid.simulate(start, output={"t_end": t_end, "dt": t_end / 4000})
        assert traj.theta[0] < 2e-6
        fitted = math.log(10.0) / (reaching(traj.t, traj.theta, 1e-4) - reaching(traj.t, traj.theta, 1e-5))
        assert fitted == pytest.approx(rate, rel=0.01), (fitted, rate)


def test_bad_perturbations_are_refused() -> None:
    res = ellipsoid.steady(ellipsoid.Scenario(**EGG), "upright")
    with pytest.raises(ellipsoid.ScenarioError, match="index"):
        res.scenario(0, 1e-6, index=3)
    with pytest.raises(ellipsoid.ScenarioError, match="not a mode"):
        res.scenario("sideways", 1e-6)
    with pytest.raises(ellipsoid.ScenarioError, match="column from 0 to 3"):
        res.scenario(7, 1e-6)
    with pytest.raises(ellipsoid.ScenarioError, match="at most 0.1"):
        res.scenario(0, 0.5)


def test_steady_writes_parquet_equal_to_its_csv(cli: Path, tmp_path: Path) -> None:
    pd = pytest.importorskip("pandas")
    pytest.importorskip("pyarrow")
    scene = tmp_path / "egg.toml"
    scene.write_text(ellipsoid.Scenario(**EGG).text)
    for name in ("t.csv", "t.parquet"):
        subprocess.run([cli, "steady", scene, "--vary", "initial.psi_dot=40:160:7", "-o", tmp_path / name], check=True, capture_output=True)
    csv = pd.read_csv(tmp_path / "t.csv", dtype=str, keep_default_na=False)
    table = pd.read_parquet(tmp_path / "t.parquet")
    assert [c.split(" [")[0] for c in table.columns] == list(csv.columns)
    assert table.columns[0] == "initial.psi_dot [rad/s]"
    assert "lambda1_re [1/s]" in table.columns and "mode1" in table.columns
    assert len(table) == len(csv) == 7
    for parquet_name, name in zip(table.columns, csv.columns):
        got, want = list(table[parquet_name]), list(csv[name])
        if name == "stable" or name.startswith("mode") or name == "error":
            # a missing text value (null) reads back as None, or NaN in an all-null column
            assert ["" if v is None or (isinstance(v, float) and math.isnan(v)) else v for v in got] == want, name
        else:
            np.testing.assert_array_equal(np.array(got, dtype=float), [float(v) if v else math.nan for v in want], name)


def test_plot_draws_the_diagram_into_an_axes_and_returns_it() -> None:
    """`Steady.plot`: the egg's diagram against its spin. Each Re λ is a line over the
    values (the largest first drawn bold), the critical spin a vertical line at the
    analytic n_c, the frequencies on a twin axis, the shading green above n_c and red
    below; into a given Axes it draws there and returns it; a non-Axes is refused."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    spins = np.linspace(40.0, 160.0, 13)
    res = ellipsoid.steady(ellipsoid.Scenario(**EGG), vary={"initial.psi_dot": spins})
    n_c = critical_spin()
    fig, ax = plt.subplots()
    assert res.plot(ax=ax) is ax
    bold = [line for line in ax.get_lines() if line.get_label() == "largest Re λ"]
    assert len(bold) == 1
    assert np.array_equal(bold[0].get_ydata(), res.eigenvalues[:, 0].real)
    verticals = [line for line in ax.get_lines() if len(set(np.atleast_1d(line.get_xdata()))) == 1
                 and line.get_linestyle() == "--"]
    assert len(verticals) == 1 and abs(verticals[0].get_xdata()[0] / n_c - 1) < 1e-10
    twins = [a for a in fig.axes if a is not ax]
    assert len(twins) == 1 and twins[0].get_ylabel() == "|Im λ| (1/s)"
    spans = [(p.get_x(), p.get_x() + p.get_width(), p.get_facecolor()) for p in ax.patches]
    green, red = matplotlib.colors.to_rgba("#d6f0d6"), matplotlib.colors.to_rgba("#fad6d6")
    assert all(c == (green if lo >= n_c * (1 - 1e-12) else red) for lo, _, c in spans)
    assert min(lo for lo, _, c in spans if c == green) == pytest.approx(n_c, rel=1e-12)
    plt.close(fig)
    new = res.plot(frequencies=False)
    assert len(new.figure.axes) == 1
    plt.close(new.figure)
    with pytest.raises(ellipsoid.ScenarioError, match="ax"):
        res.plot(ax="left")


VISCOUS_TOP = {
    "body": {"a": 0.015, "c": 0.015, "mass": 6e-3, "com_offset": 0.003, "inertia": [8e-7, 8e-7, 7e-7]},
    "initial": {"theta": 0.0, "phi_dot": 180.0},
    "contact": {"model": "viscous", "viscous_friction": 1.0},
    "output": {"t_end": 1.0, "dt": 0.01},
}


def test_the_viscous_law_is_analysed_with_and_without_vary() -> None:
    """Under viscous sliding, `ellipsoid.steady` gives six eigenvalues per row; a sweep of
    I3 finds where the tippe top's upright spin (α = 0.2, 180 rad/s) destabilises, near
    the criterion's end I1/I3 = 1 − α, and single analyses just either side of it agree
    with the sweep's verdicts there and with its own eigenvalues at a swept value; a run
    started on an unstable spin displaced along its tilt grows at the predicted rate."""
    top = ellipsoid.Scenario(**VISCOUS_TOP)
    i3 = np.linspace(6e-7, 1.2e-6, 13)
    res = ellipsoid.steady(top, vary={"body.inertia[2]": i3})
    assert res.eigenvalues.shape == (13, 6) and res.phi_dot is None and res.circles is None
    assert set(m for row in res.modes for m in row) <= {"tilt", "slip"}
    (c,) = res.critical
    assert c["stable_side"] == "above" and 0.80 < 8e-7 / c["value"] < 0.82
    for factor, stable in ((1 + 1e-6, True), (1 - 1e-6, False)):
        one = ellipsoid.steady(top.replace(**{"body.inertia[2]": c["value"] * factor}))
        assert bool(one.stable[0]) is stable
    one = ellipsoid.steady(top.replace(**{"body.inertia[2]": float(i3[3])}))
    assert np.array_equal(one.eigenvalues[0], res.eigenvalues[3])
    # Started on the unstable upright spin at I3 = i3[3] (I1/I3 = 1.07), displaced 1e-6
    # along its tilt (by column, by name, or from the sweep's row): the tilt grows from
    # 1e-5 to 1e-4 rad at Re λ within 1 %.
    rate = float(one.eigenvalues[0, 0].real)
    assert rate > 0 and one.modes[0][0] == "tilt"
    start = one.scenario(0, 1e-6)
    assert one.scenario("tilt", 1e-6) == start
    assert res.scenario(0, 1e-6, index=3) == start
    t_end = 16.0 / rate
    traj = ellipsoid.simulate(start, output={"t_end": t_end, "dt": t_end / 4000})
    assert traj.theta[0] < 2e-6
    fitted = math.log(10.0) / (reaching(traj.t, traj.theta, 1e-4) - reaching(traj.t, traj.theta, 1e-5))
    assert fitted == pytest.approx(rate, rel=0.01), (fitted, rate)
