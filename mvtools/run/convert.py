"""Conversions between videos, images and depth values: the run functions of ``mvtools
convert``.

:func:`convert_video` writes a video in another pixel format or container,
:func:`video_to_images` one picture per frame, :func:`depth_video_to_pfm` and
:func:`pfm_to_depth_video` turn a depth video into PFM images of z or disparity and back
(:class:`DepthValues`), and :func:`images_to_video` makes a video of pictures. Each works
one frame at a time (:func:`mvtools.run.stream.stream_frames`).
"""

from __future__ import annotations

import os
import re
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from mvtools.color.levels import convert_planes, depth_preview, requantize
from mvtools.color.space import rgb_to_yuv, yuv_to_rgb
from mvtools.errors import DataError, UsageError, at_fault
from mvtools.geometry.depth import (
    depth_sign,
    depth_to_z,
    disparity_to_z,
    z_to_depth,
    z_to_disparity,
)
from mvtools.io.images import read_image, write_image
from mvtools.io.inputs import frame_range, open_input_video
from mvtools.io.yuv import YuvFormat, frame_from_luma, open_writer
from mvtools.run.stream import ProgressCallback, stream_frames

#: What PFM images of depth hold.
DEPTH_QUANTITIES = ("z", "disparity")


@dataclass(frozen=True)
class DepthValues:
    """What the PFM images of a depth video hold, and how the video codes depth.

    Attributes
    ----------
    quantity : {"z", "disparity"}
        z signed as the depth video codes it, or disparity (positive, in pixels).
    depth_range : (float, float)
        Znear and Zfar of the depth video (checked, as
        :func:`mvtools.geometry.depth.check_depth_range` does).
    focal, baseline : float, optional
        Focal length in pixels and baseline in the units of z; needed for disparity
        (checked, as :func:`mvtools.geometry.depth.check_stereo` does).
    """

    quantity: str
    depth_range: tuple[float, float]
    focal: float | None = None
    baseline: float | None = None

    def __post_init__(self):
        if self.quantity not in DEPTH_QUANTITIES:
            raise ValueError(f"quantity must be one of {', '.join(DEPTH_QUANTITIES)}")
        if self.quantity == "disparity" and (self.focal is None or self.baseline is None):
            raise ValueError("disparities need the focal length and the baseline")


def convert_video(
    source: str | os.PathLike,
    output: str | os.PathLike,
    *,
    size: tuple[int, int] | None = None,
    pix_fmt: str | None = None,
    out_pix_fmt: str | None = None,
    depth: bool = False,
    start_frame: int = 0,
    frame_count: int | None = None,
    progress: ProgressCallback | None = None,
) -> YuvFormat:
    """Write the frames of a video in another pixel format, or raw <-> Y4M.

    Texture bit depths change as ffmpeg changes them (up shifted, down with its ordered
    dither); chroma is resampled only for another layout
    (:func:`mvtools.color.levels.convert_planes`).

    Parameters
    ----------
    source, output : path
        A ``.yuv`` or ``.y4m`` video each.
    size, pix_fmt : optional
        The source's size and pixel format when its name or header does not say.
    out_pix_fmt : str, optional
        The output's pixel format; default the source's.
    depth : bool
        The video is a depth map: only luma counts, bit-depth changes keep v / vmax and
        the output's chroma is mid-grey.
    start_frame, frame_count : int
        The frames converted; ``frame_count`` None for all.
    progress : callable, optional
        ``progress(done, total)`` after each frame.

    Returns
    -------
    YuvFormat
        The output's format.
    """
    with open_input_video(source, size, pix_fmt) as video:
        source_format = video.format
        target = (
            YuvFormat.from_pix_fmt(source_format.width, source_format.height, out_pix_fmt)
            if out_pix_fmt
            else source_format
        )
        frames = frame_range([video], start_frame, frame_count)

        def convert(index, planes):
            with _samples_of(source, index):
                return [
                    convert_planes(
                        planes,
                        bits=source_format.bits,
                        to_chroma=target.chroma,
                        to_bits=target.bits,
                        depth=depth,
                    )
                ]

        with open_writer(output, target, frame_rate=video.frame_rate) as writer:
            stream_frames(frames, convert, readers=[video], writers=[writer], progress=progress)
    return target


