"""estimate-depth through DERS configurations (issue 20): the Middlebury pairs written as
DERS cases (:func:`mvtools.datasets.write_middlebury_ders_case`: center = left picture,
parallel cameras, the set's disparity range as the search range at the finest SearchLevel
within DERS's 256 labels), bad 1.0 over each set's scored region beside OpenCV StereoSGBM
on the same pair and the issue's bar; Tsukuba also with views 2 and 4 as the left and
right neighbours of view 3.

Then a 1920x1088 frame of three views (the synthetic scene's line, cameras 1, 2 and 3, as
``mvtools scene --size 1920x1088`` writes it, with its exact depth): seconds and peak
resident memory of the whole ``estimate-depth`` process with 128 and 256 planes between
Znear and Zfar, beside the bars (20 s with 128 planes, 3 GB with 256), and the share of
pixels whose depth is within one plane of the truth. Last, Poznan Hall 2's camera 7
synthesized from camera 5 with the depth estimated for camera 5 against the shipped depth.

Environment: MVTOOLS_BENCH_METHODS=sgm,bp (default: the default method alone),
MVTOOLS_BENCH_SETS=tsukuba,cones (default: all), MVTOOLS_BENCH_HD_METHODS=sgm,bp
(default: the default method; graphcut takes minutes).
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from common import DATA, report, run_measured

from mvtools.datasets import (
    load_middlebury_ground_truth,
    middlebury_pair,
    opencv_sgbm_reference,
    score_ders_case,
    score_middlebury,
    write_hall_ders_case,
    write_middlebury_ders_case,
)
from mvtools.depth.options import DEFAULT_METHOD
from mvtools.geometry.depth import DepthCoding
from mvtools.io.middlebury import MIDDLEBURY_SETS
from mvtools.io.yuv import YuvFormat, read_frame
from mvtools.run.depth import estimate_depth_config

ROOT = DATA / "middlebury"
#: case -> (set, left neighbour's picture or None)
CASES = {
    "tsukuba": ("tsukuba", None),
    "tsukuba 2-3-4": ("tsukuba", "2001/tsukuba/tsukuba2.png"),
    "venus": ("venus", None),
    "teddy": ("teddy", None),
    "cones": ("cones", None),
    "Art": ("Art", None),
    "Dolls": ("Dolls", None),
    "Moebius": ("Moebius", None),
}
#: bad 1.0 bars of issue 20 (None: half of StereoSGBM's)
BARS = {"tsukuba": 2.0, "tsukuba 2-3-4": 1.8, "venus": 1.0, "teddy": 6.0, "cones": 3.0}


def ders_bad(case: str, method: str | None) -> tuple[float, float]:
    name, left_view = CASES[case]
    with tempfile.TemporaryDirectory() as folder:
        settings = {} if method is None else {"method": method}
        config = write_middlebury_ders_case(ROOT, name, folder, left_view=left_view, **settings)
        output = re.search(r"FileOutputDepthMapImage\s+(\S+)", config.read_text()).group(1)
        start = time.perf_counter()
        written = estimate_depth_config(config, data_dirs=[folder], output=Path(folder) / output)
        seconds = time.perf_counter() - start
        bad = score_ders_case(written["depth"], ROOT, name)
    return bad, seconds


def hd_rows(folder: Path) -> list:
    subprocess.run(
        [sys.executable, "-m", "mvtools", "scene", str(folder), "--size", "1920x1088",
         "--frames", "1", "--samples", "1", "--part", "line", "-q"],
        check=True,
    )  # fmt: skip
    line = folder / "line"
    truth = read_frame(
        line / "v2_depth_1920x1088_gray16le.yuv", YuvFormat(1920, 1088, chroma="400", bits=16)
    )[0]
    true_z = DepthCoding((2.0, 13.0), 16).z(truth)
    rows = []
    methods = os.environ.get("MVTOOLS_BENCH_HD_METHODS", DEFAULT_METHOD).split(",")
    for method in methods:
        for planes, bar, what in ((128, 20.0, "seconds"), (256, 3072.0, "peak MB")):
            output = line / f"hd_{method}_{planes}_1920x1088_gray16le.yuv"
            start = time.perf_counter()
            _, usage = run_measured(
                [sys.executable, "-m", "mvtools", "estimate-depth", str(line / "depth_cam2.cfg"),
                 f"Method={method}", "NearestSearchDepthValue=2", "FarthestSearchDepthValue=13",
                 f"NumberOfDepthSteps={planes}", "NearestDepthValue=2", "FarthestDepthValue=13",
                 "-o", str(output), "-q"],
                check=True, cwd=line,
            )  # fmt: skip
            seconds = time.perf_counter() - start
            peak = usage.peak_mib
            estimate = DepthCoding((2.0, 13.0), 16).z(
                read_frame(output, YuvFormat(1920, 1088, chroma="400", bits=16))[0]
            )
            step = (1 / 2.0 - 1 / 13.0) / (planes - 1)
            within = float(np.mean(np.abs(1 / estimate - 1 / true_z) <= step)) * 100
            figure = seconds if what == "seconds" else peak
            rows.append((f"1920x1088 3 views {method} {planes} planes {what}", figure, "bar", bar))
            rows.append(
                (f"1920x1088 3 views {method} {planes} planes, % within a plane", within, "", None)
            )
    return rows


def hall_rows(folder: Path) -> list:
    """Camera 7 of Poznan Hall 2 synthesized from camera 5 with the depth estimated for
    camera 5 (from camera 7) and with the shipped depth, Y-PSNR against the real one."""
    from test_depth_hall import hall_camera_7_psnr

    hall = DATA / "mpeg" / "poznan_hall2"
    config = write_hall_ders_case(hall, folder)
    start = time.perf_counter()
    written = estimate_depth_config(
        config, output=folder / "estimated_D_cam05_1920x1088_yuv420p.yuv"
    )
    seconds = time.perf_counter() - start
    estimated = hall_camera_7_psnr(hall, written["depth"], folder / "from_estimated.yuv")
    shipped = hall_camera_7_psnr(hall, hall / "hall_D_cam05.yuv", folder / "from_shipped.yuv")
    return [
        ("Hall cam7 from cam5, estimated depth Y-PSNR (dB)", estimated, "shipped depth", shipped),
        ("Hall cam5 depth from cam7, 128 planes (s)", seconds, "", None),
    ]


def main() -> None:
    methods = os.environ.get("MVTOOLS_BENCH_METHODS")
    methods = methods.split(",") if methods else [None]
    cases = os.environ.get("MVTOOLS_BENCH_SETS", ",".join(CASES)).split(",")
    rows = []
    for case in cases:
        name = CASES[case][0]
        left, right = middlebury_pair(ROOT, name)
        truth = load_middlebury_ground_truth(ROOT, name)
        sgbm = opencv_sgbm_reference(left, right, disparities=MIDDLEBURY_SETS[name].disparities)
        sgbm_bad = score_middlebury(sgbm, truth, name)
        bar = BARS.get(case, sgbm_bad / 2)
        for method in methods:
            label = f"{case} DERS {method or 'default'}"
            bad, seconds = ders_bad(case, method)
            rows.append((f"{label} bad 1.0 %", bad, "OpenCV StereoSGBM", sgbm_bad))
            rows.append((f"{label} bad 1.0 %", bad, "bar", bar))
            rows.append((f"{label} seconds", seconds, "", None))
    with tempfile.TemporaryDirectory() as folder:
        rows += hd_rows(Path(folder))
    if (DATA / "mpeg" / "poznan_hall2").exists():
        with tempfile.TemporaryDirectory() as folder:
            rows += hall_rows(Path(folder))
    report(rows)


if __name__ == "__main__":
    main()
