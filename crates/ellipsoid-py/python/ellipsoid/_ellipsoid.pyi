"""Type stubs of the compiled module `ellipsoid._ellipsoid` (re-exported by `ellipsoid`).

SI units and radians throughout; the unit of every column and argument is in its docstring.
"""

import os
import pathlib
from collections.abc import Iterable, Mapping, Sequence
from typing import Any, ClassVar, Final, Literal, SupportsIndex, final, overload

import numpy as np
import numpy.typing as npt

__all__ = [
    "COLUMNS",
    "UNITS",
    "HDF5",
    "EllipsoidError",
    "InternalError",
    "OutputError",
    "PlausibilityWarning",
    "PrecisionTable",
    "Scenario",
    "ScenarioError",
    "Study",
    "ScenarioKeyError",
    "ScenarioTypeError",
    "SimulationError",
    "Trajectory",
    "__version__",
    "_PANELS",
    "_argument_error",
    "_hdf5_plugins",
    "_study_workers",
    "check",
    "linearize",
    "load",
    "make_study",
    "precision",
    "simulate",
    "steady_raw",
    "steady_start",
    "sweep",
]

__version__: Final[str]
#: Whether this build writes HDF5 (`Trajectory.to_hdf5`).
HDF5: Final[bool]
#: Column names of a trajectory, in the CSV file's order (a body with contact spheres
#: adds five per surface after them: `Trajectory.columns`).
COLUMNS: Final[list[str]]
#: Column name -> unit of `COLUMNS` ("1" for `mode`).
UNITS: Final[dict[str, str]]
#: The figure's panels as JSON, declared once for `ellipsoid plot` and `Trajectory.plot`.
_PANELS: Final[str]

def _study_workers(workers: Any = None) -> int:
    """`study`'s workers checked as `sweep`'s: 0 (one per CPU) or 1 to 4 per CPU (at least 8)."""
def _argument_error(key: str, value: str | None, rule: str, wrong_type: bool = False, source: str = "study") -> ScenarioError:
    """The ScenarioError (ScenarioTypeError if `wrong_type`) for a bad argument of `source`."""
def _hdf5_plugins() -> tuple[bool, int]:
    """Whether HDF5 may load plugins, and how many plugin directories it searches: (False, 0)."""

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
    #: Every independent error of the scenario, in file order (this one alone if it is the only one).
    errors: list[ScenarioError]

class ScenarioTypeError(ScenarioError, TypeError):
    """A ScenarioError for a Python value of a type a scenario cannot hold, or an argument of the wrong type."""

class ScenarioKeyError(ScenarioError, KeyError):
    """A ScenarioError (and a KeyError) for a name that is not there: a column of a Trajectory (`traj["nope"]`)."""

class SimulationError(EllipsoidError, RuntimeError):
    """A run that stopped on an error; `trajectory` holds it up to the stop.

    From `precision`: the reference run did not finish cleanly; `trajectory` holds its
    summary (no samples)."""

    status: Literal["painleve", "inconsistent_contact", "several_contacts", "solver_failure", "chattering", "non_finite", "below_plane", "cancelled"]
    trajectory: Trajectory

class OutputError(EllipsoidError, OSError):
    """A trajectory file could not be written."""

class InternalError(EllipsoidError, RuntimeError):
    """A bug in ellipsoid (a Rust panic caught at the Python boundary)."""

class PlausibilityWarning(UserWarning):
    """A scenario value that is valid but likely a unit slip (an angle beyond 2π in a
    radian key, a density outside 10 to 3e4 kg/m³, an initial spin energy above
    100 m g L). Issued by simulate, sweep, check, precision and steady; silence it with
    `warnings.filterwarnings("ignore", category=ellipsoid.PlausibilityWarning)`."""

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
        **unknown: _Table,
    ) -> Scenario: ...
    @staticmethod
    def from_toml(text: str, name: str = "<string>", **changes: _Value) -> Scenario: ...
    def replace(self, **changes: _Value) -> Scenario: ...
    def get(self, key: str, default: Any = None) -> Any:
        """The document's value at the key path `key` (after its changes), or `default` when it does not set it."""
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
    def __reduce__(self) -> tuple[Any, tuple[str, str, list[str]]]: ...
    @staticmethod
    def _from_parts(text: str, source: str, overrides: list[str]) -> Scenario: ...
    def __copy__(self) -> Scenario: ...
    def __deepcopy__(self, memo: Any, /) -> Scenario: ...
    __hash__: ClassVar[None]  # type: ignore[assignment]