def video_to_images(
    source: str | os.PathLike,
    output: str | os.PathLike,
    *,
    size: tuple[int, int] | None = None,
    pix_fmt: str | None = None,
    depth: bool = False,
    preview: bool = False,
    start_frame: int = 0,
    frame_count: int | None = None,
    progress: ProgressCallback | None = None,
) -> list[Path]:
    """Write one picture per frame of a video: RGB, or the grey depth map with ``depth``.

    Parameters
    ----------
    source : path
        A ``.yuv`` or ``.y4m`` video.
    output : path
        A picture's name with a frame number field (``frame_%03d.png``, see
        :func:`check_frame_pattern`), or a plain name for one frame.
    size, pix_fmt : optional
        The source's size and pixel format when its name or header does not say.
    depth : bool
        The video is a depth map: write its luma.
    preview : bool
        8-bit pictures: RGB of more bits requantized, or depth colour-mapped.
    start_frame, frame_count : int
        The frames written; ``frame_count`` None for all.
    progress : callable, optional
        ``progress(done, total)`` after each frame.

    Returns
    -------
    list of Path
        The pictures written, in frame order.
    """
    output = Path(output)
    with open_input_video(source, size, pix_fmt) as video:
        bits = video.format.bits
        frames = frame_range([video], start_frame, frame_count)
        written = []

        def write(index, planes):
            if depth:
                image = depth_preview(planes[0], bits=bits) if preview else np.array(planes[0])
            else:
                image = yuv_to_rgb(planes, bits=bits)
                if preview and bits > 8:
                    image = requantize(image, bits, 8)
            written.append(_frame_name(output, index, len(frames)))
            write_image(written[-1], image)

        stream_frames(frames, write, readers=[video], progress=progress)
    return written


def depth_video_to_pfm(
    source: str | os.PathLike,
    output: str | os.PathLike,
    values: DepthValues,
    *,
    size: tuple[int, int] | None = None,
    pix_fmt: str | None = None,
    start_frame: int = 0,
    frame_count: int | None = None,
    progress: ProgressCallback | None = None,
) -> list[Path]:
    """Write PFM images of the z or disparity that a depth video's frames code.

    Parameters
    ----------
    source : path
        A depth video (MPEG convention, luma only counts).
    output : path
        A ``.pfm`` name with a frame number field (``z_%03d.pfm``), or a plain name for
        one frame.
    values : DepthValues
    size, pix_fmt : optional
        The source's size and pixel format when its name or header does not say.
    start_frame, frame_count : int
        The frames written; ``frame_count`` None for all.
    progress : callable, optional
        ``progress(done, total)`` after each frame.

    Returns
    -------
    list of Path
        The images written, in frame order.
    """
    output = Path(output)
    with open_input_video(source, size, pix_fmt) as video:
        frames = frame_range([video], start_frame, frame_count)
        written = []

        def write(index, planes):
            with _samples_of(source, index):
                # z signed as the file codes it; disparity positive, as in front of the camera
                z = depth_to_z(planes[0], *values.depth_range, bits=video.format.bits)
                quantity = (
                    z
                    if values.quantity == "z"
                    else z_to_disparity(np.abs(z), values.focal, values.baseline)
                )
            written.append(_frame_name(output, index, len(frames)))
            write_image(written[-1], quantity.astype(np.float32))

        stream_frames(frames, write, readers=[video], progress=progress)
    return written


def pfm_to_depth_video(
    inputs: Sequence[str | os.PathLike],
    output: str | os.PathLike,
    values: DepthValues,
    *,
    out_pix_fmt: str = "yuv420p",
    progress: ProgressCallback | None = None,
) -> YuvFormat:
    """Write the depth video whose frames code PFM images of z or disparity.

    Parameters
    ----------
    inputs : sequence of path
        One-channel PFM images of one size, a frame each.
    output : path
        A ``.yuv`` or ``.y4m`` video; chroma, if any, is mid-grey.
    values : DepthValues
    out_pix_fmt : str
        The video's pixel format.
    progress : callable, optional
        ``progress(done, total)`` after each frame.

    Returns
    -------
    YuvFormat
        The video's format.
    """

    def frame(video: _VideoFromImages, path: Path) -> list:
        quantity = read_image(path)
        if quantity.ndim != 2 or quantity.dtype.kind != "f":
            raise DataError("expected a one-channel PFM of z or disparity", path=path)
        target = video.format_for(quantity.shape, path)
        with _samples_of(path):
            z = (
                quantity
                if values.quantity == "z"
                else (
                    depth_sign(*values.depth_range)
                    * disparity_to_z(quantity, values.focal, values.baseline)
                )
            )
            luma = z_to_depth(z, *values.depth_range, bits=target.bits)
        return [frame_from_luma(target, luma)]

    return _images_to_frames(inputs, output, out_pix_fmt, frame, progress)


