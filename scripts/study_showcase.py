"""The figures of docs/studies.md, drawn from the tables of two studies:

    ellipsoid study studies/tippe-top-map.toml -o out/tippe-top-map.parquet
    ellipsoid study studies/tippe-top-map-disc.toml -o out/tippe-top-map-disc.parquet
    ellipsoid study studies/egg-rise.toml -o out/egg-rise.parquet
    .venv/bin/python scripts/study_showcase.py [--out docs/studies]

Needs pandas, pyarrow and matplotlib. Prints the numbers the text quotes (how many points
the map and the criterion agree on, and where they do not).
"""

from __future__ import annotations

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from matplotlib.colors import ListedColormap

REPO = Path(__file__).resolve().parents[1]
R = 0.015  # sphere radius of scenarios/tippe-top.toml [m]
I3 = 7e-7  # its axial moment [kg m²]


def grid(df: pd.DataFrame, x: str, y: str, value) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    xs = np.sort(df[x].unique())
    ys = np.sort(df[y].unique())
    z = np.full((len(ys), len(xs)), np.nan)
    ix = {v: i for i, v in enumerate(xs)}
    iy = {v: i for i, v in enumerate(ys)}
    for xv, yv, v in zip(df[x], df[y], value):
        z[iy[yv], ix[xv]] = v
    return xs, ys, z


def edges(v: np.ndarray) -> np.ndarray:
    d = np.diff(v)
    return np.concatenate([[v[0] - d[0] / 2], v[:-1] + d / 2, [v[-1] + d[-1] / 2]])


def tippe_top(path: Path, out: Path, name: str = "tippe-top-map", friction: str = "coulomb μ = 0.3", stays: str = "criterion only: slip stops, rolls upright") -> None:
    t = pd.read_parquet(path)
    t["alpha"] = t["body.com_offset [m]"] / R
    t["ratio"] = t["body.inertia[0] [kg m^2]"] / I3
    t_h = t["t_horizontal [s]"].astype(float)
    flip = t_h.notna()
    crit = (1 - t.alpha < t.ratio) & (t.ratio < 1 + t.alpha)
    jumped = t["t_jump [s]"].notna()
    failed = t.status.isin(["solver_failure", "chattering", "painleve", "non_finite", "invalid", "internal_error"])
    xs, ys, z = grid(t, "alpha", "ratio", t_h.to_numpy())
    _, _, zmax = grid(t, "alpha", "ratio", t["max.theta [rad]"].astype(float).to_numpy())
    # Agreement categories: 0 both turn, 1 neither, 2 map only (criterion says no),
    # 3 criterion only (the top stays up), 4 the run failed (step budget).
    cat = np.select(
        [failed, flip & crit, ~flip & ~crit, flip & ~crit, crit & ~flip],
        [4, 0, 1, 2, 3],
        default=5,
    )
    _, _, zj = grid(t, "alpha", "ratio", jumped.astype(float).to_numpy())
    _, _, zc = grid(t, "alpha", "ratio", cat.astype(float))
    a = np.linspace(0, xs.max() * 1.02, 50)
    fig, axs = plt.subplots(1, 3, figsize=(17, 5.2), constrained_layout=True)
    ex, ey = edges(xs), edges(ys)
    ax = axs[0]
    m = ax.pcolormesh(ex, ey, np.ma.masked_invalid(z), cmap="viridis", shading="flat")
    ax.pcolormesh(ex, ey, np.ma.masked_where(~np.isnan(z), np.ones_like(z)), cmap=ListedColormap(["#d9d9d9"]), shading="flat")
    fig.colorbar(m, ax=ax, label="time θ passes π/2 [s]")
    ax.set_title(f"turn-over map ({friction}, φ̇0 = 180 rad/s, 8 s)\ngrey: θ never reached π/2", fontsize=10)
    ax = axs[1]
    m = ax.pcolormesh(ex, ey, zmax, cmap="magma", shading="flat", vmin=0, vmax=np.pi)
    fig.colorbar(m, ax=ax, label="largest θ in the run [rad]")
    ax.set_title("how far it turns: max θ (π = fully inverted)")
    ax = axs[2]
    colours = ["#1a9850", "#bdbdbd", "#fdae61", "#d73027", "#000000", "#ffffff"]
    ax.pcolormesh(ex, ey, zc, cmap=ListedColormap(colours), vmin=-0.5, vmax=5.5, shading="flat")
    ax.contourf(xs, ys, zj, levels=[0.5, 1.5], hatches=["////"], colors="none")
    labels = [
        "both: turns over",
        "both: stays up",
        "map only: passes π/2, settles on its side",
        stays,
        "run failed (step budget)",
    ]
    ax.fill([], [], hatch="////", facecolor="none", label="hops off the plane on the way")
    for c, lab in zip(colours[: len(labels)], labels):
        ax.plot([], [], "s", color=c, label=lab, markersize=9)
    ax.legend(loc="upper left", fontsize=7.5, framealpha=0.9)
    ax.set_title("map against the criterion 1 − α < I1/I3 < 1 + α")
    for ax in axs:
        ax.plot(a, 1 - a, "w--" if ax is not axs[2] else "k--", lw=1.2)
        ax.plot(a, 1 + a, "w--" if ax is not axs[2] else "k--", lw=1.2)
        ax.set_xlim(ex[0], ex[-1])
        ax.set_ylim(ey[0], ey[-1])
        ax.set_xlabel("α = D2/R [1]")
        ax.set_ylabel("I1/I3 [1]")
    fig.savefig(out / f"{name}.png", dpi=110)
    n = len(t)
    print(f"{name}: {n} runs; statuses {t.status.value_counts().to_dict()}")
    print(
        f"  agree {int(((flip & crit) | (~flip & ~crit)).sum())} ({((flip & crit) | (~flip & ~crit)).mean():.0%}); "
        f"map only {int((flip & ~crit).sum())} (max θ {t['max.theta [rad]'][flip & ~crit].astype(float).median():.2f} rad median, all above 1 + α: {bool((t.ratio[flip & ~crit] > 1 + t.alpha[flip & ~crit]).all())}); "
        f"criterion only {int((crit & ~flip).sum())}: stayed up rolling {int((crit & ~flip & ~failed & (t['final.mode'] == 'rolling')).sum())}, failed {int((crit & ~flip & failed).sum())}; "
        f"failed {int(failed.sum())} (turned before failing {int((failed & flip).sum())}); hops {int(jumped.sum())} (of which turn over {int((jumped & flip).sum())}, inside the criterion {int((jumped & crit).sum())}; first hop {t['t_jump [s]'][jumped].astype(float).min():.2f} … {t['t_jump [s]'][jumped].astype(float).max():.2f} s, α ≥ {t.alpha[jumped].min():.2f})"
    )
    missed = crit & ~flip
    print(f"  criterion only: largest θ {t['max.theta [rad]'][missed].astype(float).min():.2f} … {t['max.theta [rad]'][missed].astype(float).max():.2f} rad, final modes {t['final.mode'][missed].value_counts().to_dict()}")
    inside = flip & crit
    print(f"  inside the criterion: max θ median {t['max.theta [rad]'][inside].astype(float).median():.2f} rad; t(π/2) {t_h[inside].min():.2f} … {t_h[inside].max():.2f} s")


