"""Depth estimation of a center view from its neighbours, as DERS configurations ask.

:class:`DersEstimator` turns :class:`mvtools.params.DersParams` and the cameras into
depth maps, one frame at a time: depth planes uniform in ``1/z`` (from the disparity
search range and the BaselineBasis camera, or from NearestSearchDepthValue,
FarthestSearchDepthValue and NumberOfDepthSteps), the plane-sweep cost volume
(:mod:`mvtools.depth.planesweep`), a method of :data:`mvtools.depth.METHODS`, then the
stereo-pair mode's chain (:func:`mvtools.depth.stereo.estimate_disparity`) on the levels
of the sweep: the winners kept on the search grid, as the stereo-pair mode keeps integer
disparities; for rectified neighbours its left-right check (a neighbour's own choice of
plane, from the same volume, must confirm the center's; with a left and a right
neighbour one that confirms is enough, DERS's occlusion rule); its segment planes and
fattening trim, with its tolerances in pixels of motion in the neighbours
(:attr:`DersEstimator.pixels_per_level`); its clean-up
(:func:`mvtools.depth.refine.fill_invalid`: the pixels no neighbour sees or confirms
filled from the background side, a colour-weighted median around depth edges); and
DERS's temporal enhancement.

Measured through DERS configurations of the Middlebury pairs
(:func:`mvtools.datasets.write_middlebury_ders_case`, ``benchmarks/bench_ders.py``,
SearchLevel the finest within 256 labels, YUV 4:2:0 pictures), bad 1.0 % with ``sgm``,
before (sub-level winners by a parabola through the method's costs, no segment planes)
and after: Tsukuba 4.27 and 2.38, Venus 1.52 and 0.40, Teddy 5.19 and 4.35, Cones 3.37
and 3.10, Art 8.64 and 8.29, Dolls 6.03 and 5.52, Moebius 9.89 and 8.81. The parabola
was the largest loss: on Tsukuba at SearchLevel 1, ``bp``'s raw winners score 5.18
on the grid and 13.5 with it. The price: depths are planes of the search grid (as DERS's
own labels are), so on the synthetic line at SearchLevel 2 90.5 % of the pixels are
within a quarter pixel of the truth instead of 95 % (98.4 % within half a pixel, 98 %
before); a finer SearchLevel gives finer depths.

How DERS's keys are read:

- MatchingMethod 0/1 (disparity shift), 2 (homography) and 4 (epipolar) are all the plane
  sweep: for rectified cameras its homographies are the shifts, in general they follow the
  epipolar lines. 3 (soft-segment) adds to the sweep DERS's soft-segment weighting: each
  pixel's costs averaged over a SoftBlockWidth x SoftBlockHeight block with weights
  ``exp(-distance / SoftDistanceCoeff - colour difference / SoftColorCoeff)``.
- Precision, VerticalPrecision: sub-pixel grid of the neighbours' census signatures
  (the colour term is interpolated at the exact positions); Filter, VerticalFilter:
  bilinear (0) or bicubic (1, and 2 for the AVC filter) interpolation of that grid.
- SmoothingCoefficient scales the smoothness against the data term: the costs are
  multiplied by ``4 / SmoothingCoefficient`` before the method runs, so DERS's default 4
  keeps the balance the methods are tuned for, and 0 is winner-takes-all on the costs.
- ImageSegmentation 1: the stereo-pair mode's ``segmentation``: pixels that no neighbour
  sees or confirms take their colour segment's plane where it explains the segment's
  other pixels, before the background fill (the segment planes themselves always run);
  SegmentationMethod and MaxCluster are not read.
- TemporalEnhancement 1: 8x8 blocks whose mean absolute change of brightness (mean of
  R, G, B) from the previous frame is below Threshold keep the previous frame's depth.
  The depth kept can come from any earlier frame, so the estimator is fed the frames in
  order; :meth:`DersEstimator.refresh` starts afresh (TemporalRefreshPeriod).
- ViewCombination (our own key): ``least-cost``, one sweep over all the neighbours, each
  plane's cost the least of the views that see the point (DERS); ``vote``, the linear
  array mode's rule (:mod:`mvtools.depth.array`) on the sweep's planes: each neighbour
  gives the levels on its own, with its left-right check and the segment planes at its
  own pixels per level, and each pixel takes the level most of them agree on. The least
  cost lets a wide neighbour's costs blur the minimum; the vote lets it refine and
  outvote: Tsukuba's DERS case (``bp``) 1.92 % from views 2 to 4 and 2.00 % with views 1
  and 5, the vote 1.94 and 1.77 %.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numba import njit, prange

from mvtools.depth import METHODS, bp
from mvtools.depth.array import majority_vote
from mvtools.depth.bp import bp_strips
from mvtools.depth.graphcut import graphcut_levels
from mvtools.depth.local import LevelSlices, local_levels, soft_segment_aggregate
from mvtools.depth.options import DEFAULT_METHOD
from mvtools.depth.oversegment import plane_segments
from mvtools.depth.plane_selection import refine_on_segment_planes
from mvtools.depth.planesweep import plane_sweep_cost, sweep_homographies
from mvtools.depth.refine import fill_invalid
from mvtools.depth.sgm import sgm_strips
from mvtools.geometry.camera import Camera
from mvtools.geometry.depth import depth_sign, ders_depth_range, facing_camera
from mvtools.params import DersParams

__all__ = ["TEMPORAL_BLOCK", "DersEstimator", "Neighbour"]

#: Block size (pixels) of TemporalEnhancement's static test.
TEMPORAL_BLOCK = 8

#: Methods whose volume comes a strip of rows at a time, never whole.
_STRIPS = {"sgm": sgm_strips, "bp": bp_strips}

#: Methods whose volume comes a few levels at a time, never whole, from costs read a few
#: levels at a time.
_LEVELWISE = {"local": local_levels, "graphcut": graphcut_levels}

#: SmoothingCoefficient at which the methods run with their own tuning (DERS's default).
_NEUTRAL_SMOOTHING = 4.0


@dataclass(frozen=True)
class Neighbour:
    """A neighbour view's camera and side of the center: ``"left"`` or ``"right"`` for
    the configuration's LeftCameraName and RightCameraName, which BaselineBasis refers
    to, or None for a further view, which only adds its costs to the sweep (or its vote,
    ViewCombination vote)."""

    camera: Camera
    side: str | None = None

    def __post_init__(self):
        if self.side not in ("left", "right", None):
            raise ValueError(f"side must be 'left', 'right' or None, got {self.side!r}")


class DersEstimator:
    """Depth of a center view from its neighbours, frame after frame.

    Parameters
    ----------
    params : DersParams
    center : Camera
    neighbours : sequence of Neighbour
        The views matched: those MatchDirection selects, at most one per side, and any
        further views (side None).
    method : str
        Key of :data:`mvtools.depth.METHODS`.

    Attributes
    ----------
    center : Camera
        The center camera, turned to face a negative range
        (:func:`mvtools.geometry.depth.facing_camera`); likewise the neighbours'.
    inverse_depths : ndarray of float64, shape (D,)
        ``1/z`` of the planes searched along the facing center camera's axis (world
        z for DepthType 1), far to near.
    depth_range : (float, float)
        (Znear, Zfar) that the output depth values mean, signed as given:
        NearestDepthValue and FarthestDepthValue, or the z of the disparity range's
        ends (Zfar may be inf); :class:`mvtools.geometry.depth.DepthCoding` of it
        writes :meth:`frame`'s depths.
    pixels_per_level : float
        Pixels that one level moves a point in the left or right neighbour (the larger
        mean over the levels): the refinement's unit, as a pixel of disparity is the stereo-pair
        mode's.

    Raises
    ------
    ValueError
        No neighbour, two on one side, an unknown method, a BaselineBasis view that is
        not matched, a search range of fewer than two planes or reaching behind the
        cameras, DepthType 1 without a z search range (DersParams itself refuses the
        DepthEstimationMode values other than 0).
    """

    def __init__(
        self,
        params: DersParams,
        center: Camera,
        neighbours: Sequence[Neighbour],
        *,
        method: str = DEFAULT_METHOD,
    ):
        if not neighbours:
            raise ValueError("depth estimation needs a left or a right neighbour")
        sides = [neighbour.side for neighbour in neighbours if neighbour.side is not None]
        if len(set(sides)) != len(sides):
            raise ValueError(f"at most one left and one right neighbour, got sides {sides}")
        if method not in METHODS:
            raise ValueError(f"unknown method {method!r}; known methods: {', '.join(METHODS)}")
        self.params = params
        # A negative range (or world planes behind a camera) turns the cameras round to
        # face the scene (mvtools.geometry.depth): depths along their axes are positive.
        facing_range = params.depth_range or params.search_depth_range
        if facing_range is not None:
            center = facing_camera(center, facing_range, depth_type=params.depth_type)
            neighbours = [
                Neighbour(
                    facing_camera(n.camera, facing_range, depth_type=params.depth_type), n.side
                )
                for n in neighbours
            ]
        self.center = center
        self.neighbours = list(neighbours)
        self.method = method
        self.inverse_depths = self._search_planes()
        self.depth_range = self._output_range()
        self._shifts = _rectified_shifts(self.center, self.neighbours, self.inverse_depths, params)
        self.pixels_per_level = _pixels_per_level(
            self.center, self.neighbours, self.inverse_depths, params.depth_type
        )
        # ViewCombination vote: the neighbours nearest first, each with its pixels per level
        self._voters = []
        if params.view_combination == "vote":
            for index in _nearest_first(center, neighbours):
                step = _pixels_per_level(
                    center, [neighbours[index]], self.inverse_depths, params.depth_type
                )
                self._voters.append((index, step))
        self._previous: tuple[np.ndarray, np.ndarray] | None = None

    # ------------------------------------------------------------------ planes and ranges

    def _basis(self) -> tuple[float, float]:
        """``(f B, offset)`` of the BaselineBasis view: ``1/z = (d + offset) / (f B)``."""
        basis = self.params.baseline_basis
        baselines = {
            n.side: float(np.linalg.norm(n.camera.t - self.center.t))
            for n in self.neighbours
            if n.side is not None
        }
        if not baselines:
            raise ValueError(
                "a disparity search range needs a left or right neighbour for "
                "its baseline (BaselineBasis); give the z search range "
                "(NearestSearchDepthValue, FarthestSearchDepthValue) instead"
            )
        if basis in (2, 3):
            side = "left" if basis == 2 else "right"
            if side not in baselines:
                raise ValueError(
                    f"BaselineBasis {basis} refers to the {side} view, which is not matched"
                )
        else:
            pick = min if basis == 0 else max
            side = pick(baselines, key=baselines.get)
        if baselines[side] == 0:
            raise ValueError(f"the {side} camera is at the center camera's position: no baseline")
        camera = next(n.camera for n in self.neighbours if n.side == side)
        # Principal-point offset of a parallel pair, disparity measured left x - right x.
        offset = self.center.cx - camera.cx if side == "left" else camera.cx - self.center.cx
        return self.center.fx * baselines[side], offset

    def _search_planes(self) -> np.ndarray:
        params = self.params
        if params.search_depth_range is not None:
            nearest, farthest = params.search_depth_range
            # Inverse depths along the facing cameras' axes (world z for DepthType 1).
            sign = depth_sign(nearest, farthest) if params.depth_type == 0 else 1
            return sign * np.linspace(1.0 / farthest, 1.0 / nearest, params.number_of_depth_steps)
        if params.depth_type == 1:
            raise ValueError(
                "DepthType 1 needs the search range in z (NearestSearchDepthValue, "
                "FarthestSearchDepthValue)"
            )
        low = params.minimum_value_of_disparity_search_range
        high = params.maximum_value_of_disparity_search_range
        steps = round((high - low) * params.search_level)
        if steps < 1:
            raise ValueError(
                f"disparity search range [{low}, {high}] at SearchLevel "
                f"{params.search_level:g} holds a single disparity: nothing to search"
            )
        focal_baseline, offset = self._basis()
        disparities = low + np.arange(steps + 1) / params.search_level
        if disparities[0] + offset < 0:
            raise ValueError(
                f"disparity {low} with principal-point offset {offset:g} puts the "
                "farthest plane behind the cameras"
            )
        return (disparities + offset) / focal_baseline

    def _output_range(self) -> tuple[float, float]:
        params = self.params
        if params.depth_range is not None:
            return params.depth_range
        focal_baseline, offset = self._basis()
        return ders_depth_range(
            focal_baseline,
            1.0,
            params.minimum_value_of_disparity_range,
            params.maximum_value_of_disparity_range,
            offset=offset,
        )

    # ------------------------------------------------------------------ frames

    def frame(self, center: np.ndarray, neighbours: Sequence[np.ndarray]) -> np.ndarray:
        """Depth of one frame of the center view.

        Parameters
        ----------
        center : ndarray, shape (H, W, 3)
            The center view, RGB on an 8-bit scale (0..255, float allowed).
        neighbours : sequence of ndarray, each shape (H, W, 3)
            The neighbours' views of the same instant, in the order of the constructor.

        Returns
        -------
        ndarray of float64, shape (H, W)
            Depth ``z`` along the facing center camera's axis (DepthType 0) or world ``Z``
            (DepthType 1); ``inf`` for the plane at infinity.
        """
        center = np.asarray(center, np.float32)
        if self.params.view_combination == "vote":
            level = self._voted_levels(center, neighbours)
        else:
            shifts = None if self._shifts is None else list(self._shifts)
            chosen, seen, cost = self._matched_levels(
                center, neighbours, self.neighbours, shifts, self.pixels_per_level
            )
            segments = plane_segments(center)
            level, valid = _segment_levels(
                chosen, seen, cost, center, segments, self.pixels_per_level
            )
            del cost
            level = self._filled(level, valid, center, segments)
        inverse = np.interp(level, np.arange(self.inverse_depths.size), self.inverse_depths)
        with np.errstate(divide="ignore"):
            z = 1.0 / inverse
        if self.params.temporal_enhancement:
            z = self._temporal(z, center)
        return z

    def _matched_levels(
        self,
        center: np.ndarray,
        images: Sequence[np.ndarray],
        neighbours: Sequence[Neighbour],
        shifts: list[np.ndarray] | None,
        step: float,
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The levels the method chooses from the sweep over ``neighbours`` (their
        ``images``), the pixels some neighbour sees and, for rectified neighbours (their
        ``shifts``), confirms, and the sweep's cost volume. ``step``: pixels of motion per
        level, the unit of the method's smoothness."""
        params = self.params
        sweep = plane_sweep_cost(
            center,
            images,
            self.center,
            [n.camera for n in neighbours],
            self.inverse_depths,
            depth_type=params.depth_type,
            precision=(params.precision, params.vertical_precision),
            filter="linear" if params.filter == 0 else "cubic",
            block=params.matching_block,
        )
        cost = sweep.cost
        if params.matching_method == 3:
            cost = soft_segment_aggregate(
                cost,
                center,
                block=(params.soft_block_width, params.soft_block_height),
                distance_coeff=params.soft_distance_coeff,
                colour_coeff=params.soft_color_coeff,
            )
        shifts = shifts or []
        if params.smoothing_coefficient > 0:
            scale = _NEUTRAL_SMOOTHING / params.smoothing_coefficient
            smoothness = _smoothness_in_pixels(self.method, step)
            if self.method in _STRIPS:
                # at the neutral smoothing no scaled copy of the volume is made
                scaled = cost * np.float32(scale) if scale != 1 else cost
                level, own = _streamed_winners(
                    _STRIPS[self.method](scaled, center, **smoothness), shifts
                )
            else:
                # neither the scaled costs nor the method's volume is ever whole; the
                # segment planes read the costs afterwards
                chunks = _LEVELWISE[self.method](
                    _scaled_levels(cost, scale), cost.shape[2], center, **smoothness
                )
                level, own = _levelwise_winners(chunks, cost.shape[:2], cost.shape[2], shifts)
        else:
            level, own = _winners(cost, shifts)
        # the levels of the search grid, as the stereo-pair mode keeps integer disparities:
        # a parabola through a method's costs is no sub-pixel measurement
        chosen = np.clip(np.rint(level).astype(np.intp), 0, self.inverse_depths.size - 1)
        seen = sweep.seen_at(chosen)
        del sweep
        if shifts:
            seen &= _confirmed_by_a_neighbour(chosen, own, shifts)
        return chosen, seen, cost

    def _voted_levels(self, center: np.ndarray, images: Sequence[np.ndarray]) -> np.ndarray:
        """ViewCombination vote, the linear-array mode's rule
        (:func:`mvtools.depth.array.estimate_array_disparity`) on the search grid: each
        neighbour alone gives the center's levels, with its left-right check when
        rectified and refined by the segment planes at its own pixels per level; each
        pixel takes the level most neighbours agree on within a pixel of motion in the
        left or right neighbour (:attr:`pixels_per_level`), the nearest neighbour's first
        on a tie (the one to the right before the one to the left), or rather the nearest
        level to the mean of the neighbours that agree with it weighted by their squared
        pixels per level (the inverse of the variance of a level that is uncertain by a
        pixel); then the fill. The neighbours are matched one after the other, so that
        one cost volume is held at a time, as in the least-cost sweep: a DERS run is one
        of many that ``make -j`` or ``mvtools run`` start a core each."""
        segments = plane_segments(center)
        levels, valid, precision = [], [], []
        for index, step in self._voters:
            shifts = None if self._shifts is None else [self._shifts[index]]
            chosen, seen, cost = self._matched_levels(
                center, [images[index]], [self.neighbours[index]], shifts, step
            )
            level, confirmed = _segment_levels(chosen, seen, cost, center, segments, step)
            del cost
            levels.append(level)
            valid.append(confirmed)
            precision.append(step**2)
        levels, valid = np.stack(levels), np.stack(valid)
        level, confirmed = majority_vote(
            levels, valid, 1.0 / self.pixels_per_level, weights=precision, whole=True
        )
        return self._filled(level, confirmed, center, segments)

    def refresh(self) -> None:
        """Forget the earlier frames: the next frame is estimated as a first one."""
        self._previous = None

    def fresh_frame(self, index: int) -> int:
        """The last frame at or before frame ``index`` that a run estimates afresh.

        Frame ``index`` comes out as in a run from frame 0 when the estimator is
        :meth:`refresh`-ed and fed the frames from this one on: ``index`` itself
        without TemporalEnhancement, else the last multiple of TemporalRefreshPeriod
        (0 when the period is 0).
        """
        if not self.params.temporal_enhancement:
            return index
        period = self.params.temporal_refresh_period
        return index - index % period if period else 0

    def _filled(
        self, level: np.ndarray, valid: np.ndarray, center: np.ndarray, segments: np.ndarray
    ) -> np.ndarray:
        """Levels with the pixels no neighbour sees or confirms filled by
        :func:`mvtools.depth.refine.fill_invalid` from the background side (from their
        segment's plane first with ImageSegmentation 1), depth edges smoothed, in pixels
        of motion in the neighbours (:attr:`pixels_per_level`)."""
        step = self.pixels_per_level
        disparity = fill_invalid(
            level * np.float32(step),
            valid,
            center,
            segments=segments if self.params.image_segmentation else None,
        )
        # A row that no neighbour sees at all has no background to take: farthest plane.
        return np.where(np.isnan(disparity), 0.0, disparity / step)

    def _temporal(self, z: np.ndarray, center: np.ndarray) -> np.ndarray:
        luma = center.mean(axis=2)
        previous, self._previous = self._previous, (luma, z)
        if previous is None:
            return z
        change = _block_mean(np.abs(luma - previous[0]), TEMPORAL_BLOCK)
        static = np.repeat(
            np.repeat(change < self.params.threshold, TEMPORAL_BLOCK, axis=0),
            TEMPORAL_BLOCK,
            axis=1,
        )[: z.shape[0], : z.shape[1]]
        kept = np.where(static, previous[1], z)
        self._previous = (luma, kept)
        return kept


