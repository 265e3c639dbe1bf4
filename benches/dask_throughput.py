"""Dask LocalCluster (2 worker processes, 1 thread each) against the local rayon sweep on
the same machine, for a tippe-top map of N runs (default 10⁴: the map of
studies/tippe-top-map.toml on a 100 × 100 grid). Prints runs/s of each and the
ratio; checks that the two tables agree (every column but wall time).

    .venv/bin/python benches/dask_throughput.py [N]
"""

import math
import sys
import time
from pathlib import Path

import distributed

import ellipsoid

REPO = Path(__file__).resolve().parents[1]


def main() -> None:
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 10_000
    side = int(math.isqrt(n))
    base = ellipsoid.load(
        REPO / "scenarios/tippe-top.toml",
        solver={"rtol": 1e-8, "atol": 1e-10, "max_steps": 20000},
        output={"dt": 0.01},
        observe=[{"name": "horizontal", "column": "theta", "crosses": 1.5707963267948966, "direction": "up"}],
    )
    axes = {
        "body.com_offset": {"linspace": [0.0005, 0.009, side]},
        ("body.inertia[0]", "body.inertia[1]"): {"linspace": [3.85e-7, 1.12e-6, side]},
    }
    outcomes = {"final": ["theta", "mode"], "max": ["theta"]}
    t = time.perf_counter()
    local = ellipsoid.study(base, axes, outcomes, workers=2)
    t_local = time.perf_counter() - t
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None)
    client = distributed.Client(cluster)
    try:
        t = time.perf_counter()
        remote = ellipsoid.study(base, axes, outcomes, executor=client)
        t_dask = time.perf_counter() - t
    finally:
        client.close()
        cluster.close()
    same = local.drop(columns=["wall_time [s]"]).equals(remote.drop(columns=["wall_time [s]"]))
    runs = len(local)
    print(f"{runs} runs: local {runs / t_local:.1f} runs/s ({t_local:.1f} s), Dask LocalCluster {runs / t_dask:.1f} runs/s ({t_dask:.1f} s): {t_local / t_dask * 100:.1f} % of local; tables equal: {same}")
    print(f"CPU time in the runs (sum of wall_time): {local['wall_time [s]'].sum():.1f} s local, {remote['wall_time [s]'].sum():.1f} s on Dask")


if __name__ == "__main__":
    main()
