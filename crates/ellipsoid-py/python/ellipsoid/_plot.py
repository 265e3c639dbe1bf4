"""`Trajectory.plot`: the panels of `ellipsoid plot` drawn with matplotlib (an optional
dependency, imported only here).

The panels are declared once for both renderers (the extension's `_PANELS`, the JSON of
`crates/ellipsoid-io/assets/panels.json`): each a row of one or two axes with their titles,
labels with units, series, colours and the contact-mode shading. Top to bottom: theta
(θ(t)), rates (θ̇, φ̇, ψ̇, and the world-frame vertical spin when the trajectory has it;
φ̇ and ψ̇ are left out where sin θ < 0.1, near the z-x-z singularity at θ = 0 where they
diverge as 1/sin θ), energy (E, E + W when work is dissipated, and the relative drift of
the conserved quantity on a log axis), forces (normal force and slip speed with the
contact mode shaded), surfaces (for a body with contact spheres: the normal force of each
surface, one line each, the contact phase shaded), path (the paths on the plane of G, the
contact point and the geometric centre C0). Events are dashed vertical lines, labelled by kind in the first time
panel. SI units on every axis. Or any output columns, one panel each (`columns=`), or
drawn into an existing matplotlib Axes (`ax=`), so figures compose.

As pandas' `DataFrame.plot`: every figure is made by pyplot, so in Jupyter it is shown
once (with or without a trailing `;`), `plt.show()` shows it and `plt.savefig("x.pdf")`
writes it (PDF, SVG or PNG); what is returned is the Axes (the one given as `ax=`), or a
numpy array of Axes for a figure of several.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import json
import os
import re

import numpy as np

from ellipsoid._ellipsoid import _PANELS

#: The declaration of the panels, shared with `ellipsoid plot`.
DECLARATION: dict[str, Any] = json.loads(_PANELS)
PANELS = tuple(p["name"] for p in DECLARATION["panels"])
_BY_NAME = {p["name"]: p for p in DECLARATION["panels"]}
#: Drift values below this are drawn at it (an exact zero has no place on a log axis).
_FLOOR = 1e-17
#: At most this many events are labelled (all are drawn).
_EVENT_LABELS = 12


def _figure(**kw: Any) -> Any:
    """A new pyplot figure (pyplot knows it, as it knows pandas' figures: Jupyter's inline
    backend shows it once at the end of the cell, `plt.show()` and `plt.savefig` find it)."""
    try:
        import matplotlib.pyplot as plt
    except ImportError as e:  # pragma: no cover - exercised with matplotlib hidden
        raise ImportError(f"Trajectory.plot needs matplotlib (`pip install matplotlib`): {e}") from e
    return plt.figure(**kw)


def _axes(axes: Sequence[Any]) -> Any:
    """What a plot returns, as pandas does: one Axes, or a numpy array of several."""
    if len(axes) == 1:
        return axes[0]
    out = np.empty(len(axes), dtype=object)
    out[:] = list(axes)
    return out


def _bad(key: str, value: Any, rule: str, wrong_type: bool = False) -> Exception:
    """The ScenarioError (ScenarioTypeError if `wrong_type`) for a bad argument of `plot`."""
    from ellipsoid._ellipsoid import _argument_error

    shown = None if wrong_type else repr(value)[:60]
    return _argument_error(key, shown, rule, wrong_type, "plot")


def _names(key: str, value: Any) -> list[str]:
    """`value` as a list of names: a comma-separated str, or a list or tuple of str."""
    if isinstance(value, str):
        return [p.strip() for p in value.split(",")]
    if isinstance(value, (list, tuple)) and all(isinstance(p, str) for p in value):
        return list(value)
    raise _bad(key, value, f"expected a comma-separated str or a list of str, found {type(value).__name__}", True)


def _per_surface(traj: Any, quantity: str) -> list[tuple[str, np.ndarray]]:
    """The per-surface columns of `quantity` (`normal_force` → `normal_force_ellipsoid`,
    `normal_force_stem`, …) as (surface, values), in column order; none for a one-surface
    body."""
    pattern = re.compile(re.escape(quantity) + r"_(\w+)")
    found = (pattern.fullmatch(c) for c in traj.columns)
    return [(m.group(1), np.asarray(traj[m.group(0)])) for m in found if m]


def _has(traj: Any, need: str) -> bool:
    """Whether `traj` has the column `need`, or for `QUANTITY_*` that quantity of a surface."""
    if need.endswith("_*"):
        return bool(_per_surface(traj, need[:-2]))
    return need in traj.columns


def _panels(traj: Any, panels: str | Sequence[str] | None) -> list[str]:
    """The panels asked for, checked; by default every declared one, those of per-surface
    columns only for a body with contact spheres."""
    if panels is None:
        return [p["name"] for p in DECLARATION["panels"] if not p.get("per_surface") or all(_has(traj, n) for n in p["needs"])]
    names = _names("panels", panels)
    if not names:
        raise _bad("panels", panels, f"give at least one of {', '.join(PANELS)}")
    for i, p in enumerate(names):
        if p not in PANELS:
            raise _bad("panels", p, f"unknown panel {p!r}; the panels are {', '.join(PANELS)}")
        if p in names[:i]:
            raise _bad("panels", p, "a panel is named twice")
        missing = [n for n in _BY_NAME[p]["needs"] if n.endswith("_*") and not _has(traj, n)]
        if missing:
            raise _bad("panels", p, f"the {p} panel needs the per-surface columns `{missing[0][:-1]}S` of a body with contact spheres, which this run does not have")
    return names


def _drift(traj: Any) -> tuple[np.ndarray, str]:
    e, w = np.asarray(traj.energy), np.asarray(traj.work)
    dissipative = bool(np.any(w != 0))
    d = getattr(traj, "drift", None)
    if isinstance(d, np.ndarray):  # the run's own: E where energy is conserved, else E + W
        return d, ("E + W" if dissipative else "E")
    total = e + w if dissipative else e
    scale = abs(total[0]) if total[0] != 0 else max(float(np.max(np.abs(total))), np.finfo(float).tiny)
    return (total - total[0]) / scale, ("E + W" if dissipative else "E")


def _phase(mode: Any) -> str:
    """The contact phase of a mode label: the label before `@` (`sliding@stem` → `sliding`)."""
    return str(mode).split("@", 1)[0]


def _shade(ax: Any, traj: Any) -> None:
    """The contact mode shaded behind the data, in the declared fills (by contact phase:
    `sliding@stem` is shaded as sliding)."""
    fills = {m["mode"]: m["fill"] for m in DECLARATION["modes"]}
    t, mode = traj.t, traj.mode
    start = 0
    for i in range(1, len(t) + 1):
        if i == len(t) or mode[i] != mode[start]:
            end = t[i - 1] if i == len(t) else t[i]
            fill = fills.get(_phase(mode[start]), DECLARATION["modes"][-1]["fill"])
            ax.axvspan(t[start], end, color=fill, lw=0, zorder=0)
            start = i


def _shaded_title(traj: Any) -> str:
    """The suffix of a shaded axis's title for the contact phases present, in order of
    appearance."""
    names = {m["mode"]: m["name"] for m in DECLARATION["modes"]}
    modes = [m for m in dict.fromkeys(_phase(m) for m in traj.mode.tolist()) if m]
    if not modes:
        return ""
    listed = ", ".join(f"{m} {names.get(m, DECLARATION['modes'][-1]['name'])}" for m in modes)
    return str(DECLARATION["shaded_suffix"]).replace("{modes}", listed)


def _time_axis(ax: Any, traj: Any, labels: bool = False) -> None:
    """The time label, the events (dashed; the first ones named when `labels`), the grid."""
    ax.set_xlabel(DECLARATION["time_label"])
    color = DECLARATION["events"]["color"]
    for i, e in enumerate(traj.events):
        ax.axvline(e["t"], color=color, ls="--", lw=0.9)
        if labels and i < _EVENT_LABELS:
            name = e.get("name", e["kind"])
            ax.annotate(name, (e["t"], 1.0), xycoords=("data", "axes fraction"), xytext=(2, -2),
                        textcoords="offset points", rotation=90, va="top", fontsize=7, color=color)
    ax.grid(alpha=0.3)


def _legend(ax: Any) -> None:
    """The legend beside the axes, off the data."""
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8)


def _columns(traj: Any, columns: str | Sequence[str]) -> list[str]:
    names = _names("columns", columns)
    if not names:
        raise _bad("columns", columns, "give at least one output column")
    for c in names:
        if c not in traj.columns or c in ("t", "mode"):
            raise _bad("columns", c, f"not a numeric output column; the columns are {', '.join(traj.columns[1:])}")
    return names


def _draw_column(ax: Any, traj: Any, name: str, labels: bool, alone: bool = True) -> None:
    """One output column against time; `alone` on its axes: titled by its name, in the
    declared colour (else in matplotlib's colour cycle, beside the others)."""
    unit = traj.units[name]
    color = DECLARATION["column_color"] if alone else None
    ax.plot(traj.t, traj[name], color=color, label=f"{name} ({unit})")
    ax.set_ylabel(f"{name} ({unit})")
    if alone:
        ax.set_title(name)
    _time_axis(ax, traj, labels=labels)


def _suptitle(traj: Any) -> str:
    """The figure's title, as `ellipsoid plot` makes it: the scenario's file name."""
    return os.path.basename(traj.scenario.source)


def _series_data(traj: Any, series: dict[str, Any]) -> tuple[np.ndarray, bool] | None:
    """A declared series' values against `traj.t` (NaN where left out) and whether some were
    left out: a column, or `energy_plus_work` (when work is dissipated) or `drift`; an
    `euler` series only where |sin θ| is at least the declared threshold. None when the
    trajectory lacks it."""
    data = series["data"]
    if data == "energy_plus_work":
        work = np.asarray(traj.work)
        if not np.any(work != 0):
            return None
        values = np.asarray(traj.energy) + work
    elif data == "drift":
        values = _drift(traj)[0]
    else:
        values = getattr(traj, data, None)
        if not isinstance(values, np.ndarray):
            return None
    if series.get("euler"):
        singular = np.abs(np.sin(traj.theta)) < DECLARATION["euler_min_sin_theta"]
        return np.where(singular, np.nan, values), bool(singular.any())
    return np.asarray(values), False


def _draw_axis(ax: Any, traj: Any, axis: dict[str, Any], labels: bool = False) -> None:
    """One declared axis against time: its series, its title with the suffixes of what is
    drawn (optional series present, Euler rates left out, the modes shaded)."""
    conserved = _drift(traj)[1]
    title = axis["title"].replace("{conserved}", conserved)
    left_out, drawn = False, 0
    for series in axis["series"]:
        if series["data"].endswith("_*"):
            colors = DECLARATION["surface_colors"]
            for k, (surface, values) in enumerate(_per_surface(traj, series["data"][:-2])):
                ax.plot(traj.t, values, color=colors[k % len(colors)], label=series["label"].replace("{surface}", surface))
                drawn += 1
            continue
        found = _series_data(traj, series)
        if found is None:
            if series.get("optional"):
                continue
            from ellipsoid._ellipsoid import InternalError

            # The panels' declaration names a series every trajectory has: a bug if not.
            raise InternalError(f"the {series['data']} series has no data")
        values, some_out = found
        left_out |= some_out
        if np.all(np.isnan(values)):
            continue
        label = series["label"].replace("{conserved}", conserved)
        if axis.get("log"):
            ax.semilogy(traj.t, np.maximum(np.abs(values), _FLOOR), color=series["color"], label=label)
        else:
            ax.plot(traj.t, values, color=series["color"], label=label)
        title += series.get("title_suffix", "")
        drawn += 1
    if left_out:
        title += DECLARATION["euler_singular_suffix"]
    if axis.get("shade") and len(traj):
        _shade(ax, traj)
        title += _shaded_title(traj)
    ax.set_title(title)
    ax.set_ylabel(axis["ylabel"])
    _time_axis(ax, traj, labels=labels)
    if drawn > 1 or traj.events:
        _legend(ax)


def _draw_path(ax: Any, traj: Any, axis: dict[str, Any]) -> None:
    """The declared path panel: the paths on the plane of G, the contact point and the
    geometric centre (those the trajectory gives), the start marked; equal scales."""
    paths = {"G": (traj.x, traj.y), "contact": traj._contact_path(), "centre": traj._centre_path()}
    widths = {"G": 2.0}
    for series in axis["series"]:
        data, color, label = series["data"], series["color"], series["label"]
        if data == "start":
            ax.plot([traj.x[0]], [traj.y[0]], "o", color=color, label=label)
        elif paths.get(data) is not None:
            x, y = paths[data]
            ax.plot(x, y, color=color, lw=widths.get(data, 0.8), label=label)
    unknown = axis["unknown_contact_suffix"].replace("{note}", "body unknown") if paths["contact"] is None else ""
    ax.set_title(axis["title"] + unknown)
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel(axis.get("xlabel", "x (m)"))
    ax.set_ylabel(axis["ylabel"])
    _legend(ax)
    ax.grid(alpha=0.3)


def _draw_panel(axes: Sequence[Any], traj: Any, name: str, labels: bool) -> None:
    """A declared panel into its axes (one per declared axis)."""
    declared = _BY_NAME[name]["axes"]
    if name == "path":
        _draw_path(axes[0], traj, declared[0])
        return
    for i, (ax, axis) in enumerate(zip(axes, declared)):
        _draw_axis(ax, traj, axis, labels=labels and i == 0)


def plot(traj: Any, panels: str | Sequence[str] | None = None, columns: str | Sequence[str] | None = None, ax: Any = None) -> Any:
    if ax is not None and not (callable(getattr(ax, "plot", None)) and hasattr(ax, "figure")):
        raise _bad("ax", ax, f"expected a matplotlib Axes, found {type(ax).__name__}", True)
    if columns is not None:
        if panels is not None:
            raise _bad("columns", columns, "give panels or columns, not both")
        names = _columns(traj, columns)
        if ax is not None:
            for i, c in enumerate(names):
                _draw_column(ax, traj, c, labels=i == 0, alone=len(names) == 1)
            if len(names) > 1:
                ax.set_ylabel(", ".join(f"{c} ({traj.units[c]})" for c in names))
            _legend(ax)
            return ax
        fig = _figure(figsize=(11, 2.6 * len(names)), layout="constrained")
        fig.suptitle(_suptitle(traj))
        axes = fig.subplots(len(names), 1, sharex=True, squeeze=False)[:, 0]
        for i, (a, c) in enumerate(zip(axes, names)):
            _draw_column(a, traj, c, labels=i == 0)
        return _axes(list(axes))
    names = _panels(traj, panels)
    if ax is not None:
        if len(names) != 1 or len(_BY_NAME[names[0]]["axes"]) != 1:
            single = ", ".join(n for n in PANELS if len(_BY_NAME[n]["axes"]) == 1)
            raise _bad("panels", panels, f"ax= takes one panel of {single} (or columns=); the others draw two axes")
        _draw_panel([ax], traj, names[0], labels=True)
        return ax
    fig = _figure(figsize=(11, 3.0 * len(names)), layout="constrained")
    grid = fig.add_gridspec(len(names), 2)
    fig.suptitle(_suptitle(traj))
    first_time = next((n for n in names if n != "path"), None)
    drawn: list[Any] = []
    for row, name in enumerate(names):
        if len(_BY_NAME[name]["axes"]) == 1:
            axes = [fig.add_subplot(grid[row, :])]
        else:
            axes = [fig.add_subplot(grid[row, 0]), fig.add_subplot(grid[row, 1])]
        _draw_panel(axes, traj, name, labels=name == first_time)
        drawn += axes
    return _axes(drawn)


def plot_section(traj: Any, name: Any, x: Any, y: Any, ax: Any = None, wrap: Any = None) -> Any:
    """`Trajectory.plot_section`: section `name`'s column `y` against column `x`, one
    marker per crossing, the axes labelled with the columns' SI units; the angle columns
    that `wrap` names (one name or several, of `x` and `y`) drawn modulo 2π, in [0, 2π)."""
    if ax is not None and not (callable(getattr(ax, "plot", None)) and hasattr(ax, "figure")):
        raise _bad("ax", ax, f"expected a matplotlib Axes, found {type(ax).__name__}", True)
    sections = traj.sections
    if not isinstance(name, str):
        raise _bad("name", name, f"expected the name of a section (str), found {type(name).__name__}", True)
    if name not in sections:
        known = ", ".join(sections) or "none: the scenario has no [[section]]"
        raise _bad("name", name, f"not a section of the scenario (its sections: {known})")
    points = sections[name]
    for key, column in (("x", x), ("y", y)):
        if not isinstance(column, str):
            raise _bad(key, column, f"expected a column name (str), found {type(column).__name__}", True)
        if column not in points or column == "mode":
            raise _bad(key, column, "not a numeric column (one of Trajectory.columns but mode)")
    wrapped = [wrap] if isinstance(wrap, str) else ([] if wrap is None else wrap)
    if not isinstance(wrapped, (list, tuple)) or not all(isinstance(w, str) for w in wrapped):
        raise _bad("wrap", wrap, "expected a column name or a list of them (str)", True)
    for w in wrapped:
        if w not in (x, y):
            raise _bad("wrap", w, f"not a column of this plot (x = {x!r}, y = {y!r})")
        if traj.units[w] != "rad":
            raise _bad("wrap", w, f"not an angle: its unit is {traj.units[w]}, and only angles (rad) are taken modulo 2π")
    # The second modulo maps a value that rounds to 2π (a tiny negative one) to 0.
    values = {c: np.mod(np.mod(points[c], 2 * np.pi), 2 * np.pi) if c in wrapped else points[c] for c in (x, y)}
    if ax is None:
        fig = _figure(figsize=(6, 5), layout="constrained")
        fig.suptitle(f"{_suptitle(traj)}: section {name}")
        ax = fig.subplots()
    ax.plot(values[x], values[y], ".", ms=3, label=f"{name} ({len(points[x])} points)")
    ax.set_xlabel(f"{x} ({traj.units[x]}{', modulo 2π' if x in wrapped else ''})")
    ax.set_ylabel(f"{y} ({traj.units[y]}{', modulo 2π' if y in wrapped else ''})")
    ax.grid(alpha=0.3)
    return ax
