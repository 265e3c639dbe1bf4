#!/usr/bin/env bash
# Builds the Python package's source distribution and, from it, the wheel for any x86-64
# Linux with glibc >= 2.17: `maturin sdist`, then `pip wheel` of that sdist, as `pip
# install` builds one from source (maturin and CMake from PyPI in an isolated build
# environment, per pyproject.toml), with maturin compiling and linking by `zig cc` (the
# `ziglang` package from PyPI) against glibc 2.17's symbols; the HDF5 C library, built from
# source by the hdf5-metno-src crate with CMake, is compiled by the same `zig cc`.
# auditwheel then shows the platform tag (manylinux_2_17_x86_64, alias
# manylinux2014_x86_64). One compile gives both files, and proves that the sdist builds.
# Needs Rust (rustup) and Python; maturin, ziglang, CMake and auditwheel come from PyPI.
#
#   scripts/build-wheel.sh [OUT_DIR]      # default: $CARGO_TARGET_DIR/wheels-manylinux or target/...
#   WHEEL_VENV=.venv scripts/build-wheel.sh DIR   # use (and add the tools to) an existing venv
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-${CARGO_TARGET_DIR:-target}/wheels-manylinux}"
venv="${WHEEL_VENV:-.venv-wheel}"
[ -x "$venv/bin/python" ] || python3 -m venv "$venv"
venv="$(cd "$venv" && pwd)"
"$venv/bin/python" -m pip install --quiet --disable-pip-version-check 'maturin>=1.9,<2' ziglang 'cmake>=3.26' auditwheel
# maturin (in the isolated build environment, which keeps PATH) finds `zig` on the PATH:
# the ziglang package's binary, linked into a directory of its own.
zig_dir="$venv/zig-bin"
mkdir -p "$zig_dir"
ln -sf "$("$venv/bin/python" -c 'import ziglang, os; print(os.path.join(os.path.dirname(ziglang.__file__), "zig"))')" "$zig_dir/zig"
export PATH="$zig_dir:$venv/bin:$PATH"
# The HDF5 build runs CMake through scripts/cmake-hdf5 (no build machine's path in the
# binary; the sdist does not carry .cargo/config.toml, which names it for cargo builds).
export ELLIPSOID_CMAKE="${ELLIPSOID_CMAKE:-$venv/bin/cmake}"
export CMAKE="$PWD/scripts/cmake-hdf5"
# The wheel's extension is stripped: no debug info to compile (the workspace's release
# profile keeps it for profiling), which makes the build, HDF5's included, about a fifth cheaper.
export CARGO_PROFILE_RELEASE_DEBUG=false
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$PWD/target}"
case "$CARGO_TARGET_DIR" in /*) ;; *) CARGO_TARGET_DIR="$PWD/$CARGO_TARGET_DIR" ;; esac
mkdir -p "$out"
rm -f "$out"/ellipsoid-*.whl "$out"/ellipsoid-*.tar.gz
# HDF5's CMake build directory of an earlier wheel names that build's compiler: a zig cc
# wrapper that runs maturin from the isolated build environment pip has since deleted
# ("maturin: not found" at the second build in one checkout). Built afresh each time.
rm -rf "$CARGO_TARGET_DIR"/x86_64-unknown-linux-gnu/release/build/hdf5-metno-src-*
maturin sdist -m crates/ellipsoid-py/Cargo.toml -o "$out"
MATURIN_PEP517_ARGS="--zig --compatibility manylinux_2_17" \
  "$venv/bin/python" -m pip wheel --disable-pip-version-check --no-cache-dir --no-deps -w "$out" "$out"/ellipsoid-*.tar.gz
auditwheel show "$out"/ellipsoid-*.whl
