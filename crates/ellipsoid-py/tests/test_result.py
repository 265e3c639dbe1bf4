"""A result a solve_ivp user already knows: `sol`, `t_events`/`y_events`, `success`,
`nfev`, `states`, `t_eval`/`method`, pickling, `repr`, pandas and xarray views."""

from __future__ import annotations

import pickle
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np
import pytest

import ellipsoid
from conftest import REPO, oblate

SCENARIOS = REPO / "scenarios"
INVERTED = {"name": "inverted", "column": "theta", "crosses": 1.5707963, "direction": "up", "terminal": False}


def tippe_top(t_end: float = 1.5) -> ellipsoid.Trajectory:
    return ellipsoid.simulate(SCENARIOS / "tippe-top.toml", output={"t_end": t_end}, observe=[INVERTED])


def test_sol_is_a_rerun_at_those_times_in_any_order() -> None:
    traj = tippe_top()
    ts = np.array([1.2, 0.0, 0.3337, 1.2, 0.75, 1.5])
    at = traj.sol(ts)
    np.testing.assert_array_equal(at.t, ts)  # the order given, repeats kept
    rerun = ellipsoid.simulate(traj.scenario, t_eval=np.unique(ts))
    order = np.searchsorted(np.unique(ts), ts)
    for name in ellipsoid.COLUMNS:
        np.testing.assert_array_equal(getattr(at, name), getattr(rerun, name)[order], err_msg=name)
    # At the run's own sample times it is the run itself (the steps do not depend on them).
    again = traj.sol(traj.t)
    for name in ("theta", "phi", "x", "omega_z", "energy", "work", "slip_speed"):
        np.testing.assert_array_equal(getattr(again, name), getattr(traj, name), err_msg=name)
    assert len(traj.sol(0.5)) == 1
    with pytest.raises(ellipsoid.ScenarioError, match=r"t = 2: Trajectory.sol: every time must lie in \[0, 1.5\] s, the span of the run"):
        traj.sol([0.1, 2.0])


def test_sol_between_samples_conserves_what_the_scene_conserves() -> None:
    """Frictionless body of revolution: E, L_z and ω·e3* are conserved; the dense output
    at times off the sample grid keeps E to the solver's tolerance (an interpolant that
    were merely linear between 1 ms samples would miss it by ~1e-6)."""
    traj = ellipsoid.simulate(oblate())
    ts = np.linspace(0.0, 1.0, 997)[1:-1] + 1.234e-4
    at = traj.sol(ts)
    e0 = traj.energy[0]
    assert np.max(np.abs(at.energy - e0)) / abs(e0) < 1e-10
    linear = np.interp(ts, traj.t, traj.theta)
    assert np.max(np.abs(at.theta - linear)) > 1e-8, "the interpolant is not the samples'"


def test_sol_across_flight_and_impacts() -> None:
    traj = ellipsoid.simulate(SCENARIOS / "drop.toml", output={"t_end": 0.6})
    kinds = {e["kind"] for e in traj.events}
    assert {"touchdown", "impact"} <= kinds, kinds
    t_hit = traj.t_events["touchdown"][0]
    ts = np.array([0.5 * t_hit, t_hit, 0.5 * (t_hit + traj.t[-1])])
    at = traj.sol(ts)
    assert at.mode[0] == "flight"
    assert abs(at.gap[1]) < 1e-9, "the body touches the plane at the touchdown's time"
    g = traj.scenario.text  # free fall before the touchdown: z(t) = z0 + vz0 t − g t²/2
    assert "gravity" not in g or "9.81" in g
    z = traj.z[0] + traj.vz[0] * ts[0] - 0.5 * 9.81 * ts[0] ** 2
    assert abs(at.z[0] - z) < 1e-12


def test_events_by_name_and_kind() -> None:
    traj = tippe_top()
    te, ye = traj.t_events, traj.y_events
    assert set(te) == set(ye) and "inverted" in te and "slip_stop" in te and "impact" in te
    assert te["impact"].shape == (0,) and ye["impact"].shape == (0, len(traj.state_names))
    for e in traj.events:
        key = e.get("name", e["kind"])
        assert e["t"] in te[key]
    theta = traj.state_names.index("theta")
    # An observable's state is located with it: θ is the value crossed.
    assert abs(ye["inverted"][0, theta] - INVERTED["crosses"]) < 1e-12
    # A built-in event's state is the dense output there: at the slip stop the contact
    # point stops (slip speed from the rerun at that time).
    t_stop = te["slip_stop"][0]
    assert traj.sol(t_stop).slip_speed[0] < 1e-9
    np.testing.assert_array_equal(ye["slip_stop"][0], traj.sol(t_stop).states[:, 0])


