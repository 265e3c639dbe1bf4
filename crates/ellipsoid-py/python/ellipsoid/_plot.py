"""`Trajectory.plot`: the panels of `ellipsoid plot` drawn with matplotlib (an optional
dependency, imported only here).

Panels, top to bottom: theta (θ(t)), rates (θ̇, φ̇, ψ̇, and the world-frame vertical spin
when the trajectory has it; φ̇ and ψ̇ are left out where sin θ < 0.1, near the z-x-z
singularity at θ = 0 where they diverge as 1/sin θ), energy (E, E + W when work is dissipated, and the relative
drift of the conserved quantity on a log axis), forces (normal force and slip speed with
the contact mode shaded), path (the paths on the plane of the contact point, G and the geometric centre C0). Events
are dashed vertical lines, labelled by kind in the first time panel. SI units on every
axis. Or any output columns, one panel each (`columns=`), or drawn into an existing
matplotlib Axes (`ax=`), so figures compose.

In a Jupyter notebook the Figure displays itself (PNG, no `%matplotlib inline` needed);
in a script it is a pyplot figure, so `plt.show()` shows it and `fig.savefig("x.pdf")`
writes PDF, SVG or PNG.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import io
import sys

import numpy as np

PANELS = ("theta", "rates", "energy", "forces", "path")
_MODE_COLORS = {"sliding": "#ffe3c4", "rolling": "#d4f0d4", "frictionless": "#eeeeee"}
_EVENT = "#8040a0"
#: Below this sin θ the Euler rates φ̇, ψ̇ are not drawn (they diverge as 1/sin θ).
_SIN_SINGULAR = 0.1
#: At most this many events are labelled (all are drawn).
_EVENT_LABELS = 12


def _in_kernel() -> bool:
    """Whether this runs in a Jupyter kernel, which displays what a cell returns."""
    ipython = sys.modules.get("IPython")
    shell = ipython.get_ipython() if ipython is not None else None  # type: ignore[attr-defined]
    return shell is not None and hasattr(shell, "kernel")


def _png(fig: Any) -> bytes:
    """A figure as PNG (Jupyter's `_repr_png_`)."""
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=80)
    return buf.getvalue()


def _figure(**kw: Any) -> Any:
    """A matplotlib Figure that Jupyter displays as PNG without `%matplotlib inline`
    (`_repr_png_`); outside a Jupyter kernel it is pyplot's (so `plt.show()` shows it)."""
    try:
        from matplotlib.figure import Figure
    except ImportError as e:  # pragma: no cover - exercised with matplotlib hidden
        raise ImportError(f"Trajectory.plot needs matplotlib (`pip install matplotlib`): {e}") from e
    cls = type("TrajectoryFigure", (Figure,), {"_repr_png_": _png})
    if not _in_kernel():
        try:
            import matplotlib.pyplot as plt

            return plt.figure(FigureClass=cls, **kw)
        except ImportError:  # pragma: no cover - pyplot without a usable backend
            pass
    return cls(**kw)


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


def _panels(panels: str | Sequence[str] | None) -> list[str]:
    if panels is None:
        return list(PANELS)
    names = _names("panels", panels)
    if not names:
        raise _bad("panels", panels, f"give at least one of {', '.join(PANELS)}")
    for i, p in enumerate(names):
        if p not in PANELS:
            raise _bad("panels", p, f"unknown panel {p!r}; the panels are {', '.join(PANELS)}")
        if p in names[:i]:
            raise _bad("panels", p, "a panel is named twice")
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


def _time_axis(ax: Any, traj: Any, shade: bool = False, labels: bool = False) -> None:
    ax.set_xlabel("time t (s)")
    events = traj.events
    for i, e in enumerate(events):
        ax.axvline(e["t"], color=_EVENT, ls="--", lw=0.9)
        if labels and i < _EVENT_LABELS:
            name = e.get("name", e["kind"])
            ax.annotate(name, (e["t"], 1.0), xycoords=("data", "axes fraction"), xytext=(2, -2),
                        textcoords="offset points", rotation=90, va="top", fontsize=7, color=_EVENT)
    if shade and len(traj):
        t, mode = traj.t, traj.mode
        start = 0
        for i in range(1, len(t) + 1):
            if i == len(t) or mode[i] != mode[start]:
                end = t[i - 1] if i == len(t) else t[i]
                ax.axvspan(t[start], end, color=_MODE_COLORS.get(str(mode[start]), "#e0e0f8"), lw=0, zorder=0)
                start = i
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


def _draw_column(ax: Any, traj: Any, name: str, labels: bool) -> None:
    unit = traj.units[name]
    ax.plot(traj.t, getattr(traj, name), label=f"{name} ({unit})")
    ax.set_ylabel(f"{name} ({unit})")
    _time_axis(ax, traj, labels=labels)


