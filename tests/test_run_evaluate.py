"""The run functions of ``mvtools evaluate`` called from Python: scores of known
differences computed by hand, and the program's output for the same input."""

from __future__ import annotations

import json
import math
import subprocess
import sys

import numpy as np
import pytest
from program_runner import invoke
from shared_data import shared_data

from mvtools.cli import evaluate
from mvtools.errors import ConfigError, DataError, UsageError
from mvtools.geometry.camera import Camera
from mvtools.geometry.depth import z_to_depth
from mvtools.io.cameras import write_cameras
from mvtools.io.images import write_image
from mvtools.io.yuv import YuvFormat, open_video, write_video
from mvtools.run.evaluate import (
    DisparityGeometry,
    disparity_geometry,
    evaluate_depth_videos,
    evaluate_disparity,
    evaluate_videos,
    score_videos,
    video_depth_range,
)


def _constant_frames(fmt: YuvFormat, lumas: list[int], chroma: int = 128) -> list[tuple]:
    shapes = fmt.plane_shapes
    return [
        (np.full(shapes[0], luma, np.uint8),)
        + tuple(np.full(s, chroma, np.uint8) for s in shapes[1:])
        for luma in lumas
    ]


# --------------------------------------------------------------------------- videos


def test_score_videos_gives_the_psnr_of_a_known_difference_and_reports_progress(tmp_path):
    # frame 0 identical, frame 1 luma off by 5 everywhere: MSE 25, PSNR 10 log10(255^2 / 25)
    fmt = YuvFormat(16, 8)
    write_video(tmp_path / "ref.yuv", fmt, _constant_frames(fmt, [100, 100]))
    frames = _constant_frames(fmt, [100, 105])
    # frame 1's V plane off by 2: MSE 4
    frames[1] = (*frames[1][:2], frames[1][2] + np.uint8(2))
    write_video(tmp_path / "test.yuv", fmt, frames)
    calls = []
    with (
        open_video(tmp_path / "ref.yuv", fmt) as ref,
        open_video(tmp_path / "test.yuv", fmt) as test,
    ):
        result = score_videos(
            ref, test, range(2), ("psnr",), progress=lambda *args: calls.append(args)
        )
    assert calls == [(1, 2), (2, 2)]
    assert [row["frame"] for row in result["frames"]] == [0, 1]
    assert result["frames"][0]["Y-PSNR"] == math.inf
    expected = 10 * math.log10(255**2 / 25)
    assert result["frames"][1]["Y-PSNR"] == pytest.approx(expected)
    assert result["frames"][1]["U-PSNR"] == math.inf
    v_psnr = 10 * math.log10(255**2 / 4)
    assert result["frames"][1]["V-PSNR"] == pytest.approx(v_psnr)
    # YUV-PSNR weighs the planes' PSNR 6:1:1, infinite when one plane is identical
    assert result["frames"][1]["YUV-PSNR"] == math.inf
    assert result["mean"]["V-PSNR"] == math.inf  # frame 0's V is identical
    assert result["mean"]["Y-PSNR"] == math.inf


def test_evaluate_videos_gives_the_programs_scores(tmp_path):
    fmt = YuvFormat(16, 16)
    ref, test = tmp_path / "ref_16x16_yuv420p.yuv", tmp_path / "test_16x16_yuv420p.yuv"
    write_video(ref, fmt, _constant_frames(fmt, [100, 120, 140]))
    rng = np.random.default_rng(5)
    noisy = [
        tuple(
            np.clip(p.astype(int) + rng.integers(-9, 10, p.shape), 0, 255).astype(np.uint8)
            for p in f
        )
        for f in _constant_frames(fmt, [100, 120, 140])
    ]
    write_video(test, fmt, noisy)
    result = evaluate_videos(ref, test, start_frame=1, frame_count=2)
    assert [row["frame"] for row in result["frames"]] == [1, 2]
    assert list(result["mean"]) == ["Y-PSNR", "U-PSNR", "V-PSNR", "YUV-PSNR", "Y-SSIM", "IV-PSNR"]
    code, out, err = invoke(evaluate.command, ref, test, "--start-frame", 1, "--json")
    assert code == 0, err
    assert json.loads(out) == result


def test_evaluate_videos_of_different_formats_is_a_data_error(tmp_path):
    write_video(
        tmp_path / "b_16x8_gray.yuv",
        YuvFormat(16, 8, "400"),
        [(np.zeros((8, 16), np.uint8),)],
    )
    fmt = YuvFormat(16, 8)
    write_video(tmp_path / "a_16x8_yuv420p.yuv", fmt, _constant_frames(fmt, [0]))
    with pytest.raises(DataError, match="the test video is"):
        evaluate_videos(tmp_path / "a_16x8_yuv420p.yuv", tmp_path / "b_16x8_gray.yuv")


