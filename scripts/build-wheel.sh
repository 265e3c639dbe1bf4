#!/usr/bin/env bash
# Builds the Python wheel for any x86-64 Linux with glibc >= 2.17: maturin compiles and
# links with `zig cc` (the `ziglang` package from PyPI) against glibc 2.17's symbols, and
# the HDF5 C library, built from source by the hdf5-metno-src crate with CMake, is
# compiled by the same `zig cc`. auditwheel then shows the platform tag
# (manylinux_2_17_x86_64, alias manylinux2014_x86_64). Needs Rust (rustup) and Python;
# maturin, ziglang, CMake and auditwheel come from PyPI into the venv.
#
#   scripts/build-wheel.sh [OUT_DIR]      # default: $CARGO_TARGET_DIR/wheels-manylinux or target/...
#   WHEEL_VENV=.venv scripts/build-wheel.sh DIR   # use (and add the tools to) an existing venv
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-${CARGO_TARGET_DIR:-target}/wheels-manylinux}"
venv="${WHEEL_VENV:-.venv-wheel}"
[ -x "$venv/bin/python" ] || python3 -m venv "$venv"
"$venv/bin/python" -m pip install --quiet --disable-pip-version-check 'maturin>=1.9,<2' ziglang 'cmake>=3.26' auditwheel
# maturin runs `python -m ziglang` and the HDF5 build runs `cmake`: both from the venv.
export PATH="$PWD/$venv/bin:$PATH"
export ELLIPSOID_CMAKE="${ELLIPSOID_CMAKE:-$PWD/$venv/bin/cmake}"   # run by scripts/cmake-hdf5
# The wheel's extension is stripped: no debug info to compile (the workspace's release
# profile keeps it for profiling), which makes the build, HDF5's included, about a fifth cheaper.
export CARGO_PROFILE_RELEASE_DEBUG=false
rm -f "$out"/ellipsoid-*.whl
maturin build --release --zig --compatibility manylinux_2_17 -m crates/ellipsoid-py/Cargo.toml -o "$out"
auditwheel show "$out"/ellipsoid-*.whl
