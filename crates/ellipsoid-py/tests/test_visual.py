"""`Trajectory.view`, `_repr_html_` and `Trajectory.plot`."""

from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

import pytest

import ellipsoid
from conftest import SCENARIOS


def tippe_top() -> ellipsoid.Trajectory:
    return ellipsoid.simulate(str(SCENARIOS / "tippe-top.toml"), output={"t_end": 1.5})


def test_view_is_the_command_line_page_byte_for_byte(cli: Path, tmp_path: Path) -> None:
    scenario = str(SCENARIOS / "tippe-top.toml")
    done = subprocess.run(
        [str(cli), "run", scenario, "-o", str(tmp_path / "t.csv"), "--summary", str(tmp_path / "t.json"), "--set", "output.t_end=1.5", "-q"],
        capture_output=True,
        text=True,
    )
    assert done.returncode == 0, done.stderr
    done = subprocess.run(
        [str(cli), "view", str(tmp_path / "t.csv"), "--summary", str(tmp_path / "t.json"), "-o", str(tmp_path / "cli.html"), "--title", "tt", "-q"],
        capture_output=True,
        text=True,
    )
    assert done.returncode == 0, done.stderr
    traj = ellipsoid.simulate(scenario, **{"output.t_end": 1.5})
    page = traj.view(title="tt")
    assert isinstance(page, str)
    assert page == (tmp_path / "cli.html").read_text(encoding="utf-8")
    written = traj.view(tmp_path / "py.html", title="tt")
    assert os.fspath(written) == str(tmp_path / "py.html")  # in Jupyter: an iframe of the file
    assert (tmp_path / "py.html").read_text(encoding="utf-8") == page


def test_view_side_plots_and_default_title_are_the_command_line_s(cli: Path, tmp_path: Path) -> None:
    """`columns=` chooses the side plots as `ellipsoid view --columns` does, and both title
    the page with the scenario's file name (no directories) by default."""
    scenario = str(SCENARIOS / "tippe-top.toml")
    run = [str(cli), "run", scenario, "-o", str(tmp_path / "t.csv"), "--summary", str(tmp_path / "t.json"), "--set", "output.t_end=1.5", "-q"]
    subprocess.run(run, check=True)
    view = [str(cli), "view", str(tmp_path / "t.csv"), "--summary", str(tmp_path / "t.json"), "-o", str(tmp_path / "cli.html"),
            "--columns", "omega_world_z,theta", "-q"]
    subprocess.run(view, check=True)
    traj = ellipsoid.simulate(scenario, **{"output.t_end": 1.5})
    page = traj.view(columns=["omega_world_z", "theta"])
    assert page == (tmp_path / "cli.html").read_text(encoding="utf-8")
    assert traj.view(columns="omega_world_z, theta") == page
    assert "<title>tippe-top.toml</title>" in page and str(SCENARIOS) not in page
    assert '"name":"omega_world_z","label":"omega_world_z (rad/s)"' in page
    with pytest.raises(ellipsoid.ScenarioError, match='columns = thetaa: "thetaa" is not a numeric output column'):
        traj.view(columns=["thetaa"])


def test_view_page_carries_the_run() -> None:
    page = tippe_top().view()
    assert page.startswith("<!DOCTYPE html>") and "three.js authors" in page
    assert '"semi_axes":[' in page and "sliding → rolling" in page


def test_view_to_an_unwritable_place_is_an_output_error(tmp_path: Path) -> None:
    with pytest.raises(ellipsoid.OutputError, match="nowhere"):
        tippe_top().view(tmp_path / "nowhere" / "v.html")


def test_repr_html_is_the_viewer_in_an_iframe() -> None:
    import html as html_lib

    traj = tippe_top()
    html = traj._repr_html_()
    assert html.startswith('<iframe srcdoc="')
    assert html.count('"') == 6, "the page is escaped inside the attribute"
    srcdoc = html[len('<iframe srcdoc="') : html.index('" style=')]
    assert html_lib.unescape(srcdoc) == traj.view(), "the iframe holds the viewer page"


