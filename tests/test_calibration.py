"""Checkerboard detection and rig calibration against known truth.

Truth: the synthetic rig of ``sample_data/checkerboard`` (exact cameras, board poses
and corner positions, in ``truth.json``) and OpenCV's published stereo captures, whose
reference results are OpenCV's own: ``calibrateCamera`` on the left camera, fx 536.07 px
at RMS 0.41 px, and ``stereoCalibrate``'s baseline, 0.08362 m.
"""

from __future__ import annotations

import itertools
import json
from pathlib import Path

import cv2
import numpy as np
import pytest
from shared_data import shared_data

from mvtools.calibration import Board, Detection, calibrate_rig, detect_board, grid_defect
from mvtools.errors import DataError
from mvtools.geometry.camera import Camera
from mvtools.io.images import read_image

CHECKERBOARD = Path(__file__).resolve().parent.parent / "sample_data" / "checkerboard"
STEREO_CAPTURES = (1, 2, 3, 4, 5, 6, 7, 8, 9, 11, 12, 13, 14)  # left10/right10 do not exist


def rotation_degrees(first: np.ndarray, second: np.ndarray) -> float:
    cosine = (np.trace(first @ second.T) - 1.0) / 2.0
    return float(np.degrees(np.arccos(np.clip(cosine, -1.0, 1.0))))


# --------------------------------------------------------------------------- the sample rig


@pytest.fixture(scope="module")
def truth():
    """The sample rig's true cameras, board poses and corners, shape (C, P, N, 2)."""
    data = json.loads((CHECKERBOARD / "truth.json").read_text())
    cameras = [
        Camera(
            c["name"],
            K=c["K"],
            R=c["R"],
            t=c["t"],
            distortion=c["distortion"],
            size=tuple(c["size"]),
        )
        for c in data["cameras"]
    ]
    captures = data["captures"]
    corners = np.array(
        [[capture["corners"][camera.name] for capture in captures] for camera in cameras]
    )
    visible = np.array(
        [[capture["visible"][camera.name] for capture in captures] for camera in cameras]
    )
    board = Board(tuple(data["board"]["inner_corners"]), data["board"]["square_size"])
    return {
        "cameras": cameras,
        "board": board,
        "corners": corners,
        "visible": visible,
        "rotations": np.array([capture["rotation"] for capture in captures]),
        "translations": np.array([capture["translation"] for capture in captures]),
    }


def in_frame_of(cameras, reference: int):
    """Rotations and centres of ``cameras`` in the frame of camera ``reference``, where a
    calibration puts its world."""
    R0, t0 = cameras[reference].R, cameras[reference].t
    return [camera.R @ R0.T for camera in cameras], [R0 @ (camera.t - t0) for camera in cameras]


def sample_images(noise: float) -> np.ndarray:
    """The committed captures (rendered without noise), shape (C, P, H, W), with Gaussian
    noise of ``noise`` grey levels added as the renderer adds it."""
    images = np.array(
        [
            [read_image(path) for path in sorted((CHECKERBOARD / f"cam{c}").glob("capture*.png"))]
            for c in range(5)
        ]
    )
    rng = np.random.default_rng(2024)
    return (
        np.clip(np.round(images + rng.normal(0.0, noise, images.shape)), 0, 255).astype(np.uint8)
        if noise
        else images
    )


@pytest.fixture(scope="module", params=[0.0, 1.0], ids=["noise0", "noise1"])
def sample_detections(request, truth):
    images = sample_images(request.param)
    return [[detect_board(image, truth["board"]) for image in camera] for camera in images]


@pytest.mark.slow
def test_detected_corners_are_the_true_corners_in_their_order(sample_detections, truth):
    found = np.array([[d.corners is not None for d in camera] for camera in sample_detections])
    corners = truth["corners"]
    inside = np.all((corners >= 0) & (corners <= [639, 479]), axis=(2, 3))
    # Every board in full view (10 px from the border) is found, none partly out of view.
    assert np.all(found[truth["visible"]]) and not np.any(found & ~inside)
    assert all(
        d.method == "sector"
        for camera in sample_detections
        for d in camera
        if d.corners is not None
    )
    errors = np.concatenate(
        [
            d.corners - corners[c, p]
            for c, camera in enumerate(sample_detections)
            for p, d in enumerate(camera)
            if d.corners is not None
        ]
    )
    distance = np.linalg.norm(errors, axis=1)
    # Compared in the truth's order, unmatched: the canonical order is the board's own.
    # Measured: RMS 0.056 px, max 0.16 px, at noise 0 and 1 alike (the sector
    # detector alone: RMS 0.10, max 0.45; half a pixel would show a convention slip).
    assert np.sqrt(np.mean(distance**2)) < 0.08
    assert distance.max() < 0.25
    assert np.all(np.abs(errors.mean(axis=0)) < 0.02)


