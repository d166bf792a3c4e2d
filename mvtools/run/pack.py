"""Frame-compatible packing of views and depth maps, and unpacking: the run functions of
``mvtools pack``.

:func:`pack_views` packs texture views (and depth maps, for an atlas) into the frames
of one larger video and writes the layout's JSON sidecar beside it
(:mod:`mvtools.io.sidecar`); :func:`unpack_views` restores the views of a packed video
from its sidecar. Both work one frame at a time (:func:`mvtools.run.stream.stream_frames`),
through :func:`pack_frames` and :func:`write_unpacked`, which ``mvtools encode`` also
uses for its packed mode. Messages name the options of ``mvtools pack``.
"""

from __future__ import annotations

import contextlib
import os
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

from mvtools.errors import DataError, UsageError
from mvtools.io.atomic import output_folder_exists
from mvtools.io.guard import check_output
from mvtools.io.inputs import frame_range, open_input_video
from mvtools.io.sidecar import PackedVideo, read_sidecar, repeated_file, sidecar_path, write_sidecar
from mvtools.io.yuv import VideoReader, VideoWriter, YuvFormat, open_video, open_writer
from mvtools.pack import Layout, pack_frame, plan_layout, unpack_frame
from mvtools.run.stream import ProgressCallback, stream_frames

#: A video to read: an opened reader, or its file (opened as ``--size``/``--pix-fmt`` say).
Source = VideoReader | str | os.PathLike

# The option of mvtools pack that gives a packed stream of each kind.
_OPTIONS = {"texture": "--view", "depth": "--depth"}


@dataclass(frozen=True)
class PackOptions:
    """How :func:`pack_views` lays the views out (checked by
    :func:`mvtools.pack.plan_layout`).

    Attributes
    ----------
    layout : {"side-by-side", "top-bottom", "grid", "atlas"}
        Two views next to each other or one above the other, a grid of any number of
        views, or an atlas: the textures' grid above the depth maps' grid.
    half : bool
        Halve the views along the packing direction (side-by-side and top-bottom), as
        stereo broadcasting does; the round trip is then not exact.
    columns : int, optional
        Views per row of a grid or atlas; default the count nearest a square.
    block : int
        The packed frame's size is a multiple of this (the encoder's block size).
    frame_size : (int, int), optional
        A packed frame size (width, height) to keep to, e.g. 7680x4320 for 16 HD views.
    """

    layout: str = "grid"
    half: bool = False
    columns: int | None = None
    block: int = 8
    frame_size: tuple[int, int] | None = None


@dataclass(frozen=True)
class PackedViews:
    """What :func:`pack_views` wrote.

    Attributes
    ----------
    layout : Layout
        Where each view sits in the packed frame.
    format : YuvFormat
        The packed frames' format: the layout's size, the textures' chroma and bits.
    frames : range
        The frames of the inputs that were packed.
    sidecar : Path
        The layout's JSON sidecar.
    """

    layout: Layout
    format: YuvFormat
    frames: range
    sidecar: Path


