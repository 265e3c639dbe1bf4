#!/usr/bin/env bash
# Runs every test of the project on a machine that has only the toolchains (Rust via
# rustup, Python 3.10+): installs the HDF5 system library, Chromium and the DejaVu fonts
# if missing, runs the Rust tests (release: the physics tests integrate for real), builds
# the Python wheel in a fresh venv and runs pytest, then the viewer's browser tests.
# Exits non-zero on the first failure.
set -euo pipefail
cd "$(dirname "$0")/.."

# 1. System library: HDF5 (the CLI's .h5 output links Debian's libhdf5 dynamically).
if ! pkg-config --exists hdf5 2>/dev/null; then
  sudo=""; [ "$(id -u)" = 0 ] || sudo="sudo"
  $sudo apt-get install -y --no-install-recommends libhdf5-dev pkg-config \
    || { $sudo apt-get update && $sudo apt-get install -y --no-install-recommends libhdf5-dev pkg-config; }
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
cargo test --release --features ellipsoid-cli/hdf5

# 3. Python: the package built from source by pip (PEP 517 through maturin) in a fresh
#    venv, with HDF5 (the library is installed above), then pytest. The command-line tool
#    that `cargo test --release` just built is the reference of the parity tests.
echo "== python"
target="${CARGO_TARGET_DIR:-target}"
case "$target" in /*) ;; *) target="$PWD/$target" ;; esac
export ELLIPSOID_CLI="$target/release/ellipsoid"
[ -x "$ELLIPSOID_CLI" ] || cargo build --release --features ellipsoid-cli/hdf5 -p ellipsoid-cli
export ELLIPSOID_EXPECT_HDF5=1
export ELLIPSOID_EXPECT_BROWSER=1  # installed above: a browser test that cannot find it fails
rm -rf .venv
python3 -m venv .venv
.venv/bin/python -m pip install --quiet --disable-pip-version-check maturin numpy pytest scipy h5py pandas mypy matplotlib websocket-client pillow
.venv/bin/python -m pip install --quiet --disable-pip-version-check ./crates/ellipsoid-py -C maturin.build-args="--features hdf5"
.venv/bin/python -m pytest -q crates/ellipsoid-py/tests

# 4. The 3-D viewer in a real browser (headless Chromium over the DevTools protocol).
echo "== browser"
.venv/bin/python -m pytest -q tests/browser

echo "all tests passed"