def test_plot_draws_every_panel_with_units() -> None:
    pytest.importorskip("matplotlib")
    fig = tippe_top().plot()[0].figure
    labels = {ax.get_ylabel() for ax in fig.axes} | {ax.get_xlabel() for ax in fig.axes}
    for want in ["θ (rad)", "rate (rad/s)", "energy (J)", "|relative drift| (1, log)", "normal force N (N)", "slip speed |v_C| (m/s)", "x (m)", "y (m)", "time t (s)"]:
        assert want in labels, want
    assert len(fig.axes) == 7
    for ax in fig.axes:
        assert ax.lines, f"{ax.get_title()}: nothing drawn"
    path = [ax for ax in fig.axes if ax.get_xlabel() == "x (m)"][0]
    assert [ln.get_label() for ln in path.lines][:2] == ["G", "contact point"]
    drift = [ax for ax in fig.axes if ax.get_yscale() == "log"][0]
    assert "E + W" in drift.get_title()
    one = tippe_top().plot("theta, path")
    assert len(one) == 2 and len(one[0].figure.axes) == 2
    with pytest.raises(ValueError, match="unknown panel 'wobble'"):
        tippe_top().plot(["theta", "wobble"])


def svg_texts(path: Path) -> set[str]:
    """Every text of an SVG figure, stripped."""
    import xml.etree.ElementTree as ET

    return {(el.text or "").strip() for el in ET.parse(path).iter() if el.tag.endswith("}text") or el.tag == "text"}


def test_both_renderers_draw_the_declared_panels_alike(cli: Path, tmp_path: Path) -> None:
    """`ellipsoid plot` (plotters) and `Trajectory.plot` (matplotlib) draw from one
    declaration: the same axes with the same titles (suffixes included: the vertical spin,
    the Euler rates left out near θ = 0, the modes shaded), labels and legend entries."""
    pytest.importorskip("matplotlib")
    scene = str(SCENARIOS / "tippe-top.toml")
    run = [str(cli), "run", scene, "--set", "output.t_end=1.5", "-o", str(tmp_path / "run.csv"),
           "--summary", str(tmp_path / "run.json"), "-q"]
    subprocess.run(run, check=True)
    subprocess.run([str(cli), "plot", str(tmp_path / "run.csv"), "--summary", str(tmp_path / "run.json"),
                    "-o", str(tmp_path / "fig.svg"), "-q"], check=True)
    texts = svg_texts(tmp_path / "fig.svg")
    fig = tippe_top().plot()[0].figure
    from ellipsoid._plot import DECLARATION

    # (the surfaces panel only for a body with contact spheres: see below)
    assert len(fig.axes) == sum(len(p["axes"]) for p in DECLARATION["panels"] if not p.get("per_surface"))
    assert fig.get_suptitle() == "tippe-top.toml" and "tippe-top.toml" in texts
    titles = [ax.get_title() for ax in fig.axes]
    assert "Euler rates and the vertical spin (φ̇, ψ̇ left out where sin θ < 0.1)" in titles
    assert "normal force (shaded: sliding orange, rolling green)" in titles
    for ax in fig.axes:
        drawn = [ax.get_title(), ax.get_ylabel(), ax.get_xlabel()]
        drawn += [t.get_text() for t in ax.get_legend().get_texts()] if ax.get_legend() else []
        for text in drawn:
            assert text in texts, f"matplotlib draws {text!r}, ellipsoid plot does not"
    # and the other way: every caption of the SVG (its largest text but the figure's title)
    # is a matplotlib title
    import xml.etree.ElementTree as ET

    captions = {(el.text or "").strip() for el in ET.parse(tmp_path / "fig.svg").iter()
                if el.tag.endswith("text") and float(el.get("font-size", "0")) > 15}
    assert captions == set(titles), captions ^ set(titles)


def test_plot_writes_pdf(tmp_path: Path) -> None:
    pytest.importorskip("matplotlib")
    import matplotlib.pyplot as plt

    tippe_top().plot("theta,forces")
    plt.savefig(tmp_path / "fig.pdf")
    plt.close()
    data = (tmp_path / "fig.pdf").read_bytes()
    assert data.startswith(b"%PDF-") and data.rstrip().endswith(b"%%EOF") and len(data) > 10_000


