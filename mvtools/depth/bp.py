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
def _send(data, own, weight0, weight1, weight2, weight3, truncation, sent0, sent1, sent2, sent3):
    # sent<s>(d) = min_e [h(e) + w min(|d - e|, T)] with h = data + all four incoming
    # messages but own[s], the message to the neighbour on side s, by the two-pass
    # distance transform of the linear term, capped at min h + w T; shifted to a minimum
    # of 0 so that messages stay bounded. The four messages' scans run side by side in
    # one pass each way, four independent dependency chains that the processor overlaps
    # (one message's scan is a chain of adds and mins, latency-bound), and the second
    # pass caps and shifts as it goes; each value gets the same float operations, in
    # the same order and types, as a message at a time.
    levels = data.shape[0]
    # (the minima in float32: a float32 difference rounds exactly as a float64 one
    # rounded to float32, the float64 having more than twice the float32's precision
    # bits, so shifting by them gives the same bits as shifting by a float64 minimum)
    lowest0 = lowest1 = lowest2 = lowest3 = np.float32(np.inf)
    total = data[0] + own[0, 0] + own[1, 0] + own[2, 0] + own[3, 0]
    last0 = total - own[0, 0]
    last1 = total - own[1, 0]
    last2 = total - own[2, 0]
    last3 = total - own[3, 0]
    lowest0 = min(lowest0, last0)
    lowest1 = min(lowest1, last1)
    lowest2 = min(lowest2, last2)
    lowest3 = min(lowest3, last3)
    sent0[0] = last0
    sent1[0] = last1
    sent2[0] = last2
    sent3[0] = last3
    for d in range(1, levels):
        total = data[d] + own[0, d] + own[1, d] + own[2, d] + own[3, d]
        h0 = total - own[0, d]
        h1 = total - own[1, d]
        h2 = total - own[2, d]
        h3 = total - own[3, d]
        lowest0 = min(lowest0, h0)
        lowest1 = min(lowest1, h1)
        lowest2 = min(lowest2, h2)
        lowest3 = min(lowest3, h3)
        last0 = min(h0, last0 + weight0)
        last1 = min(h1, last1 + weight1)
        last2 = min(h2, last2 + weight2)
        last3 = min(h3, last3 + weight3)
        sent0[d] = last0
        sent1[d] = last1
        sent2[d] = last2
        sent3[d] = last3
    cap0 = weight0 * truncation
    cap1 = weight1 * truncation
    cap2 = weight2 * truncation
    cap3 = weight3 * truncation
    for d in range(levels - 2, -1, -1):
        h0 = min(sent0[d], last0 + weight0)
        h1 = min(sent1[d], last1 + weight1)
        h2 = min(sent2[d], last2 + weight2)
        h3 = min(sent3[d], last3 + weight3)
        sent0[d + 1] = min(last0 - lowest0, cap0)
        sent1[d + 1] = min(last1 - lowest1, cap1)
        sent2[d + 1] = min(last2 - lowest2, cap2)
        sent3[d + 1] = min(last3 - lowest3, cap3)
        last0, last1, last2, last3 = h0, h1, h2, h3
    sent0[0] = min(last0 - lowest0, cap0)
    sent1[0] = min(last1 - lowest1, cap1)
    sent2[0] = min(last2 - lowest2, cap2)
    sent3[0] = min(last3 - lowest3, cap3)