# --------------------------------------------------------------------------- disparity maps


@pytest.fixture
def disparity_case(tmp_path):
    """A 4x6 ground truth of 10 px (PNG value / 4), unknown at row 3 column 5; the
    estimate errs by 0.5, 1.5 and -3 px on the first three pixels of row 0."""
    truth = np.full((4, 6), 40, np.uint8)
    truth[3, 5] = 0
    write_image(tmp_path / "truth.png", truth)
    estimate = np.full((4, 6), 10.0, np.float32)
    estimate[0, :3] += np.array([0.5, 1.5, -3.0], np.float32)
    write_image(tmp_path / "estimate.pfm", estimate)
    write_image(tmp_path / "exact.pfm", np.full((4, 6), 10.0, np.float32))
    mask = np.full((4, 6), 255, np.uint8)
    mask[0] = 0  # row 0 occluded
    write_image(tmp_path / "nonocc.png", mask)
    return tmp_path


def test_a_disparity_map_equal_to_the_ground_truth_has_no_bad_pixel(disparity_case):
    result = evaluate_disparity(
        disparity_case / "truth.png", disparity_case / "exact.pfm", gt_scale=4
    )
    assert result["bad_all"] == {"1": 0.0, "2": 0.0}
    assert result["bad_nonocc"] is None and result["nonocc_pixels"] is None
    assert result["mean_abs_error"] == 0.0 and result["rms_error"] == 0.0
    assert result["known_pixels"] == 23 and result["invalid_pixels"] == 0
    assert result["histogram"]["pixels"] == [23, 0, 0, 0, 0, 0, 0]


def test_disparity_scores_of_known_errors(disparity_case):
    result = evaluate_disparity(
        disparity_case / "truth.png",
        disparity_case / "estimate.pfm",
        gt_scale=4,
        nonoccluded_mask=disparity_case / "nonocc.png",
        thresholds=(1, 2, 0.25),
    )
    # bad when the error exceeds t: 1.5 and 3 exceed 1; 3 exceeds 2; all three 0.25
    assert result["bad_all"] == {"1": 200 / 23, "2": 100 / 23, "0.25": 300 / 23}
    # every error is in the occluded row 0
    assert result["bad_nonocc"] == {"1": 0.0, "2": 0.0, "0.25": 0.0}
    assert result["nonocc_pixels"] == 17
    assert result["mean_abs_error"] == pytest.approx(5.0 / 23)
    assert result["rms_error"] == pytest.approx(math.sqrt(11.5 / 23))
    histogram = result["histogram"]
    assert histogram["bins"] == ["0-0.25", "0.25-0.5", "0.5-1", "1-2", "2-4", "4-8", ">= 8"]
    assert histogram["pixels"] == [20, 0, 1, 1, 1, 0, 0]
    assert histogram["percent"][0] == pytest.approx(100 * 20 / 23)


def test_disparity_errors(disparity_case):
    with pytest.raises(UsageError, match="scale is unknown"):
        evaluate_disparity(disparity_case / "truth.png", disparity_case / "exact.pfm")
    with pytest.raises(DataError, match="one channel"):
        write_image(disparity_case / "colour.png", np.zeros((4, 6, 3), np.uint8))
        evaluate_disparity(disparity_case / "truth.png", disparity_case / "colour.png", gt_scale=4)
    with pytest.raises(ValueError, match="thresholds"):
        evaluate_disparity(
            disparity_case / "truth.png", disparity_case / "exact.pfm", gt_scale=4, thresholds=()
        )


def test_evaluate_disparity_on_middlebury_gives_the_programs_scores():
    teddy = shared_data("middlebury", "2003", "teddy")
    result = evaluate_disparity(teddy / "disp2.png", teddy / "disp6.png")
    assert result["gt_scale"] == 4  # the set's, found from the path
    assert result["nonocc_pixels"] < result["known_pixels"]  # the set's occl.png
    code, out, err = invoke(
        evaluate.command, "--disparity", teddy / "disp2.png", teddy / "disp6.png", "--json"
    )
    assert code == 0, err
    assert json.loads(out) == result


# --------------------------------------------------------------------------- depth videos


