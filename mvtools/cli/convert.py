"""``mvtools convert``: images <-> YUV/Y4M, pixel formats, depth maps <-> z/disparity, previews."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import click

from mvtools.cli.options import (
    FINITE,
    POSITIVE,
    ProgramCommand,
    depth_range_option,
    frame_range_options,
    program,
    transposed_rotation_option,
    video_format_options,
)
from mvtools.cli.progress import Progress
from mvtools.errors import UsageError, at_fault
from mvtools.geometry.depth import check_depth_range, check_stereo
from mvtools.io.cameras import read_cameras, write_cameras
from mvtools.io.captures import VIDEO_EXTENSIONS
from mvtools.io.images import IMAGE_EXTENSIONS
from mvtools.io.json_cameras import (
    DEFAULT_FPS,
    read_json_cameras,
    read_json_sequence,
    write_json_cameras,
    write_json_sequence,
)
from mvtools.io.yuv import is_standard_stream
from mvtools.run.convert import (
    DepthValues,
    check_frame_pattern,
    convert_video,
    depth_video_to_pfm,
    images_to_video,
    pfm_to_depth_video,
    video_to_images,
)


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
@depth_range_option(of="the depth video or the cameras (their Depth_range)")
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
    depth_range,
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
    Depth video -> PFM of z or disparity (--depth --to z|disparity, with --depth-range).
    PFM of z or disparity -> depth video (--from z|disparity, with --depth-range).
    MPEG camera parameter file <-> MPEG-I JSON sequence file (.json; --size,
    --depth-range, --fps and --frames fill Resolution, Depth_range, Fps and
    Frames_number; JSON -> JSON keeps the input's fields unless given).
    """
    output = Path(output)
    first = Path(inputs[0])
    if ".json" in (output.suffix.lower(), first.suffix.lower()):
        _convert_cameras(inputs, output, size, depth_range, fps, frame_count, transposed_rotation)
        return
    out_is_video = output.suffix.lower() in VIDEO_EXTENSIONS or is_standard_stream(output)
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
    if first.suffix.lower() in VIDEO_EXTENSIONS or is_standard_stream(first):
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
            check_frame_pattern(output)
        frames = {
            "size": size,
            "pix_fmt": pix_fmt,
            "start_frame": start_frame,
            "frame_count": frame_count,
        }
        if to_quantity is not None:
            depth_range = _range(depth_range)
            if output.suffix.lower() != ".pfm":
                raise UsageError("--to writes PFM images (e.g. z_%03d.pfm)", path=output)
            values = _depth_values(to_quantity, depth_range, focal, baseline)
            depth_video_to_pfm(first, output, values, **frames)
        elif out_is_video:
            convert_video(
                first,
                output,
                out_pix_fmt=out_pix_fmt,
                depth=depth,
                progress=Progress(None, "frames converted"),
                **frames,
            )
        else:
            video_to_images(
                first,
                output,
                depth=depth,
                preview=preview,
                progress=Progress(None, "frames written"),
                **frames,
            )
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
        values = _depth_values(from_quantity, _range(depth_range), focal, baseline)
        pfm_to_depth_video(inputs, output, values, out_pix_fmt=out_pix_fmt or "yuv420p")
    else:
        images_to_video(inputs, output, out_pix_fmt=out_pix_fmt or "yuv420p")


def _convert_cameras(
    inputs, output: Path, size, depth_range, fps, frame_count, transposed_rotation
):
    if len(inputs) != 1:
        raise UsageError("give one camera file at a time")
    source = Path(inputs[0])
    # negative ranges (VSRS) are the writer's to turn
    depth_range = tuple(depth_range) if depth_range else None
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


def _range(depth_range) -> tuple[float, float]:
    if not depth_range:
        raise UsageError("--depth-range ZNEAR ZFAR is needed to interpret depth values")
    with at_fault(UsageError, key="--depth-range"):
        check_depth_range(*depth_range)
    return tuple(depth_range)


def _depth_values(quantity, depth_range, focal, baseline) -> DepthValues:
    """What the PFM images hold; disparities need --focal and --baseline."""
    if quantity == "disparity":
        if focal is None or baseline is None:
            raise UsageError("--focal and --baseline are needed for disparities")
        with at_fault(UsageError, key="--focal/--baseline"):
            check_stereo(focal, baseline)
    return DepthValues(quantity, depth_range, focal, baseline)