def pack_views(
    views: Mapping[str, Source],
    output: VideoWriter | str | os.PathLike,
    options: PackOptions = PackOptions(),
    *,
    depths: Mapping[str, Source] | None = None,
    sidecar: str | os.PathLike | None = None,
    size: tuple[int, int] | None = None,
    pix_fmt: str | None = None,
    start_frame: int = 0,
    frame_count: int | None = None,
    progress: ProgressCallback | None = None,
) -> PackedViews:
    """Pack the frames of ``views`` (and ``depths``) into one video, and write its sidecar.

    Every view sits at even offsets, so that 4:2:0 chroma stays aligned; without
    ``options.half`` the views come back bit-exact (:func:`unpack_views`). The sidecar
    records the layout and each view's name, file name and pixel format.

    Parameters
    ----------
    views : mapping of str to reader or path
        Each texture view's name and video, in packing order; they share chroma
        format and bit depth.
    output : VideoWriter or path
        The packed video: a path (written atomically, with the sidecar), or an open
        writer of the packed format (:attr:`PackedViews.format`).
    options : PackOptions
    depths : mapping of str to reader or path, optional
        Depth maps to pack into an atlas: luma-only or of the textures' chroma, of
        their bit depth.
    sidecar : path, optional
        The sidecar; default the packed video's name with ``.json``.
    size, pix_fmt : optional
        The videos' size and pixel format when their names or headers do not say.
    start_frame, frame_count : int
        The frames packed; ``frame_count`` None for all that every video has.
    progress : callable, optional
        ``progress(done, total)`` after each frame.

    Returns
    -------
    PackedViews

    Raises
    ------
    UsageError
        Two views of one file name (unpacking restores them into one folder), or an
        output that names an input.
    DataError
        Views of different pixel formats, or depth maps that do not fit them.
    ValueError
        A layout the views do not fit (:func:`mvtools.pack.plan_layout`), or a writer
        of another format.
    """
    depths = depths or {}
    sources = {(name, "texture"): source for name, source in views.items()}
    sources.update({(name, "depth"): source for name, source in depths.items()})
    paths = {key: _path(source) for key, source in sources.items()}
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
            key: source
            if isinstance(source, VideoReader)
            else stack.enter_context(open_input_video(source, size, pix_fmt))
            for key, source in sources.items()
        }
        fmt = _packed_format(videos)
        layout = plan_layout(
            [(name, videos[(name, "texture")].format.size) for name in views],
            layout=options.layout,
            half=options.half,
            columns=options.columns,
            block=options.block,
            frame_size=options.frame_size,
            depths=[(name, videos[(name, "depth")].format.size) for name in depths],
        )
        packed_format = YuvFormat(layout.width, layout.height, chroma=fmt.chroma, bits=fmt.bits)
        frames = frame_range(list(videos.values()), start_frame, frame_count)
        if isinstance(output, VideoWriter):
            if output.format != packed_format:
                raise ValueError(
                    f"the writer of {output.path} takes {output.format} frames, the "
                    f"packed frames are {packed_format}"
                )
            writer = output
        else:
            writer = stack.enter_context(
                open_writer(output, packed_format, what="packed video (-o)")
            )
        sidecar = Path(sidecar) if sidecar is not None else sidecar_path(writer.path)
        # the video is claimed now; the sidecar, written last, is checked before the
        # frames are packed, against the inputs and the video alike
        check_output(sidecar, "sidecar (--sidecar)")
        pack_frames(writer, videos, layout, frames, progress=progress)
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
    return PackedViews(layout, packed_format, frames, sidecar)


def _path(source: Source) -> str | os.PathLike:
    """The file of a video to read, as given."""
    return source.path if isinstance(source, VideoReader) else source


def _packed_format(videos: Mapping[tuple[str, str], VideoReader]) -> YuvFormat:
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


