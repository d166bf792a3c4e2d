"""``mvtools evaluate``: score a video against a reference, a disparity map against ground
truth, or a depth video against a ground-truth depth video."""

from __future__ import annotations

import functools
import itertools
import json
import math
from collections.abc import Sequence
from pathlib import Path

import click
import numpy as np

from mvtools.cli.options import (
    DEPTH,
    FINITE,
    ProgramCommand,
    frame_range_options,
    program,
    video_format_options,
)
from mvtools.cli.progress import Progress
from mvtools.datasets import nonoccluded_pixels
from mvtools.errors import ConfigError, DataError, UsageError, at_fault
from mvtools.geometry.depth import DepthCoding, check_depth_range, z_to_disparity
from mvtools.io.atomic import atomic_output, output_folder_exists
from mvtools.io.files import read_json
from mvtools.io.guard import check_output, note_input
from mvtools.io.images import read_image
from mvtools.io.inputs import frame_range, open_input_video
from mvtools.io.json_cameras import read_camera_file
from mvtools.io.middlebury import middlebury_set_for, read_ground_truth
from mvtools.io.yuv import VideoReader
from mvtools.metrics import (
    ERROR_BIN_EDGES,
    VIDEO_METRICS,
    check_thresholds,
    error_histogram,
    frame_scores,
    score_disparity,
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
@click.option(
    "--reference-range",
    nargs=2,
    type=DEPTH,
    default=None,
    metavar="ZNEAR ZFAR",
    help="--depth: Znear, Zfar of REFERENCE (default: its sidecar REFERENCE.json, "
    "as estimate-depth writes).",
)
@click.option(
    "--test-range",
    nargs=2,
    type=DEPTH,
    default=None,
    metavar="ZNEAR ZFAR",
    help="--depth: Znear, Zfar of TEST (default: its sidecar TEST.json).",
)
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
    reference_range,
    test_range,
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
        thresholds = check_thresholds(thresholds or (1.0, 2.0))
    if disparity and depth_videos:
        raise UsageError("--disparity and --depth exclude each other")
    if disparity:
        table = _disparity_table
        scoring = functools.partial(
            _evaluate_disparity,
            Path(reference),
            Path(test),
            gt_scale,
            disparity_scale,
            nonocc_mask,
            other_gt,
            thresholds,
        )
    elif depth_videos:
        table = _depth_table
        focal, baseline = _focal_and_baseline(cameras, camera, neighbour)
        scoring = functools.partial(
            _evaluate_depth,
            Path(reference),
            Path(test),
            _depth_range(reference, reference_range, "--reference-range"),
            _depth_range(test, test_range, "--test-range"),
            neighbour,
            focal,
            baseline,
            size,
            pix_fmt,
            start_frame,
            frame_count,
            thresholds,
        )
    else:
        table = _video_table
        scoring = functools.partial(
            _evaluate_video,
            reference,
            test,
            size,
            pix_fmt,
            start_frame,
            frame_count,
            metrics or VIDEO_METRICS,
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


def _evaluate_video(reference, test, size, pix_fmt, start_frame, frame_count, metrics) -> dict:
    with (
        open_input_video(reference, size, pix_fmt) as ref_video,
        open_input_video(test, size, pix_fmt) as test_video,
    ):
        fmt = ref_video.format
        if test_video.format != fmt:
            raise DataError(
                f"the test video is {test_video.format}, the reference {fmt}", path=test
            )
        frames = frame_range([ref_video, test_video], start_frame, frame_count)
        scores = score_videos(ref_video, test_video, frames, metrics)
    return {"reference": str(reference), "test": str(test), "format": str(fmt), **scores}


def score_videos(
    reference: VideoReader,
    test: VideoReader,
    frames: Sequence[int],
    metrics: Sequence[str] = VIDEO_METRICS,
) -> dict:
    """Scores of the frames of ``test`` against ``reference`` (same format), with progress
    on stderr: ``{"frames": [{"frame": index, name: score, ...}, ...], "mean": {name:
    mean over the frames}}``, names as :func:`mvtools.metrics.frame_scores` gives them."""
    progress = Progress(len(frames), "frames scored")
    rows = []
    for index in frames:
        rows.append(
            {
                "frame": index,
                **frame_scores(
                    reference.read(index),
                    test.read(index),
                    bits=reference.format.bits,
                    metrics=metrics,
                ),
            }
        )
        progress.advance()
    columns = [key for key in rows[0] if key != "frame"]
    return {
        "frames": rows,
        "mean": {key: float(np.mean([row[key] for row in rows])) for key in columns},
    }


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


def _evaluate_disparity(
    gt_path: Path,
    disparity_path: Path,
    gt_scale,
    disparity_scale,
    nonocc_mask,
    other_gt,
    thresholds,
) -> dict:
    known_set = middlebury_set_for(gt_path)
    if gt_scale is None:
        if known_set is None:
            raise UsageError(
                "the ground truth's scale is unknown: give --gt-scale "
                "(file value / scale = disparity in pixels)",
                path=gt_path,
            )
        gt_scale = known_set.scale
    ground_truth, known = read_ground_truth(gt_path, scale=gt_scale)
    estimate = _read_disparity(disparity_path, disparity_scale)
    if estimate.shape != ground_truth.shape:
        raise DataError(
            f"the disparity map is {estimate.shape[1]}x{estimate.shape[0]}, the ground "
            f"truth {ground_truth.shape[1]}x{ground_truth.shape[0]}",
            path=disparity_path,
        )
    if nonocc_mask is None and other_gt is None and known_set is not None:
        root = gt_path.resolve().parents[2]
        nonocc_mask = root / known_set.nonoccluded_mask if known_set.nonoccluded_mask else None
        other_gt = root / known_set.right_ground_truth if known_set.right_ground_truth else None
    nonoccluded = nonoccluded_pixels(
        ground_truth, known, scale=gt_scale, mask_path=nonocc_mask, other_view_path=other_gt
    )
    # the thresholds were checked: what is left is the ground truth's fault (no known
    # pixel, none non-occluded), a data error
    with at_fault(DataError, path=gt_path):
        score = score_disparity(
            estimate, ground_truth, known=known, nonoccluded=nonoccluded, thresholds=thresholds
        )
    histogram = error_histogram(estimate, ground_truth, known=known)
    return {
        "ground_truth": str(gt_path),
        "disparity": str(disparity_path),
        "gt_scale": gt_scale,
        "histogram": _histogram(histogram),
        "bad_all": {f"{t:g}": v for t, v in score.bad_all.items()},
        "bad_nonocc": None
        if score.bad_nonocc is None
        else {f"{t:g}": v for t, v in score.bad_nonocc.items()},
        "mean_abs_error": score.mean_abs_error,
        "rms_error": score.rms_error,
        "known_pixels": score.known_pixels,
        "nonocc_pixels": score.nonocc_pixels,
        "invalid_pixels": score.invalid_pixels,
    }


def _read_disparity(path: Path, scale: float) -> np.ndarray:
    values = read_image(path)
    if values.ndim != 2:
        raise DataError("a disparity map has one channel, this image has 3", path=path)
    if values.dtype.kind == "f":
        return values.astype(np.float64)
    if not scale > 0:
        raise UsageError(f"--disparity-scale must be positive, got {scale}")
    return values.astype(np.float64) / scale


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


def _histogram(counts: np.ndarray) -> dict:
    """The error histogram as the JSON output holds it: bins, pixels and percentages."""
    total = max(int(counts.sum()), 1)
    edges = ERROR_BIN_EDGES
    return {
        "bins": [_bin_name(low, high) for low, high in itertools.pairwise(edges)],
        "pixels": [int(count) for count in counts],
        "percent": [100.0 * float(count) / total for count in counts],
    }


def _bin_name(low: float, high: float) -> str:
    return f">= {low:g}" if math.isinf(high) else f"{low:g}-{high:g}"


def _histogram_lines(histogram: dict) -> list[str]:
    return [
        "error px " + "".join(f"{name:>10}" for name in histogram["bins"]),
        "pixels % " + "".join(f"{value:>10.2f}" for value in histogram["percent"]),
    ]


def _focal_and_baseline(cameras, camera: str | None, neighbour: str | None) -> tuple[float, float]:
    """fx of --camera and its distance to --neighbour, from --cameras."""
    for option, value in (("--cameras", cameras), ("--camera", camera), ("--neighbour", neighbour)):
        if value is None:
            raise UsageError(f"--depth needs {option}")
    rig = read_camera_file(cameras)
    for option, name in (("--camera", camera), ("--neighbour", neighbour)):
        if name not in rig:
            raise ConfigError(
                f"{option}: no camera {name!r} (the file has {', '.join(rig)})", path=cameras
            )
    baseline = float(np.linalg.norm(rig[camera].t - rig[neighbour].t))
    if not baseline > 0:
        raise ConfigError(
            f"cameras {camera!r} and {neighbour!r} are at the same place", path=cameras
        )
    focal = float(rig[camera].K[0, 0])
    if not focal > 0:
        raise ConfigError(
            f"camera {camera!r} has fx {focal:g}: disparities need a positive focal length",
            path=cameras,
        )
    return focal, baseline


def _depth_range(video: str, given, option: str) -> tuple[float, float]:
    """Znear, Zfar given on the command line, or else from the video's JSON sidecar."""
    if given is not None:
        with at_fault(UsageError, key=option):
            check_depth_range(*given)
        return tuple(given)
    sidecar = Path(str(video) + ".json")
    if not sidecar.exists():
        raise UsageError(
            f"the depth range is unknown: give {option} ZNEAR ZFAR (no {sidecar})", path=video
        )
    document = read_json(sidecar)
    if not isinstance(document, dict) or "NearestDepthValue" not in document:
        raise ConfigError("no NearestDepthValue in the sidecar", path=sidecar)
    if document.get("DepthType", 0) != 0:
        raise DataError(
            "depth from the world origin (DepthType 1) is not scored; "
            "give depth along the camera's axis",
            path=sidecar,
        )
    far = document.get("FarthestDepthValue")
    return float(document["NearestDepthValue"]), math.inf if far is None else float(far)


def _evaluate_depth(
    reference: Path,
    test: Path,
    reference_range,
    test_range,
    neighbour: str,
    focal: float,
    baseline: float,
    size,
    pix_fmt,
    start_frame,
    frame_count,
    thresholds,
) -> dict:
    ranges = {"reference": reference_range, "test": test_range}
    with (
        open_input_video(reference, size, pix_fmt) as ref_video,
        open_input_video(test, size, pix_fmt) as test_video,
    ):
        if (test_video.format.width, test_video.format.height) != (
            ref_video.format.width,
            ref_video.format.height,
        ):
            raise DataError(
                f"the test video is {test_video.format}, the reference {ref_video.format}",
                path=test,
            )
        frames = frame_range([ref_video, test_video], start_frame, frame_count)
        progress = Progress(len(frames), "depth frames scored")
        rows, histogram = [], 0
        for index in frames:
            truth, estimate = (
                z_to_disparity(
                    DepthCoding(ranges[name], video.format.bits).z(video.read(index)[0]),
                    focal,
                    baseline,
                )
                for name, video in (("reference", ref_video), ("test", test_video))
            )
            # the thresholds were checked: what is left is the frame's fault (no pixel of
            # known ground truth), a data error
            with at_fault(DataError, path=reference, prefix=f"frame {index}: "):
                score = score_disparity(estimate, truth, thresholds=thresholds)
            rows.append(
                {
                    "frame": index,
                    **{f"bad {t:g}": v for t, v in score.bad_all.items()},
                    "mean abs": score.mean_abs_error,
                    "RMS": score.rms_error,
                }
            )
            histogram = histogram + error_histogram(estimate, truth)
            progress.advance()
    columns = [key for key in rows[0] if key != "frame"]
    return {
        "reference": str(reference),
        "test": str(test),
        "reference_range": list(reference_range),
        "test_range": list(test_range),
        "neighbour": neighbour,
        "focal": focal,
        "baseline": baseline,
        "frames": rows,
        "mean": {key: float(np.mean([row[key] for row in rows])) for key in columns},
        "histogram": _histogram(histogram),
    }


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
