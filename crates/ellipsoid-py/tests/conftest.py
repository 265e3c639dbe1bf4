"""Shared fixtures: the repository's paths, the command-line tool, small scenarios."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import pytest

import ellipsoid

REPO = Path(__file__).resolve().parents[3]
SCENARIOS = REPO / "scenarios"
# Every bundled scenario, the paper reproduction's (scenarios/paper/) included.
BUNDLED = sorted(SCENARIOS.rglob("*.toml"))


def scenario_id(path: Path) -> str:
    return str(path.relative_to(SCENARIOS).with_suffix(""))

# The oblate body (paper §2): a = 0.025, c = 0.0175, D2 = 0.003 m, m = 0.05 kg,
# I = m(a² + c²)/5, I3 = 2ma²/5.
A, C, D2, M = 0.025, 0.0175, 0.003, 0.05
I1 = M * (A * A + C * C) / 5
I3 = 2 * M * A * A / 5


def oblate(**tables: Any) -> ellipsoid.Scenario:
    """The oblate body, tilted 0.1745 rad and spun at 60 rad/s; `tables` replace whole tables."""
    base: dict[str, Any] = dict(
        body=dict(a=A, c=C, mass=M, com_offset=D2, inertia=[I1, I1, I3]),
        initial=dict(theta=0.1745, psi_dot=60.0),
        contact=dict(model="frictionless"),
        solver=dict(method="dop853", rtol=1e-11, atol=1e-13),
        output=dict(t_end=1.0, dt=1e-3),
    )
    base.update(tables)
    return ellipsoid.Scenario(**base)


def cli_path() -> Path | None:
    """The `ellipsoid` binary: $ELLIPSOID_CLI, else the cargo target directory's release build."""
    env = os.environ.get("ELLIPSOID_CLI")
    if env:
        return Path(env)
    target = Path(os.environ.get("CARGO_TARGET_DIR") or REPO / "target")
    if not target.is_absolute():
        target = REPO / target
    candidate = target / "release" / "ellipsoid"
    return candidate if candidate.is_file() else None


@pytest.fixture(scope="session")
def cli() -> Path:
    path = cli_path()
    if path is None:
        pytest.skip(
            "the ellipsoid command-line tool is not built: set ELLIPSOID_CLI or run "
            "`cargo build --release -p ellipsoid-cli` (scripts/test-all.sh does)"
        )
    if not path.is_file():
        pytest.fail(f"ELLIPSOID_CLI={path} does not exist")
    return path
