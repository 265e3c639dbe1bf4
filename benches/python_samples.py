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

`--clock cpu` times each run with the process's CPU time (all threads: the run's worker
thread and the caller) in place of the wall clock: on a machine other jobs share, the wall
clock counts the time the run waited for a core, the CPU time does not.

Usage: python benches/python_samples.py [--scene tippe-top] [--repeats 21] [--clock cpu]
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


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scene", choices=sorted(SCENES), default="nutation")
    ap.add_argument("--repeats", type=int, default=21)
    ap.add_argument("--clock", choices=sorted(CLOCKS), default="wall")
    args = ap.parse_args()
    _, _, t_end, sparse_dt = SCENES[args.scene]
    clock = CLOCKS[args.clock]
    dense, n = median_seconds(args.scene, 1e-3, args.repeats, clock)
    sparse, m = median_seconds(args.scene, sparse_dt, args.repeats, clock)
    print(f"1 ms samples ({n} rows): {dense * 1e3:.3f} ms = {dense / t_end * 1e3:.3f} ms per simulated second")
    print(f"sparse ({m} rows): {sparse * 1e3:.3f} ms = {sparse / t_end * 1e3:.3f} ms per simulated second")
    print(f"ratio {dense / sparse:.2f} (target <= 2); {(dense - sparse) / (n - m) * 1e6:.3f} us per sample")


if __name__ == "__main__":
    main()
