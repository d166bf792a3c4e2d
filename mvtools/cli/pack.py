"""``mvtools pack``: frame-compatible packing of views and depth maps, and unpacking."""

from __future__ import annotations

import contextlib
import logging
from pathlib import Path

import click

from mvtools.cli.options import (
    ProgramCommand,
    frame_range_options,
    parse_size,
    program,
    video_format_options,
)
from mvtools.cli.progress import Progress
from mvtools.errors import DataError, UsageError
from mvtools.io.atomic import output_folder_exists
from mvtools.io.guard import check_output
from mvtools.io.inputs import frame_range, open_input_video
from mvtools.io.sidecar import PackedVideo, read_sidecar, repeated_file, sidecar_path, write_sidecar
from mvtools.io.yuv import YuvFormat, open_video, open_writer
from mvtools.pack import LAYOUTS, pack_frame, plan_layout, unpack_frame

LOG = logging.getLogger("mvtools")

# The option that gives a packed stream of each kind.
_OPTIONS = {"texture": "--view", "depth": "--depth"}


@click.command(name="pack", cls=ProgramCommand)
@click.option(
    "--view",
    "views",
    multiple=True,
    nargs=2,
    metavar="NAME VIDEO",
    help="A texture view to pack (repeatable, in order).",
)
@click.option(
    "--depth",
    "depths",
    multiple=True,
    nargs=2,
    metavar="NAME VIDEO",
    help="A depth map to pack into an atlas (repeatable).",
)
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
        _unpack(
            Path(unpack_video),
            Path(sidecar) if sidecar else None,
            Path(output),
            size,
            start_frame,
            frame_count,
        )
        return
    if not views:
        raise UsageError("give the views to pack with --view NAME VIDEO")
    _pack(
        views,
        depths,
        layout,
        half,
        columns,
        block,
        frame_size,
        Path(output),
        Path(sidecar) if sidecar else sidecar_path(output),
        size,
        pix_fmt,
        start_frame,
        frame_count,
    )


def _pack(
    views,
    depths,
    layout_kind,
    half,
    columns,
    block,
    frame_size,
    output,
    sidecar,
    size,
    pix_fmt,
    start_frame,
    frame_count,
):
    entries = [(name, "texture", path) for name, path in views]
    entries += [(name, "depth", path) for name, path in depths]
    keys = [(name, kind) for name, kind, _ in entries]
    if len(set(keys)) != len(keys):
        raise UsageError("a view or depth map is given twice")
    paths = {(name, kind): path for name, kind, path in entries}
    files = {key: Path(path).name for key, path in paths.items()}
    repeated = repeated_file(files)
    if repeated is not None:
        first, second = (f"{_OPTIONS[kind]} {name}" for name, kind in repeated)
        raise UsageError(
            f"{second}: the same file name as {first}: unpacking restores the "
            "views under their file names in one folder; rename one",
            path=paths[repeated[1]],
        )
    with contextlib.ExitStack() as stack:
        videos = {
            key: stack.enter_context(open_input_video(path, size, pix_fmt))
            for key, path in paths.items()
        }
        fmt = _packed_format(videos)
        layout = plan_layout(
            [(name, videos[(name, "texture")].format.size) for name, _ in views],
            layout=layout_kind,
            half=half,
            columns=columns,
            block=block,
            frame_size=frame_size,
            depths=[(name, videos[(name, "depth")].format.size) for name, _ in depths],
        )
        packed_format = YuvFormat(layout.width, layout.height, chroma=fmt.chroma, bits=fmt.bits)
        frames = frame_range(list(videos.values()), start_frame, frame_count)
        with open_writer(output, packed_format, what="packed video (-o)") as writer:
            # the video is claimed now; the sidecar, written last, is checked before the
            # frames are packed, against the inputs and the video alike
            check_output(sidecar, "sidecar (--sidecar)")
            pack_frames(writer, videos, layout, frames)
            write_sidecar(
                sidecar,
                PackedVideo(
                    layout=layout,
                    pix_fmt=packed_format.pix_fmt,
                    frames=len(frames),
                    files=files,
                    pix_fmts={key: video.format.pix_fmt for key, video in videos.items()},
                ),
            )
    LOG.info(
        "%d views%s packed into %dx%d %s frames (%s)",
        len(views),
        f" and {len(depths)} depth maps" if depths else "",
        layout.width,
        layout.height,
        packed_format.pix_fmt,
        sidecar,
    )


