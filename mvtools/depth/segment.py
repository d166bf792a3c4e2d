"""Robust disparity planes of colour segments (Klaus, Sormann and Karner, "Segment-based
stereo matching using belief propagation and a self-adapting dissimilarity measure", ICPR
2006): a plane per segment of :mod:`mvtools.depth.oversegment`, fitted to the reliable
disparities, stands in for the pixels the matcher got wrong or could not check; most
surfaces of a scene are near-planar over one segment. Whether a plane also replaces
reliable disparities is decided by matching cost in :mod:`mvtools.depth.plane_selection`."""

from __future__ import annotations

import numpy as np
from numba import njit, prange

__all__ = ["fill_from_planes", "fit_segment_planes", "plane_disparity", "trusted_planes"]


@njit(cache=True, nogil=True)
def _median_slope(along, across, values, max_slope, max_pairs):
    # Median, to 1/256, of the slopes between pixel pairs on one line (equal ``across``)
    # of the segment, pixels sorted by (across, along), over the first ``max_pairs``
    # pairs in that order; pairs closer than 2 pixels carry mostly quantisation noise.
    # A line whose pairs all count is read run by run (_add_run_pairs); one that
    # reaches max_pairs pair by pair up to it.
    lowest, step = -max_slope, 1.0 / 256
    histogram = np.zeros(int(512 * max_slope), np.int64)
    run_starts = np.empty(along.size + 1, np.int64)
    counted = 0
    line = 0
    while line < along.size and counted < max_pairs:
        end = line
        while end < along.size and across[end] == across[line]:
            end += 1
        runs, pairs = _line_runs(along, values, line, end, run_starts)
        if counted + pairs <= max_pairs:
            _add_run_pairs(histogram, along, values, run_starts, runs, lowest, step)
            counted += pairs
        else:
            for i in range(line, end):
                for j in range(i + 1, end):
                    distance = along[j] - along[i]
                    if distance >= 2 and counted < max_pairs:
                        _add_slope(histogram, values[j] - values[i], distance, 1, lowest, step)
                        counted += 1
        line = end
    total = histogram.sum()
    running = 0
    for b in range(histogram.size):
        running += histogram[b]
        if 2 * running >= total > 0:
            return lowest + (b + 0.5) * step
    return 0.0


@njit(cache=True, nogil=True)
def _line_runs(along, values, line, end, run_starts):
    # The runs of equal values on neighbouring pixels of the line line..end, their
    # first indices into run_starts (then end), and the line's pairs 2 or more apart
    runs = 0
    neighbours = 0
    for index in range(line, end):
        touching = index > line and along[index] - along[index - 1] == 1
        if touching:
            neighbours += 1
        if not (touching and values[index] == values[index - 1]):
            run_starts[runs] = index
            runs += 1
    run_starts[runs] = end
    return runs, (end - line) * (end - line - 1) // 2 - neighbours


@njit(cache=True, nogil=True)
def _add_run_pairs(histogram, along, values, run_starts, runs, lowest, step):
    # Every pair 2 or more apart of a line's runs, counted as _add_slope would one by
    # one: the pairs within a run, or between two runs, at one distance share their
    # slope, so the time is linear in the runs' lengths rather than in their pairs.
    for first in range(runs):
        a0, a1 = run_starts[first], run_starts[first + 1] - 1
        for distance in range(2, a1 - a0 + 1):
            _add_slope(histogram, 0.0, distance, a1 - a0 + 1 - distance, lowest, step)
        for second in range(first + 1, runs):
            b0, b1 = run_starts[second], run_starts[second + 1] - 1
            rise = values[b0] - values[a0]
            for distance in range(
                max(int(along[b0] - along[a1]), 2), int(along[b1] - along[a0]) + 1
            ):
                # pixels of the first run whose partner at this distance is in the second
                overlap = min(along[a1], along[b1] - distance) - max(
                    along[a0], along[b0] - distance
                )
                if overlap >= 0:
                    _add_slope(histogram, rise, distance, int(overlap) + 1, lowest, step)


@njit(cache=True, nogil=True, inline="always")
def _add_slope(histogram, rise, distance, pairs, lowest, step):
    # ``pairs`` pairs of slope rise / distance into the histogram's 1/256 bins from lowest
    b = int((rise / distance - lowest) / step)
    if 0 <= b < histogram.size:
        histogram[b] += pairs


