"""Running from Python: outcomes and errors, sweeps, the GIL, Ctrl-C, output files."""

from __future__ import annotations

import _thread
import errno
import os
import signal
from pathlib import Path

import numpy as np
import pytest

import ellipsoid
from conftest import INTERRUPT_MAIN, REPO, interrupt_inside, oblate

NUTATION = REPO / "scenarios" / "nutation.toml"


def needle(friction: float = 1.0, velocity=(1.0, 0.0)) -> ellipsoid.Scenario:
    """A uniform needle sliding with μ = 1: the sliding normal-force denominator
    1 + m u·I⁻¹(r × d) reaches 0 at t ≈ 0.034 s (Painlevé)."""
    return ellipsoid.Scenario(
        body=dict(a=0.005, c=0.1, mass=0.1, inertia="uniform"),
        initial=dict(theta=0.3, velocity=list(velocity)),
        contact=dict(model="sliding", friction=friction),
        solver=dict(rtol=1e-12, atol=1e-12),
        output=dict(t_end=0.2, dt=1e-3),
        name="needle",
    )


def tumbling() -> ellipsoid.Scenario:
    """A prolate body falling over fast enough (θ̇ = −45 rad/s) to leave the plane (the
    run stops there)."""
    return ellipsoid.Scenario(
        body=dict(a=0.02, c=0.04, mass=0.1, inertia="uniform"),
        initial=dict(theta=1.5, theta_dot=-45.0, velocity=[0.0, 0.0]),
        contact=dict(model="frictionless", on_lift_off="stop"),
        solver=dict(rtol=1e-12, atol=1e-12),
        output=dict(t_end=1.0, dt=1e-4),
        name="tumbling",
    )


# ----------------------------------------------------------------- outcomes and errors


def test_trajectory_columns_are_read_only_float64_arrays() -> None:
    traj = ellipsoid.simulate(NUTATION, output={"t_end": 0.1})
    assert len(traj) == 101 and traj.t[-1] == 0.1 and traj.completed
    for name in ellipsoid.COLUMNS:
        col = getattr(traj, name)
        assert isinstance(col, np.ndarray) and col.shape == (101,)
        assert col.dtype == (np.dtype("U12") if name == "mode" else np.float64)
        assert not col.flags.writeable
        assert getattr(traj, name) is col, "arrays are made once"
    with pytest.raises(ValueError, match="read-only"):
        traj.x[0] = 1.0
    assert traj.units["t"] == "s" and traj.units["mode"] == "1" and list(traj.units) == list(ellipsoid.COLUMNS)
    assert list(traj.to_dict()) == list(ellipsoid.COLUMNS)
    assert traj.scenario == ellipsoid.load(NUTATION, output={"t_end": 0.1})
    assert "101 samples" in repr(traj)


def test_loss_of_contact_is_an_outcome_not_an_error() -> None:
    traj = ellipsoid.simulate(tumbling())
    assert traj.status == "lost_contact" and not traj.completed
    assert [e["kind"] for e in traj.events] == ["lost_contact"]
    assert traj.t[-1] == traj.events[0]["t"] < 1.0, "the trajectory ends at the event"
    assert abs(traj.normal_force[-1]) < 1e-9
    assert "the body leaves the plane" in traj.message


def test_pure_sliding_slip_stop_is_an_outcome() -> None:
    traj = ellipsoid.simulate(REPO / "scenarios" / "egg.toml")
    assert traj.status == "slip_stopped"
    assert traj.events[-1]["kind"] == "slip_stop" and traj.t[-1] == traj.events[-1]["t"]
    assert traj.slip_speed[-1] < 1e-6 * traj.slip_speed[0]


def test_painleve_returns_the_partial_trajectory_unsuccessful() -> None:
    traj = ellipsoid.simulate(needle())
    assert isinstance(traj, ellipsoid.Trajectory) and traj.status == "painleve"
    assert not traj.success and traj.status_code == -1
    assert traj.message.startswith("Painlevé inconsistency at t = 0.034"), traj.message
    assert traj.summary["message"] == traj.message
    assert traj.events[-1]["kind"] == "painleve" and traj.t[-1] == traj.events[-1]["t"]
    assert 30 < len(traj) < 40 and np.all(np.isfinite(traj.normal_force))


def test_painleve_at_t0_is_a_scenario_error() -> None:
    with pytest.raises(ellipsoid.ScenarioError, match="Painlevé inconsistency at t = 0"):
        ellipsoid.simulate(needle(friction=2.0, velocity=(0.0, 1.0)))


