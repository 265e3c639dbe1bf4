"""`ellipsoid.fit`: scenario parameters fitted to a measured motion by weighted least
squares (docs/fitting.md).

The model of a measured column y_c at the data's times t_i is the run's column at those
times (`simulate(..., t_eval=t)`: the dense output, no interpolation of samples). The fit
minimises ½ Σ_c Σ_i ((model_c(t_i; p) − y_c,i) / σ_c,i)² over the parameters p inside their
bounds with scipy's `least_squares` (trust-region reflective, on the parameters scaled to
[0, 1] by their bounds). The Jacobian of the residuals is taken by central differences of
runs with the same solver settings (one-sided, second order, at a bound): 2 k runs for k
parameters. The standard errors come from that Jacobian at the optimum: the covariance
(JᵀJ)⁻¹, times the reduced χ² (RSS / (m − k)) unless `sigma` was given (then absolute, as
scipy's `curve_fit(absolute_sigma=True)`).
"""

from __future__ import annotations

import csv
import math
import os
import re
import warnings
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from ellipsoid._ellipsoid import Scenario, SimulationError, Trajectory, _argument_error, load, simulate
from ellipsoid._plot import _names
from ellipsoid._steady import _index

#: Error messages name this source.
_SOURCE = "fit"
#: Relative step of the central differences, of max(|p|, 1e-3 (hi − lo)): for runs accurate
#: to ε the error is about step² + ε / step, 1e-8 at step 1e-4 and ε 1e-12.
_STEP = 1e-4
#: Most data rows read (a bound on memory and on the runs' output).
MAX_ROWS = 1_000_000
#: Most parameters fitted at once.
MAX_PARAMS = 32
#: A header's unit suffix, as our CSV writes it: `theta [rad]`.
_UNIT = re.compile(r"\s*\[[^\]]*\]\s*$")


def _bad(key: str, value: Any, rule: str, wrong_type: bool = False, source: str = _SOURCE) -> Exception:
    """The ScenarioError (ScenarioTypeError if `wrong_type`) naming `key`, as every input
    error of the package; `source` names the call."""
    shown = None if wrong_type else repr(value)[:60]
    return _argument_error(key, shown, rule, wrong_type, source)


def _read_csv(path: str | os.PathLike[str]) -> dict[str, list[str]]:
    """The columns of a CSV file by header (a unit suffix ` [unit]` dropped; lines starting
    with `#` skipped), as text."""
    name = os.fspath(path)
    try:
        with open(name, newline="", encoding="utf-8") as f:
            rows = [r for r in csv.reader(line for line in f if not line.lstrip().startswith("#"))]
    except (OSError, UnicodeDecodeError) as e:
        raise _bad("data", name, f"cannot be read as a CSV file: {e}") from e
    if not rows:
        raise _bad("data", name, "the CSV file has no header row")
    header = [_UNIT.sub("", h).strip() for h in rows[0]]
    body = rows[1:]
    if len(body) > MAX_ROWS:
        raise _bad("data", name, f"more than {MAX_ROWS} rows")
    cols: dict[str, list[str]] = {h: [] for h in header}
    for r, row in enumerate(body, start=2):
        if len(row) != len(header):
            raise _bad(f"data row {r}", ",".join(row)[:60], f"has {len(row)} fields, the header {len(header)}")
        for h, cell in zip(header, row):
            cols[h].append(cell)
    return cols


def _table(data: Any) -> dict[str, Any]:
    """`data` as columns by name: a pandas DataFrame (t a column, or its index named t as
    `Trajectory.to_pandas` makes it), a mapping of arrays, or a CSV file's path."""
    if isinstance(data, (str, os.PathLike)):
        return _read_csv(data)
    if hasattr(data, "columns") and hasattr(data, "index"):  # a pandas DataFrame
        cols = {_UNIT.sub("", str(c)).strip(): data[c].to_numpy() for c in data.columns}
        if "t" not in cols and str(getattr(data.index, "name", "")).split(" [")[0] == "t":
            cols = {"t": np.asarray(data.index), **cols}
        return cols
    if isinstance(data, Mapping):
        return {str(k): v for k, v in data.items()}
    raise _bad("data", data, f"expected a pandas DataFrame, a dict of arrays or a CSV file's path, found {type(data).__name__}", True)