def _draw_rates(ax: Any, traj: Any) -> None:
    t = traj.t
    singular = np.abs(np.sin(traj.theta)) < _SIN_SINGULAR
    ax.plot(t, traj.theta_dot, label="θ̇ (theta_dot)")
    for data, label in ((traj.phi_dot, "φ̇ (phi_dot)"), (traj.psi_dot, "ψ̇ (psi_dot)")):
        ax.plot(t, np.where(singular, np.nan, data), label=label)
    wz = getattr(traj, "omega_world_z", None)
    if wz is not None:
        ax.plot(t, wz, label="ω_z, world (omega_world_z)")
    ax.set_ylabel("rate (rad/s)")
    title = "Euler rates" + (" and the vertical spin" if wz is not None else "")
    if singular.any():
        title += f" (φ̇, ψ̇ hidden where sin θ < {_SIN_SINGULAR}: singular there)"
    ax.set_title(title)
    _legend(ax)
    _time_axis(ax, traj)


def _draw_path(ax: Any, traj: Any) -> None:
    ax.plot(traj.x, traj.y, color="#808080", lw=2, label="G")
    contact = traj._contact_path()
    centre = traj._centre_path()
    if contact is not None:
        ax.plot(contact[0], contact[1], color="#1f77b4", lw=0.8, label="contact point")
        ax.set_title("paths on the plane: contact point, G" + (", centre C0" if centre is not None else ""))
    if centre is not None:
        ax.plot(centre[0], centre[1], color="#ff7f0e", lw=0.8, label="centre C0")
    else:
        ax.set_title("path of G on the plane")
    ax.plot([traj.x[0]], [traj.y[0]], "o", color="#2ca02c", label="start")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    _legend(ax)
    ax.grid(alpha=0.3)


def _draw_theta(ax: Any, traj: Any) -> None:
    ax.plot(traj.t, traj.theta, color="#1f77b4", label="θ")
    ax.set_ylabel("θ (rad)")
    ax.set_title("tilt of the symmetry axis θ")
    _time_axis(ax, traj, labels=True)


#: The panels drawn on one Axes (the others take two).
_SINGLE = {"theta": _draw_theta, "rates": _draw_rates, "path": _draw_path}


def plot(traj: Any, panels: str | Sequence[str] | None = None, columns: str | Sequence[str] | None = None, ax: Any = None) -> Any:
    if ax is not None and not (callable(getattr(ax, "plot", None)) and hasattr(ax, "figure")):
        raise _bad("ax", ax, f"expected a matplotlib Axes, found {type(ax).__name__}", True)
    if columns is not None:
        if panels is not None:
            raise _bad("columns", columns, "give panels or columns, not both")
        names = _columns(traj, columns)
        if ax is not None:
            for i, c in enumerate(names):
                _draw_column(ax, traj, c, labels=i == 0)
            if len(names) > 1:
                ax.set_ylabel(", ".join(f"{c} ({traj.units[c]})" for c in names))
            _legend(ax)
            return ax.figure
        fig = _figure(figsize=(11, 2.6 * len(names)), layout="constrained")
        fig.suptitle(traj.scenario.source)
        axes = fig.subplots(len(names), 1, sharex=True, squeeze=False)[:, 0]
        for i, (a, c) in enumerate(zip(axes, names)):
            _draw_column(a, traj, c, labels=i == 0)
        return fig
    names = _panels(panels)
    if ax is not None:
        if len(names) != 1 or names[0] not in _SINGLE:
            raise _bad("panels", panels, f"ax= takes one panel of {', '.join(_SINGLE)} (or columns=); energy and forces draw two axes")
        _SINGLE[names[0]](ax, traj)
        return ax.figure
    fig = _figure(figsize=(11, 3.0 * len(names)), layout="constrained")
    grid = fig.add_gridspec(len(names), 2)
    t = traj.t
    fig.suptitle(traj.scenario.source)
    for row, name in enumerate(names):
        if name in _SINGLE:
            _SINGLE[name](fig.add_subplot(grid[row, :]), traj)
        elif name == "energy":
            ax = fig.add_subplot(grid[row, 0])
            ax.plot(t, traj.energy, label="E")
            d, what = _drift(traj)
            if what == "E + W":
                ax.plot(t, traj.energy + traj.work, color="#2ca02c", label="E + W")
                _legend(ax)
            ax.set_ylabel("energy (J)")
            ax.set_title("energy")
            _time_axis(ax, traj)
            ax = fig.add_subplot(grid[row, 1])
            ax.semilogy(t, np.maximum(np.abs(d), 1e-17), color="#d62728")
            ax.set_ylabel("|relative drift| (1, log)")
            ax.set_title(f"relative drift of {what}")
            _time_axis(ax, traj)
        else:
            for col, (data, label, title) in enumerate(
                ((traj.normal_force, "normal force N (N)", "normal force"), (traj.slip_speed, "slip speed |v_C| (m/s)", "slip speed"))
            ):
                ax = fig.add_subplot(grid[row, col])
                ax.plot(t, data, color="#1f77b4" if col == 0 else "#ff7f0e")
                ax.set_ylabel(label)
                ax.set_title(f"{title} (shaded: contact mode)")
                _time_axis(ax, traj, shade=True)
    return fig
