"""The package as installed: public names, docstrings, stubs."""

from __future__ import annotations

import inspect
import subprocess
import sys
from pathlib import Path

import pytest

import ellipsoid


def test_every_public_name_has_a_docstring() -> None:
    missing = []
    for name in ellipsoid.__all__:
        obj = getattr(ellipsoid, name)
        if isinstance(obj, (str, bool, list)):
            continue
        if not (obj.__doc__ or "").strip():
            missing.append(name)
        if inspect.isclass(obj):
            for attr, member in vars(obj).items():
                if not attr.startswith("_") and callable(getattr(member, "__get__", None)) and not (getattr(member, "__doc__", "") or "").strip():
                    missing.append(f"{name}.{attr}")
    assert not missing, missing


def test_column_docstrings_state_units() -> None:
    for name in ellipsoid.COLUMNS:
        doc = getattr(ellipsoid.Trajectory, name).__doc__
        assert name == "mode" or "[" in doc, f"{name}: {doc!r} gives no unit"


def test_exception_tree() -> None:
    assert issubclass(ellipsoid.ScenarioError, (ellipsoid.EllipsoidError, ValueError))
    assert ellipsoid.ScenarioError.__mro__[1:3] == (ellipsoid.EllipsoidError, ValueError)
    assert ellipsoid.ScenarioTypeError.__mro__[1:4] == (ellipsoid.ScenarioError, ellipsoid.EllipsoidError, ValueError)
    assert issubclass(ellipsoid.ScenarioTypeError, TypeError)
    assert ellipsoid.SimulationError.__mro__[1:3] == (ellipsoid.EllipsoidError, RuntimeError)
    assert ellipsoid.OutputError.__mro__[1:3] == (ellipsoid.EllipsoidError, OSError)
    assert ellipsoid.InternalError.__mro__[1:3] == (ellipsoid.EllipsoidError, RuntimeError)
    assert all(c.__module__ == "ellipsoid" for c in (ellipsoid.EllipsoidError, ellipsoid.ScenarioError))


def test_typed_package_ships_stubs() -> None:
    root = Path(ellipsoid.__file__).parent
    assert (root / "py.typed").is_file() and (root / "_ellipsoid.pyi").is_file()


def test_stubs_match_the_module() -> None:
    pytest.importorskip("mypy")
    done = subprocess.run([sys.executable, "-m", "mypy.stubtest", "ellipsoid"], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stdout + done.stderr


def test_build_has_hdf5_when_expected() -> None:
    """scripts/test-all.sh builds with HDF5 and says so, so that a wheel that silently
    lacks it fails instead of skipping the round trip."""
    import os

    if os.environ.get("ELLIPSOID_EXPECT_HDF5") != "1":
        pytest.skip("ELLIPSOID_EXPECT_HDF5 is not set")
    assert ellipsoid.HDF5
