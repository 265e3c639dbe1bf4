#!/usr/bin/env python3
"""Checks the user documentation (README.md, docs/*.md, the Python package's README, and
examples/: its README and the markdown cells of its notebooks) for what belongs in commit
messages or the development log instead: commit hashes, the history of the work ("this
round", "before this change", issue numbers), load averages and who was building what.
Also checks that every relative link and heading anchor resolves and that README.md links
every page of docs/ and the Python package's README.

The development pages (docs/development.md and docs/development/) are exempt: they are the
record of how the work went. Exit status 1 with one line per finding (file:line: rule: text).

    python3 scripts/check-docs.py            # from the repository root, or any directory
"""
from __future__ import annotations

import json
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

# Files written by tools (viewer pages of the gallery) that the repository does not store:
# links to them are made by `scripts/gallery.py --viewers`.
GENERATED_LINK = re.compile(r"^gallery/view/[\w.-]+\.html$")

# A commit hash: 7 to 40 hex digits with a letter and a digit, not inside a number or word.
HASH = re.compile(r"(?<![\w.+-])(?=[0-9a-f]*[a-f])(?=[0-9a-f]*[0-9])[0-9a-f]{7,40}(?![\w])")

RULES: list[tuple[str, re.Pattern[str]]] = [
    ("commit hash", HASH),
    ("load average", re.compile(r"\bload averages?\b|\bat (a )?load\b|\bload \d", re.I)),
    ("history of the work", re.compile(
        r"\b(this|last|earlier|previous|next|that) round\b(?!-)"
        r"|\b(before|after|since|until) (this|that|the) (change|merge|fix|work|rewrite|round|commit|branch)\b"
        r"|\bthis (change|branch|commit|session|pull request|PR)\b"
        r"|\bre-?measured\b"
        r"|\bgit history\b"
        r"|\bwas added\b|\bwere added\b"
        r"|\bthe old (ending|behaviou?r|code|build|version)\b"
        r"|\bissues? #\d+|\(#\d+\)"
        r"|\bother (developers|engineers|helpers)\b|\bthe (helpers|lead)\b"
        r"|\bwhile (two|three|four|other) \w+ (were )?building\b",
        re.I)),
]

LINK = re.compile(r"\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")


def user_docs() -> list[Path]:
    docs = [ROOT / "README.md", ROOT / "crates/ellipsoid-py/README.md"]
    docs += sorted((ROOT / "docs").glob("*.md")) + sorted((ROOT / "docs" / "tutorials").glob("*.md"))
    docs += sorted((ROOT / "examples").glob("*.md")) + sorted((ROOT / "examples").glob("*.ipynb"))
    return [d for d in docs if d.name != "development.md"]


def lines_of(path: Path) -> list[tuple[int, str]]:
    """(line number, text); for a notebook, the markdown cells' lines numbered across them."""
    if path.suffix != ".ipynb":
        return list(enumerate(path.read_text(encoding="utf-8").splitlines(), 1))
    out, n = [], 0
    for cell in json.loads(path.read_text(encoding="utf-8"))["cells"]:
        text = "".join(cell["source"]) if isinstance(cell["source"], list) else cell["source"]
        for line in text.splitlines():
            n += 1
            if cell["cell_type"] == "markdown":
                out.append((n, line))
    return out


def anchors(page: Path) -> set[str]:
    """The heading anchors of a markdown page as GitHub makes them."""
    found = set()
    for line in page.read_text(encoding="utf-8").splitlines():
        m = re.match(r"^#{1,6}\s+(.*)$", line)
        if m:
            slug = re.sub(r"[^\w\- ]", "", m.group(1).strip().lower()).replace(" ", "-")
            found.add(slug)
    return found


def check_links(path: Path, lines: list[tuple[int, str]]) -> list[str]:
    found = []
    for n, line in lines:
        for target in LINK.findall(line):
            if re.match(r"^[a-z]+:", target) or target.startswith("#"):
                continue
            file, _, anchor = target.partition("#")
            if GENERATED_LINK.match(file):
                continue
            dest = path.parent / file
            if not dest.exists():
                found.append(f"{path.relative_to(ROOT)}:{n}: broken link: {target}")
            elif anchor and dest.suffix == ".md" and anchor not in anchors(dest):
                found.append(f"{path.relative_to(ROOT)}:{n}: no such heading: {target}")
    return found


def main() -> int:
    findings: list[str] = []
    for path in user_docs():
        lines = lines_of(path)
        for n, line in lines:
            for rule, pattern in RULES:
                m = pattern.search(line)
                if m:
                    findings.append(f"{path.relative_to(ROOT)}:{n}: {rule}: {m.group(0)!r} in {line.strip()[:120]!r}")
        findings += check_links(path, lines)
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    pages = sorted((ROOT / "docs").glob("*.md")) + [ROOT / "crates/ellipsoid-py/README.md"]
    for page in pages:
        rel = page.relative_to(ROOT).as_posix()
        if f"]({rel})" not in readme and f"]({rel}#" not in readme:
            findings.append(f"README.md: not linked: {rel}")
    for line in findings:
        print(line)
    print(f"check-docs: {len(user_docs())} files, {len(findings)} findings", file=sys.stderr)
    return 1 if findings else 0


if __name__ == "__main__":
    sys.exit(main())
