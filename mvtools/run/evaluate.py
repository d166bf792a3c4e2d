"""Scores of a result against the truth: the run functions of ``mvtools evaluate``.

:func:`evaluate_videos` scores a video against a reference (PSNR, SSIM, IV-PSNR per
frame, :func:`score_videos` on opened readers), :func:`evaluate_disparity` a disparity
map against a Middlebury ground truth, and :func:`evaluate_depth_videos` a depth video
against a ground-truth depth video, their depths seen as disparities towards a
neighbouring camera (:class:`DisparityGeometry`). Each returns the dict the program
prints as JSON. The metrics are imported when a run starts, so this module is cheap
to import.
"""

from __future__ import annotations

import itertools
import math
import os
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from mvtools.errors import ConfigError, DataError, UsageError, at_fault
from mvtools.geometry.depth import DepthCoding, check_depth_range, z_to_disparity
from mvtools.io.camera_files import read_camera_file
from mvtools.io.files import read_json
from mvtools.io.images import read_image
from mvtools.io.inputs import frame_range, open_input_video
from mvtools.io.middlebury import middlebury_set_for, read_ground_truth
from mvtools.io.yuv import VideoReader
from mvtools.metrics.disparity import (
    ERROR_BIN_EDGES,
    check_thresholds,
    error_histogram,
    score_disparity,
)
from mvtools.metrics.video import VIDEO_METRICS, frame_scores
from mvtools.run.stream import ProgressCallback, stream_frames

#: Error thresholds in pixels when none are given: the Middlebury evaluation's.
DEFAULT_THRESHOLDS = (1.0, 2.0)


# --------------------------------------------------------------------------- videos


def evaluate_videos(
    reference: str | os.PathLike,
    test: str | os.PathLike,
    *,
    size: tuple[int, int] | None = None,
    pix_fmt: str | None = None,
    start_frame: int = 0,
    frame_count: int | None = None,
    metrics: Sequence[str] = VIDEO_METRICS,
    progress: ProgressCallback | None = None,
) -> dict:
    """Score the video ``test`` against the video ``reference``, frame by frame, as
    ``mvtools evaluate REFERENCE TEST`` does.

    Parameters
    ----------
    reference, test : path
        Raw YUV or Y4M videos of one format; ``"-"`` reads Y4M from standard input.
    size, pix_fmt : optional
        Picture size (width, height) and ffmpeg pixel format of raw YUV files whose
        names do not carry them (:func:`mvtools.io.inputs.open_input_video`).
    start_frame, frame_count : int, optional
        The frames scored: ``frame_count`` (default all) from ``start_frame``.
    metrics : sequence of str
        Names from :data:`mvtools.metrics.video.VIDEO_METRICS`.
    progress : callable, optional
        ``progress(done, total)`` after each frame.

    Returns
    -------
    dict
        ``reference``, ``test`` (as given), ``format`` (the videos'), and the
        ``frames`` and ``mean`` of :func:`score_videos`.

    Raises
    ------
    DataError
        The videos differ in format.
    UsageError
        ``start_frame`` is past the end of a video.
    """
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
        scores = score_videos(ref_video, test_video, frames, metrics, progress=progress)
    return {"reference": str(reference), "test": str(test), "format": str(fmt), **scores}


def score_videos(
    reference: VideoReader,
    test: VideoReader,
    frames: range,
    metrics: Sequence[str] = VIDEO_METRICS,
    *,
    progress: ProgressCallback | None = None,
) -> dict:
    """Scores of the frames of ``test`` against ``reference`` (same format).

    Parameters
    ----------
    reference, test : VideoReader
        Or any objects with ``read(index)`` giving a frame's planes; the bit depth is
        ``reference.format.bits``.
    frames : range
        The frames scored, at least one.
    metrics : sequence of str
        Names from :data:`mvtools.metrics.video.VIDEO_METRICS`.
    progress : callable, optional
        ``progress(done, total)`` after each frame.

    Returns
    -------
    dict
        ``{"frames": [{"frame": index, name: score, ...}, ...], "mean": {name: mean
        over the frames}}``, names as :func:`mvtools.metrics.video.frame_scores` gives
        them (an identical frame's PSNR is infinite, and so is then the mean).
    """
    bits = reference.format.bits
    rows = []

    def score(index: int, reference_frame, test_frame) -> None:
        scores = frame_scores(reference_frame, test_frame, bits=bits, metrics=metrics)
        rows.append({"frame": index, **scores})

    stream_frames(frames, score, readers=[reference, test], progress=progress)
    return {"frames": rows, "mean": _column_means(rows)}


