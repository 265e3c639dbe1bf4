#!/usr/bin/env python3
"""Executes every tutorial notebook of examples/ with nbclient against the installed
`ellipsoid` package, as CI does.

A notebook fails if it is stored with outputs, if a cell raises, if a cell prints a
traceback (a caught exception printed, a warning's traceback), or if it takes longer than
the budget (60 s by default). Cells run in examples/ (the notebooks read
`../scenarios/*.toml`), in a kernel of this Python.

    python scripts/run-notebooks.py                 # execute all, report the time of each
    python scripts/run-notebooks.py --html DIR      # ... and write each executed notebook as HTML
    python scripts/run-notebooks.py --strip         # clear outputs (before committing)
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import nbformat

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "examples"


def has_outputs(book: nbformat.NotebookNode) -> bool:
    return any(c.get("outputs") or c.get("execution_count") for c in book.cells if c.cell_type == "code")


def printed_tracebacks(book: nbformat.NotebookNode) -> list[str]:
    found = []
    for i, cell in enumerate(book.cells):
        for out in cell.get("outputs", []):
            text = out.get("text", "") if out.get("output_type") == "stream" else ""
            if out.get("output_type") == "error" or "Traceback (most recent call last)" in text:
                found.append(f"cell {i}: {(text or out.get('ename', ''))[:300]}")
    return found


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("notebooks", nargs="*", type=Path, help="default: examples/*.ipynb")
    ap.add_argument("--budget", type=float, default=60.0, help="seconds per notebook (default 60)")
    ap.add_argument("--html", type=Path, help="write the executed notebooks as HTML to this directory")
    ap.add_argument("--strip", action="store_true", help="clear the outputs in place and exit")
    args = ap.parse_args()
    paths = args.notebooks or sorted(EXAMPLES.glob("*.ipynb"))
    if not paths:
        print("no notebooks in examples/", file=sys.stderr)
        return 1
    if args.strip:
        for path in paths:
            book = nbformat.read(path, as_version=4)
            for cell in book.cells:
                if cell.cell_type == "code":
                    cell.outputs, cell.execution_count = [], None
            nbformat.write(book, path)
        return 0

    from nbclient import NotebookClient
    from nbclient.exceptions import CellExecutionError

    failures = []
    for path in paths:
        book = nbformat.read(path, as_version=4)
        if has_outputs(book):
            failures.append(f"{path.name}: stored with outputs (run with --strip)")
            continue
        start = time.perf_counter()
        try:
            NotebookClient(book, timeout=args.budget, kernel_name="python3",
                           resources={"metadata": {"path": str(path.parent)}}).execute()
        except CellExecutionError as e:
            failures.append(f"{path.name}: {e}")
        seconds = time.perf_counter() - start
        failures += [f"{path.name}: printed a traceback: {t}" for t in printed_tracebacks(book)]
        if seconds > args.budget:
            failures.append(f"{path.name}: took {seconds:.1f} s, over the budget of {args.budget:.0f} s")
        print(f"{path.name}: {seconds:.1f} s")
        if args.html:
            from nbconvert import HTMLExporter

            args.html.mkdir(parents=True, exist_ok=True)
            html, _ = HTMLExporter().from_notebook_node(book)
            (args.html / path.with_suffix(".html").name).write_text(html, encoding="utf-8")
    for f in failures:
        print(f, file=sys.stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