@pytest.fixture(scope="module")
def sample_calibration(sample_detections, truth):
    sizes = [camera.size for camera in truth["cameras"]]
    return calibrate_rig(sample_detections, truth["board"], sizes)


@pytest.mark.slow
def test_sample_rig_recovers_the_true_cameras(sample_calibration, truth):
    result = sample_calibration
    rotations, centres = in_frame_of(truth["cameras"], 0)
    baseline = np.linalg.norm(centres[1] - centres[0])
    np.testing.assert_allclose(baseline, 0.1, rtol=1e-12)
    for c, (camera, true) in enumerate(zip(result.cameras, truth["cameras"])):
        # Measured (noise 0 / 1): fx, fy within 0.02 %, principal points within 0.34 px,
        # k1 within 0.0013, centres within 0.27 mm, rotations within 0.036 degree.
        assert camera.name == true.name and camera.size == (640, 480)
        assert abs(camera.fx / true.fx - 1) < 0.002 and abs(camera.fy / true.fy - 1) < 0.002
        assert np.hypot(camera.cx - true.cx, camera.cy - true.cy) < 1.0
        assert abs(camera.distortion[0] - true.distortion[0]) < 0.01
        assert np.linalg.norm(camera.t - centres[c]) < 0.005 * baseline
        assert rotation_degrees(camera.R, rotations[c]) < 0.1
        assert camera.distortion.shape == (4,) and camera.distortion.dtype == np.float64
    np.testing.assert_array_equal(result.cameras[0].R, np.eye(3))
    np.testing.assert_array_equal(result.cameras[0].t, np.zeros(3))
    # The detections' reasons are kept; the cameras' corners fit to the detector's scatter.
    assert result.rejected[(0, 1)] == "board not found"
    assert set(result.rejected) == set(zip(*np.nonzero(~result.used)))
    assert np.all(result.rms < 0.08) and np.all(result.intrinsic_rms < 0.08)


@pytest.mark.slow
def test_board_poses_and_reprojections_follow_the_truth(sample_calibration, truth):
    result = sample_calibration
    R0, t0 = truth["cameras"][0].R, truth["cameras"][0].t
    seen = result.used.any(axis=0)
    for p in np.flatnonzero(seen):
        assert rotation_degrees(result.board_rotations[p], R0 @ truth["rotations"][p]) < 0.1
        np.testing.assert_allclose(
            result.board_translations[p], R0 @ (truth["translations"][p] - t0), atol=1e-3
        )
    assert np.all(np.isnan(result.board_rotations[~seen]))
    used = result.used
    assert np.all(np.isfinite(result.reprojected[used])) and np.all(
        np.isnan(result.reprojected[~used])
    )
    # The model's projections are the exact corners, to well below the detector's error.
    error = np.linalg.norm(result.reprojected[used] - truth["corners"][used], axis=-1)
    assert np.sqrt(np.mean(error**2)) < 0.03
    assert np.all(np.isnan(result.capture_rms[~used]))
    for c in range(5):
        # Every capture has the same 54 corners: the camera's mean square is theirs.
        np.testing.assert_allclose(
            result.rms[c] ** 2, np.mean(result.capture_rms[c, used[c]] ** 2), rtol=1e-12
        )


@pytest.mark.slow
def test_baselines_and_axis_angles_by_hand(sample_calibration, truth):
    result = sample_calibration
    true_centres = [camera.t for camera in truth["cameras"]]
    np.testing.assert_allclose(result.baselines(), [0.1] * 4, rtol=0.005)
    assert np.allclose(np.diff(true_centres, axis=0), [0.1, 0, 0])
    axes = [camera.R[2] for camera in truth["cameras"]]
    true_angles = [np.degrees(np.arccos(a @ b)) for a, b in itertools.pairwise(axes)]
    np.testing.assert_allclose(result.axis_angles(), true_angles, atol=0.1)


# --------------------------------------------------------------------------- exact corners


