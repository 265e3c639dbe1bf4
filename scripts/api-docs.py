#!/usr/bin/env python3
"""Builds the API reference of the installed `ellipsoid` package with pdoc (docstrings of
the Rust extension and of the Python modules; signatures and types from the stubs,
`_ellipsoid.pyi`) and fails on any warning pdoc gives, or on a public function, class,
method or property without a docstring.

    python scripts/api-docs.py                 # -> target/api/ellipsoid.html
    python scripts/api-docs.py -o DIR
"""
from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path

import pdoc
import pdoc.doc

ROOT = Path(__file__).resolve().parent.parent


def undocumented(module: pdoc.doc.Module) -> list[str]:
    """Public members (those pdoc shows) with an empty docstring."""
    missing = []

    def walk(ns: pdoc.doc.Namespace) -> None:
        members = ns.own_members if isinstance(ns, pdoc.doc.Class) else list(ns.members.values())
        for member in members:
            if not member.is_public or member.name.startswith("__"):
                continue
            if isinstance(member, pdoc.doc.Variable) and isinstance(ns, pdoc.doc.Module):
                continue  # module constants (COLUMNS, HDF5, __version__) are described in the module's text
            if not member.docstring.strip():
                missing.append(member.fullname)
            if isinstance(member, pdoc.doc.Class):
                walk(member)

    walk(module)
    return missing


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("-o", "--out", type=Path, default=ROOT / "target" / "api")
    args = ap.parse_args()
    pdoc.render.configure(docformat="markdown", show_source=False)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        pdoc.pdoc("ellipsoid", output_directory=args.out)
        module = pdoc.doc.Module.from_name("ellipsoid")
        missing = undocumented(module)
    problems = [f"pdoc warning: {w.message}" for w in caught]
    problems += [f"no docstring: {name}" for name in missing]
    for p in problems:
        print(p, file=sys.stderr)
    print(f"api-docs: {args.out / 'ellipsoid.html'}, {len(problems)} problems")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
