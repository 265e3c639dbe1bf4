"""Parameter studies: ``ellipsoid.study`` (docs/studies.md).

The points run in Rust (``Study.run``: a rayon sweep without the GIL). Locally, one sweep
over every point on all cores. With an ``executor`` (a ``concurrent.futures.Executor`` or a
``dask.distributed.Client``) the points are cut into chunks of about ``chunk_seconds`` of
work each (measured on a short pilot run here), each chunk is one task running
``Study.run(start, stop)`` on the worker, and the chunks' rows are gathered in point order.
Every point is deterministic, so the table is the same whichever way it ran, and a chunk
that ran twice (a Dask worker lost mid-task and the task resubmitted) gives the same rows.
"""

from __future__ import annotations

import io
import json
import math
import os
import time
from typing import Any, Literal, SupportsIndex

from ellipsoid._ellipsoid import Study, _argument_error, _study_workers, make_study

__all__ = ["study", "load_study", "Study"]


def load_study(path: "str | os.PathLike[str]") -> Study:
    """Reads a study file (TOML, docs/studies.md); its ``base`` is relative to the file."""
    return Study.load(path)


_STUDIES: dict[str, Study] = {}


def _study_from_json(text: str) -> Study:
    """The study of `text`, parsed once per process (the last few are kept)."""
    st = _STUDIES.get(text)
    if st is None:
        if len(_STUDIES) >= 8:
            _STUDIES.pop(next(iter(_STUDIES)))
        st = _STUDIES[text] = Study.from_json(text)
    return st


def _run_chunk(text: str, start: int, stop: int, threads: int = 1) -> list:
    """One task: points ``start`` to ``stop`` of the study given as JSON (a worker keeps
    the last few studies it saw, so the JSON is parsed once per worker, not per chunk)."""
    return _study_from_json(text).run(start, stop, threads)


def _is_dask(executor: Any) -> bool:
    return type(executor).__module__.split(".")[0] == "distributed" and hasattr(executor, "scheduler_info")


def _slots(executor: Any) -> int:
    """How many chunks the executor runs at once."""
    if _is_dask(executor):
        return max(1, sum(executor.nthreads().values()))
    n = getattr(executor, "_max_workers", None)
    return int(n) if n else (os.cpu_count() or 1)


def _frame(st: Study, rows: list, nullable_dtypes: bool = False):
    import pandas as pd  # type: ignore[import-untyped,unused-ignore]  # optional: pandas-stubs may be absent

    cols = st.columns
    by_column = list(zip(*rows)) if rows else [()] * len(cols)
    data = {}
    for name, ty, nullable, values in zip(cols, st.types, st.nullable, by_column):
        if nullable and not nullable_dtypes and ty in ("float", "int"):
            # plain float64, NaN where there is no value (matplotlib, numpy take it as is)
            data[name] = pd.array([float("nan") if v is None else v for v in values], dtype="float64")
        elif ty == "float":
            data[name] = pd.array(values, dtype="Float64") if nullable else pd.array(values, dtype="float64")
        elif ty == "int":
            data[name] = pd.array(values, dtype="Int64") if nullable else pd.array(values, dtype="int64")
        else:
            data[name] = pd.array(values, dtype="str")
    df = pd.DataFrame(data, columns=cols)
    df.attrs["units"] = dict(st.units)
    df.attrs["study"] = st.source
    # the axes' columns (the first key of each), for `ellipsoid.to_xarray(df)`
    spec = json.loads(st.to_json())
    keys = [axis["dims"][0]["key"] for axis in spec["axes"]]
    df.attrs["axes"] = [c for k in keys for c in cols if c.split(" [")[0] == k][: len(keys)]
    df.attrs["combine"] = spec["combine"]
    return df