def _segment_levels(
    chosen: np.ndarray,
    seen: np.ndarray,
    cost: np.ndarray,
    center: np.ndarray,
    segments: np.ndarray,
    step: float,
) -> tuple[np.ndarray, np.ndarray]:
    """The stereo-pair mode's refinement of the chosen levels, in pixels of motion
    (``step`` per level): colour segments whose robust plane costs about as much as their
    levels take it, fattened foreground next to depth steps falls back onto its segment's
    plane. Returns the levels, back on the search grid (float32), and the pixels kept."""
    disparity = chosen.astype(np.float32) * np.float32(step)
    disparity, valid = refine_on_segment_planes(disparity, seen, segments, cost, center, step=step)
    return np.rint(disparity / step), valid


def _nearest_first(center: Camera, neighbours: Sequence[Neighbour]) -> list[int]:
    """Indices of ``neighbours`` by distance from the center camera, the one to the right
    (positive x of the center camera) first at the same distance."""

    def place(index: int) -> tuple[float, bool]:
        offset = neighbours[index].camera.t - center.t
        right = float((center.R @ offset)[0]) > 0
        return round(float(np.linalg.norm(offset)), 9), not right

    return sorted(range(len(neighbours)), key=place)


def _pixels_per_level(
    center: Camera, neighbours: Sequence[Neighbour], inverse_depths: np.ndarray, depth_type: int
) -> float:
    """How far, in pixels, one level of the search moves the center's principal point in
    the left or right neighbour it moves most (any neighbour when neither is named), on
    average over the levels: the unit in which the refinement's tolerances (a pixel of
    disparity in the stereo-pair mode) are stated. Further views only add their costs,
    as they do not define DERS's disparities either."""
    middle = np.array([center.cx, center.cy, 1.0])
    largest = 0.0
    sided = [neighbour for neighbour in neighbours if neighbour.side is not None]
    for neighbour in sided or neighbours:
        points = (
            sweep_homographies(center, neighbour.camera, inverse_depths, depth_type=depth_type)
            @ middle
        )
        with np.errstate(divide="ignore", invalid="ignore"):
            positions = points[:, :2] / points[:, 2:]
            travel = np.linalg.norm(np.diff(positions, axis=0), axis=1).sum()
        if np.isfinite(travel):
            largest = max(largest, travel / (len(inverse_depths) - 1))
    return largest if largest > 0 else 1.0


