#!/usr/bin/env python3
"""Regenerates the reproduction of the seed paper's figures and tables.

    python scripts/paper.py --out docs/paper

Runs the scenarios of `scenarios/paper/` with the `ellipsoid` command-line tool (found at
$ELLIPSOID_CLI, else $CARGO_TARGET_DIR/release/ellipsoid or target/release/ellipsoid, built
with cargo if absent) and writes, into --out:

- figNN.png for Figs. 7–24 (and fig07b.png, Fig. 7 with Table 1's mass m = 1e-4 kg),
- table1.csv/.md and table2.csv/.md,
- measurements.json: every number quoted in docs/paper-reproduction.md.

Needs Python 3.11+ with numpy and matplotlib. Each figure's scenario file, with its
`--set` overrides, is named in the figure's footer and in docs/paper-reproduction.md.
"""

from __future__ import annotations

import argparse
import csv
import json
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
SCEN = ROOT / "scenarios" / "paper"
DPI = 100

# The paper's parameter sweeps.
C_VALUES = [0.0125, 0.015, 0.0175, 0.02, 0.0225]  # Fig. 7, 9 (m)
TABLE1 = [  # D2 (m), I (kg m^2) as printed in Table 1
    (0.0001, 3.075001e-6), (0.0010, 3.0751e-6), (0.0020, 3.0754e-6), (0.0030, 3.0759e-6),
    (0.0040, 3.0766e-6), (0.0050, 3.0775e-6), (0.0060, 3.0786e-6), (0.0065, 3.0792e-6),
    (0.0070, 3.0799e-6), (0.0075, 3.0806e-6), (0.0078, 3.0810e-6), (0.0080, 3.0814e-6),
    (0.0090, 3.0831e-6), (0.010, 3.085e-6),
]
TABLE2 = [  # D2, E_min, E_max, dE, mean E, % error, as printed in Table 2 (J)
    (0.0001, 0.0216, 0.02241, 0.00081, 0.0219900, 3.68),
    (0.0010, 0.02136, 0.02228, 0.00092, 0.0217800, 4.216),
    (0.0020, 0.02108, 0.02213, 0.00068, 0.0215400, 3.147),
    (0.0030, 0.02082, 0.02198, 0.00116, 0.0214000, 5.445),
    (0.0040, 0.02059, 0.02184, 0.00125, 0.0212100, 5.892),
    (0.0050, 0.02042, 0.02169, 0.00127, 0.0211000, 6.031),
    (0.0060, 0.02033, 0.02155, 0.00122, 0.0209500, 5.826),
    (0.0070, 0.02029, 0.02140, 0.00111, 0.0209400, 5.325),
    (0.0080, 0.02030, 0.02125, 0.00095, 0.0207900, 4.572),
    (0.0090, 0.02033, 0.02111, 0.00078, 0.0208000, 3.769),
    (0.010, 0.02035, 0.02096, 0.00061, 0.0207200, 2.953),
]
DOP853 = ["solver.method=dop853", "solver.rtol=1e-11", "solver.atol=1e-13"]


# ----------------------------------------------------------------------------- running


def find_cli() -> Path:
    """The `ellipsoid` binary: $ELLIPSOID_CLI, else the release build (built if absent)."""
    env = os.environ.get("ELLIPSOID_CLI")
    if env:
        return Path(env)
    target = Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    if not target.is_absolute():
        target = ROOT / target
    exe = target / "release" / ("ellipsoid.exe" if os.name == "nt" else "ellipsoid")
    if not exe.exists():
        if shutil.which("cargo") is None:
            sys.exit(f"paper.py: {exe} not found and cargo is not on PATH; set ELLIPSOID_CLI")
        print(f"building {exe} (cargo build --release -p ellipsoid-cli) …", file=sys.stderr)
        subprocess.run(["cargo", "build", "--release", "-p", "ellipsoid-cli"], cwd=ROOT, check=True)
    return exe