def test_solver_failure_returns_an_unsuccessful_trajectory() -> None:
    s = ellipsoid.load(NUTATION, solver={"max_steps": 5}, output={"t_end": 1.0})
    traj = ellipsoid.simulate(s)
    assert traj.status == "solver_failure" and not traj.success and traj.status_code == -1
    assert len(traj) >= 1


def test_no_panic_reaches_python_on_odd_inputs() -> None:
    """Extreme but accepted values end in a finite result or an EllipsoidError, never a
    panic and never a NaN or infinity in the trajectory."""
    base = ellipsoid.load(NUTATION, output={"t_end": 0.05})
    odd: list[dict[str, object]] = [
        {"initial.theta": 0.0, "initial.theta_deg": None},
        {"initial.psi_dot": 1e12},
        {"initial.psi_dot": 0.0},
        {"body.a": 1e-9, "body.c": 1e-9, "body.com_offset": 0.0, "body.inertia": "uniform"},
        {"body.mass": 1e30},
        {"effects.gravity": 0.0},
        {"effects.gravity": 1e5},
        {"solver.method": "rk4", "solver.step": 0.05},
        {"solver.rtol": 1e-3, "solver.atol": 1e3},
        {"output.times": [0.05], "output.dt": None},
        {"contact.model": "coulomb", "contact.friction": 0.0},
        {"contact.model": "coulomb", "contact.friction": 1e9},
    ]
    for changes in odd:
        sets = {k: v for k, v in changes.items() if v is not None}
        if "initial.theta_deg" in changes or "output.dt" in changes:
            text = NUTATION.read_text().replace("theta_deg = 10.0\n", "" if "initial.theta_deg" in changes else "theta_deg = 10.0\n")
            text = text.replace("dt = 1e-3\n", "" if "output.dt" in changes else "dt = 1e-3\n")
            make = lambda: ellipsoid.Scenario.from_toml(text, name="odd", **{"output.t_end": 0.05, **sets})  # noqa: E731
        else:
            make = lambda: base.replace(**sets)  # noqa: E731
        try:
            traj = ellipsoid.simulate(make())
        except ellipsoid.EllipsoidError as e:
            assert not isinstance(e, ellipsoid.InternalError), (changes, e)
            trajectory = getattr(e, "trajectory", None)
        except BaseException as e:  # pragma: no cover - the failure we test for
            pytest.fail(f"{changes}: {type(e).__name__}: {e}")
        else:
            trajectory = traj
        if trajectory is not None:
            for name in trajectory.columns:
                if name != "mode":
                    assert np.all(np.isfinite(getattr(trajectory, name))), (changes, name)


# ----------------------------------------------------------------- sweeps


def test_sweep_equals_serial_runs_in_input_order() -> None:
    base = ellipsoid.load(REPO / "scenarios" / "tippe-top.toml", output={"t_end": 1.0})
    scenarios: list[ellipsoid.Scenario | str] = [base.replace(contact={"friction": mu}) for mu in (0.5, 0.05, 0.3, 0.1, 0.2)]
    scenarios.append(str(NUTATION))  # paths are accepted too
    serial = [ellipsoid.simulate(s) for s in scenarios]
    for workers in (None, 1, 2):
        parallel = ellipsoid.sweep(scenarios, workers=workers)
        assert len(parallel) == len(serial)
        for a, b in zip(serial, parallel):
            assert a.scenario == b.scenario
            for name in ellipsoid.COLUMNS:
                np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)
            sa, sb = a.summary, b.summary
            sa.pop("wall_time_s"), sb.pop("wall_time_s")
            assert sa == sb
    summaries = ellipsoid.sweep(scenarios, 2, summaries_only=True)
    assert [s["final"] for s in summaries] == [t.summary["final"] for t in serial]
    assert [s["samples"] for s in summaries] == [len(t) for t in serial]


def test_sweep_failures_raise_in_order_or_are_returned() -> None:
    good = ellipsoid.load(NUTATION, output={"t_end": 0.1})
    items: list[ellipsoid.Scenario | str] = [good, needle(), "/nonexistent.toml", tumbling()]
    with pytest.raises(ellipsoid.ScenarioError, match="/nonexistent.toml"):
        ellipsoid.sweep(items)
    runs = ellipsoid.sweep([good, needle(), tumbling()])
    assert [r.success for r in runs] == [True, False, True] and runs[1].status == "painleve"
    out = ellipsoid.sweep(items, errors="return")
    assert isinstance(out[0], ellipsoid.Trajectory) and out[0].completed
    assert isinstance(out[1], ellipsoid.Trajectory) and out[1].status == "painleve"
    assert isinstance(out[2], ellipsoid.ScenarioError)
    assert isinstance(out[3], ellipsoid.Trajectory) and out[3].status == "lost_contact"
    with pytest.raises(ValueError, match="workers = 0"):
        ellipsoid.sweep([good], workers=0)
    with pytest.raises(ValueError, match="errors"):
        ellipsoid.sweep([good], errors="ignore")  # type: ignore[call-overload]
    assert ellipsoid.sweep([]) == []