def _column_means(rows: list[dict]) -> dict[str, float]:
    """The mean over the rows of each score (every key but ``frame``)."""
    columns = [key for key in rows[0] if key != "frame"]
    return {key: float(np.mean([row[key] for row in rows])) for key in columns}


# --------------------------------------------------------------------------- disparity maps


def evaluate_disparity(
    ground_truth: str | os.PathLike,
    disparity: str | os.PathLike,
    *,
    gt_scale: float | None = None,
    disparity_scale: float = 1.0,
    nonoccluded_mask: str | os.PathLike | None = None,
    other_ground_truth: str | os.PathLike | None = None,
    thresholds: Sequence[float] = DEFAULT_THRESHOLDS,
) -> dict:
    """Score a disparity map against a Middlebury ground truth, as ``mvtools evaluate
    --disparity`` does: the percentage of pixels whose error exceeds each threshold,
    over the known pixels and over the non-occluded ones, the mean absolute and RMS
    errors and the histogram of the errors (Scharstein and Szeliski, "A taxonomy and
    evaluation of dense two-frame stereo correspondence algorithms", IJCV 2002).

    Parameters
    ----------
    ground_truth : path
        The ground-truth disparity map (file value / ``gt_scale`` = disparity in
        pixels, 0 where unknown).
    disparity : path
        The map scored: PFM (disparities in pixels) or PNG/PGM (file value /
        ``disparity_scale``).
    gt_scale : float, optional
        Default: the scale of the Middlebury set that ``ground_truth`` belongs to,
        found from its path (:func:`mvtools.io.middlebury.middlebury_set_for`).
    disparity_scale : float
        Positive; ignored for PFM.
    nonoccluded_mask, other_ground_truth : path, optional
        The non-occluded pixels: those of a mask (non-zero = non-occluded, the 2003
        sets' ``occl.png``), or those the other view's ground truth confirms within
        1 px (the 2005 rule). Default, when neither is given: the set's own, for a
        Middlebury set; none otherwise.
    thresholds : sequence of float
        Error thresholds in pixels (:func:`mvtools.metrics.disparity.check_thresholds`).

    Returns
    -------
    dict
        ``ground_truth``, ``disparity``, ``gt_scale``, ``histogram`` (bins, pixels,
        percent), ``bad_all`` and ``bad_nonocc`` (None without non-occluded pixels:
        threshold as ``f"{t:g}"`` to percent), ``mean_abs_error``, ``rms_error``,
        ``known_pixels``, ``nonocc_pixels``, ``invalid_pixels``.

    Raises
    ------
    UsageError
        The ground truth's scale is unknown, or ``disparity_scale`` is not positive.
    DataError
        The map is not one channel, or differs in size from the ground truth; the
        ground truth knows no pixel.
    ValueError
        ``thresholds`` are empty or negative.
    """
    # the non-occluded pixels of a set are read with its helpers, which load OpenCV
    from mvtools.datasets import nonoccluded_pixels

    thresholds = check_thresholds(thresholds)
    gt_path, disparity_path = Path(ground_truth), Path(disparity)
    known_set = middlebury_set_for(gt_path)
    if gt_scale is None:
        if known_set is None:
            raise UsageError(
                "the ground truth's scale is unknown: give --gt-scale "
                "(file value / scale = disparity in pixels)",
                path=gt_path,
            )
        gt_scale = known_set.scale
    truth, known = read_ground_truth(gt_path, scale=gt_scale)
    estimate = _read_disparity(disparity_path, disparity_scale)
    if estimate.shape != truth.shape:
        raise DataError(
            f"the disparity map is {estimate.shape[1]}x{estimate.shape[0]}, the ground "
            f"truth {truth.shape[1]}x{truth.shape[0]}",
            path=disparity_path,
        )
    if nonoccluded_mask is None and other_ground_truth is None and known_set is not None:
        root = gt_path.resolve().parents[2]
        if known_set.nonoccluded_mask:
            nonoccluded_mask = root / known_set.nonoccluded_mask
        if known_set.right_ground_truth:
            other_ground_truth = root / known_set.right_ground_truth
    nonoccluded = nonoccluded_pixels(
        truth,
        known,
        scale=gt_scale,
        mask_path=nonoccluded_mask,
        other_view_path=other_ground_truth,
    )
    # the thresholds were checked: what is left is the ground truth's fault (no known
    # pixel, none non-occluded), a data error
    with at_fault(DataError, path=gt_path):
        score = score_disparity(
            estimate, truth, known=known, nonoccluded=nonoccluded, thresholds=thresholds
        )
    histogram = error_histogram(estimate, truth, known=known)
    return {
        "ground_truth": str(gt_path),
        "disparity": str(disparity_path),
        "gt_scale": gt_scale,
        "histogram": _histogram(histogram),
        "bad_all": _by_threshold(score.bad_all),
        "bad_nonocc": None if score.bad_nonocc is None else _by_threshold(score.bad_nonocc),
        "mean_abs_error": score.mean_abs_error,
        "rms_error": score.rms_error,
        "known_pixels": score.known_pixels,
        "nonocc_pixels": score.nonocc_pixels,
        "invalid_pixels": score.invalid_pixels,
    }


