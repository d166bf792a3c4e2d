"""Segment planes against the matcher's disparities, decided by matching cost.

Klaus, Sormann and Karner ("Segment-based stereo matching using belief propagation and a
self-adapting dissimilarity measure", ICPR 2006) charge a segment's plane the matching
cost of its pixels on it and choose among the planes by belief propagation over the
segments. Here a trusted plane (:func:`mvtools.depth.segment.trusted_planes`) competes
only with the segment's own disparities, and both are charged colour-weighted window
means of the cost volume: whole segments take their plane where it costs about as much
(:func:`select_segment_planes`), and pixels of fattened foreground next to a depth step
fall back onto the plane of their segment (:func:`trim_fattening`); the matchers run the
two in turn on planes fitted once (:func:`refine_on_segment_planes`)."""

from __future__ import annotations

import cv2
import numpy as np
from numba import njit, prange

from mvtools.depth.cost import as_colour
from mvtools.depth.segment import plane_disparity, trusted_planes

__all__ = ["refine_on_segment_planes", "select_segment_planes", "trim_fattening"]

#: The plane tests' settings: the cost windows' half size and colour scale
#: (:func:`select_segment_planes`), a plane's trust (:func:`mvtools.depth.segment.trusted_planes`),
#: the relative cost increase a plane may bring to a whole segment and to a fattened
#: pixel, and the columns and disparity difference of a depth step (:func:`trim_fattening`).
RADIUS = 2
SIGMA_COLOUR = 20.0
MIN_SUPPORT = 0.5
MIN_INLIERS = 0.6
TOLERANCE = 1.0
SELECT_MARGIN = 0.1
TRIM_MARGIN = 1.0
REACH = 2
JUMP = 1.0


@njit(cache=True, nogil=True, inline="always")
def _level_between(level, levels):
    # the integer levels below and above a fractional level within the costs' range,
    # its fraction past below, and whether it lies in the range at all
    if not 0.0 <= level <= levels - 1:
        return 0, 0, 0.0, False
    below = min(int(level), max(levels - 2, 0))
    return below, min(below + 1, levels - 1), level - below, True


@njit(cache=True, nogil=True, inline="always")
def _interpolated(cost, y, x, below, above, fraction):
    # pixel (y, x)'s cost at a fractional level, linear between the levels around it
    return (1.0 - fraction) * cost[y, x, below] + fraction * cost[y, x, above]


@njit(cache=True, nogil=True, parallel=True)
def _window_costs(cost, guide, pixels, planes, owns, radius, weight_table, outside):
    # Colour-weighted means over each listed (flat-indexed) pixel's window of the costs
    # at two fractional levels, its plane's and its own, each linearly interpolated
    # between the two integer levels around it; the window's weights, the same for both,
    # are read once.
    rows, cols, levels = cost.shape
    on_plane = np.empty(pixels.size, np.float64)
    own = np.empty(pixels.size, np.float64)
    for i in prange(pixels.size):
        y, x = pixels[i] // cols, pixels[i] % cols
        plane_below, plane_above, plane_fraction, plane_inside = _level_between(planes[i], levels)
        own_below, own_above, own_fraction, own_inside = _level_between(owns[i], levels)
        plane_total = 0.0
        own_total = 0.0
        weights = 0.0
        if plane_inside or own_inside:
            for wy in range(max(0, y - radius), min(rows, y + radius + 1)):
                for wx in range(max(0, x - radius), min(cols, x + radius + 1)):
                    weight = weight_table[
                        abs(guide[wy, wx, 0] - guide[y, x, 0])
                        + abs(guide[wy, wx, 1] - guide[y, x, 1])
                        + abs(guide[wy, wx, 2] - guide[y, x, 2])
                    ]
                    plane_total += weight * _interpolated(
                        cost, wy, wx, plane_below, plane_above, plane_fraction
                    )
                    own_total += weight * _interpolated(
                        cost, wy, wx, own_below, own_above, own_fraction
                    )
                    weights += weight
        # beyond the searched range a disparity costs as much as the worst match
        on_plane[i] = plane_total / weights if plane_inside else outside
        own[i] = own_total / weights if own_inside else outside
    return on_plane, own


