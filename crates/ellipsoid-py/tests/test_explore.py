"""`ellipsoid.explore`: each slider reruns the scenario at its value (the same run as
`simulate` of the changed scenario), a refused value is shown and not raised, bad
`params` are refused by name as `fit` refuses them, and Jupyter displays the widget."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

import ellipsoid
from conftest import REPO

pytest.importorskip("ipywidgets")
pytest.importorskip("matplotlib")

TIPPE = os.path.join(REPO, "scenarios", "tippe-top.toml")


def tippe() -> ellipsoid.Scenario:
    return ellipsoid.load(TIPPE).replace(output={"t_end": 0.5})


def test_each_slider_reruns_the_scenario_at_its_value() -> None:
    base = tippe()
    ex = ellipsoid.explore(base, {"contact.friction": (0.05, 0.8), "initial.phi_dot": (50.0, 300.0)})
    assert list(ex.sliders) == ["contact.friction", "initial.phi_dot"]
    assert [s.value for s in ex.sliders.values()] == [0.3, 180.0]  # the scenario's own
    assert np.array_equal(ex.trajectory.theta, ellipsoid.simulate(base).theta)
    ex.sliders["contact.friction"].value = 0.5
    ex.sliders["initial.phi_dot"].value = 120.0
    moved = base.replace(**{"contact.friction": 0.5, "initial.phi_dot": 120.0})
    assert ex.scenario.get("contact.friction") == 0.5 and ex.scenario.get("initial.phi_dot") == 120.0
    assert np.array_equal(ex.trajectory.theta, ellipsoid.simulate(moved).theta)
    assert not np.array_equal(ex.trajectory.theta, ellipsoid.simulate(base).theta)
    assert ex.status.value.startswith("completed at t = 0.5 s")


def test_changes_reach_every_run_and_the_sliders_win_over_them() -> None:
    ex = ellipsoid.explore(TIPPE, {"contact.friction": (0.05, 0.8)}, columns=["theta", "omega_world_z"],
                           output={"t_end": 0.2}, contact={"friction": 0.4}, rtol=1e-6)  # fmt: skip
    assert ex.sliders["contact.friction"].value == 0.4  # starts at the changed value
    ex.sliders["contact.friction"].value = 0.1
    assert ex.trajectory.t[-1] == 0.2 and ex.scenario.get("contact.friction") == 0.1
    ref = ellipsoid.simulate(TIPPE, output={"t_end": 0.2}, contact={"friction": 0.1}, rtol=1e-6)
    assert np.array_equal(ex.trajectory.theta, ref.theta)


def test_a_refused_value_is_shown_not_raised() -> None:
    ex = ellipsoid.explore(tippe(), {"body.com_offset": (0.0, 0.03)})
    ex.sliders["body.com_offset"].value = 0.029  # G outside the body (c = 15 mm)
    assert ex.trajectory is None and ex.scenario is None
    assert ex.status.value.startswith("<b>refused</b>") and "com_offset" in ex.status.value
    ex.sliders["body.com_offset"].value = 0.002
    assert ex.trajectory is not None and ex.trajectory.success


@pytest.mark.parametrize(
    ("params", "needle"),
    [
        ({}, "params"),
        ({"contact.friction": (0.8, 0.1)}, "low < high"),
        ({"contact.friction": (0.5, 0.9)}, "outside the bounds"),
        ({"initial.psi_dot": (0.0, 10.0)}, "does not set this key"),
        ({"contact.model": (0.0, 1.0)}, "not a number"),
        ({"contact.friction": "wide"}, "two numbers"),
    ],
)
def test_bad_params_are_refused_by_name(params: dict, needle: str) -> None:
    with pytest.raises(ellipsoid.ScenarioError, match=needle) as err:
        ellipsoid.explore(tippe(), params)
    assert str(err.value).startswith("explore: params")


def test_a_notebook_displays_the_explorer_once(tmp_path: Path) -> None:
    nbformat = pytest.importorskip("nbformat")
    nbclient = pytest.importorskip("nbclient")
    pytest.importorskip("ipykernel")
    from jupyter_client.kernelspec import NATIVE_KERNEL_NAME

    cells = [f"import ellipsoid\nex = ellipsoid.explore({TIPPE!r}, {{'contact.friction': (0.05, 0.8)}}, output={{'t_end': 0.3}})\nex",
             "ex.sliders['contact.friction'].value = 0.6\nfloat(ex.trajectory.t[-1])"]  # fmt: skip
    nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell(c) for c in cells])
    client = nbclient.NotebookClient(nb, timeout=300, kernel_name=NATIVE_KERNEL_NAME, resources={"metadata": {"path": str(tmp_path)}})
    client.execute()
    shown = [o for o in nb.cells[0].outputs if o.output_type in ("execute_result", "display_data")]
    assert len(shown) == 1 and "application/vnd.jupyter.widget-view+json" in shown[0]["data"], nb.cells[0].outputs
    assert not [o for c in nb.cells for o in c.outputs if o.output_type == "error"]
    assert nb.cells[1].outputs[0]["data"]["text/plain"] == "0.3"
