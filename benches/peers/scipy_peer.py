"""A plain SciPy implementation of the frictionless and sliding models (numpy
right-hand side, the equations of docs/physics.md, `solve_ivp` with DOP853 and RK45), timed
against `ellipsoid precision` on the same scenes and measured with the same error:

- frictionless body of revolution: max(|T_run - T|/T, largest relative invariant
  drift over 101 equally spaced samples), T_run the mean period between the first and
  last theta maxima (located as events by solve_ivp), T the exact period our tool prints;
- otherwise: the final-state error against our DOP853 reference at rtol = 1e-14 (the
  rotation angle between final orientations, |dx_G|/l, |dv_G|/(|v_G(0)| + |w(0)| l),
  |dw|/|w(0)|; l the largest semi-axis).

For each SciPy run the ratio is its wall time over the wall time of the cheapest of our
runs of the same family (RK45 ~ dopri5, DOP853 ~ dop853) whose error is at most SciPy's:
"how much longer SciPy takes for that accuracy". Wall times are medians of 3 runs.

    python benches/peers/scipy_peer.py [--bin target/release/ellipsoid] [--markdown]
"""
from __future__ import annotations

import argparse
import csv
import math
import re
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import scipy
from scipy.integrate import solve_ivp

sys.path.insert(0, str(Path(__file__).resolve().parent))
import scene as sc  # noqa: E402

# (scenario, t_end [s]): 2 s of nutation (32 periods); the sliding scene up to 1 s,
# before its slip stops at 1.214 s (our pure sliding model ends there).
SCENES = [("nutation.toml", 2.0), ("paper-sliding.toml", 1.0)]
TOLS = [1e-5, 1e-7, 1e-9, 1e-11]
REPEATS = 3


def ours(binary: Path, scenario: Path, t_end: float, workdir: Path) -> tuple[list[dict], str]:
    out_dir = workdir / scenario.stem
    stdout = sc.ellipsoid(binary, "precision", str(scenario), "--t-end", str(t_end), "-o", str(out_dir), "-q")
    with open(out_dir / "precision.csv") as f:
        rows = list(csv.DictReader(f))
    return rows, stdout


def reference_state(binary: Path, scenario: Path, t_end: float, workdir: Path) -> dict:
    """Our DOP853 final state at rtol = 1e-14 (the reference of `precision`)."""
    s = sc.load(scenario)
    path = workdir / f"{scenario.stem}-ref.csv"
    sc.ellipsoid(
        binary, "run", str(scenario), "-o", str(path), "-q",
        "--set", f"output.t_end={t_end}", "--set", f"output.dt={t_end}",
        "--set", "solver.rtol=1e-14", "--set", f"solver.atol={1e-14 * s.atol / s.rtol}",
    )  # fmt: skip
    with open(path) as f:
        last = list(csv.DictReader(line for line in f if not line.startswith("#")))[-1]  # past the comment line
    return {k: float(v) for k, v in last.items() if k != "mode"}


def theta_max_event(s: sc.Scene):
    def g(t, y):
        r = sc.rotation(y[2:6])
        return r[2, 0] * y[9] - r[2, 1] * y[8]  # d(cos theta)/dt; rising = theta maximum

    g.direction = 1.0
    return g


def run_scipy(s: sc.Scene, method: str, tol: float, t_end: float, period: bool):
    y0 = sc.initial_state(s)
    samples = np.linspace(0.0, t_end, 101)
    events = [theta_max_event(s)] if period else None
    atol = tol * s.atol / s.rtol
    times, sol = [], None
    for _ in range(REPEATS):
        t0 = time.perf_counter()
        sol = solve_ivp(lambda t, y: sc.rhs(s, y), (0.0, t_end), y0, method=method, rtol=tol, atol=atol, t_eval=samples, events=events)
        times.append(time.perf_counter() - t0)
    return sol, float(np.median(times))


def drift(s: sc.Scene, sol) -> float:
    inv0 = sc.invariants(s, sol.y[:, 0])
    scale = sc.scales(s, sol.y[:, 0], inv0)
    worst = 0.0
    for k in range(sol.y.shape[1]):
        inv = sc.invariants(s, sol.y[:, k])
        for name in sc.conserved(s):
            worst = max(worst, abs(inv[name] - inv0[name]) / scale[name])
    return worst


