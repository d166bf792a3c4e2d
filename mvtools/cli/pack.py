"""``mvtools pack``: frame-compatible packing of views and depth maps, and unpacking."""

from __future__ import annotations

import logging

import click

from mvtools.cli.options import (
    ProgramCommand,
    depth_video_option,
    frame_range_options,
    parse_size,
    program,
    video_format_options,
    view_option,
)
from mvtools.cli.progress import Progress
from mvtools.errors import UsageError
from mvtools.pack import LAYOUTS
from mvtools.run.pack import PackOptions, pack_views, unpack_views

LOG = logging.getLogger("mvtools")


@click.command(name="pack", cls=ProgramCommand)
@view_option("The texture video of camera NAME to pack (repeatable, in order).")
@depth_video_option("The depth video of camera NAME, packed into an atlas (repeatable).")
@click.option(
    "--layout",
    type=click.Choice(LAYOUTS),
    default="grid",
    show_default=True,
    help="side-by-side or top-bottom (two views), a grid of any number of views, or "
    "an atlas: the textures' grid above the depth maps' grid.",
)
@click.option(
    "--half",
    is_flag=True,
    help="Halve the views along the packing direction, as stereo broadcasting does "
    "(side-by-side and top-bottom); the round trip is then not exact.",
)
@click.option(
    "--columns",
    type=click.IntRange(min=1),
    default=None,
    help="Views per row of a grid or atlas (default: nearest a square).",
)
@click.option(
    "--block",
    type=click.IntRange(min=2),
    default=8,
    show_default=True,
    help="The packed frame's size is a multiple of this (the encoder's block size).",
)
@click.option(
    "--frame-size",
    callback=parse_size,
    default=None,
    metavar="WxH",
    help="A packed frame size to keep to, e.g. 7680x4320 for 16 HD views.",
)
@click.option(
    "--unpack",
    "unpack_video",
    type=click.Path(dir_okay=False),
    default=None,
    help="Restore the views of this packed video (-o is then a folder).",
)
@click.option(
    "--sidecar",
    type=click.Path(dir_okay=False),
    default=None,
    help="The layout's JSON sidecar (default: the packed video's name with .json).",
)
@click.option(
    "-o",
    "--output",
    required=True,
    type=click.Path(),
    help="The packed video (its sidecar is written beside it), or with --unpack the "
    "folder for the views, named as when they were packed.",
)
@video_format_options
@frame_range_options
@program
def command(
    views,
    depths,
    layout,
    half,
    columns,
    block,
    frame_size,
    unpack_video,
    sidecar,
    output,
    size,
    pix_fmt,
    start_frame,
    frame_count,
):
    """Pack views (and depth maps) into frames of one larger video, as frame-compatible
    formats and texture-plus-depth atlases do for monoscopic encoders, or restore them.

    Every view sits at even offsets, so that 4:2:0 chroma stays aligned; without --half
    the views come back bit-exact. A JSON sidecar records the layout, the views' names,
    files, sizes, offsets and decimation.
    """
    if unpack_video is not None:
        if views or depths:
            raise UsageError(
                "--unpack restores the views of a packed video: give no --view or --depth"
            )
        unpack_views(
            unpack_video,
            output,
            sidecar=sidecar or None,
            size=size,
            start_frame=start_frame,
            frame_count=frame_count,
            progress=Progress(None, "frames unpacked"),
        )
        return
    if not views:
        raise UsageError("give the views to pack with --view NAME VIDEO")
    packed = pack_views(
        views,
        output,
        PackOptions(layout=layout, half=half, columns=columns, block=block, frame_size=frame_size),
        depths=depths,
        sidecar=sidecar or None,
        size=size,
        pix_fmt=pix_fmt,
        start_frame=start_frame,
        frame_count=frame_count,
        progress=Progress(None, "frames packed"),
    )
    LOG.info(
        "%d views%s packed into %dx%d %s frames (%s)",
        len(views),
        f" and {len(depths)} depth maps" if depths else "",
        packed.layout.width,
        packed.layout.height,
        packed.format.pix_fmt,
        packed.sidecar,
    )
