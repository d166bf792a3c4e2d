"""``mvtools colorcorrect``: make the colours of the views of an array agree."""

from __future__ import annotations

from pathlib import Path

import click
import numpy as np

from mvtools.cli.options import (
    ProgramCommand,
    depth_range_option,
    depth_video_option,
    frame_range_options,
    program,
    transposed_rotation_option,
    video_format_options,
    view_option,
)
from mvtools.cli.progress import Progress
from mvtools.color.correct import SPACES
from mvtools.errors import UsageError
from mvtools.io.camera_files import read_camera_file
from mvtools.io.cameras import get_camera
from mvtools.io.color_charts import DEFAULT_CHART, read_colorchecker
from mvtools.io.images import IMAGE_EXTENSIONS
from mvtools.run.colorcorrect import CORRECTION_TARGETS, ColourCorrectionOptions, correct_colours


@click.command(name="colorcorrect", cls=ProgramCommand)
@view_option(
    "A view to correct: the texture video of camera NAME (repeatable, in the array's order).",
    required=True,
)
@click.option(
    "--reference",
    default=None,
    metavar="NAME",
    help="The view whose colours the others take (default: the middle view).",
)
@click.option(
    "--target",
    type=click.Choice(CORRECTION_TARGETS),
    default="reference",
    show_default=True,
    help="reference: every view takes the reference's colours; average: every view, "
    "the reference too, takes the average colour profile of all views; chart: "
    "every view takes the reference colours of the ColorChecker it shows.",
)
@click.option(
    "--chart-reference",
    type=click.Path(dir_okay=False),
    default=None,
    help="With --target chart: the chart's reference values, colour-science's "
    "CCS_COLOURCHECKERS JSON file.",
)
@click.option(
    "--chart-name",
    default=DEFAULT_CHART,
    show_default=True,
    help="The chart's entry in --chart-reference.",
)
@click.option(
    "--chart-corners",
    "chart_corners",
    multiple=True,
    nargs=2,
    metavar="NAME X,Y,X,Y,X,Y,X,Y",
    help="Corners of the chart's patch area in a view (top-left, top-right, "
    "bottom-right, bottom-left of the upright chart); without, the chart is "
    "detected.",
)
@click.option(
    "--chart-model",
    type=click.Choice(("3x3", "4x3")),
    default="3x3",
    show_default=True,
    help="The colour matrix: linear (3x3) or affine (4x3), after a per-channel "
    "tone curve fitted to the chart's grey patches.",
)
@click.option(
    "--cameras",
    "camera_file",
    type=click.Path(dir_okay=False),
    default=None,
    help="Camera parameter file (MPEG text or JSON). With --depth, tables come from "
    "the pixels that show the same scene point in both views; without, the "
    "histograms are taken over the field of view both cameras share.",
)
@depth_video_option(
    "Depth map video of a view (MPEG convention, repeatable). Without depth "
    "for a view and the reference, their cumulative histograms are matched."
)
@depth_range_option(default="the cameras' Depth_range in an MPEG-I JSON camera file")
@click.option(
    "--space",
    type=click.Choice(SPACES),
    default="rgb",
    show_default=True,
    help="Channels the tables work on: RGB (a camera's response is per sensor "
    "channel) or the Y, U, V planes as they are (no resampling of chroma).",
)
@click.option(
    "--estimate-frames",
    type=click.IntRange(min=1),
    default=1,
    show_default=True,
    help="Frames whose samples estimate the tables.",
)
@click.option(
    "--estimate-from",
    type=click.IntRange(min=0),
    default=None,
    help="First of those frames (default: the first frame processed). Chunks of a "
    "sequence corrected in parallel give one run's bytes when they all estimate "
    "from the same frames.",
)
@click.option(
    "-o",
    "--out-dir",
    required=True,
    type=click.Path(file_okay=False),
    help="Folder for the corrected videos (named as their inputs) and each view's "
    "tables, NAME.lut.txt and NAME.cube.",
)
@video_format_options
@frame_range_options
@transposed_rotation_option
@program
def command(
    views,
    reference,
    target,
    chart_reference,
    chart_name,
    chart_corners,
    chart_model,
    camera_file,
    depths,
    depth_range,
    space,
    estimate_frames,
    estimate_from,
    out_dir,
    size,
    pix_fmt,
    start_frame,
    frame_count,
    transposed_rotation,
):
    """Per-channel look-up tables that make the views' colours agree (the chapter's eq. 1.18),
    estimated from pixels that project onto each other (given cameras and depth maps)
    or else by cumulative-histogram matching, then applied to every frame.

    The tables are monotonic and smooth, estimated from the first --estimate-frames
    frames and applied to all, one frame at a time.
    """
    names = list(views)
    out = Path(out_dir)
    outputs = {}
    for name, path in views.items():
        for other, corrected in outputs.items():
            if corrected.name == Path(path).name:
                raise UsageError(
                    f"--view {name}: the same file name as --view {other}: their "
                    "corrected videos would share one name in -o; rename one",
                    path=path,
                )
        outputs[name] = out / Path(path).name
    estimation = {"estimate_frames": estimate_frames, "estimate_from": estimate_from}
    video_frames = {
        "size": size,
        "pix_fmt": pix_fmt,
        "start_frame": start_frame,
        "frame_count": frame_count,
        "progress": Progress(None, "frames corrected"),
    }
    if target == "chart":
        if chart_reference is None:
            raise UsageError(
                "--target chart needs --chart-reference: colour-science's "
                "CCS_COLOURCHECKERS JSON file of reference values"
            )
        if space != "rgb":
            raise UsageError("--target chart corrects RGB: leave --space at rgb")
        corners = _chart_corners(dict(chart_corners), names)
        options = ColourCorrectionOptions(
            target="chart",
            chart=read_colorchecker(chart_reference, chart=chart_name),
            chart_corners=corners,
            chart_model=chart_model,
            **estimation,
        )
        result = correct_colours(views, outputs, options, **video_frames)
        lines = [
            f"{'view':12s} {'patches':>8s} {'mean dE00 before':>17s} {'after':>7s} {'max after':>10s}"
        ]
        for view in result.views:
            lines.append(
                f"{view.name:12s} {int(view.chart.used.sum()):8d} {view.before:17.2f} "
                f"{view.after:7.2f} {view.chart.delta_e.max():10.2f}"
            )
        click.echo("\n".join(lines))
        return
    if len(views) < 2:
        raise UsageError("colour correction needs at least two views (or --target chart)")
    if reference is not None and reference not in names:
        raise UsageError(f"--reference {reference}: no such view (views: {', '.join(names)})")
    unknown = sorted(set(depths) - set(names))
    if unknown:
        raise UsageError(f"--depth {unknown[0]}: no such view (views: {', '.join(names)})")
    options = ColourCorrectionOptions(reference=reference, target=target, space=space, **estimation)
    images = [Path(path).suffix.lower() in IMAGE_EXTENSIONS for path in views.values()]
    if any(images):
        if not all(images) or depths or camera_file:
            raise UsageError(
                "views given as images are matched by their histograms: give "
                "only images, without --depth and --cameras"
            )
        result = correct_colours(views, outputs, options)
        lines = [f"{'view':12s} mean RGB difference to {result.reference}: before   after"]
        lines += [
            f"{view.name:12s} {'':>33s}{view.before:7.2f} {view.after:7.2f}"
            for view in result.views
        ]
        click.echo("\n".join(lines))
        return
    result = correct_colours(
        views,
        outputs,
        options,
        cameras=_cameras(camera_file, depths, names, transposed_rotation),
        depths=depths,
        depth_range=depth_range,
        **video_frames,
    )
    lines = [f"{'view':12s} {'method':16s} before   after"]
    lines += [
        f"{view.name:12s} {result.method:16s} {view.before:7.2f} {view.after:7.2f}  {view.measure}"
        for view in result.views
    ]
    click.echo("\n".join(lines))


def _chart_corners(corners_of, names):
    unknown = sorted(set(corners_of) - set(names))
    if unknown:
        raise UsageError(f"--chart-corners {unknown[0]}: no such view (views: {', '.join(names)})")
    return {name: _parse_corners(name, text) for name, text in corners_of.items()}


def _parse_corners(name: str, text: str) -> np.ndarray:
    try:
        values = [float(value) for value in text.split(",")]
    except ValueError:
        values = []
    if len(values) != 8:
        raise UsageError(f"--chart-corners {name} {text}: give eight numbers X,Y,X,Y,X,Y,X,Y")
    return np.array(values).reshape(4, 2)


def _cameras(camera_file, depth_of, names, transposed_rotation):
    if camera_file is None:
        if depth_of:
            raise UsageError("--depth needs --cameras: the camera parameter file of the views")
        return None
    cameras = read_camera_file(camera_file, transposed_rotation=transposed_rotation)
    return {name: get_camera(cameras, name, path=camera_file) for name in names}