class Runner:
    """Runs scenarios through the CLI into a scratch directory and reads them back."""

    def __init__(self, cli: Path, scratch: Path):
        self.cli = cli
        self.scratch = scratch
        self.count = 0

    def __call__(self, name: str, sets: list[str] | tuple[str, ...] = ()) -> "Run":
        self.count += 1
        csv_path = self.scratch / f"run{self.count}.csv"
        json_path = self.scratch / f"run{self.count}.json"
        cmd = [str(self.cli), "run", str(SCEN / name), "-o", str(csv_path), "--summary", str(json_path), "-q"]
        for s in sets:
            cmd += ["--set", s]
        proc = subprocess.run(cmd, capture_output=True, text=True)
        if proc.returncode not in (0, 3):  # 3: stopped early, an outcome (trajectory written)
            sys.exit(f"paper.py: {' '.join(cmd)} failed ({proc.returncode}):\n{proc.stderr}")
        return Run(name, list(sets), csv_path, json.loads(json_path.read_text()))


class Run:
    def __init__(self, name: str, sets: list[str], csv_path: Path, summary: dict):
        self.name, self.sets, self.summary = name, sets, summary
        with open(csv_path, newline="") as f:  # skipping the `#` comment line
            rows = list(csv.reader(line for line in f if not line.startswith("#")))
        head = rows[0]
        cols = list(zip(*rows[1:]))
        self.mode = np.array(cols[head.index("mode")])
        self.d = {h: np.array(c, dtype=float) for h, c in zip(head, cols) if h != "mode"}

    def __getitem__(self, key: str) -> np.ndarray:
        return self.d[key]

    @property
    def label(self) -> str:
        return f"scenarios/paper/{self.name}" + "".join(f" --set {s}" for s in self.sets)


# ----------------------------------------------------------------------------- analysis


def maxima(t: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Interior local maxima, refined by a parabola through the three samples: (times, values)."""
    i = np.where((y[1:-1] > y[:-2]) & (y[1:-1] >= y[2:]))[0] + 1
    y0, y1, y2 = y[i - 1], y[i], y[i + 1]
    den = y0 - 2 * y1 + y2
    off = np.where(den != 0, 0.5 * (y0 - y2) / np.where(den != 0, den, 1), 0.0)
    h = t[1] - t[0]
    return t[i] + off * h, y1 - 0.25 * (y0 - y2) * off


def minima(t: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    tm, v = maxima(t, -y)
    return tm, -v


def period(t: np.ndarray, y: np.ndarray) -> float:
    tm, _ = maxima(t, y)
    return float(np.mean(np.diff(tm))) if len(tm) > 1 else float("nan")


def c0(r: Run, d2: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The geometric centre C0 = G + D2 e3*, e3* = (sin φ sin θ, −cos φ sin θ, cos θ) (paper eq. 1)."""
    th, ph = r["theta"], r["phi"]
    return r["x"] + d2 * np.sin(ph) * np.sin(th), r["y"] - d2 * np.cos(ph) * np.sin(th), r["z"] + d2 * np.cos(th)


def self_intersections(x: np.ndarray, y: np.ndarray) -> int:
    """Proper crossings between non-adjacent segments of the polyline (x, y)."""
    p = np.stack([x, y], 1)
    a, b = p[:-1], p[1:]
    count = 0

    def orient(p0, p1, q):
        return (p1[..., 0] - p0[..., 0]) * (q[..., 1] - p0[..., 1]) - (p1[..., 1] - p0[..., 1]) * (q[..., 0] - p0[..., 0])

    for i in range(len(a) - 2):
        c, d = a[i + 2:], b[i + 2:]
        o1, o2 = orient(a[i], b[i], c), orient(a[i], b[i], d)
        o3, o4 = orient(c, d, a[i][None, :]), orient(c, d, b[i][None, :])
        count += int(np.sum((o1 * o2 < 0) & (o3 * o4 < 0)))
    return count


def rosette_centre(t: np.ndarray, theta: np.ndarray, x: np.ndarray, y: np.ndarray) -> tuple[float, float]:
    """Centre of the rosette drawn by C0: the circle through C0 at the minima of θ (t = 0, T, 2T, …),
    fitted by least squares (x² + y² = 2 cx x + 2 cy y + k)."""
    i = list(np.where((theta[1:-1] < theta[:-2]) & (theta[1:-1] <= theta[2:]))[0] + 1)
    if theta[0] <= theta[1]:
        i = [0] + i
    a = np.column_stack([2 * x[i], 2 * y[i], np.ones(len(i))])
    sol = np.linalg.lstsq(a, x[i] ** 2 + y[i] ** 2, rcond=None)[0]
    return float(sol[0]), float(sol[1])


def spread(e: np.ndarray) -> dict:
    lo, hi, mean = float(e.min()), float(e.max()), float(e.mean())
    return {"E_min": lo, "E_max": hi, "dE": hi - lo, "E_mean": mean, "percent": 100 * (hi - lo) / mean}


# ----------------------------------------------------------------------------- plotting


def footer(fig, text: str) -> None:
    fig.text(0.005, 0.005, text, fontsize=6, color="0.4", ha="left", va="bottom")


def save(fig, out: Path, name: str) -> None:
    fig.savefig(out / name, dpi=DPI)
    plt.close(fig)
    print(f"  {out / name}")


def fmt_md_table(header: list[str], rows: list[list[str]]) -> str:
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(r) + " |" for r in rows]
    return "\n".join(lines) + "\n"