def unpack_views(
    packed: VideoReader | str | os.PathLike,
    out: str | os.PathLike,
    *,
    sidecar: str | os.PathLike | None = None,
    size: tuple[int, int] | None = None,
    start_frame: int = 0,
    frame_count: int | None = None,
    progress: ProgressCallback | None = None,
) -> dict[tuple[str, str], Path]:
    """Restore the views of a packed video into a folder, under the names they had.

    Parameters
    ----------
    packed : VideoReader or path
        The packed video (a reader must have the format its sidecar gives).
    out : path
        The folder for the views; made if missing.
    sidecar : path, optional
        The layout's JSON sidecar; default the packed video's name with ``.json``.
    size : (int, int), optional
        The packed frames' size, checked against the sidecar's.
    start_frame, frame_count : int
        The frames restored; ``frame_count`` None for all.
    progress : callable, optional
        ``progress(done, total)`` after each frame.

    Returns
    -------
    dict of (name, kind) to Path
        Each view's restored video, by name and kind (``"texture"``, ``"depth"``).

    Raises
    ------
    UsageError
        No sidecar, a ``size`` it disagrees with, or ``out`` not a folder.
    ConfigError
        A damaged sidecar (:func:`mvtools.io.sidecar.read_sidecar`).
    DataError
        A packed video that does not belong to the sidecar.
    """
    packed_path = Path(_path(packed))
    sidecar = Path(sidecar) if sidecar is not None else sidecar_path(packed_path)
    if not sidecar.exists():
        raise UsageError(
            f"no sidecar {sidecar}: give the layout's JSON with --sidecar", path=packed_path
        )
    document = read_sidecar(sidecar)
    layout = document.layout
    fmt = YuvFormat.from_pix_fmt(layout.width, layout.height, document.pix_fmt)
    if size is not None and tuple(size) != (layout.width, layout.height):
        raise UsageError(
            f"--size {size[0]}x{size[1]} disagrees with the sidecar's "
            f"{layout.width}x{layout.height}",
            path=sidecar,
        )
    with contextlib.ExitStack() as stack:
        if isinstance(packed, VideoReader):
            if packed.format != fmt:
                raise DataError(
                    f"the packed video is {packed.format}, its sidecar {sidecar} says {fmt}",
                    path=packed_path,
                )
            video = packed
        else:
            video = stack.enter_context(open_video(packed_path, fmt))
        if len(video) != document.frames:
            raise DataError(
                f"the packed video has {len(video)} frames, its sidecar {sidecar} "
                f"says {document.frames}: they do not belong together",
                path=packed_path,
            )
        frames = frame_range([video], start_frame, frame_count)
        out = Path(out)
        if out.exists():
            output_folder_exists(out)  # -o names a file, not the views' folder
        out.mkdir(parents=True, exist_ok=True)
        targets = {}
        for placement in layout.placements:
            key = (placement.name, placement.kind)
            targets[key] = (
                out / document.files[key],
                YuvFormat.from_pix_fmt(
                    placement.source_width, placement.source_height, document.pix_fmts[key]
                ),
            )
        write_unpacked(video, layout, targets, frames, progress=progress)
    return {key: path for key, (path, _) in targets.items()}


def pack_frames(
    writer: VideoWriter,
    videos: Mapping[tuple[str, str], VideoReader],
    layout: Layout,
    frames: range,
    *,
    progress: ProgressCallback | None = None,
) -> None:
    """Pack ``frames`` of the ``videos`` (by (name, kind)) into the open ``writer``, whose
    format gives the packed frames' chroma and bits (:func:`mvtools.pack.pack_frame`)."""
    keys = list(videos)

    def pack(index, *planes):
        return [
            pack_frame(
                layout,
                dict(zip(keys, planes)),
                chroma=writer.format.chroma,
                bits=writer.format.bits,
            )
        ]

    stream_frames(frames, pack, readers=list(videos.values()), writers=[writer], progress=progress)


def write_unpacked(
    video: VideoReader,
    layout: Layout,
    targets: Mapping[tuple[str, str], tuple[Path, YuvFormat]],
    frames: range,
    *,
    progress: ProgressCallback | None = None,
) -> None:
    """Every view of ``frames`` of a packed ``video`` to its ``targets[(name, kind)]``,
    a (path, format) pair, each written atomically; depth maps get mid-grey chroma
    planes when their format has them."""
    chroma = video.format.chroma
    with contextlib.ExitStack() as stack:
        writers = {
            key: stack.enter_context(open_writer(path, fmt)) for key, (path, fmt) in targets.items()
        }

        def unpack(index, planes):
            restored = unpack_frame(
                layout, planes, chroma=chroma, depth_planes=1 if chroma == "400" else 3
            )
            return [
                restored[key][: len(writer.format.plane_shapes)] for key, writer in writers.items()
            ]

        stream_frames(
            frames, unpack, readers=[video], writers=list(writers.values()), progress=progress
        )
