"""Semi-global matching (Hirschmueller 2008): the cost volume aggregated along 8 image
paths with a small penalty P1 for 1-pixel disparity changes and a larger one P2, lowered
across image edges, for jumps; winner-takes-all with a parabola fit for sub-pixel values."""

from __future__ import annotations

import numba
import numpy as np
from numba import njit, prange

__all__ = [
    "PATHS_8",
    "aggregate_paths",
    "sgm_strips",
    "sgm_volume",
    "sgm_winners",
    "winner_takes_all",
]

# (dy, dx) steps of the 8 paths: each pixel's cost is smoothed along the line it came from.
PATHS_8 = ((0, 1), (0, -1), (1, 0), (-1, 0), (1, 1), (1, -1), (-1, 1), (-1, -1))


@njit(cache=True, nogil=True, inline="always")
def _path_step(cost, total, y, x, previous, p, current, c, p1, p2):
    # L(x, d) = C(x, d) + min(L(x-r, d), L(x-r, d+-1) + P1, min L(x-r) + P2) - min L(x-r),
    # with L(x-r) = previous[p] and the result written to current[c] and added to total.
    _strip_step(cost, total, y, y, x, previous, p, current, c, p1, p2, True)


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


@njit(cache=True, nogil=True, inline="always")
def _strip_step(cost, total, ty, y, x, previous, p, current, c, p1, p2, accumulate):
    # _path_step with the sum in a strip of rows (total[ty] holds row y), or none
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
        if accumulate:
            total[ty, x, k] += value


@njit(cache=True, nogil=True, inline="always")
def _strip_start(cost, total, ty, y, x, current, c, accumulate):
    for k in range(cost.shape[2]):
        current[c, k] = cost[y, x, k]
        if accumulate:
            total[ty, x, k] += cost[y, x, k]


@njit(cache=True, nogil=True, parallel=True)
def _rows_strip(cost, guide, dx, p1, p2, edge_scale, total, y0, strip):
    # a horizontal path over the rows y0 .. y0 + strip - 1, summed into their strip
    cols, levels = cost.shape[1], cost.shape[2]
    for ty in prange(strip):
        y = y0 + ty
        buffers = np.empty((2, levels), np.float32)
        x = 0 if dx > 0 else cols - 1
        _strip_start(cost, total, ty, y, x, buffers, 0, True)
        for i in range(1, cols):
            x += dx
            _strip_step(
                cost,
                total,
                ty,
                y,
                x,
                buffers,
                (i - 1) % 2,
                buffers,
                i % 2,
                p1,
                _edge_penalty(guide, y, x, y, x - dx, p1, p2, edge_scale),
                True,
            )