def test_success_status_code_nfev_message() -> None:
    done = ellipsoid.simulate(oblate(output=dict(t_end=0.1, dt=1e-2)))
    assert done.success and done.status_code == 0 and done.nfev == done.summary["stats"]["rhs_evals"] > 0
    assert done.message.startswith("reached t_end")
    stopped = ellipsoid.simulate(oblate(output=dict(t_end=1.0, dt=1e-2)), observe=[{"name": "half", "column": "t", "crosses": 0.5, "terminal": True}])
    assert stopped.status == "observed" and stopped.success and stopped.status_code == 1
    failed = ellipsoid.simulate(SCENARIOS / "nutation.toml", solver={"max_steps": 5}, output={"t_end": 1.0})
    assert not failed.success and failed.status_code == -1 and "steps" in failed.message


def test_states_matrix_rows_are_the_named_columns() -> None:
    traj = tippe_top(0.2)
    assert traj.states.shape == (len(traj.state_names), len(traj))
    for row, name in zip(traj.states, traj.state_names):
        np.testing.assert_array_equal(row, getattr(traj, name))
    np.testing.assert_array_equal(traj.states[traj.state_names.index("y")], traj.y)  # y is G's y
    assert not traj.states.flags.writeable


def test_t_eval_and_scipy_method_names() -> None:
    ts = np.array([0.0, 0.013, 0.25, 0.5])
    traj = ellipsoid.simulate(SCENARIOS / "nutation.toml", t_eval=ts, method="RK45", output={"t_end": 0.5})
    np.testing.assert_array_equal(traj.t, ts)
    assert 'solver.method="dopri5"' in traj.scenario.overrides
    assert traj.scenario.sample_times.tolist() == ts.tolist()
    ref = ellipsoid.simulate(SCENARIOS / "nutation.toml", t_eval=ts, method="dop853", output={"t_end": 0.5})
    np.testing.assert_allclose(traj.theta, ref.theta, rtol=0, atol=1e-7)  # two methods, one motion
    # The scenario rebuilds from its text and changes (dt removed, times set).
    assert pickle.loads(pickle.dumps(traj.scenario)) == traj.scenario
    with pytest.raises(ellipsoid.ScenarioError, match="t_eval = 0.1 after 0.2: the times in t_eval must be strictly increasing"):
        ellipsoid.simulate(SCENARIOS / "nutation.toml", t_eval=[0.2, 0.1])
    with pytest.raises(ellipsoid.ScenarioError, match=r"t_eval = 20: every time in t_eval must lie in \[0, t_end\]"):
        ellipsoid.simulate(SCENARIOS / "nutation.toml", t_eval=[0.0, 20.0])
    with pytest.raises(ellipsoid.ScenarioError, match="method = \"lsoda\": .*LSODA have no counterpart"):
        ellipsoid.simulate(SCENARIOS / "nutation.toml", method="LSODA")
    with pytest.raises(ellipsoid.ScenarioError, match="solver.step"):
        ellipsoid.simulate(SCENARIOS / "nutation.toml", method="rk4")


def test_solve_ivp_tolerances_rtol_and_atol() -> None:
    """`rtol=`, `atol=` as solve_ivp's: they are solver.rtol and solver.atol, and they
    override the scenario's own (the file's 1e-11 and 1e-13, and a `solver` change)."""
    path = SCENARIOS / "nutation.toml"
    short = {"output": {"t_end": 0.5}}
    traj = ellipsoid.simulate(path, rtol=1e-8, atol=1e-10, **short)
    ref = ellipsoid.simulate(path, solver={"rtol": 1e-8, "atol": 1e-10}, **short)
    np.testing.assert_array_equal(traj.theta, ref.theta)
    assert traj.nfev == ref.nfev < ellipsoid.simulate(path, **short).nfev
    changed = dict(o.split("=", 1) for o in traj.scenario.overrides)
    assert float(changed["solver.rtol"]) == 1e-8 and float(changed["solver.atol"]) == 1e-10
    clash = ellipsoid.simulate(path, solver={"rtol": 1e-6, "atol": 1e-6}, rtol=1e-8, atol=np.float64(1e-10), **short)
    np.testing.assert_array_equal(clash.theta, ref.theta)
    only = ellipsoid.simulate(path, rtol=1e-8, **short)
    assert only.nfev == ellipsoid.simulate(path, solver={"rtol": 1e-8}, **short).nfev
    with pytest.raises(ellipsoid.ScenarioTypeError, match="rtol: expected a number, found str"):
        ellipsoid.simulate(path, rtol="tight")
    with pytest.raises(ellipsoid.ScenarioTypeError, match="atol: expected a number, found bool"):
        ellipsoid.simulate(path, atol=True)
    with pytest.raises(ellipsoid.ScenarioError, match="solver.rtol = -1"):
        ellipsoid.simulate(path, rtol=-1.0)
    with pytest.raises(ellipsoid.ScenarioError, match="solver.atol = NaN: the absolute tolerance must be positive and finite"):
        ellipsoid.simulate(path, atol=float("nan"))