def exact_points(truth, keep):
    """The true corners as image points, None where ``keep`` (C, P) is False."""
    return [
        [truth["corners"][c, p] if keep[c, p] else None for p in range(keep.shape[1])]
        for c in range(keep.shape[0])
    ]


@pytest.mark.slow
def test_exact_corners_give_the_exact_rig_through_a_chain_of_cameras(truth):
    keep = truth["visible"].copy()
    # cam0 and cam4 never see the board at the same instant: cam4 joins the
    # reference through the others.
    keep[4, keep[0]] = False
    assert keep.sum(axis=1).min() >= 3 and not np.any(keep[0] & keep[4])
    sizes = [camera.size for camera in truth["cameras"]]
    result = calibrate_rig(
        exact_points(truth, keep),
        truth["board"],
        sizes,
        reference=2,
        tangential=False,
        names=["a", "b", "c", "d", "e"],
    )
    rotations, centres = in_frame_of(truth["cameras"], 2)
    for c, (camera, true) in enumerate(zip(result.cameras, truth["cameras"])):
        np.testing.assert_allclose(camera.K, true.K, rtol=1e-10, atol=1e-8)
        np.testing.assert_allclose(camera.distortion, [*true.distortion, 0.0, 0.0], atol=1e-10)
        np.testing.assert_allclose(camera.R, rotations[c], atol=1e-11)
        np.testing.assert_allclose(camera.t, centres[c], atol=1e-11)
    assert [camera.name for camera in result.cameras] == ["a", "b", "c", "d", "e"]
    np.testing.assert_array_equal(result.used, keep)
    # cv2.calibrateCamera takes float32 points (1e-5 px at 640); the adjustment float64.
    assert np.all(result.rms < 1e-10) and np.all(result.intrinsic_rms < 1e-4)
    np.testing.assert_allclose(result.reprojected[keep], truth["corners"][keep], atol=1e-10)
    assert set(result.rejected) == set(zip(*np.nonzero(~keep)))
    again = calibrate_rig(
        exact_points(truth, keep),
        truth["board"],
        sizes,
        reference=2,
        tangential=False,
        names=["a", "b", "c", "d", "e"],
    )
    np.testing.assert_array_equal(again.cameras[4].K, result.cameras[4].K)
    np.testing.assert_array_equal(again.board_translations, result.board_translations)


@pytest.mark.slow
def test_a_full_rig_of_exact_corners_is_fit_exactly(truth):
    # 5 cameras x 12 captures x 54 corners (every board, also those partly out of view).
    keep = np.ones(truth["visible"].shape, dtype=bool)
    result = calibrate_rig(
        exact_points(truth, keep), truth["board"], [camera.size for camera in truth["cameras"]]
    )
    assert result.used.all() and np.all(result.rms < 1e-10)


@pytest.mark.slow
def test_an_outlier_capture_is_dropped_and_its_camera_recalibrated(truth):
    keep = truth["visible"]
    points = exact_points(truth, keep)
    rng = np.random.default_rng(5)
    points[1][4] = points[1][4] + rng.normal(0.0, 3.0, points[1][4].shape)
    result = calibrate_rig(points, truth["board"], [camera.size for camera in truth["cameras"]])
    assert not result.used[1, 4] and result.used[1].sum() == keep[1].sum() - 1
    assert result.rejected[(1, 4)].startswith("reprojection RMS ")
    assert "in the calibration of cam1 alone, above 1 px" in result.rejected[(1, 4)]
    assert np.all(result.rms < 1e-10)
    np.testing.assert_allclose(result.cameras[1].K, truth["cameras"][1].K, rtol=1e-10)


def test_too_few_captures_name_the_camera_and_its_captures(truth):
    keep = truth["visible"].copy()
    keep[3] = False
    keep[3, [4, 7]] = True
    sizes = [camera.size for camera in truth["cameras"]]
    with pytest.raises(DataError) as raised:
        calibrate_rig(exact_points(truth, keep), truth["board"], sizes)
    assert raised.value.key == "cam3"
    assert str(raised.value) == (
        "cam3: board found in 2 of 12 captures (captures 4, 7); at least 3 needed"
    )
    keep[3, 4] = False
    names = [f"shot{p}.png" for p in range(12)]
    with pytest.raises(
        DataError,
        match=r"board found in 1 of 12 captures \(shot7.png\); "
        r"at least 4 needed",
    ):
        calibrate_rig(
            exact_points(truth, keep), truth["board"], sizes, min_captures=4, capture_names=names
        )


