"""``mvtools estimate-depth``: depth maps from DERS configurations, disparity maps from
a rectified stereo pair.

DERS mode (``estimate-depth CONFIG [Key=Value ...]``): the configuration is read
unmodified (:func:`mvtools.io.loaded_config.load_config`), ``Key=Value`` items and one option
per DERS key override it; the center view's depth is estimated from its left and/or
right neighbours by plane sweeping (:class:`mvtools.depth.ders.DersEstimator`), frames
streamed one at a time, and written as an MPEG depth map (8-bit 4:2:0 with chroma 128,
or 16-bit 4:0:0 with ``--depth-bits 16`` or a ``_gray16le`` name). The Znear/Zfar that the
values mean are printed and saved next to the output as ``OUTPUT.json``. Every output is
written atomically.

Stereo-pair mode: the left view's disparity is written as PFM (float, ``inf`` where
no disparity was found, as Middlebury stores unknown values) and, on request, as a
16-bit PNG holding ``round(disparity * scale)`` with 0 for unknown, the convention
of Middlebury's ground-truth files, so that ``mvtools evaluate --disparity`` scores
either file.
"""

from __future__ import annotations

import contextlib
import json
import logging
import time
from collections.abc import Sequence
from pathlib import Path

import click
import numpy as np

from mvtools.cli.options import (
    FINITE,
    ProgramCommand,
    data_dir_option,
    overrides_argument,
    param_options,
    program,
    transposed_rotation_option,
)
from mvtools.cli.progress import Progress
from mvtools.depth import COSTS, METHODS, estimate_disparity
from mvtools.depth.ders import DersEstimator, Neighbour
from mvtools.errors import ConfigError, DataError, UsageError, at_fault
from mvtools.geometry.depth import DepthCoding
from mvtools.io.atomic import atomic_output, output_folder_exists
from mvtools.io.config import param_entry
from mvtools.io.guard import check_output
from mvtools.io.images import read_image, write_image
from mvtools.io.loaded_config import (
    LoadedConfig,
    command_line_input,
    load_config,
    video_format_for,
)
from mvtools.io.yuv import (
    YuvFormat,
    format_from_name,
    frame_from_luma,
    open_video,
    open_writer,
)
from mvtools.params import DersParams
from mvtools.synthesis.working import to_working

LOG = logging.getLogger(__name__)

#: Disparity-map PNG value / scale = disparity in pixels: quarter pixels, as the
#: Middlebury 2003 ground truth (Teddy, Cones) stores them.
DEFAULT_PNG_SCALE = 4.0
_PNG_MAX = np.iinfo(np.uint16).max

#: Default method of the stereo-pair mode, the best measured on the Middlebury pairs
#: (bad 1.0 and the synthesized Cones view, :func:`mvtools.depth.estimate_disparity`).
#: DERS mode's default is the Method key's, ``sgm``, the best on Kendo: the fetch error
#: of view 3 into camera 1 is a median of 1.53, bp 1.45, local 1.39, graphcut 1.44, in
#: 5.3 s per frame against 9.9, 15.1 and 105 s.
PAIR_METHOD = "bp"

#: Default matching cost of the stereo-pair mode: the better synthesized views
#: (:func:`mvtools.depth.cost.census_gradient_cost`, Notes).
PAIR_COST = "ad-census"


#: Command-line names of DERS keys beyond ``--`` + the key in snake case.
_SECONDARY_NAMES = {"total_number_of_frames": ("--frames",)}


