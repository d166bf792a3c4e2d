"""Calibration of a camera array from checkerboard captures: the run functions of
``mvtools calibrate``.

:func:`calibrate_rig` searches every capture for the board and fits the rig, giving the
:class:`mvtools.calibration.RigCalibration` and its report; :func:`write_rig_cameras`
and :func:`write_rig_report` write them as the program does. The detection and the fit
(:mod:`mvtools.calibration`) load OpenCV and SciPy when a run starts, so this module is
cheap to import.
"""

from __future__ import annotations

import itertools
import json
import logging
import os
from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from mvtools.errors import DataError, UsageError
from mvtools.geometry.camera import Camera
from mvtools.geometry.lens import distort_normalized
from mvtools.io.atomic import atomic_output
from mvtools.io.cameras import write_cameras
from mvtools.io.captures import CaptureSource
from mvtools.io.images import write_image
from mvtools.io.json_cameras import write_json_cameras
from mvtools.run.stream import ProgressCallback, stream_frames

if TYPE_CHECKING:
    from mvtools.calibration import Board, Detection, RigCalibration

LOG = logging.getLogger(__name__)

#: The report's file in the report folder, beside the corner pictures.
REPORT_FILE = "report.json"

# Tangential terms that move no pixel by more than this (about the RMS error of a good
# calibration) are not worth a warning when the MPEG file drops them.
_NEGLIGIBLE_PIXELS = 0.25


@dataclass(frozen=True)
class CalibrateOptions:
    """How a rig is fitted (the options of ``mvtools calibrate``).

    Attributes
    ----------
    reference : str, optional
        The camera whose frame is the world's (default: the first).
    tangential : bool
        Fit the tangential distortion P1, P2 besides K1, K2 (the chapter's lens model);
        the MPEG camera file stores only K1 and K2.
    max_capture_rms : float
        Captures whose reprojection error (px RMS) exceeds this are dropped.
    """

    reference: str | None = None
    tangential: bool = True
    max_capture_rms: float = 1.0


@dataclass(frozen=True)
class CalibratedRig:
    """What :func:`calibrate_rig` found.

    Attributes
    ----------
    calibration : RigCalibration
        The cameras (distortion K1, K2, P1, P2) and their errors.
    report : dict
        The report (JSON-ready): per camera its model, errors and the captures used and
        rejected, named by file; the baselines and axis angles of neighbours.
    detections : list of list of Detection
        Per camera, the board's detection in each capture.
    first_images : list of ndarray or None
        Per camera, its first capture with a board (None if it saw none).
    where : list of list of str
        Per camera, the file of each capture (a video's: ``file, frame N``).
    """

    calibration: RigCalibration
    report: dict
    detections: list[list[Detection]]
    first_images: list[np.ndarray | None]
    where: list[list[str]]

    @property
    def mpeg_cameras(self) -> list[Camera]:
        """The cameras as the MPEG camera file holds them: K1, K2 alone."""
        return [
            _with_distortion(camera, camera.distortion[:2]) for camera in self.calibration.cameras
        ]

    @property
    def pinhole_cameras(self) -> list[Camera]:
        """The cameras without lens distortion, as MPEG-I JSON holds them (what they are
        after ``mvtools rectify`` has removed it)."""
        return [_with_distortion(camera, np.zeros(2)) for camera in self.calibration.cameras]


def camera_names(sources: Sequence[CaptureSource], names: Sequence[str] | None) -> list[str]:
    """The cameras' names: ``names``, else the sources' own.

    Raises
    ------
    UsageError
        Not one name per source, names not distinct, or sources with different
        numbers of captures (captures are matched by their order).
    """
    if names is not None:
        given = list(names)
        if len(given) != len(sources):
            raise UsageError(f"--names gives {len(given)} names for {len(sources)} cameras")
    else:
        given = [source.name for source in sources]
    if len(set(given)) != len(given):
        raise UsageError(f"camera names {', '.join(given)} are not distinct; give --names")
    counts = {len(source) for source in sources}
    if len(counts) > 1:
        listed = ", ".join(f"{name} {len(source)}" for name, source in zip(given, sources))
        raise UsageError(
            f"the cameras have different numbers of captures ({listed}); "
            "captures are matched by their order, one per instant"
        )
    return given


def corner_picture(folder: str | os.PathLike, name: str) -> Path:
    """The report's picture of camera ``name``'s detected corners, in ``folder``."""
    return Path(folder) / f"{name}_corners.png"


