"""Disparity of one view of a dense linear array, from every view jointly.

With many cameras on a line, registered so that a scene point stays on one row in every
view, the row through the stack of views (an epipolar-plane image) shows each point as a
line whose slope is its disparity per unit of baseline; where a nearer line crosses a
farther one, the farther point is hidden in the views beyond the crossing ("Multiview
video: acquisition, processing, compression, and virtual view rendering", section
1.4.3.2). :func:`estimate_array_disparity` reads those lines through the chosen view
pair by pair: each other view gives the chosen view's disparity with its left-right
check (:func:`mvtools.depth.stereo.checked_disparity`, the stereo-pair chain at that
pair's baseline), the check marking the pixels that view does not see, where a nearer
line cuts the point's; beyond the nearest view on each side, the chosen view's map is
only trimmed of fattening, not refined on its segment planes, and checked against the
other view's map as the method leaves it, which spares over a third of such a pair's
time, and where such views are, the nearest views' maps are only trimmed of fattening
for the check, their errors being outvoted by the farther views. A pixel then takes the
value that most of the views that see it agree on, so an occlusion on one side of the
chosen view is outvoted by the views on the other side; its value is the mean of the
views that agree, weighted by their precision, so wider baselines, whose disparities are
finer per unit of baseline, refine the nearest pairs. Pixels no view confirms are filled
as in the stereo-pair mode (:func:`mvtools.depth.refine.fill_invalid`).
"""

from __future__ import annotations

import functools
import math
import os
from collections.abc import Callable, Sequence
from concurrent.futures import ThreadPoolExecutor, as_completed
from typing import TypeVar

import numba
import numpy as np

from mvtools.depth.cost import ad_census_signatures
from mvtools.depth.oversegment import plane_segments
from mvtools.depth.refine import fill_invalid
from mvtools.depth.stereo import checked_disparity

__all__ = ["estimate_array_disparity", "majority_vote", "side_by_side"]

T = TypeVar("T")
R = TypeVar("R")


