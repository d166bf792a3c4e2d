"""Semi-global matching (Hirschmueller 2008): the cost volume aggregated along 8 image
paths with a small penalty P1 for 1-pixel disparity changes and a larger one P2, lowered
across image edges, for jumps; winner-takes-all with a parabola fit for sub-pixel values."""

from __future__ import annotations

import numba
import numpy as np
from numba import njit, prange

__all__ = ["PATHS_8", "aggregate_paths", "sgm_volume", "winner_takes_all"]

# (dy, dx) steps of the 8 paths: each pixel's cost is smoothed along the line it came from.
PATHS_8 = ((0, 1), (0, -1), (1, 0), (-1, 0), (1, 1), (1, -1), (-1, 1), (-1, -1))


@njit(cache=True, nogil=True, inline="always")
def _path_step(cost, total, y, x, previous, p, current, c, p1, p2):
    # L(x, d) = C(x, d) + min(L(x-r, d), L(x-r, d+-1) + P1, min L(x-r) + P2) - min L(x-r),
    # with L(x-r) = previous[p] and the result written to current[c] and added to total.
    levels = cost.shape[2]
    best_previous = previous[p, 0]
    for k in range(1, levels):
        best_previous = min(best_previous, previous[p, k])
    jump = best_previous + p2
    for k in range(levels):
        value = min(previous[p, k], jump)
        if k > 0:
            value = min(value, previous[p, k - 1] + p1)
        if k < levels - 1:
            value = min(value, previous[p, k + 1] + p1)
        value += cost[y, x, k] - best_previous
        current[c, k] = value
        total[y, x, k] += value


@njit(cache=True, nogil=True, inline="always")
def _edge_penalty(guide, y, x, y0, x0, p1, p2, edge_scale):
    # Hirschmueller's P2 / |dI|, kept finite and never below P1.
    return max(p1, p2 / (np.float32(1.0) + abs(guide[y, x] - guide[y0, x0]) / edge_scale))


@njit(cache=True, nogil=True, inline="always")
def _path_start(cost, total, y, x, current, c):
    for k in range(cost.shape[2]):
        current[c, k] = cost[y, x, k]
        total[y, x, k] += cost[y, x, k]


@njit(cache=True, nogil=True, parallel=True)
def _aggregate_rows(cost, guide, dx, p1, p2, edge_scale, total):
    rows, cols, levels = cost.shape
    for y in prange(rows):
        buffers = np.empty((2, levels), np.float32)
        x = 0 if dx > 0 else cols - 1
        _path_start(cost, total, y, x, buffers, 0)
        for i in range(1, cols):
            x += dx
            _path_step(
                cost,
                total,
                y,
                x,
                buffers,
                (i - 1) % 2,
                buffers,
                i % 2,
                p1,
                _edge_penalty(guide, y, x, y, x - dx, p1, p2, edge_scale),
            )


#: Fewest path lines per parallel task of :func:`_aggregate_sweep`; tasks are wider
#: on large frames (four per thread), as longer runs of a row in memory are faster.
_MIN_BAND = 32


