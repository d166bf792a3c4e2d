"""``mvtools calibrate`` end to end: the sample rig's captures, whose cameras are exactly
known, OpenCV's published stereo captures, and bad input.

The limits are the issue's bars: focal lengths within 0.2 %, principal points within
1 px, K1 within 0.01, centres within 0.5 % of the baseline and rotations within 0.1
degree on the synthetic rig; on OpenCV's set, fx within 0.5 % of 536.1 px, RMS at most
0.45 px and the baseline within 1 % of 0.0836 m.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from program_runner import assert_one_line_error, invoke
from shared_data import shared_data

from mvtools.cli import calibrate
from mvtools.io.cameras import read_cameras
from mvtools.io.images import read_image, write_image
from mvtools.io.json_cameras import read_json_cameras
from mvtools.io.yuv import YuvFormat, write_video

CHECKERBOARD = Path(__file__).resolve().parent.parent / "sample_data" / "checkerboard"


def rotation_angle_degrees(first: np.ndarray, second: np.ndarray) -> float:
    cosine = (np.trace(first @ second.T) - 1.0) / 2.0
    return float(np.degrees(np.arccos(np.clip(cosine, -1.0, 1.0))))


@pytest.fixture(scope="module")
def sample_rig(tmp_path_factory):
    out = tmp_path_factory.mktemp("calibrate")
    truth = json.loads((CHECKERBOARD / "truth.json").read_text())
    names = [camera["name"] for camera in truth["cameras"]]
    code, stdout, stderr = invoke(
        calibrate.command,
        *(CHECKERBOARD / name for name in names),
        "--board",
        "9x6",
        "--square",
        "0.05",
        "-o",
        out / "cameras.txt",
        "--json",
        out / "cameras.json",
        "--report",
        out / "report",
    )
    assert code == 0, stderr
    return truth, out, stdout


@pytest.mark.slow
def test_sample_rig_recovers_the_true_cameras(sample_rig):
    truth, out, _ = sample_rig
    found = read_cameras(out / "cameras.txt")
    true_cameras = truth["cameras"]
    reference_R = np.array(true_cameras[0]["R"])
    reference_t = np.array(true_cameras[0]["t"])
    baseline = np.linalg.norm(np.array(true_cameras[1]["t"]) - reference_t)
    for true in true_cameras:
        camera = found[true["name"]]
        K = np.array(true["K"])
        assert abs(camera.fx / K[0, 0] - 1) < 0.002
        assert abs(camera.fy / K[1, 1] - 1) < 0.002
        assert np.hypot(camera.cx - K[0, 2], camera.cy - K[1, 2]) < 1.0
        assert abs(camera.distortion[0] - true["distortion"][0]) < 0.01
        # the truth in the reference camera's frame, which calibrate makes the world
        R = np.array(true["R"]) @ reference_R.T
        centre = reference_R @ (np.array(true["t"]) - reference_t)
        assert rotation_angle_degrees(camera.R, R) < 0.1
        assert np.linalg.norm(camera.t - centre) < 0.005 * baseline


@pytest.mark.slow
def test_sample_rig_report_lists_the_captures_each_camera_saw(sample_rig):
    truth, out, stdout = sample_rig
    report = json.loads((out / "report" / "report.json").read_text())
    missed = 0
    for entry in report["cameras"]:
        name = entry["name"]
        corners = [np.array(capture["corners"][name]) for capture in truth["captures"]]
        inside = {
            f"capture{index:02d}.png"
            for index, uv in enumerate(corners)
            if np.all(uv >= 0) and np.all(uv < [640, 480])
        }
        visible = {
            f"capture{index:02d}.png"
            for index, capture in enumerate(truth["captures"])
            if capture["visible"][name]
        }
        used = {Path(path).name for path in entry["captures_used"]}
        # a board partly out of view is never taken; nearly every one in full view (10 px
        # from the border) is found
        assert used <= inside
        missed += len(visible - used)
        assert 0 < entry["rms_px"] < 0.2
        assert set(entry["capture_rms_px"]) == set(entry["captures_used"])
        picture = read_image(out / "report" / f"{name}_corners.png")
        assert picture.shape == (480, 640, 3)
        assert name in stdout
    assert missed <= 2
    assert len(report["baselines_m"]) == len(truth["cameras"]) - 1
    for baseline in report["baselines_m"].values():
        assert baseline == pytest.approx(0.1, rel=0.005)


def test_sample_rig_json_holds_the_same_pinhole_cameras(sample_rig):
    _, out, _ = sample_rig
    text = read_cameras(out / "cameras.txt")
    for name, camera in read_json_cameras(out / "cameras.json").items():
        np.testing.assert_allclose(camera.K, text[name].K, atol=1e-6)
        np.testing.assert_allclose(camera.t, text[name].t, atol=1e-9)


def test_opencv_stereo_captures_by_pattern(tmp_path):
    folder = shared_data("calibration", "opencv_stereo")
    code, _stdout, stderr = invoke(
        calibrate.command,
        folder / "left[0-9]*.jpg",
        folder / "right[0-9]*.jpg",
        "--board",
        "9x6",
        "--square",
        "0.025",
        "-o",
        tmp_path / "stereo.txt",
        "--report",
        tmp_path / "report",
    )
    assert code == 0, stderr
    cameras = read_cameras(tmp_path / "stereo.txt")
    assert set(cameras) == {"left", "right"}
    assert cameras["left"].fx == pytest.approx(536.1, rel=0.005)
    baseline = np.linalg.norm(cameras["right"].t - cameras["left"].t)
    assert baseline == pytest.approx(0.0836, rel=0.01)
    report = json.loads((tmp_path / "report" / "report.json").read_text())
    assert report["cameras"][0]["rms_px"] <= 0.45


def write_captures(folder: Path, images) -> None:
    folder.mkdir(parents=True)
    for index, image in enumerate(images):
        write_image(folder / f"capture{index:02d}.png", image)


def sample_capture(camera: str, index: int) -> np.ndarray:
    return read_image(CHECKERBOARD / camera / f"capture{index:02d}.png")


@pytest.mark.slow
def test_no_board_in_any_capture_names_the_camera(tmp_path):
    blank = np.full((480, 640), 128, np.uint8)
    write_captures(tmp_path / "camA", [sample_capture("cam0", index) for index in range(4)])
    write_captures(tmp_path / "camB", [blank] * 4)
    code, _, stderr = invoke(
        calibrate.command,
        tmp_path / "camA",
        tmp_path / "camB",
        "--board",
        "9x6",
        "--square",
        "0.05",
        "-o",
        tmp_path / "out.txt",
    )
    assert code == 1
    assert_one_line_error(stderr, "camB")
    assert not (tmp_path / "out.txt").exists()


def test_different_capture_counts_are_a_usage_error(tmp_path):
    write_captures(tmp_path / "camA", [sample_capture("cam0", index) for index in range(3)])
    write_captures(tmp_path / "camB", [sample_capture("cam1", index) for index in range(2)])
    code, _, stderr = invoke(
        calibrate.command,
        tmp_path / "camA",
        tmp_path / "camB",
        "--board",
        "9x6",
        "--square",
        "0.05",
        "-o",
        tmp_path / "out.txt",
    )
    assert code == 2
    assert_one_line_error(stderr, "camA 3", "camB 2")
    assert not (tmp_path / "out.txt").exists()


def test_a_capture_of_another_size_names_its_file(tmp_path):
    images = [sample_capture("cam0", index) for index in range(3)]
    images[1] = images[1][:240, :320]
    write_captures(tmp_path / "camA", images)
    code, _, stderr = invoke(
        calibrate.command,
        tmp_path / "camA",
        "--board",
        "9x6",
        "--square",
        "0.05",
        "-o",
        tmp_path / "out.txt",
    )
    assert code == 1
    assert_one_line_error(stderr, "capture01.png", "320x240")
    assert not (tmp_path / "out.txt").exists()


@pytest.mark.parametrize(
    "arguments, fragment",
    [
        (["--board", "9"], "COLUMNSxROWS"),
        (["--board", "9x6", "--reference", "nosuch"], "nosuch"),
        (["--board", "9x6", "--names", "a,b"], "--names"),
    ],
)
def test_bad_options_exit_2(tmp_path, arguments, fragment):
    code, _, stderr = invoke(
        calibrate.command,
        CHECKERBOARD / "cam0",
        "--square",
        "0.05",
        "-o",
        tmp_path / "out.txt",
        *arguments,
    )
    assert code == 2
    assert_one_line_error(stderr, fragment)
    assert not (tmp_path / "out.txt").exists()


def test_empty_folder_is_a_usage_error(tmp_path):
    (tmp_path / "empty").mkdir()
    code, _, stderr = invoke(
        calibrate.command,
        tmp_path / "empty",
        "--board",
        "9x6",
        "--square",
        "0.05",
        "-o",
        tmp_path / "out.txt",
    )
    assert code == 2
    assert_one_line_error(stderr, "empty", "no images")


@pytest.mark.slow
def test_captures_from_grey_videos(tmp_path):
    fmt = YuvFormat(640, 480, chroma="400")
    videos = []
    for camera in ("cam1", "cam2"):
        path = tmp_path / f"{camera}_640x480_gray.yuv"
        write_video(path, fmt, [(sample_capture(camera, index),) for index in range(12)])
        videos.append(path)
    code, _stdout, stderr = invoke(
        calibrate.command,
        *videos,
        "--board",
        "9x6",
        "--square",
        "0.05",
        "-o",
        tmp_path / "cameras.txt",
    )
    assert code == 0, stderr
    truth = {
        camera["name"]: camera
        for camera in json.loads((CHECKERBOARD / "truth.json").read_text())["cameras"]
    }
    cameras = read_cameras(tmp_path / "cameras.txt")
    assert set(cameras) == {"cam1", "cam2"}
    for name, camera in cameras.items():
        assert camera.fx == pytest.approx(truth[name]["K"][0][0], rel=0.002)
    true_baseline = np.linalg.norm(np.subtract(truth["cam2"]["t"], truth["cam1"]["t"]))
    assert np.linalg.norm(cameras["cam2"].t - cameras["cam1"].t) == pytest.approx(
        true_baseline, rel=0.005
    )


@pytest.mark.slow
def test_a_camera_never_seeing_the_board_with_the_others_is_named(tmp_path):
    blank = np.full((480, 640), 128, np.uint8)
    seen_by_first = [0, 2, 3]
    seen_by_second = [4, 6, 7]
    write_captures(
        tmp_path / "camA",
        [sample_capture("cam2", index) if index in seen_by_first else blank for index in range(8)],
    )
    write_captures(
        tmp_path / "camB",
        [sample_capture("cam3", index) if index in seen_by_second else blank for index in range(8)],
    )
    code, _, stderr = invoke(
        calibrate.command,
        tmp_path / "camA",
        tmp_path / "camB",
        "--board",
        "9x6",
        "--square",
        "0.05",
        "-o",
        tmp_path / "out.txt",
    )
    assert code == 1
    assert_one_line_error(
        stderr, "camB", "never sees the board together with camA", "capture04.png"
    )
    assert not (tmp_path / "out.txt").exists()
