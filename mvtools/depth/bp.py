"""Hierarchical min-sum belief propagation (Felzenszwalb & Huttenlocher 2006) on the
4-connected grid: truncated linear smoothness with per-edge weights from
:func:`mvtools.depth.graphcut.smoothness_weights` (the energy the ``graphcut`` method
minimises), O(D) messages by a distance transform, checkerboard updates, coarse-to-fine
message initialisation."""

from __future__ import annotations

import numpy as np
from numba import njit, prange

from mvtools.depth.graphcut import smoothness_weights
from mvtools.depth.sgm import winner_takes_all

__all__ = ["belief_propagation", "bp_strips", "bp_volume", "bp_winners"]

#: The ``bp`` method's tuning, shared by :func:`bp_volume` and :func:`bp_strips` (see
#: :func:`bp_volume`).
SMOOTHING = 16.0
SMOOTHING2 = 0.3
TRUNCATION = 4.0
COLOUR_SCALE = 10.0
SCALES = 5
ITERATIONS = 5

# Incoming-message slots: the message a pixel received from its neighbour above,
# below, on the left and on the right.
_FROM_UP, _FROM_DOWN, _FROM_LEFT, _FROM_RIGHT = 0, 1, 2, 3


@njit(cache=True, nogil=True, inline="always")
def _send(total, excluded, weight, truncation, out):
    # out(d) = min_e [h(e) + w min(|d - e|, T)] with h = total - excluded, by the
    # two-pass distance transform of the linear term, capped at min h + w T; shifted
    # to a minimum of 0 so that messages stay bounded.
    levels = total.shape[0]
    lowest = np.inf
    for d in range(levels):
        out[d] = total[d] - excluded[d]
        lowest = min(lowest, out[d])
    for d in range(1, levels):
        out[d] = min(out[d], out[d - 1] + weight)
    for d in range(levels - 2, -1, -1):
        out[d] = min(out[d], out[d + 1] + weight)
    cap = weight * truncation
    for d in range(levels):
        out[d] = min(out[d] - lowest, cap)


@njit(cache=True, nogil=True, parallel=True)
def _iterate(data, right, down, messages, truncation, iterations, row_offset):
    # Checkerboard schedule: a pixel of one parity reads only its own slots, written
    # by the other parity in the previous half-sweep, and writes only into its
    # neighbours' slots, so every row runs in parallel. row_offset: the image row of
    # row 0, when the arrays are a strip of rows, which keeps the parities.
    rows, cols, levels = data.shape
    for iteration in range(iterations):
        for y in prange(rows):
            total = np.empty(levels, np.float32)
            for x in range((y + row_offset + iteration) % 2, cols, 2):
                for d in range(levels):
                    total[d] = (
                        data[y, x, d]
                        + messages[0, y, x, d]
                        + messages[1, y, x, d]
                        + messages[2, y, x, d]
                        + messages[3, y, x, d]
                    )
                if y > 0:
                    _send(
                        total,
                        messages[_FROM_UP, y, x],
                        down[y - 1, x],
                        truncation,
                        messages[_FROM_DOWN, y - 1, x],
                    )
                if y < rows - 1:
                    _send(
                        total,
                        messages[_FROM_DOWN, y, x],
                        down[y, x],
                        truncation,
                        messages[_FROM_UP, y + 1, x],
                    )
                if x > 0:
                    _send(
                        total,
                        messages[_FROM_LEFT, y, x],
                        right[y, x - 1],
                        truncation,
                        messages[_FROM_RIGHT, y, x - 1],
                    )
                if x < cols - 1:
                    _send(
                        total,
                        messages[_FROM_RIGHT, y, x],
                        right[y, x],
                        truncation,
                        messages[_FROM_LEFT, y, x + 1],
                    )