def test_plot_returns_axes_of_a_pyplot_figure_as_pandas_does(tmp_path: Path) -> None:
    """As `DataFrame.plot`: the figure is pyplot's (so `plt.savefig` writes it, not a blank
    page), one Axes is returned as it is, several as a numpy array, top to bottom; into a
    given Axes the plot draws there and returns it (the figure is not made again)."""
    pytest.importorskip("matplotlib")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.axes
    import matplotlib.image
    import matplotlib.pyplot as plt
    import numpy as np

    plt.close("all")
    traj = tippe_top()
    one = traj.plot("theta")
    assert isinstance(one, matplotlib.axes.Axes) and one.figure is plt.gcf()
    plt.savefig(tmp_path / "f.png")
    pixels = matplotlib.image.imread(tmp_path / "f.png")
    assert float(pixels[..., :3].var()) > 0, "a blank PNG"
    several = traj.plot("theta,energy,path")
    assert isinstance(several, np.ndarray) and len(several) == 4
    assert [a.get_ylabel() for a in several][:1] == ["θ (rad)"] and several[0].figure is plt.gcf()
    assert list(several[0].figure.axes) == list(several)
    columns = traj.plot(columns=["theta", "energy"])
    assert isinstance(columns, np.ndarray) and [a.get_ylabel() for a in columns] == ["theta (rad)", "energy (J)"]
    figures = len(plt.get_fignums())
    fig, ax = plt.subplots()
    assert traj.plot("theta", ax=ax) is ax
    assert traj.plot(columns="energy", ax=ax) is ax
    assert traj.plot(columns=["theta", "energy"], ax=ax) is ax
    assert len(plt.get_fignums()) == figures + 1 and len(fig.axes) == 1
    plt.close("all")