# ----------------------------------------------------------------- GIL and Ctrl-C

# A run that cannot end soon but for its step budget: 2e4 s of the nutation scene would
# take ~6.5e6 steps; after 1e6 (seconds of computing, however fast the machine) it stops
# with SimulationError (solver_failure). (Within 10 times the budget: a run projecting
# more, e.g. 1e6 s, is judged out of reach after 1e5 steps, a fraction of a second.)
# The tests below interrupt it from another thread
# at a deterministic point (once that thread sees the run in progress), so they pass by
# behaviour, never by timing: if the run held the GIL or ignored signals, it would end
# on its budget instead and `interrupt_inside` would fail, saying which.
LONG = {"output": {"t_end": 2e4, "dt": 1.0}, "solver": {"max_steps": 1_000_000}}


def test_gil_is_released_while_simulating() -> None:
    # Another thread runs Python code (a sum of 10^5 terms) while the run goes on, then
    # stops it; `interrupt_inside` fails if the run held the GIL throughout.
    scenario = ellipsoid.load(NUTATION, **LONG)
    interrupt_inside(INTERRUPT_MAIN, ellipsoid.simulate, scenario, work=lambda: sum(range(100_000)))


@pytest.mark.parametrize("how", ["interrupt_main", "os.kill"])
def test_ctrl_c_interrupts_a_long_run(how: str) -> None:
    def fire() -> None:
        if how == "interrupt_main":
            _thread.interrupt_main()
        else:
            os.kill(os.getpid(), signal.SIGINT)

    interrupt_inside(fire, ellipsoid.simulate, ellipsoid.load(NUTATION, **LONG))


def test_ctrl_c_interrupts_a_run_with_sparse_output() -> None:
    # Only two output times, 2e4 s apart: the interrupt must not wait for a sample.
    scenario = ellipsoid.load(NUTATION, output={"t_end": 2e4, "dt": 2e4}, solver={"max_steps": 1_000_000})
    interrupt_inside(INTERRUPT_MAIN, ellipsoid.simulate, scenario)


def test_ctrl_c_interrupts_a_sweep() -> None:
    interrupt_inside(INTERRUPT_MAIN, ellipsoid.sweep, [ellipsoid.load(NUTATION, **LONG)] * 4, workers=2)
    # The package still works afterwards.
    assert ellipsoid.simulate(NUTATION, output={"t_end": 0.01}).completed


def test_the_long_run_ends_on_its_step_budget_when_left_alone() -> None:
    """What `interrupt_inside` relies on: uninterrupted, LONG ends by itself (with the
    step budget spent), so a run that ignored the interrupt would fail those tests, not
    hang them. (Shortened: the same scene with a 10^4-step budget.)"""
    traj = ellipsoid.simulate(NUTATION, output={"t_end": 2e4, "dt": 1.0}, solver={"max_steps": 10_000})
    assert traj.status == "solver_failure" and "after 10000 steps" in traj.message


# ----------------------------------------------------------------- files


def test_output_errors_are_oserrors(tmp_path: Path) -> None:
    traj = ellipsoid.simulate(NUTATION, output={"t_end": 0.01})
    with pytest.raises(ellipsoid.OutputError) as info:
        traj.to_csv(tmp_path / "missing-dir" / "x.csv")
    assert isinstance(info.value, OSError) and info.value.errno == errno.ENOENT
    assert str(info.value).startswith(str(tmp_path / "missing-dir" / "x.csv"))
    assert not (tmp_path / "missing-dir").exists()


def test_to_pandas_has_every_column() -> None:
    pd = pytest.importorskip("pandas")
    traj = ellipsoid.simulate(REPO / "scenarios" / "billiard.toml", output={"t_end": 0.2})
    df = traj.to_pandas()
    assert isinstance(df, pd.DataFrame) and list(df.columns) == list(ellipsoid.COLUMNS)[1:] and len(df) == len(traj)
    assert df.index.name == "t" and np.array_equal(df.index.to_numpy(), traj.t)
    assert df.attrs["units"] == traj.units
    np.testing.assert_array_equal(df["energy"].to_numpy(), traj.energy)
    assert set(df["mode"]) <= {"sliding", "rolling"}