def test_a_camera_never_with_the_others_names_them_and_its_captures(truth):
    keep = np.zeros(truth["visible"].shape, dtype=bool)
    keep[:4, :9] = truth["visible"][:4, :9]
    keep[4, 9:] = True
    with pytest.raises(DataError) as raised:
        calibrate_rig(
            exact_points(truth, keep), truth["board"], [camera.size for camera in truth["cameras"]]
        )
    assert raised.value.key == "cam4"
    assert str(raised.value) == (
        "cam4: never sees the board together with cam0, cam1, cam2, "
        "cam3 (it sees it in captures 9, 10, 11)"
    )


def test_bad_arguments_raise_value_errors(truth):
    points = exact_points(truth, truth["visible"])
    sizes = [camera.size for camera in truth["cameras"]]
    board = truth["board"]
    with pytest.raises(ValueError, match="sizes has 4 entries for 5 cameras"):
        calibrate_rig(points, board, sizes[:4])
    with pytest.raises(ValueError, match="reference"):
        calibrate_rig(points, board, sizes, reference=5)
    with pytest.raises(ValueError, match="same, non-zero number of captures"):
        calibrate_rig([*points[:4], points[4][:11]], board, sizes)
    with pytest.raises(
        ValueError,
        match=r"image_points\[0\]\[0\] must be finite, of shape "
        r"\(54, 2\)",
    ):
        calibrate_rig([[points[0][0][:53], *points[0][1:]], *points[1:]], board, sizes)
    with pytest.raises(ValueError, match="min_captures must be at least 2"):
        calibrate_rig(points, board, sizes, min_captures=1)
    with pytest.raises(ValueError, match="distinct camera names"):
        calibrate_rig(points, board, sizes, names=["a"] * 5)


# --------------------------------------------------------------------------- one image


def test_board_object_points_by_hand():
    board = Board((3, 2), 0.1)
    np.testing.assert_allclose(
        board.object_points(),
        [[0, 0, 0], [0.1, 0, 0], [0.2, 0, 0], [0, 0.1, 0], [0.1, 0.1, 0], [0.2, 0.1, 0]],
        atol=1e-15,
    )
    assert board.object_points().dtype == np.float64
    for inner_corners, square_size in (((1, 6), 0.05), ((9, 6.5), 0.05), ((9, 6), 0.0)):
        with pytest.raises(ValueError):
            Board(inner_corners, square_size)


def test_a_blank_image_has_no_board():
    board = Board((9, 6), 0.05)
    assert detect_board(np.full((480, 640), 128, np.uint8), board) == Detection(
        corners=None, method=None, reason="board not found"
    )
    with pytest.raises(ValueError, match="uint8"):
        detect_board(np.zeros((48, 64), np.float32), board)


def test_colour_and_grey_images_give_the_same_corners(truth):
    grey = read_image(CHECKERBOARD / "cam2" / "capture04.png")
    colour = np.repeat(grey[..., None], 3, axis=2)
    np.testing.assert_array_equal(
        detect_board(colour, truth["board"]).corners, detect_board(grey, truth["board"]).corners
    )


@pytest.mark.parametrize("turns", [1, 2, 3])
def test_the_order_follows_the_picture_not_the_detector(truth, turns):
    # The capture turned by quarter turns (counter-clockwise). The board's rows run
    # left to right (rolled by at most 20 degrees): after one turn they run up, after
    # two left, after three down. Rows running up or left are taken from the other end,
    # so the first corner is the truth's last; rows running down keep the truth's order.
    image = read_image(CHECKERBOARD / "cam2" / "capture04.png")
    u, v = truth["corners"][2, 4].T
    width, height = 640, 480
    turned = {
        1: np.stack([v, width - 1 - u], -1),
        2: np.stack([width - 1 - u, height - 1 - v], -1),
        3: np.stack([height - 1 - v, u], -1),
    }[turns]
    expected = turned if turns == 3 else turned[::-1]
    detection = detect_board(np.ascontiguousarray(np.rot90(image, turns)), truth["board"])
    assert np.abs(detection.corners - expected).max() < 0.3