@click.command(name="estimate-depth", cls=ProgramCommand)
@click.argument("config", required=False, type=click.Path(dir_okay=False))
@overrides_argument
@data_dir_option
@click.option(
    "--left",
    type=click.Path(dir_okay=False),
    default=None,
    help="Stereo-pair mode: left picture of a rectified pair (PNG, PPM, JPEG...), "
    "the view whose disparity is estimated.",
)
@click.option(
    "--right",
    type=click.Path(dir_okay=False),
    default=None,
    help="Stereo-pair mode: right picture of the pair, same size as --left.",
)
@click.option(
    "--disparities",
    "max_disparity",
    type=int,
    default=None,
    metavar="N",
    help="Stereo-pair mode: largest disparity searched, in pixels (left x - right x; inclusive).",
)
@click.option(
    "--min-disparity",
    type=int,
    default=None,
    help="Stereo-pair mode: smallest disparity searched, in pixels (inclusive; default 0).",
)
@click.option(
    "--neighbour",
    "further_neighbours",
    multiple=True,
    nargs=2,
    metavar="CAMERA VIDEO",
    help="DERS mode: a further neighbour view (repeatable): camera name of the "
    "camera file and its video, matched in the plane sweep besides the left "
    "and right views of the configuration.",
)
@click.option(
    "--subpixel/--integer",
    default=None,
    help="Stereo-pair mode: sub-pixel disparities, or the integer levels "
    "(default), which score better on Middlebury's bad 1.0.",
)
@click.option(
    "--cost",
    type=click.Choice(sorted(COSTS)),
    default=None,
    help=f"Stereo-pair mode: matching cost (default {PAIR_COST}); census-gradient "
    "(colour-weighted sparse census and gradients) scores better on "
    "Middlebury's bad 1.0, ad-census gives better synthesized views.",
)
@click.option(
    "--segment-planes/--no-segment-planes",
    default=None,
    help="Stereo-pair mode: colour segments whose disparity plane matches about as "
    "well as the method's disparities take it, and fattened foreground next "
    "to depth steps returns to the background plane (default on).",
)
@click.option(
    "--segmentation",
    is_flag=True,
    default=None,
    help="Stereo-pair mode: fill the pixels failing the left-right check from "
    "disparity planes of colour segments.",
)
@click.option(
    "--view",
    "pair_view",
    type=click.Choice(("left", "right")),
    default=None,
    help="Stereo-pair mode: whose disparity to write (default left; right: "
    "x_left = x_right + disparity).",
)
@click.option(
    "-o",
    "--output",
    type=click.Path(dir_okay=False),
    default=None,
    help="DERS mode: the depth map video (FileOutputDepthMapImage). Stereo-pair "
    "mode: disparity map of the left view (or --view right), PFM (float "
    "pixels, inf = unknown).",
)
@click.option(
    "--png",
    type=click.Path(dir_okay=False),
    default=None,
    help="Stereo-pair mode: also write the disparity map as a 16-bit PNG holding "
    "disparity * --png-scale, rounded, 0 = unknown.",
)
@click.option(
    "--png-scale",
    type=FINITE,
    default=None,
    help=f"Stereo-pair mode: PNG value / scale = disparity in pixels (give the same "
    f"number to evaluate --disparity-scale; default {DEFAULT_PNG_SCALE:g}).",
)
@click.option(
    "--depth-bits",
    type=click.Choice(["8", "16"]),
    default=None,
    help="DERS mode: 8-bit 4:2:0 depth with chroma 128 (default), or 16-bit 4:0:0 "
    "(gray16le); an output name such as depth_1024x768_gray16le.yuv says the "
    "same.",
)
@transposed_rotation_option
@param_options(DersParams, _SECONDARY_NAMES)
@program
def command(
    config,
    overrides,
    data_dirs,
    left,
    right,
    max_disparity,
    min_disparity,
    further_neighbours,
    subpixel,
    cost,
    segment_planes,
    segmentation,
    pair_view,
    output,
    png,
    png_scale,
    depth_bits,
    transposed_rotation,
    **options,
):
    """Estimate depth from a DERS configuration, or disparity from a stereo pair.

    \b
    mvtools estimate-depth ders.cfg [Key=Value ...] [--data-dir DIR] [-o depth.yuv]
    mvtools estimate-depth --left im2.png --right im6.png --disparities 64 \\
        -o disparity.pfm --png disparity.png --png-scale 4

    DERS mode: CONFIG is a DERS configuration file, read unmodified; Key=Value items
    override it as on the DERS command line, and the options below (one per DERS key)
    override both. The depth of the center view (CenterCameraName) is estimated from
    its left and/or right neighbours (MatchDirection) with the camera parameter file
    (MPEG text, or MPEG-I JSON when its name ends in .json) by plane sweeping: depth
    planes uniform in 1/z from the disparity search range (pixels to the BaselineBasis
    view, SearchLevel steps per pixel) or from NearestSearchDepthValue,
    FarthestSearchDepthValue and NumberOfDepthSteps; any camera layout, and any number
    of further views with --neighbour (the least cost of the views that see a point
    counts, DERS's occlusion rule). The output holds
    MinimumValueOfDisparityRange..MaximumValueOfDisparityRange as 0..255, or
    FarthestDepthValue..NearestDepthValue when those are given; the Znear/Zfar this
    means are printed and written to OUTPUT.json. Frames: StartFrame,
    TotalNumberOfFrames; progress on stderr.

    Stereo-pair mode: the pictures are rectified (corresponding points on the same row,
    the right view's point to the left: disparity = left x - right x >= 0 for the usual
    --min-disparity 0). The PFM keeps the float disparities with inf where the method
    found none (occlusions, failed consistency checks); the PNG, for Middlebury-style
    evaluation, holds disparity * --png-scale with 0 for those (a true disparity that
    rounds to 0 is then read as unknown too).

    Exits with 2 for a bad configuration, option or missing file, 1 for inconsistent
    data (different sizes, damaged videos), leaving no output file.
    """
    pair_options = {
        "--left": left,
        "--right": right,
        "--disparities": max_disparity,
        "--min-disparity": min_disparity,
        "--png": png,
        "--png-scale": png_scale,
        "--subpixel/--integer": subpixel,
        "--cost": cost,
        "--segment-planes/--no-segment-planes": segment_planes,
        "--segmentation": segmentation,
        "--view": pair_view,
    }
    if config is not None:
        given = [name for name, value in pair_options.items() if value is not None]
        if given:
            raise UsageError(
                f"{', '.join(given)}: stereo-pair options cannot go with a DERS configuration"
            )
        _ders_mode(
            config,
            overrides,
            data_dirs,
            output=output,
            further_neighbours=further_neighbours,
            depth_bits=None if depth_bits is None else int(depth_bits),
            transposed_rotation=transposed_rotation,
            options=options,
        )
        return
    # --method, the Method key of DERS mode, chooses the method of this mode too
    method = options.pop("method") or PAIR_METHOD
    ders_given = [
        f"--{name.replace('_', '-')}" for name, value in options.items() if value is not None
    ]
    ders_given += ["--data-dir"] * bool(data_dirs) + ["--depth-bits"] * (depth_bits is not None)
    ders_given += ["--transposed-rotation"] * transposed_rotation
    ders_given += ["--neighbour"] * bool(further_neighbours)
    if overrides or ders_given:
        raise UsageError(
            f"{', '.join(ders_given + list(overrides))}: DERS options need a "
            "configuration file (CONFIG)"
        )
    min_disparity = 0 if min_disparity is None else min_disparity
    png_scale = DEFAULT_PNG_SCALE if png_scale is None else png_scale
    for name, value in (
        ("--left", left),
        ("--right", right),
        ("--disparities", max_disparity),
        ("-o/--output", output),
    ):
        if value is None:
            raise UsageError(
                f"{name} is required (stereo-pair mode: --left L --right R "
                "--disparities N -o OUT.pfm)"
            )
    if min_disparity >= max_disparity:
        raise UsageError(
            f"empty disparity range: --min-disparity {min_disparity} must be "
            f"smaller than --disparities {max_disparity}"
        )
    left_rgb, right_rgb = _read_view(Path(left)), _read_view(Path(right))
    outputs = _check_outputs(
        Path(output), None if png is None else Path(png), png_scale, min_disparity, max_disparity
    )
    if left_rgb.shape != right_rgb.shape:
        raise DataError(
            f"the right picture is {right_rgb.shape[1]}x{right_rgb.shape[0]}, the "
            f"left one {left_rgb.shape[1]}x{left_rgb.shape[0]}",
            path=right,
        )
    height, width = left_rgb.shape[:2]
    LOG.info(
        "%s: %dx%d, disparities %d..%d, method %s, cost %s",
        right if pair_view == "right" else left,
        width,
        height,
        min_disparity,
        max_disparity,
        method,
        cost or PAIR_COST,
    )
    start = time.perf_counter()
    # The method's own limits on the range or picture size, which options can break, are
    # ValueErrors: usage errors at the programs' edge.
    disparity = estimate_disparity(
        left_rgb,
        right_rgb,
        max_disparity=max_disparity,
        min_disparity=min_disparity,
        method=method,
        cost=cost or PAIR_COST,
        subpixel=bool(subpixel),
        segment_planes=segment_planes is not False,
        segmentation=bool(segmentation),
        view=pair_view or "left",
    )
    known = np.isfinite(disparity)
    LOG.info(
        "disparity estimated in %.2f s, %.1f %% of the pixels unknown",
        time.perf_counter() - start,
        100.0 * (1.0 - known.mean()),
    )
    write_image(outputs[0], np.where(known, disparity, np.inf).astype(np.float32))
    LOG.info("wrote %s", outputs[0])
    if len(outputs) > 1:
        write_image(outputs[1], disparity_png_values(disparity, scale=png_scale))
        LOG.info("wrote %s (disparity * %g)", outputs[1], png_scale)


