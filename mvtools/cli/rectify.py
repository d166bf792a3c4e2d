"""``mvtools rectify``: lens distortion removal and rectification of a camera array."""

from __future__ import annotations

from typing import TYPE_CHECKING

import click

from mvtools.cli.options import (
    FiniteFloat,
    ProgramCommand,
    depth_range_option,
    depth_video_option,
    frame_range_options,
    parse_size,
    program,
    transposed_rotation_option,
    video_format_options,
    view_option,
)
from mvtools.cli.progress import Progress
from mvtools.errors import UsageError, at_fault
from mvtools.geometry.depth import check_depth_range
from mvtools.io.camera_files import read_camera_file
from mvtools.io.cameras import get_camera
from mvtools.run.rectify import RectifyOptions, rectify_videos

if TYPE_CHECKING:
    from mvtools.rectification import Rectification


@click.command(name="rectify", cls=ProgramCommand)
@click.argument("camera_file", type=click.Path(dir_okay=False))
@click.option(
    "--camera",
    "camera_names",
    multiple=True,
    metavar="NAME",
    help="A camera of the array, in order along it (repeatable; default: the "
    "cameras of --view and --depth, in the order given).",
)
@view_option("A texture video of camera NAME to rectify (repeatable).")
@depth_video_option(
    "A depth map video of camera NAME (MPEG: 255 or 65535 = Znear), sampled at the "
    "nearest pixel and re-measured along the rectified camera's axis (repeatable)."
)
@depth_range_option(
    default="the cameras' Depth_range of an MPEG-I JSON camera file; the output keeps them"
)
@click.option(
    "--undistort",
    "undistort_only",
    is_flag=True,
    help="Only remove the lens distortion: every camera keeps its orientation.",
)
@click.option(
    "--keep-world",
    is_flag=True,
    help="Describe the rectified cameras in the input's world frame. By default the "
    "world frame turns with them, so that their rotations are the identity and "
    "the centres lie along x, as VSRS's and DERS's 1D modes read camera files.",
)
@click.option(
    "--alpha",
    type=FiniteFloat(0.0, 1.0),
    default=0.0,
    show_default=True,
    help="Kept field of view: 0 crops so that every output pixel is valid, 1 keeps "
    "every source pixel (with empty borders), values between interpolate.",
)
@click.option(
    "--virtual",
    "virtual_count",
    type=click.IntRange(min=0),
    default=0,
    show_default=True,
    help="Virtual cameras to add to the camera file between each pair of neighbours, "
    "evenly spaced (named LEFT_RIGHT_k), for the views synthesized in between.",
)
@click.option(
    "-o",
    "--out-dir",
    required=True,
    type=click.Path(file_okay=False),
    help="Folder for the rectified videos (named as their inputs) and the cameras.",
)
@click.option(
    "--cameras-out",
    default=None,
    type=click.Path(dir_okay=False),
    help="Camera file of the rectified cameras (default OUT_DIR/cameras.txt; a .json "
    "name writes MPEG-I JSON).",
)
@click.option(
    "--camera-size",
    callback=parse_size,
    default=None,
    metavar="WxH",
    help="Picture size of cameras that have no video here and no size in the camera "
    "file (MPEG camera parameter files carry none).",
)
@video_format_options
@frame_range_options
@transposed_rotation_option
@program
def command(
    camera_file,
    camera_names,
    views,
    depths,
    depth_range,
    undistort_only,
    keep_world,
    virtual_count,
    alpha,
    out_dir,
    cameras_out,
    camera_size,
    size,
    pix_fmt,
    start_frame,
    frame_count,
    transposed_rotation,
):
    """Rectify the cameras of CAMERA_FILE (a pair or a linear array) and their videos.

    Rectified cameras share one orientation (x along the line of the centres) and one
    intrinsic matrix, and have no lens distortion, so that epipolar lines are rows and
    the 1D modes of synthesize and estimate-depth apply. The camera centres stay where
    they are. Each camera's look-up table is computed once and applied to every frame:
    textures are sampled bilinearly (chroma at its own resolution), depth maps at the
    nearest pixel.
    """
    if depth_range is not None:
        with at_fault(UsageError, key="--depth-range"):
            check_depth_range(*depth_range)
    cameras = read_camera_file(camera_file, transposed_rotation=transposed_rotation)
    names = list(camera_names) or list(dict.fromkeys([*views, *depths]))
    if not names:
        raise UsageError("name the cameras to rectify with --camera, --view or --depth")
    options = RectifyOptions(
        undistort_only=undistort_only,
        alpha=alpha,
        virtual_count=virtual_count,
        keep_world=keep_world,
        depth_range=tuple(depth_range) if depth_range is not None else None,
        camera_size=camera_size,
    )
    result = rectify_videos(
        [get_camera(cameras, name, path=camera_file) for name in names],
        out_dir=out_dir,
        textures=views,
        depths=depths,
        options=options,
        cameras_out=cameras_out,
        size=size,
        pix_fmt=pix_fmt,
        start_frame=start_frame,
        frame_count=frame_count,
        camera_file=camera_file,
        video_progress=lambda path: Progress(None, f"{path.name} frames rectified"),
    )
    click.echo(_summary(result.rectification))


def _summary(result: Rectification) -> str:
    lines = [
        f"{'camera':10s} {'fx':>9s} {'cx':>8s} {'cy':>8s} {'valid %':>8s} {'kept %':>7s} "
        f"{'off line':>9s}  homography (undistorted source -> output)"
    ]
    for camera, valid, kept, offset, warp in zip(
        result.cameras,
        result.valid_fraction,
        result.kept_fraction,
        result.centre_offsets,
        result.homographies,
    ):
        rows = " / ".join(" ".join(f"{value:.6g}" for value in row) for row in warp)
        lines.append(
            f"{camera.name:10s} {camera.fx:9.2f} {camera.cx:8.2f} {camera.cy:8.2f} "
            f"{100 * valid:8.2f} {100 * kept:7.2f} {offset:9.3g}  {rows}"
        )
    return "\n".join(lines)