def _numbers(name: str, values: Any) -> np.ndarray:
    """A data column as finite float64 values, else the error naming the column and row."""
    try:
        seq = list(values)
    except TypeError as e:
        raise _bad(f"data[{name!r}]", values, "expected a 1-D sequence of numbers", True) from e
    if len(seq) > MAX_ROWS:
        raise _bad(f"data[{name!r}]", len(seq), f"more than {MAX_ROWS} rows")
    try:
        out = np.asarray(seq, dtype=float)
        if out.ndim == 1 and np.all(np.isfinite(out)) and not any(isinstance(v, (bool, np.bool_)) for v in seq):
            return out
    except (TypeError, ValueError):
        pass
    out = np.empty(len(seq))
    for i, v in enumerate(seq):
        try:
            if isinstance(v, (bool, np.bool_)):
                raise ValueError
            out[i] = float(v)
        except (TypeError, ValueError):
            raise _bad(f"data[{name!r}] row {i}", v, "not a number: a measured column holds numbers only") from None
        if not math.isfinite(out[i]):
            raise _bad(f"data[{name!r}] row {i}", v, "not finite: remove the row (the data's times may have gaps)")
    return out


def _params(scenario: Scenario, params: Any, source: str = _SOURCE) -> tuple[list[str], np.ndarray, np.ndarray, np.ndarray]:
    """The keys, their starting values (the scenario's own) and bounds; `source` (fit,
    explore) names the call in messages."""
    if not isinstance(params, Mapping) or not params:
        raise _bad("params", params, "expected a non-empty dict {key: (low, high)}", not isinstance(params, Mapping), source=source)
    if len(params) > MAX_PARAMS:
        raise _bad("params", len(params), f"at most {MAX_PARAMS} parameters", source=source)
    keys, start, lo, hi = [], [], [], []
    for key, bounds in params.items():
        if not isinstance(key, str):
            raise _bad("params", key, f"a key is a str, found {type(key).__name__}", True, source=source)
        try:
            low, high = (float(b) for b in bounds)
        except (TypeError, ValueError):
            raise _bad(f"params[{key!r}]", bounds, "expected (low, high), two numbers", source=source) from None
        if not (math.isfinite(low) and math.isfinite(high) and low < high):
            raise _bad(f"params[{key!r}]", bounds, "expected finite bounds with low < high", source=source)
        value = scenario.get(key)
        if value is None:
            raise _bad(f"params[{key!r}]", bounds, "the scenario does not set this key: its value there is the starting value (set it, or use the twin the scenario sets, e.g. initial.theta_deg)", source=source)
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise _bad(f"params[{key!r}]", value, "the scenario's value is not a number", source=source)
        if not low <= value <= high:
            raise _bad(f"params[{key!r}]", bounds, f"the scenario's value {value!r}, the starting value, is outside the bounds", source=source)
        keys.append(key)
        start.append(float(value))
        lo.append(low)
        hi.append(high)
    return keys, np.array(start), np.array(lo), np.array(hi)