def _depth_videos(folder, test_disparity: float, *, size=(8, 4)):
    """Depth videos (16-bit, Znear 1, Zfar 100) of 3 frames whose left half is at
    disparity 5 and right half at 10 in the truth, ``test_disparity`` in the test, for
    disparity = 20 / z."""
    width, height = size
    fmt = YuvFormat(width, height, "400", 16)
    paths = {}
    for name, right in (("truth", 10.0), ("test", test_disparity)):
        z = np.where(np.arange(width) < width // 2, 4.0, 20.0 / right) * np.ones((height, 1))
        paths[name] = folder / f"{name}_{width}x{height}_gray16le.yuv"
        write_video(paths[name], fmt, [(z_to_depth(z, 1.0, 100.0, bits=16),)] * 3)
    return paths["truth"], paths["test"]


def test_depth_videos_scored_as_disparities(tmp_path):
    truth, test = _depth_videos(tmp_path, 11.5)
    calls = []
    result = evaluate_depth_videos(
        truth,
        test,
        DisparityGeometry("b", 100.0, 0.2),
        reference_range=(1.0, 100.0),
        test_range=(1.0, 100.0),
        start_frame=1,
        thresholds=(1, 2),
        progress=lambda *args: calls.append(args),
    )
    assert calls == [(1, 2), (2, 2)]
    assert [row["frame"] for row in result["frames"]] == [1, 2]
    # half the pixels err by 1.5 px: bad 1 is 50 %, bad 2 none; a 16-bit step is 0.0003 px
    assert result["mean"]["bad 1"] == 50.0 and result["mean"]["bad 2"] == 0.0
    assert result["mean"]["mean abs"] == pytest.approx(0.75, abs=1e-3)
    assert result["mean"]["RMS"] == pytest.approx(math.sqrt(1.5**2 / 2), abs=1e-3)
    # 2 frames of 32 pixels, half right and half 1.5 px off
    assert result["histogram"]["pixels"] == [32, 0, 0, 32, 0, 0, 0]
    assert (result["neighbour"], result["focal"], result["baseline"]) == ("b", 100.0, 0.2)


def test_depth_videos_of_different_sizes_are_a_data_error(tmp_path):
    truth, _ = _depth_videos(tmp_path, 10.0)
    (tmp_path / "other").mkdir()
    _, test = _depth_videos(tmp_path / "other", 10.0, size=(6, 4))
    with pytest.raises(DataError, match="the test video is"):
        evaluate_depth_videos(
            truth,
            test,
            DisparityGeometry("b", 100.0, 0.2),
            reference_range=(1.0, 100.0),
            test_range=(1.0, 100.0),
        )


def test_disparity_geometry_from_a_camera_file(tmp_path):
    K = np.array([[100.0, 0, 4], [0, 100.0, 2], [0, 0, 1]])
    cameras = tmp_path / "cameras.txt"
    write_cameras(
        cameras,
        [Camera("a", K), Camera("b", K, t=np.array([0.3, 0.4, 0])), Camera("c", K)],
    )
    assert disparity_geometry(cameras, "a", "b") == DisparityGeometry("b", 100.0, 0.5)
    with pytest.raises(ConfigError, match="same place"):
        disparity_geometry(cameras, "a", "c")
    with pytest.raises(ConfigError, match="no camera 'd'"):
        disparity_geometry(cameras, "a", "d")


def test_video_depth_range_given_or_from_the_sidecar(tmp_path):
    video = tmp_path / "depth.yuv"
    assert video_depth_range(video, (2.0, 13.0), option="--test-depth-range") == (2.0, 13.0)
    with pytest.raises(UsageError, match="give --test-depth-range"):
        video_depth_range(video, option="--test-depth-range")
    (tmp_path / "depth.yuv.json").write_text(
        json.dumps({"NearestDepthValue": 2.0, "FarthestDepthValue": None})
    )
    assert video_depth_range(video, option="--test-depth-range") == (2.0, math.inf)
    (tmp_path / "depth.yuv.json").write_text(json.dumps({"NearestDepthValue": 2.0, "DepthType": 1}))
    with pytest.raises(DataError, match="DepthType 1"):
        video_depth_range(video, option="--test-depth-range")


# --------------------------------------------------------------------------- start-up


def test_the_run_module_and_the_metrics_load_no_heavy_library():
    script = (
        "import sys, mvtools.run.evaluate, mvtools.metrics.video\n"
        "from mvtools.metrics import psnr, ssim\n"
        "print(callable(psnr), callable(ssim), "
        "[m for m in ('numba', 'cv2', 'scipy', 'maxflow') if m in sys.modules])"
    )
    out = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, check=True
    ).stdout
    # psnr and ssim are the functions, not their modules of the same name
    assert out.strip() == "True True []"