# ----------------------------------------------------------------------------- sections


def frictionless(run: Runner, out: Path, m: dict) -> None:
    print("frictionless (Figs. 7–9)")
    base = "fig07-frictionless-theta.toml"
    runs = [run(base, [f"body.c={c}"]) for c in C_VALUES]
    fig, ax = plt.subplots(figsize=(7, 4.5))
    rows = []
    for c, r in zip(C_VALUES, runs):
        th = np.degrees(r["theta"])
        T = period(r["t"], r["theta"])
        ax.plot(r["t"], th, lw=1.2, label=f"c = {c} m: θ ∈ [{th.min():.2f}°, {th.max():.2f}°], T = {T * 1e3:.1f} ms")
        rows.append({"c": c, "theta_min_deg": float(th.min()), "theta_max_deg": float(th.max()),
                     "amplitude_deg": float(th.max() - th.min()), "period_s": T,
                     "energy_drift": r.summary["drift"]["energy"]})
    ax.set(xlabel="t (s)", ylabel="θ (°)", xlim=(0, 0.4), ylim=(0, 13),
           title="Fig. 7 (reproduced): θ(t) without friction as c varies")
    ax.legend(fontsize=7, loc="upper right")
    footer(fig, f"scenarios/paper/{base} --set body.c=… (DOP853, rtol 1e-11)")
    fig.tight_layout(rect=(0, 0.02, 1, 1))
    save(fig, out, "fig07.png")
    m["fig07"] = rows

    # Fig. 7 with Table 1's mass: the curves hardly depend on c.
    fig, ax = plt.subplots(figsize=(7, 4.5))
    rows = []
    for c in C_VALUES:
        r = run(base, [f"body.c={c}", "body.mass=1e-4"])
        th = np.degrees(r["theta"])
        ax.plot(r["t"], th, lw=1.2, label=f"c = {c} m: θmax = {th.max():.2f}°")
        rows.append({"c": c, "theta_max_deg": float(th.max())})
    ax.set(xlabel="t (s)", ylabel="θ (°)", xlim=(0, 0.4),
           title="Fig. 7 with Table 1's mass m = 1e-4 kg: c hardly matters")
    ax.legend(fontsize=7)
    footer(fig, f"scenarios/paper/{base} --set body.c=… --set body.mass=1e-4")
    fig.tight_layout(rect=(0, 0.02, 1, 1))
    save(fig, out, "fig07b.png")
    m["fig07b_mass_1e-4"] = rows
    # The trend with c depends on the initial state: released at 12° spinning about its own
    # axis only, the amplitude falls as c grows.
    rows = []
    for c in (C_VALUES[0], C_VALUES[-1]):
        r = run(base, [f"body.c={c}", "initial.theta_deg=12.0", "initial.phi_dot=0.0", "initial.psi_dot=60.0"])
        th = np.degrees(r["theta"])
        rows.append({"c": c, "theta_min_deg": float(th.min()), "theta_max_deg": float(th.max())})
    m["fig07_spin_only_theta0_12deg_psi_dot_60"] = rows

    # Fig. 8: the three rates at c = 0.0125 m share the period of θ.
    r = run("fig08-frictionless-rates.toml")
    t = r["t"]
    tmax, _ = maxima(t, r["theta"])
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for key, lab in [("theta_dot", "θ̇"), ("phi_dot", "φ̇"), ("psi_dot", "ψ̇")]:
        ax.plot(t, r[key], lw=1.2, label=lab)
    for tm in tmax:
        ax.axvline(tm, color="0.6", lw=0.6, ls="--")
    ax.set(xlabel="t (s)", ylabel="rate (rad/s)", xlim=(0, 0.4),
           title="Fig. 8 (reproduced): Euler-angle rates, c = 0.0125 m (dashed: maxima of θ)")
    ax.legend(fontsize=8)
    footer(fig, "scenarios/paper/fig08-frictionless-rates.toml")
    fig.tight_layout(rect=(0, 0.02, 1, 1))
    save(fig, out, "fig08.png")
    T = period(t, r["theta"])
    m["fig08"] = {"period_theta_s": T, **{f"period_{k}_s": period(t, r[k]) for k in ("theta_dot", "phi_dot", "psi_dot")},
                  "phi_dot_range": [float(r["phi_dot"].min()), float(r["phi_dot"].max())],
                  "psi_dot_range": [float(r["psi_dot"].min()), float(r["psi_dot"].max())],
                  "theta_dot_range": [float(r["theta_dot"].min()), float(r["theta_dot"].max())]}

    # Fig. 9: energy, with the paper's RK4 h = 1e-4 and with DOP853.
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 4.2))
    rows = []
    for k, c in enumerate(C_VALUES):
        rk = run("fig09-frictionless-energy.toml", [f"body.c={c}"])
        dp = run("fig09-frictionless-energy.toml", [f"body.c={c}", *DOP853])
        a1.plot(rk["t"], rk["energy"] * 1e3, lw=1.2, color=f"C{k}", label=f"c = {c} m")
        e0 = rk["energy"][0]
        a2.plot(dp["t"], (dp["energy"] - dp["energy"][0]) / dp["energy"][0], lw=0.6, ls=":", color=f"C{k}", label=f"DOP853, c = {c} m")
        a2.plot(rk["t"], (rk["energy"] - e0) / e0, lw=1.2, color=f"C{k}", label=f"RK4 h = 1e-4, c = {c} m")
        rows.append({"c": c, "energy_J": float(e0), "rk4_drift": rk.summary["drift"]["energy"],
                     "dop853_drift": dp.summary["drift"]["energy"]})
    a1.set(xlabel="t (s)", ylabel="E (mJ)", title="Fig. 9 (reproduced): energy without friction")
    a1.legend(fontsize=7)
    a2.set(xlabel="t (s)", ylabel="(E − E0)/E0", title="relative deviation: round-off level")
    a2.ticklabel_format(axis="y", style="sci", scilimits=(0, 0))
    a2.legend(fontsize=5, ncol=2)
    footer(fig, "scenarios/paper/fig09-frictionless-energy.toml --set body.c=… (RK4 h = 1e-4; DOP853 with --set solver.method=dop853 …)")
    fig.tight_layout(rect=(0, 0.02, 1, 1))
    save(fig, out, "fig09.png")
    m["fig09"] = rows


