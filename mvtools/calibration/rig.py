"""Intrinsics, lens distortion and poses of a camera rig from checkerboard corners.

Three stages, as calibration toolboxes do it: each camera alone with
``cv2.calibrateCamera`` (its lens, and the board's pose in it at every capture),
rejecting captures it fits badly; the cameras' poses relative to the reference
camera chained through the captures they share; one bundle adjustment of every
camera (intrinsics, distortion, pose) and every board pose over all corners.

Cameras follow :class:`mvtools.geometry.camera.Camera` (``x_cam = R (X - t)``);
the world frame is the reference camera's, in metres (the board's square size).
A board pose ``(B, b)`` maps board to world coordinates, ``X = B @ X_board + b``.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Sequence
from dataclasses import dataclass

import cv2
import numpy as np
from scipy.optimize import least_squares
from scipy.sparse import csr_matrix
from scipy.spatial.transform import Rotation

from mvtools.calibration.detect import Board, Detection
from mvtools.errors import DataError
from mvtools.geometry.camera import Camera
from mvtools.geometry.lens import project_points

__all__ = ["RigCalibration", "calibrate_rig"]

# A capture is an outlier of its camera's single-camera calibration when its RMS is
# this many times the median of the camera's captures (and above max_capture_rms):
# one bad capture stands out; a camera whose every capture fits poorly keeps them.
_OUTLIER_FACTOR = 2.0


@dataclass(eq=False)
class RigCalibration:
    """A calibrated rig and how well it explains the corners.

    Attributes
    ----------
    cameras : list of Camera
        Name, ``K`` (no skew), distortion ``(k1, k2, p1, p2)`` (float64, shape (4,)),
        ``R``, ``t`` and size; the reference camera has ``R = I``, ``t = 0``.
    board_rotations : ndarray, shape (P, 3, 3)
        Board-to-world rotation per capture; NaN for captures no camera used.
    board_translations : ndarray, shape (P, 3)
        Board origin (first inner corner) in the world; NaN likewise.
    used : ndarray, shape (C, P), bool
        The corners of camera ``c`` at capture ``p`` were used.
    rejected : dict
        ``{(camera_index, capture_index): reason}`` for every capture of a camera
        that gave no corners or whose corners were dropped.
    reprojected : ndarray, shape (C, P, N, 2)
        The board's corners projected by the final model; NaN where unused.
    rms : ndarray, shape (C,)
        RMS reprojection error per camera over its used captures (px), after the
        bundle adjustment.
    capture_rms : ndarray, shape (C, P)
        The same per capture; NaN where unused.
    intrinsic_rms : ndarray, shape (C,)
        RMS of the single-camera calibration (px).
    """

    cameras: list
    board_rotations: np.ndarray
    board_translations: np.ndarray
    used: np.ndarray
    rejected: dict
    reprojected: np.ndarray
    rms: np.ndarray
    capture_rms: np.ndarray
    intrinsic_rms: np.ndarray

    def baselines(self) -> np.ndarray:
        """Distance between the centres of cameras ``i`` and ``i + 1`` (metres), shape (C-1,)."""
        centres = np.array([camera.t for camera in self.cameras])
        return np.linalg.norm(np.diff(centres, axis=0), axis=1)

    def axis_angles(self) -> np.ndarray:
        """Angle between the optical axes of cameras ``i`` and ``i + 1`` (degrees), shape (C-1,)."""
        axes = np.array([camera.optical_axis for camera in self.cameras])
        cosines = np.clip(np.sum(axes[:-1] * axes[1:], axis=1), -1.0, 1.0)
        return np.degrees(np.arccos(cosines))


def calibrate_rig(
    image_points,
    board: Board,
    sizes,
    *,
    names: Sequence[str] | None = None,
    reference: int = 0,
    tangential: bool = True,
    max_capture_rms: float = 1.0,
    min_captures: int = 3,
    capture_names: Sequence[str] | None = None,
) -> RigCalibration:
    """Calibrate a rig of cameras that saw one checkerboard at the same instants.

    Parameters
    ----------
    image_points : list over cameras of list over captures
        Each entry an ndarray of shape (N, 2) (corners in :meth:`Board.object_points`
        order), None (board not seen) or a :class:`Detection` (its corners, or its
        reason, which goes to ``rejected``). Capture ``p`` of every camera is the
        same instant.
    board : Board
    sizes : sequence of (width, height)
        Image size per camera.
    names : sequence of str, optional
        Camera names; ``cam0, cam1, ...`` by default.
    reference : int
        Index of the camera whose frame is the world frame.
    tangential : bool
        Estimate the tangential distortion p1, p2; False fixes them at 0. k3 is
        always 0.
    max_capture_rms : float
        A capture whose RMS in its camera's single-camera calibration exceeds this
        (px), and twice the camera's median, is dropped and the camera recalibrated.
    min_captures : int
        Fewest usable captures per camera.
    capture_names : sequence of str, optional
        Names of the captures in error messages (e.g. file names); their indices
        by default.

    Returns
    -------
    RigCalibration

    Raises
    ------
    DataError
        With the camera's name as ``key``: a camera with fewer than
        ``min_captures`` usable captures, or one that never sees the board at the
        same instant as a camera connected to the reference.
    """
    cameras_count = len(image_points)
    if cameras_count == 0:
        raise ValueError("image_points has no camera")
    captures_count = len(image_points[0])
    names = [f"cam{c}" for c in range(cameras_count)] if names is None else list(names)
    _check_arguments(
        image_points,
        board,
        sizes,
        names,
        reference,
        max_capture_rms,
        min_captures,
        capture_names,
        captures_count,
    )
    sizes = [(int(width), int(height)) for width, height in sizes]
    observed, rejected = _observed_corners(image_points, board)
    objects = board.object_points()

    flags = cv2.CALIB_FIX_K3 | (0 if tangential else cv2.CALIB_ZERO_TANGENT_DIST)
    singles = []
    for c, name in enumerate(names):
        found = list(np.flatnonzero(np.isfinite(observed[c, :, 0, 0])))
        if len(found) < min_captures:
            raise DataError(
                f"board found in {len(found)} of {captures_count} captures"
                f"{_listing(found, capture_names, ' (', ')')}; at least "
                f"{min_captures} needed",
                key=name,
            )
        single, dropped = _calibrate_camera(
            name, sizes[c], observed[c], found, objects, flags, max_capture_rms, min_captures
        )
        singles.append(single)
        rejected.update({(c, p): reason for p, reason in dropped.items()})
    used = np.array([np.isfinite(single.board_translations[:, 0]) for single in singles])

    poses, board_rotations, board_translations = _initial_poses(
        singles, used, reference, names, capture_names
    )
    cameras, board_rotations, board_translations = _bundle_adjustment(
        [single.camera for single in singles],
        poses,
        board_rotations,
        board_translations,
        observed,
        used,
        objects,
        reference,
        tangential,
    )

    reprojected = np.full(observed.shape, np.nan)
    for c, camera in enumerate(cameras):
        reprojected[c, used[c]] = _board_corners(
            camera, board_rotations[used[c]], board_translations[used[c]], objects
        )
    squared = np.sum((reprojected - observed) ** 2, axis=-1)
    return RigCalibration(
        cameras=cameras,
        board_rotations=board_rotations,
        board_translations=board_translations,
        used=used,
        rejected=rejected,
        reprojected=reprojected,
        rms=np.sqrt(np.nanmean(squared.reshape(cameras_count, -1), axis=1)),
        capture_rms=np.sqrt(np.mean(squared, axis=-1)),
        intrinsic_rms=np.array([single.rms for single in singles]),
    )


def _check_arguments(
    image_points,
    board,
    sizes,
    names,
    reference,
    max_capture_rms,
    min_captures,
    capture_names,
    captures_count,
):
    cameras_count = len(image_points)
    if not isinstance(board, Board):
        raise ValueError(f"board must be a Board, got {type(board).__name__}")
    if len(sizes) != cameras_count:
        raise ValueError(f"sizes has {len(sizes)} entries for {cameras_count} cameras")
    for size in sizes:
        if len(size) != 2 or min(size) <= 0:
            raise ValueError(f"sizes must be positive (width, height) pairs, got {size!r}")
    if len(names) != cameras_count or len(set(names)) != cameras_count:
        raise ValueError(f"need {cameras_count} distinct camera names, got {names}")
    if not 0 <= reference < cameras_count:
        raise ValueError(
            f"reference must be a camera index in [0, {cameras_count}), got {reference}"
        )
    if not max_capture_rms > 0:
        raise ValueError(f"max_capture_rms must be positive, got {max_capture_rms!r}")
    if min_captures < 2:
        raise ValueError(
            f"min_captures must be at least 2 (one view of a plane does not "
            f"determine a camera's intrinsics), got {min_captures}"
        )
    counts = [len(captures) for captures in image_points]
    if set(counts) != {captures_count} or captures_count == 0:
        raise ValueError(f"every camera needs the same, non-zero number of captures, got {counts}")
    if capture_names is not None and len(capture_names) != captures_count:
        raise ValueError(
            f"capture_names has {len(capture_names)} entries for {captures_count} captures"
        )


def _observed_corners(image_points, board: Board) -> tuple[np.ndarray, dict]:
    """The corners as one array, shape (C, P, N, 2), NaN where a camera has none at a
    capture, and the reasons why it has none."""
    observed = np.full((len(image_points), len(image_points[0]), board.corner_count, 2), np.nan)
    rejected = {}
    for c, captures in enumerate(image_points):
        for p, entry in enumerate(captures):
            reason = "board not found"
            if isinstance(entry, Detection):
                entry, reason = entry.corners, entry.reason
            if entry is None:
                rejected[(c, p)] = reason
                continue
            points = np.asarray(entry, dtype=np.float64)
            if points.shape != (board.corner_count, 2) or not np.all(np.isfinite(points)):
                raise ValueError(
                    f"image_points[{c}][{p}] must be finite, of shape "
                    f"({board.corner_count}, 2), got shape {points.shape}"
                )
            observed[c, p] = points
    return observed, rejected


def _listing(captures, capture_names, before="", after="") -> str:
    """``"captures 4, 7"`` (or the captures' names), between ``before`` and ``after``."""
    if not captures:
        return ""
    if capture_names is not None:
        text = ", ".join(str(capture_names[p]) for p in captures)
    else:
        text = ("capture " if len(captures) == 1 else "captures ") + ", ".join(map(str, captures))
    return before + text + after


def _board_corners(camera: Camera, rotations, translations, objects) -> np.ndarray:
    """The board's corners at poses ``(rotations[i], translations[i])`` seen by ``camera``,
    shape (len(rotations), N, 2)."""
    world = objects @ np.transpose(rotations, (0, 2, 1)) + translations[:, None]
    return project_points(camera, world.reshape(-1, 3))[0].reshape(len(rotations), -1, 2)


@dataclass
class _SingleCamera:
    camera: Camera  # K and (k1, k2, p1, p2); R = I, t = 0
    rms: float
    board_rotations: np.ndarray  # (P, 3, 3) board to camera, NaN where not kept
    board_translations: np.ndarray  # (P, 3)


def _calibrate_camera(
    name, size, observed, found, objects, flags, max_capture_rms, min_captures
) -> tuple[_SingleCamera, dict]:
    """``cv2.calibrateCamera`` on the captures in ``found`` (``observed`` of shape
    (P, N, 2)), dropping outliers one at a time, the worst first (one bad capture also
    inflates the others' errors). Returns the camera and ``{capture: reason}`` of the
    dropped captures."""
    kept, dropped = list(found), {}
    while True:
        rms, K, distortion, rvecs, tvecs = _single_threaded(
            cv2.calibrateCamera,
            [objects.astype(np.float32)] * len(kept),
            list(observed[kept].astype(np.float32)),
            size,
            None,
            None,
            flags=flags,
        )
        camera = Camera(name, K=K, distortion=distortion.ravel()[:4], size=size)
        rotations = np.full((len(observed), 3, 3), np.nan)
        translations = np.full((len(observed), 3), np.nan)
        rotations[kept] = [cv2.Rodrigues(rvec)[0] for rvec in rvecs]
        translations[kept] = np.reshape(tvecs, (-1, 3))
        projected = _board_corners(camera, rotations[kept], translations[kept], objects)
        errors = np.sqrt(np.mean(np.sum((projected - observed[kept]) ** 2, axis=-1), axis=-1))
        worst, median = int(np.argmax(errors)), float(np.median(errors))
        if (
            len(kept) <= min_captures
            or errors[worst] <= max_capture_rms
            or errors[worst] <= _OUTLIER_FACTOR * median
        ):
            return _SingleCamera(
                camera=camera,
                rms=float(rms),
                board_rotations=rotations,
                board_translations=translations,
            ), dropped
        dropped[kept[worst]] = (
            f"reprojection RMS {errors[worst]:.2f} px in the calibration of {name} alone, "
            f"above {max_capture_rms:g} px and {_OUTLIER_FACTOR:g} times the median "
            f"{median:.2f} px"
        )
        del kept[worst]


def _single_threaded(function, *args, **kwargs):
    """``function`` run with OpenCV on one thread: calibrateCamera's parallel sums
    otherwise differ in the last bits from one call to the next."""
    threads = cv2.getNumThreads()
    cv2.setNumThreads(1)
    try:
        return function(*args, **kwargs)
    finally:
        cv2.setNumThreads(threads)


def _initial_poses(singles, used, reference, names, capture_names):
    """Camera poses ``(R, T)`` (``x_cam = R X + T``) and board poses ``(B, b)`` in the
    reference camera's frame, chained breadth-first through the bipartite graph of
    cameras and the captures they used, from each camera's own board poses
    (``x_cam = R_cp X_board + T_cp = R (B X_board + b) + T``)."""
    captures_count = used.shape[1]
    poses = {reference: (np.eye(3), np.zeros(3))}
    board_rotations = np.full((captures_count, 3, 3), np.nan)
    board_translations = np.full((captures_count, 3), np.nan)
    queue = deque([reference])
    while queue:
        c = queue.popleft()
        rotation, translation = poses[c]
        for p in np.flatnonzero(used[c] & np.isnan(board_translations[:, 0])):
            board_rotations[p] = rotation.T @ singles[c].board_rotations[p]
            board_translations[p] = rotation.T @ (singles[c].board_translations[p] - translation)
            for other in np.flatnonzero(used[:, p]):
                if other not in poses:
                    other_rotation = singles[other].board_rotations[p] @ board_rotations[p].T
                    poses[other] = (
                        other_rotation,
                        singles[other].board_translations[p]
                        - other_rotation @ board_translations[p],
                    )
                    queue.append(other)
    for c, name in enumerate(names):
        if c not in poses:
            connected = ", ".join(names[other] for other in sorted(poses))
            raise DataError(
                f"never sees the board together with {connected} (it sees it in "
                f"{_listing(list(np.flatnonzero(used[c])), capture_names)})",
                key=name,
            )
    return poses, board_rotations, board_translations


def _bundle_adjustment(
    cameras,
    poses,
    board_rotations,
    board_translations,
    observed,
    used,
    objects,
    reference,
    tangential,
):
    """Refine every camera's intrinsics, distortion and pose (the reference's stays the
    identity) and every board pose by least squares over all used corners.

    Returns the cameras and the board poses (NaN for captures no camera used)."""
    intrinsic_count = 8 if tangential else 6
    moving = [c for c in range(len(cameras)) if c != reference]
    captures = np.flatnonzero(used.any(axis=0))

    def intrinsics_of(camera):
        return np.concatenate(
            [[camera.fx, camera.fy, camera.cx, camera.cy], camera.distortion[: intrinsic_count - 4]]
        )

    def pose_vectors(rotations, translations):
        return np.hstack([Rotation.from_matrix(rotations).as_rotvec(), translations]).ravel()

    x0 = np.concatenate(
        [intrinsics_of(camera) for camera in cameras]
        + [
            pose_vectors(
                np.reshape([poses[c][0] for c in moving], (-1, 3, 3)),
                np.reshape([poses[c][1] for c in moving], (-1, 3)),
            )
        ]
        + [pose_vectors(board_rotations[captures], board_translations[captures])]
    )
    pose_column = {c: intrinsic_count * len(cameras) + 6 * i for i, c in enumerate(moving)}
    board_start = intrinsic_count * len(cameras) + 6 * len(moving)
    board_column = dict(zip(captures, board_start + 6 * np.arange(len(captures))))

    def unpack(x):
        rig = []
        for c, camera in enumerate(cameras):
            fx, fy, cx, cy, *distortion = x[intrinsic_count * c : intrinsic_count * (c + 1)]
            rotation, translation = np.eye(3), np.zeros(3)
            if c != reference:
                vector = x[pose_column[c] : pose_column[c] + 6]
                rotation, translation = Rotation.from_rotvec(vector[:3]).as_matrix(), vector[3:]
            rig.append(
                Camera(
                    camera.name,
                    K=[[fx, 0.0, cx], [0.0, fy, cy], [0.0, 0.0, 1.0]],
                    R=rotation,
                    t=-rotation.T @ translation,
                    distortion=np.pad(distortion, (0, 4 - len(distortion))),
                    size=camera.size,
                )
            )
        rotations = np.full((used.shape[1], 3, 3), np.nan)
        translations = np.full((used.shape[1], 3), np.nan)
        vectors = x[board_start:].reshape(-1, 6)
        rotations[captures] = Rotation.from_rotvec(vectors[:, :3]).as_matrix()
        translations[captures] = vectors[:, 3:]
        return rig, rotations, translations

    target = observed[used].ravel()

    def residuals(x):
        rig, rotations, translations = unpack(x)
        projected = [
            _board_corners(camera, rotations[used[c]], translations[used[c]], objects)
            for c, camera in enumerate(rig)
        ]
        return np.concatenate([corners.ravel() for corners in projected]) - target

    # The rows of an observation, 2 N residuals (u, v per corner, in the order of
    # observed[used]), depend on its camera's intrinsics and pose (unless the
    # reference) and its board's pose.
    rows_per_observation = 2 * len(objects)
    rows, columns = [], []
    for o, (c, p) in enumerate(zip(*np.nonzero(used))):
        parameters = list(range(intrinsic_count * c, intrinsic_count * (c + 1)))
        if c != reference:
            parameters += range(pose_column[c], pose_column[c] + 6)
        parameters += range(board_column[p], board_column[p] + 6)
        rows.append(
            np.repeat(
                np.arange(o * rows_per_observation, (o + 1) * rows_per_observation), len(parameters)
            )
        )
        columns.append(np.tile(parameters, rows_per_observation))
    rows, columns = np.concatenate(rows), np.concatenate(columns)
    sparsity = csr_matrix(
        (np.ones(len(rows), dtype=np.int8), (rows, columns)), shape=(len(target), len(x0))
    )
    # lsmr stopped at its default min(m, n) iterations leaves the Gauss-Newton step
    # unfinished on this ill-conditioned problem (focal length against distance):
    # 30-40 outer iterations instead of the 4 a dense solver takes to the same minimum.
    solution = least_squares(
        residuals,
        x0,
        jac_sparsity=sparsity,
        method="trf",
        x_scale="jac",
        tr_options={"atol": 1e-12, "btol": 1e-12, "maxiter": 10 * len(x0)},
    )
    return unpack(solution.x)
