"""ellipsoid.study (issue #15): the table of a parameter study, the same however it ran —
locally, from the command line, on a concurrent.futures executor, on a Dask LocalCluster of
two worker processes, and on that cluster with one worker killed mid-study."""

from __future__ import annotations

import concurrent.futures
import importlib.util
import json
import os
import pickle
import signal
import subprocess
import threading
import time
from pathlib import Path

import pytest

import ellipsoid
from conftest import SCENARIOS

pd = pytest.importorskip("pandas")

# 160 frictionless nutation runs of 2 s (a few ms each), every kind of outcome column.
AXES = {"initial.psi_dot": {"linspace": [20.0, 80.0, 16]}, "initial.theta_deg": [5.0, 10.0, 15.0, 20.0, 25.0, 30.0, 35.0, 40.0, 45.0, 50.0]}
OUTCOMES = {"final": ["theta", "mode"], "min": ["normal_force"], "max": ["theta"]}
OBSERVE = [{"name": "tilt", "column": "theta", "crosses": 0.3, "direction": "up"}]


def base() -> ellipsoid.Scenario:
    return ellipsoid.load(SCENARIOS / "nutation.toml", output={"t_end": 2.0, "dt": 0.01}, observe=OBSERVE)


def deterministic(df):
    """Every column but the measured wall time."""
    return df.drop(columns=["wall_time [s]"]).reset_index(drop=True)


@pytest.fixture(scope="module")
def local():
    return ellipsoid.study(base(), AXES, OUTCOMES)


def test_the_table_has_the_files_columns_units_and_plain_float_dtypes(local) -> None:
    """The default table holds float64 with NaN where a run has no value, so matplotlib
    and numpy take its columns (and `pivot(...).values`) as they are."""
    import numpy as np

    df = local
    assert len(df) == 160
    assert list(df.columns[:3]) == ["point", "initial.psi_dot [rad/s]", "initial.theta_deg [deg]"]
    assert "t_tilt [s]" in df.columns and "drift.energy [1]" in df.columns and df.columns[-1] == "key"
    # Grid in row-major order: the last key varies fastest.
    assert list(df["initial.theta_deg [deg]"][:3]) == [5.0, 10.0, 15.0]
    assert (df["initial.psi_dot [rad/s]"][:10] == 20.0).all()
    assert (df["status"] == "completed").all()
    assert str(df["t_final [s]"].dtype) == "float64" and str(df["rhs_evals"].dtype) == "float64"
    assert not any(str(t) in ("Float64", "Int64") for t in df.dtypes)
    # A tilt of 5° never reaches 0.3 rad: NaN; a larger one does.
    assert np.isnan(df["t_tilt [s]"][0]) and not df["t_tilt [s]"].isna().all()
    grid = df.pivot(index="initial.psi_dot [rad/s]", columns="initial.theta_deg [deg]", values="t_tilt [s]").values
    assert grid.dtype == np.float64 and grid.shape == (16, 10)
    # Frictionless: energy conserved; Jellett's quantity is not (not a sphere): no value.
    assert (df["drift.energy [1]"] < 1e-8).all() and df["drift.jellett [1]"].isna().all()
    assert df.attrs["units"]["t_tilt [s]"] == "s"
    assert df["key"].nunique() == 160


def test_nullable_true_gives_pandas_nullable_dtypes(local) -> None:
    """`nullable=True`: `Float64` and `Int64`, `pd.NA` where there is no value (never
    NaN), the same values as the default table."""
    df = ellipsoid.study(base(), AXES, OUTCOMES, nullable=True)
    assert str(df["t_final [s]"].dtype) == "Float64" and str(df["rhs_evals"].dtype) == "Int64"
    assert df["t_tilt [s]"][0] is pd.NA and not df["t_tilt [s]"].isna().all()
    for col in df.columns:  # no NaN anywhere: missing values are pd.NA
        if str(df[col].dtype) in ("Float64", "float64"):
            assert not (df[col].dropna().astype(float) != df[col].dropna().astype(float)).any(), col
    for col in df.columns:
        if col != "wall_time [s]":
            a = df[col].astype(object).where(df[col].notna(), None).tolist()
            b = local[col].astype(object).where(local[col].notna(), None).tolist()
            assert a == b, col


def test_a_failed_point_is_a_row_with_its_status_and_message() -> None:
    df = ellipsoid.study(base(), {"body.mass": [0.05, -1.0]})
    assert list(df["status"]) == ["completed", "invalid"]
    assert "body.mass = -1" in df["message"][1] and "positive" in df["message"][1]
    assert df["t_final [s]"].isna()[1]


