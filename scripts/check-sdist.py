#!/usr/bin/env python3
"""Checks the Python package's source distribution (`maturin sdist -m
crates/ellipsoid-py/Cargo.toml`): that it holds every file a build from source needs, and
nothing a build leaves behind.

Needed: the workspace's Cargo.toml and Cargo.lock (the lock file unchanged: the build from
source uses the tested versions), pyproject.toml and PKG-INFO, the README, both licence
files (LICENSE-MIT, LICENSE-APACHE, as in the repository), and, for the Python crate and
every workspace crate it depends on (found with `cargo metadata`, transitively), its
Cargo.toml and every file git tracks under its src/ and assets/; for the Python crate also
every file under python/. Refused: anything under target/, .venv*, .git, __pycache__,
.pytest_cache, .mypy_cache or .ipynb_checkpoints, compiled files (.so, .pyd, .pyc, .whl),
trajectories (.h5, .csv), members that are not plain files or directories, and an archive
of more than 5 MB.

    python scripts/check-sdist.py target/sdist/ellipsoid-0.1.0.tar.gz
"""
from __future__ import annotations

import json
import subprocess
import sys
import tarfile
from pathlib import Path, PurePosixPath

ROOT = Path(__file__).resolve().parent.parent
PY_CRATE = "ellipsoid-py"
MAX_BYTES = 5_000_000
BUILD_DIRS = {"target", ".git", "__pycache__", ".pytest_cache", ".mypy_cache", ".ipynb_checkpoints"}
BUILD_SUFFIXES = {".so", ".pyd", ".pyc", ".whl", ".h5", ".csv"}
TOP = ["Cargo.toml", "Cargo.lock", "pyproject.toml", "PKG-INFO", "README.md", "LICENSE-MIT", "LICENSE-APACHE"]


def workspace_crates() -> list[Path]:
    """The Python crate's directory and those of the workspace crates it depends on."""
    meta = json.loads(subprocess.run(
        ["cargo", "metadata", "--format-version", "1", "--no-deps", "--offline"],
        cwd=ROOT, check=True, capture_output=True, text=True).stdout)
    by_name = {p["name"]: p for p in meta["packages"]}
    todo, seen = [PY_CRATE], set()
    while todo:
        name = todo.pop()
        if name in seen:
            continue
        seen.add(name)
        todo += [d["name"] for d in by_name[name]["dependencies"] if d.get("path") and d["kind"] is None]
    return sorted(Path(by_name[n]["manifest_path"]).parent.relative_to(ROOT) for n in seen)


def tracked(under: Path) -> list[str]:
    out = subprocess.run(["git", "ls-files", "--", str(under)], cwd=ROOT, check=True,
                         capture_output=True, text=True).stdout
    return out.split()


def problems(archive: Path) -> list[str]:
    found: list[str] = []
    if archive.stat().st_size > MAX_BYTES:
        found.append(f"{archive.name}: {archive.stat().st_size} bytes, more than {MAX_BYTES}")
    with tarfile.open(archive) as tar:
        members = tar.getmembers()
        tops = {PurePosixPath(m.name).parts[0] for m in members}
        if len(tops) != 1:
            return found + [f"{archive.name}: not one top directory but {sorted(tops)}"]
        top = tops.pop()
        files = {}
        for m in members:
            rel = PurePosixPath(m.name).relative_to(top)
            if not (m.isfile() or m.isdir()):
                found.append(f"{rel}: not a plain file or directory")
            if BUILD_DIRS & set(rel.parts) or any(p.startswith(".venv") for p in rel.parts):
                found.append(f"{rel}: a build or tool directory")
            elif rel.suffix in BUILD_SUFFIXES:
                found.append(f"{rel}: a compiled or output file")
            if m.isfile():
                files[str(rel)] = m

        def read(rel: str) -> bytes:
            f = tar.extractfile(files[rel])
            assert f is not None
            return f.read()

        needed = list(TOP)
        for crate in workspace_crates():
            needed.append(str(crate / "Cargo.toml"))
            for sub in ("src", "assets") + (("python",) if crate.name == PY_CRATE else ()):
                needed += tracked(crate / sub)
        # maturin puts the Python crate's pyproject.toml and python/ at the archive's root.
        py = str(next(c for c in workspace_crates() if c.name == PY_CRATE))
        needed = [n[len(py) + 1:] if n.startswith(py + "/python/") else n for n in needed]
        found += [f"{n}: missing" for n in needed if n not in files]
        for same in ("Cargo.lock", "LICENSE-MIT", "LICENSE-APACHE"):
            if same in files and read(same) != (ROOT / same).read_bytes():
                found.append(f"{same}: differs from the repository's")
    return found


def main() -> int:
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    archive = Path(sys.argv[1])
    found = problems(archive)
    for p in found:
        print(p, file=sys.stderr)
    print(f"check-sdist: {archive.name}, {len(found)} problems")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
