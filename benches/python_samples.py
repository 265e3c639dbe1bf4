#!/usr/bin/env python3
"""What a sample costs from Python: a run sampled every 1 ms against the same run sampled
sparsely, each followed by reading every column as numpy arrays (`to_dict`). Prints the
median of `--repeats` runs of each, their ratio, and the cost per extra sample in µs.

Scenes (`--scene`): `nutation` (default) is 10 s of the frictionless nutation scene
(scenarios/nutation.toml at rtol = 1e-8, atol = 1e-10, the scene of benches/output.rs),
sparse = samples only at 0 and t_end; `tippe-top` is scenarios/tippe-top.toml as bundled
(8 s, DOP853 at rtol = 1e-11), sparse = a sample every 0.1 s.

The Rust side of the same path (rows built and kept in a Vec, then turned into columns)
is criterion's `nutation_10s_1ms/{kept,columns}` in benches/output.rs.

`--t-eval` compares instead the two ways of asking for the same 10,001 samples of the
nutation scene (10 s every 1 ms, at rtol = 1e-8, atol = 1e-10): `output={"dt": 1e-3}`
against `t_eval=np.arange(0, 10.0005, 1e-3)` (solve_ivp's way), each run `--repeats`
times, alternating; it prints both medians and their ratio (t_eval / dt; target <= 1.1).

`--clock cpu` times each run with the process's CPU time (all threads: the run's worker
thread and the caller) in place of the wall clock: on a machine other jobs share, the wall
clock counts the time the run waited for a core, the CPU time does not.

Usage: python benches/python_samples.py [--scene tippe-top] [--repeats 21] [--clock cpu] [--t-eval]
(with the package installed)
"""

from __future__ import annotations

import argparse
import statistics
import time
from pathlib import Path

import ellipsoid

SCENARIOS = Path(__file__).resolve().parents[1] / "scenarios"

#: scene → (file, changes, simulated time [s], sparse dt [s])
SCENES = {
    "nutation": ("nutation.toml", {"solver": {"rtol": 1e-8, "atol": 1e-10}}, 10.0, 10.0),
    "tippe-top": ("tippe-top.toml", {}, 8.0, 0.1),
}


CLOCKS = {"wall": time.perf_counter, "cpu": time.process_time}


def median_seconds(scene: str, dt: float, repeats: int, clock=time.perf_counter) -> tuple[float, int]:
    name, changes, t_end, _ = SCENES[scene]
    s = ellipsoid.load(SCENARIOS / name, **changes, output={"t_end": t_end, "dt": dt})
    times, rows = [], 0
    for _ in range(repeats):
        t0 = clock()
        traj = ellipsoid.simulate(s)
        traj.to_dict()
        times.append(clock() - t0)
        rows = len(traj)
    return statistics.median(times), rows


def t_eval_against_dt(repeats: int, clock=time.perf_counter) -> tuple[float, float, int]:
    """The median seconds of `simulate` with `output.dt` and with the same times as
    `t_eval`, and the sample count (the runs alternate, so that a change of the machine's
    load falls on both)."""
    import numpy as np

    name, changes, t_end, _ = SCENES["nutation"]
    s = ellipsoid.load(SCENARIOS / name, **changes, output={"t_end": t_end, "dt": 1e-3})
    ts = np.arange(0.0, t_end + 5e-4, 1e-3)
    assert np.array_equal(ts, s.sample_times), "t_eval and output.dt must ask for the same samples"
    by_dt, by_t_eval = [], []
    for _ in range(repeats):
        t0 = clock()
        a = ellipsoid.simulate(s, output={"dt": 1e-3})
        by_dt.append(clock() - t0)
        t0 = clock()
        b = ellipsoid.simulate(s, t_eval=ts)
        by_t_eval.append(clock() - t0)
    assert len(a) == len(b) == len(ts) and np.array_equal(a.theta, b.theta)
    return statistics.median(by_dt), statistics.median(by_t_eval), len(ts)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scene", choices=sorted(SCENES), default="nutation")
    ap.add_argument("--repeats", type=int, default=21)
    ap.add_argument("--clock", choices=sorted(CLOCKS), default="wall")
    ap.add_argument("--t-eval", action="store_true", help="compare t_eval with output.dt (the nutation scene)")
    args = ap.parse_args()
    _, _, t_end, sparse_dt = SCENES[args.scene]
    clock = CLOCKS[args.clock]
    if args.t_eval:
        dt, t_eval, n = t_eval_against_dt(args.repeats, clock)
        print(f"output.dt ({n} samples): {dt * 1e3:.3f} ms")
        print(f"t_eval    ({n} samples): {t_eval * 1e3:.3f} ms")
        print(f"ratio t_eval / output.dt {t_eval / dt:.3f} (target <= 1.1)")
        return
    dense, n = median_seconds(args.scene, 1e-3, args.repeats, clock)
    sparse, m = median_seconds(args.scene, sparse_dt, args.repeats, clock)
    print(f"1 ms samples ({n} rows): {dense * 1e3:.3f} ms = {dense / t_end * 1e3:.3f} ms per simulated second")
    print(f"sparse ({m} rows): {sparse * 1e3:.3f} ms = {sparse / t_end * 1e3:.3f} ms per simulated second")
    print(f"ratio {dense / sparse:.2f} (target <= 2); {(dense - sparse) / (n - m) * 1e6:.3f} us per sample")


if __name__ == "__main__":
    main()