@njit(cache=True, nogil=True, parallel=True)
def _iterate(data, right, down, messages, truncation, iterations, row_offset, first, stop):
    # Checkerboard schedule: a pixel of one parity reads only its own slots, written
    # by the other parity in the previous half-sweep, and writes only into its
    # neighbours' slots, so every row runs in parallel. row_offset: the image row of
    # row 0, when the arrays are a band of rows, which keeps the parities.
    # Half-sweep k updates only rows first - k .. stop - k - 1 (0 .. rows - 1 with
    # first <= 0 and stop >= rows + iterations): a staircase whose rows above have had
    # one half-sweep more than the rows below, which is all that a row's update needs
    # (its neighbours' previous half-sweep, not yet their next one), so a level can be
    # swept a band at a time, each row updated once per half-sweep (see _Level).
    rows, cols, levels = data.shape
    for iteration in range(iterations):
        for y in prange(max(0, first - iteration), min(rows, stop - iteration)):
            # a side without a neighbour gets its message in a row nobody reads
            spare = np.empty((4, levels), np.float32)
            for x in range((y + row_offset + iteration) % 2, cols, 2):
                _send(
                    data[y, x],
                    messages[:, y, x],
                    down[y - 1, x] if y > 0 else np.float32(0),
                    down[y, x] if y < rows - 1 else np.float32(0),
                    right[y, x - 1] if x > 0 else np.float32(0),
                    right[y, x] if x < cols - 1 else np.float32(0),
                    truncation,
                    messages[_FROM_DOWN, y - 1, x] if y > 0 else spare[_FROM_UP],
                    messages[_FROM_UP, y + 1, x] if y < rows - 1 else spare[_FROM_DOWN],
                    messages[_FROM_RIGHT, y, x - 1] if x > 0 else spare[_FROM_LEFT],
                    messages[_FROM_LEFT, y, x + 1] if x < cols - 1 else spare[_FROM_RIGHT],
                )


