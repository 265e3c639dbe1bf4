"""`Trajectory.animate` (and `ellipsoid animate`, the same renderer): a GIF rendered
without a browser."""

from __future__ import annotations

import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

import ellipsoid
from conftest import REPO

Image = pytest.importorskip("PIL.Image")


def test_gif_frames_timing_and_the_body_where_g_is(tmp_path: Path) -> None:
    traj = ellipsoid.simulate(REPO / "scenarios" / "tippe-top.toml", output={"t_end": 2.0})
    path = tmp_path / "top.gif"
    frames = traj.animate(path, width=240, height=180, fps=20, speed=0.5)
    assert frames == int(2.0 / (0.5 / 20)) + 1 == 81
    im = Image.open(path)
    assert im.size == (240, 180) and im.n_frames == frames
    assert im.info["duration"] == 50  # 1/20 s per frame
    assert path.stat().st_size < 3_000_000
    # The top stays near the origin: the frame's middle third holds the body (not the
    # plane's two greys), the corners do not.
    rgb = np.asarray(im.convert("RGB"), dtype=int)
    plane = {(222, 226, 232), (200, 206, 214)}
    middle = {tuple(p) for p in rgb[60:120, 80:160].reshape(-1, 3)}
    assert len(middle - plane - {(255, 255, 255), (20, 20, 20)}) > 10
    assert tuple(rgb[-1, -1]) in plane and tuple(rgb[-1, 0]) in plane
    with pytest.raises(ellipsoid.ScenarioError, match="fps = 0"):
        traj.animate(tmp_path / "x.gif", fps=0)
    with pytest.raises(ellipsoid.ScenarioError, match="written as .gif, or as .mp4"):
        traj.animate(tmp_path / "x.avi")


def test_mp4_without_ffmpeg_says_what_is_missing(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    traj = ellipsoid.simulate(REPO / "scenarios" / "tippe-top.toml", output={"t_end": 0.2})
    monkeypatch.setenv("ELLIPSOID_FFMPEG", str(tmp_path / "no-such-ffmpeg"))
    with pytest.raises(ellipsoid.OutputError, match=r"top.mp4: MP4 needs ffmpeg, .*no-such-ffmpeg.*apt-get install ffmpeg.*write a GIF"):
        traj.animate(tmp_path / "top.mp4")
    assert list(tmp_path.iterdir()) == [], "nothing written"


def have_ffmpeg() -> bool:
    try:
        return subprocess.run(["ffmpeg", "-version"], capture_output=True).returncode == 0
    except OSError:
        return False


@pytest.mark.skipif(not have_ffmpeg() and os.environ.get("ELLIPSOID_EXPECT_FFMPEG") != "1", reason="no ffmpeg (apt-get install ffmpeg)")
def test_mp4_where_ffmpeg_exists_has_the_gif_s_frames(tmp_path: Path) -> None:
    traj = ellipsoid.simulate(REPO / "scenarios" / "tippe-top.toml", output={"t_end": 2.0})
    frames = traj.animate(tmp_path / "top.mp4", width=241, height=181, fps=20, speed=0.5)
    data = (tmp_path / "top.mp4").read_bytes()
    assert frames == 81 and data[4:8] == b"ftyp" and len(data) > 10_000
    probe = subprocess.run(["ffprobe", "-v", "error", "-count_frames", "-show_entries", "stream=codec_name,width,height,nb_read_frames",
                            "-of", "csv=p=0", str(tmp_path / "top.mp4")], capture_output=True, text=True)
    if probe.returncode == 0:  # ffprobe comes with ffmpeg: H.264, the odd sides padded to even
        assert probe.stdout.strip() == "h264,242,182,81", probe.stdout


def test_the_cli_writes_the_same_gif(tmp_path: Path, cli: Path) -> None:
    scenario = REPO / "scenarios" / "egg-jump.toml"
    csv, summary = tmp_path / "egg.csv", tmp_path / "egg.json"
    subprocess.run([cli, "run", scenario, "-o", csv, "--summary", summary, "--set", "output.t_end=0.5", "-q"], check=True)
    subprocess.run([cli, "animate", csv, "--summary", summary, "-o", tmp_path / "cli.gif", "--width", "160", "--height", "120", "-q"], check=True)
    traj = ellipsoid.simulate(scenario, output={"t_end": 0.5})
    traj.animate(tmp_path / "py.gif", width=160, height=120)
    a = Image.open(tmp_path / "cli.gif")
    b = Image.open(tmp_path / "py.gif")
    assert a.n_frames == b.n_frames == 13
    for k in (0, 6, 12):
        a.seek(k)
        b.seek(k)
        diff = np.abs(np.asarray(a.convert("RGB"), dtype=int) - np.asarray(b.convert("RGB"), dtype=int))
        assert (diff.max(axis=2) > 0).mean() < 0.01, k  # the CSV's round trip moves a few edge pixels at most


def test_ctrl_c_interrupts_an_animation(tmp_path: Path) -> None:
    # Issue 48: Ctrl-C ran the animation to its end; now it stops before the next frame,
    # raises KeyboardInterrupt and writes nothing.
    from conftest import INTERRUPT_MAIN, interrupt_inside

    traj = ellipsoid.simulate(ellipsoid.load(REPO / "scenarios" / "nutation.toml", output={"t_end": 20.0, "dt": 1e-3}))
    out = tmp_path / "long.gif"
    # 1981 frames of 2000 × 2000 px (20 s at 100 fps, 1.01 simulated seconds per second).
    interrupt_inside(INTERRUPT_MAIN, traj.animate, out, width=2000, height=2000, fps=100, speed=1.01)
    assert not out.exists()
