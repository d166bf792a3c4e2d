"""Segment-based disparity planes: an over-segmentation of the view by colour
(Felzenszwalb and Huttenlocher 2004) and a robust disparity plane per segment fitted
to the reliable disparities (Klaus et al. 2006), which then stands in for the pixels
the matcher got wrong or could not check. Homogeneous colour regions rarely straddle a
depth edge, and most surfaces of a scene are near-planar over one segment."""

from __future__ import annotations

import cv2
import numpy as np
from numba import njit, prange

from mvtools.depth.cost import as_colour

__all__ = [
    "fill_from_planes",
    "fit_segment_planes",
    "plane_disparity",
    "plane_segments",
    "segment_image",
    "select_segment_planes",
    "trim_fattening",
]


@njit(cache=True, nogil=True)
def _find(parent, node):
    root = node
    while parent[root] != root:
        root = parent[root]
    while parent[node] != root:
        parent[node], node = root, parent[node]
    return root


@njit(cache=True, nogil=True)
def _felzenszwalb(first, second, weight, order, pixels, scale, min_size):
    parent = np.arange(pixels)
    size = np.ones(pixels, np.int64)
    # a component's internal difference plus scale / size: the merge threshold
    threshold = np.full(pixels, scale, np.float64)
    for e in order:
        a, b = _find(parent, first[e]), _find(parent, second[e])
        if a != b and weight[e] <= threshold[a] and weight[e] <= threshold[b]:
            if size[a] < size[b]:
                a, b = b, a
            parent[b] = a
            size[a] += size[b]
            threshold[a] = weight[e] + scale / size[a]
    # components below min_size join their most similar neighbour
    for e in order:
        a, b = _find(parent, first[e]), _find(parent, second[e])
        if a != b and (size[a] < min_size or size[b] < min_size):
            if size[a] < size[b]:
                a, b = b, a
            parent[b] = a
            size[a] += size[b]
    labels = np.empty(pixels, np.int64)
    number = np.full(pixels, -1, np.int64)
    count = 0
    for i in range(pixels):
        root = _find(parent, i)
        if number[root] < 0:
            number[root] = count
            count += 1
        labels[i] = number[root]
    return labels


def segment_image(
    image: np.ndarray, *, scale: float = 300.0, min_size: int = 40, sigma: float = 0.8
) -> np.ndarray:
    """Over-segmentation by Felzenszwalb and Huttenlocher's graph-based merging.

    Pixels are nodes of an 8-connected graph weighted by Euclidean colour distance;
    edges are visited by increasing weight and join two components when the weight does
    not exceed either's largest internal edge plus ``scale / size``.

    Parameters
    ----------
    image : ndarray, shape (H, W, 3) or (H, W)
        Colour or grey view.
    scale : keyword-only float
        Larger values give larger segments (colour units, 0..255 per channel).
    min_size : keyword-only int
        Segments smaller than this join their most similar neighbour.
    sigma : keyword-only float
        Gaussian smoothing before the colour differences; 0 for none.

    Returns
    -------
    ndarray of int64, shape (H, W)
        Labels ``0 .. n - 1``, numbered in raster order of their first pixel;
        deterministic for a given image.
    """
    image = np.asarray(image, np.float32)
    if image.ndim not in (2, 3) or (image.ndim == 3 and image.shape[2] != 3):
        raise ValueError(f"image must be (H, W) or (H, W, 3), got {image.shape}")
    if scale <= 0 or min_size < 1 or sigma < 0:
        raise ValueError(
            f"need scale > 0, min_size >= 1, sigma >= 0, got {scale}, {min_size}, {sigma}"
        )
    colour = image[:, :, None] if image.ndim == 2 else image
    if sigma > 0:
        colour = cv2.GaussianBlur(colour, (0, 0), sigma).reshape(colour.shape)
    rows, cols = colour.shape[:2]
    index = np.arange(rows * cols).reshape(rows, cols)
    # right, down, down-right and down-left neighbours: each 8-connected edge once
    pairs = [
        (index[:, :-1], index[:, 1:]),
        (index[:-1, :], index[1:, :]),
        (index[:-1, :-1], index[1:, 1:]),
        (index[:-1, 1:], index[1:, :-1]),
    ]
    first = np.concatenate([a.ravel() for a, _ in pairs])
    second = np.concatenate([b.ravel() for _, b in pairs])
    flat = colour.reshape(rows * cols, -1)
    weight = np.sqrt(((flat[first] - flat[second]) ** 2).sum(axis=1))
    order = np.argsort(weight, kind="stable")
    return _felzenszwalb(
        first, second, weight, order, rows * cols, float(scale), int(min_size)
    ).reshape(rows, cols)