@njit(cache=True, nogil=True, parallel=True)
def _finer_messages(coarse, fine, row_offset, coarse_row_offset):
    # each pixel starts from the messages its 2x2 block received, written straight into
    # the finer array (no repeated intermediate copies); the finer rows are those from
    # row_offset on, the coarse ones from coarse_row_offset on
    for y in prange(fine.shape[1]):
        for s in range(coarse.shape[0]):
            for x in range(fine.shape[2]):
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
        else _finer_messages(coarse, np.empty((4,) + cost.shape, np.float32), 0, 0)
    )
    del coarse
    _iterate(
        cost, right, down, messages, np.float32(truncation), iterations, 0, 0, rows + iterations
    )
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
            messages = _finer_messages(messages, np.empty((4,) + data.shape, np.float32), 0, 0)
        _iterate(
            np.ascontiguousarray(data),
            np.ascontiguousarray(level_right),
            np.ascontiguousarray(level_down),
            messages,
            np.float32(truncation),
            iterations,
            0,
            0,
            data.shape[0] + iterations,
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

    Every level is swept top to bottom a band of rows at a time, as far as the finest
    strip asked for needs, each row updated once per half-sweep (a staircase of
    half-sweeps, see :class:`_Level`), its messages started from the level above's as
    soon as those are final: the strips' messages and beliefs are those of the whole
    frame, bit for bit, for the work of one frame. Beside the costs only a few rows of
    messages and of summed costs per level are kept, instead of four message volumes and
    the beliefs.

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
    # the pyramid's sizes and weights (small); its data costs come band by band
    shapes = [(rows, cols)]
    weights = [(np.ascontiguousarray(right, np.float32), np.ascontiguousarray(down, np.float32))]
    while len(shapes) < scales and min(shapes[-1]) > 1:
        level_right, level_down = weights[-1]
        shapes.append((-(-shapes[-1][0] // 2), -(-shapes[-1][1] // 2)))
        weights.append((_pair_sum(level_right[:, 1::2], 0), _pair_sum(level_down[1::2], 1)))
    data = _DataBands(cost, shapes)
    finest = None
    for level in reversed(range(len(shapes))):
        finest = _Level(level, data, weights[level], finest, np.float32(truncation), iterations)
    for y0 in range(0, rows, strip_rows):
        y1 = min(rows, y0 + strip_rows)
        beliefs = _beliefs(
            cost[y0:y1],
            finest.final(y0, y1),
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


class _DataBands:
    # The pyramid's data costs a band of rows at a time, each coarse row summed once from
    # the finer level's rows as _coarser sums them. Two readers walk down each coarse
    # level, its own sweep (_Level) and the summing of the level below it, each asking
    # for rows no higher than it asked last; the rows above both are dropped.
    def __init__(self, cost, shapes):
        self.cost, self.shapes = cost, shapes
        self.chunks = [[] for _ in shapes]  # (first row, rows) of each coarse level
        self.reader_rows = [[0, 0] for _ in shapes]  # first row each reader still needs
        self.reader_rows[-1][1] = shapes[-1][0]  # nothing sums the coarsest level

    def rows(self, level, r0, r1, reader):
        # data of a level's rows r0 .. r1 - 1; reader 0: the level's sweep, 1: the
        # summing of the level below
        if level == 0:
            return self.cost[r0:r1]
        chunks = self.chunks[level]
        self.reader_rows[level][reader] = r0
        keep = min(self.reader_rows[level])
        while chunks and chunks[0][0] + chunks[0][1].shape[0] <= keep:
            chunks.pop(0)
        held = chunks[-1][0] + chunks[-1][1].shape[0] if chunks else 0
        if r1 > held:
            finer = self.rows(level - 1, 2 * held, min(2 * r1, self.shapes[level - 1][0]), reader=1)
            chunks.append((held, _pair_sum(_pair_sum(finer, 0), 1)))
        parts = [
            band[max(0, r0 - first) : r1 - first]
            for first, band in chunks
            if first < r1 and first + band.shape[0] > r0
        ]
        return parts[0] if len(parts) == 1 else np.concatenate(parts)


class _Level:
    # Final messages of one pyramid level, a band of rows at a time top to bottom. After
    # sweeping to front f, rows up to f have had all the half-sweeps, row f + j
    # (0 < j < iterations) iterations - j of them and the rows below none: _iterate's
    # staircase. Rows above f are then final (their neighbours are done too); moving the
    # front on to b gives each row between the two staircases its missing half-sweeps,
    # in order, once. The rows swept are kept from the first one asked for down to the
    # first row still untouched, whose messages start, as each row's do, from the
    # coarser level's final ones (zero at the coarsest level).
    def __init__(self, level, data, weights, coarser, truncation, iterations):
        self.level, self.data, self.coarser = level, data, coarser
        self.right, self.down = weights
        self.rows, self.cols = data.shapes[level]
        self.truncation, self.iterations = truncation, iterations
        self.front, self.start = -iterations, 0
        self.messages = np.empty((4, 0, self.cols, data.cost.shape[2]), np.float32)

    def final(self, a, b):
        # the final messages of rows a .. b - 1, a and b no lower than in the last call
        if b > self.front:
            start = max(0, min(a, self.front))
            end = min(self.rows, b + self.iterations + 1)
            kept = self.start + self.messages.shape[1]
            # the band moves down: its kept rows go up in place when its size stays (the
            # finest level's strips), so that no second band is alive meanwhile
            shape = (4, end - start) + self.messages.shape[2:]
            messages = (
                self.messages if self.messages.shape == shape else np.empty(shape, np.float32)
            )
            messages[:, : kept - start] = self.messages[:, start - self.start : kept - self.start]
            if self.coarser is None:
                messages[:, kept - start :] = 0
            else:
                c0, c1 = kept // 2, (end - 1) // 2 + 1
                _finer_messages(self.coarser.final(c0, c1), messages[:, kept - start :], kept, c0)
            _iterate(
                np.ascontiguousarray(self.data.rows(self.level, start, end, reader=0)),
                self.right[start:end],
                self.down[start : end - 1],
                messages,
                self.truncation,
                self.iterations,
                start,
                self.front + self.iterations - start,
                b + self.iterations - start,
            )
            self.messages, self.start, self.front = messages, start, b
        return self.messages[:, a - self.start : b - self.start]
