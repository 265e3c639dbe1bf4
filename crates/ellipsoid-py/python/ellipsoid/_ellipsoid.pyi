"""Type stubs of the compiled module `ellipsoid._ellipsoid` (re-exported by `ellipsoid`).

SI units and radians throughout; the unit of every column and argument is in its docstring.
"""

import os
from collections.abc import Iterable, Mapping, Sequence
from typing import Any, ClassVar, Final, Literal, final, overload

import numpy as np
import numpy.typing as npt

__all__ = [
    "COLUMNS",
    "HDF5",
    "EllipsoidError",
    "InternalError",
    "OutputError",
    "Scenario",
    "ScenarioError",
    "SimulationError",
    "Trajectory",
    "__version__",
    "load",
    "simulate",
    "sweep",
]

__version__: Final[str]
#: Whether this build writes HDF5 (`Trajectory.to_hdf5`).
HDF5: Final[bool]
#: Column names of a trajectory, in the CSV file's order.
COLUMNS: Final[list[str]]

_Path = str | os.PathLike[str]
# A scenario value: bool, int, float, str, list/tuple, dict (a table), numpy array or scalar.
_Value = Any
_Table = Mapping[str, Any]
_FloatArray = npt.NDArray[np.float64]

class EllipsoidError(Exception):
    """Base class of every error raised by the ellipsoid package."""

class ScenarioError(EllipsoidError, ValueError):
    """A scenario that cannot be run (file, TOML syntax, key, type, or physical rule)."""

    kind: Literal["io", "syntax", "override", "unknown_key", "missing", "type", "conflict", "invalid"]
    key: str | None
    value: str | None
    rule: str
    source: str
    line: int | None
    column: int | None
    override: str | None

class SimulationError(EllipsoidError, RuntimeError):
    """A run that stopped on an error; `trajectory` holds it up to the stop."""

    status: Literal["painleve", "solver_failure", "chattering", "cancelled"]
    trajectory: Trajectory

class OutputError(EllipsoidError, OSError):
    """A trajectory file could not be written."""

class InternalError(EllipsoidError, RuntimeError):
    """A bug in ellipsoid (a Rust panic caught at the Python boundary)."""

@final
class Scenario:
    """A validated scenario, from a TOML file (`load`) or keyword tables."""

    def __new__(
        cls,
        *,
        body: _Table | None = None,
        initial: _Table | None = None,
        contact: _Table | None = None,
        effects: _Table | None = None,
        solver: _Table | None = None,
        output: _Table | None = None,
        check: _Table | None = None,
        name: str = "<scenario>",
    ) -> Scenario: ...
    @staticmethod
    def from_toml(text: str, name: str = "<string>", **changes: _Value) -> Scenario: ...
    def replace(self, **changes: _Value) -> Scenario: ...
    @property
    def source(self) -> str: ...
    @property
    def stem(self) -> str: ...
    @property
    def text(self) -> str: ...
    @property
    def overrides(self) -> list[str]: ...
    @property
    def t_end(self) -> float:
        """End time of the run [s]."""
    @property
    def sample_times(self) -> _FloatArray:
        """Output times [s]."""
    @property
    def contact_model(self) -> Literal["frictionless", "sliding", "rolling", "coulomb"]: ...
    def __eq__(self, other: object, /) -> bool: ...
    def __copy__(self) -> Scenario: ...
    def __deepcopy__(self, memo: Any, /) -> Scenario: ...
    __hash__: ClassVar[None]  # type: ignore[assignment]

