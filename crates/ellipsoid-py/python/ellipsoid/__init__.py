"""Fast, exact simulation of a rigid ellipsoid on a horizontal plane (SI units, radians).

    import ellipsoid
    traj = ellipsoid.simulate("scenarios/nutation.toml", output={"t_end": 1.0})
    traj.t, traj.theta, traj.energy         # numpy float64 arrays [s], [rad], [J]
    traj.summary["drift"]                    # the command-line tool's summary dict
    traj.to_csv("nutation.csv")              # byte-identical to `ellipsoid run -o`

Scenarios come from TOML files (`load`) or keyword arguments mirroring the file's tables
(`Scenario(body=dict(...), contact=dict(model="coulomb", friction=0.3), ...)`); both go
through the same parser, so every check and every message is the command-line tool's.
`Scenario.replace(contact={"friction": 0.2})` (or `**{"contact.friction": 0.2}`) makes
variants for a `sweep`, which runs them in parallel in Rust.

`check(scenario)` returns as a dict what `ellipsoid check` prints (derived quantities,
the state at t = 0); `precision(scenario, quick=True, out="report")` runs the
work–precision study of `ellipsoid precision` and returns a `PrecisionTable` (numpy
columns named like its `precision.csv`, `to_pandas()`), writing the same CSV and plots
when `out` is given.

`study(base, axes)` runs a parameter study — axes over any scenario key, a grid or zipped,
locally on every core or on a `concurrent.futures` executor or a Dask client — and returns
its table as a pandas DataFrame, one row per run (docs/studies.md); `load_study(path)`
reads a study file.

Results follow solve_ivp's conventions where they can: `traj.success`, `traj.nfev`,
`traj.message`, `traj.status_code`, `traj.states` (the state matrix; `traj.y` is G's y),
`traj.t_events` / `traj.y_events` by name, `traj.sol(ts)` the dense interpolant, and
`simulate(scenario, t_eval=ts, method="RK45", rtol=1e-8, atol=1e-10)`. Plots behave as
pandas' (`traj.plot()`: a pyplot figure, its Axes returned). Trajectories and scenarios pickle;
`traj.to_pandas()` is indexed by t, `traj.to_xarray()` and `to_xarray(study_table)` give
xarray Datasets with units as attributes.

`steady(scenario, family="upright", vary={"initial.psi_dot": values})` finds the steady
motions of a family ("upright", "inverted"; for a body of revolution the tilted
"precession" and "rolling-circle", at the scenario's tilt and precession rate, the spin
solved for) and their eigenvalues and critical values (`Steady`: `.values`,
`.eigenvalues`, `.critical`, `.states`, `.to_pandas()`); `linearize(scenario, state=None)`
returns the Jacobian of the reduced dynamics and its coordinates' names
(docs/physics.md, "Steady motions and their stability").

`fit(scenario, data, params={"contact.friction": (0.05, 0.8)}, columns=["theta"])` fits
scenario keys to a measured motion (a DataFrame, a dict of arrays or a CSV file with t [s]
and measured output columns) by weighted least squares and returns a `Fit` with the
estimates, their standard errors and correlation, the residuals and `plot()`
(docs/fitting.md).

Errors: every exception derives from `EllipsoidError`: `ScenarioError` (a ValueError) for
bad input (`ScenarioTypeError`, also a TypeError, for a value of the wrong Python type;
`ScenarioKeyError`, also a KeyError, for a column a Trajectory does not have),
`SimulationError` (a RuntimeError) when `precision`'s reference run fails (a simulation
that stops on an error returns its trajectory with `success` False), `OutputError` (an OSError) for files that cannot be written,
`InternalError` for bugs.

Warnings: a value that is valid but likely a unit slip — `theta = 80` (degrees in a radian
key), `mass = 60` for a 2 × 3 cm egg (grams: a density no solid has), `phi_dot = 1600`
(rpm: a spin energy over 100 times m g L) — is reported by `simulate`, `sweep`,
`check`, `precision` and `steady` as a `PlausibilityWarning` (a UserWarning) and the run
goes on; `warnings.filterwarnings("ignore", category=ellipsoid.PlausibilityWarning)`
silences it (docs/scenarios.md, "Plausibility warnings").
"""

from ellipsoid._ellipsoid import (
    COLUMNS,
    HDF5,
    UNITS,
    EllipsoidError,
    InternalError,
    OutputError,
    PlausibilityWarning,
    PrecisionTable,
    Scenario,
    ScenarioError,
    ScenarioKeyError,
    ScenarioTypeError,
    SimulationError,
    Trajectory,
    __version__,
    check,
    linearize,
    load,
    precision,
    simulate,
    sweep,
)
from ellipsoid._explore import Explorer, explore
from ellipsoid._fit import Fit, fit
from ellipsoid._result import study_to_xarray as to_xarray
from ellipsoid._steady import Steady, steady
from ellipsoid._study import Study, load_study, study

__all__ = [
    "COLUMNS",
    "HDF5",
    "UNITS",
    "EllipsoidError",
    "Explorer",
    "Fit",
    "InternalError",
    "OutputError",
    "PlausibilityWarning",
    "PrecisionTable",
    "Scenario",
    "Steady",
    "Study",
    "ScenarioError",
    "ScenarioKeyError",
    "ScenarioTypeError",
    "SimulationError",
    "Trajectory",
    "__version__",
    "check",
    "explore",
    "fit",
    "linearize",
    "load",
    "load_study",
    "precision",
    "simulate",
    "steady",
    "study",
    "sweep",
    "to_xarray",
]