class Fit:
    """The result of `ellipsoid.fit`.

    `params` and `stderr`: dicts by key, the estimates and their standard errors (from the
    Jacobian at the optimum; inf for a parameter the data do not determine). `correlation`
    and `covariance`: arrays in the order of `params`. `residuals`: data − model at the
    data's times, a dict by column. `chi2` (Σ of the squared weighted residuals), `dof`
    (m − k), `success`, `message`, `nfev` (runs made, the Jacobian's too), `scenario` (the
    scenario at the estimates), `trajectory` (its run at the data's times), `t` and `data`
    (the measured columns), `warnings` (events that changed within a difference step)."""

    def __init__(self, **fields: Any) -> None:
        self.__dict__.update(fields)

    params: dict[str, float]
    """The estimates by key, in the order given."""
    stderr: dict[str, float]
    """Their standard errors by key (inf where the data do not determine a parameter)."""
    correlation: np.ndarray
    """The estimates' correlation matrix, rows and columns in the order of `params`."""
    covariance: np.ndarray
    """Their covariance matrix, in the order of `params` (units: those of the keys)."""
    residuals: dict[str, np.ndarray]
    """Data − model at the data's times, by column (the column's unit)."""
    chi2: float
    """Σ of the squared weighted residuals at the estimates."""
    dof: int
    """Degrees of freedom: measured values − parameters."""
    success: bool
    """Whether the least-squares solver converged."""
    message: str
    """The solver's message, and what limits the standard errors (a bound, a singular Jacobian)."""
    nfev: int
    """Runs made, the Jacobian's included."""
    scenario: Scenario
    """The scenario at the estimates."""
    trajectory: Trajectory
    """Its run, sampled at the data's times."""
    t: np.ndarray
    """The data's times [s]."""
    data: dict[str, np.ndarray]
    """The measured columns by name."""
    warnings: list[str]
    """Parameters whose difference steps changed the events before the data's last time
    (there the derivative, and the standard error, is not defined)."""

    def __repr__(self) -> str:
        est = ", ".join(f"{k} = {v:.6g} ± {self.stderr[k]:.2g}" for k, v in self.params.items())
        return f"<Fit {'converged' if self.success else 'not converged'}: {est}; χ² = {self.chi2:.4g}, dof {self.dof}, {self.nfev} runs>"

    def plot(self, columns: str | Sequence[str] | None = None) -> Any:
        """Data (points), fit (line) and residuals (below) of each column against t [s], in a
        new pyplot figure (shown once in Jupyter, as pandas' plots are); returns the numpy
        array of its Axes, two rows per column."""
        from ellipsoid._plot import _figure

        names = list(self.data) if columns is None else _names("columns", columns)
        for n in names:
            if n not in self.data:
                raise _bad("columns", n, f"not a fitted column (fitted: {', '.join(self.data)})")
        fig = _figure(figsize=(8, 3.2 * len(names)), layout="constrained")
        axes = fig.subplots(2 * len(names), 1, sharex=True, height_ratios=[3, 1] * len(names), squeeze=False)[:, 0]
        unit = self.trajectory.units
        for k, n in enumerate(names):
            top, low = axes[2 * k], axes[2 * k + 1]
            top.plot(self.t, self.data[n], ".", ms=3, color="0.35", label="data")
            top.plot(self.t, self.data[n] - self.residuals[n], "-", color="#1f77b4", lw=1.4, label="fit")
            top.set_ylabel(f"{n} [{unit[n]}]")
            top.legend(loc="best", fontsize=8)
            top.grid(alpha=0.3)
            low.plot(self.t, self.residuals[n], ".", ms=2, color="#d62728")
            low.axhline(0.0, color="0.5", lw=0.8)
            low.set_ylabel(f"data − fit [{unit[n]}]", fontsize=8)
            low.grid(alpha=0.3)
        axes[-1].set_xlabel("t [s]")
        axes[0].set_title(", ".join(f"{k} = {v:.5g} ± {self.stderr[k]:.2g}" for k, v in self.params.items()), fontsize=9)
        return axes


