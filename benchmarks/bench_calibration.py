"""calibrate and rectify against OpenCV on its own stereo captures (13 pairs, 9x6 corners,
25 mm squares): corner detection, calibration and the rows of the board corners after
rectifying, side by side with OpenCV's classic detector, calibrateCamera, stereoCalibrate
and stereoRectify; the synthetic 5-camera rig against its exact truth; and the
throughput of rectifying 1920x1088 4:2:0 frames.
"""

from __future__ import annotations

import json
import time
from pathlib import Path

import cv2
import numpy as np
from common import DATA, median_seconds, report

from mvtools.calibration import Board, calibrate_rig, detect_board
from mvtools.geometry.camera import Camera
from mvtools.geometry.depth import depth_to_z, z_to_depth
from mvtools.io.images import read_image
from mvtools.io.yuv import YuvFormat
from mvtools.rectification import DepthResampler, chroma_maps, rectify_cameras, remap_plane

CAPTURES = [1, 2, 3, 4, 5, 6, 7, 8, 9, 11, 12, 13, 14]
BOARD = Board(inner_corners=(9, 6), square_size=0.025)
BOARD_SAMPLE = Board(inner_corners=(9, 6), square_size=0.05)
SIZE = (640, 480)
SAMPLE_RIG = Path(__file__).resolve().parents[1] / "sample_data" / "checkerboard"
_SUBPIX = (cv2.TERM_CRITERIA_EPS + cv2.TERM_CRITERIA_MAX_ITER, 30, 0.01)


def _opencv_corners(image):
    found, corners = cv2.findChessboardCorners(image, BOARD.inner_corners)
    return cv2.cornerSubPix(image, corners, (11, 11), (-1, -1), _SUBPIX) if found else None


def _row_errors(left_rows, right_rows):
    rows = np.concatenate(left_rows) - np.concatenate(right_rows)
    return float(np.sqrt(np.mean(rows**2))), float(np.max(np.abs(rows)))


def stereo_rows() -> list:
    folder = DATA / "calibration" / "opencv_stereo"
    images = [
        [read_image(folder / f"{side}{index:02d}.jpg", grayscale=True) for index in CAPTURES]
        for side in ("left", "right")
    ]
    start = time.perf_counter()
    ours = [[detect_board(image, BOARD).corners for image in side] for side in images]
    detect_seconds = (time.perf_counter() - start) / (2 * len(CAPTURES))
    start = time.perf_counter()
    theirs = [[_opencv_corners(image) for image in side] for side in images]
    opencv_detect_seconds = (time.perf_counter() - start) / (2 * len(CAPTURES))

    calibration = None

    def calibrate():
        nonlocal calibration
        calibration = calibrate_rig(ours, BOARD, [SIZE] * 2, names=["left", "right"])

    seconds = median_seconds(calibrate, repeats=3)
    left, _right = calibration.cameras
    rectification = rectify_cameras(calibration.cameras)
    rows = _row_errors(
        *(
            [rectification.rectify_points(corners, side)[:, 1] for corners in ours[side]]
            for side in (0, 1)
        )
    )

    objects = [BOARD.object_points().astype(np.float32)] * len(CAPTURES)
    opencv = {}

    def opencv_calibrate():
        rms, K1, D1, _, _ = cv2.calibrateCamera(objects, theirs[0], SIZE, None, None)
        _, K2, D2, _, _ = cv2.calibrateCamera(objects, theirs[1], SIZE, None, None)
        _, K1, D1, K2, D2, R, T, _, _ = cv2.stereoCalibrate(
            objects, theirs[0], theirs[1], K1, D1, K2, D2, SIZE, flags=cv2.CALIB_FIX_INTRINSIC
        )
        opencv.update(rms=rms, K1=K1, D1=D1, K2=K2, D2=D2, R=R, T=T)

    opencv_seconds = median_seconds(opencv_calibrate, repeats=3)
    R1, R2, P1, P2, *_ = cv2.stereoRectify(
        opencv["K1"], opencv["D1"], opencv["K2"], opencv["D2"], SIZE, opencv["R"], opencv["T"]
    )
    opencv_rows = _row_errors(
        *(
            [cv2.undistortPoints(corners, K, D, R=R, P=P)[:, 0, 1] for corners in theirs[side]]
            for side, K, D, R, P in (
                (0, opencv["K1"], opencv["D1"], R1, P1),
                (1, opencv["K2"], opencv["D2"], R2, P2),
            )
        )
    )
    return [
        (
            "stereo: s per capture, corner detection",
            detect_seconds,
            "findChessboardCorners + cornerSubPix 11",
            opencv_detect_seconds,
        ),
        (
            "stereo: s, calibration of the pair",
            seconds,
            "calibrateCamera x2 + stereoCalibrate",
            opencv_seconds,
        ),
        ("stereo: left fx (px), 536.1 +- 0.5 %", left.fx, "calibrateCamera", opencv["K1"][0, 0]),
        (
            "stereo: left RMS (px), at most 0.45",
            calibration.rms[0],
            "calibrateCamera",
            opencv["rms"],
        ),
        (
            "stereo: baseline (m), 0.0836 +- 1 %",
            float(calibration.baselines()[0]),
            "stereoCalibrate",
            float(np.linalg.norm(opencv["T"])),
        ),
        ("stereo: rectified row error RMS (px), <= 0.30", rows[0], "stereoRectify", opencv_rows[0]),
        ("stereo: rectified row error max (px)", rows[1], "stereoRectify", opencv_rows[1]),
    ]


