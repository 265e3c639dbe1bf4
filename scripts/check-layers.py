#!/usr/bin/env python3
"""Checks that the top-level modules of a crate import each other without a circle.

    python3 scripts/check-layers.py [CRATE_SRC ...]     (default: crates/ellipsoid-core/src)

Every `crate::NAME` a module's non-test code names (in `use` trees, grouped or nested, and
in paths) is an edge from that module to module NAME. A strongly connected component of
more than one module is a circle: each is printed with the imports that close it, and the
exit status is 1. Otherwise the modules are printed in layers (each imports only from the
layers before it) and the exit status is 0. `pub use` re-exports count as imports too:
a facade that re-exports from a lower layer is no circle, one that re-exports from a
higher layer is.
"""

import os
import re
import sys
from collections import defaultdict

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")


def strip_comments_and_tests(src: str) -> str:
    """The source without comments, string literals and `#[cfg(test)]` items."""
    src = re.sub(r"//[^\n]*", "", src)
    src = re.sub(r"/\*.*?\*/", "", src, flags=re.S)
    src = re.sub(r'"(?:\\.|[^"\\])*"', '""', src)
    out, i = [], 0
    for m in re.finditer(r"#\[cfg\(test\)\]", src):
        if m.start() < i:
            continue
        out.append(src[i : m.start()])
        # skip the item: up to its matching closing brace (or `;` for `mod x;`)
        j = m.end()
        while j < len(src) and src[j] not in "{;":
            j += 1
        if j < len(src) and src[j] == "{":
            depth = 0
            while j < len(src):
                depth += {"{": 1, "}": -1}.get(src[j], 0)
                j += 1
                if depth == 0:
                    break
        else:
            j += 1
        i = j
    out.append(src[i:])
    return "".join(out)


def use_roots(tree: str) -> set[str]:
    """The first segments of every path in a `use crate::TREE;` tree."""
    tree = tree.strip()
    if not tree.startswith("{"):
        return {re.match(r"[A-Za-z_][A-Za-z0-9_]*", tree).group(0)}
    roots, depth, start = set(), 0, 1
    for k, ch in enumerate(tree):
        if ch == "{":
            depth += 1
        elif ch == "}":
            depth -= 1
        if (ch == "," and depth == 1) or (ch == "}" and depth == 0):
            part = tree[start:k].strip()
            if part:
                roots.add(re.match(r"[A-Za-z_][A-Za-z0-9_]*", part).group(0))
            start = k + 1
    return roots


def module_edges(src_dir: str) -> dict[str, dict[str, str]]:
    """module -> {imported module: the file that imports it}."""
    edges: dict[str, dict[str, str]] = defaultdict(dict)
    # Files of `#[cfg(test)] mod NAME;` are test code: NAME.rs or NAME/mod.rs beside it.
    test_files = set()
    for dirpath, _, files in os.walk(src_dir):
        for name in files:
            if name.endswith(".rs"):
                src = open(os.path.join(dirpath, name), encoding="utf-8").read()
                here = dirpath if name in ("mod.rs", "lib.rs") else os.path.join(dirpath, name[:-3])
                for m in re.findall(r"#\[cfg\(test\)\]\s*(?:pub(?:\([^)]*\))?\s+)?mod\s+(\w+)\s*;", src):
                    test_files.add(os.path.join(here, m + ".rs"))
                    test_files.add(os.path.join(here, m, "mod.rs"))
    for dirpath, _, files in os.walk(src_dir):
        for name in sorted(files):
            if not name.endswith(".rs"):
                continue
            path = os.path.join(dirpath, name)
            if path in test_files:
                continue
            rel = os.path.relpath(path, src_dir)
            top = rel.split(os.sep)[0].removesuffix(".rs")
            if top in ("lib", "main"):
                continue
            edges.setdefault(top, {})
            src = strip_comments_and_tests(open(path, encoding="utf-8").read())
            names = set()
            for tree in re.findall(r"\buse\s+crate::(.*?);", src, re.S):
                names |= use_roots(tree)
            names |= set(re.findall(r"\bcrate::([a-z_][a-z0-9_]*)", src))
            for dep in names - {top}:
                edges[top].setdefault(dep, os.path.relpath(path, ROOT))
    return edges


def components(nodes, edges):
    """Tarjan's strongly connected components."""
    index, low, stack, on, out, counter = {}, {}, [], set(), [], [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in edges.get(v, {}):
            if w not in nodes:
                continue
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            out.append(sorted(comp))

    for v in sorted(nodes):
        if v not in index:
            visit(v)
    return out


def check(src_dir: str) -> bool:
    edges = module_edges(src_dir)
    nodes = set(edges)
    circles = [c for c in components(nodes, edges) if len(c) > 1]
    print(f"{os.path.relpath(src_dir, ROOT)}: {len(nodes)} modules")
    if circles:
        for comp in circles:
            print(f"  circle through {', '.join(comp)}:")
            for a in comp:
                for b, where in sorted(edges[a].items()):
                    if b in comp:
                        print(f"    {a} -> {b}   ({where})")
        return False
    placed, layer = set(), 0
    while len(placed) < len(nodes):
        now = sorted(v for v in nodes - placed if set(edges[v]) & nodes <= placed)
        print(f"  layer {layer}: {' '.join(now)}")
        placed |= set(now)
        layer += 1
    return True


if __name__ == "__main__":
    dirs = sys.argv[1:] or [os.path.join(ROOT, "crates", "ellipsoid-core", "src")]
    ok = all([check(d) for d in dirs])
    sys.exit(0 if ok else 1)
