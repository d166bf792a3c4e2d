"""``mvtools encode`` with Debian's x265 and ffmpeg on the sample views, the bitrate
calculator against the chapter's worked figures, and the missing-encoder message."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from program_runner import assert_one_line_error, invoke

from mvtools.cli import encode
from mvtools.io.yuv import YuvFormat, open_video
from mvtools.metrics import psnr
from mvtools.pack.bitrate import compressed_bitrate, raw_bitrate

LINE = Path(__file__).resolve().parent.parent / "sample_data" / "line"
TEXTURE = "v{}_texture_256x192_yuv420p.yuv"
DEPTH = "v{}_depth_256x192_yuv420p.yuv"
QPS = (20, 28, 36, 44)

needs_encoders = pytest.mark.skipif(
    (shutil.which("x265") is None or shutil.which("ffmpeg") is None)
    and os.environ.get("MVTOOLS_REQUIRE_DATA") != "1",
    reason="x265 and ffmpeg are not installed (.ci/run installs them)",
)


def test_the_seeds_worked_bitrates():
    # the chapter's eq. 1.7: nine HD cameras, 8-bit 4:2:0, 25 frames/s: about 5.6 Gbit/s
    assert raw_bitrate(1920, 1080, fps=25, views=9) == pytest.approx(5.5987e9, rel=1e-4)
    # the chapter's eq. 1.21-1.22: ten HD views simulcast with HEVC: about 40 Mbit/s
    assert compressed_bitrate(1920, 1080, fps=25, views=10, codec="hevc") == pytest.approx(40e6)
    # each codec generation halves the rate
    assert compressed_bitrate(1920, 1080, fps=25, codec="avc") == 2 * compressed_bitrate(
        1920, 1080, fps=25, codec="hevc"
    )
    with pytest.raises(ValueError, match="codec"):
        compressed_bitrate(1920, 1080, fps=25, codec="h263")
    for fps in (0.0, float("nan"), float("inf")):
        with pytest.raises(ValueError, match="frame rate"):
            raw_bitrate(1920, 1080, fps=fps)


@pytest.fixture(scope="module")
def experiment(tmp_path_factory):
    out = tmp_path_factory.mktemp("encode")
    arguments = []
    for view in (1, 3):
        arguments += [
            "--view",
            f"cam{view}",
            LINE / TEXTURE.format(view),
            "--depth",
            f"cam{view}",
            LINE / DEPTH.format(view),
        ]
    code, stdout, stderr = invoke(
        encode.command,
        *arguments,
        *(arg for qp in QPS for arg in ("--qp", qp)),
        "--preset",
        "ultrafast",
        "--frames",
        2,
        "--synthesize",
        LINE / "synthesize_cam2.cfg",
        "-o",
        out,
    )
    assert code == 0, stderr
    return out, json.loads((out / "report.json").read_text()), stdout


@pytest.mark.slow
@needs_encoders
def test_rates_and_qualities_fall_with_the_qp(experiment):
    _, report, stdout = experiment
    for mode in ("simulcast", "packed"):
        points = report["modes"][mode]
        assert [point["qp"] for point in points] == list(QPS)
        rates = [point["kbps"] for point in points]
        quality = [point["mean_texture_y_psnr"] for point in points]
        synthesized = [point["synthesis"]["iv_psnr"] for point in points]
        assert rates == sorted(rates, reverse=True)
        assert quality == sorted(quality, reverse=True)
        assert synthesized == sorted(synthesized, reverse=True)
        # QP 20 on smooth synthetic views: near-transparent coding; a misplaced view in the
        # packed frame would score below 20 dB
        assert quality[0] > 40.0
    assert "BD-rate" in stdout and set(report["bjontegaard"]) == {"cubic", "pchip"}


@needs_encoders
def test_bitrates_are_the_bitstreams_sizes(experiment):
    out, report, _ = experiment
    point = report["modes"]["simulcast"][0]
    folder = out / "simulcast" / f"qp{QPS[0]}"
    texture_bytes = sum(
        (folder / (TEXTURE.format(view)[:-4] + ".hevc")).stat().st_size for view in (1, 3)
    )
    depth_bytes = sum(
        (folder / (DEPTH.format(view)[:-4] + ".hevc")).stat().st_size for view in (1, 3)
    )
    # two frames at 25 frames/s last 0.08 s
    assert point["texture_kbps"] == pytest.approx(texture_bytes * 8 / 0.08 / 1000)
    assert point["depth_kbps"] == pytest.approx(depth_bytes * 8 / 0.08 / 1000)
    assert point["kbps"] == pytest.approx(point["texture_kbps"] + point["depth_kbps"])


@needs_encoders
def test_decoded_views_match_their_scores(experiment):
    out, report, _ = experiment
    fmt = YuvFormat(256, 192)
    decoded = out / "packed" / f"qp{QPS[-1]}" / TEXTURE.format(3)
    with open_video(LINE / TEXTURE.format(3), fmt) as original, open_video(decoded, fmt) as test:
        scores = [psnr(original.read(i)[0], test.read(i)[0], max_value=255) for i in range(2)]
    assert report["modes"]["packed"][-1]["scores"]["cam3 texture"]["y_psnr"] == pytest.approx(
        np.mean(scores)
    )


def test_a_missing_encoder_says_how_to_install_it(tmp_path):
    environment = {**os.environ, "PATH": str(tmp_path)}
    completed = subprocess.run(
        [
            sys.executable,
            "-m",
            "mvtools",
            "encode",
            "--view",
            "cam1",
            str(LINE / TEXTURE.format(1)),
            "--qp",
            "30",
            "--mode",
            "simulcast",
            "--frames",
            "1",
            "-o",
            str(tmp_path / "out"),
        ],
        capture_output=True,
        text=True,
        env=environment,
    )
    assert completed.returncode == 2
    assert_one_line_error(completed.stderr, "x265", "apt-get install x265")
    assert not (tmp_path / "out").exists()
