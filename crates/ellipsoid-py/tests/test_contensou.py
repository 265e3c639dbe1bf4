"""The reference of the contact-disc friction law (issue #14): the table the Rust test
`tests/contensou.rs` checks the law against (f, g to 2e-15) is the two-dimensional
quadrature of the traction over the disc, recomputed here with mpmath, and agrees with the
closed forms of docs/physics.md.

Needs only mpmath (no extension call): the law itself is tested in Rust.
"""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

import pytest

mp = pytest.importorskip("mpmath")

REPO = Path(__file__).resolve().parents[3]
TABLE = REPO / "tests" / "data" / "contensou" / "reference.json"


def reference_module():
    spec = importlib.util.spec_from_file_location(
        "contensou_reference", REPO / "scripts" / "contensou_reference.py"
    )
    assert spec and spec.loader
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def stored() -> dict[float, dict[str, str]]:
    return {float(r["d"]): r for r in json.loads(TABLE.read_text())["values"]}


def test_table_covers_the_range() -> None:
    d = sorted(stored())
    assert d[0] <= 1e-8 and d[-1] >= 1e8 and 1.0 in d
    assert len(d) >= 30


@pytest.mark.parametrize("d", [1.0, 3.0, 30.0])
def test_table_is_the_two_dimensional_quadrature(d: float) -> None:
    ref = reference_module()
    row = ref.compute(d)
    old = stored()[d]
    for key in ("f", "g"):
        new, was = mp.mpf(row[key]), mp.mpf(old[key])
        assert abs(new - was) <= mp.mpf("1e-22") * abs(new), (key, d, new, was)


def test_closed_forms_agree_with_the_quadrature() -> None:
    ref = reference_module()
    for d, row in stored().items():
        mp.mp.dps = 40 + int(4 * abs(mp.log10(d)))
        f, g = ref.closed_form(d)
        for key, value in (("f", f), ("g", g)):
            q = mp.mpf(row[key])
            assert abs(q - value) <= mp.mpf("1e-22") * abs(value), (key, d, q, value)
