#!/usr/bin/env python3
"""Executes every tutorial notebook of examples/ with nbclient against the installed
`ellipsoid` package, as CI does, and renders them as the tutorial pages of the docs.

A notebook fails if it is stored with outputs, if a cell raises, if a cell prints a
traceback (a caught exception printed, a warning's traceback), or if it takes longer than
the budget (60 s by default). Cells run in examples/ (the notebooks read
`../scenarios/*.toml`), in a kernel of this Python.

The pages (docs/tutorials/NAME.md, figures in docs/tutorials/NAME/) are each notebook
executed: its markdown cells as they are, its code cells as Python blocks, then their
outputs — printed text and results as text, figures as PNG (256 colours, a few tens of kB
each), the viewer's HTML as a note. Each cell's outputs sit between `<!-- outputs -->`
and `<!-- /outputs -->`, so `--check-pages` can compare a page with its notebook without
executing it: the page must have the notebook's cells, in order, unchanged; every figure
it shows must exist and every stored figure must be shown; every notebook needs a page
and every page a notebook.

    python scripts/run-notebooks.py                          # execute all, report the time of each
    python scripts/run-notebooks.py --html DIR               # ... and write each as HTML
    python scripts/run-notebooks.py --markdown docs/tutorials  # ... and write the tutorial pages
    python scripts/run-notebooks.py --check-pages docs/tutorials  # CI: the pages are current (no execution)
    python scripts/run-notebooks.py --strip                  # clear outputs (before committing)
"""
from __future__ import annotations

import argparse
import base64
import io
import os
import re
import sys
import time
from pathlib import Path

import nbformat

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "examples"
OPEN, CLOSE = "<!-- outputs -->", "<!-- /outputs -->"
#: A figure wider than this (px) is scaled down on the page.
MAX_WIDTH = 900


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


def relink(text: str, pages: Path) -> str:
    """Markdown links relative to examples/ made relative to the pages' directory; a link to
    another notebook becomes a link to its page."""

    def move(m: re.Match[str]) -> str:
        target = m.group(2)
        if re.match(r"^[a-z]+:|^#", target):
            return m.group(0)
        file, sep, anchor = target.partition("#")
        dest = (EXAMPLES / file).resolve()
        if dest.parent == EXAMPLES and dest.suffix == ".ipynb":
            return f"{m.group(1)}({dest.stem}.md{sep}{anchor})"
        moved = Path(os.path.relpath(dest, pages.resolve())).as_posix()
        return f"{m.group(1)}({moved}{sep}{anchor})"

    return re.sub(r"(\]\s*)\(([^)\s]+)\)", move, text)


def small_png(data: str) -> tuple[bytes, int]:
    """A figure's PNG (base64) as a PNG of at most 256 colours, and its width in px."""
    from PIL import Image

    img = Image.open(io.BytesIO(base64.b64decode(data))).convert("RGB")
    out = io.BytesIO()
    img.quantize(colors=256).save(out, format="PNG", optimize=True)
    return out.getvalue(), img.width


def text_block(text: str) -> str:
    return "```text\n" + text.rstrip("\n") + "\n```\n"


def outputs(cell: nbformat.NotebookNode, stem: str, figures: dict[str, bytes]) -> list[str]:
    """A code cell's outputs as markdown; its figures are added to `figures` (file name under
    the page's figure directory -> PNG bytes). Standard error (progress and log lines of
    the libraries) is left out; tracebacks fail the run before a page is written."""
    parts: list[str] = []
    printed = ""  # consecutive prints, one block (the kernel may send them in pieces)
    for out in cell.get("outputs", []):
        kind = out.get("output_type")
        if kind == "stream":
            printed += out["text"] if out.get("name") == "stdout" else ""
            continue
        if printed:
            parts.append(text_block(printed))
            printed = ""
        if kind in ("execute_result", "display_data"):
            data = out.get("data", {})
            if "image/png" in data:
                png, width = small_png(data["image/png"])
                name = f"fig-{len(figures) + 1}.png"
                figures[name] = png
                alt = f"figure {len(figures)} of {stem}"
                if width > MAX_WIDTH:
                    parts.append(f'<img src="{stem}/{name}" alt="{alt}" width="{MAX_WIDTH}">\n')
                else:
                    parts.append(f"![{alt}]({stem}/{name})\n")
            elif "<iframe" in data.get("text/html", ""):
                parts.append("*(In Jupyter the 3-D viewer shows here, inline.)*\n")
            elif "text/plain" in data:
                parts.append(text_block(data["text/plain"]))
    if printed:
        parts.append(text_block(printed))
    return parts