def _read_disparity(path: Path, scale: float) -> np.ndarray:
    """A disparity map in pixels: PFM as it is, an integer image divided by ``scale``."""
    values = read_image(path)
    if values.ndim != 2:
        raise DataError("a disparity map has one channel, this image has 3", path=path)
    if values.dtype.kind == "f":
        return values.astype(np.float64)
    if not scale > 0:
        raise UsageError(f"--disparity-scale must be positive, got {scale}")
    return values.astype(np.float64) / scale


def _by_threshold(percentages: dict[float, float]) -> dict[str, float]:
    return {f"{t:g}": value for t, value in percentages.items()}


def _histogram(counts: np.ndarray) -> dict:
    """The error histogram as the result holds it: bins, pixels and percentages."""
    total = max(int(counts.sum()), 1)
    return {
        "bins": [_bin_name(low, high) for low, high in itertools.pairwise(ERROR_BIN_EDGES)],
        "pixels": [int(count) for count in counts],
        "percent": [100.0 * float(count) / total for count in counts],
    }


def _bin_name(low: float, high: float) -> str:
    return f">= {low:g}" if math.isinf(high) else f"{low:g}-{high:g}"


# --------------------------------------------------------------------------- depth videos


@dataclass(frozen=True)
class DisparityGeometry:
    """How a camera's depths become disparities towards a neighbouring camera: for
    rectified cameras, disparity = ``focal`` * ``baseline`` / z
    (:func:`mvtools.geometry.depth.z_to_disparity`).

    Attributes
    ----------
    neighbour : str
        The camera the disparities point to (named in the result).
    focal : float
        fx of the camera whose depth is scored, in pixels; positive.
    baseline : float
        The distance between the two cameras' centres, in the depths' unit; positive.
    """

    neighbour: str
    focal: float
    baseline: float


def disparity_geometry(
    cameras: str | os.PathLike, camera: str, neighbour: str
) -> DisparityGeometry:
    """The :class:`DisparityGeometry` of ``camera`` towards ``neighbour``, two cameras
    of the camera file ``cameras`` (MPEG text, or MPEG-I JSON by its name).

    Raises
    ------
    ConfigError
        The file lacks a camera, the two are at the same place, or ``camera``'s fx is
        not positive.
    """
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
    return DisparityGeometry(neighbour, focal, baseline)