def _packed_format(videos) -> YuvFormat:
    """The textures' format, which the depth maps must share in bit depth."""
    textures = {key: video for key, video in videos.items() if key[1] == "texture"}
    formats = {(video.format.chroma, video.format.bits) for video in textures.values()}
    if len(formats) > 1:
        listed = ", ".join(
            f"{name} {video.format.pix_fmt}" for (name, _), video in textures.items()
        )
        raise DataError(
            f"the views differ in pixel format ({listed}); convert them to one with mvtools convert"
        )
    chroma, bits = formats.pop()
    for (name, kind), video in videos.items():
        if kind == "depth" and video.format.bits != bits:
            raise DataError(
                f"depth map {name} has {video.format.bits}-bit samples, the views "
                f"{bits}: convert it with mvtools convert --depth --out-pix-fmt",
                path=video.path,
            )
        if kind == "depth" and video.format.chroma not in ("400", chroma):
            raise DataError(
                f"depth map {name} is {video.format.pix_fmt}; an atlas of "
                f"{chroma} views takes luma-only or {chroma} depth maps",
                path=video.path,
            )
    return next(iter(textures.values())).format


def _unpack(packed_path: Path, sidecar: Path | None, out: Path, size, start_frame, frame_count):
    sidecar = sidecar or sidecar_path(packed_path)
    if not sidecar.exists():
        raise UsageError(
            f"no sidecar {sidecar}: give the layout's JSON with --sidecar", path=packed_path
        )
    packed = read_sidecar(sidecar)
    layout = packed.layout
    fmt = YuvFormat.from_pix_fmt(layout.width, layout.height, packed.pix_fmt)
    if size is not None and tuple(size) != (layout.width, layout.height):
        raise UsageError(
            f"--size {size[0]}x{size[1]} disagrees with the sidecar's "
            f"{layout.width}x{layout.height}",
            path=sidecar,
        )
    with open_video(packed_path, fmt) as video:
        if len(video) != packed.frames:
            raise DataError(
                f"the packed video has {len(video)} frames, its sidecar {sidecar} "
                f"says {packed.frames}: they do not belong together",
                path=packed_path,
            )
        frames = frame_range([video], start_frame, frame_count)
        if out.exists():
            output_folder_exists(out)  # -o names a file, not the views' folder
        out.mkdir(parents=True, exist_ok=True)
        targets = {}
        for placement in layout.placements:
            key = (placement.name, placement.kind)
            targets[key] = (
                out / packed.files[key],
                YuvFormat.from_pix_fmt(
                    placement.source_width, placement.source_height, packed.pix_fmts[key]
                ),
            )
        write_unpacked(video, layout, targets, frames)


@contextlib.contextmanager
def write_packed(videos, layout, packed_format: YuvFormat, output: Path, frames):
    """Pack ``frames`` of the ``videos`` (by (name, kind)) into ``output``; the file
    appears when the block that follows ends without error."""
    with open_writer(output, packed_format) as writer:
        pack_frames(writer, videos, layout, frames)
        yield


def pack_frames(writer, videos, layout, frames) -> None:
    """Pack ``frames`` of the ``videos`` (by (name, kind)) into the open ``writer``."""
    progress = Progress(len(frames), "frames packed")
    for index in frames:
        writer.write(
            pack_frame(
                layout,
                {key: video.read(index) for key, video in videos.items()},
                chroma=writer.format.chroma,
                bits=writer.format.bits,
            )
        )
        progress.advance()


def write_unpacked(video, layout, targets, frames) -> None:
    """Every view of ``frames`` of a packed ``video`` to its ``targets[(name, kind)]``,
    a (path, format) pair; depth maps get chroma planes when their format has them."""
    chroma = video.format.chroma
    with contextlib.ExitStack() as stack:
        writers = {
            key: stack.enter_context(open_writer(path, fmt)) for key, (path, fmt) in targets.items()
        }
        progress = Progress(len(frames), "frames unpacked")
        for index in frames:
            restored = unpack_frame(
                layout, video.read(index), chroma=chroma, depth_planes=1 if chroma == "400" else 3
            )
            for key, writer in writers.items():
                writer.write(restored[key][: len(writer.format.plane_shapes)])
            progress.advance()
