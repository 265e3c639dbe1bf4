"""The conventions of a result that solve_ivp and pandas/xarray users already know, for
`Trajectory` (its methods call these): the state matrix, events by name, DataFrame and
Dataset views, and pickling. SI units throughout (`Trajectory.units`)."""

from __future__ import annotations

import re
from typing import Any

import numpy as np

from ellipsoid._ellipsoid import Scenario, Trajectory

#: Built-in event kinds, as `Trajectory.events` names them (`kind`).
EVENT_KINDS = ("slip_stop", "mode_switch", "lost_contact", "lift_off", "touchdown", "impact", "painleve", "contact_surface", "grip", "flat")


def _readonly(a: np.ndarray) -> np.ndarray:
    a.setflags(write=False)
    return a


def states(traj: Trajectory) -> np.ndarray:
    """`Trajectory.states`: shape (n_states, n_t), rows named by `state_names`."""
    if len(traj) == 0:
        return _readonly(np.empty((len(traj.state_names), 0)))
    return _readonly(np.vstack([getattr(traj, name) for name in traj.state_names]))


def _event_times(traj: Trajectory) -> dict[str, list[float]]:
    times: dict[str, list[float]] = {name: [] for name in traj._observables}
    for kind in EVENT_KINDS:
        times.setdefault(kind, [])
    for e in traj.events:
        key = e["name"] if e["kind"] == "observed" else e["kind"]
        times.setdefault(key, []).append(e["t"])
    return times


def t_events(traj: Trajectory) -> dict[str, np.ndarray]:
    """`Trajectory.t_events`: event times [s] by observable name and built-in kind."""
    return {k: _readonly(np.array(v, dtype=float)) for k, v in _event_times(traj).items()}


def y_events(traj: Trajectory) -> dict[str, np.ndarray]:
    """`Trajectory.y_events`: the state at each event, (n_events, n_states) by name."""
    names = traj.state_names
    out: dict[str, np.ndarray] = {}
    builtin: list[float] = []
    for e in traj.events:
        if e["kind"] != "observed":
            builtin.append(e["t"])
    dense = None
    if builtin:
        at = traj.sol(np.array(builtin))
        dense = np.vstack([getattr(at, n) for n in names]).T
    row = 0
    rows: dict[str, list[np.ndarray]] = {k: [] for k in _event_times(traj)}
    for e in traj.events:
        if e["kind"] == "observed":
            rows[e["name"]].append(np.array([e["state"][n] for n in names], dtype=float))
        else:
            assert dense is not None
            rows[e["kind"]].append(dense[row])
            row += 1
    for k, v in rows.items():
        out[k] = _readonly(np.vstack(v) if v else np.empty((0, len(names))))
    return out


def _attrs(traj: Trajectory) -> dict[str, Any]:
    return {"units": dict(traj.units), "scenario": traj.scenario.source, "status": traj.status}


def to_pandas(traj: Trajectory) -> Any:
    """`Trajectory.to_pandas`: a DataFrame indexed by t [s], units in `attrs`."""
    try:
        import pandas as pd  # type: ignore[import-untyped,unused-ignore]
    except ImportError as e:
        raise ImportError(f"Trajectory.to_pandas needs pandas (`pip install pandas`): {e}") from e
    cols = traj.to_dict()
    t = cols.pop("t")
    df = pd.DataFrame(cols, index=pd.Index(t, name="t"))
    df.attrs.update(_attrs(traj))
    return df


def to_xarray(traj: Trajectory) -> Any:
    """`Trajectory.to_xarray`: a Dataset over t [s], each variable with its `units`."""
    try:
        import xarray as xr  # type: ignore[import-untyped,unused-ignore]
    except ImportError as e:
        raise ImportError(f"Trajectory.to_xarray needs xarray (`pip install xarray`): {e}") from e
    units = traj.units
    cols = traj.to_dict()
    t = cols.pop("t")
    data = {name: ("t", np.asarray(v), {"units": units[name]}) for name, v in cols.items()}
    ds = xr.Dataset(data, coords={"t": ("t", np.asarray(t), {"units": units["t"]})})
    ds.attrs.update({"scenario": traj.scenario.source, "status": traj.status, "message": traj.message})
    return ds


#: A study column's name and its unit: `t_final [s]` → (`t_final`, `s`).
_UNIT = re.compile(r"(.+) \[([^\[\]]*)\]")


def _bare(name: str) -> tuple[str, str | None]:
    """A study column's name without its `[unit]`, and the unit (None without one)."""
    m = _UNIT.fullmatch(name)
    return (m.group(1), m.group(2)) if m else (name, None)


def study_to_xarray(table: Any) -> Any:
    """`ellipsoid.to_xarray(table)`: a study's DataFrame as an xarray Dataset. A grid
    study (its axes in `table.attrs["axes"]`, every combination present once) becomes an
    n-D Dataset over its axes; any other table a Dataset over `point`. Names lose their
    `[unit]` (the dimension `"contact.friction"`, the variable `"t_final"`: so
    `ds.sel({"contact.friction": 0.05})` works) and the unit becomes each variable's
    `attrs["units"]` (from `table.attrs["units"]`, else from the name), as in
    `Trajectory.to_xarray`. Missing values are NaN (float64)."""
    try:
        import xarray as xr  # type: ignore[import-untyped,unused-ignore]
    except ImportError as e:
        raise ImportError(f"ellipsoid.to_xarray needs xarray (`pip install xarray`): {e}") from e
    known: dict[str, str | None] = dict(table.attrs.get("units", {}))
    axes = list(table.attrs.get("axes", []))
    df = table.copy()
    # pandas' nullable dtypes (NA) as plain floats (NaN), which xarray holds.
    for name in df.columns:
        if str(df[name].dtype) in ("Float64", "Int64"):
            df[name] = df[name].astype("float64")
    grid = table.attrs.get("combine", "grid") == "grid" and axes and not df.duplicated(subset=axes).any()
    if grid:
        size = int(np.prod([df[a].nunique() for a in axes]))
        grid = size == len(df)
    # names without their unit (unless two columns would then share a name)
    bare = {str(c): _bare(str(c)) for c in df.columns}
    if len({b for b, _ in bare.values()}) == len(bare):
        rename = {c: b for c, (b, _) in bare.items()}
    else:
        rename = {c: c for c in bare}
    units = {rename[c]: known.get(c, u) for c, (_, u) in bare.items()}
    df = df.rename(columns=rename)
    index = [rename[str(a)] for a in axes] if grid else ["point"]
    ds = xr.Dataset.from_dataframe(df.set_index(index))
    for name in ds.variables:
        unit = units.get(str(name))
        if unit:
            ds[name].attrs["units"] = unit
    ds.attrs.update({k: v for k, v in table.attrs.items() if k in ("study", "combine")})
    return ds


def _trajectory(
    scenario: Scenario,
    values: bytes,
    modes: list[str],
    summary: str,
    status: str,
    sections: list[tuple[bytes, list[str]]] | None = None,
) -> Trajectory:
    """Unpickles a Trajectory (`Trajectory.__reduce__`), with its sections' points."""
    return Trajectory._from_pickle(scenario, values, modes, summary, status, sections or [])  # type: ignore[attr-defined]


def _scenario(text: str, source: str, overrides: list[str]) -> Scenario:
    """Unpickles a Scenario (`Scenario.__reduce__`)."""
    return Scenario._from_parts(text, source, overrides)  # type: ignore[attr-defined]