@final
class Trajectory:
    """The samples of a run as read-only numpy columns named like the CSV, and its summary."""

    @property
    def columns(self) -> list[str]:
        """Column names in the CSV file's order: `COLUMNS`, and for a body with contact spheres five per surface after them."""
    def __getitem__(self, key: str, /) -> _FloatArray | npt.NDArray[np.str_]:
        """The column called `key` (any of `columns`, the per-surface ones too, and `mode`); KeyError otherwise."""
    @property
    def units(self) -> dict[str, str]:
        """Column name -> unit ("1" for `mode`)."""

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
    def gap(self) -> _FloatArray:
        """Height of the body's lowest point above the plane [m] (0 in contact)."""
    @property
    def mode(self) -> npt.NDArray[np.str_]:
        """Contact regime per sample: "frictionless", "sliding", "rolling", "flight" or "two_contacts"; with contact spheres, the surfaces in contact after `@` ("sliding@stem")."""
    @property
    def summary(self) -> dict[str, Any]:
        """The command-line tool's summary dict (a fresh copy)."""
    @property
    def status(self) -> Literal["completed", "observed", "lost_contact", "slip_stopped", "painleve", "inconsistent_contact", "several_contacts", "solver_failure", "chattering", "non_finite", "below_plane", "cancelled"]: ...
    @property
    def message(self) -> str: ...
    @property
    def completed(self) -> bool: ...
    @property
    def events(self) -> list[dict[str, Any]]: ...
    @property
    def scenario(self) -> Scenario: ...
    @property
    def success(self) -> bool:
        """Whether the run reached t_end or stopped at an outcome (solve_ivp's `success`)."""
    @property
    def status_code(self) -> Literal[-1, 0, 1]:
        """solve_ivp's integer status: 0 reached t_end, 1 a terminal event, -1 failed."""
    @property
    def nfev(self) -> int:
        """Right-hand-side evaluations."""
    @property
    def states(self) -> npt.NDArray[np.float64]:
        """The state matrix, shape (n_states, n_t), rows named by `state_names` (`y` is G's y)."""
    #: Row names of `states`.
    state_names: ClassVar[list[str]]
    @property
    def t_events(self) -> dict[str, _FloatArray]:
        """Event times [s] per observable name and built-in event kind."""
    @property
    def y_events(self) -> dict[str, npt.NDArray[np.float64]]:
        """States at the events, (n_events, n_states) per name of `t_events`."""
    @property
    def _observables(self) -> list[str]: ...
    def sol(self, t: float | npt.ArrayLike) -> Trajectory:
        """The dense interpolant at times `t` [s] (a rerun with them as output times)."""
    def __reduce__(self) -> tuple[Any, tuple[Any, ...]]: ...
    @staticmethod
    def _from_pickle(scenario: Scenario, values: bytes, modes: list[str], summary: str, status: str, sections: list[tuple[bytes, list[str]]] = ...) -> Trajectory: ...
    def __len__(self) -> int: ...
    def to_dict(self) -> dict[str, npt.NDArray[Any]]: ...
    def to_pandas(self) -> Any:
        """A pandas.DataFrame indexed by t [s], units in `attrs` (needs pandas)."""
    def to_xarray(self) -> Any:
        """An xarray.Dataset over t [s], units as attributes (needs xarray)."""
    def power_law(self, column: str, window: tuple[float, float], t0: float | tuple[float, float] | None = None) -> dict[str, Any]:
        """The power law |y| = A (t0 - t)^p of a column over t0 - t in `window` [s]."""
    def to_csv(self, path: _Path) -> None: ...
    def to_hdf5(self, path: _Path) -> None: ...
    def save(self, path: _Path) -> None: ...
    @overload
    def view(self, path: None = None, *, title: str | None = None, columns: str | Sequence[str] | None = None) -> str:
        """The 3-D viewer page (the HTML of `ellipsoid view`), as text that Jupyter displays."""
    @overload
    def view(self, path: _Path, *, title: str | None = None, columns: str | Sequence[str] | None = None) -> os.PathLike[str]:
        """Writes the 3-D viewer page to `path`; Jupyter displays the file."""
    def _repr_html_(self) -> str: ...
    def animate(self, path: _Path, *, width: SupportsIndex = 480, height: SupportsIndex = 360, fps: float = 25.0, speed: float = 1.0) -> int:
        """Writes the run as an animated GIF (no browser needed), or MP4 for a `.mp4` path (needs ffmpeg); returns the frame count."""
    def plot(self, panels: str | Sequence[str] | None = None, *, columns: str | Sequence[str] | None = None, ax: Any = None) -> Any:
        """The panels of `ellipsoid plot`, or any columns, on a pyplot figure (or into `ax`); the Axes, or a numpy array of Axes for several (needs matplotlib)."""
    @property
    def sections(self) -> dict[str, dict[str, _FloatArray | npt.NDArray[np.str_]]]:
        """The points of each Poincaré section (`[[section]]`): name → a dict of read-only numpy arrays named like the columns (`mode` a str array), one element per crossing, in time order."""
    def plot_section(self, name: str, x: str, y: str, ax: Any = None, wrap: str | Sequence[str] | None = None) -> Any:
        """Section `name`'s column `y` against column `x`, one marker per crossing, on a pyplot figure (or into `ax`), the angle columns `wrap` names modulo 2π; the Axes (needs matplotlib)."""