def estimate_array_disparity(
    views: Sequence[np.ndarray],
    *,
    reference: int,
    max_disparity: float,
    min_disparity: float = 0,
    positions: Sequence[float] | None = None,
    method: str = "bp",
    cost: str = "ad-census",
    segment_planes: bool = True,
    subpixel: bool = False,
    tolerance: float = 1.0,
    progress: Callable[[int, int], None] | None = None,
) -> np.ndarray:
    """Disparity per unit of baseline of ``views[reference]`` from all the views of a line.

    Parameters
    ----------
    views : sequence of ndarray, shape (H, W, 3) uint8 RGB or (H, W) grey
        Two or more rectified views of the same size on a line, in the order of
        ``positions``: a point at disparity ``d`` of the reference view is seen in
        view ``i`` at ``x - d * (positions[i] - positions[reference])``, so views to
        the right of the reference have larger positions.
    reference : int
        Index in ``views`` of the view whose disparity is estimated.
    max_disparity, min_disparity : float
        Disparities searched, per unit of ``positions``; each pair searches them
        times its baseline, rounded outwards to whole pixels.
    positions : sequence of float, optional
        Each view's place on the line, distinct; by default ``0, 1, 2, ...``: equal
        steps, the disparity being that of neighbouring views.
    method, cost, segment_planes
        The stereo-pair chain of each pair (:func:`mvtools.depth.estimate_disparity`).
    subpixel : bool
        Keep each pixel's disparity as the weighted mean gives it (see Notes), finer
        than a pixel per unit of ``positions`` wherever views wider apart than that
        unit agree, rather than rounded to whole pixels per unit (which Middlebury's
        integer ground truths favour).
    tolerance : float
        Largest difference, per unit of baseline, between two views' disparities that
        agree.
    progress : callable, optional
        ``progress(done, total)`` as each pair is matched.

    Returns
    -------
    ndarray of float32, shape (H, W)
        Disparity per unit of ``positions``, whole numbers unless ``subpixel``; NaN
        only on rows where no view confirmed any pixel.

    Notes
    -----
    Each pixel's candidates are the disparities of the pairs whose left-right check
    it passes; each candidate counts the other candidates within ``tolerance``, and
    the pixel takes the one with the most, the nearest view's first on a tie (the
    right one's before the left one's at the same distance), if another view
    confirms it or it is the only candidate (:func:`majority_vote`). Its value is the
    mean of the candidates within ``tolerance`` of it weighted by their squared
    baselines: a pair's whole-pixel disparity is uncertain by a pixel over its
    baseline, and these weights are the inverse of that variance. Then it is rounded
    to a whole number, halfway towards the candidate agreed on, unless ``subpixel``.

    The pairs beyond the nearest view on each side confirm or outvote the nearest
    pairs rather than decide alone, and are refined less: the chosen view's map is
    trimmed of fattening but its segment planes are left to the nearest pairs
    (``refine="trim"``), and it is checked against the other view's map as the method
    leaves it (``refine_other="none"``). Checked against the fully refined map as the
    nearest pairs were, Tsukuba's five views took 0.60 s instead of 0.53 on two cores,
    and scored 1.32 % instead of 1.36; Cones 2.03 instead of 2.05; the synthetic line
    0.28, 0.23, 0.24 instead of 0.26, 0.21, 0.21. Where such pairs are, the nearest
    pairs are checked against the other view's map trimmed of fattening but not refined
    on its segment planes (``refine_other="trim"``), the farther views outvoting what
    that lets through: 7 to 20 % off the five views' time, Tsukuba 1.360 % instead of
    1.359 (one pixel), Cones 2.048 instead of 2.050, the synthetic line 0.258, 0.210,
    0.210 instead of 0.264, 0.214, 0.212. The nearest views alone keep the full check:
    trimmed only, Tsukuba's views 2 to 4 score 1.77 instead of 1.48. Leaving the
    farther pairs' own segment planes out took another 0.04 to 0.08 s off the five
    views (0.45 to 0.47 s), for Tsukuba 1.380 % instead of 1.360 (18 pixels), Cones
    2.034 instead of 2.048 (6.750 instead of 6.754 for view 6 from views 6, 4 and 2,
    all known pixels), the synthetic line 0.236, 0.189, 0.191 instead of 0.258, 0.210,
    0.210, but slightly worse in most of 15 other cases of the line (cameras 8 cm
    apart, other textures: 9 worse by at most 0.02, 4 better). Trimming the other
    view's map too scored better than both in most of these cases (Tsukuba 1.357) but
    gave back more time than the planes saved. (The figures of this paragraph are
    from before AD-census counted only the neighbours like the centre in colour.)

    Bad 1.0 % (``bp``): Tsukuba's view 3 (all known pixels) 1.29 from view 4 alone
    (:func:`mvtools.depth.estimate_disparity`), 1.24 from views 2 to 4, 1.19 from all
    five; Cones' view 2 (non-occluded pixels) 2.28 from view 6 alone, 1.82 from views
    2, 4 and 6 at ``positions`` 0, 0.5, 1 (20.7 when the nearest pair's value was
    taken as it is: whole pixels of the pair 2-4 are two of the ground truth's).
    Before AD-census counted only the neighbours like the centre in colour
    (:func:`mvtools.depth.cost.ad_census_cost`): 1.56, 1.48, 1.38; 2.47 and 2.03.

    The time is that of one stereo-pair chain per other view, run side by side on the
    cores (:func:`side_by_side`), after the reference's colour segments and every view's
    census signatures (:func:`mvtools.depth.cost.ad_census_signatures`), made once for
    all the pairs: five views of Tsukuba 1.6 to 1.8 times one pair's time on two cores,
    timed in turn (1.1 to 1.2 as whole ``mvtools estimate-depth`` runs, start-up
    included); as many cost volumes are held at once as cores work.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> scene = rng.integers(0, 256, (32, 80, 3)).astype(np.uint8)
    >>> views = [np.ascontiguousarray(np.roll(scene, -2 * i, axis=1)) for i in range(3)]
    >>> disparity = estimate_array_disparity(
    ...     views, reference=1, max_disparity=4, segment_planes=False
    ... )
    >>> float(np.median(disparity))
    2.0
    """
    views = [np.asarray(view) for view in views]
    if len(views) < 2:
        raise ValueError(f"need at least two views, got {len(views)}")
    if not 0 <= reference < len(views):
        raise ValueError(f"reference {reference} is not an index of the {len(views)} views")
    positions = np.arange(len(views), dtype=np.float64) if positions is None else positions
    positions = np.asarray(positions, np.float64)
    if positions.shape != (len(views),) or not np.all(np.isfinite(positions)):
        raise ValueError(f"need one finite position per view ({len(views)}), got {positions}")
    if len(np.unique(positions)) != len(positions):
        raise ValueError(f"positions must be distinct, got {positions.tolist()}")
    if min_disparity >= max_disparity:
        raise ValueError(f"empty disparity range {min_disparity}..{max_disparity}")
    chosen = views[reference]
    # nearest views first, the right one before the left one at the same distance
    others = sorted(
        (index for index in range(len(views)) if index != reference),
        key=lambda index: (
            abs(positions[index] - positions[reference]),
            positions[index] < positions[reference],
        ),
    )

    # the reference's colour segments and every view's census signatures once, rather
    # than once per pair, a core each: mostly serial work apiece
    preparations = [functools.partial(plane_segments, chosen)] if segment_planes else []
    if cost == "ad-census":
        preparations += [functools.partial(ad_census_signatures, view) for view in views]
    prepared = side_by_side(lambda prepare: prepare(), preparations)
    segments = prepared.pop(0) if segment_planes else None
    signatures = prepared or None
    on_the_right = [positions[index] > positions[reference] for index in others]
    nearest_on_each_side = {others[on_the_right.index(side)] for side in set(on_the_right)}
    # views beyond the nearest outvote what a lighter check of the nearest lets through
    nearest_check = "trim" if len(others) > len(nearest_on_each_side) else "planes"

    def pair_disparity(index: int) -> tuple[np.ndarray, np.ndarray]:
        baseline = positions[index] - positions[reference]
        scale = abs(baseline)
        nearest = index in nearest_on_each_side
        pair = (reference, index) if baseline > 0 else (index, reference)
        disparity, consistent = checked_disparity(
            *(views[view] for view in pair),
            max_disparity=math.ceil(max_disparity * scale),
            min_disparity=math.floor(min_disparity * scale),
            method=method,
            cost=cost,
            segment_planes=segment_planes,
            view="left" if baseline > 0 else "right",
            segments=segments,
            signatures=None if signatures is None else [signatures[view] for view in pair],
            refine="planes" if nearest else "trim",
            refine_other=nearest_check if nearest else "none",
        )
        return disparity / np.float32(scale), consistent

    candidates, valid = zip(
        *side_by_side(
            pair_disparity,
            others,
            cost=lambda index: abs(positions[index] - positions[reference]),
            progress=progress,
        )
    )
    baselines = np.abs(positions[others] - positions[reference])
    disparity, confirmed = majority_vote(
        np.stack(candidates),
        np.stack(valid),
        tolerance,
        weights=baselines**2,
        whole=not subpixel,
    )
    return fill_invalid(disparity, confirmed, chosen)