@pytest.mark.skipif(not ellipsoid.HDF5, reason="built without HDF5 (see test_hdf5_unavailable_says_how_to_get_it)")
def test_hdf5_round_trip_through_h5py(tmp_path: Path) -> None:
    h5py = pytest.importorskip("h5py")
    traj = ellipsoid.simulate(REPO / "scenarios" / "billiard.toml", output={"t_end": 0.3})
    path = tmp_path / "billiard.h5"
    traj.to_hdf5(path)
    with h5py.File(path, "r") as f:
        for name in ellipsoid.COLUMNS:
            if name == "mode":
                assert [m.decode() for m in f["mode"][...]] == traj.mode.tolist()
                assert f["mode"].attrs["values"] == "frictionless, sliding, rolling, flight, two_contacts, viscous, three_contacts, face"
            else:
                np.testing.assert_array_equal(f[name][...], getattr(traj, name), err_msg=name)
                assert f[name].attrs["units"] == traj.units[name]
        assert f.attrs["status"] == "completed"
        assert f.attrs["scenario"] == traj.scenario.text
        import json

        stored = json.loads(f.attrs["summary"])
        expected = traj.summary
        assert stored["output"] == str(path)
        stored.pop("output"), expected.pop("output")
        assert stored == expected
    traj.save(tmp_path / "again.hdf5")
    assert (tmp_path / "again.hdf5").stat().st_size > 0


@pytest.mark.skipif(not ellipsoid.HDF5, reason="built without HDF5")
def test_hdf5_files_are_read_by_h5dump(tmp_path: Path) -> None:
    """The statically linked HDF5 (2.x) writes files that the HDF5 command-line tools
    (Debian's hdf5-tools, 1.10) read: every column, with its units."""
    import shutil
    import subprocess

    h5dump = shutil.which("h5dump")
    if h5dump is None:
        if os.environ.get("ELLIPSOID_EXPECT_HDF5") == "1":
            pytest.fail("h5dump is not installed (scripts/test-all.sh installs hdf5-tools)")
        pytest.skip("h5dump is not installed")
    traj = ellipsoid.simulate(REPO / "scenarios" / "billiard.toml", output={"t_end": 0.3, "dt": 0.1})
    path = tmp_path / "b.h5"
    traj.to_hdf5(path)
    header = subprocess.run([h5dump, "-H", str(path)], capture_output=True, text=True, check=True).stdout
    for name in ellipsoid.COLUMNS:
        assert f'DATASET "{name}"' in header, name
    assert 'ATTRIBUTE "units"' in header and 'ATTRIBUTE "summary"' in header
    t = subprocess.run([h5dump, "-d", "/t", "-m", "%.17g", str(path)], capture_output=True, text=True, check=True).stdout
    data = t.split("DATA {", 1)[1].split("}", 1)[0]
    values = [float(v.split(":")[-1]) for v in data.replace("\n", " ").split(",")]
    assert values == traj.t.tolist()


@pytest.mark.skipif(ellipsoid.HDF5, reason="built with HDF5")
def test_hdf5_unavailable_says_how_to_get_it(tmp_path: Path) -> None:
    traj = ellipsoid.simulate(NUTATION, output={"t_end": 0.01})
    for write in (traj.to_hdf5, traj.save):
        with pytest.raises(ellipsoid.OutputError, match=r"built without HDF5 support; reinstall it with the default features"):
            write(tmp_path / "x.h5")
    assert not list(tmp_path.iterdir())


def test_a_dropped_body_flies_bounces_and_settles() -> None:
    """scenarios/drop.toml through Python: flight rows, the gap column, impact events."""
    traj = ellipsoid.simulate(REPO / "scenarios" / "drop.toml", output={"t_end": 1.0})
    assert traj.completed
    assert traj.mode[0] == "flight" and traj.mode[-1] != "flight"
    flying = traj.mode == "flight"
    assert (traj.gap[flying] >= 0).all() and (traj.gap[~flying] == 0).all()
    assert (traj.normal_force[flying] == 0).all()
    impacts = [e for e in traj.events if e["kind"] == "impact"]
    assert impacts and all(e["energy_loss"] >= 0 for e in impacts)
    assert impacts[-1]["persistent"] is True
    # E + W is the balance: every impact books its loss in W.
    balance = traj.energy + traj.work
    assert abs(balance[-1] - balance[0]) < 1e-9 * abs(balance[0])


def test_without_gravity_the_body_flies_and_stop_keeps_the_old_error() -> None:
    traj = ellipsoid.simulate(NUTATION, effects={"gravity": 0.0}, output={"t_end": 0.2})
    assert traj.completed and (traj.mode == "flight").all()
    with pytest.raises(ellipsoid.ScenarioError, match="on_lift_off"):
        ellipsoid.simulate(
            NUTATION, effects={"gravity": 0.0}, contact={"on_lift_off": "stop"}, output={"t_end": 0.2}
        )