@final
class Study:
    """A parameter study ready to run: a base scenario, axes over its keys, the outcomes to
    record (docs/studies.md). `Study.load(path)` reads a study file; `ellipsoid.study(...)`
    runs one and returns its table as a pandas DataFrame. Picklable (as JSON)."""

    @staticmethod
    def load(path: _Path) -> Study:
        """Reads a study file; its `base` path is relative to the file."""
    @staticmethod
    def from_json(text: str) -> Study:
        """A study from `to_json()`'s text."""
    def to_json(self) -> str:
        """The study as JSON (what pickling sends to workers)."""
    def __reduce__(self) -> tuple[Any, tuple[str]]: ...
    def replace(self, base: Scenario | _Path | None = None, outcomes: _Table | None = None) -> Study:
        """This study with another base scenario and/or outcomes."""
    def __len__(self) -> int: ...
    @property
    def source(self) -> str:
        """The study file, or "ellipsoid.study"."""
    @property
    def columns(self) -> list[str]:
        """Column headers of the table, `name [unit]`."""
    @property
    def types(self) -> list[Literal["int", "float", "text"]]:
        """Each column's type."""
    @property
    def nullable(self) -> list[bool]:
        """Whether each column may hold no value (None) in some rows."""
    @property
    def units(self) -> dict[str, str | None]:
        """Header -> SI unit (None for names and counts)."""
    def point(self, index: SupportsIndex) -> tuple[list[str], str]:
        """The `key=value` overrides and the key (hash of the resolved scenario) of point `index`."""
    def run(
        self, start: SupportsIndex = 0, stop: SupportsIndex | None = None, threads: SupportsIndex | None = None, journal: _Path | None = None
    ) -> list[tuple[Any, ...]]:
        """Runs points `start` to `stop` (exclusive) without the GIL; their rows in point order."""
    def _warn_plausibility(self) -> None:
        """Issues the study's plausibility warnings, each once (`ellipsoid.study` calls it before running)."""
    def write(self, path: _Path, rows: list[tuple[Any, ...]]) -> None:
        """Writes rows from `run` as the table at `path` (.csv, .h5; .parquet if built in), atomically."""
    def write_bytes(self, path: _Path, data: bytes) -> None:
        """Writes `data` (pandas' Parquet table) at `path` atomically, refusing a link, directory or device there."""

def make_study(base: Scenario | _Path, axes: Mapping[str | tuple[str, ...], Any], outcomes: _Table | None = None, combine: Literal["grid", "zip"] | None = None) -> Study:
    """A study from Python arguments (what `ellipsoid.study` calls)."""

