"""``mvtools evaluate``: score a video against a reference, a disparity map against ground
truth, or a depth video against a ground-truth depth video."""

from __future__ import annotations

import functools
import json
import math
from pathlib import Path

import click

from mvtools.cli.options import (
    FINITE,
    ProgramCommand,
    depth_range_option,
    frame_range_options,
    program,
    video_format_options,
)
from mvtools.cli.progress import Progress
from mvtools.errors import UsageError, at_fault
from mvtools.io.atomic import atomic_output, output_folder_exists
from mvtools.io.guard import check_output, note_input
from mvtools.metrics.disparity import check_thresholds
from mvtools.metrics.video import VIDEO_METRICS
from mvtools.run.evaluate import (
    DEFAULT_THRESHOLDS,
    disparity_geometry,
    evaluate_depth_videos,
    evaluate_disparity,
    evaluate_videos,
    video_depth_range,
)


@click.command(name="evaluate", cls=ProgramCommand)
@click.argument("reference", type=click.Path(dir_okay=False))
@click.argument("test", type=click.Path(dir_okay=False))
@click.option(
    "--metric",
    "metrics",
    multiple=True,
    type=click.Choice(VIDEO_METRICS),
    help="Video metrics to compute (repeatable; default: all). psnr gives Y, U, V "
    "and the 6:1:1 YUV-PSNR; ssim is on luma; ivpsnr is MPEG's IV-PSNR.",
)
@video_format_options
@frame_range_options
@click.option(
    "--disparity",
    is_flag=True,
    help="Score TEST, a disparity map (PFM, or PNG/PGM divided by --disparity-scale), "
    "against REFERENCE, a ground-truth disparity map.",
)
@click.option(
    "--gt-scale",
    type=FINITE,
    default=None,
    help="Ground-truth file value / scale = disparity in pixels (known for the "
    "Middlebury sets, found from the file's path).",
)
@click.option(
    "--disparity-scale",
    type=FINITE,
    default=1.0,
    show_default=True,
    help="Disparity-map file value / scale = disparity in pixels (ignored for PFM).",
)
@click.option(
    "--nonocc",
    "nonocc_mask",
    type=click.Path(dir_okay=False),
    default=None,
    help="Non-occlusion mask, non-zero = non-occluded (Middlebury occl.png).",
)
@click.option(
    "--other-gt",
    type=click.Path(dir_okay=False),
    default=None,
    help="Ground truth of the other view: non-occluded pixels are those it confirms "
    "within 1 px (Middlebury 2005 rule).",
)
@click.option(
    "--depth",
    "depth_videos",
    is_flag=True,
    help="Score TEST, a depth video, against REFERENCE, a ground-truth depth video "
    "(MPEG depth values), as disparities towards --neighbour.",
)
@click.option(
    "--cameras",
    type=click.Path(dir_okay=False),
    default=None,
    help="--depth: the camera file of --camera and --neighbour.",
)
@click.option("--camera", default=None, help="--depth: the camera whose depth is scored.")
@click.option(
    "--neighbour",
    default=None,
    help="--depth: the camera the disparities point to (rectified cameras: "
    "disparity = fx * baseline / z).",
)
@depth_range_option(
    "--reference-depth-range",
    of="--depth's REFERENCE",
    default="its sidecar REFERENCE.json, as estimate-depth writes",
)
@depth_range_option("--test-depth-range", of="--depth's TEST", default="its sidecar TEST.json")
@click.option(
    "--threshold",
    "thresholds",
    type=FINITE,
    multiple=True,
    help="Error thresholds in pixels (repeatable; default 1 and 2).",
)
@click.option("--json", "as_json", is_flag=True, help="Print JSON instead of a table.")
@click.option(
    "--json-file",
    type=click.Path(dir_okay=False),
    default=None,
    help="Also write the scores as JSON to this file (the table still printed).",
)
@program
def command(
    reference,
    test,
    metrics,
    size,
    pix_fmt,
    start_frame,
    frame_count,
    disparity,
    gt_scale,
    disparity_scale,
    nonocc_mask,
    other_gt,
    depth_videos,
    cameras,
    camera,
    neighbour,
    reference_depth_range,
    test_depth_range,
    thresholds,
    as_json,
    json_file,
):
    """Compare TEST with REFERENCE and print the scores.

    Videos (raw YUV or Y4M): PSNR per plane, YUV-PSNR (6:1:1), SSIM and IV-PSNR per
    frame and their mean. With --disparity: the Middlebury scores (percentage of
    pixels whose error exceeds each threshold, over all known pixels and over
    non-occluded ones) and the histogram of the errors. With --depth: the same for
    every frame of two depth videos, their depths turned into disparities towards
    --neighbour.
    """
    with at_fault(UsageError, key="--threshold"):
        thresholds = check_thresholds(thresholds or DEFAULT_THRESHOLDS)
    if disparity and depth_videos:
        raise UsageError("--disparity and --depth exclude each other")
    if disparity:
        table = _disparity_table
        scoring = functools.partial(
            evaluate_disparity,
            reference,
            test,
            gt_scale=gt_scale,
            disparity_scale=disparity_scale,
            nonoccluded_mask=nonocc_mask,
            other_ground_truth=other_gt,
            thresholds=thresholds,
        )
    elif depth_videos:
        table = _depth_table
        for option, value in (
            ("--cameras", cameras),
            ("--camera", camera),
            ("--neighbour", neighbour),
        ):
            if value is None:
                raise UsageError(f"--depth needs {option}")
        scoring = functools.partial(
            evaluate_depth_videos,
            reference,
            test,
            disparity_geometry(cameras, camera, neighbour),
            reference_range=video_depth_range(
                reference, reference_depth_range, option="--reference-depth-range"
            ),
            test_range=video_depth_range(test, test_depth_range, option="--test-depth-range"),
            size=size,
            pix_fmt=pix_fmt,
            start_frame=start_frame,
            frame_count=frame_count,
            thresholds=thresholds,
            progress=Progress(None, "depth frames scored"),
        )
    else:
        table = _video_table
        scoring = functools.partial(
            evaluate_videos,
            reference,
            test,
            size=size,
            pix_fmt=pix_fmt,
            start_frame=start_frame,
            frame_count=frame_count,
            metrics=metrics or VIDEO_METRICS,
            progress=Progress(None, "frames scored"),
        )
    if json_file is not None:
        _check_json_file(json_file, (reference, test, nonocc_mask, other_gt))
    _report(scoring(), table, as_json, json_file)


