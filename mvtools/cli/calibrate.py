"""``mvtools calibrate``: checkerboard captures to an MPEG camera parameter file."""

from __future__ import annotations

import itertools
import json
import logging
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING

import click
import numpy as np

from mvtools.cli.options import POSITIVE, ProgramCommand, program, video_format_options
from mvtools.cli.progress import Progress
from mvtools.errors import DataError, UsageError
from mvtools.geometry.lens import distort_normalized
from mvtools.io.atomic import atomic_output, output_folder_exists
from mvtools.io.cameras import write_cameras
from mvtools.io.captures import open_captures
from mvtools.io.guard import check_outputs
from mvtools.io.images import write_image
from mvtools.io.inputs import open_input_video
from mvtools.io.json_cameras import write_json_cameras

if TYPE_CHECKING:
    from mvtools.calibration import RigCalibration

LOG = logging.getLogger("mvtools")

# Tangential terms that move no pixel by more than this (about the RMS error of a good
# calibration) are not worth a warning when the MPEG file drops them.
_NEGLIGIBLE_PIXELS = 0.25

#: The report's file in the --report folder, beside the corner pictures.
_REPORT = "report.json"


def _parse_corners(ctx, param, value):
    try:
        columns, rows = (int(part) for part in value.lower().split("x"))
    except ValueError:
        raise click.BadParameter(
            f"{value!r} is not COLUMNSxROWS of inner corners (e.g. 9x6)"
        ) from None
    if columns < 2 or rows < 2:
        raise click.BadParameter(f"{value!r}: a board has at least 2x2 inner corners")
    return columns, rows


@click.command(name="calibrate", cls=ProgramCommand)
@click.argument("captures", nargs=-1, required=True, metavar="CAPTURES...")
@click.option(
    "--board",
    "inner_corners",
    required=True,
    callback=_parse_corners,
    metavar="COLUMNSxROWS",
    help="Inner corners of the checkerboard, e.g. 9x6.",
)
@click.option(
    "--square",
    "square_size",
    required=True,
    type=POSITIVE,
    help="Side of a square in metres: the scale of the camera centres.",
)
@click.option(
    "-o",
    "--output",
    required=True,
    type=click.Path(dir_okay=False),
    help="MPEG camera parameter file to write (K1, K2 in the distortion slots).",
)
@click.option(
    "--json",
    "json_output",
    type=click.Path(dir_okay=False),
    default=None,
    help="Also write the cameras as MPEG-I JSON (which has no lens distortion).",
)
@click.option(
    "--report",
    "report_dir",
    type=click.Path(file_okay=False),
    default=None,
    help="Folder for report.json (errors per camera and capture, baselines, axis "
    "angles, captures used) and one PNG per camera with the detected corners "
    "and their reprojection errors drawn.",
)
@click.option(
    "--names",
    default=None,
    metavar="NAME,NAME...",
    help="Camera names, one per CAPTURES (default: folder names, the fixed part "
    "of patterns, video names).",
)
@click.option(
    "--reference",
    default=None,
    metavar="NAME",
    help="Camera that defines the world frame (default: the first).",
)
@click.option(
    "--tangential/--no-tangential",
    default=True,
    show_default=True,
    help="Fit the tangential distortion P1, P2 besides K1, K2 (the chapter's lens "
    "model). The MPEG camera file stores only K1 and K2; --no-tangential fits "
    "a model the file holds exactly.",
)
@click.option(
    "--max-capture-rms",
    type=POSITIVE,
    default=1.0,
    show_default=True,
    help="Captures whose reprojection error (px RMS) exceeds this are dropped.",
)
@video_format_options
@program
def command(
    captures,
    inner_corners,
    square_size,
    output,
    json_output,
    report_dir,
    names,
    reference,
    tangential,
    max_capture_rms,
    size,
    pix_fmt,
):
    """Calibrate a camera array from checkerboard captures taken at the same instants.

    Each of CAPTURES is one camera's captures in capture order: a folder of images, a
    quoted image pattern ('left*.jpg') or a YUV/Y4M video whose frames are captures.
    The board may be out of some cameras' view at some instants. Per camera, the lens
    distortion and intrinsics are fitted first, then all cameras' poses jointly with the
    board poses (bundle adjustment); the world frame is the reference camera's and the
    scale is metric.
    """
    sources = [
        open_captures(spec, lambda path: open_input_video(path, size, pix_fmt)) for spec in captures
    ]
    # detection and the rig's fit load OpenCV and SciPy: for a run, not for --help
    from mvtools.calibration import Board, calibrate_rig

    try:
        camera_names = _camera_names(sources, names)
        _check_outputs(output, json_output, report_dir, camera_names)
        reference_index = _reference_index(camera_names, reference)
        board = Board(inner_corners=inner_corners, square_size=square_size)
        image_points, sizes, first_images = _detect(sources, camera_names, board)
        where = [[source.where(index) for index in range(len(source))] for source in sources]
    finally:
        for source in sources:
            source.__exit__(None, None, None)
    result = calibrate_rig(
        image_points,
        board,
        sizes,
        names=camera_names,
        reference=reference_index,
        tangential=tangential,
        max_capture_rms=max_capture_rms,
        capture_names=_instant_names([source.labels for source in sources]),
    )
    for (camera, capture), reason in sorted(result.rejected.items()):
        LOG.info("%s: %s: %s", camera_names[camera], where[camera][capture], reason)
    _write_cameras(result, output, json_output)
    if report_dir is not None:
        _write_report(Path(report_dir), result, where, image_points, first_images)
    click.echo(_summary(result))