def test_errors_of_the_study_are_scenario_errors_naming_key_value_and_rule() -> None:
    t = time.perf_counter()
    with pytest.raises(ellipsoid.ScenarioError) as e:
        ellipsoid.study(base(), {"initial.psi_dot": {"linspace": [0, 1, 10**9]}, "initial.theta": [0.1]})
    assert time.perf_counter() - t < 0.5
    assert e.value.key == 'axes["initial.psi_dot"].linspace' and e.value.value == "1000000000"
    assert "n must be an integer from 1 to 10000000" in str(e.value)
    with pytest.raises(ellipsoid.ScenarioError, match="1e10 points; a study has at most 10000000"):
        ellipsoid.study(base(), {"initial.psi_dot": {"linspace": [1, 2, 100000]}, "initial.theta": {"linspace": [0.1, 0.2, 100000]}})
    with pytest.raises(ellipsoid.ScenarioError, match="did you mean `psi_dot`"):
        ellipsoid.study(base(), {"initial.psi_dott": [1.0]})
    with pytest.raises(ellipsoid.ScenarioTypeError):
        ellipsoid.study(base(), [1, 2])
    with pytest.raises(ellipsoid.ScenarioError, match="expected the name of a numeric output column"):
        ellipsoid.study(base(), {"initial.psi_dot": [1.0]}, {"max": ["thetta"]})


def test_a_study_pickles_and_a_journal_resumes(tmp_path: Path, local) -> None:
    st = ellipsoid.Study.from_json(ellipsoid._ellipsoid.make_study(base(), AXES, OUTCOMES).to_json())
    assert pickle.loads(pickle.dumps(st)).columns == st.columns
    # Floats that a JSON parser rounding to within an ulp would change (another scenario).
    tricky = ellipsoid._ellipsoid.make_study(base(), {"body.inertia[0]": {"linspace": [3.85e-7, 1.12e-6, 40]}})
    again = pickle.loads(pickle.dumps(tricky))
    assert [again.point(i) for i in range(40)] == [tricky.point(i) for i in range(40)]
    journal = tmp_path / "j"
    first = ellipsoid.study(base(), AXES, OUTCOMES, journal=journal)
    assert len(journal.read_text().splitlines()) == 161
    t = time.perf_counter()
    again = ellipsoid.study(base(), AXES, OUTCOMES, journal=journal)
    # Every row from the journal (wall times included), nothing run again.
    pd.testing.assert_frame_equal(again, first)
    assert time.perf_counter() - t < 2.0
    pd.testing.assert_frame_equal(deterministic(first), deterministic(local))


