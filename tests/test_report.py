"""``mvtools report``: the page of a build folder, checked in a real browser (Debian's
headless Chromium) that every picture is shown, with a screenshot."""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
from program_runner import invoke

from mvtools.cli import calibrate, evaluate, report
from mvtools.io.images import read_image
from mvtools.report import bar_plot, line_plot

SAMPLE = Path(__file__).resolve().parent.parent / "sample_data"
LINE = SAMPLE / "line"
CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")

needs_chromium = pytest.mark.skipif(
    CHROMIUM is None and os.environ.get("MVTOOLS_REQUIRE_DATA") != "1",
    reason="Debian's chromium is not installed (.ci/run installs it)",
)


@pytest.fixture(scope="module")
def build(tmp_path_factory) -> Path:
    """A build folder as the pipeline leaves one: a calibration, videos, a scores file."""
    folder = tmp_path_factory.mktemp("build")
    code, _, stderr = invoke(
        calibrate.command,
        SAMPLE / "checkerboard" / "cam1",
        SAMPLE / "checkerboard" / "cam2",
        "--board",
        "9x6",
        "--square",
        0.05,
        "-o",
        folder / "rig.txt",
        "--report",
        folder / "calibration",
    )
    assert code == 0, stderr
    for name in (
        "v1_texture_256x192_yuv420p.yuv",
        "v2_texture_256x192_yuv420p.yuv",
        "v2_depth_256x192_yuv420p.yuv",
    ):
        shutil.copy(LINE / name, folder / name)
    code, stdout, stderr = invoke(
        evaluate.command,
        folder / "v2_texture_256x192_yuv420p.yuv",
        folder / "v1_texture_256x192_yuv420p.yuv",
    )
    assert code == 0, stderr
    (folder / "v1_against_v2.scores").write_text(stdout)
    # the 8-bit depth of camera 2 against its 16-bit truth: quantisation alone, below
    # 0.02 px of disparity towards camera 3 (fx 240 x baseline 0.1 / z, 1/z in 255 steps)
    code, _, stderr = invoke(
        evaluate.command,
        "--depth",
        LINE / "v2_depth_256x192_gray16le.yuv",
        folder / "v2_depth_256x192_yuv420p.yuv",
        "--reference-depth-range",
        2,
        13,
        "--test-depth-range",
        2,
        13,
        "--cameras",
        LINE / "cameras.txt",
        "--camera",
        "cam2",
        "--neighbour",
        "cam3",
        "--json-file",
        folder / "v2_depth.errors.json",
    )
    assert code == 0, stderr
    return folder


@pytest.fixture(scope="module")
def page(build) -> str:
    code, _, stderr = invoke(report.command, build)
    assert code == 0, stderr
    return (build / "report.html").read_text()


@pytest.mark.slow
def test_page_holds_every_stage(page):
    # 2 corner pictures, 3 videos, 1 comparison of the scored pair
    assert page.count("<img ") == 6
    for heading in ("Calibration", "Pictures", "Scores", "Depth and disparity errors"):
        assert f"<h2>{heading}" in page
    # the depth errors' table: no pixel off by 1 px
    assert re.search(r"<td>v2_depth</td><td>0</td><td>0</td><td>0\.0\d+</td>", page)
    assert "cam1" in page and "cam2" in page
    # the scores table holds evaluate's figures: the mean Y-PSNR of view 1 against view 2
    assert re.search(r"<td>mean</td><td>2\d\.\d\d</td>", page)


def test_rate_distortion_runs_show_as_curves_not_pictures(tmp_path):
    # an encode folder: its report and a decoded video, next to a video of the pipeline
    shutil.copy(LINE / "v1_texture_256x192_yuv420p.yuv", tmp_path)
    run = tmp_path / "compression"
    (run / "packed").mkdir(parents=True)
    shutil.copy(LINE / "v2_texture_256x192_yuv420p.yuv", run / "packed")
    points = [
        {"qp": qp, "kbps": rate, "mean_texture_yuv_psnr": psnr}
        for qp, rate, psnr in ((22, 900.0, 44.0), (32, 300.0, 37.0))
    ]
    (run / "report.json").write_text(json.dumps({"modes": {"simulcast": points}}))
    code, _, stderr = invoke(report.command, tmp_path)
    assert code == 0, stderr
    page = (tmp_path / "report.html").read_text()
    assert page.count("<img ") == 1 and "v1_texture" in page and "packed/" not in page
    assert "<h2>Compression" in page and page.count("<circle ") == 2


def test_plots_place_points_where_the_values_say():
    svg = bar_plot({"a": [1.0, 2.0], "b": [2.0]}, y_label="px")
    # the bars (the plot's frame is a rect without fill)
    heights = [float(value) for value in re.findall(r'height="([^"]+)" fill="#', svg)]
    # drawn to 0.1 px
    assert heights[1] == pytest.approx(2 * heights[0], abs=0.2)
    assert heights[2] == pytest.approx(heights[1], abs=0.2)
    # with series, the bars of a group take the series' colours, named in a legend
    svg = bar_plot({"0-1": [50.0, 10.0], "1-2": [50.0, 90.0]}, y_label="%", series=["x", "y"])
    colours = re.findall(r'height="[^"]+" fill="(#[0-9a-f]+)"', svg)
    assert colours[0] == colours[2] != colours[1] == colours[3]
    assert f'fill="{colours[1]}">y</text>' in svg
    with pytest.raises(ValueError, match="more bars than the 1 series"):
        bar_plot({"a": [1.0, 2.0]}, y_label="%", series=["x"])
    svg = line_plot(
        {"s": [(100.0, 30.0), (1000.0, 40.0), (10000.0, 50.0)]},
        x_label="kbit/s",
        y_label="dB",
        log_x=True,
    )
    xs = [float(x) for x in re.findall(r'<circle cx="([^"]+)"', svg)]
    # equal steps in log rate are equal steps across the plot
    assert xs[1] - xs[0] == pytest.approx(xs[2] - xs[1], abs=0.2)


@pytest.mark.slow
@needs_chromium
def test_every_picture_shows_in_a_browser(build, page, tmp_path):
    options = [
        CHROMIUM,
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--no-first-run",
        "--disable-background-networking",
        "--disable-component-update",
        "--disable-sync",
        "--window-size=1200,2400",
    ]
    url = (build / "report.html").resolve().as_uri()
    dom = subprocess.run(
        [*options, f"--user-data-dir={tmp_path / 'profile1'}", "--dump-dom", url],
        capture_output=True,
        text=True,
        timeout=120,
    ).stdout
    # the page's own count, once every picture has loaded
    assert re.search(r"<title>[^<]*: 6 of 6 pictures</title>", dom), dom[:300]
    screenshot = tmp_path / "report.png"
    subprocess.run(
        [*options, f"--user-data-dir={tmp_path / 'profile2'}", f"--screenshot={screenshot}", url],
        capture_output=True,
        timeout=120,
    )
    picture = read_image(screenshot)
    assert picture.shape[:2] == (2400, 1200)
    # pictures, not an empty page: many distinct colours
    assert len(np.unique(picture.reshape(-1, picture.shape[-1]), axis=0)) > 1000
