"""``ellipsoid.steady``: steady motions and their linear stability (docs/physics.md,
"Steady motions and their stability"). The analysis is the core's (``steady`` module);
this wraps its arrays in a result object."""

from __future__ import annotations

import operator
import os
from collections.abc import Mapping, Sequence
from typing import Any, SupportsIndex

import numpy as np

from ellipsoid._ellipsoid import Scenario, ScenarioError, _argument_error, steady_raw, steady_start


def _number(key: str, value: Any, source: str) -> float:
    """``value`` as a float (an int or a float, not a bool), else the ScenarioTypeError
    naming ``key``."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise _argument_error(key, None, f"expected a number, found {type(value).__name__}", True, source)
    return float(value)


def _index(value: Any) -> int | None:
    """`value` as an int if `operator.index` takes it (an int, a numpy integer), not a
    bool; else None."""
    if isinstance(value, (bool, np.bool_)):
        return None
    try:
        return operator.index(value)
    except TypeError:
        return None


class Steady:
    """Steady motions of one family, one per value of the varied key.

    ``values``: the varied values (without ``vary``, the one motion's spin n [rad/s]);
    ``eigenvalues``: complex array, one row per value, four eigenvalues [1/s] (body frame;
    two for the tilted families "precession" and "rolling-circle", in the frame turning
    with the motion; six under the viscous sliding law) sorted by decreasing real part,
    the zeros of the symmetries, the constraints and the family removed; ``modes``: the
    name of each eigenvalue's mode ("tilt", "roll", "pitch", "wobble", "spin",
    "nutation"; under the viscous law "tilt" or "slip"); ``states``: (ζ1, ζ2, ζ3,
    ω1, ω2, ω3) per value (world up and the angular velocity in body axes [rad/s]);
    ``spin`` [rad/s], ``theta`` [rad], ``normal_force`` [N], ``max_real`` [1/s],
    ``stable``, ``surface`` (the surface each motion rests on); for the tilted families ``phi_dot`` [rad/s] and ``circles`` [m] (None
    otherwise); ``critical``: the critical values, dicts with ``value``, ``kind``
    ("collision", "hopf", "real"), ``stable_side`` ("above" or "below") and
    ``eigenvalue``.
    """

    def __init__(self, raw: dict[str, Any]) -> None:
        self.family: str = raw["family"]
        """The family: "upright", "inverted", "precession" or "rolling-circle"."""
        self.key: str | None = raw["key"]
        """The varied scenario key, or None without ``vary``."""
        self.values: np.ndarray = raw["values"]
        """The varied values (without ``vary``, the one motion's spin n [rad/s])."""
        self.eigenvalues: np.ndarray = raw["eigenvalues"]
        """Complex, one row per value: four eigenvalues [1/s] (two for a tilted family) sorted by decreasing real part (the zeros of the symmetries, constraints and family removed)."""
        self.modes: list[list[str]] = raw["modes"]
        """The mode of each eigenvalue: "tilt", "roll", "pitch", "wobble", "spin" or "nutation" (a tilted family: the tilt θ oscillates or grows)."""
        self.states: np.ndarray = raw["states"]
        """(ζ1, ζ2, ζ3, ω1, ω2, ω3) per value: world up in body axes [1] and the angular velocity in body axes [rad/s]."""
        self.spin: np.ndarray = raw["spin"]
        """The spin n per value [rad/s]: about the vertical (upright, inverted), about the body's axis and solved for (precession, rolling-circle)."""
        self.theta: np.ndarray = raw["theta"]
        """The tilt of the symmetry axis per value [rad] (0 upright, π inverted)."""
        self.normal_force: np.ndarray = raw["normal_force"]
        """The normal force N of each steady motion [N]."""
        self.phi_dot: np.ndarray | None = raw["phi_dot"]
        """A tilted family's precession rate φ̇ about the vertical per value [rad/s] (None for upright and inverted)."""
        self.circles: np.ndarray | None = raw["circles"]
        """A tilted family's circles per value: the radii of G's and of the contact point's circle [m] (inf where φ̇ = 0 and the body rolls straight on; None for upright and inverted)."""
        self.max_real: np.ndarray = raw["max_real"]
        """The largest real part of each row of eigenvalues [1/s]."""
        self.stable: np.ndarray = raw["stable"]
        """Whether each steady motion is linearly stable (max_real ≤ 0 to round-off)."""
        self.surface: list[str] = raw["surface"]
        """The surface each steady motion rests on: "ellipsoid", or a contact sphere's name (a body with contact spheres rests on the surface lowest where the family starts: a tippe top's stem when inverted)."""
        self.critical: list[dict[str, Any]] = raw["critical"]
        """The critical values: dicts with ``value``, ``kind`` ("collision", "hopf", "real"), ``stable_side`` ("above" or "below") and ``eigenvalue``."""
        self._source: tuple[Any, str] = (None, "spin")

    def __len__(self) -> int:
        return len(self.values)

    def scenario(self, mode: int | SupportsIndex | str, eps: float, index: int | SupportsIndex = 0) -> Scenario:
        """The scenario started on steady motion ``index`` (a row of ``eigenvalues``)
        displaced by ``eps`` along ``mode`` (its column in ``eigenvalues``, 0 = the least
        stable, or its name in ``modes``: the first of that name), as ``ellipsoid steady
        --perturb`` writes it: its ``[initial]`` table the displaced state, every other
        table the scenario's. ``simulate`` of it shows the mode grow (Re λ > 0) or
        oscillate. |eps| at most 0.1 (rad of tilt). ``index`` and a column ``mode`` are
        anything ``operator.index`` takes (an int, a numpy integer)."""
        row = _index(index)
        if row is None or not 0 <= row < len(self):
            raise ScenarioError(f"index = {index!r}: must be a row number from 0 to {len(self) - 1}")
        names = self.modes[row]
        if isinstance(mode, str):
            if mode not in names:
                raise ScenarioError(f"mode = {mode!r}: not a mode of this motion (its modes: {', '.join(names)})")
            column: int | None = names.index(mode)
        else:
            column = _index(mode)
        if column is None or not 0 <= column < len(names):
            raise ScenarioError(f"mode = {mode!r}: must be a column from 0 to {len(names) - 1} or a mode's name")
        scenario, solve = self._source
        value = None if self.key is None else float(self.values[row])
        return steady_start(scenario, self.family, column, _number("eps", eps, "Steady.scenario"), self.key, value, solve)

    def __repr__(self) -> str:
        crit = ", ".join(f"{c['value']:.10g} ({c['kind']})" for c in self.critical) or "none"
        return (
            f"<Steady {self.family}: {len(self)} value(s) of {self.key or 'spin'}, "
            f"{int(self.stable.sum())} stable; critical: {crit}>"
        )

    def plot(self, ax: Any = None, frequencies: bool = True) -> Any:
        """The stability diagram into the matplotlib Axes ``ax`` (else a new pyplot
        figure's, shown once in Jupyter as pandas' plots are), which it returns: the growth rates Re λ against ``values`` (the largest bold, the
        others thin), the values' stable and unstable ranges shaded green and red (each
        range ending at a located critical value, else midway between two values), each
        critical value a dashed line labelled with its value and kind, and with
        ``frequencies`` the angular frequencies |Im λ| (one point per pair) on a second
        y axis at the right (``ax.twinx()``). As ``ellipsoid steady --vary ... --plot``
        draws it."""
        from ellipsoid._plot import _bad, _figure

        if ax is not None and not (callable(getattr(ax, "plot", None)) and hasattr(ax, "figure")):
            raise _bad("ax", ax, f"expected a matplotlib Axes, found {type(ax).__name__}", True)
        if ax is None:
            ax = _figure(figsize=(8, 4.5), layout="constrained").subplots()
        x = np.asarray(self.values, dtype=float)
        order = np.argsort(x, kind="stable")
        x, eig, stable = x[order], self.eigenvalues[order], np.asarray(self.stable)[order]
        crit = [float(c["value"]) for c in self.critical]
        for k in range(len(x)):
            def edge(j: int) -> float:
                between = [c for c in crit if min(x[k], x[j]) <= c <= max(x[k], x[j])]
                return between[0] if stable[k] != stable[j] and between else float(0.5 * (x[k] + x[j]))
            lo = x[k] if k == 0 else edge(k - 1)
            hi = x[k] if k == len(x) - 1 else edge(k + 1)
            ax.axvspan(lo, hi, color="#d6f0d6" if stable[k] else "#fad6d6", lw=0, zorder=0)
        ax.axhline(0.0, color="0.5", lw=0.8)
        for k in range(eig.shape[1] - 1, -1, -1):
            bold = k == 0
            ax.plot(x, eig[:, k].real, color="#1f77b4" if bold else "#8caac8", lw=2.2 if bold else 0.8,
                    label="largest Re λ" if bold else ("other Re λ" if k == 1 else None))
        for c in self.critical:
            ax.axvline(c["value"], color="#6e2896", ls="--", lw=1.2)
            ax.annotate(f"{c['value']:.5g} ({c['kind']})", (c["value"], 1.0), xycoords=("data", "axes fraction"),
                        xytext=(2, -10), textcoords="offset points", color="#6e2896", fontsize=8)
        ax.set_xlabel(self.key or "spin (rad/s)")
        ax.set_ylabel("Re λ (1/s)")
        ax.grid(alpha=0.3)
        handles, labels = ax.get_legend_handles_labels()
        if frequencies:
            twin = ax.twinx()
            fx = np.repeat(x, eig.shape[1])
            fy = np.abs(eig.imag).ravel()
            twin.plot(fx, fy, ".", color="#d62728", ms=3, label="|Im λ|")
            twin.set_ylabel("|Im λ| (1/s)", color="#d62728")
            twin.set_ylim(bottom=0.0)
            h, lab = twin.get_legend_handles_labels()
            handles, labels = handles + h, labels + lab
        from matplotlib.patches import Patch  # type: ignore[import-untyped,unused-ignore]

        handles += [Patch(color="#d6f0d6"), Patch(color="#fad6d6")]
        labels += ["stable", "unstable"]
        ax.legend(handles, labels, fontsize=8, loc="best")
        ax.set_title(f"{self.family}: against {self.key or 'spin'}")
        return ax

    def to_pandas(self) -> Any:
        """The table of ``ellipsoid steady -o``: the key, spin, theta, normal_force (for a
        tilted family phi_dot, radius_g, radius_contact), stable, max_real, lambdaK_re,
        lambdaK_im, modeK (K = 1..4; 1..2 tilted), as a ``pandas.DataFrame``."""
        import pandas as pd  # type: ignore[import-untyped,unused-ignore]  # optional dependency

        columns: dict[str, Any] = {
            self.key or "spin": self.values,
            "spin": self.spin,
            "theta": self.theta,
            "normal_force": self.normal_force,
        }
        if self.phi_dot is not None and self.circles is not None:
            columns["phi_dot"] = self.phi_dot
            columns["radius_g"] = self.circles[:, 0]
            columns["radius_contact"] = self.circles[:, 1]
        columns |= {
            "stable": self.stable,
            "max_real": self.max_real,
        }
        for k in range(self.eigenvalues.shape[1]):
            columns[f"lambda{k + 1}_re"] = self.eigenvalues[:, k].real
            columns[f"lambda{k + 1}_im"] = self.eigenvalues[:, k].imag
            columns[f"mode{k + 1}"] = [row[k] for row in self.modes]
        return pd.DataFrame(columns)


def steady(
    scenario: Scenario | str | os.PathLike[str],
    family: str = "upright",
    vary: Mapping[str, Sequence[float] | np.ndarray] | None = None,
    solve: str = "spin",
) -> Steady:
    """The steady motions of ``family`` of ``scenario``'s body under its contact model
    (frictionless, rolling, the Coulomb model's rolling phase, or viscous sliding: its
    upright and inverted spins, six eigenvalues each) and their stability:
    "upright" and "inverted" spin about the vertical at the scenario's initial spin;
    "precession" (frictionless, G fixed) and "rolling-circle" (Routh's steady rolling) are
    the tilted motions of a body of revolution at the scenario's ``initial.theta`` and
    ``initial.phi_dot``, the spin about the body's axis solved for — or, with ``solve``
    "phi_dot" or "theta", that unknown solved for from the other two, the spin being the
    scenario's φ̇ cos θ + ψ̇ (the root nearest ``initial.phi_dot``; Newton from
    ``initial.theta``). Without ``vary``, the one motion the scenario defines; ``vary``
    maps one scenario key to a 1-D array of values. Raises ScenarioError for a bad
    scenario, family, unknown or key, or a value without a steady motion; Ctrl-C stops a
    sweep before its next value and raises KeyboardInterrupt."""
    for name, given in (("family", family), ("solve", solve)):
        if not isinstance(given, str):
            raise _argument_error(name, None, f"expected a str, found {type(given).__name__}", True, "steady")
    if vary is None:
        res = Steady(steady_raw(scenario, family, solve=solve))
        res._source = (scenario, solve)
        return res
    if not isinstance(vary, Mapping) or len(vary) != 1:
        raise ScenarioError(
            f"vary = {vary!r}: must map exactly one scenario key to a 1-D array of values"
        )
    ((key, values),) = vary.items()
    if not isinstance(key, str):
        raise _argument_error("vary", None, f"a key of vary is a dotted scenario key (str), found {type(key).__name__}", True, "steady")
    try:
        array = np.asarray(values, dtype=float)
    except (TypeError, ValueError) as e:
        raise _argument_error(f"vary[{key!r}]", None, f"expected a 1-D array of numbers: {e}", True, "steady") from None
    if array.ndim != 1:
        raise ScenarioError(f"vary[{key!r}]: must be a 1-D array of values (got shape {array.shape})")
    res = Steady(steady_raw(scenario, family, str(key), [float(v) for v in array], solve))
    res._source = (scenario, solve)
    return res
