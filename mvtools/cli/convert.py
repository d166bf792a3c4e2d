"""``mvtools convert``: images <-> YUV/Y4M, pixel formats, depth maps <-> z/disparity, previews."""

from __future__ import annotations

import re
from dataclasses import replace
from pathlib import Path

import click
import numpy as np

from mvtools.cli.options import (
    DEPTH,
    FINITE,
    POSITIVE,
    ProgramCommand,
    frame_range_options,
    program,
    transposed_rotation_option,
    video_format_options,
)
from mvtools.cli.progress import Progress
from mvtools.color.levels import convert_planes, depth_preview, requantize
from mvtools.color.space import rgb_to_yuv, yuv_to_rgb
from mvtools.errors import DataError, UsageError, at_fault
from mvtools.geometry.depth import (
    check_depth_range,
    check_stereo,
    depth_sign,
    depth_to_z,
    disparity_to_z,
    z_to_depth,
    z_to_disparity,
)
from mvtools.io.cameras import read_cameras, write_cameras
from mvtools.io.images import IMAGE_EXTENSIONS, read_image, write_image
from mvtools.io.inputs import frame_range, open_input_video
from mvtools.io.json_cameras import (
    DEFAULT_FPS,
    read_json_cameras,
    read_json_sequence,
    write_json_cameras,
    write_json_sequence,
)
from mvtools.io.yuv import YuvFormat, frame_from_luma, open_writer

VIDEO_EXTENSIONS = (".yuv", ".y4m")


@click.command(name="convert", cls=ProgramCommand)
@click.argument("inputs", nargs=-1, required=True, type=click.Path(dir_okay=False))
@click.option(
    "-o",
    "--output",
    required=True,
    type=click.Path(dir_okay=False),
    help="Output: a .yuv/.y4m video, or an image name with a frame number pattern "
    "(frame_%03d.png, z_%03d.pfm) for one image per frame.",
)
@video_format_options
@frame_range_options
@click.option(
    "--out-pix-fmt",
    default=None,
    metavar="NAME",
    help="Pixel format of a video output (default: the input's, or yuv420p for images).",
)
@click.option(
    "--depth",
    is_flag=True,
    help="The video is a depth map: only luma counts, bit-depth changes keep "
    "v / vmax, chroma of the output is mid-grey, PNG output is grey.",
)
@click.option(
    "--preview",
    is_flag=True,
    help="8-bit preview images: RGB of texture frames, colour-mapped depth with --depth.",
)
@click.option(
    "--to",
    "to_quantity",
    type=click.Choice(["z", "disparity"]),
    default=None,
    help="Depth video -> PFM images of z, or of disparity (needs --focal, --baseline).",
)
@click.option(
    "--from",
    "from_quantity",
    type=click.Choice(["z", "disparity"]),
    default=None,
    help="PFM images of z or disparity -> depth video.",
)
@click.option("--znear", type=DEPTH, default=None, help="Depth of the largest depth value.")
@click.option("--zfar", type=DEPTH, default=None, help="Depth of depth value 0.")
@click.option("--focal", type=FINITE, default=None, help="Focal length in pixels (disparity).")
@click.option(
    "--baseline", type=FINITE, default=None, help="Baseline, in the units of z (disparity)."
)
@click.option(
    "--fps",
    type=POSITIVE,
    default=None,
    help=f"Fps of MPEG-I JSON cameras (default: the input's, else {DEFAULT_FPS}).",
)
@transposed_rotation_option
@program
def command(
    inputs,
    output,
    size,
    pix_fmt,
    start_frame,
    frame_count,
    out_pix_fmt,
    depth,
    preview,
    to_quantity,
    from_quantity,
    znear,
    zfar,
    focal,
    baseline,
    fps,
    transposed_rotation,
):
    """Convert INPUTS into OUTPUT.

    \b
    Image files (PNG, JPEG, PGM, ...) -> .yuv/.y4m video (BT.601 limited range).
    Video -> video in another pixel format (--out-pix-fmt), or raw <-> Y4M
    (the same samples). Texture bit depths change as ffmpeg changes them: up
    shifted, down with its ordered dither; chroma is resampled only for another
    layout.
    Video -> one image per frame (RGB, or grey depth with --depth; --preview for
    8-bit pictures, colour-mapped for depth).
    Depth video -> PFM of z or disparity (--depth --to z|disparity, with --znear --zfar).
    PFM of z or disparity -> depth video (--from z|disparity, with --znear --zfar).
    MPEG camera parameter file <-> MPEG-I JSON sequence file (.json; --size,
    --znear/--zfar, --fps and --frames fill Resolution, Depth_range, Fps and
    Frames_number; JSON -> JSON keeps the input's fields unless given).
    """
    output = Path(output)
    first = Path(inputs[0])
    if ".json" in (output.suffix.lower(), first.suffix.lower()):
        _convert_cameras(inputs, output, size, znear, zfar, fps, frame_count, transposed_rotation)
        return
    out_is_video = output.suffix.lower() in VIDEO_EXTENSIONS
    if not out_is_video and output.suffix.lower() not in IMAGE_EXTENSIONS:
        raise UsageError(
            f"unknown output type {output.suffix!r}: use .yuv, .y4m or an image "
            f"extension ({', '.join(IMAGE_EXTENSIONS)})",
            path=output,
        )
    if to_quantity is not None and from_quantity is not None:
        raise UsageError(
            "--to writes PFM images of a depth video, --from reads them: give one",
            key="--to/--from",
        )
    if first.suffix.lower() in VIDEO_EXTENSIONS:
        if len(inputs) > 1:
            raise UsageError("give one video input at a time")
        if from_quantity is not None:
            raise UsageError(
                "the input is a video, and --from reads PFM images of z or "
                "disparity (--to writes them)",
                path=first,
                key="--from",
            )
        if not out_is_video:
            _check_frame_pattern(output)
        if to_quantity is not None:
            _depth_video_to_pfm(
                first,
                size,
                pix_fmt,
                start_frame,
                frame_count,
                output,
                to_quantity,
                _range(znear, zfar),
                focal,
                baseline,
            )
        elif out_is_video:
            _video_to_video(
                first, size, pix_fmt, start_frame, frame_count, output, out_pix_fmt, depth
            )
        else:
            _video_to_images(first, size, pix_fmt, start_frame, frame_count, output, depth, preview)
        return
    if not out_is_video:
        raise UsageError("images convert to a .yuv or .y4m video", path=output)
    if to_quantity is not None:
        raise UsageError(
            "the input is not a video, and --to writes PFM images of a depth "
            "video (--from reads them)",
            path=first,
            key="--to",
        )
    if from_quantity is not None:
        _pfm_to_depth_video(
            inputs,
            output,
            out_pix_fmt or "yuv420p",
            from_quantity,
            _range(znear, zfar),
            focal,
            baseline,
        )
    else:
        _images_to_video(inputs, output, out_pix_fmt or "yuv420p")