def fit(
    scenario: Scenario | str | os.PathLike[str],
    data: Any,
    params: Mapping[str, tuple[float, float]],
    columns: str | Sequence[str] | None = None,
    sigma: float | Mapping[str, Any] | None = None,
    *,
    method: str | None = None,
    rtol: float | None = None,
    atol: float | None = None,
    max_nfev: int = 200,
    step: float = _STEP,
) -> Fit:
    """Fits scenario keys to a measured motion by weighted least squares (docs/fitting.md).

    `data`: the measurements, a pandas DataFrame (t a column, or its index as
    `Trajectory.to_pandas` makes it), a dict of arrays, or a CSV file's path (headers may
    carry units, `theta [rad]`), with a column `t` [s] (strictly increasing, within
    [0, t_end] of the scenario; any sampling, gaps allowed) and the measured output columns
    in SI units. `params`: {key: (low, high)}, any numeric key the scenario sets (the
    override grammar's names, `"contact.friction"`, `"initial.psi_dot"`,
    `"body.inertia[0]"`), its value in the scenario starting the fit. `columns`: the data's
    columns to fit (default: all but t). `sigma`: the measurement errors, a number or a dict
    by column of numbers or arrays; given, the standard errors are absolute, else scaled by
    the reduced χ². `method`, `rtol`, `atol`: the runs' solver, as `simulate`'s. `step`: the
    relative step of the Jacobian's differences. Bad input raises ScenarioError naming the
    key, column or row before the fit starts; a run that fails during the fit raises
    SimulationError with its parameters."""
    from scipy.optimize import least_squares  # type: ignore[import-untyped,unused-ignore]

    if not isinstance(scenario, Scenario):
        scenario = load(scenario)
    table = _table(data)
    if "t" not in table:
        raise _bad("data", sorted(table)[:8], "has no column t [s] (nor an index named t)")
    t = _numbers("t", table["t"])
    if len(t) == 0:
        raise _bad("data['t']", [], "no rows")
    if np.any(np.diff(t) <= 0):
        i = int(np.argmax(np.diff(t) <= 0)) + 1
        raise _bad(f"data['t'] row {i}", float(t[i]), "t must increase strictly from row to row")
    if t[0] < 0 or t[-1] > scenario.t_end:
        i = 0 if t[0] < 0 else int(np.argmax(t > scenario.t_end))
        raise _bad(f"data['t'] row {i}", float(t[i]), f"outside the run's time span [0, {scenario.t_end:g}] s (output.t_end)")
    names = [c for c in table if c != "t"] if columns is None else list(dict.fromkeys(_names("columns", columns)))
    if "t" in names:
        raise _bad("columns", "t", "t is the time of the samples, not a measured column")
    if not names:
        raise _bad("columns", columns, "no column to fit: the data have only t")
    keys, start, lo, hi = _params(scenario, params)
    measured: dict[str, np.ndarray] = {}
    for n in names:
        if n not in table:
            raise _bad("columns", n, f"not a column of the data (its columns: {', '.join(table)})")
        measured[n] = _numbers(n, table[n])
        if len(measured[n]) != len(t):
            raise _bad(f"data[{n!r}]", len(measured[n]), f"has {len(measured[n])} rows, t has {len(t)}")
    weight = _weights(sigma, names, len(t))
    if not (isinstance(step, (int, float)) and not isinstance(step, bool) and 1e-10 <= step <= 0.1):
        raise _bad("step", step, "a relative step from 1e-10 to 0.1")
    max_nfev = _count("max_nfev", max_nfev)
    m = len(t) * len(names)
    if m <= len(keys):
        raise _bad("data", m, f"{m} measured values cannot determine {len(keys)} parameters")

    runs = 0

    def run(p: np.ndarray) -> Trajectory:
        nonlocal runs
        runs += 1
        variant = scenario.replace(**dict(zip(keys, (float(v) for v in p))))
        traj = simulate(variant, t_eval=t, method=method, rtol=rtol, atol=atol)
        if not traj.success or len(traj) != len(t):
            at = ", ".join(f"{k} = {v:.10g}" for k, v in zip(keys, p))
            err = SimulationError(f"fit: the run at {at} stopped ({traj.status}: {traj.message}) before the data's last time")
            err.trajectory = traj
            raise err
        for n in names:
            if n not in traj.columns or traj[n].dtype.kind != "f":
                raise _bad("columns", n, "not a numeric output column of this scenario's runs (`Trajectory.columns`)")
        return traj

    def residual(traj: Trajectory) -> np.ndarray:
        return np.concatenate([(traj[n] - measured[n]) * weight[n] for n in names])

    def events(traj: Trajectory) -> dict[str, int]:
        return {k: int(np.sum(v <= t[-1])) for k, v in traj.t_events.items()}

    span = hi - lo
    cache: dict[bytes, Trajectory] = {}

    def model(u: np.ndarray) -> Trajectory:
        key = np.asarray(u, dtype=float).tobytes()
        if key not in cache:
            cache.clear()
            cache[key] = run(lo + u * span)
        return cache[key]

    notes: list[str] = []

    def jac_p(p: np.ndarray, traj0: Trajectory) -> np.ndarray:
        """∂r/∂p by central differences (second-order one-sided differences at a bound)."""
        r0, seq0 = residual(traj0), events(traj0)
        cols = []
        for j in range(len(p)):
            h = step * max(abs(p[j]), 1e-3 * span[j])
            sides = (1.0, -1.0) if p[j] - h >= lo[j] and p[j] + h <= hi[j] else ((1.0, 2.0) if p[j] + 2 * h <= hi[j] else (-1.0, -2.0))
            rs = []
            for s in sides:
                q = p.copy()
                q[j] += s * h
                tr = run(q)
                if events(tr) != seq0:
                    note = f"{keys[j]}: the events before the data's last time change within the step ±{h:.3g}; the derivative is not defined there (the sequence of events depends on this parameter)"
                    if note not in notes:
                        notes.append(note)
                        warnings.warn(note, RuntimeWarning, stacklevel=4)
                rs.append(residual(tr))
            if sides == (1.0, -1.0):
                cols.append((rs[0] - rs[1]) / (2 * h))
            else:
                sgn = sides[0]
                cols.append(sgn * (-3 * r0 + 4 * rs[0] - rs[1]) / (2 * h))
        return np.column_stack(cols)

    u0 = (start - lo) / span
    result = least_squares(
        lambda u: residual(model(u)),
        u0,
        jac=lambda u: jac_p(lo + u * span, model(u)) * span,
        bounds=(np.zeros_like(u0), np.ones_like(u0)),
        method="trf",
        x_scale=1.0,
        max_nfev=max_nfev,
    )
    p = lo + result.x * span
    best = model(result.x)
    r = residual(best)
    jac = result.jac / span  # ∂r/∂p at the solution (least_squares keeps ∂r/∂u there)
    chi2 = float(r @ r)
    dof = m - len(keys)
    cov = _covariance(jac) * (1.0 if sigma is not None else chi2 / dof)
    err = np.sqrt(np.diag(cov))
    with np.errstate(invalid="ignore", divide="ignore"):
        corr = cov / np.outer(err, err)
    corr = np.where(np.isfinite(corr), corr, 0.0)
    np.fill_diagonal(corr, 1.0)
    message = str(result.message)
    at_bound = [k for k, v, a, b in zip(keys, p, lo, hi) if v <= a or v >= b]
    if at_bound:
        message += f" At a bound: {', '.join(at_bound)} (its standard error assumes it free)."
    if not np.all(np.isfinite(err)):
        message += " The data do not determine every parameter (the Jacobian is singular): their standard errors are inf."
    return Fit(
        params=dict(zip(keys, p.tolist())),
        stderr=dict(zip(keys, err.tolist())),
        correlation=corr,
        covariance=cov,
        residuals={n: measured[n] - best[n] for n in names},
        chi2=chi2,
        dof=dof,
        success=bool(result.success),
        message=message,
        nfev=runs,
        scenario=best.scenario,
        trajectory=best,
        t=t,
        data=measured,
        warnings=notes,
    )