# --------------------------------------------------------------------------- DERS mode

#: The sidecar OUTPUT.json in messages.
_SIDECAR = "depth values' description (OUTPUT.json)"

#: Neighbour sides that MatchDirection matches.
_DIRECTIONS = {1: ("left",), 2: ("right",), 3: ("left", "right")}


def _ders_mode(
    config: str,
    overrides,
    data_dirs,
    *,
    output: str | None,
    further_neighbours: Sequence[tuple[str, str]],
    depth_bits: int | None,
    transposed_rotation: bool,
    options: dict,
) -> None:
    """Depth maps of the center view that a DERS configuration describes."""
    if output is not None:
        options = {**options, "file_output_depth_map_image": output}
    loaded = load_config(
        DersParams,
        config,
        overrides=overrides,
        options=options,
        data_dirs=data_dirs,
        transposed_rotation=transposed_rotation,
    )
    params = loaded.params
    if params.method not in METHODS:
        raise param_entry(params, "method").error(
            f"method {params.method!r} is for stereo pairs; DERS mode methods: {', '.join(METHODS)}"
        )
    if params.file_camera_parameter == "":
        raise param_entry(params, "file_camera_parameter").error("no camera parameter file given")
    if "center_camera_name" not in loaded.cameras:
        raise param_entry(params, "center_camera_name").error("no camera name given")
    sides = _matched_sides(loaded, further=bool(further_neighbours))
    fields = ["file_center_view_image"] + [f"file_{side}_view_image" for side in sides]
    for field in fields:
        if field not in loaded.inputs:
            raise param_entry(params, field).error("no file given")
    size = (params.source_width, params.source_height)
    # (path, format) of every view read, the center first, then the neighbours in order
    videos = [(loaded.inputs[field], loaded.video_format(field)) for field in fields]
    neighbours = [Neighbour(loaded.cameras[f"{side}_camera_name"], side) for side in sides]
    for name, video in further_neighbours:
        label = f"--neighbour {name}"
        camera = loaded.command_line_camera(name, label)
        path = command_line_input(label, video, data_dirs)
        videos.append((path, video_format_for(path, size, key=label)))
        neighbours.append(Neighbour(camera))
    if "file_output_depth_map_image" not in loaded.outputs:
        raise param_entry(params, "file_output_depth_map_image").error(
            "no output file given (or -o)", UsageError
        )
    target = loaded.outputs["file_output_depth_map_image"]
    sidecar = target.with_name(target.name + ".json")
    depth_format = _depth_format(target, size, depth_bits)
    center = loaded.cameras["center_camera_name"]
    with at_fault(ConfigError, path=config):
        estimator = DersEstimator(params, center, neighbours, method=params.method)
        coding = DepthCoding(estimator.depth_range, depth_format.bits, depth_type=params.depth_type)
    znear, zfar = estimator.depth_range
    with contextlib.ExitStack() as stack:
        readers = [stack.enter_context(open_video(path, fmt)) for path, fmt in videos]
        for reader in readers:
            if reader.format.chroma == "400":
                raise DataError(
                    "a view needs colour planes, this video is grey (4:0:0)", path=reader.path
                )
        # Every input is now open, so the run's guard knows it: an output that names
        # one is refused before any work.
        check_output(target)
        check_output(sidecar, _SIDECAR)
        frames = loaded.frame_range(readers)
        LOG.info(
            "estimating the depth of %s from %s (%s, %d planes), %d frame%s from frame %d",
            center.name,
            " and ".join(n.camera.name for n in neighbours),
            params.method,
            estimator.inverse_depths.size,
            len(frames),
            "s" if len(frames) != 1 else "",
            frames.start,
        )
        LOG.info(
            "depth values mean NearestDepthValue %.6f FarthestDepthValue %.6f (%d-bit, %s)",
            znear,
            zfar,
            depth_format.bits,
            sidecar,
        )
        writer = stack.enter_context(open_writer(target, depth_format))
        description = stack.enter_context(atomic_output(sidecar, "w", what=_SIDECAR))
        first = estimator.fresh_frame(frames.start)
        if first < frames.start:
            # a chunk of a longer run estimates, unwritten, the frames whose depth
            # TemporalEnhancement can keep
            LOG.warning(
                "estimating frames %d to %d first, unwritten: TemporalEnhancement "
                "carries depth from frame %d on (TemporalRefreshPeriod %d)",
                first,
                frames.start - 1,
                first,
                params.temporal_refresh_period,
            )
        earlier = Progress(frames.start - first, "earlier frames estimated")
        progress = Progress(len(frames), "frames estimated")
        for index in range(first, frames.stop):
            if estimator.fresh_frame(index) == index:
                estimator.refresh()
            views = [_rgb_8bit_scale(reader.read(index), reader.format.bits) for reader in readers]
            z = estimator.frame(views[0], views[1:])
            if index < frames.start:
                earlier.advance()
                continue
            writer.write(frame_from_luma(depth_format, coding.values(z)))
            progress.advance()
        json.dump(
            _description(center.name, znear, zfar, depth_format, params.depth_type),
            description,
            indent=2,
        )
        description.write("\n")
    LOG.info("wrote %s and %s", target, sidecar)