@njit(cache=True, nogil=True, parallel=True)
def _sweep_strip(
    cost, guide, dy, dx, p1, p2, edge_scale, total, y0, strip, state_in, state_out, band_width
):
    # A path with a vertical step over the rows y0 .. y0 + strip - 1 only, in bands of
    # lines as in _aggregate_sweep: state_in holds its values on the row before the strip
    # in path order, state_out gets them on the strip's last row in path order. The sums
    # go into the strip (total[y - y0]) unless total is empty.
    rows, cols, levels = cost.shape
    accumulate = total.shape[0] > 0
    i0 = y0 if dy > 0 else rows - (y0 + strip)
    first = min(0, -dx * (rows - 1))
    lines = cols + abs(dx) * (rows - 1)
    for band in prange(-(-lines // band_width)):
        c0 = first + band * band_width
        width = min(band_width, first + lines - c0)
        previous = np.empty((width, levels), np.float32)
        current = np.empty((width, levels), np.float32)
        if i0 > 0:
            for c in range(width):
                x = c0 + c + dx * (i0 - 1)
                if 0 <= x < cols:
                    previous[c, :] = state_in[x, :]
        for i in range(i0, i0 + strip):
            y = i if dy > 0 else rows - 1 - i
            for x in range(max(0, c0 + dx * i), min(cols, c0 + width + dx * i)):
                c = x - dx * i - c0
                x0 = x - dx
                if i == 0 or x0 < 0 or x0 >= cols:
                    _strip_start(cost, total, y - y0, y, x, current, c, accumulate)
                else:
                    _strip_step(
                        cost,
                        total,
                        y - y0,
                        y,
                        x,
                        previous,
                        c,
                        current,
                        c,
                        p1,
                        _edge_penalty(guide, y, x, y - dy, x0, p1, p2, edge_scale),
                        accumulate,
                    )
            previous, current = current, previous
        for c in range(width):
            x = c0 + c + dx * (i0 + strip - 1)
            if 0 <= x < cols:
                state_out[x, :] = previous[c, :]


def sgm_strips(
    cost: np.ndarray,
    guide: np.ndarray,
    *,
    p1: float = 1.0,
    p2: float = 10.0,
    edge_scale: float = 3.0,
    strip_rows: int | None = None,
):
    """The ``sgm`` method's volume a strip of rows at a time, top to bottom.

    The path sums of :func:`sgm_volume` are made a strip of rows at a time: the
    downward paths carry their last row from strip to strip, the upward ones start
    each strip from their row below it, kept from a first upward sweep over the image.
    Every sum is the same as in :func:`sgm_volume`, added in the same order, so each
    strip is those rows of its volume, bit for bit, while beside the costs only a strip
    of sums and the upward paths' rows at the strip boundaries are kept (about
    ``2 sqrt(3 H)`` rows of the volume instead of ``H``).

    Parameters
    ----------
    cost, guide, p1, p2, edge_scale
        As for :func:`sgm_volume`; ``cost`` is not changed.
    strip_rows : int, optional
        Rows per strip; ``sqrt(3 H)`` by default, which balances the strip against the
        kept boundary rows.

    Yields
    ------
    (y0, strip)
        The first row and the rows ``y0 ..`` of the volume, float32 of shape
        (rows in the strip, W, D); a strip is valid until the next is asked for.
    """
    if not 0 <= p1 <= p2:
        raise ValueError(f"SGM penalties need 0 <= P1 <= P2, got P1={p1}, P2={p2}")
    cost = np.ascontiguousarray(cost, dtype=np.float32)
    guide = np.asarray(guide, np.float32)
    grey = np.ascontiguousarray(guide.mean(axis=2) if guide.ndim == 3 else guide, np.float32)
    rows, cols, levels = cost.shape
    strip = max(1, int(strip_rows or np.sqrt(3 * rows)))
    starts = list(range(0, rows, strip))
    heights = [min(strip, rows - y0) for y0 in starts]
    penalties = (np.float32(p1), np.float32(p2), np.float32(edge_scale))
    tasks = 4 * numba.get_num_threads()
    band = {
        (dy, dx): max(_MIN_BAND, -(-(cols + abs(dx) * (rows - 1)) // tasks)) for dy, dx in PATHS_8
    }
    none = np.empty((0, cols, levels), np.float32)
    # the upward paths' values on the row below each strip (its entry state)
    entry = {}
    for path in (path for path in PATHS_8 if path[0] < 0):
        state = np.empty((cols, levels), np.float32)
        entry[path] = [None] * (len(starts) - 1) + [state]  # the last starts the path
        for s in range(len(starts) - 1, 0, -1):
            following = np.empty_like(state)
            _sweep_strip(
                cost, grey, *path, *penalties, none, starts[s], heights[s], state, following,
                band[path],
            )  # fmt: skip
            entry[path][s - 1] = state = following
    downward = {path: np.empty((cols, levels), np.float32) for path in PATHS_8 if path[0] > 0}
    for s, (y0, height) in enumerate(zip(starts, heights, strict=True)):
        total = np.zeros((height, cols, levels), np.float32)
        for path in PATHS_8:
            dy, dx = path
            if dy == 0:
                _rows_strip(cost, grey, dx, *penalties, total, y0, height)
                continue
            state = downward[path] if dy > 0 else entry[path][s]
            following = np.empty((cols, levels), np.float32)
            _sweep_strip(
                cost, grey, dy, dx, *penalties, total, y0, height, state, following, band[path]
            )
            if dy > 0:
                downward[path] = following
            else:
                entry[path][s] = None
        yield y0, total


def sgm_winners(
    cost: np.ndarray,
    guide: np.ndarray,
    *,
    min_disparity: int = 0,
    p1: float = 1.0,
    p2: float = 10.0,
    edge_scale: float = 3.0,
    strip_rows: int | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """The ``sgm`` method's winner-takes-all levels of both views, without its volume:
    each strip of :func:`sgm_strips` gives its rows' winners at once (a row's
    right-view levels lie on the same row).

    Parameters
    ----------
    cost, guide, p1, p2, edge_scale, strip_rows
        As for :func:`sgm_strips`.
    min_disparity : int
        Disparity of level 0, for the right view's diagonals.

    Returns
    -------
    left, right : ndarray of float32, shape (H, W)
        ``winner_takes_all(volume)`` and ``winner_takes_all(volume, right_view=True,
        min_disparity=min_disparity)`` of the ``sgm`` volume.
    """
    rows, cols = cost.shape[:2]
    left = np.empty((rows, cols), np.float32)
    right = np.empty((rows, cols), np.float32)
    strips = sgm_strips(cost, guide, p1=p1, p2=p2, edge_scale=edge_scale, strip_rows=strip_rows)
    for y0, total in strips:
        height = total.shape[0]
        left[y0 : y0 + height] = winner_takes_all(total)
        right[y0 : y0 + height] = winner_takes_all(
            total, right_view=True, min_disparity=min_disparity
        )
    return left, right
