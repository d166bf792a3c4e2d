"""``mvtools report``: the page of a build folder, checked in a real browser (Debian's
headless Chromium) that every picture is shown, with a screenshot."""

from __future__ import annotations

import base64
import html
import json
import math
import os
import re
import shutil
import subprocess
from pathlib import Path

import cv2
import numpy as np
import pytest
from program_runner import invoke

from mvtools.cli import calibrate, evaluate, report
from mvtools.io.images import read_image
from mvtools.io.yuv import YuvFormat, open_writer
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


# --------------------------------------------------------------------------- scores along frames

WIDTH, HEIGHT = 32, 16
# frame k of the test video: the reference's luma + 4 k (frame 0 identical)
OFFSETS = (0, 4, 8, 12)


@pytest.fixture(scope="module")
def scored_pair(tmp_path_factory) -> tuple[Path, Path, Path]:
    """A 4-frame reference and test video (uniform luma 60 + 30 k, grey chroma; the
    test's luma higher by OFFSETS[k]), and the table mvtools evaluate printed of them."""
    folder = tmp_path_factory.mktemp("scores")
    fmt = YuvFormat.from_pix_fmt(WIDTH, HEIGHT, "yuv420p")
    reference, test = folder / "ref_32x16_yuv420p.yuv", folder / "test_32x16_yuv420p.yuv"
    chroma = np.full((HEIGHT // 2, WIDTH // 2), 128, np.uint8)
    with open_writer(reference, fmt) as ref_writer, open_writer(test, fmt) as test_writer:
        for k, offset in enumerate(OFFSETS):
            luma = np.full((HEIGHT, WIDTH), 60 + 30 * k, np.uint8)
            ref_writer.write((luma, chroma, chroma))
            test_writer.write((luma + offset, chroma, chroma))
    code, stdout, stderr = invoke(evaluate.command, reference, test)
    assert code == 0, stderr
    (folder / "pair.scores").write_text(stdout)
    return folder, reference, test


def _pictures_of(page: str) -> list[tuple[str, np.ndarray]]:
    """(caption, decoded picture) of every picture embedded in ``page``."""
    pictures = []
    for data, caption in re.findall(
        r'<img src="data:image/png;base64,([^"]+)" alt="([^"]*)">', page
    ):
        pictures.append(
            (
                html.unescape(caption),
                cv2.imdecode(np.frombuffer(base64.b64decode(data), np.uint8), cv2.IMREAD_COLOR)[
                    ..., ::-1
                ],
            )
        )
    return pictures


def test_scores_of_several_frames_show_as_a_plot_and_a_contact_sheet(scored_pair):
    folder, _, test = scored_pair
    code, _, stderr = invoke(report.command, folder)
    assert code == 0, stderr
    page = (folder / "report.html").read_text()
    # the plot: the luma PSNR of frames 1..3, 20 log10(255 / d) dB; frame 0's is infinite
    assert page.count("<svg") == 1
    svg = page[page.index("<svg") : page.index("</svg>")]
    assert ">Y-PSNR</text>" in svg and "U-PSNR" not in svg
    assert "frames 0 left out (infinite PSNR" in page
    ys = [float(y) for y in re.findall(r'<circle cx="[^"]+" cy="([^"]+)"', svg)]
    xs = [float(x) for x in re.findall(r'<circle cx="([^"]+)"', svg)]
    assert len(ys) == 3
    # x: equal steps of frames; y: the dB differences 20 log10(2) and 20 log10(1.5), the
    # higher PSNR the higher up (smaller y)
    assert xs[1] - xs[0] == pytest.approx(xs[2] - xs[1], abs=0.2)
    assert ys[0] < ys[1] < ys[2]
    assert (ys[1] - ys[0]) / (ys[2] - ys[1]) == pytest.approx(
        math.log10(2) / math.log10(1.5), rel=0.03
    )
    # the contact sheet: one picture of the pair, a row per frame
    sheets = [
        (caption, picture) for caption, picture in _pictures_of(page) if "pair.scores" in caption
    ]
    assert len(sheets) == 1
    caption, sheet = sheets[0]
    assert caption.endswith(f"{test.name} | error x4, frames 0, 1, 2, 3")
    assert sheet.shape == (len(OFFSETS) * HEIGHT, 3 * WIDTH, 3)
    scale = 255 / 219  # limited-range luma to RGB, grey chroma
    for k, offset in enumerate(OFFSETS):
        row = sheet[k * HEIGHT : (k + 1) * HEIGHT].astype(int)
        reference_panel, test_panel, error = (row[:, i * WIDTH : (i + 1) * WIDTH] for i in range(3))
        # the frames in order: the reference's grey of frame k
        assert np.all(np.abs(reference_panel - scale * (60 + 30 * k - 16)) <= 1)
        assert np.all(np.abs(test_panel - scale * (60 + 30 * k + offset - 16)) <= 1)
        # the error x4: zero where the frames are identical (frame 0)
        if offset == 0:
            assert not error.any()
        else:
            assert np.all(np.abs(error - 4 * scale * offset) <= 4)


def test_scores_of_one_frame_keep_the_single_comparison(scored_pair, tmp_path):
    _, reference, test = scored_pair
    code, stdout, stderr = invoke(evaluate.command, reference, test, "--frames", 1)
    assert code == 0, stderr
    (tmp_path / "one.scores").write_text(stdout)
    code, _, stderr = invoke(report.command, tmp_path)
    assert code == 0, stderr
    page = (tmp_path / "report.html").read_text()
    # no plot of one point, and the first frame alone: identical, no error
    assert "<svg" not in page
    ((caption, picture),) = _pictures_of(page)
    assert caption == f"one.scores: {reference.name} | {test.name} | error"
    assert picture.shape == (HEIGHT, 3 * WIDTH, 3)
    assert not picture[:, 2 * WIDTH :].any()


def test_a_long_video_shows_six_frames_spread_over_it():
    assert report._spread(list(range(10))) == [0, 2, 4, 5, 7, 9]
    assert report._spread(list(range(7))) == [0, 1, 2, 4, 5, 6]
    assert report._spread([3, 4]) == [3, 4]