def sliding(run: Runner, out: Path, m: dict) -> None:
    print("sliding (Figs. 10–11)")
    r = run("fig10-sliding-theta.toml")
    t, th, thd = r["t"], np.degrees(r["theta"]), np.degrees(r["theta_dot"])
    stops = [e["t"] for e in r.summary["events"] if e["kind"] == "slip_stop"]
    t90 = float(t[np.argmax(th > 90)]) if (th > 90).any() else None
    late = t >= 5.0
    tm_late, _ = maxima(t[late], th[late])
    m["fig10"] = {
        "theta0_deg": float(th[0]), "t_cross_90_s": t90, "theta_max_deg": float(th.max()),
        "t_theta_max_s": float(t[np.argmax(th)]), "slip_stop_s": stops,
        "theta_after_5s_deg": [float(th[late].min()), float(th[late].max())],
        "period_after_5s_s": float(np.mean(np.diff(tm_late))) if len(tm_late) > 1 else None,
        "theta_before_2s_deg": [float(th[t <= 2].min()), float(th[t <= 2].max())],
        "energy_J": [float(r["energy"][0]), float(r["energy"][-1])],
        "energy_plus_work_drift": r.summary["drift"]["energy_plus_work"],
        "final_mode": str(r.mode[-1]),
        "theta_at_deg": {f"{tq:g}": float(np.interp(tq, t, th)) for tq in (0.5, 1.0, 2.0, 3.0, 3.5)},
    }
    m["fig11"] = {"theta_dot_max_abs_deg_s": float(np.abs(thd).max()),
                  "theta_dot_max_abs_deg_s_after_5s": float(np.abs(thd[late]).max())}

    def marks(ax):
        for s in stops:
            ax.axvline(s, color="C3", lw=0.8, ls="--")
            ax.annotate("slip stops: rolling from here", (s, 0.5), xycoords=("data", "axes fraction"),
                        fontsize=7, color="C3", rotation=90, ha="right", va="center")

    fig, ax = plt.subplots(figsize=(7, 4.5))
    ax.plot(t, th, lw=1.0)
    ax.axhline(90, color="0.7", lw=0.6)
    marks(ax)
    ax.set(xlabel="t (s)", ylabel="θ (°)", xlim=(0, 10), ylim=(0, 180),
           title="Fig. 10 (reproduced): θ(t) with sliding friction, c = 0.0225 m, μ = 0.1")
    ins = ax.inset_axes([0.55, 0.12, 0.4, 0.32])
    sel = t <= 2.1
    ins.plot(t[sel], th[sel], lw=0.7)
    ins.set_title("t ∈ [0, 2.1] s", fontsize=7)
    ins.tick_params(labelsize=6)
    footer(fig, "scenarios/paper/fig10-sliding-theta.toml (model coulomb: sliding, then rolling once the slip stops)")
    fig.tight_layout(rect=(0, 0.02, 1, 1))
    save(fig, out, "fig10.png")

    r = run("fig11-sliding-theta-dot.toml")
    fig, ax = plt.subplots(figsize=(7, 4.5))
    ax.plot(t, thd, lw=0.5)
    marks(ax)
    ax.set(xlabel="t (s)", ylabel="θ̇ (°/s)", xlim=(0, 10),
           title="Fig. 11 (reproduced): θ̇(t) with sliding friction, c = 0.0225 m")
    ins = ax.inset_axes([0.62, 0.62, 0.35, 0.3])
    sel = (t >= 6) & (t <= 6.5)
    ins.plot(t[sel], thd[sel], lw=0.7)
    ins.set_title("t ∈ [6, 6.5] s", fontsize=7)
    ins.tick_params(labelsize=6)
    footer(fig, "scenarios/paper/fig11-sliding-theta-dot.toml")
    fig.tight_layout(rect=(0, 0.02, 1, 1))
    save(fig, out, "fig11.png")