def side_by_side(
    function: Callable[[T], R],
    items: Sequence[T],
    *,
    cost: Callable[[T], float] | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> list[R]:
    """``[function(item) for item in items]``, the calls a core each, with
    ``progress(done, total)`` in the caller's thread as each call returns.

    The calls run side by side where numba's threading layer takes kernels from several
    threads at once (OpenMP, not the workqueue fallback), started first by a trivial
    kernel; the dearest by ``cost`` start first, so that no long call starts last. The
    depth chains leave cores idle (Tsukuba's four pairs: 1.2 s with the first alone and
    the others two at a time, 0.8 to 0.9 s all two at a time, the widest first), at the
    price of a cost volume per call at work.

    Examples
    --------
    >>> calls = []
    >>> side_by_side(
    ...     lambda value: value * value,
    ...     [1, 2, 3],
    ...     cost=lambda value: value,
    ...     progress=lambda done, total: calls.append((done, total)),
    ... )
    [1, 4, 9]
    >>> calls
    [(1, 3), (2, 3), (3, 3)]
    """
    report = progress or (lambda done, total: None)
    workers = min(os.cpu_count() or 1, len(items))
    if workers < 2 or _started_threading_layer() != "omp":
        results = []
        for item in items:
            results.append(function(item))
            report(len(results), len(items))
        return results
    order = range(len(items))
    if cost is not None:
        order = sorted(order, key=lambda index: -cost(items[index]))
    threads = max(1, numba.get_num_threads() // workers)

    def on_its_cores(item: T) -> R:
        # numba's thread count is per calling thread: a call's kernels share out only
        # its own cores, instead of each asking for all of them and the OpenMP workers
        # of one spinning on the cores where another's compute
        numba.set_num_threads(threads)
        return function(item)

    with ThreadPoolExecutor(workers) as pool:
        futures = {index: pool.submit(on_its_cores, items[index]) for index in order}
        for done, _ in enumerate(as_completed(futures.values()), start=1):
            report(done, len(items))
        return [futures[index].result() for index in range(len(items))]


@functools.cache
def _started_threading_layer() -> str:
    # numba names its threading layer once a parallel kernel has run
    _parallel_sum(np.ones(2))
    return numba.threading_layer()


@numba.njit(cache=True, parallel=True)
def _parallel_sum(values):
    total = 0.0
    for index in numba.prange(values.size):
        total += values[index]
    return total


def majority_vote(
    candidates: np.ndarray,
    valid: np.ndarray,
    tolerance: float,
    *,
    weights: Sequence[float] | None = None,
    whole: bool = False,
) -> tuple[np.ndarray, np.ndarray]:
    """Each pixel's value that most of its valid candidates agree on.

    Parameters
    ----------
    candidates : ndarray, shape (N, H, W)
        Each view's value per pixel, in order of preference on a tie.
    valid : ndarray of bool, shape (N, H, W)
        Which candidates count.
    tolerance : float
        Largest difference between two candidates that agree.
    weights : sequence of float, optional
        One per candidate: the value becomes the mean of the valid candidates within
        ``tolerance`` of the one agreed on, weighted so (the inverse of each one's
        variance gives the most precise mean).
    whole : bool
        Round the value to a whole number, halfway to the one nearer the candidate
        agreed on.

    Returns
    -------
    value : ndarray, shape (H, W)
        The valid candidate with the most others within ``tolerance``, the first on a
        tie (the first candidate where none is valid); or the weighted mean around it.
    confirmed : ndarray of bool, shape (H, W)
        Where another candidate agrees with it, or it is the only valid one.

    Examples
    --------
    >>> candidates = np.array([3.0, 7.0, 7.5]).reshape(3, 1, 1)
    >>> value, confirmed = majority_vote(candidates, np.ones((3, 1, 1), bool), 1.0)
    >>> float(value[0, 0]), bool(confirmed[0, 0])
    (7.0, True)
    >>> value, _ = majority_vote(candidates, np.ones((3, 1, 1), bool), 1.0, weights=[1, 1, 3])
    >>> float(value[0, 0])
    7.375
    >>> value, _ = majority_vote(
    ...     candidates, np.ones((3, 1, 1), bool), 1.0, weights=[1, 1, 1], whole=True
    ... )
    >>> float(value[0, 0])
    7.0
    """
    candidates = np.asarray(candidates)
    valid = np.asarray(valid, bool)
    if valid.shape != candidates.shape or candidates.ndim != 3:
        raise ValueError(
            f"need (N, H, W) candidates and valid flags of one shape, got "
            f"{candidates.shape} and {valid.shape}"
        )
    weighted = weights is not None
    weights = np.asarray(weights if weighted else np.ones(len(candidates)), np.float64)
    if weights.shape != (len(candidates),):
        raise ValueError(f"need one weight per candidate ({len(candidates)}), got {weights.shape}")
    value, confirmed = _vote(
        candidates,
        valid,
        candidates.dtype.type(tolerance),
        weights,
        weighted,
        whole,
    )
    return value.astype(candidates.dtype), confirmed


@numba.njit(cache=True, nogil=True, parallel=True)
def _vote(candidates, valid, tolerance, weights, weighted, whole):
    # majority_vote pixel by pixel: the candidate with the most valid others within
    # tolerance (the first on a tie), then the weighted mean of those around it
    count, rows, cols = candidates.shape
    value = np.empty((rows, cols), np.float64)
    confirmed = np.empty((rows, cols), np.bool_)
    for y in numba.prange(rows):
        for x in range(cols):
            best, best_support, valid_count = 0, -1, 0
            for i in range(count):
                if not valid[i, y, x]:
                    continue
                valid_count += 1
                support = -1
                for j in range(count):
                    if (
                        valid[j, y, x]
                        and abs(candidates[j, y, x] - candidates[i, y, x]) <= tolerance
                    ):
                        support += 1
                if support > best_support:
                    best, best_support = i, support
            agreed = np.float64(candidates[best, y, x])
            confirmed[y, x] = best_support >= 1 or valid_count == 1
            result = agreed
            if weighted:
                total = 0.0
                weighted_sum = 0.0
                for j in range(count):
                    if (
                        valid[j, y, x]
                        and abs(candidates[j, y, x] - candidates[best, y, x]) <= tolerance
                    ):
                        total += weights[j]
                        weighted_sum += weights[j] * candidates[j, y, x]
                if total > 0:
                    result = weighted_sum / total
            if whole:
                below = np.floor(result)
                above_half = result - below > 0.5 or (result - below == 0.5 and agreed > result)
                result = below + above_half
            value[y, x] = result
    return value, confirmed