#: The ``bp`` method's smoothness, truncated linear in the difference of levels,
#: ``w min(|f_p - f_q|, T)``: its weight ``w`` and truncation ``T`` per pixel of disparity.
_BP_SMOOTHNESS = (bp.SMOOTHING, bp.TRUNCATION)


def _smoothness_in_pixels(method: str, step: float) -> dict[str, float]:
    """Options of ``method`` that charge its smoothness per pixel of disparity, not per
    level of the search grid, so that a depth map costs what it costs in the stereo-pair
    mode whatever the SearchLevel or the number of planes: with ``step`` pixels per
    level, ``w min(step |f_p - f_q|, T)`` is ``(w step) min(|f_p - f_q|, T / step)``, and
    for levels more than ``T`` pixels apart every change of level costs ``w T`` (Potts).

    For ``bp`` alone. Charged per level, its quarter-pixel levels made a one-pixel step
    four times dearer and cut the truncation to one pixel. Through the DERS cases of the
    Middlebury pairs (``benchmarks/bench_ders.py``, bad 1.0 %, per level and in
    pixels, before AD-census's census tolerance): Tsukuba 2.19 and 2.46, Tsukuba 2-3-4 2.02 and 1.92, Venus 0.38 and 0.38,
    Teddy 5.09 and 4.25, Cones 2.88 and 2.70, Art 8.69 and 7.58, Dolls 4.46 and 4.53,
    Moebius 8.71 and 8.60: a mean of 4.30 and 4.05 (at SearchLevel 1 the two are the
    same: Art 7.53). ``graphcut``, the same energy minimised otherwise, lost by it (mean
    4.25 and 4.39: Tsukuba 2.11 and 3.03, Art 8.80 and 7.59, Moebius 8.73 and 9.81), so
    it keeps its weights per level, as ``sgm`` (P1 and P2 per level) does."""
    if method != "bp":
        return {}
    weight, truncation = _BP_SMOOTHNESS
    if truncation / step >= 1:
        return {"smoothing": weight * step, "truncation": truncation / step}
    return {"smoothing": weight * truncation, "truncation": 1.0}