def scene_body(name: str) -> dict:
    import tomllib

    return tomllib.loads((SCEN / name).read_text())["body"]


def rolling(run: Runner, out: Path, m: dict) -> None:
    print("rolling (Tables 1–2, Figs. 12–14)")
    body = scene_body("table1-inertia.toml")
    mass, i_g = body["mass"], body["inertia"][0]
    rows, md = [], []
    for d2, i_paper in TABLE1:
        fit = 3.075e-6 + 1.0e-4 * d2**2
        ours = i_g + mass * d2**2
        rows.append([d2, i_paper, fit, ours])
        md.append([f"{d2:g}", f"{i_paper:.7g}", f"{fit:.7g}", f"{(i_paper - fit) / fit:+.1e}", f"{ours:.5g}"])
    with open(out / "table1.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["D2_m", "I_paper_kg_m2", "I_fit_3.075e-6_plus_1e-4_D2sq", f"I_C0_this_body_m_{mass}"])
        w.writerows(rows)
    (out / "table1.md").write_text(
        "Table 1: the paper's I against D2, the fit I = 3.075e-6 + m D2² with m = 1.0e-4 kg, and this "
        f"reproduction's moment about C0, I_G + m D2² with I_G = {i_g:g} kg m² and m = {mass:g} kg.\n\n"
        + fmt_md_table(["D2 (m)", "I, paper (kg m²)", "3.075e-6 + 1e-4 D2²", "relative difference", f"I_C0 here (m = {mass} kg)"], md))
    print(f"  {out / 'table1.csv'}, table1.md")
    m["table1"] = {"max_relative_difference_from_fit": max(abs(r[1] - r[2]) / r[2] for r in rows)}

    # Figs. 12–13: θ(t) for every D2 of Table 1.
    d2s = [d for d, _ in TABLE1]
    r12 = {d2: run("fig12-rolling-theta.toml", [f"body.com_offset={d2}"]) for d2 in d2s}
    r13 = {d2: run("fig13-rolling-theta-d2.toml", [f"body.com_offset={d2}"]) for d2 in d2s}
    fig, axes = plt.subplots(2, 7, figsize=(14, 5), sharex=True, sharey=True)
    for ax, d2 in zip(axes.flat, d2s):
        r = r12[d2]
        sel = r["t"] <= 0.5
        ax.plot(r["t"][sel], r["theta"][sel], lw=1.0)
        ax.set_title(f"D2 = {d2:g} m", fontsize=8)
        ax.set_ylim(0, 0.45)
        ax.tick_params(labelsize=7)
    for ax in axes[1]:
        ax.set_xlabel("t (s)", fontsize=8)
    for ax in axes[:, 0]:
        ax.set_ylabel("θ (rad)", fontsize=8)
    fig.suptitle("Fig. 12 (reproduced): θ(t) rolling without slipping, c = 0.0125 m, one panel per D2 of Table 1")
    footer(fig, "scenarios/paper/fig12-rolling-theta.toml --set body.com_offset=D2")
    fig.tight_layout(rect=(0, 0.02, 1, 1))
    save(fig, out, "fig12.png")

    rows = []
    for d2 in d2s:
        r = r13[d2]
        th = r["theta"]
        rows.append({"D2": d2, "theta_min": float(th.min()), "theta_max": float(th.max()),
                     "amplitude": float(th.max() - th.min()), "period_s": period(r["t"], th),
                     "energy_J": float(r["energy"][0]), "energy_drift": r.summary["drift"]["energy"]})
    m["fig12_13"] = rows
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4.3))
    for d2 in [0.0001, 0.002, 0.004, 0.006, 0.008, 0.01]:
        r = r13[d2]
        sel = r["t"] <= 0.5
        a1.plot(r["t"][sel], r["theta"][sel], lw=1.0, label=f"D2 = {d2:g} m")
    a1.set(xlabel="t (s)", ylabel="θ (rad)", title="θ(t) as D2 varies", ylim=(0.15, 0.45))
    a1.legend(fontsize=7)
    amp = [row["amplitude"] for row in rows]
    per = [row["period_s"] * 1e3 for row in rows]
    a2.plot(d2s, amp, "o-", color="C0", label="amplitude θmax − θmin (rad)")
    a2.set(xlabel="D2 (m)", ylabel="amplitude (rad)", title="amplitude and period of θ against D2")
    a2.axvline(0.004, color="C0", ls=":", lw=0.8)
    a2.axvline(0.002, color="C1", ls=":", lw=0.8)
    a2.text(0.004, 0.98, " paper: amplitude peaks here", color="C0", fontsize=7, transform=a2.get_xaxis_transform(), va="top")
    a2.text(0.002, 0.90, " paper: period peaks here", color="C1", fontsize=7, transform=a2.get_xaxis_transform(), va="top")
    b2 = a2.twinx()
    b2.plot(d2s, per, "s-", color="C1", label="period (ms)")
    b2.set_ylabel("period (ms)")
    h1, l1 = a2.get_legend_handles_labels()
    h2, l2 = b2.get_legend_handles_labels()
    a2.legend(h1 + h2, l1 + l2, fontsize=7, loc="center right")
    fig.suptitle("Fig. 13 (reproduced): rolling θ(t) as D2 varies")
    footer(fig, "scenarios/paper/fig13-rolling-theta-d2.toml --set body.com_offset=D2")
    fig.tight_layout(rect=(0, 0.02, 1, 1))
    save(fig, out, "fig13.png")

    # Fig. 14: the rates share the period of θ, for each D2.
    fig, axes = plt.subplots(2, 2, figsize=(11, 7), sharex=True)
    rows = []
    for ax, d2 in zip(axes.flat, [0.0001, 0.001, 0.003, 0.005]):
        r = run("fig14-rolling-rates.toml", [f"body.com_offset={d2}"])
        t = r["t"]
        for key, lab in [("theta_dot", "θ̇"), ("phi_dot", "φ̇"), ("psi_dot", "ψ̇")]:
            ax.plot(t, r[key], lw=1.0, label=lab)
        for tm in maxima(t, r["theta"])[0]:
            ax.axvline(tm, color="0.6", lw=0.6, ls="--")
        ax.set_title(f"D2 = {d2:g} m", fontsize=9)
        ax.set_ylabel("rad/s")
        ax.legend(fontsize=7, loc="upper right")
        rows.append({"D2": d2, **{f"period_{k}_s": period(t, r[k]) for k in ("theta", "theta_dot", "phi_dot", "psi_dot")}})
    for ax in axes[1]:
        ax.set_xlabel("t (s)")
    fig.suptitle("Fig. 14 (reproduced): Euler-angle rates rolling (dashed: maxima of θ)")
    footer(fig, "scenarios/paper/fig14-rolling-rates.toml --set body.com_offset=D2")
    fig.tight_layout(rect=(0, 0.02, 1, 1))
    save(fig, out, "fig14.png")
    m["fig14"] = rows

    # Table 2: the energy spread, RK4 h = 1e-4 (the paper's method) and DOP853.
    rows, md = [], []
    for d2, *paper in TABLE2:
        rk = spread(run("table2-rolling-energy.toml", [f"body.com_offset={d2}"])["energy"])
        dp = spread(run("table2-rolling-energy.toml", [f"body.com_offset={d2}", *DOP853])["energy"])
        rows.append({"D2": d2, "paper": dict(zip(["E_min", "E_max", "dE", "E_mean", "percent"], paper)), "rk4": rk, "dop853": dp})
        md.append([f"{d2:g}", f"{paper[3]:.5f}", f"{paper[4]:.4g} %", f"{rk['E_mean']:.6f}",
                   f"{rk['dE']:.1e}", f"{rk['percent']:.1e} %", f"{dp['dE']:.1e}", f"{dp['percent']:.1e} %"])
    with open(out / "table2.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["D2_m", "paper_E_min", "paper_E_max", "paper_dE", "paper_E_mean", "paper_percent",
                    "rk4_E_min", "rk4_E_max", "rk4_dE", "rk4_E_mean", "rk4_percent",
                    "dop853_E_min", "dop853_E_max", "dop853_dE", "dop853_E_mean", "dop853_percent"])
        for row in rows:
            p, a, b = row["paper"], row["rk4"], row["dop853"]
            keys = ["E_min", "E_max", "dE", "E_mean", "percent"]
            w.writerow([row["D2"], *(p[k] for k in keys), *(repr(a[k]) for k in keys), *(repr(b[k]) for k in keys)])
    (out / "table2.md").write_text(
        "Table 2: the energy rolling without slipping over 2 s, c = 0.0125 m. Paper: its mean energy and "
        "spread (ΔE / mean). Here: the same statistics in this reproduction's scene with the paper's RK4 at "
        "h = 1e-4 s and with DOP853 (rtol 1e-11, atol 1e-13). % = 100 ΔE / mean.\n\n"
        + fmt_md_table(["D2 (m)", "paper: mean E (J)", "paper: %", "here: mean E (J)", "RK4: ΔE (J)", "RK4: %", "DOP853: ΔE (J)", "DOP853: %"], md))
    print(f"  {out / 'table2.csv'}, table2.md")
    m["table2"] = rows


