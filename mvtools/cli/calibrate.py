"""``mvtools calibrate``: checkerboard captures to an MPEG camera parameter file."""

from __future__ import annotations

import itertools
from pathlib import Path
from typing import TYPE_CHECKING

import click
import numpy as np

from mvtools.cli.options import POSITIVE, ProgramCommand, program, video_format_options
from mvtools.cli.progress import Progress
from mvtools.io.atomic import output_folder_exists
from mvtools.io.captures import open_captures
from mvtools.io.guard import check_outputs
from mvtools.io.inputs import open_input_video
from mvtools.run.calibrate import (
    REPORT_FILE,
    CalibrateOptions,
    calibrate_rig,
    camera_names,
    corner_picture,
    write_rig_cameras,
    write_rig_report,
)

if TYPE_CHECKING:
    from mvtools.calibration import RigCalibration


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
    try:
        rig_names = camera_names(
            sources, None if names is None else [name.strip() for name in names.split(",")]
        )
        _check_outputs(output, json_output, report_dir, rig_names)
        # the board's detection loads OpenCV: for a run, not for --help
        from mvtools.calibration import Board

        rig = calibrate_rig(
            sources,
            Board(inner_corners=inner_corners, square_size=square_size),
            names=rig_names,
            options=CalibrateOptions(
                reference=reference, tangential=tangential, max_capture_rms=max_capture_rms
            ),
            progress=Progress(None, "captures searched"),
        )
    finally:
        for source in sources:
            source.__exit__(None, None, None)
    write_rig_cameras(rig, output, json_output)
    if report_dir is not None:
        write_rig_report(rig, report_dir)
    click.echo(_summary(rig.calibration))


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
        named.append((folder / REPORT_FILE, "report (--report)"))
        named += [
            (corner_picture(folder, name), f"corner picture of {name} (--report)") for name in names
        ]
    check_outputs(named)


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
