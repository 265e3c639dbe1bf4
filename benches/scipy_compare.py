#!/usr/bin/env python3
"""Step counts of our DOPRI5/DOP853 next to SciPy's solve_ivp (RK45/DOP853).

Both sides use the same Dormand–Prince tableaux, scaled RMS error norm
(atol + rtol·max(|y0|, |y1|)) and an automatic initial step; they differ in the
step-size controller (ours: Hairer's, with the PI term for DOPRI5 and the 0.333..6
limits for DOP853; SciPy: pure I-controller, limits 0.2..10).

Ours come from `cargo run --release -p ellipsoid-core --example step_counts` (CSV).
SciPy does not report accepted/rejected steps, so they are recovered from solve_ivp:
accepted = len(sol.t) - 1 (no t_eval, so every accepted step is returned), and every
attempt costs a fixed number of calls (RK45: 5 stages + f(t+h, y1) = 6; DOP853: 11 + 1
= 12) after 2 start-up calls (f(t0, y0) and the initial-step guess), so
attempts = (nfev - 2) / calls_per_attempt.

Usage: python3 -m venv .venv-scipy && .venv-scipy/bin/pip install scipy numpy
       .venv-scipy/bin/python benches/scipy_compare.py [--markdown]
"""

import csv
import io
import subprocess
import sys
from pathlib import Path

import numpy as np
import scipy
from scipy.integrate import solve_ivp

MU = 0.012277471
ARENSTORF_Y0 = [0.994, 0.0, 0.0, -2.00158510637908252240537862224]
ARENSTORF_T = 17.0652165601579625588917206249


def arenstorf(t, y):
    mu1 = 1.0 - MU
    d1 = ((y[0] + MU) ** 2 + y[1] ** 2) ** 1.5
    d2 = ((y[0] - mu1) ** 2 + y[1] ** 2) ** 1.5
    return [
        y[2],
        y[3],
        y[0] + 2.0 * y[3] - mu1 * (y[0] + MU) / d1 - MU * (y[0] - mu1) / d2,
        y[1] - 2.0 * y[2] - mu1 * y[1] / d1 - MU * y[1] / d2,
    ]


def kepler(t, y):
    r3 = (y[0] ** 2 + y[1] ** 2) ** 1.5
    return [y[2], y[3], -y[0] / r3, -y[1] / r3]


def kepler_exact(e, t):
    ea = t
    for _ in range(50):
        ea -= (ea - e * np.sin(ea) - t) / (1.0 - e * np.cos(ea))
    b = np.sqrt(1.0 - e * e)
    r = 1.0 - e * np.cos(ea)
    return np.array([np.cos(ea) - e, b * np.sin(ea), -np.sin(ea) / r, b * np.cos(ea) / r])


def expsin(t, y):
    return [2 * t * y[0] * y[3], 10 * t * np.exp(5 * (y[2] - 1)) * y[3], 2 * t * y[3], -2 * t * np.log(y[0])]


def expsin_exact(t):
    s, c = np.sin(t * t), np.cos(t * t)
    return np.array([np.exp(s), np.exp(5 * s), s + 1, c])


def vanderpol5(t, y):
    return [y[1], 5.0 * (1 - y[0] ** 2) * y[1] - y[0]]


E = 0.5
PROBLEMS = {
    "arenstorf": (arenstorf, ARENSTORF_Y0, ARENSTORF_T, np.array(ARENSTORF_Y0)),
    "kepler_e0.5": (kepler, [1 - E, 0.0, 0.0, np.sqrt((1 + E) / (1 - E))], 4 * np.pi, kepler_exact(E, 4 * np.pi)),
    "expsin": (expsin, [1.0, 1.0, 1.0, 1.0], 2.0, expsin_exact(2.0)),
    "vanderpol_mu5": (vanderpol5, [2.0, 0.0], 20.0, None),
}
SCIPY_METHOD = {"dopri5": ("RK45", 6), "dop853": ("DOP853", 12)}


def ours():
    root = Path(__file__).resolve().parent.parent
    out = subprocess.run(
        ["cargo", "run", "--quiet", "--release", "-p", "ellipsoid-core", "--example", "step_counts"],
        cwd=root,
        check=True,
        capture_output=True,
        text=True,
    ).stdout
    return list(csv.DictReader(io.StringIO(out)))


def theirs(problem, method, rtol, atol):
    fun, y0, t_end, exact = PROBLEMS[problem]
    name, per_attempt = SCIPY_METHOD[method]
    sol = solve_ivp(fun, (0.0, t_end), y0, method=name, rtol=rtol, atol=atol)
    assert sol.success, sol.message
    accepted = len(sol.t) - 1
    attempts = (sol.nfev - 2) / per_attempt
    assert attempts == int(attempts), (problem, method, sol.nfev)
    err = float(np.max(np.abs(sol.y[:, -1] - exact))) if exact is not None else float("nan")
    return accepted, int(attempts) - accepted, sol.nfev, err


def main():
    markdown = "--markdown" in sys.argv
    header = ["problem", "method", "tol", "ours acc+rej", "scipy acc+rej", "ratio", "ours nfev", "scipy nfev", "ours err", "scipy err"]
    rows = []
    for r in ours():
        rtol, atol = float(r["rtol"]), float(r["atol"])
        acc, rej, nfev, err = theirs(r["problem"], r["method"], rtol, atol)
        o_steps = int(r["accepted"]) + int(r["rejected"])
        s_steps = acc + rej
        rows.append([
            r["problem"],
            f"{r['method']} / {SCIPY_METHOD[r['method']][0]}",
            f"{rtol:.0e}",
            f"{r['accepted']}+{r['rejected']} = {o_steps}",
            f"{acc}+{rej} = {s_steps}",
            f"{o_steps / s_steps:.2f}",
            r["rhs_evals"],
            str(nfev),
            f"{float(r['error']):.1e}",
            f"{err:.1e}",
        ])
    if markdown:
        print("| " + " | ".join(header) + " |")
        print("|" + "---|" * len(header))
        for row in rows:
            print("| " + " | ".join(row) + " |")
    else:
        widths = [max(len(h), *(len(row[i]) for row in rows)) for i, h in enumerate(header)]
        print("  ".join(h.ljust(w) for h, w in zip(header, widths)))
        for row in rows:
            print("  ".join(c.ljust(w) for c, w in zip(row, widths)))
    print(f"\nscipy {scipy.__version__}, numpy {np.__version__}; ratio = ours / scipy (accepted + rejected)")
    worst = max(float(row[5]) for row in rows)
    print(f"largest ratio: {worst:.2f} (goal: <= 1.15)")


if __name__ == "__main__":
    main()