TRAJ = {  # figure: (scenario, D2, periods, kind)
    15: ("fig15-rolling-c0-d2-0.01.toml", 0.01, 3, "xy"),
    16: ("fig16-rolling-c0-d2-0.01.toml", 0.01, 3, "3d"),
    17: ("fig17-rolling-c0-d2-0.01.toml", 0.01, 15, "proj"),
    18: ("fig18-rolling-c0-d2-0.01.toml", 0.01, 15, "3d"),
    19: ("fig19-rolling-c0-d2-0.0007.toml", 0.0007, 1, "3d"),
    20: ("fig20-rolling-c0-d2-0.0007.toml", 0.0007, 15, "proj"),
    21: ("fig21-rolling-c0-d2-0.0007.toml", 0.0007, 15, "3d"),
    22: ("fig22-rolling-c0-d2-0.0004.toml", 0.0004, 1, "3d"),
    23: ("fig23-rolling-c0-d2-0.0004.toml", 0.0004, 10, "proj"),
    24: ("fig24-rolling-c0-d2-0.0004.toml", 0.0004, 10, "3d"),
}


def trajectories(run: Runner, out: Path, m: dict) -> None:
    print("trajectories of C0 (Figs. 15–24)")
    res = {}
    for fig_no, (name, d2, n, kind) in TRAJ.items():
        r = run(name)
        t = r["t"]
        T = period(t, r["theta"])
        if not (t[-1] >= n * T - 1e-12):
            sys.exit(f"paper.py: {name}: t_end = {t[-1]} s does not cover {n} periods of {T} s")
        xa, ya, za = (v * 1e3 for v in c0(r, d2))  # mm
        cx, cy = rosette_centre(t, r["theta"], xa, ya)
        sel = t <= n * T
        x, y, z, tt = xa[sel], ya[sel], za[sel], t[sel]
        rad = np.hypot(x - cx, y - cy)
        rmin, rmax = float(rad.min()), float(rad.max())
        three = t <= 3 * T
        res[fig_no] = {"D2": d2, "periods": n, "T_s": T, "self_intersections": self_intersections(x, y),
                       "self_intersections_3T": self_intersections(xa[three], ya[three]) if t[-1] >= 3 * T else None,
                       "centre_mm": [cx, cy], "r_min_mm": rmin, "r_max_mm": rmax,
                       "z_mm": [float(z.min()), float(z.max())]}
        title = f"Fig. {fig_no} (reproduced): C0, D2 = {d2:g} m, t ∈ [0, {n}T], T = {T * 1e3:.1f} ms"
        foot = f"scenarios/paper/{name}; C0 = G + D2 e3*"
        ticks = np.searchsorted(tt, np.arange(1, n + 1) * T) - 1
        if kind == "xy":
            fig, ax = plt.subplots(figsize=(6, 6))
            ax.plot(x, y, lw=1.0)
            ax.plot(x[0], y[0], "ko", ms=4, label="t = 0")
            ax.plot(x[ticks], y[ticks], "C3s", ms=4, label="t = T, 2T, 3T")
            ax.set(xlabel="X (mm)", ylabel="Y (mm)", aspect="equal", title=title)
            ax.title.set_fontsize(9)
            ax.legend(fontsize=7)
        elif kind == "proj":
            fig, axes = plt.subplots(1, 3, figsize=(13, 4.5))
            axes[0].plot(x, y, lw=0.5)
            axes[0].add_patch(plt.Circle((cx, cy), rmin, color="C3", alpha=0.15, label=f"forbidden zone, r = {rmin:.2f} mm"))
            axes[0].set(xlabel="X (mm)", ylabel="Y (mm)", aspect="equal", title="a) XY")
            axes[0].legend(fontsize=7, loc="upper right")
            axes[1].plot(x, z, lw=0.5)
            axes[1].set(xlabel="X (mm)", ylabel="Z (mm)", title="b) XZ")
            axes[2].plot(y, z, lw=0.5)
            axes[2].set(xlabel="Y (mm)", ylabel="Z (mm)", title="c) YZ")
            fig.suptitle(title)
        else:
            fig = plt.figure(figsize=(7, 6))
            ax = fig.add_subplot(projection="3d")
            ax.plot(x, y, z, lw=0.8)
            # Shadows on the floor and two walls: the XY, XZ and YZ projections.
            zf = np.full_like(z, z.min() - 0.2 * (z.max() - z.min() + 1e-9))
            ax.plot(x, y, zf, lw=0.4, color="0.6")
            pad = 0.15 * max(np.ptp(x), np.ptp(y))
            ax.plot(x, np.full_like(y, y.max() + pad), z, lw=0.4, color="0.6")
            ax.plot(np.full_like(x, x.min() - pad), y, z, lw=0.4, color="0.6")
            ax.plot(x[:1], y[:1], z[:1], "ko", ms=4)
            ax.set(xlabel="X (mm)", ylabel="Y (mm)", zlabel="Z (mm)")
            ax.set_title(title, fontsize=9)
        footer(fig, foot)
        if kind != "3d":
            fig.tight_layout(rect=(0, 0.02, 1, 1))
        save(fig, out, f"fig{fig_no:02d}.png")
    m["trajectories"] = res


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default="docs/paper", help="output directory (default docs/paper)")
    args = ap.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    cli = find_cli()
    plt.rcParams.update({"font.size": 9, "axes.grid": True, "grid.alpha": 0.3})
    m: dict = {"cli": str(cli)}
    with tempfile.TemporaryDirectory(prefix="paper-") as scratch:
        run = Runner(cli, Path(scratch))
        frictionless(run, out, m)
        sliding(run, out, m)
        rolling(run, out, m)
        trajectories(run, out, m)
        m["runs"] = run.count
    del m["cli"]
    (out / "measurements.json").write_text(json.dumps(m, indent=1) + "\n")
    print(f"  {out / 'measurements.json'}  ({m['runs']} runs)")


if __name__ == "__main__":
    main()
