#!/usr/bin/env python3
"""Reference values of the Coulomb–Contensou law over a contact disc, by direct
two-dimensional quadrature of the traction (issue #14; docs/physics.md, "Friction over a
contact disc").

A disc of radius R under uniform pressure p = N/(πR²), each point under Coulomb's law
with coefficient μ. The disc slides at v (along x) and spins at ω > 0 about its normal;
in units of R and Rω the velocity of the point (x, y) of the unit disc is
u = (d − y, x), d = |v|/(R|ω|) (the instantaneous centre of rotation is (0, d)).
Integrating −μ p u/|u| over the disc:

    f(d) = (1/π) ∬ (d − y)/|u| dx dy          F = −μ N f(d) v/|v|
    g(d) = (1/π) ∬ (x² + y² − d y)/|u| dx dy  M_n = −μ N R g(d) sgn ω

This script integrates those two double integrals with mpmath (tanh-sinh, nested), in
polar coordinates about the disc's centre, half disc x ≥ 0 (the integrands are even in
x), the angle φ ∈ [−π/2, π/2] with the ray through the centre of rotation (φ = π/2) as
an endpoint, and the radius split where it passes closest to the centre of rotation
(r = d sin φ). Nothing of the closed forms is used; they are evaluated afterwards
(mpmath's ellipk/ellipe, the formulas of docs/physics.md) only as a cross-check, and
the largest difference is printed.

    python3 scripts/contensou_reference.py                 # writes tests/data/contensou/reference.json
    python3 scripts/contensou_reference.py --check 1 0.3   # recomputes those d, compares with the file

The working precision grows with the cancellation: f ≈ d for small d and g ≈ 1/(4d) for
large d come out of O(1) integrands, so dps = 34 + |log10 d|.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import mpmath as mp

REPO = Path(__file__).resolve().parents[1]
OUT = REPO / "tests" / "data" / "contensou" / "reference.json"
DIGITS = 25  # significant digits written

# d values: decades from 1e-8 to 1e8, the series/closed-form boundaries of the Rust
# implementation (d² = 1/2, d² = 2), and the neighbourhood of d = 1.
D_VALUES = [
    1e-8, 1e-6, 1e-4, 1e-3, 1e-2, 0.05, 0.1, 0.2, 0.3, 0.5, 0.6,
    0.7071067811865475, 0.7071067811865476, 0.75, 0.8, 0.9, 0.99, 0.999, 0.999999,
    1.0, 1.000001, 1.001, 1.01, 1.1, 1.25, 1.414213562373095, 1.4142135623730951,
    1.5, 2.0, 3.0, 5.0, 10.0, 30.0, 100.0, 1e3, 1e4, 1e6, 1e8,
]


def quadrature(d: float) -> tuple[mp.mpf, mp.mpf]:
    """f(d), g(d) by the two-dimensional quadrature described above."""
    dd = mp.mpf(d)

    def inner(phi: mp.mpf, which: int) -> mp.mpf:
        s, c = mp.sin(phi), mp.cos(phi)
        r0 = dd * s

        def integrand(r: mp.mpf) -> mp.mpf:
            # |u|² = (r − d sin φ)² + d² cos² φ, free of cancellation near (0, d)
            norm = mp.sqrt((r - r0) ** 2 + (dd * c) ** 2)
            if which == 0:
                num = dd - r * s  # d − y
            else:
                num = r * (r - r0)  # x² + y² − d y
            return num / norm * r  # dA = r dr dφ

        pts = [0, r0, 1] if 0 < r0 < 1 else [0, 1]
        return mp.quad(integrand, pts)

    half = mp.pi / 2
    f = 2 * mp.quad(lambda p: inner(p, 0), [-half, half]) / mp.pi
    g = 2 * mp.quad(lambda p: inner(p, 1), [-half, half]) / mp.pi
    return f, g


def closed_form(d: float) -> tuple[mp.mpf, mp.mpf]:
    """The closed forms of docs/physics.md (mpmath's ellipk/ellipe take m = k²)."""
    dd = mp.mpf(d)
    if dd == 1:
        return mp.mpf(8) / (3 * mp.pi), mp.mpf(8) / (9 * mp.pi)
    if dd < 1:
        m = dd * dd
        K, E = mp.ellipk(m), mp.ellipe(m)
        f = 4 / (3 * mp.pi * dd) * ((1 + m) * E - (1 - m) * K)
        g = 4 / (9 * mp.pi) * (2 * (2 - m) * E - (1 - m) * K)
    else:
        m = 1 / (dd * dd)
        K, E = mp.ellipk(m), mp.ellipe(m)
        f = 4 / (3 * mp.pi) * ((dd * dd + 1) * E - (dd * dd - 1) * K)
        g = 4 * dd**3 / (9 * mp.pi) * (2 * (2 * m - 1) * E + (1 - m) * (2 - 3 * m) * K)
    return f, g


def compute(d: float) -> dict[str, str]:
    mp.mp.dps = 34 + int(abs(mp.log10(d)) + 0.5)
    t0 = time.time()
    f, g = quadrature(d)
    fc, gc = closed_form(d)
    df = abs(f - fc) / abs(f)
    dg = abs(g - gc) / abs(g)
    print(
        f"d = {d!r:>22}  f = {mp.nstr(f, 20):>24}  g = {mp.nstr(g, 20):>24}  "
        f"|quad − closed|/value: f {mp.nstr(df, 2)}, g {mp.nstr(dg, 2)}  ({time.time() - t0:.1f} s)",
        flush=True,
    )
    return {
        "d": repr(d),
        "f": mp.nstr(f, DIGITS, strip_zeros=False),
        "g": mp.nstr(g, DIGITS, strip_zeros=False),
        "closed_form_rel_diff_f": mp.nstr(df, 3),
        "closed_form_rel_diff_g": mp.nstr(dg, 3),
    }


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--check", nargs="*", type=float, metavar="D",
                    help="recompute these d values and compare with the stored file")
    args = ap.parse_args()
    if args.check is not None:
        stored = {float(r["d"]): r for r in json.loads(OUT.read_text())["values"]}
        worst = 0.0
        for d in args.check:
            row = compute(d)
            for key in ("f", "g"):
                rel = abs(mp.mpf(row[key]) - mp.mpf(stored[d][key])) / abs(mp.mpf(row[key]))
                worst = max(worst, float(rel))
        print(f"largest relative difference from the stored values: {worst:.2e}")
        return 0 if worst < 1e-20 else 1
    rows = [compute(d) for d in D_VALUES]
    OUT.parent.mkdir(parents=True, exist_ok=True)
    doc = {
        "what": "f(d), g(d) of the Coulomb–Contensou law over a uniformly loaded disc, "
        "by two-dimensional mpmath quadrature (scripts/contensou_reference.py)",
        "digits": DIGITS,
        "values": rows,
    }
    OUT.write_text(json.dumps(doc, indent=1) + "\n")
    print(f"wrote {OUT.relative_to(REPO)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