def test_the_command_line_writes_the_same_table(cli: Path, tmp_path: Path, local) -> None:
    spec = tmp_path / "s.toml"
    spec.write_text(
        f'base = "{SCENARIOS / "nutation.toml"}"\n'
        '[set]\n"output.t_end" = 2.0\n"output.dt" = 0.01\n'
        'observe = [{ name = "tilt", column = "theta", crosses = 0.3, direction = "up" }]\n'
        '[[axis]]\nkey = "initial.psi_dot"\nlinspace = [20.0, 80.0, 16]\n'
        '[[axis]]\nkey = "initial.theta_deg"\nvalues = [5.0, 10.0, 15.0, 20.0, 25.0, 30.0, 35.0, 40.0, 45.0, 50.0]\n'
        '[outcomes]\nfinal = ["theta", "mode"]\nmin = ["normal_force"]\nmax = ["theta"]\n'
    )
    out = tmp_path / "t.csv"
    r = subprocess.run([str(cli), "study", str(spec), "-o", str(out), "-q"], capture_output=True, text=True)
    if "unrecognized subcommand" in r.stderr:
        pytest.skip(f"{cli} predates `ellipsoid study`")
    assert r.returncode == 0, r.stderr
    from_file = ellipsoid.study(None, ellipsoid.load_study(spec))
    csv = pd.read_csv(out)
    assert list(csv.columns) == list(local.columns)
    # The file's study and the Python one resolve to the same scenarios: the same keys.
    assert list(csv["key"]) == list(local["key"]) == list(from_file["key"])
    for col in local.columns:
        if col in ("wall_time [s]",):
            continue
        a = local[col].astype(object).where(local[col].notna(), None).tolist()
        b = csv[col].astype(object).where(csv[col].notna(), None).tolist()
        assert a == b, col
    # The same table as Parquet (nulls as nulls) and HDF5 (a dataset per column).
    pq = tmp_path / "t.parquet"
    r = subprocess.run([str(cli), "study", str(spec), "-o", str(pq), "-q"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    if importlib.util.find_spec("pyarrow") is not None:
        par = pd.read_parquet(pq)
        assert list(par.columns) == list(local.columns)
        assert list(par["key"]) == list(local["key"])
        assert par["t_tilt [s]"].isna().tolist() == local["t_tilt [s]"].isna().tolist()
        assert par["max.theta [rad]"].tolist() == local["max.theta [rad]"].astype(float).tolist()
    if importlib.util.find_spec("h5py") is not None:
        import h5py

        h5 = tmp_path / "t.h5"
        r = subprocess.run([str(cli), "study", str(spec), "-o", str(h5), "-q"], capture_output=True, text=True)
        if r.returncode == 2 and "HDF5" in r.stderr:
            pytest.skip("the command-line tool was built without HDF5")
        assert r.returncode == 0, r.stderr
        with h5py.File(h5) as f:
            assert json.loads(f.attrs["headers"]) == list(local.columns)
            assert json.loads(f.attrs["columns"])[:3] == ["point", "initial.psi_dot", "initial.theta_deg"]
            assert f["max.theta"][:].tolist() == local["max.theta [rad]"].astype(float).tolist()
            assert f["initial.psi_dot"].attrs["units"] == "rad/s"
            assert json.loads(f.attrs["units"])["t_final [s]"] == "s"


def test_a_concurrent_futures_executor_gives_the_local_table(local) -> None:
    with concurrent.futures.ThreadPoolExecutor(2) as ex:
        df = ellipsoid.study(base(), AXES, OUTCOMES, executor=ex, chunk_seconds=0.01)
    pd.testing.assert_frame_equal(deterministic(df), deterministic(local))
    with concurrent.futures.ProcessPoolExecutor(2) as ex:
        df = ellipsoid.study(base(), AXES, OUTCOMES, executor=ex, chunk_seconds=0.05)
    pd.testing.assert_frame_equal(deterministic(df), deterministic(local))


@pytest.fixture(scope="module")
def dask_client():
    distributed = pytest.importorskip("distributed")
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None)
    client = distributed.Client(cluster)
    try:
        yield client
    finally:
        client.close()
        cluster.close()


def test_a_dask_local_cluster_gives_the_local_table(dask_client, local) -> None:
    df = ellipsoid.study(base(), AXES, OUTCOMES, executor=dask_client, chunk_seconds=0.02)
    pd.testing.assert_frame_equal(deterministic(df), deterministic(local))


def test_a_dask_worker_killed_mid_study_still_gives_the_complete_identical_table(dask_client, local) -> None:
    # Longer runs (6 s each) so that the study is still going when the worker dies.
    slow = ellipsoid.load(SCENARIOS / "nutation.toml", output={"t_end": 6.0, "dt": 0.01}, observe=OBSERVE)
    expected = ellipsoid.study(slow, AXES, OUTCOMES)
    pids = dask_client.run(os.getpid)
    result: dict = {}

    def run() -> None:
        try:
            result["df"] = ellipsoid.study(slow, AXES, OUTCOMES, executor=dask_client, chunk_seconds=0.05)
        except BaseException as e:  # noqa: BLE001 - reported below
            result["error"] = e

    thread = threading.Thread(target=run)
    thread.start()
    # Kill a worker once the cluster has finished some chunks, choosing one that is running
    # a chunk at that moment (the lowest pid may be between chunks on a loaded machine).
    def busy_workers(dask_scheduler) -> list:
        return [ws.address for ws in dask_scheduler.workers.values() if any(str(t.key).startswith("_run_chunk") for t in ws.processing)]

    deadline = time.monotonic() + 60
    busy: list = []
    while time.monotonic() < deadline:
        done = dask_client.run_on_scheduler(lambda dask_scheduler: sum(t.state == "memory" for t in dask_scheduler.tasks.values() if str(t.key).startswith("_run_chunk")))
        busy = dask_client.run_on_scheduler(busy_workers) if done >= 2 else []
        if busy:
            break
        time.sleep(0.01)
    assert busy, "no worker was running a chunk"
    victim = pids[busy[0]]
    assert thread.is_alive(), "the study ended before a worker could be killed"
    os.kill(victim, signal.SIGKILL)
    # Chunks that were on the dead worker are marked suspicious by the scheduler and rerun.
    lost = 0
    deadline = time.monotonic() + 10
    while lost == 0 and time.monotonic() < deadline:
        time.sleep(0.05)
        lost = dask_client.run_on_scheduler(lambda dask_scheduler: sum(t.suspicious > 0 for t in dask_scheduler.tasks.values()))
    thread.join(120)
    assert not thread.is_alive()
    assert "error" not in result, result.get("error")
    assert thread is not None and not any(p == victim for p in dask_client.run(os.getpid).values()), "the worker was not replaced"
    assert lost >= 1, "no chunk was running on the killed worker"
    pd.testing.assert_frame_equal(deterministic(result["df"]), deterministic(expected))


def test_a_parquet_table_is_written_atomically_and_never_through_a_link(tmp_path: Path) -> None:
    """`out=x.parquet` is written like .csv and .h5: a temporary renamed into place, and a
    symbolic link there refused (pandas' `to_parquet` on the path overwrote its target)."""
    pytest.importorskip("pyarrow")
    axes = {"initial.psi_dot": [20.0, 40.0]}
    victim = tmp_path / "victim.txt"
    victim.write_text("keep me")
    link = tmp_path / "t.parquet"
    link.symlink_to(victim)
    with pytest.raises(ellipsoid.OutputError, match="is a symbolic link"):
        ellipsoid.study(base(), axes, out=link)
    assert victim.read_text() == "keep me" and link.is_symlink()
    out = tmp_path / "sub.parquet"
    df = ellipsoid.study(base(), axes, out=out)
    assert list(pd.read_parquet(out)["key"]) == list(df["key"])
    assert sorted(p.name for p in tmp_path.iterdir()) == ["sub.parquet", "t.parquet", "victim.txt"]


def test_ctrl_c_cancels_the_queued_chunks_of_a_concurrent_futures_executor() -> None:
    """Ctrl-C while `study` waits on a concurrent.futures executor drops the chunks not yet
    started (they used to run to the end before the interrupt reached the caller)."""

    class Recording(concurrent.futures.ThreadPoolExecutor):
        def __init__(self) -> None:
            super().__init__(1)
            self.futures: list[concurrent.futures.Future] = []

        def submit(self, *args, **kwargs):  # type: ignore[no-untyped-def]
            f = super().submit(*args, **kwargs)
            self.futures.append(f)
            return f

    with Recording() as ex:

        finished = threading.Event()

        def interrupt_after_the_first_chunk() -> None:
            while not any(f.done() for f in ex.futures):
                time.sleep(0.001)
            # A SIGINT that lands while Python runs a weakref callback is swallowed
            # ("Exception ignored in ... KeyboardInterrupt"), so it is sent again, as a
            # user's second Ctrl-C would be, while the study still runs.
            while not finished.is_set():
                os.kill(os.getpid(), signal.SIGINT)
                finished.wait(0.5)

        watcher = threading.Thread(target=interrupt_after_the_first_chunk, daemon=True)
        watcher.start()
        with pytest.raises(KeyboardInterrupt):
            try:
                ellipsoid.study(base(), AXES, OUTCOMES, executor=ex, chunk_seconds=0.001)
            finally:
                finished.set()
        watcher.join()
        waiting = [f for f in ex.futures if not (f.done() or f.running())]
        assert waiting == [], f"{len(waiting)} of {len(ex.futures)} chunks still queued"
        assert sum(f.cancelled() for f in ex.futures) > len(ex.futures) // 2


@pytest.mark.parametrize(
    ("kwargs", "cls", "match"),
    [
        ({"workers": True}, ellipsoid.ScenarioTypeError, r"study: workers: expected an integer, found bool"),
        ({"workers": "4"}, ellipsoid.ScenarioTypeError, r"workers: expected an integer, found str"),
        ({"workers": -1}, ellipsoid.ScenarioError, r"workers = -1: give 1 to \d+ worker threads"),
        ({"workers": 2**64}, ellipsoid.ScenarioError, r"workers = 18446744073709551616: give 1 to"),
        ({"chunk_seconds": "2"}, ellipsoid.ScenarioTypeError, r"chunk_seconds: expected a number of seconds, found str"),
        ({"chunk_seconds": float("nan")}, ellipsoid.ScenarioError, r"chunk_seconds = nan: give a positive, finite number"),
        ({"out": 5}, ellipsoid.ScenarioTypeError, r"out: expected a path"),
        ({"journal": 5.0}, ellipsoid.ScenarioTypeError, r"journal: expected a path"),
        ({"combine": "zip", "axes": "study"}, ellipsoid.ScenarioError, r"combine = 'zip': combine belongs to the study file"),
        ({"journal": "j", "executor": "threads"}, ellipsoid.ScenarioError, r"journal: journal= is for local runs"),
    ],
)
def test_every_argument_error_of_study_is_an_ellipsoid_error(kwargs, cls, match, tmp_path: Path) -> None:
    """Argument errors used to be plain OverflowError/TypeError/ValueError, and workers=True
    was accepted (sweep refuses it)."""
    axes: object = {"initial.psi_dot": [20.0]}
    if kwargs.pop("axes", None) == "study":
        spec = tmp_path / "s.toml"
        spec.write_text(f'base = "{SCENARIOS / "nutation.toml"}"\n[[axis]]\nkey = "initial.psi_dot"\nvalues = [20.0]\n')
        axes = ellipsoid.load_study(spec)
    with concurrent.futures.ThreadPoolExecutor(1) as ex:
        if kwargs.get("executor") == "threads":
            kwargs["executor"] = ex
        with pytest.raises(cls, match=match) as info:
            ellipsoid.study(None if not isinstance(axes, dict) else base(), axes, **kwargs)
    assert isinstance(info.value, ellipsoid.EllipsoidError)
