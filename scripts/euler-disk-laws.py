#!/usr/bin/env python3
"""Euler's disk under each dissipation law: the figure of docs/physics.md ("Dissipation of
a rolling disc") and the gallery, docs/figures/euler-disk-laws.png, and the table of the
exponents fitted on the runs.

The disc of scenarios/euler-disk.toml is started on its steady motion with its centre
fixed at a tilt α0 = 0.05 rad and spun down by one law at a time (Moffatt's air film,
Bildsten's boundary layer, rolling friction), then by the scenario's own pair (rolling
friction and the boundary layer, Thorne et al.'s disc), each run until its tilt passes
2e-4 rad. Each run's tilt α and precession rate Ω are plotted against t0 − t on log–log
axes, t0 the time the approach's power law reaches α = 0, fitted within the second after
the tilt passes 3e-3 rad (`Trajectory.power_law`; under the air laws the disc then creeps
before it lands, so the landing is not the approach's t0), with the fitted slope of each
line in the legend beside the law's prediction.

    python scripts/euler-disk-laws.py             # writes the figure, prints the table
    python scripts/euler-disk-laws.py --markdown  # the table as markdown
"""
from __future__ import annotations

import argparse
import re
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import ellipsoid  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
SCENARIO = ROOT / "scenarios" / "euler-disk.toml"
FIGURE = ROOT / "docs" / "figures" / "euler-disk-laws.png"

# Air at 20 °C and 1 atm (the scenario's values).
VISCOSITY, DENSITY = 1.81e-5, 1.204
# The steady motion with the centre fixed at α0 = 0.05 rad (docs/physics.md, "Rims": "A
# disc spinning with its centre fixed", the lower rim: d = −4.9 mm, R = 35.9 mm, r = 1.6 mm).
START = {"theta": 0.05, "phi_dot": 139.56470825311774, "psi_dot": -138.13054086669425}
# The fitted window of t0 − t [s]: two decades before t0, above the lowest tilts where
# the air laws' creep takes over.
WINDOW = (0.03, 3.0)
# Where the run stops, and where the bracket of t0 starts: tilts [rad].
STOP, NEAR = 2e-4, 3e-3

# name, effects, predicted exponent of α (Ω ∝ α^(−1/2) on the thin disc).
LAWS = [
    ("air film (Moffatt)", {"air_film": {"viscosity": VISCOSITY}}, 1 / 3),
    ("boundary layer (Bildsten)", {"air_boundary_layer": {"viscosity": VISCOSITY, "density": DENSITY}}, 4 / 9),
    ("rolling friction, μ_r = 1e-4", {"rolling_friction": 1e-4}, 2 / 3),
    ("both (scenarios/euler-disk.toml)", None, None),
]  # fmt: skip


def scenario(effects: dict | None) -> ellipsoid.Scenario:
    """The scenario's disc from START with `effects` instead of its own (None: its own)."""
    text = SCENARIO.read_text()
    if effects is not None:
        text = re.sub(r"^(rolling_friction|air_boundary_layer) = .*\n", "", text, flags=re.M)
    base = ellipsoid.Scenario.from_toml(text, name="euler-disk")
    changes = {"initial": START, "output": {"t_end": 40.0, "dt": 1e-4}}
    if effects is not None:
        changes["effects"] = effects
    return base.replace(**changes)


def run(effects: dict | None) -> tuple[ellipsoid.Trajectory, dict, dict]:
    """The run and its fitted power laws of α (theta) and Ω (phi_dot)."""
    observe = [
        {"name": "near", "column": "theta", "crosses": NEAR, "direction": "down"},
        {"name": "stop", "column": "theta", "crosses": STOP, "direction": "down", "terminal": True},
    ]
    traj = ellipsoid.simulate(scenario(effects), observe=observe)
    near = traj.t_events["near"][0]
    alpha = traj.power_law("theta", WINDOW, t0=(near, near + 1.0))
    return traj, alpha, traj.power_law("phi_dot", WINDOW, t0=alpha["t0"])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--markdown", action="store_true", help="print the table as markdown")
    args = parser.parse_args()
    fig, (ax_a, ax_w) = plt.subplots(1, 2, figsize=(10, 4.2), constrained_layout=True)
    rows = []
    for name, effects, predicted in LAWS:
        traj, alpha, omega = run(effects)
        tau = alpha["t0"] - traj.t
        keep = tau > 0
        label = f"{name}: {alpha['exponent']:.3f}" + (f" ({predicted:.3f})" if predicted else "")
        ax_a.loglog(tau[keep], traj["theta"][keep], label=label)
        label_w = f"{name}: {omega['exponent']:.3f}" + (f" ({-predicted / 2:.3f})" if predicted else "")
        ax_w.loglog(tau[keep], np.abs(traj["phi_dot"][keep]), label=label_w)
        rows.append((name, alpha, omega, predicted, traj))
    for ax, what in ((ax_a, "tilt α [rad]"), (ax_w, "precession rate |Ω| [rad/s]")):
        ax.axvspan(*WINDOW, color="0.92", zorder=0)
        ax.set_xlabel("t0 − t [s]")
        ax.set_ylabel(what)
        ax.legend(fontsize=7, title="fitted slope (predicted)", title_fontsize=7)
        ax.grid(True, which="both", lw=0.3)
    ax_a.set_title("Euler's disk from α0 = 0.05 rad: the tilt")
    ax_w.set_title("and the precession rate")
    FIGURE.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(FIGURE, dpi=110)
    print(f"wrote {FIGURE.relative_to(ROOT)}")
    head = "| law | exponent of α (predicted) | exponent of Ω (predicted) | fitted t0 (s) |"
    print(head if args.markdown else head.replace("|", " "))
    if args.markdown:
        print("|---|---|---|---|")
    for name, alpha, omega, predicted, traj in rows:
        p = f" ({predicted:.4f})" if predicted else ""
        q = f" ({-predicted / 2:.4f})" if predicted else ""
        line = f"| {name} | {alpha['exponent']:.4f}{p} | {omega['exponent']:.4f}{q} | {alpha['t0']:.4f} |"
        print(line if args.markdown else line.replace("|", " "))


if __name__ == "__main__":
    main()
