"""``mvtools pointcloud``: texture-plus-depth views to a PLY point cloud, and back.

``to-ply`` backprojects every pixel with a depth of the chosen views into one coloured
cloud, points that several cameras see kept once; ``render`` draws a PLY cloud into a
camera of a camera file. docs/ply.md describes the files.
"""

from __future__ import annotations

import contextlib
import logging
from pathlib import Path

import click

from mvtools import __version__
from mvtools.cli.options import (
    FiniteFloat,
    ProgramCommand,
    _OneLineUsageError,
    depth_range_option,
    depth_video_option,
    parse_size,
    program,
    view_option,
)
from mvtools.errors import UsageError
from mvtools.io.camera_files import read_camera_file
from mvtools.io.guard import check_output, check_outputs, note_input
from mvtools.io.loaded_config import video_format_for
from mvtools.io.yuv import YuvFormat, format_from_name, open_video, open_writer
from mvtools.run.synthesize import depth_coding
from mvtools.synthesis.views import HOLE_FILLING

LOG = logging.getLogger(__name__)


class _Group(click.Group):
    """A group whose command-line mistakes are one ``PROGRAM: error:`` line (exit 2)."""

    def parse_args(self, ctx: click.Context, args: list[str]) -> list[str]:
        try:
            return super().parse_args(ctx, args)
        except click.UsageError as error:
            raise _OneLineUsageError(ctx.command_path, error.format_message()) from None

    def resolve_command(self, ctx: click.Context, args: list[str]):
        try:
            return super().resolve_command(ctx, args)
        except click.UsageError as error:
            raise _OneLineUsageError(ctx.command_path, error.format_message()) from None


@click.group(
    name="pointcloud", cls=_Group, context_settings={"help_option_names": ["-h", "--help"]}
)
@click.version_option(__version__, prog_name="mvtools")
def command():
    """Views with depth as a coloured point cloud (PLY), and point clouds as views.

    \b
    to-ply   one frame of texture and depth videos to a PLY file
    render   a PLY file drawn into a camera: texture (and depth) video
    """


def _camera(cameras, name: str, option: str, camera_file: str):
    if name not in cameras:
        raise UsageError(
            f"camera {name!r} is not in the camera file (it has {', '.join(cameras)})",
            path=camera_file,
            key=option,
        )
    return cameras[name]


def _size_of(camera, size, output: str) -> tuple[int, int]:
    """--size, else the camera file's, else the output's name (name_1024x768_yuv420p.yuv)."""
    if size is not None:
        return tuple(size)
    if camera.size is not None:
        return tuple(camera.size)
    named = format_from_name(output)
    if named is not None:
        return named.size
    raise UsageError(f"the picture size of camera {camera.name!r} is unknown: give --size WxH")


@command.command(name="to-ply", cls=ProgramCommand)
@click.argument("camera_file", metavar="CAMERAS", type=click.Path(dir_okay=False))
@view_option("The texture video of camera NAME of CAMERAS (repeatable).", required=True)
@depth_video_option("The depth video of camera NAME (repeatable; one for each --view).")
@depth_range_option(
    of="the depth maps", default="a camera's Depth_range in an MPEG-I JSON camera file"
)
@click.option(
    "--size",
    callback=parse_size,
    default=None,
    metavar="WxH",
    help="Picture size of videos whose names do not carry it (default: the camera file's).",
)
@click.option(
    "--frame",
    type=click.IntRange(min=0),
    default=0,
    show_default=True,
    help="The frame of the videos to take.",
)
@click.option(
    "--camera",
    "chosen",
    multiple=True,
    metavar="NAME",
    help="Use the view of camera NAME only (repeatable, in this order; default: every --view).",
)
@click.option(
    "--merge-tolerance",
    type=FiniteFloat(min=0),
    default=None,
    help="Relative depth difference under which a point that an earlier camera holds is "
    "dropped (default 0.01, 1 %).",
)
@click.option("--double", is_flag=True, help="Store positions as float64 (default float32).")
@click.option(
    "-o", "--output", required=True, type=click.Path(dir_okay=False), help="The PLY file to write."
)
@program
def to_ply(
    camera_file, views, depths, depth_range, size, frame, chosen, merge_tolerance, double, output
):
    """Backproject one frame of texture and depth videos into a PLY point cloud.

    CAMERAS is an MPEG camera parameter file or an MPEG-I JSON file (.json). Each
    --view NAME VIDEO needs its --depth NAME VIDEO. Depth maps are 8-bit 4:2:0
    (chroma ignored) or 16-bit grey by name (name_1024x768_gray16le.yuv), depth
    along each camera's axis (DepthType 0).

    Exits with 2 for a bad option or camera file, 1 for damaged data, leaving no
    output file.
    """
    from mvtools.geometry.depth import facing_camera
    from mvtools.run.pointcloud import ReferenceVideo, views_to_ply

    note_input(camera_file)
    cameras = read_camera_file(camera_file)
    for name in depths.keys() - views.keys():
        raise UsageError(f"--depth {name} has no --view {name}")
    names = list(chosen) if chosen else list(views)
    for name in names:
        if name not in views:
            raise UsageError(f"--camera {name}: no --view {name} given")
    if len(set(names)) != len(names):
        raise UsageError("--camera names a camera twice")
    plan = []
    for name in names:
        camera = _camera(cameras, name, f"--view {name}", camera_file)
        if name not in depths:
            raise UsageError(f"--view {name}: give its depth video with --depth {name}")
        znear_zfar = tuple(depth_range) if depth_range else camera.depth_range
        if znear_zfar is None:
            raise UsageError(
                f"--view {name}: give the Znear and Zfar of its depth with --depth-range"
            )
        plan.append((camera, tuple(znear_zfar)))
    with contextlib.ExitStack() as stack:
        videos = []
        for camera, znear_zfar in plan:
            frame_size = size or camera.size
            readers = []
            for label, path in (
                (f"--view {camera.name}", views[camera.name]),
                (f"--depth {camera.name}", depths[camera.name]),
            ):
                fmt = (
                    video_format_for(Path(path), tuple(frame_size), key=label)
                    if frame_size
                    else None
                )
                readers.append(stack.enter_context(open_video(path, fmt)))
            range_label = "--depth-range" if depth_range else f"--view {camera.name}"
            coding = depth_coding(znear_zfar, readers[1].format.bits, range_label, depth_type=0)
            videos.append(ReferenceVideo(facing_camera(camera, znear_zfar), *readers, coding))
        check_output(Path(output))
        views_to_ply(
            videos,
            output,
            frame=frame,
            merge_tolerance=merge_tolerance,
            precision="double" if double else "single",
        )
    LOG.info("wrote %s", output)


