"""Scoring of disparity maps against ground truth, Middlebury style.

D. Scharstein and R. Szeliski, "A taxonomy and evaluation of dense two-frame
stereo correspondence algorithms", IJCV 47(1/2/3):7-42, 2002: a pixel is "bad"
when its disparity error exceeds a threshold (1 or 2 pixels); the score is the
percentage of bad pixels over all pixels with known ground truth ("all") and over
the non-occluded ones ("nonocc").

Ground-truth convention: a disparity of 0 (or NaN) means "unknown", as in the
Middlebury files.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class DisparityScore:
    """Scores of one disparity map.

    Attributes
    ----------
    bad_all : dict of float to float
        Threshold (pixels) -> percentage of known pixels whose absolute error
        exceeds it.
    bad_nonocc : dict of float to float or None
        The same over known, non-occluded pixels; None when no non-occlusion mask
        was given.
    mean_abs_error, rms_error : float
        Mean absolute and root-mean-square error (pixels) over the known pixels
        that have a finite estimate.
    known_pixels : int
        Number of pixels scored for "all".
    nonocc_pixels : int or None
        Number of pixels scored for "nonocc".
    invalid_pixels : int
        Known pixels whose estimate is not finite (NaN, inf); they count as bad
        at every threshold and are left out of the mean and RMS errors.
    """

    bad_all: dict[float, float]
    bad_nonocc: dict[float, float] | None
    mean_abs_error: float
    rms_error: float
    known_pixels: int
    nonocc_pixels: int | None
    invalid_pixels: int


def known_ground_truth(ground_truth: np.ndarray) -> np.ndarray:
    """Pixels whose ground truth is known: finite and non-zero (0 = unknown)."""
    ground_truth = np.asarray(ground_truth)
    return np.isfinite(ground_truth) & (ground_truth != 0)


def check_thresholds(thresholds: Sequence[float]) -> tuple[float, ...]:
    """The error thresholds of :func:`score_disparity` as floats.

    Raises
    ------
    ValueError
        Unless ``thresholds`` holds at least one value and every value is >= 0 (``inf``
        counts only the pixels without an estimate; NaN would count none).

    Examples
    --------
    >>> check_thresholds([1, 2])
    (1.0, 2.0)
    """
    thresholds = tuple(float(t) for t in thresholds)
    # written so that NaN fails: no comparison with it is true
    if not thresholds or not all(t >= 0 for t in thresholds):
        raise ValueError(
            f"thresholds must be a non-empty list of values >= 0, got "
            f"{', '.join(f'{t:g}' for t in thresholds) or 'none'}"
        )
    return thresholds


def score_disparity(
    disparity: np.ndarray,
    ground_truth: np.ndarray,
    *,
    known: np.ndarray | None = None,
    nonoccluded: np.ndarray | None = None,
    thresholds: Sequence[float] = (1.0, 2.0),
) -> DisparityScore:
    """Percentages of bad pixels of a disparity map, over all and non-occluded pixels.

    A pixel is bad at threshold ``t`` when ``|disparity - ground_truth| > t``
    (strictly greater), or when its estimate is not finite. Following the
    Middlebury protocol as the data README states it, every pixel with known
    ground truth is scored: no border or other region is excluded beyond what
    ``known`` and ``nonoccluded`` say (the 2001 Tsukuba ground truth already
    marks its 18-pixel border unknown).

    Parameters
    ----------
    disparity : ndarray, shape (H, W)
        Estimated disparity in pixels (any real dtype).
    ground_truth : ndarray, shape (H, W)
        True disparity in pixels.
    known : ndarray of bool, shape (H, W), optional
        Pixels with known ground truth; by default those where ``ground_truth``
        is finite and non-zero.
    nonoccluded : ndarray of bool, shape (H, W), optional
        Non-occluded pixels; "nonocc" scores use ``known & nonoccluded``.
    thresholds : sequence of float
        Error thresholds in pixels (:func:`check_thresholds`).

    Returns
    -------
    DisparityScore
    """
    disparity = np.asarray(disparity, dtype=np.float64)
    ground_truth = np.asarray(ground_truth, dtype=np.float64)
    if disparity.ndim != 2:
        raise ValueError(f"disparity must be 2-D, got shape {disparity.shape}")
    if disparity.shape != ground_truth.shape:
        raise ValueError(
            f"disparity shape {disparity.shape} differs from ground-truth "
            f"shape {ground_truth.shape}"
        )
    thresholds = check_thresholds(thresholds)
    known = (
        _mask(known, disparity.shape, "known")
        if known is not None
        else known_ground_truth(ground_truth)
    )
    known = known & np.isfinite(ground_truth)
    if not known.any():
        raise ValueError("no pixel has known ground truth")

    with np.errstate(invalid="ignore"):  # inf - inf where both are unusable
        error = np.abs(disparity - ground_truth)
    finite = np.isfinite(error)
    # A missing estimate is wrong whatever the threshold: score it as infinite error.
    error = np.where(finite, error, np.inf)

    def bad_percentages(region: np.ndarray) -> dict[float, float]:
        region_error = error[region]
        return {
            t: float(100.0 * np.count_nonzero(region_error > t) / region_error.size)
            for t in thresholds
        }

    bad_nonocc = None
    nonocc_pixels = None
    if nonoccluded is not None:
        nonocc_region = known & _mask(nonoccluded, disparity.shape, "nonoccluded")
        if not nonocc_region.any():
            raise ValueError("no known pixel is non-occluded")
        bad_nonocc = bad_percentages(nonocc_region)
        nonocc_pixels = int(np.count_nonzero(nonocc_region))

    valid_error = error[known & finite]
    return DisparityScore(
        bad_all=bad_percentages(known),
        bad_nonocc=bad_nonocc,
        mean_abs_error=float(valid_error.mean()) if valid_error.size else float("nan"),
        rms_error=float(np.sqrt(np.mean(np.square(valid_error))))
        if valid_error.size
        else float("nan"),
        known_pixels=int(np.count_nonzero(known)),
        nonocc_pixels=nonocc_pixels,
        invalid_pixels=int(np.count_nonzero(known & ~finite)),
    )


#: Bin edges (pixels) of :func:`error_histogram`: fine where good matchers are, coarse
#: beyond, the last bin open (it also takes the pixels without an estimate).
ERROR_BIN_EDGES = (0.0, 0.25, 0.5, 1.0, 2.0, 4.0, 8.0, np.inf)


def error_histogram(
    disparity: np.ndarray,
    ground_truth: np.ndarray,
    *,
    known: np.ndarray | None = None,
    edges: Sequence[float] = ERROR_BIN_EDGES,
) -> np.ndarray:
    """How many known pixels have an absolute disparity error in each bin.

    Bin ``i`` holds the errors ``edges[i] <= error < edges[i + 1]``; an estimate that
    is not finite counts in the last bin, so the counts add up to the known pixels.

    Parameters
    ----------
    disparity, ground_truth : ndarray, shape (H, W)
        Estimated and true disparity in pixels.
    known : ndarray of bool, shape (H, W), optional
        Pixels with known ground truth; by default where ``ground_truth`` is finite and
        non-zero.
    edges : sequence of float
        Increasing bin edges from 0; the last may be ``inf``.

    Returns
    -------
    ndarray of int64, shape (len(edges) - 1,)
    """
    disparity = np.asarray(disparity, dtype=np.float64)
    ground_truth = np.asarray(ground_truth, dtype=np.float64)
    if disparity.ndim != 2 or disparity.shape != ground_truth.shape:
        raise ValueError(
            f"need two 2-D maps of one shape, got {disparity.shape} and {ground_truth.shape}"
        )
    edges = np.asarray(edges, dtype=np.float64)
    if edges.size < 2 or edges[0] != 0 or np.any(np.diff(edges) <= 0):
        raise ValueError(f"edges must increase from 0 with at least two values, got {edges}")
    known = (
        _mask(known, disparity.shape, "known")
        if known is not None
        else known_ground_truth(ground_truth)
    )
    with np.errstate(invalid="ignore"):
        error = np.abs(disparity - ground_truth)[known & np.isfinite(ground_truth)]
    error = np.where(np.isfinite(error), error, np.inf)
    # searchsorted puts error e in bin i with edges[i] <= e < edges[i+1]; inf goes last
    bins = np.minimum(np.searchsorted(edges, error, side="right") - 1, edges.size - 2)
    return np.bincount(bins, minlength=edges.size - 1).astype(np.int64)


def nonoccluded_from_other_view(
    gt_left: np.ndarray, gt_right: np.ndarray, *, tolerance: float = 1.0
) -> np.ndarray:
    """Non-occluded pixels of the left view, by checking the right view's ground truth.

    The rule stated for the Middlebury 2005 sets: a left pixel ``(x, y)`` with
    disparity ``d`` is non-occluded when its right-view correspondent
    ``x_r = round(x - d)`` (halves rounded up) lies inside the image, has known
    ground truth and agrees: ``|gt_right(x_r, y) - d| <= tolerance``. Pixels with
    unknown ground truth (0 or NaN), in either view, count as occluded.

    Parameters
    ----------
    gt_left, gt_right : ndarray, shape (H, W)
        Ground-truth disparities in pixels of the left and right views (left
        disparities map ``x`` to ``x - d`` in the right view, right ones map
        ``x`` to ``x + d`` in the left view).
    tolerance : float
        Largest disagreement in pixels still counted as consistent.

    Returns
    -------
    ndarray of bool, shape (H, W)
    """
    gt_left = np.asarray(gt_left, dtype=np.float64)
    gt_right = np.asarray(gt_right, dtype=np.float64)
    if gt_left.ndim != 2 or gt_left.shape != gt_right.shape:
        raise ValueError(
            f"left and right ground truths must be 2-D of equal shape, got "
            f"{gt_left.shape} and {gt_right.shape}"
        )
    height, width = gt_left.shape
    known_left = known_ground_truth(gt_left)
    x_right = np.floor(np.arange(width) - np.where(known_left, gt_left, 0.0) + 0.5).astype(np.int64)
    inside = known_left & (x_right >= 0) & (x_right < width)
    rows = np.arange(height)[:, None]
    right_value = gt_right[rows, np.clip(x_right, 0, width - 1)]
    return inside & known_ground_truth(right_value) & (np.abs(right_value - gt_left) <= tolerance)


def _mask(mask: np.ndarray, shape: tuple[int, ...], name: str) -> np.ndarray:
    mask = np.asarray(mask)
    if mask.shape != shape:
        raise ValueError(f"{name} mask shape {mask.shape} differs from disparity shape {shape}")
    return mask.astype(bool)