class _WindowCost:
    # Colour-weighted window means of a cost volume at fractional disparities, the
    # measure both plane tests compare.
    def __init__(self, cost, guide, min_disparity, step, radius, sigma_colour):
        cost = np.ascontiguousarray(cost, np.float32)
        if cost.ndim != 3 or np.ndim(guide) not in (2, 3) or cost.shape[:2] != np.shape(guide)[:2]:
            raise ValueError(
                f"cost must be an (H, W, D) volume over the guide's pixels, got "
                f"{cost.shape} and {np.shape(guide)}"
            )
        if radius < 0 or sigma_colour <= 0 or not step > 0:
            raise ValueError(
                f"need radius >= 0, sigma_colour > 0 and step > 0, got {radius}, "
                f"{sigma_colour} and {step}"
            )
        self.colour = as_colour(guide)
        self.table = np.exp(-np.arange(3 * max(int(self.colour.max()), 0) + 1) / sigma_colour)
        self.cost, self.min_disparity, self.radius = cost, float(min_disparity), int(radius)
        self.step = float(step)
        # beyond the searched range a disparity costs as much as the worst match
        self.outside = float(cost.max()) if cost.size else 0.0

    def within_range(self, disparities):
        # disparities on the costs' levels, not beyond the searched range
        top = self.min_disparity + (self.cost.shape[2] - 1) * self.step
        return (disparities >= self.min_disparity) & (disparities <= top)

    def __call__(self, pixels, on_planes, disparities):
        # pixels: flat indices; the pixels' window costs on their planes and at their
        # disparities, one of each per pixel
        plane_levels, own_levels = (
            (np.asarray(values, np.float64) - self.min_disparity) / self.step
            for values in (on_planes, disparities)
        )
        return _window_costs(
            self.cost,
            self.colour,
            np.asarray(pixels, np.int64),
            plane_levels,
            own_levels,
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
    min_disparity: float = 0,
    step: float = 1.0,
    margin: float = SELECT_MARGIN,
    radius: int = RADIUS,
    sigma_colour: float = SIGMA_COLOUR,
    min_support: float = MIN_SUPPORT,
    min_inliers: float = MIN_INLIERS,
    tolerance: float = TOLERANCE,
) -> tuple[np.ndarray, np.ndarray]:
    """Segments whose plane matches about as well as their disparities take the plane.

    Each trusted plane (:func:`mvtools.depth.segment.trusted_planes`) is charged the
    matching cost of the segment's valid pixels on it, and compared with the cost of
    their current disparities; where it costs at most ``1 + margin`` times as much,
    every pixel of the segment takes the plane and counts as valid. The costs of both are
    colour-weighted window means (as in :func:`mvtools.depth.refine.weighted_median`): single-pixel
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
        Segments ``0 .. n - 1`` (:func:`mvtools.depth.oversegment.segment_image`).
    cost : ndarray, shape (H, W, D)
        Matching costs of the disparities ``min_disparity + k step``, ``k = 0 .. D - 1``,
        e.g. :func:`mvtools.depth.cost.ad_census_cost` (``step`` 1) or a plane sweep's
        levels (``step`` the pixels a level moves a point in the neighbour).
    guide : ndarray, shape (H, W, 3) or (H, W)
        The view, integer values (others are rounded).
    min_disparity : keyword-only float
        Disparity of the costs' level 0.
    step : keyword-only float
        Disparity from one level of the costs to the next, positive.
    margin : keyword-only float
        Accepted relative cost increase of the plane, at least 0.
    radius : keyword-only int
        Half size of the cost windows, at least 0.
    sigma_colour : keyword-only float
        Absolute colour difference summed over three channels at which a window pixel's
        weight falls to 1/e.
    min_support, min_inliers, tolerance : keyword-only float
        Trust in a segment's plane, see :func:`mvtools.depth.segment.trusted_planes`.

    Returns
    -------
    disparity : ndarray of float32, shape (H, W)
        Sub-pixel on the chosen planes; pixels where the plane leaves the cost's
        disparity range keep their value.
    valid : ndarray of bool, shape (H, W)
    """
    if margin < 0:
        raise ValueError(f"margin must be at least 0, got {margin}")
    window_cost = _WindowCost(cost, guide, min_disparity, step, radius, sigma_colour)
    disparity, valid, labels, planes = _prepared(
        disparity, valid, labels, window_cost, min_support, min_inliers, tolerance
    )
    return _selected(disparity, valid, labels, window_cost, planes, margin)