def _rectified_shifts(
    center: Camera, neighbours: Sequence[Neighbour], inverse_depths: np.ndarray, params
) -> np.ndarray | None:
    """Horizontal shift of each plane into each neighbour, shape (N, D), when every
    neighbour is a rectified partner of the center camera (each plane's homography a
    translation along the rows: ``x_neighbour = x + shift``); None otherwise."""
    if params.depth_type != 0:
        return None
    shifts = []
    for neighbour in neighbours:
        homographies = sweep_homographies(center, neighbour.camera, inverse_depths)
        translation = np.zeros_like(homographies)
        translation[:] = np.eye(3)
        translation[:, 0, 2] = homographies[:, 0, 2] / homographies[:, 2, 2]
        if not np.allclose(
            homographies / homographies[:, 2:3, 2:3], translation, atol=1e-9, rtol=0
        ):
            return None
        shifts.append(translation[:, 0, 2])
    return np.array(shifts)


def _winners(volume: np.ndarray, shifts: list[np.ndarray]) -> tuple[np.ndarray, list]:
    """The center's sub-pixel winning level, and each rectified neighbour's own winning
    plane, from one volume: :func:`_levelwise_winners` of all its levels at once."""
    return _levelwise_winners([(0, volume)], volume.shape[:2], volume.shape[2], shifts)


