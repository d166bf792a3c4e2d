"""Depth estimation as DERS users run it (issue 20): the Middlebury pairs written as DERS
cases, scored with the Middlebury protocol.

Truth: the published ground truth, hand-computed SearchLevels, and depth values written
from the ground truth by the depth formula. Issue 20's bars are measured by
``benchmarks/bench_ders.py``; the data tests here hold the figures reached so far.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
from program_runner import run
from shared_data import shared_data

from mvtools.datasets import (
    DERS_CASE_BASELINE,
    DERS_CASE_FOCAL,
    ders_case_disparity,
    ders_search_level,
    load_middlebury_ground_truth,
    middlebury_pair,
    opencv_sgbm_reference,
    score_ders_case,
    score_middlebury,
    write_middlebury_ders_case,
)
from mvtools.geometry.depth import DepthCoding, ders_depth_range
from mvtools.io.cameras import read_cameras
from mvtools.io.config import read_config
from mvtools.io.depth_sidecar import DepthSidecar, depth_sidecar_path, write_depth_sidecar
from mvtools.io.yuv import YuvFormat, write_video
from mvtools.run.depth import estimate_depth_config


@pytest.mark.parametrize(
    ("disparities", "level"), [(16, 4.0), (64, 4.0), (65, 2.0), (128, 2.0), (129, 1.0), (256, 1.0)]
)
def test_the_finest_search_level_within_256_labels(disparities, level):
    # labels: (disparities - 1) * level + 1
    assert ders_search_level(disparities) == level


def test_more_disparities_than_labels_are_refused():
    with pytest.raises(ValueError, match="257 disparities"):
        ders_search_level(257)


def test_a_case_is_parallel_cameras_and_the_sets_search_range(tmp_path):
    root = shared_data("middlebury")
    config = write_middlebury_ders_case(
        root, "tsukuba", tmp_path, left_view="2001/tsukuba/tsukuba2.png"
    )
    text = config.read_text()
    for key, value in (
        ("MinimumValueOfDisparitySearchRange", "0"),
        ("MaximumValueOfDisparitySearchRange", "15"),
        ("SearchLevel", "4.0"),
        ("LeftCameraName", "left"),
        ("RightCameraName", "right"),
    ):
        assert re.search(rf"^{key}\s+{re.escape(value)}\s", text, re.M), key
    assert read_config(config)  # the program's own reader takes it
    cameras = read_cameras(tmp_path / "cameras.txt")
    assert [cameras[name].t[0] for name in ("left", "center", "right")] == [-1.0, 0.0, 1.0]
    for camera in cameras.values():
        np.testing.assert_array_equal(camera.R, np.eye(3))
        assert camera.fx == DERS_CASE_FOCAL and camera.cx == (384 - 1) / 2


def test_the_disparity_read_back_from_a_depth_video_is_the_one_written(tmp_path):
    truth = load_middlebury_ground_truth(shared_data("middlebury"), "tsukuba")
    focal_baseline = DERS_CASE_FOCAL * DERS_CASE_BASELINE
    depth_range = ders_depth_range(DERS_CASE_FOCAL, DERS_CASE_BASELINE, 0, 15)
    disparity = np.where(truth.known, truth.disparity, 0.0)
    with np.errstate(divide="ignore"):
        z = focal_baseline / disparity
    video = tmp_path / "estimated_depth_384x288_gray16le.yuv"
    write_video(
        video,
        YuvFormat(384, 288, chroma="400", bits=16),
        [(DepthCoding(depth_range, 16).values(z),)],
    )
    write_depth_sidecar(
        depth_sidecar_path(video), DepthSidecar(nearest=depth_range[0], farthest=depth_range[1])
    )
    # 16-bit values over 15 px of disparity: a step of 15 / 65535 px
    decoded, step = ders_case_disparity(video)
    assert step == pytest.approx(15 / 65535)
    np.testing.assert_allclose(decoded, disparity, atol=step / 2 + 1e-6)


def _ders_bad(tmp_path: Path, name: str, **settings) -> float:
    root = shared_data("middlebury")
    config = write_middlebury_ders_case(root, name, tmp_path, **settings)
    output = re.search(r"FileOutputDepthMapImage\s+(\S+)", config.read_text()).group(1)
    written = estimate_depth_config(config, data_dirs=[tmp_path], output=tmp_path / output)
    return score_ders_case(written["depth"], root, name)


@pytest.mark.slow
@pytest.mark.parametrize(
    ("name", "limit", "left_view"),
    [
        ("tsukuba", 2.3, None),
        ("tsukuba", 2.0, "2001/tsukuba/tsukuba2.png"),
        ("venus", 1.0, None),
        ("teddy", 4.6, None),
        ("cones", 3.0, None),
    ],
)
def test_ders_mode_on_the_middlebury_pairs(tmp_path, name, limit, left_view):
    # measured with the default method (bp, its smoothness per pixel of disparity, the
    # census tolerance) and the stereo-pair mode's chain: 2.17, 1.92 (views 2-3-4), 0.39,
    # 4.34, 2.70 (no tolerance: 2.46, 1.92, 0.38, 4.25, 2.70; nor smoothness per pixel:
    # 2.19, 2.02, 0.38, 5.09, 2.88; sgm 2.38, -, 0.40, 4.35, 3.10; before the chain, sgm
    # with sub-level winners and no segment planes: 4.27, -, 1.52, 5.19, 3.37);
    # issue 20's bars: 2.0, 1.8, 1.0, 6.0, 3.0
    bad = _ders_bad(tmp_path, name, left_view=left_view)
    print(f"{name}: bad 1.0 {bad:.2f} %")
    assert bad <= limit


@pytest.mark.slow
def test_voting_makes_tsukubas_outer_views_count(tmp_path):
    # Views 2 to 4 as the configuration's cameras, views 1 and 5 given with --view
    root = shared_data("middlebury")
    further = [("2001/tsukuba/tsukuba1.png", -2), ("2001/tsukuba/tsukuba5.png", 2)]
    bad = {}
    for combination, views in (("least-cost", 3), ("least-cost", 5), ("vote", 5)):
        folder = tmp_path / f"{combination}{views}"
        folder.mkdir()
        config = write_middlebury_ders_case(
            root,
            "tsukuba",
            folder,
            left_view="2001/tsukuba/tsukuba2.png",
            further_views=further if views == 5 else (),
            view_combination=combination,
        )
        items = []
        for picture, _ in further if views == 5 else ():
            stem = Path(picture).stem
            items += ["--view", stem, str(folder / f"{stem}_384x288_yuv420p.yuv")]
        output = folder / "depth_384x288_gray16le.yuv"
        code, _, err = run("estimate-depth", config, "-o", output, *items)
        assert code == 0, err
        bad[combination, views] = score_ders_case(output, root, "tsukuba")
    print(bad)
    # Measured (bp): least-cost 1.92 from three views, 2.00 from five (the wide views'
    # costs blur the sweep's minimum); vote 1.94 and 1.77
    assert bad["vote", 5] < min(bad["least-cost", 3], bad["least-cost", 5]) - 0.1


@pytest.mark.slow
def test_ders_mode_on_art_beats_half_of_stereo_sgbm(tmp_path):
    # issue 20's bar for the 2005 pairs: half of OpenCV StereoSGBM's bad 1.0 on the same
    # pair (Art: 16.5 %, measured here); bp 7.42 (7.58 without the census tolerance, 8.69
    # with neither it nor the smoothness per pixel)
    root = shared_data("middlebury")
    truth = load_middlebury_ground_truth(root, "Art")
    sgbm = score_middlebury(
        opencv_sgbm_reference(*middlebury_pair(root, "Art"), disparities=80), truth, "Art"
    )
    bad = _ders_bad(tmp_path, "Art")
    print(f"Art: bad 1.0 {bad:.2f} %, StereoSGBM {sgbm:.2f} %")
    assert bad <= sgbm / 2