def test_t_eval_takes_any_array_of_times_as_output_dt_samples() -> None:
    """`t_eval` of the times `output.dt` gives: the same samples; an array of another
    dtype, a strided view or a list is taken too; the scenario pickles."""
    path = SCENARIOS / "nutation.toml"
    grid = ellipsoid.simulate(path, output={"t_end": 0.5, "dt": 0.01})
    for ts in (np.linspace(0.0, 0.5, 51), np.linspace(0.0, 0.5, 101)[::2], np.linspace(0.0, 0.5, 51).tolist(),
               np.linspace(0.0, 0.5, 51).astype(np.float32).astype(np.float64)):
        traj = ellipsoid.simulate(path, t_eval=ts, output={"t_end": 0.5})
        np.testing.assert_array_equal(traj.t, np.asarray(ts, dtype=float))
        if np.array_equal(traj.t, grid.t):
            np.testing.assert_array_equal(traj.theta, grid.theta)
        assert pickle.loads(pickle.dumps(traj.scenario)).sample_times.tolist() == traj.t.tolist()
    # times k·dt from 0 to t_end are the scenario's own dt grid, recorded as such
    arange = ellipsoid.simulate(path, t_eval=np.arange(0.0, 0.5 + 0.005, 0.01), output={"t_end": 0.5})
    assert "output.dt=0.01" in arange.scenario.overrides
    np.testing.assert_array_equal(arange.scenario.sample_times, grid.scenario.sample_times)
    np.testing.assert_array_equal(arange.theta, grid.theta)
    ints = ellipsoid.simulate(path, t_eval=np.arange(0, 3), output={"t_end": 2.0})
    assert ints.t.tolist() == [0.0, 1.0, 2.0]
    tiny = ellipsoid.simulate(path, t_eval=[0.0, 1e-300, 0.1], output={"t_end": 0.1})
    assert tiny.t.tolist() == [0.0, 1e-300, 0.1]
    with pytest.raises(ellipsoid.ScenarioTypeError, match="t_eval: expected a sequence of output times"):
        ellipsoid.simulate(path, t_eval=["a", "b"])


def _run(path: str) -> ellipsoid.Trajectory:
    return ellipsoid.simulate(path, output={"t_end": 0.3})


def test_trajectory_and_scenario_pickle_and_cross_processes(tmp_path: Path) -> None:
    traj = tippe_top(0.8)
    back = pickle.loads(pickle.dumps(traj))
    assert back.summary == traj.summary and back.success == traj.success and len(back) == len(traj)
    for name in ellipsoid.COLUMNS:
        np.testing.assert_array_equal(getattr(back, name), getattr(traj, name), err_msg=name)
    traj.to_csv(tmp_path / "a.csv")
    back.to_csv(tmp_path / "b.csv")
    assert (tmp_path / "a.csv").read_bytes() == (tmp_path / "b.csv").read_bytes()
    original = ellipsoid.simulate(SCENARIOS / "nutation.toml", solver={"max_steps": 5})
    failed = pickle.loads(pickle.dumps(original))
    assert not failed.success and failed.status == original.status == "solver_failure"
    assert failed.status_code == original.status_code == -1 and failed.summary == original.summary
    assert failed.events == original.events and failed.message == original.message
    with ProcessPoolExecutor(2) as pool:
        got = list(pool.map(_run, [str(SCENARIOS / "nutation.toml"), str(SCENARIOS / "billiard.toml")]))
    assert [g.completed for g in got] == [True, True]
    np.testing.assert_array_equal(got[0].theta, _run(str(SCENARIOS / "nutation.toml")).theta)


