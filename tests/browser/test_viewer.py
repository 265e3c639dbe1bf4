"""The viewer page (`ellipsoid view`) in a real browser: headless Chromium from the system
packages, driven over the DevTools protocol (tests/browser/cdp.py). Each test builds its
page from a real run of the `ellipsoid` binary and checks what a person would see."""

from __future__ import annotations

import math
import subprocess
import time
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[2]

# A prolate uniform ellipsoid (a = b = 0.02 m, c = 0.04 m) at rest: upright (θ = 0) it
# stands on its tip, on its side (θ = π/2, φ = 0) its axis lies along −y.
EGG = """
[body]
a = 0.02
c = 0.04
mass = 0.1
inertia = "uniform"
[initial]
theta = {theta}
[contact]
model = "frictionless"
[output]
t_end = 0.05
dt = 0.01
"""


def run(cli: Path, tmp: Path, scenario: Path, name: str, *sets: str, ext: str = "csv") -> Path:
    out = tmp / f"{name}.{ext}"
    summary = tmp / f"{name}.json"
    args = [str(cli), "run", str(scenario), "-o", str(out), "--summary", str(summary), "-q"]
    for s in sets:
        args += ["--set", s]
    done = subprocess.run(args, capture_output=True, text=True)
    assert done.returncode in (0, 3), done.stderr
    html = tmp / f"{name}.html"
    view = [str(cli), "view", str(out), "-o", str(html), "-q"] + (["--summary", str(summary)] if ext == "csv" else [])
    done = subprocess.run(view, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return html


def open_page(page, html: Path) -> float:
    page.goto(html.as_uri())
    return page.wait("document.body && document.body.dataset.ready === '1'")


def scene_shot(page):
    return page.screenshot(page.rect("#scene canvas"))


def body_mask(img: np.ndarray) -> np.ndarray:
    """Pixels of the body's painted parts: saturated colours (blue meridians, orange band,
    red axis); the sky, the plane and the grid are nearly grey."""
    return (img.max(axis=2) - img.min(axis=2)) > 60


def test_page_loads_offline_without_console_errors(cli: Path, tmp_path: Path, page) -> None:
    html = run(cli, tmp_path, REPO / "scenarios/tippe-top.toml", "tt", "output.t_end=1.5")
    open_page(page, html)
    page.pump(0.3)
    assert page.errors() == []
    for url in page.requests():
        assert url.startswith(("file:", "blob:", "data:")), f"network request: {url}"
    assert page.eval("document.getElementById('three-license').textContent").count("three.js authors") == 1
    info = page.eval("({f: ellipsoidViewer.frames, s: ellipsoidViewer.shapeKnown, c: ellipsoidViewer.contactKnown, r: ellipsoidViewer.rendered()})")
    assert info["f"] == 1501 and info["s"] and info["c"] and info["r"] >= 1
    assert "slip stop" in page.eval("document.getElementById('events').textContent")
    img = scene_shot(page)
    assert img.std() > 10, "the 3-D view is blank"
    assert body_mask(img).sum() > 2000, "the body is not drawn"


def test_the_body_is_drawn_where_and_as_the_trajectory_puts_it(cli: Path, tmp_path: Path, page) -> None:
    boxes = {}
    for name, theta in (("upright", 0.0), ("lying", math.pi / 2)):
        toml = tmp_path / f"{name}.toml"
        toml.write_text(EGG.format(theta=theta))
        open_page(page, run(cli, tmp_path, toml, name))
        # Camera on the +x side, level: world y runs across the screen, z up it.
        page.eval("ellipsoidViewer.setCamera({az: 0, el: 0.05, dist: 0.4})")
        img = scene_shot(page)
        ys, xs = np.nonzero(body_mask(img))
        assert len(xs) > 1000, f"{name}: body not visible"
        boxes[name] = (xs.max() - xs.min(), ys.max() - ys.min())
        # Its centre C0 (G + R·(0, 0, 0) here: no offset) projects where the pixels are.
        p = page.eval("ellipsoidViewer.pose()")
        r = page.rect("#scene canvas")
        cx, cy = page.eval(f"ellipsoidViewer.project({p['x']}, {p['y']}, {p['z']})")
        assert abs(xs.mean() + r["x"] - cx) < 12 and abs(ys.mean() + r["y"] - cy) < 12, f"{name}: body centre at {(xs.mean(), ys.mean())}, G projects to {(cx - r['x'], cy - r['y'])}"
        assert page.errors() == []
    (wu, hu), (wl, hl) = boxes["upright"], boxes["lying"]
    assert hu > 1.5 * wu, f"upright egg drawn {wu}×{hu} px: should be tall"
    assert wl > 1.5 * hl, f"lying egg drawn {wl}×{hl} px: should be wide"


def test_the_slider_changes_the_pose_and_play_advances_time(cli: Path, tmp_path: Path, page) -> None:
    html = run(cli, tmp_path, REPO / "scenarios/nutation.toml", "nut", "output.t_end=1")
    open_page(page, html)
    before = scene_shot(page)
    slider = page.rect("#slider")
    # A click at 60 % of the slider's track, as a user would.
    page.click(slider["x"] + 0.6 * slider["width"], slider["y"] + slider["height"] / 2)
    page.pump(0.2)
    t = page.eval("ellipsoidViewer.time()")
    assert 0.5 < t < 0.7, f"slider at 60 % gave t = {t}"
    after = scene_shot(page)
    changed = (np.abs(after - before).max(axis=2) > 40).mean()
    assert changed > 0.01, f"only {100 * changed:.2f} % of the view changed with the time"
    assert abs(page.eval("ellipsoidViewer.pose().psi") - page.eval(f"ellipsoidViewer.pose({t})").get("psi")) < 1e-9
    page.eval("ellipsoidViewer.seek(0)")
    page.click(*(lambda r: (r["x"] + r["width"] / 2, r["y"] + r["height"] / 2))(page.rect("#play")))
    start = time.monotonic()
    page.pump(0.8)
    t1 = page.eval("ellipsoidViewer.time()")
    assert page.eval("ellipsoidViewer.playing()")
    elapsed = time.monotonic() - start
    assert 0.05 * elapsed < t1 <= 0.25 * elapsed + 0.05, f"playing at 0.25x for {elapsed:.2f} s reached t = {t1}"
    assert page.errors() == []


def cursor_column(img: np.ndarray) -> float:
    """Mean x of the plot cursor (exactly rgb(220, 0, 0))."""
    hit = (np.abs(img[:, :, 0] - 220) < 12) & (img[:, :, 1] < 25) & (img[:, :, 2] < 25)
    cols = np.nonzero(hit.sum(axis=0) > 20)[0]
    assert len(cols), "no cursor in the plot"
    return float(cols.mean())


def test_the_plot_cursor_follows_the_slider(cli: Path, tmp_path: Path, page) -> None:
    html = run(cli, tmp_path, REPO / "scenarios/nutation.toml", "nut", "output.t_end=2")
    open_page(page, html)
    slider = page.rect("#slider")
    xs = []
    for frac in (0.25, 0.75):
        page.click(slider["x"] + frac * slider["width"], slider["y"] + slider["height"] / 2)
        page.pump(0.15)
        t = page.eval("ellipsoidViewer.time()")
        plot = page.rect("#plot-theta")
        x = cursor_column(page.screenshot(plot))
        want = page.eval(f"ellipsoidViewer.plotX('theta', {t})")
        assert abs(x + 0.5 - want) < 2.5, f"cursor at {x}, t = {t} belongs at {want}"
        xs.append(x)
    # Half the run apart: half the plot width (360 px less the 80 px of margins) apart.
    assert abs((xs[1] - xs[0]) - 0.5 * 280) < 6, xs
    assert page.errors() == []


def test_a_million_samples_open_in_under_two_seconds(cli: Path, tmp_path: Path, page) -> None:
    import os

    ext = "h5" if os.environ.get("ELLIPSOID_EXPECT_HDF5") == "1" else "csv"
    html = run(cli, tmp_path, REPO / "scenarios/nutation.toml", "big", "output.dt=1e-5", ext=ext)
    info = subprocess.run([str(cli), "view", str(tmp_path / f"big.{ext}"), "-o", str(tmp_path / "big2.html")], capture_output=True, text=True)
    assert "1000001 rows" in info.stderr, info.stderr
    open_page(page, html)
    ready_ms = page.eval("ellipsoidViewer.readyAt")
    frames = page.eval("ellipsoidViewer.frames")
    assert frames <= 20_010, frames
    assert ready_ms < 2000, f"the page took {ready_ms:.0f} ms to show the first frame"
    print(f"10^6 samples: {html.stat().st_size / 1e6:.1f} MB page, {frames} poses, ready in {ready_ms:.0f} ms")
    assert page.errors() == []


def test_the_side_plots_are_the_columns_asked_for(cli: Path, tmp_path: Path, page) -> None:
    """`--columns` chooses the side plots (a rattleback wants its vertical spin): one drawn
    canvas each, in the order asked, with the cursor."""
    out, summary = tmp_path / "rb.csv", tmp_path / "rb.json"
    subprocess.run([str(cli), "run", str(REPO / "scenarios/rattleback.toml"), "-o", str(out), "--summary", str(summary),
                    "--set", "output.t_end=5", "-q"], check=True)
    html = tmp_path / "rb.html"
    subprocess.run([str(cli), "view", str(out), "--summary", str(summary), "-o", str(html),
                    "--columns", "omega_world_z,theta,slip_speed", "-q"], check=True)
    open_page(page, html)
    page.pump(0.2)
    ids = page.eval("[...document.querySelectorAll('#plots canvas')].map((c) => c.id)")
    assert ids == ["plot-omega_world_z", "plot-theta", "plot-slip_speed"]
    for name in ("omega_world_z", "theta"):
        img = page.screenshot(page.rect(f"#plot-{name}"))
        blue = (abs(img[..., 0] - 0x1f) < 40) & (abs(img[..., 1] - 0x77) < 40) & (abs(img[..., 2] - 0xb4) < 40)
        assert blue.sum() > 200, f"{name}: no curve drawn"
        cursor_column(img)  # the cursor is drawn (asserts)
    assert page.errors() == []


def test_a_long_event_list_scrolls(cli: Path, tmp_path: Path, page) -> None:
    """300 events: the list keeps its height and scrolls, the plots stay in view."""
    import json

    out, summary = tmp_path / "tt.csv", tmp_path / "tt.json"
    subprocess.run([str(cli), "run", str(REPO / "scenarios/tippe-top.toml"), "-o", str(out), "--summary", str(summary),
                    "--set", "output.t_end=1.5", "-q"], check=True)
    data = json.loads(summary.read_text(encoding="utf-8"))
    data["events"] = [{"kind": "observed", "name": f"e{k}", "t": 0.005 * k} for k in range(300)]
    summary.write_text(json.dumps(data), encoding="utf-8")
    html = tmp_path / "tt.html"
    subprocess.run([str(cli), "view", str(out), "--summary", str(summary), "-o", str(html), "-q"], check=True)
    open_page(page, html)
    box = page.eval("(() => { const e = document.getElementById('events'); e.scrollTop = 1e6;"
                    " return {n: e.children.length, h: e.clientHeight, full: e.scrollHeight, top: e.scrollTop}; })()")
    assert box["n"] == 300
    assert box["h"] < 400 and box["full"] > 3 * box["h"] and box["top"] > 0, box
    assert page.rect("#plot-energy")["y"] < 800, "the plots above the list stay in view"


def test_a_failed_webgl_context_says_so_on_the_page(cli: Path, tmp_path: Path, page) -> None:
    """A browser that gives no WebGL context (as a GPU-less one may): the page says why
    there is no 3-D view instead of staying blank, and loses only that (issue 47): the
    plots, the event list, the slider and the HUD work, the plot cursor following the
    slider."""
    # The tippe top with its contact disc: two events in 2 s (its inversion observed).
    html = run(cli, tmp_path, REPO / "scenarios/tippe-top-disc.toml", "top", "output.t_end=2")
    script = page.send("Page.addScriptToEvaluateOnNewDocument", {"source": (
        "const get = HTMLCanvasElement.prototype.getContext;"
        "HTMLCanvasElement.prototype.getContext = function (kind, ...rest) {"
        " return /webgl/.test(kind) ? null : get.call(this, kind, ...rest); };")})
    try:
        page.goto(html.as_uri())
        page.wait("document.body && document.body.dataset.ready === '1'")
        text = page.eval("document.getElementById('error').textContent")
        assert "WebGL is not available in this browser" in text and "3-D view cannot be drawn" in text, text
        shown = page.rect("#error")
        assert shown["width"] > 100 and shown["height"] > 5, "the message is visible"
        assert page.eval("ellipsoidViewer.webgl") is False
        assert page.eval("document.querySelectorAll('#scene canvas').length") == 0
        assert page.eval("document.getElementById('events').children.length") == 2, "the event list"
        slider = page.rect("#slider")
        for frac in (0.25, 0.75):
            page.click(slider["x"] + frac * slider["width"], slider["y"] + slider["height"] / 2)
            page.pump(0.15)
            t = page.eval("ellipsoidViewer.time()")
            assert abs(t - frac * 2.0) < 0.1, t
            assert f"t = {t:.4f} s" in page.eval("document.getElementById('hud').textContent")
            x = cursor_column(page.screenshot(page.rect("#plot-theta")))
            want = page.eval(f"ellipsoidViewer.plotX('theta', {t})")
            assert abs(x + 0.5 - want) < 2.5, f"cursor at {x}, t = {t} belongs at {want}"
        assert [e for e in page.errors() if "WebGL" not in e] == []
    finally:
        page.send("Page.removeScriptToEvaluateOnNewDocument", {"identifier": script["identifier"]})



def hue_mask(img: np.ndarray, hue: str) -> np.ndarray:
    """Pixels whose colour is clearly `hue`: "green" (the mark of a surface in contact) or
    "violet" (a contact sphere that does not touch)."""
    r, g, b = (img[..., k].astype(int) for k in range(3))
    if hue == "green":
        return (g > r + 40) & (g > b + 30)
    return (r > g + 15) & (b > g + 30)


def test_the_stem_is_drawn_and_the_surface_in_contact_marked(cli: Path, tmp_path: Path, page) -> None:
    """The tippe top with its stem (tippe-top-stem.toml): the stem is drawn fixed in the
    body, violet while the ball carries the top and green once the stem touches (at
    1.372 s, mode sliding@stem); the default side plots add each surface's normal force,
    one line per surface."""
    html = run(cli, tmp_path, REPO / "scenarios/tippe-top-stem.toml", "stem", "output.t_end=1.6")
    open_page(page, html)
    assert page.eval("ellipsoidViewer.surfaces()") == ["ellipsoid", "stem"]
    ids = page.eval("[...document.querySelectorAll('#plots canvas')].map((c) => c.id)")
    assert ids == ["plot-theta", "plot-energy", "plot-normal_force-each"]
    forces = page.screenshot(page.rect("#plot-normal_force-each"))
    for name, rgb in (("ellipsoid", (0x1F, 0x77, 0xB4)), ("stem", (0xFF, 0x7F, 0x0E))):
        near = (np.abs(forces[..., :3].astype(int) - rgb) < 40).all(axis=2)
        assert near.sum() > 100, f"no line of the {name}'s normal force"
    shots = {}
    for t, touching in ((0.3, ["ellipsoid"]), (1.5, ["stem"])):
        page.eval(f"ellipsoidViewer.seek({t})")
        # A level camera on the side, close: the stem is in view whether it is up or down.
        page.eval("ellipsoidViewer.setCamera({az: -0.9, el: 0.0, dist: 0.09})")
        assert page.eval("ellipsoidViewer.touching()") == touching, t
        img = scene_shot(page)
        r = page.rect("#scene canvas")
        # Where the stem stands out of the ball: 3.5 mm beyond its centre (r2 = 5 mm),
        # 16.5 mm from the ball's centre C0 = G − R g (r1 = 15 mm, g = −3 mm on the axis).
        p = page.eval("ellipsoidViewer.pose()")
        axis = np.array([math.sin(p["phi"]) * math.sin(p["theta"]), -math.cos(p["phi"]) * math.sin(p["theta"]), math.cos(p["theta"])])
        c0 = np.array([p["x"], p["y"], p["z"]]) + 0.003 * axis
        stem = np.array(page.eval("ellipsoidViewer.sphereCentre('stem')"))
        assert abs(np.linalg.norm(stem - c0) - 0.013) < 1e-6, "the stem is 13 mm from the ball's centre"
        out = stem + 0.0035 * (stem - c0) / np.linalg.norm(stem - c0)
        x, y = page.eval(f"ellipsoidViewer.project({out[0]}, {out[1]}, {out[2]})")
        i, j = int(x - r["x"]), int(y - r["y"])
        shots[t] = img[max(j - 3, 0):j + 4, max(i - 3, 0):i + 4]
        assert page.errors() == []
    # Before the stem touches: drawn in its own colour, not marked; on the stem: marked.
    assert hue_mask(shots[0.3], "violet").mean() > 0.5, "the stem is not drawn"
    assert hue_mask(shots[0.3], "green").mean() == 0, "an open stem is marked"
    assert hue_mask(shots[1.5], "green").mean() > 0.3, "the stem in contact is not marked"


def test_a_coin_is_drawn_with_its_rim_marked_where_it_touches(cli: Path, tmp_path: Path, page) -> None:
    """The coin of coin.toml touches with its rim alone (its ellipsoid does not touch): the
    page names that one surface, draws the rim as its torus about G (the rim's centre is
    the coin's centre, G), green while it rolls on it, and the ellipsoid never glows."""
    html = run(cli, tmp_path, REPO / "scenarios/coin.toml", "coin", "output.t_end=1.0")
    open_page(page, html)
    assert page.eval("ellipsoidViewer.surfaces()") == ["edge"]
    page.eval("ellipsoidViewer.seek(0.5)")
    page.eval("ellipsoidViewer.setCamera({az: -0.9, el: 0.3, dist: 0.08})")
    assert page.eval("ellipsoidViewer.touching()") == ["edge"]
    assert page.eval("ellipsoidViewer.rimColour('edge')") == 0x2CA02C
    p = page.eval("ellipsoidViewer.pose()")
    centre = np.array(page.eval("ellipsoidViewer.rimCentre('edge')"))
    assert np.linalg.norm(centre - np.array([p["x"], p["y"], p["z"]])) < 1e-7
    img = scene_shot(page)
    assert hue_mask(img, "green").sum() > 200, "the rim in contact is not drawn green"
    assert page.errors() == []