@final
class PrecisionTable:
    """The table of a work–precision study: one row per setting, read-only numpy columns
    named and ordered like the `precision.csv` of `ellipsoid precision`."""

    #: Column names in the CSV file's order.
    columns: ClassVar[list[str]]

    @property
    def scene(self) -> npt.NDArray[np.str_]:
        """The scenario's name, per row."""
    @property
    def t_end(self) -> _FloatArray:
        """Simulated time of every run [s]."""
    @property
    def measure(self) -> npt.NDArray[np.str_]:
        """The error measure: "period" or "final_state"."""
    @property
    def method(self) -> npt.NDArray[np.str_]:
        """ "rk4", "dopri5" or "dop853"."""
    @property
    def setting(self) -> npt.NDArray[np.str_]:
        """ "h=1e-4" (RK4) or "rtol=1e-10"."""
    @property
    def h(self) -> _FloatArray:
        """RK4's fixed step [s]; NaN for the adaptive methods."""
    @property
    def rtol(self) -> _FloatArray:
        """Relative tolerance [1]; NaN for RK4."""
    @property
    def atol(self) -> _FloatArray:
        """Absolute tolerance [1]; NaN for RK4."""
    @property
    def status(self) -> npt.NDArray[np.str_]:
        """How each run ended (the summary's status name)."""
    @property
    def t_final(self) -> _FloatArray:
        """Time at which the run ended [s]."""
    @property
    def error(self) -> _FloatArray:
        """The headline error [1] (inf where it could not be measured)."""
    @property
    def period_error(self) -> _FloatArray:
        """|T_run − T|/T [1] (measure "period"); NaN otherwise."""
    @property
    def state_error(self) -> _FloatArray:
        """Final-state error against the reference run [1]; NaN for measure "period"."""
    @property
    def energy_drift(self) -> _FloatArray:
        """Relative drift of E (conservative scenes) or E + W [1]."""
    @property
    def invariant_drift(self) -> _FloatArray:
        """Largest relative drift of the conserved invariants [1]."""
    @property
    def wall_time_median_s(self) -> _FloatArray:
        """Median wall time of the timed runs [s]."""
    @property
    def wall_time_min_s(self) -> _FloatArray:
        """Shortest wall time of the timed runs [s]."""
    @property
    def repeats(self) -> npt.NDArray[np.int64]:
        """Timed runs made of each setting."""
    @property
    def rhs_evals(self) -> npt.NDArray[np.int64]:
        """Right-hand-side evaluations of the integrator."""
    @property
    def steps(self) -> npt.NDArray[np.int64]:
        """Accepted steps."""
    @property
    def rejected(self) -> npt.NDArray[np.int64]:
        """Rejected steps."""
    @property
    def reference(self) -> dict[str, Any]:
        """What the errors are measured against (`measure`, `description`, `status`, and
        `period` [s] … or `rtol`, `uncertainty`, `t_final` [s])."""
    @property
    def summary(self) -> str:
        """The table and the cheapest settings, as `ellipsoid precision` prints them."""
    @property
    def notes(self) -> list[str]: ...
    def __len__(self) -> int: ...
    def to_dict(self) -> dict[str, npt.NDArray[Any]]: ...
    def to_pandas(self) -> Any:
        """A pandas.DataFrame of the columns (needs pandas)."""
    def to_csv(self, path: _Path) -> None: ...
    def write(self, dir: _Path) -> list[pathlib.Path]: ...

def load(path: _Path, **changes: _Value) -> Scenario: ...
def simulate(
    scenario: Scenario | _Path,
    /,
    *,
    t_eval: npt.ArrayLike | None = None,
    method: Literal["RK45", "DOP853", "RK4", "dopri5", "dop853", "rk4"] | str | None = None,
    rtol: float | None = None,
    atol: float | None = None,
    **changes: _Value,
) -> Trajectory:
    """Runs a scenario; `t_eval` output times [s], `method` scipy's or the scenario's name, `rtol`/`atol` solver.rtol/solver.atol (overriding the scenario's)."""
def check(scenario: Scenario | _Path, /, **changes: _Value) -> dict[str, Any]:
    """What `ellipsoid check` prints, as a dict (SI units, radians)."""
def precision(
    scenario: Scenario | _Path,
    /,
    *,
    t_end: float | None = None,
    quick: bool = False,
    repeats: SupportsIndex | None = None,
    out: _Path | None = None,
    **changes: _Value,
) -> PrecisionTable:
    """The work–precision study of `ellipsoid precision`; `out` also writes its CSV and plots."""
@overload
def sweep(
    scenarios: Iterable[Scenario | _Path],
    workers: SupportsIndex | None = None,
    *,
    summaries_only: Literal[False] = False,
    errors: Literal["raise"] = "raise",
) -> list[Trajectory]: ...
@overload
def sweep(
    scenarios: Iterable[Scenario | _Path],
    workers: SupportsIndex | None = None,
    *,
    summaries_only: Literal[True],
    errors: Literal["raise"] = "raise",
) -> list[dict[str, Any]]: ...
@overload
def sweep(
    scenarios: Iterable[Scenario | _Path],
    workers: SupportsIndex | None = None,
    *,
    summaries_only: bool = False,
    errors: Literal["raise", "return"] = "raise",
) -> list[Any]: ...

def steady_raw(
    scenario: Scenario | _Path,
    family: str,
    key: str | None = None,
    values: list[float] | None = None,
    solve: str = "spin",
) -> dict[str, Any]:
    """The arrays behind `ellipsoid.steady` (use that)."""
def steady_start(
    scenario: Scenario | _Path,
    family: str,
    mode: int,
    epsilon: float,
    key: str | None = None,
    value: float | None = None,
    solve: str = "spin",
) -> Scenario:
    """The scenario behind `Steady.scenario` (use that)."""
def linearize(scenario: Scenario | _Path, state: Sequence[float] | None = None) -> tuple[npt.NDArray[np.float64], list[str]]:
    """The Jacobian (5 × 5) of the reduced dynamics (ζ·t1, ζ·t2, ω1, ω2, ω3) of `scenario` at
    `state` = (ζ1, ζ2, ζ3, ω1, ω2, ω3) (world up and ω in body axes), or at the scenario's
    initial state, and the coordinates' names (docs/physics.md, "Steady motions and their stability")."""