def calibrate_rig(
    sources: Sequence[CaptureSource],
    board: Board,
    *,
    names: Sequence[str] | None = None,
    options: CalibrateOptions | None = None,
    progress: ProgressCallback | None = None,
) -> CalibratedRig:
    """Calibrate a camera array from checkerboard captures taken at the same instants.

    Per camera, the lens distortion and intrinsics are fitted first, then all cameras'
    poses jointly with the board poses (:func:`mvtools.calibration.calibrate_rig`);
    the world frame is the reference camera's and the scale is the board's.

    Parameters
    ----------
    sources : sequence of CaptureSource
        Each camera's captures in capture order, opened
        (:func:`mvtools.io.captures.open_captures`); the caller closes them.
    board : Board
    names : sequence of str, optional
        One per source (default: the sources' names; see :func:`camera_names`).
    options : CalibrateOptions, optional
    progress : callable, optional
        ``progress(done, total)`` after each capture searched, over all cameras.

    Returns
    -------
    CalibratedRig

    Raises
    ------
    UsageError
        Bad names or reference, sources of different lengths.
    DataError
        A capture of another size than its camera's others; a rig the captures
        cannot calibrate.
    """
    from mvtools import calibration

    options = options or CalibrateOptions()
    names = camera_names(sources, names)
    reference = _reference_index(names, options.reference)
    detections, sizes, first_images = _detect(sources, names, board, progress)
    where = [[source.where(index) for index in range(len(source))] for source in sources]
    result = calibration.calibrate_rig(
        detections,
        board,
        sizes,
        names=names,
        reference=reference,
        tangential=options.tangential,
        max_capture_rms=options.max_capture_rms,
        capture_names=_instant_names([source.labels for source in sources]),
    )
    for (camera, capture), reason in sorted(result.rejected.items()):
        LOG.info("%s: %s: %s", names[camera], where[camera][capture], reason)
    return CalibratedRig(result, _report(result, where), detections, first_images, where)


def write_rig_cameras(
    rig: CalibratedRig,
    output: str | os.PathLike,
    json_output: str | os.PathLike | None = None,
) -> None:
    """Write the cameras as an MPEG camera parameter file (K1, K2 in the distortion
    slots) and, when ``json_output`` is given, as MPEG-I JSON (no lens distortion).

    Warns of what each format cannot hold: tangential terms that move a pixel by more
    than a quarter pixel, any distortion in the JSON file.
    """
    cameras = rig.calibration.cameras
    for camera in cameras:
        lost = tangential_pixels(camera)
        if lost > _NEGLIGIBLE_PIXELS:
            LOG.warning(
                "%s: the MPEG camera file cannot store the tangential distortion "
                "P1 %.3g, P2 %.3g (up to %.2f px in the picture); --no-tangential "
                "fits a model the file holds exactly",
                camera.name,
                camera.distortion[2],
                camera.distortion[3],
                lost,
            )
    write_cameras(output, rig.mpeg_cameras)
    if json_output is not None:
        if any(np.any(camera.distortion != 0) for camera in cameras):
            LOG.warning(
                "%s: MPEG-I JSON has no lens distortion: it describes the cameras "
                "after `mvtools rectify` has removed it",
                json_output,
            )
        write_json_cameras(json_output, rig.pinhole_cameras)


def write_rig_report(rig: CalibratedRig, folder: str | os.PathLike) -> None:
    """Write :data:`REPORT_FILE` (the rig's report) into ``folder`` (created), and per
    camera that saw the board its first such capture with the detected corners and
    their reprojections drawn (:func:`corner_picture`)."""
    from mvtools.calibration.drawing import draw_corners

    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    with atomic_output(folder / REPORT_FILE, "w") as handle:
        json.dump(rig.report, handle, indent=2)
        handle.write("\n")
    result = rig.calibration
    for index, camera in enumerate(result.cameras):
        if rig.first_images[index] is None:
            continue
        used = np.flatnonzero(result.used[index])
        detected = [rig.detections[index][capture].corners for capture in used]
        reprojected = [result.reprojected[index, capture] for capture in used]
        write_image(
            corner_picture(folder, camera.name),
            draw_corners(rig.first_images[index], detected, reprojected),
        )


