"""Fixtures of the browser tests: the `ellipsoid` binary, a headless Chromium page."""

from __future__ import annotations

import os
import sys
from pathlib import Path
from typing import Iterator

import pytest

sys.path.insert(0, str(Path(__file__).parent))
import cdp  # noqa: E402

REPO = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def cli() -> Path:
    env = os.environ.get("ELLIPSOID_CLI")
    target = Path(os.environ.get("CARGO_TARGET_DIR") or REPO / "target")
    path = Path(env) if env else (target if target.is_absolute() else REPO / target) / "release" / "ellipsoid"
    if not path.is_file():
        pytest.fail(f"the ellipsoid binary is not built ({path}): run `cargo build --release -p ellipsoid-cli`")
    return path


@pytest.fixture(scope="session")
def browser() -> Iterator[cdp.Browser]:
    exe = cdp.chromium_path()
    if exe is None:
        if os.environ.get("ELLIPSOID_EXPECT_BROWSER") == "1":
            pytest.fail("no Chromium found (scripts/test-all.sh installs Debian's chromium)")
        pytest.skip("no Chromium found: apt-get install -y chromium")
    b = cdp.Browser(exe)
    yield b
    b.close()


@pytest.fixture()
def page(browser: cdp.Browser) -> Iterator[cdp.Page]:
    p = browser.page()
    p.events.clear()
    yield p
    p.goto("about:blank")
    p.close()