def _count(key: str, value: Any) -> int:
    """A positive integer argument (anything `operator.index` takes, not a bool)."""
    n = _index(value)
    if n is None:
        raise _bad(key, value, f"expected an integer, found {type(value).__name__}", True)
    if not 1 <= n <= 100_000:
        raise _bad(key, value, "from 1 to 100000")
    return n


def _weights(sigma: Any, names: list[str], rows: int) -> dict[str, np.ndarray]:
    """1/σ per column and row: σ = 1 by default, a number for every column, or a dict by
    column of numbers or arrays (columns not named get 1)."""
    per: Mapping[str, Any] = {} if sigma is None else (sigma if isinstance(sigma, Mapping) else {n: sigma for n in names})
    out = {}
    for n in names:
        try:
            s = np.asarray(per.get(n, 1.0), dtype=float)
        except (TypeError, ValueError):
            raise _bad(f"sigma[{n!r}]", per.get(n), "expected a number or an array of numbers", True) from None
        if s.ndim == 0:
            s = np.full(rows, float(s))
        if s.shape != (rows,):
            raise _bad(f"sigma[{n!r}]", s.shape, f"a number or {rows} numbers (one per data row)")
        if not np.all(np.isfinite(s) & (s > 0)):
            raise _bad(f"sigma[{n!r}]", s[~(np.isfinite(s) & (s > 0))][0], "measurement errors are finite and > 0")
        out[n] = 1.0 / s
    for n in per:
        if n not in names:
            raise _bad("sigma", n, f"not a fitted column (fitted: {', '.join(names)})")
    return out


def _covariance(jac: np.ndarray) -> np.ndarray:
    """(JᵀJ)⁻¹ through the SVD of J; inf where J is singular (a direction the data do not
    determine)."""
    _, s, vt = np.linalg.svd(jac, full_matrices=False)
    tiny = s <= np.finfo(float).eps * max(jac.shape) * (s[0] if len(s) else 0.0)
    if np.any(tiny):
        return np.full((jac.shape[1],) * 2, np.inf)
    return (vt.T / s**2) @ vt