def tangential_pixels(camera: Camera) -> float:
    """Largest displacement in pixels that P1, P2 cause over the picture's border."""
    if camera.distortion.size <= 2 or not np.any(camera.distortion[2:]):
        return 0.0
    width, height = camera.size
    u = np.concatenate(
        [
            np.linspace(0, width - 1, 64),
            np.linspace(0, width - 1, 64),
            np.zeros(64),
            np.full(64, width - 1.0),
        ]
    )
    v = np.concatenate(
        [
            np.zeros(64),
            np.full(64, height - 1.0),
            np.linspace(0, height - 1, 64),
            np.linspace(0, height - 1, 64),
        ]
    )
    x, y = (u - camera.cx) / camera.fx, (v - camera.cy) / camera.fy
    full = np.stack(distort_normalized(x, y, camera.distortion))
    radial = np.stack(distort_normalized(x, y, camera.distortion[:2]))
    shift = (full - radial) * np.array([[camera.fx], [camera.fy]])
    return float(np.max(np.hypot(*shift)))


def _reference_index(names: list[str], reference: str | None) -> int:
    if reference is None:
        return 0
    if reference not in names:
        raise UsageError(f"--reference {reference}: no such camera (cameras: {', '.join(names)})")
    return names.index(reference)


def _instant_names(labels: list[list[str]]) -> list[str]:
    """Names of the capture instants in messages: the file names where every camera uses
    the same ones (cam0/capture03.png, cam1/capture03.png), else the 1-based order."""
    if all(camera_labels == labels[0] for camera_labels in labels):
        return list(labels[0])
    return [f"#{index + 1}" for index in range(len(labels[0]))]


def _detect(sources, names, board, progress):
    """The board's detection in every capture, image sizes, and each camera's first
    capture with a board (for the report)."""
    total = sum(len(source) for source in sources)
    searched = 0
    image_points, sizes, first_images = [], [], []
    for name, source in zip(names, sources):

        def overall(done, _, before=searched):
            if progress is not None:
                progress(before + done, total)

        points, size, first = _detect_camera(source, name, board, overall)
        searched += len(source)
        found = sum(detection.corners is not None for detection in points)
        LOG.info("%s: board found in %d of %d captures", name, found, len(points))
        image_points.append(points)
        sizes.append(size)
        first_images.append(first)
    return image_points, sizes, first_images


def _detect_camera(source: CaptureSource, name: str, board, progress):
    """One camera's detections, image size and first capture with a board."""
    from mvtools.calibration import detect_board

    points, size, first = [], None, None

    def search(index, image):
        nonlocal size, first
        shape = (image.shape[1], image.shape[0])
        if size is None:
            size = shape
        elif shape != size:
            raise DataError(
                f"capture is {shape[0]}x{shape[1]}, the camera's earlier "
                f"captures {size[0]}x{size[1]}",
                path=source.where(index),
                key=name,
            )
        detection = detect_board(image, board)
        if detection.corners is not None and first is None:
            first = image
        points.append(detection)

    stream_frames(range(len(source)), search, readers=[source], progress=progress)
    return points, size, first


def _with_distortion(camera: Camera, distortion) -> Camera:
    return replace(camera, distortion=np.array(distortion, dtype=np.float64))


def _report(result: RigCalibration, where) -> dict:
    cameras = []
    for index, camera in enumerate(result.cameras):
        used = np.flatnonzero(result.used[index])
        cameras.append(
            {
                "name": camera.name,
                "size": list(camera.size),
                "K": camera.K.tolist(),
                "distortion": {
                    "K1": camera.distortion[0],
                    "K2": camera.distortion[1],
                    "P1": camera.distortion[2] if camera.distortion.size > 2 else 0.0,
                    "P2": camera.distortion[3] if camera.distortion.size > 3 else 0.0,
                },
                "R": camera.R.tolist(),
                "t": camera.t.tolist(),
                "rms_px": float(result.rms[index]),
                "intrinsic_rms_px": float(result.intrinsic_rms[index]),
                "captures_used": [where[index][capture] for capture in used],
                "capture_rms_px": {
                    where[index][capture]: float(result.capture_rms[index, capture])
                    for capture in used
                },
                "captures_rejected": {
                    where[camera_index][capture]: reason
                    for (camera_index, capture), reason in sorted(result.rejected.items())
                    if camera_index == index
                },
            }
        )
    names = [camera.name for camera in result.cameras]
    neighbours = [f"{a}-{b}" for a, b in itertools.pairwise(names)]
    return {
        "cameras": cameras,
        "baselines_m": dict(zip(neighbours, result.baselines().tolist())),
        "axis_angles_deg": dict(zip(neighbours, result.axis_angles().tolist())),
    }