def images_to_video(
    inputs: Sequence[str | os.PathLike],
    output: str | os.PathLike,
    *,
    out_pix_fmt: str = "yuv420p",
    progress: ProgressCallback | None = None,
) -> YuvFormat:
    """Write a video of pictures (BT.601 limited range), a frame each.

    Parameters
    ----------
    inputs : sequence of path
        Pictures of one size: RGB, or grey (8 or 16 bits) for luma.
    output : path
        A ``.yuv`` or ``.y4m`` video.
    out_pix_fmt : str
        The video's pixel format.
    progress : callable, optional
        ``progress(done, total)`` after each frame.

    Returns
    -------
    YuvFormat
        The video's format.
    """

    def frame(video: _VideoFromImages, path: Path) -> list:
        image = read_image(path)
        target = video.format_for(image.shape, path)
        if image.ndim == 2:
            bits = 8 if image.dtype == np.uint8 else 16
            return [
                convert_planes((image,), bits=bits, to_chroma=target.chroma, to_bits=target.bits)
            ]
        return [rgb_to_yuv(image, chroma=target.chroma, bits=target.bits)]

    return _images_to_frames(inputs, output, out_pix_fmt, frame, progress)


# One printf field of an integer (frame_%03d.png, f%x.png); %% is a % sign.
_FRAME_FIELD = re.compile(r"%[-#0 +]*\d*(?:\.\d+)?[diouxX]")


def check_frame_pattern(pattern: str | os.PathLike) -> None:
    """A name with a ``%`` must hold one frame number field, so that every frame gets
    a name of its own (check it before any frame is read or written).

    Raises
    ------
    UsageError
        No field, or more than one, or a lone ``%``.
    """
    pattern = Path(pattern)
    if "%" not in pattern.name:
        return
    name = pattern.name.replace("%%", "")
    if len(_FRAME_FIELD.findall(name)) != 1 or "%" in _FRAME_FIELD.sub("", name):
        raise UsageError(
            "a numbered output name holds one frame number field such as %03d "
            "(and %% for a % sign)",
            path=pattern,
            key="-o",
        )


def _frame_name(pattern: Path, index: int, count: int) -> Path:
    if "%" in pattern.name:
        return pattern.with_name(pattern.name % index)
    if count > 1:
        raise UsageError(
            "several frames need a numbered output name such as frame_%03d.png",
            path=pattern,
            key="-o",
        )
    return pattern


def _samples_of(path, frame: int | None = None):
    """The algorithm layer's ValueErrors on the samples of ``path`` (the options were
    checked before) are the file's fault: a DataError naming it and the frame."""
    return at_fault(DataError, path=path, prefix="" if frame is None else f"frame {frame}: ")


class _VideoFromImages:
    """A video of images, a frame each: its writer opens when the first image tells the
    size, and the output is removed on error."""

    def __init__(self, path: str | os.PathLike, pix_fmt: str):
        self.path = Path(path)
        self.pix_fmt = pix_fmt
        self.format: YuvFormat | None = None
        self._writer = None

    def format_for(self, shape: tuple[int, ...], path: Path) -> YuvFormat:
        """The video's format, set by the first image; every other image has its size."""
        if self.format is None:
            self.format = YuvFormat.from_pix_fmt(shape[1], shape[0], self.pix_fmt)
            self._writer = open_writer(self.path, self.format)
        if (shape[1], shape[0]) != self.format.size:
            raise DataError(
                f"image is {shape[1]}x{shape[0]}, the first one "
                f"{self.format.width}x{self.format.height}",
                path=path,
            )
        return self.format

    def write(self, planes) -> None:
        self._writer.write(planes)

    def __enter__(self):
        return self

    def __exit__(self, exc_type, exc, tb):
        if self._writer is not None:
            self._writer.__exit__(exc_type, exc, tb)


def _images_to_frames(inputs, output, out_pix_fmt, frame, progress) -> YuvFormat:
    """Each of ``inputs`` through ``frame(video, path)`` into the video ``output``."""
    paths = [Path(path) for path in inputs]
    with _VideoFromImages(output, out_pix_fmt) as video:
        stream_frames(
            range(len(paths)),
            lambda index: frame(video, paths[index]),
            writers=[video],
            progress=progress,
        )
    return video.format