def _streamed_winners(strips, shifts: list[np.ndarray]):
    """:func:`_winners` of a method's volume given a strip of rows at a time
    (:func:`mvtools.depth.sgm.sgm_strips`, :func:`mvtools.depth.bp.bp_strips`), so that
    the volume is never whole: each neighbour's pixel picks among center pixels of its
    own row."""
    level, own = [], [[] for _ in shifts]
    for _, strip in strips:
        strip_level, strip_own = _winners(strip, shifts)
        level.append(strip_level)
        for levels, theirs in zip(own, strip_own):
            levels.append(theirs)
    return np.concatenate(level), [np.concatenate(levels) for levels in own]


def _scaled_levels(cost: np.ndarray, scale: float) -> LevelSlices:
    """Levels ``start`` to ``stop`` of ``cost * float32(scale)`` (the SmoothingCoefficient
    factor), a contiguous copy made a few levels at a time: the same values as slices of
    the whole scaled volume, which is never made."""
    factor = np.float32(scale)
    if scale == 1:
        return lambda start, stop: np.ascontiguousarray(cost[:, :, start:stop])
    return lambda start, stop: cost[:, :, start:stop] * factor


def _levelwise_winners(chunks, shape: tuple[int, int], levels: int, shifts: list[np.ndarray]):
    """:func:`_winners` of a method's volume given a few levels at a time, ``(start,
    chunk)`` in order of level (:func:`mvtools.depth.local.local_levels`,
    :func:`mvtools.depth.graphcut.graphcut_levels`), so that the volume is never whole:
    per pixel a running minimum over the levels for the center, and per rectified
    neighbour a running minimum of the center values at the shifted pixel; bit for bit
    the same levels."""
    rows, cols = shape
    best = np.zeros(shape, np.int64)
    best_cost = np.empty(shape, np.float32)
    below = np.empty(shape, np.float32)
    above = np.empty(shape, np.float32)
    last = np.empty(shape, np.float32)
    shift_table = np.array(shifts, np.float64).reshape(len(shifts), levels)
    neighbour_cost = np.full((len(shifts), rows, cols), np.inf, np.float32)
    own = np.full((len(shifts), rows, cols), -1, np.int64)
    expected = 0
    for start, chunk in chunks:
        if start != expected or chunk.shape[:2] != shape:
            raise ValueError(
                f"chunks must follow level by level over {shape}: got level {start} of "
                f"shape {chunk.shape} after {expected} levels"
            )
        chunk = np.ascontiguousarray(chunk, np.float32)
        _add_levels(
            chunk, start, best, best_cost, below, above, last, shift_table, neighbour_cost, own
        )
        expected += chunk.shape[2]
    if expected != levels:
        raise ValueError(f"chunks gave {expected} levels of {levels}")
    return _winning_levels(best, best_cost, below, above, levels), list(own)