def trim_fattening(
    disparity: np.ndarray,
    valid: np.ndarray,
    labels: np.ndarray,
    cost: np.ndarray,
    guide: np.ndarray,
    *,
    min_disparity: float = 0,
    step: float = 1.0,
    margin: float = TRIM_MARGIN,
    reach: int = REACH,
    jump: float = JUMP,
    radius: int = RADIUS,
    sigma_colour: float = SIGMA_COLOUR,
    min_support: float = MIN_SUPPORT,
    min_inliers: float = MIN_INLIERS,
    tolerance: float = TOLERANCE,
) -> np.ndarray:
    """Pixels next to a depth step that stand in front of their segment's plane take it.

    Window matchers fatten the foreground: its disparity spills over the background
    pixels whose cost windows overlap it, which also pass a left-right check, as the
    right view is fattened alike. Such pixels lie within a few columns of a horizontal
    disparity step and above the trusted plane
    (:func:`mvtools.depth.segment.trusted_planes`) of their segment, which a colour edge
    separates from the foreground; they take the plane unless its colour-weighted window
    cost (as in :func:`select_segment_planes`) exceeds ``1 + margin`` times theirs, which
    keeps true foreground pixels of segments that straddle a depth edge (textures
    without colour edges). Only larger disparities are pulled back: smaller ones are no
    fattening, and replacing them loses on curved surfaces (Dolls, Moebius).

    Parameters
    ----------
    disparity : ndarray, shape (H, W)
        Disparities, finite where ``valid``.
    valid : ndarray of bool, shape (H, W)
        Reliable pixels, the only ones fitted and changed.
    labels : ndarray of int, shape (H, W)
        Segments ``0 .. n - 1`` (:func:`mvtools.depth.oversegment.segment_image`).
    cost, guide, min_disparity, step, radius, sigma_colour
        Matching costs and their window means, see :func:`select_segment_planes`.
    margin : keyword-only float
        Accepted relative cost increase of the plane, at least 0.
    reach : keyword-only int
        Columns on either side of a step within which pixels are examined, at least 1.
    jump : keyword-only float
        Smallest difference between horizontal neighbours counted as a depth step, and
        between a pixel's disparity and its plane counted as in front of it; positive.
    min_support, min_inliers, tolerance : keyword-only float
        Trust in a segment's plane, see :func:`mvtools.depth.segment.trusted_planes`.

    Returns
    -------
    ndarray of float32, shape (H, W)
    """
    if reach < 1 or jump <= 0 or margin < 0:
        raise ValueError(f"need reach >= 1, jump > 0, margin >= 0, got {reach}, {jump}, {margin}")
    window_cost = _WindowCost(cost, guide, min_disparity, step, radius, sigma_colour)
    disparity, valid, labels, planes = _prepared(
        disparity, valid, labels, window_cost, min_support, min_inliers, tolerance
    )
    return _trimmed(disparity, valid, labels, window_cost, planes, margin, reach, jump)


