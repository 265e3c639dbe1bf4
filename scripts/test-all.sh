#!/usr/bin/env bash
# Runs every test of the project on a machine that has only the toolchains (Rust via
# rustup, Python 3.10+, a C compiler): runs the Rust tests (release: the physics tests
# integrate for real), a fixed 60 s fuzzing budget on the scenario parser, builds the sdist
# and from it the manylinux Python wheel (scripts/build-wheel.sh), checks the sdist's
# contents, installs the wheel into a venv and runs pytest, and the README's quick start
# in a fresh venv of its own; then the viewer's browser tests, then the documentation's checks: no engineering record in
# the user docs, the tutorial notebooks executed, the gallery current, the API reference
# built. Exits non-zero on the first failure.
#
# HDF5 is built from source (HDF5 2.x, linked statically) by the default build: that needs
# CMake >= 3.26. If the system's is older or missing, one comes from PyPI into the venv.
# Installed from Debian if missing: h5dump (hdf5-tools, for the test that reads our files
# with it), Chromium and the DejaVu fonts (the viewer's browser tests, the PNG figures).
set -euo pipefail
cd "$(dirname "$0")/.."
fuzz_seconds="${ELLIPSOID_FUZZ_SECONDS:-60}"
# Each stage's heading gives the time since the start (s): CI's budget is 30 min.
stage() { echo "== [${SECONDS} s] $1"; }

# Nothing here is profiled or debugged: no debug info to compile and link (the workspace's
# release profile keeps it for profiling; the wheel is built without it anyway).
export CARGO_PROFILE_RELEASE_DEBUG=false

# 1. A fresh venv: CMake first when the system's cannot build HDF5 (the Rust build needs
#    it), then the Python test tools, installed in the background while the Rust stages
#    compile (waited for before the Python stage; its log in target/venv-install.log).
rm -rf .venv
python3 -m venv .venv
pip=(.venv/bin/python -m pip install --quiet --disable-pip-version-check)
cmake_ok() { command -v cmake >/dev/null && printf '%s\n3.26\n' "$(cmake --version | head -1 | awk '{print $3}')" | sort -V -C -r 2>/dev/null; }
if [ -z "${ELLIPSOID_CMAKE:-}" ] && ! cmake_ok; then
  "${pip[@]}" 'cmake>=3.26'
  export ELLIPSOID_CMAKE="$PWD/.venv/bin/cmake"   # run by scripts/cmake-hdf5
fi
# mpmath: reference values of some tests; dask[distributed] and pyarrow: the parameter-study
# tests (a LocalCluster of 2 worker processes; Parquet tables read back).
# nbclient, nbformat, ipykernel, nbconvert: the notebooks executed (tutorials, display tests)
# and rendered; pdoc: the API reference; xarray: Trajectory.to_xarray; ipywidgets:
# ellipsoid.explore.
mkdir -p target
"${pip[@]}" numpy pytest scipy h5py pandas mypy hypothesis matplotlib websocket-client pillow mpmath "dask[distributed]" pyarrow \
  xarray nbclient nbformat ipykernel nbconvert pdoc ipywidgets >target/venv-install.log 2>&1 &
venv_install=$!
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

# 2. The cheap checks first (the user docs, formatting, lints: a red CI should say why at
#    once), then the Rust tests of every crate but the Python extension (tested below
#    through its wheel).
stage "docs: no commit hashes, history of the work or load averages; links resolve"
python3 scripts/check-docs.py
stage "core's modules in layers: no import circle"
python3 scripts/check-layers.py
stage "cargo fmt --check, cargo clippy"
cargo fmt --all --check
cargo clippy --release --all-targets --features ellipsoid-cli/hdf5 -- -D warnings
stage "cargo test"
cargo test --release