@njit(cache=True, nogil=True, parallel=True)
def _add_levels(chunk, start, best, best_cost, below, above, last, shifts, neighbour_cost, own):
    # Levels start, start + 1, ... of the volume into the running winners. The center
    # keeps, as winner_takes_all reads them, its first level of least cost and the costs
    # of the levels either side of it (below: the level before it, kept when it wins;
    # above: the level after it, met next). A neighbour pixel x keeps the level whose
    # center pixel x - shift (rounded half up) costs least, the first such; the inf it
    # starts from is never strictly beaten by a NaN.
    rows, cols, count = chunk.shape
    for y in prange(rows):
        for x in range(cols):
            for i in range(count):
                k = start + i
                value = chunk[y, x, i]
                if k == 0:
                    best[y, x] = 0
                    best_cost[y, x] = value
                else:
                    if best[y, x] == k - 1:
                        above[y, x] = value
                    if value < best_cost[y, x]:
                        best[y, x] = k
                        best_cost[y, x] = value
                        below[y, x] = last[y, x]
                last[y, x] = value
        for n in range(shifts.shape[0]):
            for x in range(cols):
                for i in range(count):
                    k = start + i
                    source = int(np.floor(x - shifts[n, k] + 0.5))
                    if 0 <= source < cols and chunk[y, source, i] < neighbour_cost[n, y, x]:
                        neighbour_cost[n, y, x] = chunk[y, source, i]
                        own[n, y, x] = k