def test_repr_shows_the_values() -> None:
    traj = tippe_top(0.2)
    r = repr(traj)
    assert "tippe-top.toml" in r and f"{len(traj)} samples" in r and "completed (success)" in r
    assert f"nfev = {traj.nfev}" in r and "final theta = " in r
    s = repr(traj.scenario)
    assert "coulomb" in s and "a = 0.015 m" in s and "t_end = 0.2 s" in s and "output.t_end=0.2" in s


def test_to_pandas_and_to_xarray_carry_units() -> None:
    pd = pytest.importorskip("pandas")
    xr = pytest.importorskip("xarray")
    traj = tippe_top(0.2)
    df = traj.to_pandas()
    assert isinstance(df, pd.DataFrame) and df.index.name == "t" and "t" not in df.columns
    assert df.attrs["units"]["theta"] == "rad" and df.attrs["status"] == "completed"
    np.testing.assert_array_equal(df.loc[traj.t[5], "theta"], traj.theta[5])
    ds = traj.to_xarray()
    assert isinstance(ds, xr.Dataset) and ds["theta"].attrs["units"] == "rad" and ds["t"].attrs["units"] == "s"
    np.testing.assert_array_equal(ds["omega_world_z"].values, traj.omega_world_z)
    assert list(ds["mode"].values[:1]) == [traj.mode[0]]


def test_study_table_as_plain_floats_and_as_an_n_d_dataset() -> None:
    pytest.importorskip("pandas")
    pytest.importorskip("xarray")
    base = oblate(output=dict(t_end=0.05, dt=1e-2))
    axes = {"initial.psi_dot": [40.0, 60.0], "initial.theta": [0.1, 0.2, 0.3]}
    df = ellipsoid.study(base, axes, outcomes={"final": ["theta"]})
    assert str(df["final.theta [rad]"].dtype) == "float64" and str(df["drift.jellett [1]"].dtype) == "float64"
    assert df["drift.jellett [1]"].isna().all()  # not conserved here: NaN, not pd.NA
    assert df.attrs["axes"] == ["initial.psi_dot [rad/s]", "initial.theta [rad]"] and df.attrs["combine"] == "grid"
    ds = ellipsoid.to_xarray(df)
    assert dict(ds.sizes) == {"initial.psi_dot": 2, "initial.theta": 3}
    assert ds["initial.psi_dot"].attrs["units"] == "rad/s" and ds["initial.theta"].attrs["units"] == "rad"
    final = ds["final.theta"]
    assert final.attrs["units"] == "rad" and final.shape == (2, 3) and final.dtype == np.float64
    # each cell is its own run: θ(0.05 s) of the run at that (ψ̇, θ0)
    run = ellipsoid.simulate(base.replace(initial={"psi_dot": 60.0, "theta": 0.3}))
    assert float(final.sel({"initial.psi_dot": 60.0, "initial.theta": 0.3})) == run.theta[-1]
    zipped = ellipsoid.study(base, axes | {"initial.theta": [0.1, 0.2]}, combine="zip")
    assert list(ellipsoid.to_xarray(zipped).sizes) == ["point"]
    # the nullable opt-in gives the same Dataset
    nullable = ellipsoid.study(base, axes, outcomes={"final": ["theta"]}, nullable=True)
    assert str(nullable["final.theta [rad]"].dtype) == "Float64"
    np.testing.assert_array_equal(ellipsoid.to_xarray(nullable)["final.theta"].values, final.values)


