"""`ellipsoid.explore`: sliders on scenario keys in a notebook, the run redrawn as they move."""

from __future__ import annotations

import html
import os
from typing import Any, Sequence

from ellipsoid._ellipsoid import EllipsoidError, Scenario, load, simulate
from ellipsoid._fit import _params
from ellipsoid._plot import _names

#: Slider positions between the bounds (a run each time one moves).
STEPS = 100
#: `simulate`'s own arguments; every other change is the scenario's.
RUN_ARGUMENTS = ("t_eval", "method", "rtol", "atol")


class Explorer:
    """The widget `ellipsoid.explore` returns: displayed in a notebook it shows one slider
    per key, a line saying how the run ended, and the run's figure, redrawn whenever a
    slider moves.

    `sliders`: the ipywidgets FloatSlider of each key (set `.value` to move one from code);
    `scenario` and `trajectory`: the scenario at the sliders' values and its run (None
    while a value is refused: `status` then says why); `widget`: the ipywidgets VBox."""

    sliders: dict[str, Any]
    """The ipywidgets FloatSlider of each key, in the order of `params`."""
    status: Any
    """The ipywidgets HTML line saying how the run ended, or why a value was refused."""
    figure: Any
    """The ipywidgets Output the run's figure is drawn into."""
    widget: Any
    """The ipywidgets VBox of the sliders, the status line and the figure."""
    scenario: Scenario | None
    """The scenario at the sliders' values (None while a value is refused)."""
    trajectory: Any
    """Its run, an `ellipsoid.Trajectory` (None while a value is refused)."""

    def __init__(self, base: Scenario, keys: list[str], lo: Any, hi: Any, start: Any, columns: list[str] | None, changes: dict[str, Any]) -> None:
        import ipywidgets as widgets  # type: ignore[import-untyped,import-not-found]

        self._base, self._columns, self._changes = base, columns, changes
        self.sliders = {
            key: widgets.FloatSlider(value=v, min=a, max=b, step=(b - a) / STEPS, description=key, readout_format=".4g",
                                     style={"description_width": "initial"}, layout=widgets.Layout(width="95%"))
            for key, a, b, v in zip(keys, lo, hi, start)
        }  # fmt: skip
        self.status = widgets.HTML()
        self.figure = widgets.Output()
        self.widget = widgets.VBox([*self.sliders.values(), self.status, self.figure])
        self.scenario = None
        self.trajectory = None
        for slider in self.sliders.values():
            slider.observe(lambda _change: self._run(), names="value")
        self._run()

    def _run(self) -> None:
        """Runs the scenario at the sliders' values and redraws (a refused value is shown,
        not raised: the slider stays where the user left it)."""
        import matplotlib.pyplot as plt

        values = {key: slider.value for key, slider in self.sliders.items()}
        try:
            self.scenario = self._base.replace(**values)
            self.trajectory = simulate(self.scenario, **self._changes)
        except EllipsoidError as err:
            self.scenario, self.trajectory = None, None
            self.status.value = f"<b>refused</b>: {html.escape(str(err), quote=False)}"
            self.figure.clear_output()
            return
        traj = self.trajectory
        self.status.value = f"{html.escape(traj.status, quote=False)} at t = {traj.t[-1]:.6g} s: {html.escape(traj.message, quote=False)}"
        with self.figure:
            self.figure.clear_output(wait=True)
            if self._columns:
                _, ax = plt.subplots(figsize=(7, 3.2), constrained_layout=True)
                traj.plot(columns=self._columns, ax=ax)
            else:
                traj.plot()
            fig = plt.gcf()
            plt.show()
            plt.close(fig)

    def _repr_mimebundle_(self, **kwargs: Any) -> Any:
        return self.widget._repr_mimebundle_(**kwargs)


def explore(
    scenario: Scenario | str | os.PathLike[str],
    params: dict[str, Sequence[float]],
    columns: str | Sequence[str] | None = "theta",
    **changes: Any,
) -> Explorer:
    """Sliders on scenario keys, the run redrawn as they move: an interactive explorer for
    a notebook (it needs `ipywidgets`).

    `scenario`: an `ellipsoid.Scenario` or the path of a scenario file. `params`: a dict
    from numeric scenario keys (the override grammar's, as `Scenario.replace` and `fit`
    take them: `"contact.friction"`, `"initial.psi_dot"`) to their bounds `(low, high)`;
    each slider starts at the scenario's own value, which must lie within them, and moves
    in 100 steps. `columns`: what the figure shows, as `Trajectory.plot(columns=...)` (None:
    `Trajectory.plot()`'s default panels). `changes`: made to the scenario before the
    sliders (e.g. `output={"t_end": 2.0}`; a slider's key set there starts at that value),
    and `simulate`'s own `t_eval`, `method`, `rtol`, `atol` given to every run.

    Each move reruns the scenario (tens of milliseconds for most scenes) and redraws; a
    value the scenario refuses (a ScenarioError, e.g. a tilt the body cannot start at) is
    shown in the status line instead of raised. Returns an `Explorer`: display it (the last
    line of a cell); its `sliders`, `scenario` and `trajectory` are there to read or set
    from code. Bad `params` raise ScenarioError naming the key, as `fit` does."""
    try:
        import ipywidgets  # type: ignore[import-untyped,import-not-found]  # noqa: F401
    except ImportError:
        raise ImportError("ellipsoid.explore needs ipywidgets: pip install ipywidgets") from None
    base = scenario if isinstance(scenario, Scenario) else load(os.fspath(scenario))
    run = {key: changes.pop(key) for key in RUN_ARGUMENTS if key in changes}
    if changes:  # the scenario's changes first: the sliders start from, and win over, them
        base = base.replace(**changes)
    keys, start, lo, hi = _params(base, params, source="explore")
    names = None if columns is None else _names("columns", columns)
    return Explorer(base, keys, lo, hi, start, names, run)