def study(
    base: Any,
    axes: Any,
    outcomes: "dict | None" = None,
    executor: Any = None,
    *,
    combine: "Literal['grid', 'zip'] | None" = None,
    workers: "SupportsIndex | None" = None,
    journal: "str | os.PathLike[str] | None" = None,
    chunk_seconds: float = 2.0,
    out: "str | os.PathLike[str] | None" = None,
    nullable: bool = False,
):
    """Runs a parameter study and returns its table as a ``pandas.DataFrame``.

    ``base``: an ``ellipsoid.Scenario`` or the path of a scenario file (None with a
    ``Study`` from a file: its own base). ``axes``: a dict from dotted scenario keys to
    lists of values — a grid in row-major order, the last key varying fastest — or to a
    generator dict (``{"linspace": [start, stop, n]}``, ``{"logspace": [...]}``,
    ``{"random": {"low": ..., "high": ..., "n": ..., "seed": ...}}``, with a tuple of keys
    ``{"latin_hypercube": {"low": [...], "high": [...], "n": ..., "seed": ...}}``; a tuple
    of keys with a list sets them all to each value); or an ``ellipsoid.Study`` (from
    ``load_study``). ``outcomes``: the ``[outcomes]`` table as a dict (``final``, ``min``,
    ``max``: column names; ``observables``, ``drift``, ``wall_time``, ``rhs_evals``: bools).
    ``combine``: "grid" (default) or "zip".

    ``executor``: None (every core of this machine), a ``concurrent.futures.Executor``, or
    a ``dask.distributed.Client``; ``chunk_seconds`` sizes its tasks. ``workers``: threads
    for the local run (default one per CPU; 1 to 4 per CPU, at least 8). ``journal``: a file keeping finished rows
    (local runs only): rerunning skips them, so a killed study resumes. ``out``: also write
    the table there (.csv, .h5; .parquet with pandas' ``to_parquet``), atomically, refusing a
    symbolic link, directory or device at that path.

    The columns are the file's (``ellipsoid study``): ``point``, the axis values, then
    ``status``, ``message``, ``t_final [s]``, ``t_NAME [s]`` per observable, the chosen
    ``final.``/``min.``/``max.`` columns, ``drift.NAME [1]``, ``wall_time [s]``,
    ``rhs_evals``, ``key``; floats are plain ``float64``, NaN where a run has no value
    (counts that may be missing become floats too), as matplotlib and numpy take them. A
    run that fails is a row with its status and message. ``nullable=True``: pandas'
    nullable dtypes instead (``Float64``, ``Int64``: ``pd.NA`` where there is no value).
    ``df.attrs["units"]`` maps each column to its SI unit, ``df.attrs["axes"]`` names the
    axes' columns and ``df.attrs["combine"]`` says "grid" or "zip"
    (``ellipsoid.to_xarray(df)`` makes a grid an n-D Dataset, its names without the
    ``[unit]``, each unit in its variable's ``attrs["units"]``).

    Before running, the plausibility warnings of its points (likely unit slips, found at
    the points that give every value of every axis) are issued as
    ``ellipsoid.PlausibilityWarning``, each once (docs/scenarios.md, "Plausibility
    warnings").
    """
    threads = _study_workers(workers)
    _check_seconds(chunk_seconds)
    for key, path in (("journal", journal), ("out", out)):
        if path is not None and not isinstance(path, (str, os.PathLike)):
            raise _argument_error(key, None, f"expected a path (str or os.PathLike), found {type(path).__name__}", True)
    if executor is not None and not callable(getattr(executor, "submit", None)):
        raise _argument_error("executor", None, f"expected a concurrent.futures.Executor or a dask.distributed.Client, found {type(executor).__name__}", True)
    if isinstance(axes, Study):
        if combine is not None:
            raise _argument_error("combine", repr(combine), "combine belongs to the study file when axes is an ellipsoid.Study")
        st = axes.replace(base=base, outcomes=outcomes) if (base is not None or outcomes is not None) else axes
    else:
        st = make_study(base, axes, outcomes, combine)
    st._warn_plausibility()
    n = len(st)
    if executor is None:
        rows = st.run(0, n, threads, journal)
    else:
        if journal is not None:
            raise _argument_error("journal", None, "journal= is for local runs; with an executor the chunks are resubmitted instead")
        rows = _distributed(st, executor, chunk_seconds)
    df = _frame(st, rows, nullable)
    if out is not None:
        ext = os.fspath(out).rsplit(".", 1)[-1].lower()
        if ext in ("parquet", "pq"):
            # Made in memory, then written like every other table: atomically, never
            # through a symbolic link.
            # Parquet keeps a missing value as null, whatever `nullable` says.
            buf = io.BytesIO()
            (df if nullable else _frame(st, rows, True)).to_parquet(buf, index=False)
            st.write_bytes(out, buf.getvalue())
        else:
            st.write(out, rows)
    return df


def _check_seconds(chunk_seconds: Any) -> None:
    """`chunk_seconds`: a positive, finite number of seconds."""
    if isinstance(chunk_seconds, bool) or not isinstance(chunk_seconds, (int, float)):
        raise _argument_error("chunk_seconds", None, f"expected a number of seconds, found {type(chunk_seconds).__name__}", True)
    if not (0 < chunk_seconds < math.inf):
        raise _argument_error("chunk_seconds", repr(chunk_seconds), "give a positive, finite number of seconds")


def _distributed(st: Study, executor: Any, chunk_seconds: float) -> list:
    n = len(st)
    # A pilot of a few points here sizes the chunks (and its rows are kept).
    pilot = min(n, 4)
    t0 = time.perf_counter()
    rows = st.run(0, pilot, 1)
    per_point = (time.perf_counter() - t0) / max(pilot, 1)
    slots = _slots(executor)
    rest = n - pilot
    size = max(1, int(chunk_seconds / max(per_point, 1e-6)))
    # At least about four chunks per slot, so that a slow chunk or a lost worker does not
    # leave the others idle.
    size = min(size, max(1, math.ceil(rest / (4 * slots)))) if rest else 1
    text = st.to_json()
    dask = _is_dask(executor)
    payload = executor.scatter(text, broadcast=True) if dask else text
    futures = []
    for start in range(pilot, n, size):
        stop = min(n, start + size)
        if dask:
            futures.append(executor.submit(_run_chunk, payload, start, stop, 1, pure=False, retries=3))
        else:
            futures.append(executor.submit(_run_chunk, text, start, stop, 1))
    try:
        for f in futures:  # in point order; each result as it is needed
            rows.extend(f.result())
    except BaseException:
        # Ctrl-C (or a failed chunk): the chunks not started yet are dropped at once, so
        # the executor is free when the exception reaches the caller (a concurrent.futures
        # executor would otherwise run every queued chunk first).
        for f in futures:
            f.cancel()
        raise
    return rows