def refine_on_segment_planes(
    disparity: np.ndarray,
    valid: np.ndarray,
    labels: np.ndarray,
    cost: np.ndarray,
    guide: np.ndarray,
    *,
    min_disparity: float = 0,
    step: float = 1.0,
    select: bool = True,
) -> tuple[np.ndarray, np.ndarray]:
    """:func:`select_segment_planes` (unless not ``select``), then :func:`trim_fattening`,
    each with its default settings, the segments' planes fitted once.

    The selection leaves every segment's plane as it was: a segment either keeps its
    pixels or takes its plane, on which a second fit lands again. So the trim takes the
    planes the selection fitted rather than fitting them anew, which spares a tenth of a
    stereo pair's time on one core (Tsukuba, ``bp``: 0.25 s instead of 0.28), for the
    same disparities as the two calls on all eight Middlebury sets (``bp`` and ``sgm``;
    ``graphcut`` on Tsukuba and Venus) and on the DERS cases of Tsukuba, Venus and Cones.

    Parameters
    ----------
    disparity, valid, labels, cost, guide, min_disparity, step
        As for :func:`select_segment_planes`.
    select : keyword-only bool
        Whether segments may take their plane whole before the trim.

    Returns
    -------
    disparity : ndarray of float32, shape (H, W)
    valid : ndarray of bool, shape (H, W)
        ``valid`` and the pixels of the segments that took their plane.
    """
    window_cost = _WindowCost(cost, guide, min_disparity, step, RADIUS, SIGMA_COLOUR)
    disparity, valid, labels, planes = _prepared(
        disparity, valid, labels, window_cost, MIN_SUPPORT, MIN_INLIERS, TOLERANCE
    )
    if select:
        disparity, valid = _selected(disparity, valid, labels, window_cost, planes, SELECT_MARGIN)
    return _trimmed(disparity, valid, labels, window_cost, planes, TRIM_MARGIN, REACH, JUMP), valid


def _prepared(disparity, valid, labels, window_cost, min_support, min_inliers, tolerance):
    # the inputs as arrays, and every segment's plane at each of its pixels with whether
    # the segment trusts it
    disparity = np.asarray(disparity, np.float32)
    valid = np.asarray(valid, bool)
    labels = np.asarray(labels, np.int64)
    if labels.shape != disparity.shape or window_cost.cost.shape[:2] != disparity.shape:
        raise ValueError(
            f"cost volume of shape {window_cost.cost.shape} and labels of shape "
            f"{labels.shape} do not fit the {disparity.shape} map"
        )
    planes, trusted = trusted_planes(disparity, valid, labels, min_support, min_inliers, tolerance)
    return disparity, valid, labels, (plane_disparity(planes, labels), trusted)


def _selected(disparity, valid, labels, window_cost, planes, margin):
    on_planes, trusted = planes
    # the valid pixels' costs summed per segment, on the plane and as they are
    pixels = np.flatnonzero((valid & np.isfinite(disparity)).ravel())
    segment_of = labels.ravel()[pixels]
    count = trusted.size
    on_plane, own = (
        np.bincount(segment_of, costs, minlength=count)
        for costs in window_cost(pixels, on_planes.ravel()[pixels], disparity.ravel()[pixels])
    )
    chosen = trusted & (on_plane <= (1.0 + margin) * own)
    replace = chosen[labels] & window_cost.within_range(on_planes)
    return np.where(replace, on_planes, disparity).astype(np.float32), valid | replace


def _trimmed(disparity, valid, labels, window_cost, planes, margin, reach, jump):
    on_planes, trusted = planes
    finite = np.ascontiguousarray(np.where(np.isfinite(disparity), disparity, 0.0), np.float32)
    row = np.ones((1, 3), np.uint8)
    step = cv2.dilate(finite, row) - cv2.erode(finite, row) > jump
    near = cv2.dilate(step.astype(np.uint8), np.ones((1, 2 * reach + 1), np.uint8)) > 0
    with np.errstate(invalid="ignore"):
        candidates = np.flatnonzero(
            (
                trusted[labels]
                & near
                & valid
                & (disparity > on_planes + jump)
                & window_cost.within_range(on_planes)
            ).ravel()
        )
    plane_values = on_planes.ravel()[candidates]
    on_plane, own = window_cost(candidates, plane_values, disparity.ravel()[candidates])
    affordable = on_plane <= (1.0 + margin) * own
    trimmed = disparity.copy()
    trimmed.ravel()[candidates[affordable]] = plane_values[affordable]
    return trimmed