@njit(cache=True, nogil=True)
def _least_squares_plane(xs, ys, ds, a, b, c, tolerance):
    # Plane through the points within ``tolerance`` of (a, b, c), about their centroid
    # so that the 3x3 normal equations stay well conditioned.
    n = 0
    mx = my = md = 0.0
    for i in range(xs.size):
        if abs(ds[i] - (a * xs[i] + b * ys[i] + c)) <= tolerance:
            n += 1
            mx += xs[i]
            my += ys[i]
            md += ds[i]
    if n < 3:
        return a, b, c, n
    mx, my, md = mx / n, my / n, md / n
    sxx = sxy = syy = sxd = syd = 0.0
    for i in range(xs.size):
        if abs(ds[i] - (a * xs[i] + b * ys[i] + c)) <= tolerance:
            dx, dy, dd = xs[i] - mx, ys[i] - my, ds[i] - md
            sxx += dx * dx
            sxy += dx * dy
            syy += dy * dy
            sxd += dx * dd
            syd += dy * dd
    determinant = sxx * syy - sxy * sxy
    if determinant <= 1e-9 * max(sxx * syy, 1e-12):
        # collinear points (one row or column): keep the voted slopes
        return a, b, md - a * mx - b * my, n
    a = (sxd * syy - syd * sxy) / determinant
    b = (syd * sxx - sxd * sxy) / determinant
    return a, b, md - a * mx - b * my, n