@final
class Trajectory:
    """The samples of a run as read-only numpy columns named like the CSV, and its summary."""

    #: Column names in the CSV file's order.
    columns: ClassVar[list[str]]
    #: Column name -> unit ("1" for `mode`).
    units: ClassVar[dict[str, str]]

    @property
    def t(self) -> _FloatArray:
        """Time [s]."""
    @property
    def x(self) -> _FloatArray:
        """x of the centre of mass G [m]."""
    @property
    def y(self) -> _FloatArray:
        """y of the centre of mass G [m]."""
    @property
    def z(self) -> _FloatArray:
        """Height of G above the plane [m]."""
    @property
    def theta(self) -> _FloatArray:
        """θ, tilt of the symmetry axis [rad]."""
    @property
    def phi(self) -> _FloatArray:
        """φ, precession angle [rad]."""
    @property
    def psi(self) -> _FloatArray:
        """ψ, spin angle [rad]."""
    @property
    def theta_dot(self) -> _FloatArray:
        """θ̇ [rad/s]."""
    @property
    def phi_dot(self) -> _FloatArray:
        """φ̇ [rad/s]."""
    @property
    def psi_dot(self) -> _FloatArray:
        """ψ̇ [rad/s]."""
    @property
    def omega_x(self) -> _FloatArray:
        """Angular velocity, body x [rad/s]."""
    @property
    def omega_y(self) -> _FloatArray:
        """Angular velocity, body y [rad/s]."""
    @property
    def omega_z(self) -> _FloatArray:
        """Angular velocity, body z [rad/s]."""
    @property
    def vx(self) -> _FloatArray:
        """Velocity of G, x [m/s]."""
    @property
    def vy(self) -> _FloatArray:
        """Velocity of G, y [m/s]."""
    @property
    def vz(self) -> _FloatArray:
        """Velocity of G, z [m/s]."""
    @property
    def energy(self) -> _FloatArray:
        """Mechanical energy [J]."""
    @property
    def normal_force(self) -> _FloatArray:
        """Normal force [N]."""
    @property
    def slip_speed(self) -> _FloatArray:
        """Speed of the contact point [m/s]."""
    @property
    def work(self) -> _FloatArray:
        """Work dissipated so far [J]."""
    @property
    def omega_world_x(self) -> _FloatArray:
        """Angular velocity about world x [rad/s]."""
    @property
    def omega_world_y(self) -> _FloatArray:
        """Angular velocity about world y [rad/s]."""
    @property
    def omega_world_z(self) -> _FloatArray:
        """Angular velocity about the vertical, world z [rad/s] (the vertical spin)."""
    @property
    def contact_x(self) -> _FloatArray:
        """x of the contact point on the plane [m]."""
    @property
    def contact_y(self) -> _FloatArray:
        """y of the contact point on the plane [m]."""
    @property
    def drift(self) -> _FloatArray:
        """Relative drift of the scene's conserved quantity (E, or E + W) since t = 0 [1]."""
    @property
    def mode(self) -> npt.NDArray[np.str_]:
        """Contact regime per sample: "frictionless", "sliding" or "rolling"."""
    @property
    def summary(self) -> dict[str, Any]:
        """The command-line tool's summary dict (a fresh copy)."""
    @property
    def status(self) -> Literal["completed", "observed", "lost_contact", "slip_stopped", "painleve", "solver_failure", "chattering", "non_finite", "cancelled"]: ...
    @property
    def message(self) -> str: ...
    @property
    def completed(self) -> bool: ...
    @property
    def events(self) -> list[dict[str, Any]]: ...
    @property
    def scenario(self) -> Scenario: ...
    def __len__(self) -> int: ...
    def to_dict(self) -> dict[str, npt.NDArray[Any]]: ...
    def to_pandas(self) -> Any:
        """A pandas.DataFrame of the columns (needs pandas)."""
    def to_csv(self, path: _Path) -> None: ...
    def to_hdf5(self, path: _Path) -> None: ...
    def save(self, path: _Path) -> None: ...
    @overload
    def view(self, path: None = None, *, title: str | None = None) -> str:
        """The 3-D viewer page (the HTML of `ellipsoid view`), as text."""
    @overload
    def view(self, path: _Path, *, title: str | None = None) -> None:
        """Writes the 3-D viewer page to `path`."""
    def plot(self, panels: str | Sequence[str] | None = None) -> Any:
        """The panels of `ellipsoid plot` as a matplotlib Figure (needs matplotlib)."""

def load(path: _Path, **changes: _Value) -> Scenario: ...
def simulate(scenario: Scenario | _Path, /, **changes: _Value) -> Trajectory: ...
@overload
def sweep(
    scenarios: Iterable[Scenario | _Path],
    workers: int | None = None,
    *,
    summaries_only: Literal[False] = False,
    errors: Literal["raise"] = "raise",
) -> list[Trajectory]: ...
@overload
def sweep(
    scenarios: Iterable[Scenario | _Path],
    workers: int | None = None,
    *,
    summaries_only: Literal[True],
    errors: Literal["raise"] = "raise",
) -> list[dict[str, Any]]: ...
@overload
def sweep(
    scenarios: Iterable[Scenario | _Path],
    workers: int | None = None,
    *,
    summaries_only: bool = False,
    errors: Literal["raise", "return"] = "raise",
) -> list[Any]: ...