def _matched_sides(loaded: LoadedConfig, *, further: bool) -> list[str]:
    """The neighbour sides to match: named in the configuration and asked for by
    MatchDirection; none is an error unless ``further`` views are given."""
    params = loaded.params
    wanted = _DIRECTIONS[params.match_direction]
    named = [side for side in ("left", "right") if f"{side}_camera_name" in loaded.cameras]
    if not named and not further:
        raise param_entry(params, "left_camera_name").error(
            "no neighbour view: give LeftCameraName and/or RightCameraName"
        )
    if params.match_direction != 3 and wanted[0] not in named and named:
        raise param_entry(params, "match_direction").error(
            f"MatchDirection {params.match_direction} matches the {wanted[0]} view, but "
            f"{wanted[0].title()}CameraName is not given"
        )
    return [side for side in named if side in wanted]


def _depth_format(path: Path, size: tuple[int, int], bits: int | None) -> YuvFormat:
    """Format of the depth output: as its name says, else 8-bit 4:2:0 or 16-bit 4:0:0."""
    named = format_from_name(path)
    if named is None:
        bits = 8 if bits is None else bits
        return YuvFormat(*size, chroma="420" if bits == 8 else "400", bits=bits)
    if named.size != size:
        raise UsageError(
            f"the output name says {named.width}x{named.height}, the configuration "
            f"{size[0]}x{size[1]} (SourceWidth, SourceHeight)",
            path=path,
        )
    if named.chroma not in ("420", "400"):
        raise UsageError(
            f"depth maps are written as 4:2:0 or 4:0:0, the name says {named.chroma}", path=path
        )
    if bits is not None and bits != named.bits:
        raise UsageError(
            f"--depth-bits {bits} disagrees with the output name ({named.bits} bits)", path=path
        )
    return named