@njit(cache=True, nogil=True, parallel=True)
def _fit_planes(
    order_by_row, order_by_column, starts, disparity, cols, max_slope, tolerance, max_pairs
):
    segments = starts.size - 1
    planes = np.zeros((segments, 3), np.float64)
    inliers = np.zeros(segments, np.int64)
    for s in prange(segments):
        start, stop = starts[s], starts[s + 1]
        if stop - start < 3:
            continue
        rows_sorted = order_by_row[start:stop]
        columns_sorted = order_by_column[start:stop]
        xs = (rows_sorted % cols).astype(np.float64)
        ys = (rows_sorted // cols).astype(np.float64)
        ds = disparity[rows_sorted]
        a = _median_slope(xs, ys, ds, max_slope, max_pairs)
        b = _median_slope(
            (columns_sorted // cols).astype(np.float64),
            (columns_sorted % cols).astype(np.float64),
            disparity[columns_sorted],
            max_slope,
            max_pairs,
        )
        c = np.median(ds - a * xs - b * ys)
        n = 0
        for _ in range(3):
            a, b, c, n = _least_squares_plane(xs, ys, ds, a, b, c, tolerance)
        planes[s, 0], planes[s, 1], planes[s, 2] = a, b, c
        inliers[s] = n
    return planes, inliers


@njit(cache=True, nogil=True)
def _grouped_by_segment(pixels, labels, starts):
    # the flat-indexed pixels grouped by their segment, in their order within each (a
    # counting sort: a stable sort by segment, without the sort's n log n)
    grouped = np.empty(pixels.size, np.int64)
    free = starts[:-1].copy()
    for pixel in pixels:
        segment = labels[pixel]
        grouped[free[segment]] = pixel
        free[segment] += 1
    return grouped


def fit_segment_planes(
    disparity: np.ndarray,
    valid: np.ndarray,
    labels: np.ndarray,
    *,
    tolerance: float = 1.0,
    max_slope: float = 1.0,
    max_pairs: int = 200_000,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Robust disparity plane ``d = a x + b y + c`` of every segment.

    Klaus et al.'s decomposed estimate: the horizontal slope is the median of the
    slopes between the valid pixels of each row, the vertical slope likewise over
    columns, the offset the median of the remaining residuals; then least squares on
    the points within ``tolerance`` of the plane, three times.

    Parameters
    ----------
    disparity : ndarray, shape (H, W)
        Disparities; only ``valid`` ones are read.
    valid : ndarray of bool, shape (H, W)
        Reliable pixels, e.g. left-right consistent.
    labels : ndarray of int, shape (H, W)
        Segments ``0 .. n - 1`` (:func:`mvtools.depth.oversegment.segment_image`).
    tolerance : keyword-only float
        Largest residual, in pixels, of a point counted as an inlier.
    max_slope : keyword-only float
        Largest slope magnitude voted for, pixels of disparity per pixel.
    max_pairs : keyword-only int
        Pixel pairs voting per segment and direction, at most, the first ones in scan
        order; bounds the time on large segments.

    Returns
    -------
    planes : ndarray of float64, shape (n, 3)
        ``(a, b, c)`` per segment, x and y in pixels from the top-left; zero for a
        segment with fewer than 3 valid pixels.
    inliers : ndarray of int64, shape (n,)
        Valid pixels within ``tolerance`` of the plane.
    support : ndarray of int64, shape (n,)
        Valid pixels of the segment.
    """
    disparity = np.asarray(disparity, np.float64)
    valid = np.asarray(valid, bool)
    labels = np.asarray(labels, np.int64)
    if disparity.ndim != 2 or valid.shape != disparity.shape or labels.shape != disparity.shape:
        raise ValueError(
            f"disparity, valid and labels must be (H, W) arrays of one shape, "
            f"got {disparity.shape}, {valid.shape}, {labels.shape}"
        )
    if tolerance <= 0 or max_slope <= 0 or max_pairs < 1:
        raise ValueError("tolerance, max_slope and max_pairs must be positive")
    segments = int(labels.max()) + 1 if labels.size else 0
    if labels.size and labels.min() < 0:
        raise ValueError("segment labels must be non-negative")
    rows, cols = disparity.shape
    usable = valid & np.isfinite(disparity)
    flat = np.flatnonzero(usable.ravel())
    label_of = labels.ravel()
    support = np.bincount(label_of[flat], minlength=segments).astype(np.int64)
    starts = np.concatenate([[0], np.cumsum(support)]).astype(np.int64)
    # valid pixels grouped by segment, in raster order and in column-major order within
    in_columns = np.flatnonzero(usable.T.ravel())
    in_columns = (in_columns % rows) * cols + in_columns // rows
    by_row = _grouped_by_segment(flat, label_of, starts)
    by_column = _grouped_by_segment(in_columns, label_of, starts)
    planes, inliers = _fit_planes(
        by_row,
        by_column,
        starts,
        disparity.ravel(),
        cols,
        float(max_slope),
        float(tolerance),
        int(max_pairs),
    )
    return planes, inliers, support


def plane_disparity(planes: np.ndarray, labels: np.ndarray) -> np.ndarray:
    """Every pixel's disparity on its segment's plane.

    Parameters
    ----------
    planes : ndarray, shape (n, 3)
        ``(a, b, c)`` of ``d = a x + b y + c`` per segment.
    labels : ndarray of int, shape (H, W)

    Returns
    -------
    ndarray of float32, shape (H, W)
    """
    planes = np.asarray(planes, np.float64)
    labels = np.asarray(labels, np.int64)
    rows, cols = labels.shape
    ys, xs = np.mgrid[0:rows, 0:cols]
    chosen = planes[labels]
    return (chosen[..., 0] * xs + chosen[..., 1] * ys + chosen[..., 2]).astype(np.float32)


def trusted_planes(
    disparity: np.ndarray,
    valid: np.ndarray,
    labels: np.ndarray,
    min_support: float,
    min_inliers: float,
    tolerance: float,
) -> tuple[np.ndarray, np.ndarray]:
    """Every segment's plane (:func:`fit_segment_planes`) and whether it is trusted.

    A plane is trusted when at least ``min_support`` of its segment's pixels are valid
    and at least ``min_inliers`` of those lie within ``tolerance`` of it; at least 3
    valid pixels: fewer leave the plane undetermined.

    Parameters
    ----------
    disparity : ndarray, shape (H, W)
    valid : ndarray of bool, shape (H, W)
    labels : ndarray of int, shape (H, W)
        Segments ``0 .. n - 1``.
    min_support, min_inliers : float
        Fractions in [0, 1].
    tolerance : float
        Inlier residual, pixels.

    Returns
    -------
    planes : ndarray of float64, shape (n, 3)
        ``(a, b, c)`` of ``d = a x + b y + c`` per segment.
    trusted : ndarray of bool, shape (n,)
    """
    if not (0 <= min_support <= 1 and 0 <= min_inliers <= 1):
        raise ValueError(
            f"min_support and min_inliers are fractions in [0, 1], got {min_support}, {min_inliers}"
        )
    planes, inliers, support = fit_segment_planes(disparity, valid, labels, tolerance=tolerance)
    size = np.bincount(np.asarray(labels, np.int64).ravel(), minlength=support.size)
    trusted = (support >= np.maximum(min_support * size, 3)) & (inliers >= min_inliers * support)
    return planes, trusted


def fill_from_planes(
    disparity: np.ndarray,
    valid: np.ndarray,
    labels: np.ndarray,
    *,
    min_support: float = 0.5,
    min_inliers: float = 0.6,
    tolerance: float = 1.0,
) -> tuple[np.ndarray, np.ndarray]:
    """Invalid pixels of well-explained segments take their segment's plane.

    A segment's plane (:func:`fit_segment_planes`) is trusted (:func:`trusted_planes`)
    when at least ``min_support`` of its pixels are valid and at least ``min_inliers`` of
    those lie within ``tolerance`` of it; the invalid pixels of such segments (occluded
    or mismatched) are then set on the plane and count as valid. Valid pixels keep their
    value: replacing plane outliers too helps the planar Venus but loses on the curved
    surfaces of Cones and the 2005 sets
    (:func:`mvtools.depth.plane_selection.select_segment_planes` replaces them where the
    matching costs agree).

    Parameters
    ----------
    disparity : ndarray, shape (H, W)
    valid : ndarray of bool, shape (H, W)
    labels : ndarray of int, shape (H, W)
        Segments ``0 .. n - 1``.
    min_support, min_inliers : keyword-only float
        Fractions in [0, 1].
    tolerance : keyword-only float
        Inlier residual, pixels.

    Returns
    -------
    disparity : ndarray of float32, shape (H, W)
    valid : ndarray of bool, shape (H, W)
    """
    planes, trusted = trusted_planes(disparity, valid, labels, min_support, min_inliers, tolerance)
    replace = trusted[labels] & ~np.asarray(valid, bool)
    filled = np.where(replace, plane_disparity(planes, labels), disparity)
    return filled.astype(np.float32), valid | replace