def egg(path: Path, out: Path) -> None:
    t = pd.read_parquet(path)
    xs, ys, zt = grid(t, "initial.phi_dot [rad/s]", "contact.friction [1]", t["min.theta [rad]"].astype(float).to_numpy())
    _, _, zr = grid(t, "initial.phi_dot [rad/s]", "contact.friction [1]", t["t_risen [s]"].astype(float).to_numpy())
    jumped = t["t_jump [s]"].notna().to_numpy()
    _, _, zj = grid(t, "initial.phi_dot [rad/s]", "contact.friction [1]", jumped.astype(float))
    ex, ey = edges(xs), edges(ys)
    fig, axs = plt.subplots(1, 2, figsize=(12, 4.8), constrained_layout=True)
    ax = axs[0]
    m = ax.pcolormesh(ex, ey, np.degrees(zt), cmap="viridis_r", shading="flat")
    fig.colorbar(m, ax=ax, label="lowest θ reached [deg] (80° = did not rise)")
    ax.set_title("egg: how far it rises (θ0 = 80°, pure sliding)")
    ax = axs[1]
    m = ax.pcolormesh(ex, ey, np.ma.masked_invalid(zr), cmap="plasma", shading="flat")
    fig.colorbar(m, ax=ax, label="time the axis passes 45° [s]")
    ax.set_title("when it rises; hatched: it hops off the plane")
    for ax in axs:
        ax.contourf(xs, ys, zj, levels=[0.5, 1.5], hatches=["////"], colors="none")
        ax.set_xlabel("φ̇0 [rad/s]")
        ax.set_ylabel("μ [1]")
    fig.savefig(out / "egg-rise.png", dpi=110)
    rose = t["t_risen [s]"].notna()
    print(f"egg: {len(t)} runs; statuses {t.status.value_counts().to_dict()}; rises past 45° in {int(rose.sum())}; hops in {int(t['t_jump [s]'].notna().sum())} (rising too: {int((rose & t['t_jump [s]'].notna()).sum())}); largest μ that rises {t['contact.friction [1]'][rose].max():.3f}")
    for mu in sorted(t["contact.friction [1]"].unique())[::8]:
        sub = t[t["contact.friction [1]"] == mu]
        r = sub[sub["t_risen [s]"].notna()]["initial.phi_dot [rad/s]"]
        j = sub[sub["t_jump [s]"].notna()]["initial.phi_dot [rad/s]"]
        print(f"  μ = {mu:.3f}: rises from φ̇0 = {r.min() if len(r) else float('nan'):.0f} rad/s; jumps from {j.min() if len(j) else float('nan'):.0f} rad/s")


def main() -> None:
    p = argparse.ArgumentParser()
    p.add_argument("--tippe-top", default=REPO / "out/tippe-top-map.parquet", type=Path)
    p.add_argument("--tippe-top-disc", default=REPO / "out/tippe-top-map-disc.parquet", type=Path)
    p.add_argument("--egg", default=REPO / "out/egg-rise.parquet", type=Path)
    p.add_argument("--out", default=REPO / "docs/studies", type=Path)
    a = p.parse_args()
    a.out.mkdir(parents=True, exist_ok=True)
    tippe_top(a.tippe_top, a.out)
    if a.tippe_top_disc.exists():
        tippe_top(a.tippe_top_disc, a.out, "tippe-top-map-disc", "disc R = 0.5 mm, μ = 0.3", "criterion only: still below π/2 at 8 s")
    egg(a.egg, a.out)


if __name__ == "__main__":
    main()