@njit(cache=True, nogil=True, parallel=True)
def _aggregate_sweep(cost, guide, dy, dx, p1, p2, edge_scale, total, band_width):
    # A path with a vertical step is a set of lines, pixel (y, x) on line c = x - dx * i
    # with i the row's place in path order; a pixel depends only on the pixel before it
    # on its line. Bands of lines are independent, so the whole path is ONE parallel
    # region: a region per row (191 of them per path on a 256x192 frame) ends in a
    # barrier that waits for a thread the scheduler has parked whenever other
    # processes share the cores, and that made a frame 10 to 250 times slower on a
    # busy machine. Each band walks its rows in path order, its pixels of a row
    # contiguous; the sums are the row-by-row ones, in the same order, whatever the
    # band width.
    rows, cols, levels = cost.shape
    first = min(0, -dx * (rows - 1))
    lines = cols + abs(dx) * (rows - 1)
    for band in prange(-(-lines // band_width)):
        c0 = first + band * band_width
        width = min(band_width, first + lines - c0)
        previous = np.empty((width, levels), np.float32)
        current = np.empty((width, levels), np.float32)
        for i in range(rows):
            y = i if dy > 0 else rows - 1 - i
            for x in range(max(0, c0 + dx * i), min(cols, c0 + width + dx * i)):
                c = x - dx * i - c0
                x0 = x - dx
                if i == 0 or x0 < 0 or x0 >= cols:
                    _path_start(cost, total, y, x, current, c)
                else:
                    _path_step(
                        cost,
                        total,
                        y,
                        x,
                        previous,
                        c,
                        current,
                        c,
                        p1,
                        _edge_penalty(guide, y, x, y - dy, x0, p1, p2, edge_scale),
                    )
            previous, current = current, previous


def aggregate_paths(
    cost: np.ndarray, guide: np.ndarray, *, p1: float, p2: float, edge_scale: float, paths=PATHS_8
) -> np.ndarray:
    """Sum of the path-wise SGM aggregations of a cost volume.

    Parameters
    ----------
    cost : ndarray of float32, shape (H, W, D)
    guide : ndarray, shape (H, W)
        Grey image whose steps lower P2: ``P2 / (1 + |dI| / edge_scale)``, at least P1.
    p1, p2 : float
        Penalties for a change of one disparity level and for larger jumps.
    paths : sequence of (dy, dx)

    Returns
    -------
    ndarray of float32, shape (H, W, D)
    """
    if not 0 <= p1 <= p2:
        raise ValueError(f"SGM penalties need 0 <= P1 <= P2, got P1={p1}, P2={p2}")
    cost = np.ascontiguousarray(cost, dtype=np.float32)
    guide = np.ascontiguousarray(guide, dtype=np.float32)
    total = np.zeros_like(cost)
    args = (np.float32(p1), np.float32(p2), np.float32(edge_scale), total)
    rows, cols = cost.shape[:2]
    tasks = 4 * numba.get_num_threads()
    for dy, dx in paths:
        if dy == 0:
            _aggregate_rows(cost, guide, dx, *args)
        else:
            lines = cols + abs(dx) * (rows - 1)
            _aggregate_sweep(cost, guide, dy, dx, *args, max(_MIN_BAND, -(-lines // tasks)))
    return total


def sgm_volume(
    cost: np.ndarray,
    guide: np.ndarray,
    *,
    p1: float = 1.0,
    p2: float = 10.0,
    edge_scale: float = 3.0,
    overwrite: bool = False,
) -> np.ndarray:
    """The ``sgm`` method: 8-path aggregation with P2 lowered across the guide's edges.

    Parameters
    ----------
    cost : ndarray of float32, shape (H, W, D)
        Matching costs, in [0, 2] for AD-census.
    guide : ndarray, shape (H, W, 3) or (H, W)
        The view the costs belong to.
    p1, p2 : float
        SGM penalties in cost units.
    edge_scale : float
        Grey-level step that halves P2.
    overwrite : bool
        Accepted for the interface of :data:`mvtools.depth.METHODS`; the costs are
        read by every path to the end, so they stay intact beside the path sums.

    Returns
    -------
    ndarray of float32, shape (H, W, D)
    """
    guide = np.asarray(guide, np.float32)
    grey = guide.mean(axis=2) if guide.ndim == 3 else guide
    return aggregate_paths(cost, grey, p1=p1, p2=p2, edge_scale=edge_scale)


@njit(cache=True, nogil=True, inline="always")
def _level_cost(volume, y, x, k, right_view, min_disparity):
    # The right view's pixel x matches the left view's x + d: its costs lie on a
    # diagonal of the left view's volume, infinite where x + d leaves the image.
    if not right_view:
        return volume[y, x, k]
    column = x + min_disparity + k
    if 0 <= column < volume.shape[1]:
        return volume[y, column, k]
    return np.float32(np.inf)


@njit(cache=True, nogil=True, parallel=True)
def winner_takes_all(volume, right_view=False, min_disparity=0):
    """Level of least cost per pixel, refined by a parabola through its neighbours.

    Parameters
    ----------
    volume : ndarray of float32, shape (H, W, D)
        Costs of the left view's pixels.
    right_view : bool
        Give the right view's levels instead, from the same volume
        (``right[y, x, k] = volume[y, x + min_disparity + k, k]``).
    min_disparity : int
        Disparity of level 0; only used for the right view.

    Returns
    -------
    ndarray of float32, shape (H, W)
        Sub-pixel level in ``[0, D - 1]``.
    """
    rows, cols, levels = volume.shape
    level = np.empty((rows, cols), np.float32)
    for y in prange(rows):
        for x in range(cols):
            best = 0
            best_cost = _level_cost(volume, y, x, 0, right_view, min_disparity)
            for k in range(1, levels):
                value = _level_cost(volume, y, x, k, right_view, min_disparity)
                if value < best_cost:
                    best, best_cost = k, value
            offset = np.float32(0.0)
            if 0 < best < levels - 1:
                below = _level_cost(volume, y, x, best - 1, right_view, min_disparity)
                above = _level_cost(volume, y, x, best + 1, right_view, min_disparity)
                curvature = below - 2 * best_cost + above
                if curvature > 0 and np.isfinite(curvature):
                    offset = (below - above) / (2 * curvature)
            level[y, x] = best + offset
    return level