def _convert_cameras(
    inputs, output: Path, size, znear, zfar, fps, frame_count, transposed_rotation
):
    if len(inputs) != 1:
        raise UsageError("give one camera file at a time")
    source = Path(inputs[0])
    depth_range = _camera_depth_range(znear, zfar)
    if source.suffix.lower() != ".json":
        write_json_cameras(
            output,
            read_cameras(source, transposed_rotation=transposed_rotation),
            size=size,
            depth_range=depth_range,
            fps=fps or DEFAULT_FPS,
            frame_count=frame_count or 1,
        )
    elif output.suffix.lower() != ".json":
        write_cameras(output, read_json_cameras(source), transposed_rotation=transposed_rotation)
    else:
        sequence = read_json_sequence(source)
        sequence.cameras = {
            name: replace(
                camera, size=size or camera.size, depth_range=depth_range or camera.depth_range
            )
            for name, camera in sequence.cameras.items()
        }
        sequence.fps = fps or sequence.fps
        sequence.frame_count = frame_count or sequence.frame_count
        write_json_sequence(output, sequence)


def _camera_depth_range(znear, zfar) -> tuple[float, float] | None:
    """``Depth_range`` from --znear/--zfar; negative ranges (VSRS) are the writer's to turn."""
    if (znear, zfar) == (None, None):
        return None
    if znear is None or zfar is None:
        raise UsageError("give both --znear and --zfar for the cameras' Depth_range")
    return znear, zfar


def _range(znear, zfar) -> tuple[float, float]:
    if znear is None or zfar is None:
        raise UsageError("--znear and --zfar are needed to interpret depth values")
    with at_fault(UsageError, key="--znear/--zfar"):
        check_depth_range(znear, zfar)
    return znear, zfar


def _stereo(focal, baseline) -> tuple[float, float]:
    if focal is None or baseline is None:
        raise UsageError("--focal and --baseline are needed for disparities")
    with at_fault(UsageError, key="--focal/--baseline"):
        check_stereo(focal, baseline)
    return focal, baseline


def _samples_of(path, frame: int | None = None):
    """The algorithm layer's ValueErrors on the samples of ``path`` (the options were
    checked before) are the file's fault: a DataError naming it and the frame."""
    return at_fault(DataError, path=path, prefix="" if frame is None else f"frame {frame}: ")


# One printf field of an integer (frame_%03d.png, f%x.png); %% is a % sign.
_FRAME_FIELD = re.compile(r"%[-#0 +]*\d*(?:\.\d+)?[diouxX]")


