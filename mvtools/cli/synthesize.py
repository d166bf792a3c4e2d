"""``mvtools synthesize``: virtual views from texture and depth, reading VSRS configurations.

The configuration file is read unmodified (:func:`mvtools.io.loaded_config.load_config`);
``Key=Value`` items and the options derived from the same parameter table override it.
Frames are streamed: one frame of every input is in memory at a time, and every
output is written atomically (nothing appears at an output path unless the whole run
succeeds).
"""

from __future__ import annotations

import logging
from pathlib import Path

import click

from mvtools.cli.options import (
    ProgramCommand,
    data_dir_option,
    depth_range_option,
    depth_video_option,
    overrides_argument,
    param_options,
    program,
    transposed_rotation_option,
    view_option,
)
from mvtools.cli.progress import Progress
from mvtools.errors import UsageError
from mvtools.io.config import COMMAND_LINE, ConfigEntry, resolve_output_path
from mvtools.io.loaded_config import command_line_input, load_config
from mvtools.io.yuv import is_standard_stream
from mvtools.params import VsrsParams
from mvtools.run.synthesize import (
    ReferenceFiles,
    depth_coding,
    synthesize_loaded,
)
from mvtools.synthesis.views import DEFAULT_HOLE_FILLING, HOLE_FILLING

LOG = logging.getLogger(__name__)


#: Command-line names of VSRS keys beyond ``--`` + the key in snake case.
_SECONDARY_NAMES = {
    "total_number_of_frames": ("--frames",),
    "output_virtual_view_image_name": ("-o", "--output"),
}


@click.command(name="synthesize", cls=ProgramCommand)
@click.argument("config", type=click.Path(dir_okay=False))
@overrides_argument
@data_dir_option
@view_option(
    "A further reference view (repeatable): the texture video of camera NAME of the "
    "camera file, with its depth video by --depth NAME. With the left and right views "
    "of the configuration, or instead of them."
)
@depth_video_option("The depth video of the further view --view NAME (repeatable).")
@depth_range_option(
    of="the further views' depth maps",
    default="a camera's Depth_range in an MPEG-I JSON camera file, else the left view's",
)
@click.option(
    "--hole-filling",
    type=click.Choice(HOLE_FILLING),
    default=None,
    help=f"How the holes no view saw are filled: background is VSRS's row rule, "
    f"inpaint plain image inpainting (default: {DEFAULT_HOLE_FILLING}, or "
    "inpaint with IvsrsInpaint 0).",
)
@click.option(
    "--output-depth",
    type=click.Path(dir_okay=False),
    default=None,
    help="Also write the virtual view's depth map, in the format of the left depth map "
    "(8-bit 4:2:0 with chroma 128, or as its name says).",
)
@depth_range_option("--output-depth-range", of="--output-depth", default="the left view's")
@click.option(
    "--output-holes",
    type=click.Path(dir_okay=False),
    default=None,
    help="Also write the hole mask: 8-bit grey (4:0:0) video, 255 where no view saw the "
    "scene (before hole filling), 0 elsewhere.",
)
@transposed_rotation_option
@param_options(VsrsParams, _SECONDARY_NAMES)
@program
def command(
    config,
    overrides,
    data_dirs,
    views,
    depths,
    depth_range,
    hole_filling,
    output_depth,
    output_depth_range,
    output_holes,
    transposed_rotation,
    **options,
):
    """Synthesize the virtual view that CONFIG describes.

    CONFIG is a VSRS configuration file, read unmodified: the camera parameter file
    (MPEG text, or MPEG-I JSON when its name ends in .json), the left and right texture
    and depth videos, the virtual camera. Key=Value items override the file as on the
    VSRS command line, and the options below override both.

    \b
    Both VSRS modes: general (3D warping, any camera layout) and 1D (rectified
    parallel cameras). One reference (left = right) extrapolates; --view adds
    reference views beyond the two of VSRS (general mode).
    Texture videos: YUV 4:2:0, 8-bit as VSRS, or 10/16-bit when the name says so
    (name_1920x1080_yuv420p10le.yuv); the output has the textures' format.
    Depth videos: 8-bit 4:2:0 (chroma ignored), or 16-bit luma only by name
    (name_1920x1080_gray16le.yuv), each with its own Znear/Zfar.
    Frames: StartFrame, TotalNumberOfFrames (the shortest input limits them,
    with a warning); progress on stderr.

    Exits with 2 for a bad configuration or option, 1 for damaged or inconsistent
    data, leaving no output file.
    """
    loaded = load_config(
        VsrsParams,
        config,
        overrides=overrides,
        options=options,
        data_dirs=data_dirs,
        transposed_rotation=transposed_rotation,
    )
    extras = _further_views(loaded, views, depths, depth_range, data_dirs)
    outputs = synthesize_loaded(
        loaded,
        config_path=Path(config),
        extra_references=extras,
        hole_filling=hole_filling,
        output_depth=_command_line_output("--output-depth", output_depth),
        output_depth_range=tuple(output_depth_range) if output_depth_range else None,
        output_holes=_command_line_output("--output-holes", output_holes),
        progress=Progress(None, "frames synthesized"),
        warm_up_progress=Progress(None, "frames taken in"),
    )
    written = (
        "standard output" if is_standard_stream(path) else str(path) for path in outputs.values()
    )
    LOG.info("wrote %s", ", ".join(written))


def _further_views(loaded, views, depths, depth_range, data_dirs) -> list[ReferenceFiles]:
    """The reference views of --view and --depth, each camera with both."""
    for name in depths.keys() - views.keys():
        raise UsageError(f"--depth {name} has no --view {name}")
    extras = []
    for name, texture in views.items():
        label = f"--view {name}"
        camera = loaded.command_line_camera(name, label)
        if name not in depths:
            raise UsageError(f"{label}: give its depth video with --depth {name}")
        znear_zfar = depth_range or camera.depth_range or loaded.params.left_depth_range
        if znear_zfar is None:
            raise UsageError(f"{label}: give the Znear and Zfar of its depth with --depth-range")
        range_label = "--depth-range" if depth_range else label
        depth_coding(znear_zfar, 8, range_label, depth_type=loaded.params.depth_type)
        paths = [
            command_line_input(label, texture, data_dirs),
            command_line_input(f"--depth {name}", depths[name], data_dirs),
        ]
        extras.append(ReferenceFiles(camera, *paths, tuple(znear_zfar), label, f"--depth {name}"))
    return extras


def _command_line_output(option: str, value: str | None) -> Path | None:
    if value is None:
        return None
    return resolve_output_path(ConfigEntry(option, value, COMMAND_LINE, None))