def _check_outputs(
    output: str, json_output: str | None, report_dir: str | None, names: list[str]
) -> None:
    """Refuse the outputs before the captures are searched, not after the long
    calibration: a missing folder, an output that names a capture (every capture is
    noted as an input when its source opens), or one file for two outputs."""
    named = [(Path(output), "camera file (-o)")]
    if json_output is not None:
        named.append((Path(json_output), "JSON camera file (--json)"))
    for path, _ in named:
        output_folder_exists(path.parent)
    if report_dir is not None:
        folder = Path(report_dir)
        named.append((folder / _REPORT, "report (--report)"))
        named += [
            (_corner_picture(folder, name), f"corner picture of {name} (--report)")
            for name in names
        ]
    check_outputs(named)


def _camera_names(sources, names: str | None) -> list[str]:
    if names is not None:
        given = [name.strip() for name in names.split(",")]
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


def _instant_names(labels: list[list[str]]) -> list[str]:
    """Names of the capture instants in messages: the file names where every camera uses
    the same ones (cam0/capture03.png, cam1/capture03.png), else the 1-based order."""
    if all(camera_labels == labels[0] for camera_labels in labels):
        return list(labels[0])
    return [f"#{index + 1}" for index in range(len(labels[0]))]


def _reference_index(names: list[str], reference: str | None) -> int:
    if reference is None:
        return 0
    if reference not in names:
        raise UsageError(f"--reference {reference}: no such camera (cameras: {', '.join(names)})")
    return names.index(reference)


def _detect(sources, names, board):
    """The board's detection in every capture, image sizes, and each camera's first
    capture with a board (for the report)."""
    from mvtools.calibration import detect_board

    progress = Progress(sum(len(source) for source in sources), "captures searched")
    image_points, sizes, first_images = [], [], []
    for name, source in zip(names, sources):
        points, size, first = [], None, None
        for index in range(len(source)):
            image = source.read(index)
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
            progress.advance()
        found = sum(detection.corners is not None for detection in points)
        LOG.info("%s: board found in %d of %d captures", name, found, len(points))
        image_points.append(points)
        sizes.append(size)
        first_images.append(first)
    return image_points, sizes, first_images


def _write_cameras(result: RigCalibration, output: str, json_output: str | None) -> None:
    for camera in result.cameras:
        lost = _tangential_pixels(camera)
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
    stored = [_with_distortion(camera, camera.distortion[:2]) for camera in result.cameras]
    write_cameras(output, stored)
    if json_output is not None:
        if any(np.any(camera.distortion != 0) for camera in result.cameras):
            LOG.warning(
                "%s: MPEG-I JSON has no lens distortion: it describes the cameras "
                "after `mvtools rectify` has removed it",
                json_output,
            )
        write_json_cameras(
            json_output, [_with_distortion(camera, np.zeros(2)) for camera in result.cameras]
        )


def _with_distortion(camera, distortion):
    return replace(camera, distortion=np.array(distortion, dtype=np.float64))


def _tangential_pixels(camera) -> float:
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


def _write_report(folder: Path, result: RigCalibration, where, image_points, first_images):
    from mvtools.calibration.drawing import draw_corners

    folder.mkdir(parents=True, exist_ok=True)
    with atomic_output(folder / _REPORT, "w") as handle:
        json.dump(_report(result, where), handle, indent=2)
        handle.write("\n")
    for index, camera in enumerate(result.cameras):
        if first_images[index] is None:
            continue
        used = np.flatnonzero(result.used[index])
        detected = [image_points[index][capture].corners for capture in used]
        reprojected = [result.reprojected[index, capture] for capture in used]
        write_image(
            _corner_picture(folder, camera.name),
            draw_corners(first_images[index], detected, reprojected),
        )


def _corner_picture(folder: Path, name: str) -> Path:
    """The report's picture of camera ``name``'s detected corners."""
    return folder / f"{name}_corners.png"


def _summary(result: RigCalibration) -> str:
    lines = [
        f"{'camera':10s} {'used':>5s} {'fx':>9s} {'fy':>9s} {'cx':>8s} {'cy':>8s} "
        f"{'K1':>8s} {'K2':>8s} {'P1':>8s} {'P2':>8s} {'RMS px':>7s}"
    ]
    for index, camera in enumerate(result.cameras):
        k1, k2, p1, p2 = np.pad(camera.distortion, (0, 4))[:4]
        lines.append(
            f"{camera.name:10s} {int(result.used[index].sum()):5d} {camera.fx:9.2f} "
            f"{camera.fy:9.2f} {camera.cx:8.2f} {camera.cy:8.2f} {k1:8.4f} {k2:8.4f} "
            f"{p1:8.5f} {p2:8.5f} {result.rms[index]:7.3f}"
        )
    names = [camera.name for camera in result.cameras]
    for (a, b), baseline, angle in zip(
        itertools.pairwise(names), result.baselines(), result.axis_angles()
    ):
        lines.append(f"{a}-{b}: baseline {baseline:.5f} m, optical axes {angle:.3f} degrees apart")
    return "\n".join(lines)
