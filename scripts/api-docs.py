#!/usr/bin/env python3
"""Builds the API reference of the installed `ellipsoid` package with pdoc (docstrings of
the Rust extension and of the Python modules; signatures and types from the stubs,
`_ellipsoid.pyi`) and fails on any warning pdoc gives, on a public function, class,
method or property without a docstring, or on a trajectory column whose docstring does
not state its unit.

    python scripts/api-docs.py                 # -> target/api/ellipsoid.html
    python scripts/api-docs.py -o DIR
"""
from __future__ import annotations

import argparse
import re
import sys
import warnings
from pathlib import Path

import pdoc
import pdoc.doc

ROOT = Path(__file__).resolve().parent.parent


def stub_comments() -> dict[str, str]:
    """`Class.attribute` -> the `#:` comment above it in the type stubs: pdoc takes the stubs'
    signatures and docstrings but not these comments on class attributes."""
    import ellipsoid

    stub = Path(ellipsoid.__file__).with_name("_ellipsoid.pyi").read_text(encoding="utf-8").splitlines()
    found, cls, comment = {}, None, []
    for line in stub:
        m = re.match(r"^class (\w+)", line)
        if m:
            cls, comment = m.group(1), []
            continue
        m = re.match(r"^    #: ?(.*)$", line)
        if m:
            comment.append(m.group(1))
            continue
        m = re.match(r"^    (\w+)\s*:", line)
        if m and cls and comment:
            found[f"{cls}.{m.group(1)}"] = " ".join(comment)
        comment = []
    return found


def undocumented(module: pdoc.doc.Module) -> list[str]:
    """Public members (in `__all__`, and their classes' own members not starting with `_`)
    with an empty docstring."""
    missing = []

    def walk(ns: pdoc.doc.Namespace) -> None:
        if isinstance(ns, pdoc.doc.Class):
            members = [m for m in ns.own_members if not m.name.startswith("_")]
        else:
            members = [m for m in ns.members.values() if m.name in ns.obj.__all__]
        for member in members:
            if isinstance(member, pdoc.doc.Variable) and isinstance(ns, pdoc.doc.Module):
                continue  # module constants (COLUMNS, HDF5, __version__) are described in the module's text
            if not member.docstring.strip():
                missing.append(member.fullname)
            if isinstance(member, pdoc.doc.Class):
                walk(member)

    walk(module)
    return missing


def missing_units() -> list[str]:
    """Trajectory columns whose docstring does not state the unit `Trajectory.units` gives
    them, as `[unit]`."""
    import ellipsoid

    traj = ellipsoid.Trajectory
    return [f"ellipsoid.Trajectory.{c} (unit {traj.units[c]})" for c in traj.columns
            if traj.units[c] != "1" and f"[{traj.units[c]}]" not in (getattr(traj, c).__doc__ or "")]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("-o", "--out", type=Path, default=ROOT / "target" / "api")
    args = ap.parse_args()
    pdoc.render.configure(docformat="markdown", show_source=False)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        module = pdoc.doc.Module.from_name("ellipsoid")
        comments = stub_comments()
        for cls in module.classes:
            for var in cls.own_members:
                qualname = var.taken_from[1]
                if isinstance(var, pdoc.doc.Variable) and not var.docstring and qualname in comments:
                    var.docstring = comments[qualname]
        missing = undocumented(module)
        modules = {"ellipsoid": module}
        args.out.mkdir(parents=True, exist_ok=True)
        (args.out / "ellipsoid.html").write_text(pdoc.render.html_module(module, modules), encoding="utf-8")
        (args.out / "index.html").write_text(pdoc.render.html_index(modules), encoding="utf-8")
        (args.out / "search.js").write_text(pdoc.render.search_index(modules), encoding="utf-8")
    problems = [f"pdoc warning: {w.message}" for w in caught]
    problems += [f"no docstring: {name}" for name in missing]
    problems += [f"no unit in the docstring: {name}" for name in missing_units()]
    for p in problems:
        print(p, file=sys.stderr)
    print(f"api-docs: {args.out / 'ellipsoid.html'}, {len(problems)} problems")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