def _check_frame_pattern(pattern: Path) -> None:
    """A name with a ``%`` must hold one frame number field, so that every frame gets
    a name of its own (checked before any frame is read or written)."""
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


def _video_to_video(path, size, pix_fmt, start, count, output, out_pix_fmt, depth):
    with open_input_video(path, size, pix_fmt) as video:
        source = video.format
        target = (
            YuvFormat.from_pix_fmt(source.width, source.height, out_pix_fmt)
            if out_pix_fmt
            else source
        )
        frames = frame_range([video], start, count)
        progress = Progress(len(frames), "frames converted")
        with open_writer(output, target, frame_rate=video.frame_rate) as writer:
            for index in frames:
                with _samples_of(path, index):
                    planes = convert_planes(
                        video.read(index),
                        bits=source.bits,
                        to_chroma=target.chroma,
                        to_bits=target.bits,
                        depth=depth,
                    )
                writer.write(planes)
                progress.advance()


def _video_to_images(path, size, pix_fmt, start, count, output, depth, preview):
    with open_input_video(path, size, pix_fmt) as video:
        bits = video.format.bits
        frames = frame_range([video], start, count)
        progress = Progress(len(frames), "frames written")
        for index in frames:
            planes = video.read(index)
            if depth:
                image = depth_preview(planes[0], bits=bits) if preview else np.array(planes[0])
            else:
                image = yuv_to_rgb(planes, bits=bits)
                if preview and bits > 8:
                    image = requantize(image, bits, 8)
            write_image(_frame_name(output, index, len(frames)), image)
            progress.advance()


def _depth_video_to_pfm(
    path, size, pix_fmt, start, count, output, quantity, depth_range, focal, baseline
):
    if output.suffix.lower() != ".pfm":
        raise UsageError("--to writes PFM images (e.g. z_%03d.pfm)", path=output)
    if quantity == "disparity":
        focal, baseline = _stereo(focal, baseline)
    with open_input_video(path, size, pix_fmt) as video:
        frames = frame_range([video], start, count)
        for index in frames:
            with _samples_of(path, index):
                # z signed as the file codes it; disparity positive, as in front of the camera
                z = depth_to_z(video.read(index)[0], *depth_range, bits=video.format.bits)
                values = z if quantity == "z" else z_to_disparity(np.abs(z), focal, baseline)
            write_image(_frame_name(output, index, len(frames)), values.astype(np.float32))


def _pfm_to_depth_video(inputs, output, out_pix_fmt, quantity, depth_range, focal, baseline):
    if quantity == "disparity":
        focal, baseline = _stereo(focal, baseline)
    target = None
    with _video_writer_for_images(output) as writer:
        for path in inputs:
            values = read_image(path)
            if values.ndim != 2 or values.dtype.kind != "f":
                raise DataError("expected a one-channel PFM of z or disparity", path=path)
            if target is None:
                target = YuvFormat.from_pix_fmt(values.shape[1], values.shape[0], out_pix_fmt)
                writer.start(target)
            _check_size(values.shape, target, path)
            with _samples_of(path):
                z = (
                    values
                    if quantity == "z"
                    else (depth_sign(*depth_range) * disparity_to_z(values, focal, baseline))
                )
                luma = z_to_depth(z, *depth_range, bits=target.bits)
            writer.write(frame_from_luma(target, luma))


def _images_to_video(inputs, output, out_pix_fmt):
    target = None
    with _video_writer_for_images(output) as writer:
        for path in inputs:
            image = read_image(path)
            if target is None:
                target = YuvFormat.from_pix_fmt(image.shape[1], image.shape[0], out_pix_fmt)
                writer.start(target)
            _check_size(image.shape, target, path)
            if image.ndim == 2:
                bits = 8 if image.dtype == np.uint8 else 16
                writer.write(
                    convert_planes(
                        (image,), bits=bits, to_chroma=target.chroma, to_bits=target.bits
                    )
                )
            else:
                writer.write(rgb_to_yuv(image, chroma=target.chroma, bits=target.bits))


def _check_size(shape, target: YuvFormat, path) -> None:
    if (shape[1], shape[0]) != target.size:
        raise DataError(
            f"image is {shape[1]}x{shape[0]}, the first one {target.width}x{target.height}",
            path=path,
        )


class _video_writer_for_images:
    """A video writer opened when the first image tells the size; removed on error."""

    def __init__(self, path: Path):
        self.path = path
        self.writer = None

    def start(self, fmt: YuvFormat) -> None:
        self.writer = open_writer(self.path, fmt)

    def write(self, planes) -> None:
        self.writer.write(planes)

    def __enter__(self):
        return self

    def __exit__(self, exc_type, exc, tb):
        if self.writer is not None:
            self.writer.__exit__(exc_type, exc, tb)
