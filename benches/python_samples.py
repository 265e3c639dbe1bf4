#!/usr/bin/env python3
"""What a sample costs from Python: 10 s of the frictionless nutation scene
(scenarios/nutation.toml at rtol = 1e-8, atol = 1e-10, the scene of benches/output.rs)
simulated with a sample every 1 ms (10 001 rows) and with samples only at 0 and t_end,
each followed by reading every column as numpy arrays (`to_dict`). Prints the median
of `--repeats` runs of each, their ratio, and the cost per sample in µs.

The Rust side of the same path (rows built and kept in a Vec) is criterion's
`nutation_10s_1ms/kept` in benches/output.rs.

Usage: python benches/python_samples.py [--repeats 21]   (with the package installed)
"""

from __future__ import annotations

import argparse
import statistics
import time
from pathlib import Path

import ellipsoid

SCENE = Path(__file__).resolve().parents[1] / "scenarios" / "nutation.toml"


def median_seconds(dt: float, repeats: int) -> tuple[float, int]:
    s = ellipsoid.load(SCENE, solver={"rtol": 1e-8, "atol": 1e-10}, output={"t_end": 10.0, "dt": dt})
    times, rows = [], 0
    for _ in range(repeats):
        t0 = time.perf_counter()
        traj = ellipsoid.simulate(s)
        traj.to_dict()
        times.append(time.perf_counter() - t0)
        rows = len(traj)
    return statistics.median(times), rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeats", type=int, default=21)
    args = ap.parse_args()
    dense, n = median_seconds(1e-3, args.repeats)
    sparse, _ = median_seconds(10.0, args.repeats)
    print(f"1 ms samples ({n} rows): {dense * 1e3:.3f} ms = {dense / 10 * 1e3:.3f} ms per simulated second")
    print(f"sparse (2 rows):          {sparse * 1e3:.3f} ms = {sparse / 10 * 1e3:.3f} ms per simulated second")
    print(f"ratio {dense / sparse:.2f} (target <= 2); {(dense - sparse) / n * 1e6:.3f} us per sample")


if __name__ == "__main__":
    main()