def sample_rig() -> list:
    truth = json.loads((SAMPLE_RIG / "truth.json").read_text())
    names = [camera["name"] for camera in truth["cameras"]]
    corners = [
        [
            detect_board(
                read_image(SAMPLE_RIG / name / f"capture{index:02d}.png"), BOARD_SAMPLE
            ).corners
            for index in range(len(truth["captures"]))
        ]
        for name in names
    ]
    start = time.perf_counter()
    calibration = calibrate_rig(corners, BOARD_SAMPLE, [SIZE] * len(names), names=names)
    seconds = time.perf_counter() - start
    true = [Camera(c["name"], K=c["K"], R=c["R"], t=c["t"]) for c in truth["cameras"]]
    baseline = np.linalg.norm(true[1].t - true[0].t)
    focal, principal, k1, centre, angle = [], [], [], [], []
    for camera, exact, entry in zip(calibration.cameras, true, truth["cameras"]):
        focal.append(max(abs(camera.fx / exact.fx - 1), abs(camera.fy / exact.fy - 1)) * 100)
        principal.append(np.hypot(camera.cx - exact.cx, camera.cy - exact.cy))
        k1.append(abs(camera.distortion[0] - entry["distortion"][0]))
        R = exact.R @ true[0].R.T
        centre.append(np.linalg.norm(camera.t - true[0].R @ (exact.t - true[0].t)) / baseline * 100)
        cosine = (np.trace(camera.R @ R.T) - 1) / 2
        angle.append(np.degrees(np.arccos(np.clip(cosine, -1, 1))))
    return [
        ("rig: s, 5 cameras x 12 captures", seconds, "", None),
        ("rig: worst focal error %, at most 0.2", max(focal), "", None),
        ("rig: worst principal point error px, at most 1", max(principal), "", None),
        ("rig: worst K1 error, at most 0.01", max(k1), "", None),
        ("rig: worst centre error % of baseline, <= 0.5", max(centre), "", None),
        ("rig: worst rotation error degrees, <= 0.1", max(angle), "", None),
    ]


def rectify_throughput() -> list:
    width, height = 1920, 1088
    K = [[1732.9, 0.0, 943.2], [0.0, 1729.9, 548.8], [0.0, 0.0, 1.0]]
    turn = cv2.Rodrigues(np.radians([0.4, -0.3, 0.2]))[0]
    cameras = [
        Camera("a", K=K, t=[0.0, 0, 0], distortion=[-0.05, 0.01], size=(width, height)),
        Camera("b", K=K, R=turn, t=[0.1, 0, 0], distortion=[0.03, 0.0], size=(width, height)),
    ]
    maps_seconds = median_seconds(lambda: rectify_cameras(cameras), repeats=3) / 2
    map_x, map_y = rectify_cameras(cameras).maps[1]
    fmt = YuvFormat(width, height)
    rng = np.random.default_rng(0)
    planes = [rng.integers(0, 256, shape, dtype=np.uint8) for shape in fmt.plane_shapes]
    chroma = chroma_maps(map_x, map_y, subsampling=(2, 2))

    def ours():
        remap_plane(planes[0], map_x, map_y, fill=16)
        for plane in planes[1:]:
            remap_plane(plane, *chroma, fill=128)

    def opencv():
        cv2.remap(
            planes[0],
            map_x,
            map_y,
            cv2.INTER_LINEAR,
            borderMode=cv2.BORDER_CONSTANT,
            borderValue=16,
        )
        for plane in planes[1:]:
            cv2.remap(
                plane, *chroma, cv2.INTER_LINEAR, borderMode=cv2.BORDER_CONSTANT, borderValue=128
            )

    rectified = rectify_cameras(cameras).cameras[1]
    resample = DepthResampler(cameras[1], rectified, map_x, map_y)
    depth = rng.integers(0, 65536, (height, width), dtype=np.uint16)

    def ours_depth():
        z_to_depth(resample(depth_to_z(depth, 2.0, 13.0, bits=16)), 2.0, 13.0, bits=16)

    def opencv_depth():
        cv2.remap(depth, map_x, map_y, cv2.INTER_NEAREST, borderMode=cv2.BORDER_CONSTANT)

    return [
        ("rectify: s per camera, maps 1920x1088", maps_seconds, "", None),
        (
            "rectify: frames/s, 1920x1088 16-bit depth",
            1 / median_seconds(ours_depth),
            "cv2.remap nearest, z not re-measured",
            1 / median_seconds(opencv_depth),
        ),
        (
            "rectify: frames/s, 1920x1088 4:2:0 texture",
            1 / median_seconds(ours),
            "cv2.remap of the three planes",
            1 / median_seconds(opencv),
        ),
    ]


def main() -> None:
    report(stereo_rows() + sample_rig() + rectify_throughput())


if __name__ == "__main__":
    main()