def plane_segments(view: np.ndarray) -> np.ndarray:
    """The over-segmentation the plane steps fit planes to: :func:`segment_image` with
    scale 120 and segments of at least 20 pixels, fine enough that a segment rarely
    straddles a depth edge."""
    return segment_image(view, scale=120.0, min_size=20)


@njit(cache=True, nogil=True)
def _histogram_median(values, count, lowest, step, bins):
    histogram = np.zeros(bins, np.int64)
    for i in range(count):
        b = int((values[i] - lowest) / step)
        if 0 <= b < bins:
            histogram[b] += 1
    total = histogram.sum()
    if total == 0:
        return 0.0
    running = 0
    for b in range(bins):
        running += histogram[b]
        if 2 * running >= total:
            return lowest + (b + 0.5) * step
    return 0.0


@njit(cache=True, nogil=True)
def _median_slope(along, across, values, start, stop, max_slope, buffer):
    # Median of the slopes between pixel pairs on one line (equal ``across``) of the
    # segment, pixels sorted by (across, along); pairs closer than 2 pixels carry
    # mostly quantisation noise.
    count = 0
    line = start
    while line < stop:
        end = line
        while end < stop and across[end] == across[line]:
            end += 1
        for i in range(line, end):
            for j in range(i + 1, end):
                distance = along[j] - along[i]
                if distance >= 2 and count < buffer.size:
                    buffer[count] = (values[j] - values[i]) / distance
                    count += 1
        line = end
    return _histogram_median(buffer, count, -max_slope, 1.0 / 256, int(512 * max_slope))


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
        buffer = np.empty(max_pairs, np.float64)
        xs = (rows_sorted % cols).astype(np.float64)
        ys = (rows_sorted // cols).astype(np.float64)
        ds = disparity[rows_sorted]
        a = _median_slope(xs, ys, ds, 0, stop - start, max_slope, buffer)
        b = _median_slope(
            (columns_sorted // cols).astype(np.float64),
            (columns_sorted % cols).astype(np.float64),
            disparity[columns_sorted],
            0,
            stop - start,
            max_slope,
            buffer,
        )
        c = np.median(ds - a * xs - b * ys)
        n = 0
        for _ in range(3):
            a, b, c, n = _least_squares_plane(xs, ys, ds, a, b, c, tolerance)
        planes[s, 0], planes[s, 1], planes[s, 2] = a, b, c
        inliers[s] = n
    return planes, inliers


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
        Segments ``0 .. n - 1`` (:func:`segment_image`).
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
    _rows, cols = disparity.shape
    usable = valid & np.isfinite(disparity)
    flat = np.flatnonzero(usable.ravel())
    segment_of = labels.ravel()[flat]
    # valid pixels grouped by segment, in raster order and in column-major order within
    by_row = flat[np.argsort(segment_of, kind="stable")]
    by_column = flat[np.lexsort((flat // cols, flat % cols, segment_of))]
    support = np.bincount(segment_of, minlength=segments).astype(np.int64)
    starts = np.concatenate([[0], np.cumsum(support)]).astype(np.int64)
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


def _trusted_planes(disparity, valid, labels, min_support, min_inliers, tolerance):
    # A segment's plane is trusted when enough of its pixels are valid and enough of
    # those lie on it; at least 3 valid pixels: fewer leave the plane undetermined.
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

    A segment's plane (:func:`fit_segment_planes`) is trusted when at least
    ``min_support`` of its pixels are valid and at least ``min_inliers`` of those lie
    within ``tolerance`` of it; the invalid pixels of such segments (occluded or
    mismatched) are then set on the plane and count as valid. Valid pixels keep their
    value: replacing plane outliers too helps the planar Venus but loses on the curved
    surfaces of Cones and the 2005 sets (:func:`select_segment_planes` replaces them
    where the matching costs agree).

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
    planes, trusted = _trusted_planes(disparity, valid, labels, min_support, min_inliers, tolerance)
    replace = trusted[labels] & ~np.asarray(valid, bool)
    filled = np.where(replace, plane_disparity(planes, labels), disparity)
    return filled.astype(np.float32), valid | replace


@njit(cache=True, nogil=True, inline="always")
def _window_cost(cost, guide, y, x, level, radius, weight_table, outside):
    # Colour-weighted mean over the window of the costs at a fractional level, linearly
    # interpolated between the two integer levels around it.
    rows, cols, levels = cost.shape
    if not 0.0 <= level <= levels - 1:
        return outside
    below = min(int(level), max(levels - 2, 0))
    fraction = level - below
    above = min(below + 1, levels - 1)
    total = 0.0
    weights = 0.0
    for wy in range(max(0, y - radius), min(rows, y + radius + 1)):
        for wx in range(max(0, x - radius), min(cols, x + radius + 1)):
            weight = weight_table[
                abs(guide[wy, wx, 0] - guide[y, x, 0])
                + abs(guide[wy, wx, 1] - guide[y, x, 1])
                + abs(guide[wy, wx, 2] - guide[y, x, 2])
            ]
            total += weight * (
                (1.0 - fraction) * cost[wy, wx, below] + fraction * cost[wy, wx, above]
            )
            weights += weight
    return total / weights


@njit(cache=True, nogil=True, parallel=True)
def _window_costs(cost, guide, pixels, levels, radius, weight_table, outside):
    # the colour-weighted window cost of each listed (flat-indexed) pixel at its level
    cols = guide.shape[1]
    costs = np.empty(pixels.size, np.float64)
    for i in prange(pixels.size):
        costs[i] = _window_cost(
            cost,
            guide,
            pixels[i] // cols,
            pixels[i] % cols,
            levels[i],
            radius,
            weight_table,
            outside,
        )
    return costs


class _WindowCost:
    # Colour-weighted window means of a cost volume at fractional disparities, the
    # measure both plane tests compare.
    def __init__(self, cost, guide, min_disparity, radius, sigma_colour):
        cost = np.ascontiguousarray(cost, np.float32)
        if cost.ndim != 3 or np.ndim(guide) not in (2, 3) or cost.shape[:2] != np.shape(guide)[:2]:
            raise ValueError(
                f"cost must be an (H, W, D) volume over the guide's pixels, got "
                f"{cost.shape} and {np.shape(guide)}"
            )
        if radius < 0 or sigma_colour <= 0:
            raise ValueError(
                f"need radius >= 0 and sigma_colour > 0, got {radius} and {sigma_colour}"
            )
        self.colour = as_colour(guide)
        self.table = np.exp(-np.arange(3 * max(int(self.colour.max()), 0) + 1) / sigma_colour)
        self.cost, self.min_disparity, self.radius = cost, float(min_disparity), int(radius)
        # beyond the searched range a disparity costs as much as the worst match
        self.outside = float(cost.max()) if cost.size else 0.0

    def __call__(self, pixels, disparities):
        # pixels: flat indices; disparities: one per pixel
        return _window_costs(
            self.cost,
            self.colour,
            np.asarray(pixels, np.int64),
            np.asarray(disparities, np.float64) - self.min_disparity,
            self.radius,
            self.table,
            self.outside,
        )


def select_segment_planes(
    disparity: np.ndarray,
    valid: np.ndarray,
    labels: np.ndarray,
    cost: np.ndarray,
    guide: np.ndarray,
    *,
    min_disparity: int = 0,
    margin: float = 0.1,
    radius: int = 2,
    sigma_colour: float = 20.0,
    min_support: float = 0.5,
    min_inliers: float = 0.6,
    tolerance: float = 1.0,
) -> tuple[np.ndarray, np.ndarray]:
    """Segments whose plane matches about as well as their disparities take the plane.

    Each trusted plane (as in :func:`fill_from_planes`) is charged the matching cost of
    the segment's valid pixels on it, and compared with the cost of their current
    disparities; where it costs at most ``1 + margin`` times as much, every pixel of the
    segment takes the plane and counts as valid. The costs of both are colour-weighted
    window means (as in :func:`mvtools.depth.refine.weighted_median`): single-pixel
    costs are too noisy to rank a plane, square windows straddle depth edges. A margin
    above 0 lets the plane win where the pixel-wise disparities are fattened or noisy
    but cheap: on the slanted planes of Venus and Teddy and around Tsukuba's objects;
    curved surfaces (Cones, Dolls) cost clearly more on one plane and keep theirs.

    Parameters
    ----------
    disparity : ndarray, shape (H, W)
        Disparities, finite where ``valid``.
    valid : ndarray of bool, shape (H, W)
        Reliable pixels, e.g. left-right consistent.
    labels : ndarray of int, shape (H, W)
        Segments ``0 .. n - 1`` (:func:`segment_image`).
    cost : ndarray, shape (H, W, D)
        Matching costs of the disparities ``min_disparity .. min_disparity + D - 1``,
        e.g. :func:`mvtools.depth.cost.ad_census_cost`.
    guide : ndarray, shape (H, W, 3) or (H, W)
        The view, integer values (others are rounded).
    min_disparity : keyword-only int
        Disparity of the costs' level 0.
    margin : keyword-only float
        Accepted relative cost increase of the plane, at least 0.
    radius : keyword-only int
        Half size of the cost windows, at least 0.
    sigma_colour : keyword-only float
        Absolute colour difference summed over three channels at which a window pixel's
        weight falls to 1/e.
    min_support, min_inliers, tolerance : keyword-only float
        Trust in a segment's plane, see :func:`fill_from_planes`.

    Returns
    -------
    disparity : ndarray of float32, shape (H, W)
        Sub-pixel on the chosen planes; pixels where the plane leaves the cost's
        disparity range keep their value.
    valid : ndarray of bool, shape (H, W)
    """
    disparity = np.asarray(disparity, np.float32)
    valid = np.asarray(valid, bool)
    labels = np.asarray(labels, np.int64)
    if margin < 0:
        raise ValueError(f"margin must be at least 0, got {margin}")
    window_cost = _WindowCost(cost, guide, min_disparity, radius, sigma_colour)
    if labels.shape != disparity.shape or window_cost.cost.shape[:2] != disparity.shape:
        raise ValueError(
            f"cost volume of shape {window_cost.cost.shape} and labels of shape "
            f"{labels.shape} do not fit the {disparity.shape} map"
        )
    planes, trusted = _trusted_planes(disparity, valid, labels, min_support, min_inliers, tolerance)
    on_planes = plane_disparity(planes, labels)
    # the valid pixels' costs summed per segment, on the plane and as they are
    pixels = np.flatnonzero((valid & np.isfinite(disparity)).ravel())
    segment_of = labels.ravel()[pixels]
    count = planes.shape[0]
    on_plane = np.bincount(
        segment_of, window_cost(pixels, on_planes.ravel()[pixels]), minlength=count
    )
    own = np.bincount(segment_of, window_cost(pixels, disparity.ravel()[pixels]), minlength=count)
    chosen = trusted & (on_plane <= (1.0 + margin) * own)
    levels = window_cost.cost.shape[2]
    replace = (
        chosen[labels] & (on_planes >= min_disparity) & (on_planes <= min_disparity + levels - 1)
    )
    return np.where(replace, on_planes, disparity).astype(np.float32), valid | replace


def trim_fattening(
    disparity: np.ndarray,
    valid: np.ndarray,
    labels: np.ndarray,
    cost: np.ndarray,
    guide: np.ndarray,
    *,
    min_disparity: int = 0,
    margin: float = 1.0,
    reach: int = 2,
    jump: float = 1.0,
    radius: int = 2,
    sigma_colour: float = 20.0,
    min_support: float = 0.5,
    min_inliers: float = 0.6,
    tolerance: float = 1.0,
) -> np.ndarray:
    """Pixels next to a depth step that stand in front of their segment's plane take it.

    Window matchers fatten the foreground: its disparity spills over the background
    pixels whose cost windows overlap it, which also pass a left-right check, as the
    right view is fattened alike. Such pixels lie within a few columns of a horizontal
    disparity step and above the trusted plane (as in :func:`fill_from_planes`) of
    their segment, which a colour edge separates from the foreground; they take the
    plane unless its colour-weighted window cost (as in :func:`select_segment_planes`)
    exceeds ``1 + margin`` times theirs, which keeps true foreground pixels of
    segments that straddle a depth edge (textures without colour edges). Only larger
    disparities are pulled back: smaller ones are no fattening, and replacing them
    loses on curved surfaces (Dolls, Moebius).

    Parameters
    ----------
    disparity : ndarray, shape (H, W)
        Disparities, finite where ``valid``.
    valid : ndarray of bool, shape (H, W)
        Reliable pixels, the only ones fitted and changed.
    labels : ndarray of int, shape (H, W)
        Segments ``0 .. n - 1`` (:func:`segment_image`).
    cost, guide, min_disparity, radius, sigma_colour
        Matching costs and their window means, see :func:`select_segment_planes`.
    margin : keyword-only float
        Accepted relative cost increase of the plane, at least 0.
    reach : keyword-only int
        Columns on either side of a step within which pixels are examined, at least 1.
    jump : keyword-only float
        Smallest difference between horizontal neighbours counted as a depth step, and
        between a pixel's disparity and its plane counted as in front of it; positive.
    min_support, min_inliers, tolerance : keyword-only float
        Trust in a segment's plane, see :func:`fill_from_planes`.

    Returns
    -------
    ndarray of float32, shape (H, W)
    """
    if reach < 1 or jump <= 0 or margin < 0:
        raise ValueError(f"need reach >= 1, jump > 0, margin >= 0, got {reach}, {jump}, {margin}")
    disparity = np.asarray(disparity, np.float32)
    valid = np.asarray(valid, bool)
    window_cost = _WindowCost(cost, guide, min_disparity, radius, sigma_colour)
    planes, trusted = _trusted_planes(disparity, valid, labels, min_support, min_inliers, tolerance)
    on_planes = plane_disparity(planes, labels)
    finite = np.ascontiguousarray(np.where(np.isfinite(disparity), disparity, 0.0), np.float32)
    row = np.ones((1, 3), np.uint8)
    step = cv2.dilate(finite, row) - cv2.erode(finite, row) > jump
    near = cv2.dilate(step.astype(np.uint8), np.ones((1, 2 * reach + 1), np.uint8)) > 0
    levels = window_cost.cost.shape[2]
    with np.errstate(invalid="ignore"):
        candidates = np.flatnonzero(
            (
                trusted[labels]
                & near
                & valid
                & (disparity > on_planes + jump)
                & (on_planes >= min_disparity)
                & (on_planes <= min_disparity + levels - 1)
            ).ravel()
        )
    plane_values = on_planes.ravel()[candidates]
    affordable = window_cost(candidates, plane_values) <= (1.0 + margin) * window_cost(
        candidates, disparity.ravel()[candidates]
    )
    trimmed = disparity.copy()
    trimmed.ravel()[candidates[affordable]] = plane_values[affordable]
    return trimmed
