"""Jupyter shows what the package makes: a notebook executed by nbclient in a fresh
kernel, without `%matplotlib inline`, has one PNG for `traj.plot()`, the viewer as HTML for
`traj.view()` and a Trajectory, and a small link for `traj.view(path)`."""

from __future__ import annotations

from pathlib import Path

import pytest

from conftest import REPO

nbformat = pytest.importorskip("nbformat")
nbclient = pytest.importorskip("nbclient")
pytest.importorskip("ipykernel")
pytest.importorskip("matplotlib")

CELLS = [
    "import ellipsoid\ntraj = ellipsoid.simulate(%r, output={'t_end': 0.5})",
    "traj.plot()",
    "traj.plot(columns=['omega_world_z', 'theta'])",
    "traj.view()",
    "traj.view('viewer.html')",
    "traj",
]


def test_a_fresh_notebook_displays_figures_and_the_viewer(tmp_path: Path) -> None:
    cells = [CELLS[0] % str(REPO / "scenarios" / "tippe-top.toml"), *CELLS[1:]]
    nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell(c) for c in cells])
    nb.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3", "language": "python"}
    from jupyter_client.kernelspec import NATIVE_KERNEL_NAME  # the kernel of this interpreter

    client = nbclient.NotebookClient(nb, timeout=300, kernel_name=NATIVE_KERNEL_NAME, resources={"metadata": {"path": str(tmp_path)}})
    client.execute()
    outs = [[o for o in c.outputs if o.output_type in ("execute_result", "display_data")] for c in nb.cells]
    for i in (1, 2):  # one figure each, as PNG, under 400 kB (and the Axes as text)
        pngs = [o["data"]["image/png"] for o in outs[i] if "image/png" in o["data"]]
        assert len(pngs) == 1, (cells[i], outs[i])
        assert 10_000 < len(pngs[0]) < 400_000, cells[i]
    for i in (3, 5):  # the viewer inline: HTML, not its text printed
        data = outs[i][0]["data"]
        assert "<iframe srcdoc=" in data["text/html"] and len(data["text/html"]) < 2_000_000
        assert len(data["text/plain"]) < 400, data["text/plain"]
    link = outs[4][0]["data"]["text/html"]
    assert '<iframe src="viewer.html"' in link and len(link) < 500
    assert (tmp_path / "viewer.html").stat().st_size > 500_000


#: Each cell of the pandas-like notebook, and how many figures (image/png outputs) it shows.
PLOTS = [
    ("import numpy as np\nimport matplotlib.pyplot as plt\nimport ellipsoid\n"
     "traj = ellipsoid.simulate(%(nutation)r, output={'t_end': 1.0, 'dt': 0.01},\n"
     "                          section=[{'name': 'bottom', 'column': 'theta_dot', 'crosses': 0.0, 'direction': 'up'}])", 0),
    ("traj.plot('theta');", 1),
    ("traj.plot()", 1),
    ("traj.plot(); plt.show()", 1),
    ("traj.plot('theta'); plt.savefig('f.png')", 1),
    ("egg = ellipsoid.Scenario(body={'a': 0.02, 'c': 0.03, 'mass': 0.06, 'inertia': 'uniform'},\n"
     "                         initial={'theta': 0.0, 'psi_dot': 100.0}, contact={'model': 'frictionless'},\n"
     "                         output={'t_end': 1.0, 'dt': 0.01})\n"
     "ellipsoid.steady(egg, vary={'initial.psi_dot': np.linspace(40.0, 160.0, 7)}).plot()", 1),
    ("fig, ax = plt.subplots()\nprint('same axes:', traj.plot(columns='theta', ax=ax) is ax)", 1),
    ("fig, ax = plt.subplots()\ntraj.plot('theta', ax=ax)", 1),
    ("traj.plot_section('bottom', 'phi', 'theta');", 1),
    ("axes = traj.plot('theta,energy')\nprint(type(axes).__name__, len(axes), axes[0].figure is plt.gcf())", 1),
]


def test_plots_show_once_as_pandas_plots_do(tmp_path: Path) -> None:
    """As `DataFrame.plot()` in Jupyter (the kernel's inline backend): every plot is shown
    exactly once — with a trailing `;`, as the cell's last expression, followed by
    `plt.show()` or `plt.savefig`, into a given Axes, `Steady.plot()` and `plot_section`;
    `plt.savefig` after `plot()` writes the figure (not a blank PNG); `plot(ax=ax)`
    returns `ax`, and several panels an array of Axes of pyplot's current figure."""
    values = {"nutation": str(REPO / "scenarios" / "nutation.toml")}
    cells = [code % values if "%(" in code else code for code, _ in PLOTS]
    nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell(c) for c in cells])
    nb.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3", "language": "python"}
    from jupyter_client.kernelspec import NATIVE_KERNEL_NAME

    client = nbclient.NotebookClient(nb, timeout=300, kernel_name=NATIVE_KERNEL_NAME, allow_errors=True,
                                     resources={"metadata": {"path": str(tmp_path)}})
    client.execute()
    for cell, (code, figures) in zip(nb.cells, PLOTS):
        errors = [o for o in cell.outputs if o.output_type == "error"]
        assert not errors, (code, errors)
        pngs = [o for o in cell.outputs if o.output_type in ("execute_result", "display_data") and "image/png" in o.get("data", {})]
        assert len(pngs) == figures, (code, [o.output_type for o in cell.outputs])
    printed = "".join(o.get("text", "") for c in nb.cells for o in c.outputs if o.output_type == "stream")
    assert "same axes: True" in printed
    assert "ndarray 3 True" in printed  # theta (one axis), energy (two)
    import matplotlib.image

    pixels = matplotlib.image.imread(tmp_path / "f.png")
    assert pixels.shape[0] > 100 and float(pixels[..., :3].var()) > 0, "savefig after plot() wrote a blank PNG"
