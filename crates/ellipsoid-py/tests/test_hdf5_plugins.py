"""HDF5 filter plugins (issue #30): the HDF5 library inside the command-line tool and the
wheel never loads code from a plugin directory, and a file compressed with a filter the
build lacks is refused with a message saying so."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import ellipsoid
from conftest import SCENARIOS

h5py = pytest.importorskip("h5py")
pytestmark = pytest.mark.skipif(not ellipsoid.HDF5, reason="this build writes no HDF5")

PLANTED = r"""
#include <stdio.h>
__attribute__((constructor)) static void planted(void) {
    FILE *f = fopen(MARKER, "w");
    if (f) { fputs("planted code ran\n", f); fclose(f); }
}
"""


def planted_plugin_dir(tmp_path: Path) -> tuple[Path, Path]:
    """A directory holding a shared library whose constructor writes a marker file when it
    is loaded: what a local user could plant in HDF5's default plugin directory."""
    cc = shutil.which("cc") or shutil.which("gcc")
    if cc is None:
        pytest.skip("no C compiler to build the planted library")
    plugins = tmp_path / "plugins"
    plugins.mkdir()
    marker = tmp_path / "planted-ran"
    source = tmp_path / "planted.c"
    source.write_text(PLANTED)
    done = subprocess.run(
        [cc, "-shared", "-fPIC", f'-DMARKER="{marker}"', "-o", str(plugins / "libplanted.so"), str(source)],
        capture_output=True,
        text=True,
    )
    assert done.returncode == 0, done.stderr
    return plugins, marker


def gzip_trajectory(tmp_path: Path) -> Path:
    """A trajectory written by `to_hdf5`, then its `theta` rewritten by h5py with gzip."""
    path = tmp_path / "gzip.h5"
    ellipsoid.simulate(str(SCENARIOS / "tippe-top.toml"), output={"t_end": 0.05}).to_hdf5(path)
    with h5py.File(path, "r+") as f:
        theta = f["theta"][()]
        units = f["theta"].attrs["units"]
        del f["theta"]
        f.create_dataset("theta", data=theta, compression="gzip")
        f["theta"].attrs["units"] = units
    return path


@pytest.mark.parametrize("command", ["view", "plot"])
def test_a_gzip_dataset_is_refused_and_no_plugin_runs(cli: Path, tmp_path: Path, command: str) -> None:
    plugins, marker = planted_plugin_dir(tmp_path)
    data = gzip_trajectory(tmp_path)
    out = tmp_path / ("v.html" if command == "view" else "f.svg")
    env = dict(os.environ, HDF5_PLUGIN_PATH=str(plugins))
    done = subprocess.run([str(cli), command, str(data), "-o", str(out), "-q"], capture_output=True, text=True, env=env)
    assert not marker.exists(), "HDF5 loaded a library from its plugin directory"
    assert done.returncode == 2, done.stderr
    assert "the dataset `theta` is compressed with a filter this build lacks (deflate (gzip))" in done.stderr
    # No path of the build tree (HDF5's default plugin directory was one) in the message.
    assert all(part not in done.stderr for part in ("lib/plugin", "/target/", "hdf5-metno-src", "HDF5_PLUGIN_PATH"))
    assert not out.exists()


def test_the_python_module_loads_no_plugin(tmp_path: Path) -> None:
    """The module turns plugin loading off when it is imported: writing HDF5 from it with a
    planted library on HDF5_PLUGIN_PATH runs nothing, and the planted path is gone."""
    plugins, marker = planted_plugin_dir(tmp_path)
    code = f"""
import ellipsoid
t = ellipsoid.simulate({str(SCENARIOS / "tippe-top.toml")!r}, output={{"t_end": 0.05}})
t.to_hdf5({str(tmp_path / "t.h5")!r})
assert ellipsoid._ellipsoid._hdf5_plugins() == (False, 0), ellipsoid._ellipsoid._hdf5_plugins()
"""
    env = dict(os.environ, HDF5_PLUGIN_PATH=str(plugins))
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env)
    assert done.returncode == 0, done.stderr
    assert not marker.exists()


@pytest.mark.parametrize("artifact", ["command-line tool", "Python module"])
def test_no_build_path_is_compiled_in(request: pytest.FixtureRequest, artifact: str) -> None:
    """Neither HDF5's default plugin directory (a directory inside the build tree) nor its
    configuration summary (with the install prefix) is in the binaries a user runs
    (scripts/cmake-hdf5 configures HDF5 so)."""
    if artifact == "command-line tool":
        path = request.getfixturevalue("cli")
    else:
        path = Path(ellipsoid._ellipsoid.__file__)
    data = path.read_bytes()
    for needle in (b"lib/plugin", b"Installation point:"):
        assert needle not in data, f"{needle!r} is compiled into the {artifact} ({path})"