def test_to_xarray_names_have_no_unit_and_select_by_key() -> None:
    """A study's Dataset is named by the scenario keys and outcomes without `[unit]`
    (dims "contact.friction", variables "t_flip", "max.theta"), each unit in its
    `attrs["units"]`, so `ds.sel({"contact.friction": 0.05})` works and xarray's plots
    label an axis `max.theta [rad]` once."""
    pytest.importorskip("pandas")
    pytest.importorskip("xarray")
    base = ellipsoid.load(SCENARIOS / "tippe-top.toml", output={"t_end": 0.2},
                          observe=[{"name": "flip", "column": "theta", "crosses": 1.0, "direction": "up"}])
    df = ellipsoid.study(base, {"contact.friction": [0.05, 0.3], "initial.phi_dot": [100.0, 180.0]},
                         outcomes={"max": ["theta"]})
    ds = ellipsoid.to_xarray(df)
    assert set(ds.dims) == {"contact.friction", "initial.phi_dot"}
    assert {"t_flip", "max.theta", "t_final", "drift.energy", "wall_time", "rhs_evals", "status"} <= set(ds.data_vars)
    assert not any("[" in str(n) for n in ds.variables)
    assert ds["t_flip"].attrs["units"] == "s" and ds["max.theta"].attrs["units"] == "rad"
    assert ds["contact.friction"].attrs["units"] == "1" and "units" not in ds["rhs_evals"].attrs
    assert np.isnan(ds["t_flip"].values).all() and ds["t_flip"].dtype == np.float64  # no flip in 0.2 s
    low = ds.sel({"contact.friction": 0.05})
    assert dict(low.sizes) == {"initial.phi_dot": 2}
    row = df[(df["contact.friction [1]"] == 0.05) & (df["initial.phi_dot [rad/s]"] == 180.0)]
    assert float(low["max.theta"].sel({"initial.phi_dot": 180.0})) == float(row["max.theta [rad]"].iloc[0])
    # a table read back from CSV (no attrs): the units come from the names
    import io

    buf = io.StringIO()
    df.to_csv(buf, index=False)
    import pandas as pd

    back = ellipsoid.to_xarray(pd.read_csv(io.StringIO(buf.getvalue())))
    assert list(back.sizes) == ["point"] and back["max.theta"].attrs["units"] == "rad"


def test_check_reports_the_velocity_of_g_and_the_slip_the_run_starts_with() -> None:
    for changes in ({}, {"initial.velocity": [0.1, -0.02]}):
        s = ellipsoid.load(SCENARIOS / "tippe-top.toml", output={"t_end": 0.01}, **changes)
        init = ellipsoid.check(s)["initial"]
        first = ellipsoid.simulate(s)
        assert init["velocity"] == [first.vx[0], first.vy[0], first.vz[0]]
        assert init["slip_speed"] == first.slip_speed[0] and init["velocity_given"]
    assert ellipsoid.check(s)["initial"]["velocity"][:2] == [0.1, -0.02]


def test_errors_name_python_changes_not_command_line_flags() -> None:
    with pytest.raises(ellipsoid.ScenarioError) as info:
        ellipsoid.load(SCENARIOS / "nutation.toml").replace(initial={"thetta": 0.1})
    msg = str(info.value)
    assert "--set" not in msg and "the change initial.thetta=0.1" in msg and "did you mean `theta`" in msg


def test_contact_spheres_add_their_columns_by_name_and_survive_pickling(tmp_path: Path) -> None:
    """A body with contact spheres: five columns per surface after `ellipsoid.COLUMNS`, read
    by name; the surface the mode names carries the normal force and touches the plane;
    pickled, the trajectory writes the same CSV byte for byte."""
    traj = ellipsoid.simulate(SCENARIOS / "tippe-top-stem.toml", output={"t_end": 6.0})
    surfaces = ["ellipsoid", "stem"]
    extra = [f"{q}_{s}" for s in surfaces for q in ("normal_force", "slip_speed", "gap", "contact_x", "contact_y")]
    assert traj.columns == list(ellipsoid.COLUMNS) + extra
    assert traj.units["normal_force_stem"] == "N" and traj.units["gap_ellipsoid"] == "m"
    assert set(traj.to_pandas().columns) == set(traj.columns) - {"t"}
    mode = traj.mode
    assert set(np.unique(mode)) == {"sliding@ellipsoid", "sliding@stem", "two_contacts@ellipsoid+stem"}
    n = traj.normal_force
    for s, other in (("ellipsoid", "stem"), ("stem", "ellipsoid")):
        alone = mode == f"sliding@{s}"
        np.testing.assert_array_equal(traj[f"normal_force_{s}"][alone], n[alone])
        assert np.all(traj[f"normal_force_{other}"][alone] == 0) and np.all(traj[f"gap_{other}"][alone] > 0)
        np.testing.assert_allclose(traj[f"contact_x_{s}"][alone], traj.contact_x[alone], atol=1e-12)
    both = mode == "two_contacts@ellipsoid+stem"
    np.testing.assert_allclose(traj["normal_force_ellipsoid"][both] + traj["normal_force_stem"][both], n[both], rtol=1e-12)
    with pytest.raises(KeyError, match="normal_force_peg"):
        traj["normal_force_peg"]
    traj.to_csv(tmp_path / "a.csv")
    pickle.loads(pickle.dumps(traj)).to_csv(tmp_path / "b.csv")
    assert (tmp_path / "a.csv").read_bytes() == (tmp_path / "b.csv").read_bytes()