def state_error(s: sc.Scene, y: np.ndarray, ref: dict) -> float:
    ell = max(s.a, s.b, s.c)
    r, w, zeta, r_b, height, hess, v_g, wxr = sc.kinematics(s, y)
    r_ref = sc.euler_rotation(ref["theta"], ref["phi"], ref["psi"])
    d = r_ref.T @ r
    axis = np.array([d[2, 1] - d[1, 2], d[0, 2] - d[2, 0], d[1, 0] - d[0, 1]])
    angle = math.atan2(np.linalg.norm(axis), np.trace(d) - 1.0)
    x_g = np.array([y[0], y[1], height])
    x_ref = np.array([ref["x"], ref["y"], ref["z"]])
    v_ref = np.array([ref["vx"], ref["vy"], ref["vz"]])
    w_ref = np.array([ref["omega_x"], ref["omega_y"], ref["omega_z"]])
    w0 = np.linalg.norm(sc.omega_body(s))
    v_scale = np.linalg.norm(s.velocity) + w0 * ell
    return max(angle, np.linalg.norm(x_g - x_ref) / ell, np.linalg.norm(v_g - v_ref) / v_scale, np.linalg.norm(w - w_ref) / w0)


def cheapest(rows: list[dict], family: str, error: float) -> dict | None:
    """Our cheapest run of `family` with error <= `error` that ended as the tightest run did."""
    ok = [r for r in rows if r["method"] == family and r["status"] == rows[-1]["status"] and float(r["error"]) <= error]
    return min(ok, key=lambda r: float(r["wall_time_median_s"]), default=None)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bin", type=Path, default=sc.DEFAULT_BIN, help="our ellipsoid binary (cargo build --release -p ellipsoid-cli)")
    ap.add_argument("--markdown", action="store_true", help="print a Markdown table")
    args = ap.parse_args()
    print(f"SciPy {scipy.__version__}, NumPy {np.__version__}; ours: {args.bin}", file=sys.stderr)
    lines = []
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        for name, t_end in SCENES:
            path = sc.ROOT / "scenarios" / name
            s = sc.load(path)
            rows, stdout = ours(args.bin, path, t_end, work)
            m = re.search(r"exact nutation period T = ([0-9.eE+-]+) s", stdout)
            period = float(m.group(1)) if m else None
            ref = None if period else reference_state(args.bin, path, t_end, work)
            for method, family in (("RK45", "dopri5"), ("DOP853", "dop853")):
                for tol in TOLS:
                    sol, wall = run_scipy(s, method, tol, t_end, period is not None)
                    if not sol.success:
                        lines.append((s.name, method, tol, sol.nfev, math.inf, wall, None, math.nan))
                        continue
                    if period:
                        tmax = sol.t_events[0]
                        t_run = (tmax[-1] - tmax[0]) / (len(tmax) - 1)
                        err = max(abs(t_run - period) / period, drift(s, sol))
                    else:
                        err = state_error(s, sol.y[:, -1], ref)
                    best = cheapest(rows, family, err)
                    ratio = wall / float(best["wall_time_median_s"]) if best else math.nan
                    lines.append((s.name, method, tol, sol.nfev, err, wall, best, ratio))
                    print(f"{s.name:<14} {method:<7} tol {tol:.0e}: nfev {sol.nfev:>7}, error {err:.1e}, {wall * 1e3:9.2f} ms, ratio {ratio:7.0f}", file=sys.stderr)
    if args.markdown:
        print("| scene | SciPy method | tol | SciPy nfev | SciPy error | SciPy time | ours (same family, cheapest reaching that error) | our error | our time | our rhs evals | SciPy time / ours |")
        print("|---|---|---|---|---|---|---|---|---|---|---|")
        for name, method, tol, nfev, err, wall, best, ratio in lines:
            if best is None:
                print(f"| {name} | {method} | {tol:.0e} | {nfev} | {err:.1e} | {wall * 1e3:.2f} ms | — | — | — | — | — |")
                continue
            print(
                f"| {name} | {method} | {tol:.0e} | {nfev} | {err:.1e} | {wall * 1e3:.2f} ms | {best['method']} {best['setting']} | "
                f"{float(best['error']):.1e} | {float(best['wall_time_median_s']) * 1e3:.3f} ms | {best['rhs_evals']} | {ratio:.0f}× |"
            )
    else:
        for name, method, tol, nfev, err, wall, best, ratio in lines:
            ours_txt = f"{best['method']} {best['setting']} {float(best['wall_time_median_s']) * 1e3:.3f} ms" if best else "-"
            print(f"{name:<14} {method:<7} {tol:.0e} nfev {nfev:>7} error {err:.1e} {wall * 1e3:9.2f} ms | ours {ours_txt} | ratio {ratio:.0f}")


if __name__ == "__main__":
    main()