def page(book: nbformat.NotebookNode, path: Path, pages: Path, figures: dict[str, bytes] | None) -> str:
    """The markdown page of a notebook; with `figures` None, without its outputs."""
    stem = path.stem
    source = Path(os.path.relpath(path.resolve(), pages.resolve())).as_posix()
    parts = [
        f"<!-- Generated from examples/{path.name} by scripts/run-notebooks.py --markdown: edit the notebook, not this page. -->\n",
        f"*This page is the notebook [`examples/{path.name}`]({source}) executed, with its"
        " outputs. Run it yourself from `examples/` (see [the tutorials](../tutorials.md)).*\n",
    ]
    for cell in book.cells:
        if cell.cell_type == "markdown":
            parts.append(relink(cell.source, pages).rstrip("\n") + "\n")
        elif cell.cell_type == "code" and cell.source.strip():
            parts.append("```python\n" + cell.source.rstrip("\n") + "\n```\n")
            shown = outputs(cell, stem, figures) if figures is not None else []
            if shown:
                parts.append(OPEN + "\n\n" + "\n".join(shown) + "\n" + CLOSE + "\n")
    return "\n".join(parts)


def without_outputs(text: str) -> str:
    return re.sub(re.escape(OPEN) + r".*?" + re.escape(CLOSE) + r"\n\n?", "", text, flags=re.S)


def write_page(book: nbformat.NotebookNode, path: Path, pages: Path) -> None:
    """Writes the page of an executed notebook and its figures (replacing the old ones)."""
    figures: dict[str, bytes] = {}
    text = page(book, path, pages, figures)
    figdir = pages / path.stem
    figdir.mkdir(parents=True, exist_ok=True)
    for old in figdir.glob("*.png"):
        old.unlink()
    for name, png in figures.items():
        (figdir / name).write_bytes(png)
    (pages / f"{path.stem}.md").write_text(text, encoding="utf-8")


def check_pages(paths: list[Path], pages: Path) -> list[str]:
    """What makes the stored pages differ from the notebooks (outputs aside)."""
    problems = []
    for path in paths:
        stored = pages / f"{path.stem}.md"
        if not stored.exists():
            problems.append(f"{path.name}: no page {stored.relative_to(ROOT)}")
            continue
        text = stored.read_text(encoding="utf-8")
        book = nbformat.read(path, as_version=4)
        if without_outputs(text).rstrip() != page(book, path, pages, None).rstrip():
            problems.append(f"{stored.relative_to(ROOT)}: not the notebook's cells (rerun with --markdown {pages.relative_to(ROOT)})")
        shown = set(re.findall(rf"{re.escape(path.stem)}/(fig-\d+\.png)", text))
        stored_figs = {p.name for p in (pages / path.stem).glob("*.png")}
        problems += [f"{stored.relative_to(ROOT)}: figure {f} is missing" for f in sorted(shown - stored_figs)]
        problems += [f"{pages.relative_to(ROOT)}/{path.stem}/{f}: not shown on its page" for f in sorted(stored_figs - shown)]
    stems = {p.stem for p in paths}
    problems += [f"{p.relative_to(ROOT)}: no notebook examples/{p.stem}.ipynb" for p in sorted(pages.glob("*.md")) if p.stem not in stems]
    return problems


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("notebooks", nargs="*", type=Path, help="default: examples/*.ipynb")
    ap.add_argument("--budget", type=float, default=60.0, help="seconds per notebook (default 60)")
    ap.add_argument("--html", type=Path, help="write the executed notebooks as HTML to this directory")
    ap.add_argument("--markdown", type=Path, help="write the executed notebooks as the tutorial pages in this directory")
    ap.add_argument("--check-pages", type=Path, help="check the tutorial pages in this directory against the notebooks; execute nothing")
    ap.add_argument("--strip", action="store_true", help="clear the outputs in place and exit")
    args = ap.parse_args()
    paths = [p.resolve() for p in args.notebooks] or sorted(EXAMPLES.glob("*.ipynb"))
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
    if args.check_pages:
        problems = check_pages(paths, args.check_pages.resolve())
        for p in problems:
            print(p, file=sys.stderr)
        print(f"check-pages: {len(paths)} notebooks, {len(problems)} problems")
        return 1 if problems else 0

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
        tracebacks = [f"{path.name}: printed a traceback: {t}" for t in printed_tracebacks(book)]
        failures += tracebacks
        if seconds > args.budget:
            failures.append(f"{path.name}: took {seconds:.1f} s, over the budget of {args.budget:.0f} s")
        print(f"{path.name}: {seconds:.1f} s")
        if args.html:
            from nbconvert import HTMLExporter

            args.html.mkdir(parents=True, exist_ok=True)
            html, _ = HTMLExporter().from_notebook_node(book)
            (args.html / path.with_suffix(".html").name).write_text(html, encoding="utf-8")
        if args.markdown and not tracebacks and not any(f.startswith(f"{path.name}:") for f in failures):
            write_page(book, path, args.markdown.resolve())
    for f in failures:
        print(f, file=sys.stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
