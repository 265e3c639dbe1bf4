"""`Trajectory.plot`: the panels of `ellipsoid plot` drawn with matplotlib (an optional
dependency, imported only here).

Panels, top to bottom: theta (θ(t)), rates (θ̇, φ̇, ψ̇, and the world-frame vertical spin
when the trajectory has it), energy (E, E + W when work is dissipated, and the relative
drift of the conserved quantity on a log axis), forces (normal force and slip speed with
the contact mode shaded), path (the paths on the plane of the contact point, G and the geometric centre C0). Events
are dashed vertical lines. SI units on every axis.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

PANELS = ("theta", "rates", "energy", "forces", "path")
_MODE_COLORS = {"sliding": "#ffe3c4", "rolling": "#d4f0d4", "frictionless": "#eeeeee"}
_EVENT = "#8040a0"


def _panels(panels: str | Sequence[str] | None) -> list[str]:
    if panels is None:
        return list(PANELS)
    names = [p.strip() for p in panels.split(",")] if isinstance(panels, str) else list(panels)
    if not names:
        raise ValueError(f"panels: give at least one of {', '.join(PANELS)}")
    for i, p in enumerate(names):
        if p not in PANELS:
            raise ValueError(f"panels: unknown panel {p!r}; the panels are {', '.join(PANELS)}")
        if p in names[:i]:
            raise ValueError(f"panels: {p!r} is named twice")
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


def _time_axis(ax: Any, traj: Any, shade: bool = False) -> None:
    ax.set_xlabel("time t (s)")
    for e in traj.events:
        ax.axvline(e["t"], color=_EVENT, ls="--", lw=0.9)
    if shade and len(traj):
        t, mode = traj.t, traj.mode
        start = 0
        for i in range(1, len(t) + 1):
            if i == len(t) or mode[i] != mode[start]:
                end = t[i - 1] if i == len(t) else t[i]
                ax.axvspan(t[start], end, color=_MODE_COLORS.get(str(mode[start]), "#e0e0f8"), lw=0, zorder=0)
                start = i
    ax.grid(alpha=0.3)


def plot(traj: Any, panels: str | Sequence[str] | None = None) -> Any:
    names = _panels(panels)
    try:
        from matplotlib.figure import Figure
    except ImportError as e:  # pragma: no cover - exercised with matplotlib hidden
        raise ImportError(f"Trajectory.plot needs matplotlib (`pip install matplotlib`): {e}") from e
    fig = Figure(figsize=(11, 3.0 * len(names)), layout="constrained")
    grid = fig.add_gridspec(len(names), 2)
    t = traj.t
    fig.suptitle(traj.scenario.source)
    for row, name in enumerate(names):
        if name == "theta":
            ax = fig.add_subplot(grid[row, :])
            ax.plot(t, traj.theta, color="#1f77b4", label="θ")
            ax.set_ylabel("θ (rad)")
            ax.set_title("tilt of the symmetry axis θ")
            _time_axis(ax, traj)
        elif name == "rates":
            ax = fig.add_subplot(grid[row, :])
            ax.plot(t, traj.theta_dot, label="θ̇ (theta_dot)")
            ax.plot(t, traj.phi_dot, label="φ̇ (phi_dot)")
            ax.plot(t, traj.psi_dot, label="ψ̇ (psi_dot)")
            wz = getattr(traj, "omega_world_z", None)
            if wz is not None:
                ax.plot(t, wz, label="ω_z, world (omega_world_z)")
            ax.set_ylabel("rate (rad/s)")
            ax.set_title("Euler rates" + (" and the vertical spin" if wz is not None else ""))
            ax.legend(loc="upper right")
            _time_axis(ax, traj)
        elif name == "energy":
            ax = fig.add_subplot(grid[row, 0])
            ax.plot(t, traj.energy, label="E")
            d, what = _drift(traj)
            if what == "E + W":
                ax.plot(t, traj.energy + traj.work, color="#2ca02c", label="E + W")
                ax.legend(loc="upper right")
            ax.set_ylabel("energy (J)")
            ax.set_title("energy")
            _time_axis(ax, traj)
            ax = fig.add_subplot(grid[row, 1])
            ax.semilogy(t, np.maximum(np.abs(d), 1e-17), color="#d62728")
            ax.set_ylabel("|relative drift| (1, log)")
            ax.set_title(f"relative drift of {what}")
            _time_axis(ax, traj)
        elif name == "forces":
            for col, (data, label, title) in enumerate(
                ((traj.normal_force, "normal force N (N)", "normal force"), (traj.slip_speed, "slip speed |v_C| (m/s)", "slip speed"))
            ):
                ax = fig.add_subplot(grid[row, col])
                ax.plot(t, data, color="#1f77b4" if col == 0 else "#ff7f0e")
                ax.set_ylabel(label)
                ax.set_title(f"{title} (shaded: contact mode)")
                _time_axis(ax, traj, shade=True)
        else:
            ax = fig.add_subplot(grid[row, :])
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
            ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0))
            ax.grid(alpha=0.3)
    return fig