@command.command(name="render", cls=ProgramCommand)
@click.argument("ply", type=click.Path(dir_okay=False))
@click.argument("camera_file", metavar="CAMERAS", type=click.Path(dir_okay=False))
@click.option(
    "--camera",
    "camera_name",
    required=True,
    metavar="NAME",
    help="The camera of CAMERAS to render into.",
)
@click.option(
    "--size",
    callback=parse_size,
    default=None,
    metavar="WxH",
    help="Picture size (default: the camera file's, else the -o name's).",
)
@depth_range_option(
    of="--depth-output (and which side of the camera the scene is)",
    default="the camera's Depth_range in an MPEG-I JSON camera file",
)
@click.option(
    "--hole-filling",
    type=click.Choice(HOLE_FILLING),
    default="background",
    show_default=True,
    help="How the pixels no point reached are filled.",
)
@click.option(
    "--splatting",
    default="bilinear",
    show_default=True,
    metavar="KIND",
    help="bilinear: each point weighs on the 2x2 pixels around it; point: on the "
    "nearest pixel; spacing: on a square as large as its spacing.",
)
@click.option(
    "-o",
    "--output",
    required=True,
    type=click.Path(dir_okay=False),
    help="The texture video to write (8-bit YUV 4:2:0, one frame).",
)
@click.option(
    "--depth-output",
    default=None,
    type=click.Path(dir_okay=False),
    help="Also write the depth map: 8-bit 4:2:0 with chroma 128, or as its name "
    "says (name_1024x768_gray16le.yuv).",
)
@program
def render(
    ply, camera_file, camera_name, size, depth_range, hole_filling, splatting, output, depth_output
):
    """Render the point cloud PLY into camera --camera of CAMERAS.

    Exits with 2 for a bad option, camera file or PLY header, 1 for damaged data,
    leaving no output file.
    """
    from mvtools.geometry.depth import facing_camera
    from mvtools.run.pointcloud import ply_to_views

    note_input(camera_file)
    cameras = read_camera_file(camera_file)
    camera = _camera(cameras, camera_name, "--camera", camera_file)
    width, height = _size_of(camera, size, output)
    znear_zfar = tuple(depth_range) if depth_range else camera.depth_range
    coding = None
    if znear_zfar is not None:
        depth_coding(znear_zfar, 8, "--depth-range", depth_type=0)
        camera = facing_camera(camera, znear_zfar)
    if not Path(ply).is_file():
        raise UsageError("no such file", path=ply)
    depth_format = None
    if depth_output is not None:
        if znear_zfar is None:
            raise UsageError("--depth-output needs the depth range: give --depth-range")
        depth_format = format_from_name(depth_output) or YuvFormat(width, height)
        if depth_format.size != (width, height):
            raise UsageError(
                f"the name says {depth_format.width}x{depth_format.height}, the picture is "
                f"{width}x{height}",
                path=depth_output,
            )
        coding = depth_coding(znear_zfar, depth_format.bits, "--depth-range", depth_type=0)
    note_input(ply)
    check_outputs(
        [(output, "texture output (-o)")]
        + ([(depth_output, "depth output (--depth-output)")] if depth_output else [])
    )
    with contextlib.ExitStack() as stack:
        texture = stack.enter_context(open_writer(output, YuvFormat(width, height)))
        depth = None
        if depth_format is not None:
            depth = stack.enter_context(open_writer(depth_output, depth_format))
        ply_to_views(
            ply,
            camera,
            size=(width, height),
            texture=texture,
            depth=depth,
            depth_coding=coding,
            hole_filling=hole_filling,
            splatting=splatting,
        )
    LOG.info("wrote %s", ", ".join(str(p) for p in (output, depth_output) if p))