def test_grid_defects(truth):
    board = truth["board"]
    image = read_image(CHECKERBOARD / "cam2" / "capture04.png")
    exact = truth["corners"][2, 4]
    assert grid_defect(image, exact, board) is None
    moved = exact.copy()
    moved[21] += (5.0, 0.0)
    # Measured: the RMS residual over the block around it is 0.3 of the move.
    assert grid_defect(image, moved, board) == (
        "corner grid irregular (homography residual 1.5 px around corner 21)"
    )
    assert grid_defect(image, moved, board, max_residual=2.0) is None
    # The grid one square off towards the board's left margin, as the sector detector
    # sometimes returns it when the board's right end is cut off: regular, but its first
    # column lies where the outer squares meet the light margin.
    grid = exact.reshape(6, 9, 2)
    shifted = np.concatenate([2 * grid[:, :1] - grid[:, 1:2], grid[:, :-1]], axis=1)
    reason = grid_defect(image, shifted.reshape(-1, 2), board)
    assert reason.startswith("corner grid off the board's crossings (6 of 54 corners")
    outside = exact.copy()
    outside[[0, 9]] = [[-0.5, 100.0], [640.0, 100.0]]  # pixel centres run 0 .. 639
    assert grid_defect(image, outside, board) == "corners outside the 640x480 image (2 of 54)"
    with pytest.raises(ValueError, match=r"shape \(54, 2\)"):
        grid_defect(image, exact[:50], board)


# --------------------------------------------------------------------------- OpenCV's stereo set


@pytest.fixture(scope="module")
def stereo():
    folder = shared_data("calibration", "opencv_stereo")
    board = Board((9, 6), 0.025)
    detections = [
        [
            detect_board(
                cv2.imread(str(folder / f"{side}{index:02d}.jpg"), cv2.IMREAD_GRAYSCALE), board
            )
            for index in STEREO_CAPTURES
        ]
        for side in ("left", "right")
    ]
    return (
        board,
        detections,
        calibrate_rig(detections, board, [(640, 480)] * 2, names=["left", "right"]),
    )


def test_opencv_stereo_set_meets_opencv_results(stereo):
    _board, detections, result = stereo
    assert all(d.corners is not None for side in detections for d in side)
    left, right = result.cameras
    print(
        f"\nleft  fx {left.fx:.2f} fy {left.fy:.2f} cx {left.cx:.2f} cy {left.cy:.2f} "
        f"RMS {result.rms[0]:.3f} (alone {result.intrinsic_rms[0]:.3f})"
        f"\nright fx {right.fx:.2f} fy {right.fy:.2f} cx {right.cx:.2f} cy {right.cy:.2f} "
        f"RMS {result.rms[1]:.3f} (alone {result.intrinsic_rms[1]:.3f})"
        f"\nbaseline {result.baselines()[0]:.5f} m, axes {result.axis_angles()[0]:.3f} deg"
    )
    # Measured: fx 533.78 (-0.43 %), RMS 0.195, baseline 0.08318 m (-0.5 %), the same
    # as cv2.stereoCalibrate on these corners. OpenCV's 536.07 at RMS 0.41 comes from
    # cornerSubPix windows of 23 x 23 px, which reach past the outer squares into the
    # board's margin (outer corners' RMS 0.53 px against 0.25 px inside).
    assert left.fx == pytest.approx(536.1, rel=0.005)
    assert result.rms[0] <= 0.45 and result.rms[1] <= 0.45
    assert result.baselines()[0] == pytest.approx(0.0836, rel=0.01)
    # The right camera sits to the right (+x) of the left one, looking the same way.
    assert result.cameras[1].t[0] > 0.08 and result.axis_angles()[0] < 1.0
    assert not result.rejected


def test_stereo_corners_are_far_from_one_homography(stereo):
    # The lens bends the board's rows (k1 = -0.29): a whole-board homography misses
    # the corners by up to 2.3 px RMS, which is why grid_defect fits 3 x 3 blocks.
    board, detections, result = stereo
    assert result.cameras[0].distortion[0] == pytest.approx(-0.29, abs=0.02)
    plane = board.object_points()[:, :2]
    residuals = []
    for d in detections[0] + detections[1]:
        homography, _ = cv2.findHomography(plane, d.corners, 0)
        fitted = cv2.perspectiveTransform(plane[None], homography)[0]
        residuals.append(np.sqrt(np.mean(np.sum((fitted - d.corners) ** 2, axis=1))))
    assert max(residuals) > 2.0