# 3. Fuzzing: the scenario parser and validation, from the bundled scenarios, for a fixed
#    budget (crashes are saved in target/fuzz/crashes and fail the run). `cargo test` has
#    built the example with the workspace's features; `cargo run -p ellipsoid-core` would
#    build it again with that crate's alone (3 minutes of a cold CI run).
target="${CARGO_TARGET_DIR:-target}"
case "$target" in /*) ;; *) target="$PWD/$target" ;; esac
stage "fuzz (${fuzz_seconds} s)"
"$target/release/examples/fuzz_scenario" --seconds "$fuzz_seconds"

# 4. Python: the sdist, and the manylinux wheel built from it (scripts/build-wheel.sh:
#    `pip wheel` of the sdist in an isolated build environment, maturin and CMake from PyPI
#    as pyproject.toml asks, compiled by zig cc, HDF5 included: one compile proves the sdist
#    builds from source and gives the wheel). The sdist's contents are checked
#    (scripts/check-sdist.py: every file the build needs, no build output); the wheel is
#    installed in the venv, then pytest. The command-line tool that `cargo test --release`
#    just built is the reference of the parity tests.
stage "python: the sdist, the wheel built from it, pytest"
wait "$venv_install" || { cat target/venv-install.log; echo "installing the Python test tools failed"; exit 1; }
export ELLIPSOID_CLI="$target/release/ellipsoid"
[ -x "$ELLIPSOID_CLI" ] || cargo build --release -p ellipsoid-cli
export ELLIPSOID_EXPECT_HDF5=1
export ELLIPSOID_EXPECT_BROWSER=1  # installed above: a browser test that cannot find it fails
rm -rf "$target/wheels"
WHEEL_VENV=.venv scripts/build-wheel.sh "$target/wheels"
.venv/bin/python scripts/check-sdist.py "$target"/wheels/ellipsoid-*.tar.gz
# (auditwheel's whole report first: `grep -q` would close the pipe on it mid-report.)
tag=$(.venv/bin/auditwheel show "$target"/wheels/ellipsoid-*.whl)
grep -q '"manylinux_2_17_x86_64"' <<<"$tag" \
  || { echo "the wheel is not manylinux_2_17_x86_64: $tag"; exit 1; }
"${pip[@]}" "$target"/wheels/ellipsoid-*.whl
.venv/bin/python -m pytest -q crates/ellipsoid-py/tests

# 4b. A fresh venv installs the wheel built from the sdist (numpy, matplotlib, pandas from
#     PyPI) and runs the README's Python quick start, in a directory of its own.
stage "the README's quick start in a fresh venv"
qs="$target/quickstart"
rm -rf "$qs" && mkdir -p "$qs"
python3 -m venv "$qs/venv"
"$qs/venv/bin/python" -m pip install --quiet --disable-pip-version-check "$target"/wheels/ellipsoid-*.whl matplotlib pandas
.venv/bin/python - "$qs/quickstart.py" <<'EOF_QS'
import re, sys
section = open("README.md", encoding="utf-8").read().split("## Python quick start", 1)[1]
open(sys.argv[1], "w", encoding="utf-8").write(re.findall(r"```python\n(.*?)```", section, re.S)[0])
EOF_QS
ln -s "$PWD/scenarios" "$qs/scenarios"
(cd "$qs" && venv/bin/python quickstart.py)

# 5. The 3-D viewer in a real browser (headless Chromium over the DevTools protocol).
stage "browser"
.venv/bin/python -m pytest -q tests/browser

# 6. The documentation against the installed wheel: every tutorial notebook executed by
#    nbclient (an error or a printed traceback fails; rendered to HTML with its figures in
#    target/site/examples) and their pages in docs/tutorials current, the gallery current (a
#    bundled scenario without an entry fails), the API reference built by pdoc without a
#    warning or an undocumented member and equal to its page docs/api.md.
stage "notebooks, gallery, API reference"
.venv/bin/python scripts/run-notebooks.py --html "$target/site/examples"
.venv/bin/python scripts/run-notebooks.py --check-pages docs/tutorials
.venv/bin/python scripts/gallery.py --check
.venv/bin/python scripts/steady-diagrams.py --check
.venv/bin/python scripts/api-docs.py -o "$target/site/api" --check-markdown docs/api.md

echo "all tests passed in ${SECONDS} s"
