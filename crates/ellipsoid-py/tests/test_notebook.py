"""Jupyter shows what the package makes: a notebook executed by nbclient in a fresh
kernel, without `%matplotlib inline`, has a PNG for `traj.plot()`, the viewer as HTML for
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
    for i in (1, 2):  # one figure each, as PNG, under 400 kB
        assert len(outs[i]) == 1, (cells[i], outs[i])
        png = outs[i][0]["data"].get("image/png")
        assert png and 10_000 < len(png) < 400_000, cells[i]
    for i in (3, 5):  # the viewer inline: HTML, not its text printed
        data = outs[i][0]["data"]
        assert "<iframe srcdoc=" in data["text/html"] and len(data["text/html"]) < 2_000_000
        assert len(data["text/plain"]) < 400, data["text/plain"]
    link = outs[4][0]["data"]["text/html"]
    assert '<iframe src="viewer.html"' in link and len(link) < 500
    assert (tmp_path / "viewer.html").stat().st_size > 500_000