def _rgb_8bit_scale(planes, bits: int) -> np.ndarray:
    """A YUV frame as (H, W, 3) float32 RGB on an 8-bit scale (the matching costs' scale)."""
    rgb = to_working(planes, color_space=1, bits=bits)
    return rgb / np.float32(1 << (bits - 8)) if bits > 8 else rgb


def _description(camera: str, znear: float, zfar: float, fmt: YuvFormat, depth_type: int) -> dict:
    """What the sidecar ``OUTPUT.json`` says: the depth values' meaning (Zfar null = infinite)."""
    return {
        "camera": camera,
        "NearestDepthValue": znear,
        "FarthestDepthValue": zfar if np.isfinite(zfar) else None,
        "DepthType": depth_type,
        "pix_fmt": fmt.pix_fmt,
        "width": fmt.width,
        "height": fmt.height,
    }


def disparity_png_values(disparity: np.ndarray, *, scale: float) -> np.ndarray:
    """16-bit PNG samples of a disparity map: ``round(disparity * scale)``, 0 where unknown.

    Parameters
    ----------
    disparity : ndarray of float, shape (H, W)
        Disparities in pixels, NaN or infinite where unknown, within
        ``[0, 65535 / scale]``.
    scale : float
        File value / scale = disparity in pixels.

    Returns
    -------
    ndarray of uint16, shape (H, W)
    """
    known = np.isfinite(disparity)
    values = np.round(np.where(known, disparity, 0.0) * scale)
    return np.clip(values, 0, _PNG_MAX).astype(np.uint16)