def test_plot_without_matplotlib_says_how_to_get_it() -> None:
    code = (
        "import sys; sys.modules['matplotlib'] = None; sys.modules['matplotlib.figure'] = None\n"
        "import ellipsoid\n"
        f"t = ellipsoid.simulate({str(SCENARIOS / 'nutation.toml')!r}, output={{'t_end': 0.1}})\n"
        "try:\n    t.plot()\nexcept ImportError as e:\n    print('IMPORT', e)\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert "IMPORT Trajectory.plot needs matplotlib (`pip install matplotlib`)" in out.stdout, out.stdout + out.stderr


def test_repr_html_runs_in_a_browser(tmp_path: Path) -> None:
    """The iframe of `_repr_html_`, in a page as a notebook would hold it, shows the viewer
    in headless Chromium (skipped without one; scripts/test-all.sh installs it)."""
    import os

    sys.path.insert(0, str(Path(__file__).resolve().parents[3] / "tests" / "browser"))
    import cdp

    exe = cdp.chromium_path()
    if exe is None:
        if os.environ.get("ELLIPSOID_EXPECT_BROWSER") == "1":
            pytest.fail("no Chromium found")
        pytest.skip("no Chromium found: apt-get install -y chromium")
    page = tmp_path / "notebook.html"
    page.write_text("<!DOCTYPE html><html><body><p>cell output:</p>" + tippe_top()._repr_html_() + "</body></html>", encoding="utf-8")

    def check(p: cdp.Page) -> None:
        p.goto(page.as_uri())
        # The viewer sets data-ready in its own document, inside the sandboxed iframe, which
        # the outer page cannot read: it sees the iframe's pixels, polled until the body
        # shows (a loaded machine renders the first frame late), for at most 60 s.
        deadline = time.monotonic() + 60.0
        while True:
            p.pump(0.5)
            img = p.screenshot(p.rect("iframe"))
            saturated = ((img.max(axis=2) - img.min(axis=2)) > 60).mean()
            if saturated > 0.01 or time.monotonic() > deadline:
                break
        assert p.errors() == []
        assert saturated > 0.01, "the iframe shows no body"

    cdp.with_page(check)


def stem_top() -> ellipsoid.Trajectory:
    """The tippe top with its stem, through the stem's touchdown (1.372 s)."""
    return ellipsoid.simulate(str(SCENARIOS / "tippe-top-stem.toml"), output={"t_end": 1.6})


def test_plot_draws_each_surface_s_normal_force() -> None:
    """A body with contact spheres gets the surfaces panel: one line per surface, named by
    it, its values the run's per-surface column; the contact phases shaded once each (the
    `@` labels shaded by phase). A one-surface body has no such panel, and asking for it
    says why."""
    pytest.importorskip("matplotlib")
    from ellipsoid._plot import DECLARATION

    traj = stem_top()
    fig = traj.plot()[0].figure
    assert len(fig.axes) == sum(len(p["axes"]) for p in DECLARATION["panels"])
    surfaces = [ax for ax in fig.axes if ax.get_ylabel() == "normal force N_S (N)"]
    assert len(surfaces) == 1
    ax = surfaces[0]
    # sliding@ellipsoid, then sliding@stem: one phase, named once
    assert ax.get_title() == "normal force of each surface (shaded: sliding orange)"
    lines = [ln for ln in ax.lines if not ln.get_label().startswith("_")]  # (events are unlabelled lines)
    assert [ln.get_label() for ln in lines] == ["N, ellipsoid", "N, stem"]
    assert [ln.get_color() for ln in lines] == DECLARATION["surface_colors"][:2]
    import numpy as np

    stem = lines[1].get_ydata()
    assert np.array_equal(stem, traj["normal_force_stem"]) and stem[-1] > 0.05, "the stem carries the top at the end"
    assert np.array_equal(lines[0].get_ydata(), traj["normal_force_ellipsoid"])
    forces = [a for a in fig.axes if a.get_ylabel() == "normal force N (N)"][0]
    assert "@" not in forces.get_title() and "sliding orange" in forces.get_title()
    one = traj.plot(columns=["normal_force_stem"])
    assert one.get_ylabel() == "normal_force_stem (N)"
    top = tippe_top()
    assert not any(a.get_ylabel() == "normal force N_S (N)" for a in top.plot())
    with pytest.raises(ValueError, match="the surfaces panel needs the per-surface columns `normal_force_S`"):
        top.plot("surfaces")


def test_both_renderers_draw_the_surfaces_panel_alike(cli: Path, tmp_path: Path) -> None:
    """`ellipsoid plot` of the stem scene's CSV draws the surfaces panel by default, with
    the titles, labels and legend entries `Trajectory.plot` draws."""
    pytest.importorskip("matplotlib")
    run = [str(cli), "run", str(SCENARIOS / "tippe-top-stem.toml"), "--set", "output.t_end=1.6",
           "-o", str(tmp_path / "run.csv"), "--summary", str(tmp_path / "run.json"), "-q"]
    subprocess.run(run, check=True)
    subprocess.run([str(cli), "plot", str(tmp_path / "run.csv"), "--summary", str(tmp_path / "run.json"),
                    "-o", str(tmp_path / "fig.svg"), "--panels", "forces,surfaces", "-q"], check=True)
    texts = svg_texts(tmp_path / "fig.svg")
    fig = stem_top().plot("forces,surfaces")[0].figure
    for ax in fig.axes:
        for text in [ax.get_title(), ax.get_ylabel()] + [t.get_text() for t in ax.get_legend().get_texts()]:
            assert text in texts, f"matplotlib draws {text!r}, ellipsoid plot does not"


def test_view_of_a_body_with_a_stem_is_the_command_line_s(cli: Path, tmp_path: Path) -> None:
    """The stem scene's page: the same as `ellipsoid view` makes from the CSV and its
    summary, carrying the stem and which surface touches, and by default
    each surface's normal force; a per-surface column the run lacks is refused."""
    scenario = str(SCENARIOS / "tippe-top-stem.toml")
    subprocess.run([str(cli), "run", scenario, "-o", str(tmp_path / "s.csv"), "--summary", str(tmp_path / "s.json"),
                    "--set", "output.t_end=1.6", "-q"], check=True)
    subprocess.run([str(cli), "view", str(tmp_path / "s.csv"), "--summary", str(tmp_path / "s.json"),
                    "-o", str(tmp_path / "cli.html"), "--title", "s", "-q"], check=True)
    traj = stem_top()
    page = traj.view(title="s")
    assert page == (tmp_path / "cli.html").read_text(encoding="utf-8")
    assert '"spheres":[{"name":"stem","center":[0.0,0.0,0.013],"radius":0.005}]' in page
    assert '"name":"normal_force_*","label":"normal_force of each surface (N)"' in page
    with pytest.raises(ellipsoid.ScenarioError, match="normal_force_stme"):
        traj.view(columns="theta,normal_force_stme")
