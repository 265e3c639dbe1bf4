"""Shared fixtures: the repository's paths, the command-line tool, small scenarios."""

from __future__ import annotations

import _thread
import os
import sys
import threading
import time
from collections.abc import Callable
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


def interrupt_inside(fire: Callable[[], None], fn: Callable[..., Any], *args: Any, work: Callable[[], Any] | None = None, **kwargs: Any) -> None:
    """Calls `fn(*args, **kwargs)` on this (the main) thread while a watcher thread
    waits, with no timer, until it sees the main thread inside that call, then runs
    `work` (Python code, if given), checks again that the call is still running, and
    calls `fire` once (e.g. `_thread.interrupt_main`). Passes only if the call then
    raised KeyboardInterrupt itself.

    The watcher is Python code, so it can run during the call only if the call released
    the GIL; and the interrupt can end the call only if the call checks for signals.
    Give `fn` work it cannot finish soon (a long run with a step budget): should either
    property fail, the call ends on its own (its budget spent) and this fails, saying
    which. The watcher sees "inside the call" from the main thread's innermost Python
    frame, this function's, standing at the line of the call: no bytecode on that line
    before the call can let the watcher run, and a call ending in an exception leaves the
    line without a switch either; a call that returns normally may switch back there,
    which is why the interrupt arriving after a return is detected below.
    """
    main = threading.get_ident()
    here = sys._getframe()
    state: dict[str, Any] = {"armed": True, "line": None, "seen": 0, "worked": False, "fired": False}

    def inside() -> bool:
        frame = sys._current_frames().get(main)
        return frame is here and frame.f_lineno == state["line"]

    def watch() -> None:
        while state["armed"]:
            if inside():
                state["seen"] += 1
                if work is not None:
                    work()
                    state["worked"] = inside()
                state["fired"] = True
                fire()
                return
            time.sleep(0.001)

    watcher = threading.Thread(target=watch, name="interrupt-inside", daemon=True)
    watcher.start()
    interrupted = late = False
    try:
        try:
            state["line"] = sys._getframe().f_lineno + 1
            fn(*args, **kwargs)
        except KeyboardInterrupt:
            interrupted = True
        finally:
            state["armed"] = False
        while watcher.is_alive():
            watcher.join(0.1)
    except KeyboardInterrupt:
        late = True
    assert state["seen"], f"no other Python thread ran during {fn.__name__}: it held the GIL until it ended"
    assert not late, f"{fn.__name__} returned before the interrupt, which arrived late"
    assert interrupted, f"{fn.__name__} ended without raising KeyboardInterrupt"
    if work is not None:
        assert state["worked"], f"{fn.__name__} ended while the other thread was working"


INTERRUPT_MAIN = _thread.interrupt_main