def _check_outputs(
    output: Path, png: Path | None, png_scale: float, min_disparity: int, max_disparity: int
) -> list[Path]:
    """The output paths, checked once the inputs are read and before the estimation, so
    that a bad one fails at once and leaves nothing behind."""
    if output.suffix.lower() != ".pfm":
        raise UsageError(
            "the disparity map is written as PFM: give a name ending in .pfm", path=output, key="-o"
        )
    outputs = [output]
    if png is not None:
        if png.suffix.lower() != ".png":
            raise UsageError("--png needs a name ending in .png", path=png, key="--png")
        if not png_scale > 0:
            raise UsageError(f"--png-scale must be positive, got {png_scale:g}")
        if min_disparity < 0:
            raise UsageError(
                f"a PNG disparity map cannot hold negative disparities "
                f"(--min-disparity {min_disparity}); use the PFM output alone"
            )
        if max_disparity * png_scale > _PNG_MAX:
            raise UsageError(
                f"--disparities {max_disparity} * --png-scale {png_scale:g} exceeds "
                f"{_PNG_MAX}, the largest 16-bit value; lower --png-scale"
            )
        outputs.append(png)
    for path in outputs:
        output_folder_exists(path.parent)
        check_output(path)
    return outputs


def _read_view(path: Path) -> np.ndarray:
    """A picture as ``(H, W, 3)`` uint8 RGB; grey is repeated, 16-bit samples reduced."""
    image = read_image(path)
    if image.dtype.kind == "f":
        raise DataError("a picture is expected, this is a float (PFM) map", path=path)
    if image.dtype == np.uint16:
        image = (image // 257).astype(np.uint8)
    if image.ndim == 2:
        image = np.repeat(image[..., None], 3, axis=2)
    return image