def _check_json_file(json_file, inputs) -> None:
    """Refuse ``--json-file`` before the scoring, which may take long, rather than when
    it is written after it: its folder must exist and it may not name an input (the
    inputs named on the command line are noted now, before they are read)."""
    for path in inputs:
        if path is not None:
            note_input(path)
    output_folder_exists(Path(json_file).parent)
    check_output(json_file)


def _report(result: dict, table, as_json: bool, json_file) -> None:
    """Print the scores (a table, or JSON) and write their JSON to ``json_file``."""
    if json_file is not None:
        with atomic_output(json_file, "w") as handle:
            handle.write(_to_json(result) + "\n")
    click.echo(_to_json(result) if as_json else table(result))


def _video_table(result: dict) -> str:
    columns = list(result["mean"])
    lines = [
        f"reference {result['reference']}",
        f"test      {result['test']}  ({result['format']})",
        " frame" + "".join(f"{name:>10}" for name in columns),
    ]
    for row in result["frames"]:
        lines.append(f"{row['frame']:>6}" + "".join(_cell(row[name], name) for name in columns))
    lines.append("  mean" + "".join(_cell(result["mean"][name], name) for name in columns))
    return "\n".join(lines)


def _cell(value: float, name: str) -> str:
    return f"{value:>10.4f}" if name.endswith("SSIM") else f"{value:>10.2f}"


def _to_json(result: dict) -> str:
    """Strict JSON: an infinite PSNR (identical frames) is written as the string "inf"."""

    def finite(value):
        if isinstance(value, float) and not math.isfinite(value):
            return str(value)
        if isinstance(value, dict):
            return {key: finite(item) for key, item in value.items()}
        if isinstance(value, list):
            return [finite(item) for item in value]
        return value

    return json.dumps(finite(result), indent=2, allow_nan=False)


def _disparity_table(result: dict) -> str:
    thresholds = list(result["bad_all"])
    lines = [
        f"ground truth {result['ground_truth']} (value / {result['gt_scale']:g})",
        f"disparity    {result['disparity']}",
        "region     pixels" + "".join(f"{'bad ' + t:>10}" for t in thresholds),
    ]
    lines.append(
        f"{'all':<8}{result['known_pixels']:>9}"
        + "".join(f"{result['bad_all'][t]:>9.2f}%" for t in thresholds)
    )
    if result["bad_nonocc"] is not None:
        lines.append(
            f"{'nonocc':<8}{result['nonocc_pixels']:>9}"
            + "".join(f"{result['bad_nonocc'][t]:>9.2f}%" for t in thresholds)
        )
    lines.append(
        f"mean abs error {result['mean_abs_error']:.3f} px, RMS {result['rms_error']:.3f} px"
        + (
            f", {result['invalid_pixels']} known pixels without estimate"
            if result["invalid_pixels"]
            else ""
        )
    )
    return "\n".join(lines + _histogram_lines(result["histogram"]))


def _histogram_lines(histogram: dict) -> list[str]:
    return [
        "error px " + "".join(f"{name:>10}" for name in histogram["bins"]),
        "pixels % " + "".join(f"{value:>10.2f}" for value in histogram["percent"]),
    ]


def _depth_table(result: dict) -> str:
    columns = list(result["mean"])
    lines = [
        f"reference {result['reference']} (Znear, Zfar {_range(result['reference_range'])})",
        f"test      {result['test']} (Znear, Zfar {_range(result['test_range'])})",
        f"disparity towards {result['neighbour']}: fx {result['focal']:.2f} px x baseline "
        f"{result['baseline']:.4g} / z; bad t: % of pixels with an error above t px",
        " frame" + "".join(f"{name:>10}" for name in columns),
    ]
    for row in result["frames"]:
        lines.append(f"{row['frame']:>6}" + "".join(f"{row[name]:>10.3f}" for name in columns))
    lines.append("  mean" + "".join(f"{result['mean'][name]:>10.3f}" for name in columns))
    return "\n".join(lines + _histogram_lines(result["histogram"]))


def _range(values) -> str:
    return ", ".join(f"{value:g}" for value in values)