@njit(cache=True, nogil=True, parallel=True)
def _finer_messages(coarse, rows, cols, row_offset, coarse_row_offset):
    # each pixel starts from the messages its 2x2 block received, written straight into
    # the finer array (no repeated intermediate copies); the finer rows are those from
    # row_offset on, the coarse ones from coarse_row_offset on
    fine = np.empty((coarse.shape[0], rows, cols, coarse.shape[3]), np.float32)
    for y in prange(rows):
        for s in range(coarse.shape[0]):
            for x in range(cols):
                fine[s, y, x, :] = coarse[s, (y + row_offset) // 2 - coarse_row_offset, x // 2, :]
    return fine


@njit(cache=True, nogil=True, parallel=True)
def _beliefs(data, messages, beliefs):
    # each element of data is read before it is written, so beliefs may be data itself
    rows, cols, levels = data.shape
    for y in prange(rows):
        for x in range(cols):
            for d in range(levels):
                beliefs[y, x, d] = (
                    data[y, x, d]
                    + messages[0, y, x, d]
                    + messages[1, y, x, d]
                    + messages[2, y, x, d]
                    + messages[3, y, x, d]
                )
    return beliefs


def _pair_sum(array: np.ndarray, axis: int) -> np.ndarray:
    # sum of consecutive pairs along an axis, an odd last element standing alone
    if array.shape[axis] % 2:
        pad = [(0, 0)] * array.ndim
        pad[axis] = (0, 1)
        array = np.pad(array, pad)
    shape = array.shape[:axis] + (array.shape[axis] // 2, 2) + array.shape[axis + 1 :]
    return array.reshape(shape).sum(axis=axis + 1)


def _coarser(data, right, down):
    # The coarse problem is the fine energy restricted to labels constant on 2x2
    # blocks: data costs add up over a block, and the weights of the fine edges
    # crossing between two blocks add up into the coarse edge's weight.
    coarse_data = _pair_sum(_pair_sum(data, 0), 1)
    coarse_right = _pair_sum(right[:, 1::2], 0)
    coarse_down = _pair_sum(down[1::2], 1)
    return coarse_data, coarse_right, coarse_down


def belief_propagation(
    cost: np.ndarray,
    right: np.ndarray,
    down: np.ndarray,
    *,
    truncation: float,
    scales: int = SCALES,
    iterations: int = ITERATIONS,
    overwrite: bool = False,
) -> np.ndarray:
    """Beliefs of hierarchical min-sum belief propagation.

    Minimises ``sum_p C(p, f_p) + sum_pq w_pq min(|f_p - f_q|, truncation)`` approximately.

    Parameters
    ----------
    cost : ndarray, shape (H, W, D)
        Data costs.
    right, down : ndarray, shapes (H, W - 1) and (H - 1, W)
        Non-negative weights of the horizontal and vertical neighbour pairs.
    truncation : float
        Largest charged label difference, at least 1 (1 is the Potts model).
    scales : int
        Pyramid levels, each half the size of the one below; the coarsest level's
        messages start at zero and every finer level starts from its parent's.
    iterations : int
        Checkerboard half-sweeps per level.
    overwrite : bool
        Write the beliefs into ``cost`` (a contiguous float32 volume), which is then
        lost: the four message volumes and that one are the largest arrays alive.

    Returns
    -------
    ndarray of float32, shape (H, W, D)
        Data cost plus the four incoming messages at each pixel.
    """
    cost = np.ascontiguousarray(cost, dtype=np.float32)
    rows, cols, _levels = cost.shape
    if right.shape != (rows, cols - 1) or down.shape != (rows - 1, cols):
        raise ValueError(
            f"weights of shapes {right.shape} and {down.shape} do not fit a {rows}x{cols} grid"
        )
    if truncation < 1 or scales < 1 or iterations < 1:
        raise ValueError(
            f"truncation, scales and iterations must be at least 1, got "
            f"{truncation}, {scales}, {iterations}"
        )
    right = np.ascontiguousarray(right, np.float32)
    down = np.ascontiguousarray(down, np.float32)
    coarse = _coarse_messages(cost, right, down, truncation, scales, iterations)
    messages = (
        np.zeros((4,) + cost.shape, np.float32)
        if coarse is None
        else _finer_messages(coarse, rows, cols, 0, 0)
    )
    del coarse
    _iterate(cost, right, down, messages, np.float32(truncation), iterations, 0)
    return _beliefs(cost, messages, cost if overwrite else np.empty_like(cost))


def _coarse_messages(cost, right, down, truncation, scales, iterations):
    # The messages of the level above the finest after its iterations (None with a
    # single level), each coarser level dropped as soon as the finer one starts.
    pyramid = [(cost, right, down)]
    while len(pyramid) < scales and min(pyramid[-1][0].shape[:2]) > 1:
        pyramid.append(_coarser(*pyramid[-1]))
    messages = None
    while len(pyramid) > 1:
        data, level_right, level_down = pyramid.pop()
        if messages is None:
            messages = np.zeros((4,) + data.shape, np.float32)
        else:
            messages = _finer_messages(messages, data.shape[0], data.shape[1], 0, 0)
        _iterate(
            np.ascontiguousarray(data),
            np.ascontiguousarray(level_right),
            np.ascontiguousarray(level_down),
            messages,
            np.float32(truncation),
            iterations,
            0,
        )
        del data, level_right, level_down
    return messages


def bp_volume(
    cost: np.ndarray,
    guide: np.ndarray,
    *,
    smoothing: float = SMOOTHING,
    smoothing2: float = SMOOTHING2,
    truncation: float = TRUNCATION,
    colour_scale: float = COLOUR_SCALE,
    scales: int = SCALES,
    iterations: int = ITERATIONS,
    overwrite: bool = False,
) -> np.ndarray:
    """The ``bp`` method: hierarchical belief propagation's beliefs.

    Parameters
    ----------
    cost : ndarray of float32, shape (H, W, D)
        Matching costs, e.g. AD-census in [0, 2].
    guide : ndarray, shape (H, W, 3)
        The view the costs belong to.
    smoothing, smoothing2, colour_scale : float
        Smoothness weights as DERS defines them (:func:`smoothness_weights`).
    truncation : float
        Largest charged label difference.
    scales, iterations : int
        See :func:`belief_propagation`.
    overwrite : bool
        Write the result into ``cost`` (a contiguous float32 volume), which is then lost.

    Returns
    -------
    ndarray of float32, shape (H, W, D)
    """
    cost = np.ascontiguousarray(cost, dtype=np.float32)
    right, down = smoothness_weights(
        cost, guide, smoothing=smoothing, smoothing2=smoothing2, colour_scale=colour_scale
    )
    return belief_propagation(
        cost,
        right,
        down,
        truncation=truncation,
        scales=scales,
        iterations=iterations,
        overwrite=overwrite,
    )


def bp_strips(
    cost: np.ndarray,
    guide: np.ndarray,
    *,
    smoothing: float = SMOOTHING,
    smoothing2: float = SMOOTHING2,
    truncation: float = TRUNCATION,
    colour_scale: float = COLOUR_SCALE,
    scales: int = SCALES,
    iterations: int = ITERATIONS,
    strip_rows: int = 16,
):
    """The ``bp`` method's volume (its beliefs) a strip of rows at a time, top to bottom.

    The coarser levels run as in :func:`belief_propagation`; the finest one a strip of
    rows at a time, each strip widened by ``iterations`` rows on either side: a
    half-sweep carries a message one row on, so the widened rows' missing neighbours
    reach no further than the widening, and the strip's messages and beliefs are those
    of the whole frame, bit for bit. Beside the costs only the messages of the level
    above (a quarter of the pixels, four slots: one volume) and a strip's are kept,
    instead of four message volumes and the beliefs.

    Parameters
    ----------
    cost, guide, smoothing, smoothing2, truncation, colour_scale, scales, iterations
        As for :func:`bp_volume`; ``cost`` is not changed.
    strip_rows : int
        Rows per strip of the finest level, at least 1.

    Yields
    ------
    (y0, strip)
        The first row and the rows ``y0 ..`` of the :func:`bp_volume` volume, float32
        of shape (rows in the strip, W, D).
    """
    if strip_rows < 1:
        raise ValueError(f"strip_rows must be at least 1, got {strip_rows}")
    cost = np.ascontiguousarray(cost, dtype=np.float32)
    right, down = smoothness_weights(
        cost, guide, smoothing=smoothing, smoothing2=smoothing2, colour_scale=colour_scale
    )
    rows, cols, _levels = cost.shape
    if truncation < 1 or scales < 1 or iterations < 1:
        raise ValueError(
            f"truncation, scales and iterations must be at least 1, got "
            f"{truncation}, {scales}, {iterations}"
        )
    # the pyramid's sizes and weights (small); its data costs come strip by strip
    shapes = [(rows, cols)]
    weights = [(np.ascontiguousarray(right, np.float32), np.ascontiguousarray(down, np.float32))]
    while len(shapes) < scales and min(shapes[-1]) > 1:
        level_right, level_down = weights[-1]
        shapes.append((-(-shapes[-1][0] // 2), -(-shapes[-1][1] // 2)))
        weights.append((_pair_sum(level_right[:, 1::2], 0), _pair_sum(level_down[1::2], 1)))
    strip = _Strips(cost, shapes, weights, np.float32(truncation), iterations)
    for y0 in range(0, rows, strip_rows):
        y1 = min(rows, y0 + strip_rows)
        beliefs = _beliefs(
            cost[y0:y1],
            strip.messages(0, y0, y1),
            np.empty((y1 - y0,) + cost.shape[1:], np.float32),
        )
        yield y0, beliefs


def bp_winners(
    cost: np.ndarray,
    guide: np.ndarray,
    *,
    min_disparity: int = 0,
    strip_rows: int = 16,
    **options,
) -> tuple[np.ndarray, np.ndarray]:
    """The ``bp`` method's winner-takes-all levels of both views, without its volume:
    each strip of :func:`bp_strips` gives its rows' winners at once.

    Parameters
    ----------
    cost, guide, strip_rows, **options
        As for :func:`bp_strips`.
    min_disparity : int
        Disparity of level 0, for the right view's diagonals.

    Returns
    -------
    left, right : ndarray of float32, shape (H, W)
        ``winner_takes_all`` of the :func:`bp_volume` volume in the left view and, along
        its diagonals, in the right view.
    """
    rows, cols = cost.shape[:2]
    left_levels = np.empty((rows, cols), np.float32)
    right_levels = np.empty((rows, cols), np.float32)
    for y0, beliefs in bp_strips(cost, guide, strip_rows=strip_rows, **options):
        y1 = y0 + beliefs.shape[0]
        left_levels[y0:y1] = winner_takes_all(beliefs)
        right_levels[y0:y1] = winner_takes_all(
            beliefs, right_view=True, min_disparity=min_disparity
        )
    return left_levels, right_levels


class _Strips:
    # Final messages of any pyramid level on a band of its rows, from the cost volume
    # alone: the band widened by the iterations, started from the messages of the
    # coarser level's band above it (computed the same way), its data costs summed
    # from the cost rows under it. Each level's result is that of the whole frame.
    def __init__(self, cost, shapes, weights, truncation, iterations):
        self.cost, self.shapes, self.weights = cost, shapes, weights
        self.truncation, self.iterations = truncation, iterations

    def data(self, level, r0, r1):
        # pyramid data of a level's rows r0 .. r1 - 1, as _coarser sums them
        if level == 0:
            return self.cost[r0:r1]
        finer = self.data(level - 1, 2 * r0, min(2 * r1, self.shapes[level - 1][0]))
        return _pair_sum(_pair_sum(finer, 0), 1)

    def messages(self, level, a, b):
        rows, cols = self.shapes[level]
        e0, e1 = max(0, a - self.iterations), min(rows, b + self.iterations)
        shape = (4, e1 - e0, cols, self.cost.shape[2])
        if level == len(self.shapes) - 1:
            messages = np.zeros(shape, np.float32)
        else:
            c0, c1 = e0 // 2, (e1 - 1) // 2 + 1
            messages = _finer_messages(self.messages(level + 1, c0, c1), e1 - e0, cols, e0, c0)
        right, down = self.weights[level]
        _iterate(
            np.ascontiguousarray(self.data(level, e0, e1)),
            np.ascontiguousarray(right[e0:e1]),
            np.ascontiguousarray(down[e0 : e1 - 1]),
            messages,
            self.truncation,
            self.iterations,
            e0,
        )
        return messages[:, a - e0 : b - e0]