def video_depth_range(
    video: str | os.PathLike, given: Sequence[float] | None = None, *, option: str
) -> tuple[float, float]:
    """Znear, Zfar of a depth video: ``given``, or else its JSON sidecar's
    (``VIDEO.json``, as ``mvtools estimate-depth`` writes it).

    ``option`` names the place that gives the range instead (``"--test-depth-range"``), in
    the error of a bad ``given`` range or of a missing sidecar.

    Raises
    ------
    UsageError
        ``given`` is no depth range, or it is None and the sidecar does not exist.
    ConfigError
        The sidecar has no NearestDepthValue.
    DataError
        The sidecar's depth is from the world origin (DepthType 1).
    """
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


def evaluate_depth_videos(
    reference: str | os.PathLike,
    test: str | os.PathLike,
    geometry: DisparityGeometry,
    *,
    reference_range: tuple[float, float],
    test_range: tuple[float, float],
    size: tuple[int, int] | None = None,
    pix_fmt: str | None = None,
    start_frame: int = 0,
    frame_count: int | None = None,
    thresholds: Sequence[float] = DEFAULT_THRESHOLDS,
    progress: ProgressCallback | None = None,
) -> dict:
    """Score the depth video ``test`` against the ground-truth depth video
    ``reference``, frame by frame, as ``mvtools evaluate --depth`` does: both frames'
    depths become disparities (``geometry``) and are scored as a disparity map with
    every pixel known (:func:`mvtools.metrics.disparity.score_disparity`).

    Parameters
    ----------
    reference, test : path
        Depth videos (MPEG depth values in the luma) of one size; their bit depths
        may differ.
    geometry : DisparityGeometry
    reference_range, test_range : (float, float)
        Znear, Zfar of each video (:func:`video_depth_range`).
    size, pix_fmt, start_frame, frame_count : optional
        As :func:`evaluate_videos`.
    thresholds : sequence of float
        Error thresholds in pixels.
    progress : callable, optional
        ``progress(done, total)`` after each frame.

    Returns
    -------
    dict
        ``reference``, ``test``, ``reference_range``, ``test_range``, ``neighbour``,
        ``focal``, ``baseline``; ``frames`` (per frame: ``bad t`` percentages for each
        threshold t, ``mean abs`` and ``RMS`` errors in pixels) and their ``mean``;
        the ``histogram`` of the errors over all the frames.

    Raises
    ------
    DataError
        The videos differ in size.
    ValueError
        ``thresholds`` are empty or negative; a range is no depth range.
    """
    thresholds = check_thresholds(thresholds)
    reference, test = Path(reference), Path(test)
    with (
        open_input_video(reference, size, pix_fmt) as ref_video,
        open_input_video(test, size, pix_fmt) as test_video,
    ):
        if test_video.format.size != ref_video.format.size:
            raise DataError(
                f"the test video is {test_video.format}, the reference {ref_video.format}",
                path=test,
            )
        frames = frame_range([ref_video, test_video], start_frame, frame_count)
        codings = [
            DepthCoding(reference_range, ref_video.format.bits),
            DepthCoding(test_range, test_video.format.bits),
        ]
        rows, histograms = [], []

        def score(index: int, reference_frame, test_frame) -> None:
            truth, estimate = (
                z_to_disparity(coding.z(frame[0]), geometry.focal, geometry.baseline)
                for coding, frame in zip(codings, (reference_frame, test_frame))
            )
            # the thresholds were checked: what is left is the frame's fault (no pixel of
            # known ground truth), a data error
            with at_fault(DataError, path=reference, prefix=f"frame {index}: "):
                frame_score = score_disparity(estimate, truth, thresholds=thresholds)
            rows.append(
                {
                    "frame": index,
                    **{f"bad {t:g}": v for t, v in frame_score.bad_all.items()},
                    "mean abs": frame_score.mean_abs_error,
                    "RMS": frame_score.rms_error,
                }
            )
            histograms.append(error_histogram(estimate, truth))

        stream_frames(frames, score, readers=[ref_video, test_video], progress=progress)
    return {
        "reference": str(reference),
        "test": str(test),
        "reference_range": list(reference_range),
        "test_range": list(test_range),
        "neighbour": geometry.neighbour,
        "focal": geometry.focal,
        "baseline": geometry.baseline,
        "frames": rows,
        "mean": _column_means(rows),
        "histogram": _histogram(np.sum(histograms, axis=0)),
    }
