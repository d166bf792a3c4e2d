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

import logging
import math
from pathlib import Path

import click

from mvtools.cli.options import (
    FINITE,
    ProgramCommand,
    data_dir_option,
    overrides_argument,
    param_options,
    program,
    transposed_rotation_option,
    view_option,
)
from mvtools.cli.progress import Progress
from mvtools.depth.options import COST_NAMES, DEFAULT_METHOD, DepthOptions
from mvtools.errors import UsageError
from mvtools.io.loaded_config import command_line_input, load_config
from mvtools.params import DersParams
from mvtools.run.depth import (
    DEFAULT_PNG_SCALE,
    FurtherView,
    estimate_depth_loaded,
    estimate_pair_disparity,
    estimate_views_disparity,
)

LOG = logging.getLogger(__name__)

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
    "--views",
    "array_pictures",
    default=None,
    metavar="PICTURES",
    help="Linear-array mode: comma-separated rectified pictures of three or more "
    "cameras on a line, left to right (a point's x falls from one view to the next), "
    "instead of --left/--right; the disparity of --reference is estimated from all.",
)
@click.option(
    "--reference",
    type=click.IntRange(min=1),
    default=None,
    metavar="K",
    help="Linear-array mode: the view whose disparity is estimated, its place in "
    "--views counted from 1 (default the middle one).",
)
@click.option(
    "--positions",
    default=None,
    metavar="P1,P2,...",
    help="Linear-array mode: each view's place on the line, comma-separated, for "
    "unequal spacing (default 0,1,2,...); disparities are per unit of these.",
)
@click.option(
    "--disparities",
    "max_disparity",
    type=int,
    default=None,
    metavar="N",
    help="Stereo-pair mode: largest disparity searched, in pixels (left x - right x; "
    "inclusive); linear-array mode: per unit of --positions (between neighbours).",
)
@click.option(
    "--min-disparity",
    type=int,
    default=None,
    help="Stereo-pair mode: smallest disparity searched, in pixels (inclusive; default 0).",
)
@view_option(
    "DERS mode: a further neighbour (repeatable): the texture video of camera NAME of "
    "the camera file, matched besides the left and right views of the configuration "
    "(in the plane sweep, or on its own with --view-combination vote)."
)
@click.option(
    "--subpixel/--integer",
    default=None,
    help="Stereo-pair mode: sub-pixel disparities, or the integer levels "
    "(default), which score better on Middlebury's bad 1.0; linear-array mode: the "
    "weighted mean of the views that agree as it is, or rounded to whole pixels per "
    "unit of --positions (default).",
)
@click.option(
    "--cost",
    type=click.Choice(COST_NAMES),
    default=None,
    help=f"Stereo-pair mode: matching cost (default {DepthOptions().cost}); census-gradient "
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
    "--disparity-of",
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
    "mode: disparity map of the left view (or --disparity-of right), PFM (float "
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
    array_pictures,
    reference,
    positions,
    max_disparity,
    min_disparity,
    views,
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
    """Estimate depth from a DERS configuration, or disparity from a stereo pair or a
    linear array of pictures.

    \b
    mvtools estimate-depth ders.cfg [Key=Value ...] [--data-dir DIR] [-o depth.yuv]
    mvtools estimate-depth --left im2.png --right im6.png --disparities 64 \\
        -o disparity.pfm --png disparity.png --png-scale 4
    mvtools estimate-depth --views v1.png,v2.png,v3.png,v4.png,v5.png --reference 3 \\
        --disparities 15 -o disparity.pfm

    DERS mode: CONFIG is a DERS configuration file, read unmodified; Key=Value items
    override it as on the DERS command line, and the options below (one per DERS key)
    override both. The depth of the center view (CenterCameraName) is estimated from
    its left and/or right neighbours (MatchDirection) with the camera parameter file
    (MPEG text, or MPEG-I JSON when its name ends in .json) by plane sweeping: depth
    planes uniform in 1/z from the disparity search range (pixels to the BaselineBasis
    view, SearchLevel steps per pixel) or from NearestSearchDepthValue,
    FarthestSearchDepthValue and NumberOfDepthSteps; any camera layout, and any number
    of further views with --view (the least cost of the views that see a point
    counts, DERS's occlusion rule; or, with ViewCombination vote, each view gives the
    depth on its own with its left-right check and each pixel takes the depth most
    views agree on, the linear-array mode's rule, better for a line of cameras). The
    output holds
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

    Linear-array mode: the pictures of cameras on a line, rectified together, give the
    disparity of --reference (per unit of --positions: between neighbours by default)
    from every view jointly, as in the epipolar-plane images of "Multiview video:
    acquisition, processing, compression, and virtual view rendering", section 1.4.3.2:
    each other view gives it with a left-right check, which drops what that view does
    not see, and each pixel takes the value most views agree on, refined by the mean of
    those that agree weighted by their squared baselines. Outputs as in the stereo-pair
    mode.

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
        "--disparity-of": pair_view,
        "--views": array_pictures,
        "--reference": reference,
        "--positions": positions,
    }
    if config is not None:
        given = [name for name, value in pair_options.items() if value is not None]
        if given:
            raise UsageError(
                f"{', '.join(given)}: stereo-pair options cannot go with a DERS configuration"
            )
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
        further_views = []
        for name, video in views.items():
            label = f"--view {name}"
            camera = loaded.command_line_camera(name, label)
            further_views.append(
                FurtherView(camera, command_line_input(label, video, data_dirs), label)
            )
        outputs = estimate_depth_loaded(
            loaded,
            config_path=Path(config),
            further_views=further_views,
            depth_bits=None if depth_bits is None else int(depth_bits),
            progress=Progress(None, "frames estimated"),
            earlier_progress=Progress(None, "earlier frames estimated"),
        )
        LOG.info("wrote %s and %s", outputs["depth"], outputs["sidecar"])
        return
    # --method, the Method key of DERS mode, chooses the method of this mode too
    method = options.pop("method") or DEFAULT_METHOD
    ders_given = [
        f"--{name.replace('_', '-')}" for name, value in options.items() if value is not None
    ]
    ders_given += ["--data-dir"] * bool(data_dirs) + ["--depth-bits"] * (depth_bits is not None)
    ders_given += ["--transposed-rotation"] * transposed_rotation
    ders_given += ["--view"] * bool(views)
    if overrides or ders_given:
        raise UsageError(
            f"{', '.join(ders_given + list(overrides))}: DERS options need a "
            "configuration file (CONFIG)"
        )
    if array_pictures is not None:
        pictures = _listed("--views", array_pictures, str)
        pair_only = {
            "--left": left,
            "--right": right,
            "--segmentation": segmentation,
            "--disparity-of": pair_view,
        }
        given = [name for name, value in pair_only.items() if value is not None]
        if given:
            raise UsageError(f"{', '.join(given)}: not in the linear-array mode (--views)")
        if len(pictures) < 3:
            raise UsageError(f"--views needs three or more pictures, got {len(pictures)}")
        reference = len(pictures) // 2 + 1 if reference is None else reference
        if reference > len(pictures):
            raise UsageError(f"--reference {reference}: --views lists {len(pictures)} pictures")
        if positions is not None:
            places, positions = positions, _listed("--positions", positions, float)
            if len(positions) != len(pictures):
                raise UsageError(
                    f"--positions gives {len(positions)} places for {len(pictures)} views"
                )
            if not all(math.isfinite(place) for place in positions):
                raise UsageError(f"--positions {places}: places must be finite numbers")
            if len(set(positions)) != len(positions):
                raise UsageError(f"--positions {places}: two views at one place")
    elif reference is not None or positions is not None:
        raise UsageError("--reference, --positions: only with --views (linear-array mode)")
    required = (("--left", left), ("--right", right)) if array_pictures is None else ()
    for name, value in (*required, ("--disparities", max_disparity), ("-o/--output", output)):
        if value is None:
            raise UsageError(
                f"{name} is required (stereo-pair mode: --left L --right R "
                "--disparities N -o OUT.pfm; linear-array mode: --views A,B,C,... "
                "--disparities N -o OUT.pfm)"
            )
    pair = DepthOptions(
        method=method,
        minimum_value_of_disparity_search_range=0 if min_disparity is None else min_disparity,
        maximum_value_of_disparity_search_range=max_disparity,
        cost=cost or DepthOptions().cost,
        subpixel=bool(subpixel),
        segment_planes=segment_planes is not False,
        segmentation=bool(segmentation),
        view=pair_view or "left",
    )
    if pair.minimum_value_of_disparity_search_range >= max_disparity:
        raise UsageError(
            f"empty disparity range: --min-disparity "
            f"{pair.minimum_value_of_disparity_search_range} must be smaller than "
            f"--disparities {max_disparity}"
        )
    # The method's own limits on the range or picture size, which options can break, are
    # ValueErrors: usage errors at the programs' edge.
    written = {
        "output": output,
        "png": png,
        "png_scale": DEFAULT_PNG_SCALE if png_scale is None else png_scale,
    }
    if array_pictures is not None:
        estimate_views_disparity(
            pictures,
            reference=reference - 1,
            positions=positions,
            options=pair,
            progress=Progress(None, "pairs matched"),
            **written,
        )
        return
    estimate_pair_disparity(left, right, options=pair, **written)


def _listed(option: str, text: str, kind: type) -> list:
    """The comma-separated values of ``option``, each converted by ``kind``."""
    try:
        return [kind(item.strip()) for item in text.split(",") if item.strip()]
    except ValueError:
        raise UsageError(f"{option} {text!r}: expected comma-separated numbers") from None