@njit(cache=True, nogil=True, parallel=True)
def _winning_levels(best, best_cost, below, above, levels):
    # winner_takes_all's parabola through the winner and the levels either side, term
    # for term in the same types: the caller rounds the level, and a tie with the level
    # above gives an offset of exactly 0.5, which np.rint takes to the even level, so
    # the offset decides as well as the winner
    rows, cols = best.shape
    level = np.empty((rows, cols), np.float32)
    for y in prange(rows):
        for x in range(cols):
            winner = best[y, x]
            offset = np.float32(0.0)
            if 0 < winner < levels - 1:
                curvature = below[y, x] - 2 * best_cost[y, x] + above[y, x]
                if curvature > 0 and np.isfinite(curvature):
                    offset = (below[y, x] - above[y, x]) / (2 * curvature)
            level[y, x] = winner + offset
    return level


def _confirmed_by_a_neighbour(
    chosen: np.ndarray, own: list[np.ndarray], shifts: list[np.ndarray]
) -> np.ndarray:
    """Pixels whose plane a rectified neighbour's own choice confirms (the left-right
    check of the stereo-pair mode, from the same volume): the neighbour's pixel where the
    center pixel's point lands takes, of all planes, the one whose center pixel costs
    least (:func:`_levelwise_winners`), and that plane lies within a pixel of shift of
    the center's. With two neighbours one that confirms is enough: a point hidden from
    one side is seen from the other (DERS's occlusion rule)."""
    consistent = np.zeros(chosen.shape, bool)
    for levels, shift in zip(own, shifts):
        consistent |= _confirmed(chosen, levels, shift)
    return consistent


def _confirmed(chosen: np.ndarray, own: np.ndarray, shift: np.ndarray) -> np.ndarray:
    rows, cols = chosen.shape
    target = np.floor(np.arange(cols)[None, :] + shift[chosen] + 0.5).astype(np.int64)
    inside = (target >= 0) & (target < cols)
    theirs = own[np.arange(rows)[:, None], np.clip(target, 0, cols - 1)]
    agree = np.abs(shift[chosen] - shift[np.maximum(theirs, 0)]) <= 1.0
    return inside & (theirs >= 0) & agree


def _block_mean(values: np.ndarray, block: int) -> np.ndarray:
    """Mean over ``block x block`` tiles (partial tiles at the right and bottom edges)."""
    rows, cols = values.shape
    tiles_y, tiles_x = -(-rows // block), -(-cols // block)
    sums = np.add.reduceat(
        np.add.reduceat(values, np.arange(0, rows, block), axis=0),
        np.arange(0, cols, block),
        axis=1,
    )
    heights = np.minimum(block, rows - np.arange(tiles_y) * block)
    widths = np.minimum(block, cols - np.arange(tiles_x) * block)
    return sums / (heights[:, None] * widths[None, :])
