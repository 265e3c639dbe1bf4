#!/usr/bin/env bash
# Runs every test of the project on a machine that has only the toolchains (Rust via
# rustup, Python 3.10+, a C compiler): runs the Rust tests (release: the physics tests
# integrate for real), a fixed 60 s fuzzing budget on the scenario parser, builds the
# Python wheel with `pip wheel` into a fresh venv and runs pytest, then the viewer's
# browser tests. Exits non-zero on the first failure.
#
# HDF5 is built from source (HDF5 2.x, linked statically) by the default build: that needs
# CMake >= 3.26. If the system's is older or missing, one comes from PyPI into the venv.
# Installed from Debian if missing: h5dump (hdf5-tools, for the test that reads our files
# with it), Chromium and the DejaVu fonts (the viewer's browser tests, the PNG figures).
set -euo pipefail
cd "$(dirname "$0")/.."
fuzz_seconds="${ELLIPSOID_FUZZ_SECONDS:-60}"

# 1. A fresh venv: the Python test tools, and CMake when the system's cannot build HDF5.
rm -rf .venv
python3 -m venv .venv
pip=(.venv/bin/python -m pip install --quiet --disable-pip-version-check)
# mpmath: reference values of some tests; dask[distributed] and pyarrow: the parameter-study
# tests (a LocalCluster of 2 worker processes; Parquet tables read back).
"${pip[@]}" numpy pytest scipy h5py pandas mypy hypothesis matplotlib websocket-client pillow mpmath "dask[distributed]" pyarrow xarray nbclient nbformat ipykernel
cmake_ok() { command -v cmake >/dev/null && printf '%s\n3.26\n' "$(cmake --version | head -1 | awk '{print $3}')" | sort -V -C -r 2>/dev/null; }
if [ -z "${CMAKE:-}" ] && ! cmake_ok; then
  "${pip[@]}" 'cmake>=3.26'
  export CMAKE="$PWD/.venv/bin/cmake"
fi
if ! command -v h5dump >/dev/null; then
  sudo=""; [ "$(id -u)" = 0 ] || sudo="sudo"
  $sudo apt-get install -y --no-install-recommends hdf5-tools \
    || { $sudo apt-get update && $sudo apt-get install -y --no-install-recommends hdf5-tools; }
fi

# 1b. Headless Chromium for the viewer's browser tests, and a font for the PNG figures
#     (Debian packages; the tests never download a browser).
if ! command -v chromium >/dev/null 2>&1 || [ ! -f /usr/share/fonts/truetype/dejavu/DejaVuSans.ttf ]; then
  sudo=""; [ "$(id -u)" = 0 ] || sudo="sudo"
  $sudo apt-get install -y --no-install-recommends chromium fonts-dejavu-core \
    || { $sudo apt-get update && $sudo apt-get install -y --no-install-recommends chromium fonts-dejavu-core; }
fi

# 2. Rust: formatting and lints first (cheap, and a red CI should say why at once), then
#    every crate but the Python extension (tested below through its wheel).
echo "== cargo fmt --check, cargo clippy"
cargo fmt --all --check
cargo clippy --release --all-targets --features ellipsoid-cli/hdf5 -- -D warnings
echo "== cargo test"
cargo test --release

# 3. Fuzzing: the scenario parser and validation, from the bundled scenarios, for a fixed
#    budget (crashes are saved in target/fuzz/crashes and fail the run).
echo "== fuzz (${fuzz_seconds} s)"
cargo run --release --quiet -p ellipsoid-core --example fuzz_scenario -- --seconds "$fuzz_seconds"

# 4. Python: a wheel built by `pip wheel` (PEP 517 through maturin, HDF5 included),
#    installed in the venv, then pytest. The command-line tool that `cargo test --release`
#    just built is the reference of the parity tests.
echo "== python"
target="${CARGO_TARGET_DIR:-target}"
case "$target" in /*) ;; *) target="$PWD/$target" ;; esac
export ELLIPSOID_CLI="$target/release/ellipsoid"
[ -x "$ELLIPSOID_CLI" ] || cargo build --release -p ellipsoid-cli
export ELLIPSOID_EXPECT_HDF5=1
export ELLIPSOID_EXPECT_BROWSER=1  # installed above: a browser test that cannot find it fails
rm -rf "$target/wheels"
.venv/bin/python -m pip wheel --quiet --disable-pip-version-check --no-deps -w "$target/wheels" ./crates/ellipsoid-py
"${pip[@]}" "$target"/wheels/ellipsoid-*.whl
.venv/bin/python -m pytest -q crates/ellipsoid-py/tests

# 4. The 3-D viewer in a real browser (headless Chromium over the DevTools protocol).
echo "== browser"
.venv/bin/python -m pytest -q tests/browser

echo "all tests passed"
