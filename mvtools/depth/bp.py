"""Hierarchical min-sum belief propagation (Felzenszwalb & Huttenlocher 2006) on the
4-connected grid: truncated linear smoothness with per-edge weights from
:func:`mvtools.depth.graphcut.smoothness_weights` (the energy the ``graphcut`` method
minimises), O(D) messages by a distance transform, checkerboard updates, coarse-to-fine
message initialisation."""

from __future__ import annotations

import numba
import numpy as np
from numba import get_thread_id, njit, prange

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

# Rows of the finest level per strip of the sweeps (see bp_strips): the messages alive
# are a band of about this many rows plus the iterations.
_STRIP_ROWS = 16

# Incoming-message slots: the message a pixel received from its neighbour above,
# below, on the left and on the right.
_FROM_UP, _FROM_DOWN, _FROM_LEFT, _FROM_RIGHT = 0, 1, 2, 3

# The layout of a band of rows' messages: every pixel has a colour, the checkerboard
# class (x + y) % 2 of its image coordinates, and a half-sweep updates the pixels of
# one colour from the messages the other colour sent them. So the messages are held as
# eight arrays, one per colour and slot (index 4 * colour + slot), each of shape
# (rows + 2, levels, columns // 2 + 2), pixel (y, x) of a band whose first row is image
# row y0 at [y - y0 + 1, :, x // 2 + 1]. A half-sweep then reads arrays distinct from
# those it writes (numba passes a parallel loop's distinct arrays to LLVM as not
# aliased), and the pixels of a row that it updates lie side by side at every level:
# the update vectorises across them, each pixel's chain of levels in a lane of its own
# (their data costs, read in the costs' own layout, are the one gathered load). The
# first and last rows and columns take the messages sent across the grid's edges,
# which nobody reads.


@njit(cache=True, nogil=True, parallel=True)
def _half_sweep(
    data,
    own_up,
    own_down,
    own_left,
    own_right,
    to_up,
    to_down,
    to_left,
    to_right,
    weight_up,
    weight_down,
    weight_left,
    weight_right,
    lowest_up,
    lowest_down,
    lowest_left,
    lowest_right,
    backward_up,
    backward_down,
    backward_left,
    backward_right,
    truncation,
    colour,
    row_offset,
    first,
    stop,
    columns,
):
    # Rows first .. stop - 1 (padded) of one colour send their messages, data holding
    # the band's data costs (rows, columns, levels) from row 0 on: to_up(d) =
    # min_e [h(e) + w min(|d - e|, T)] with h = data + all incoming messages but the
    # one from above, by the two-pass distance transform of the linear term, capped at
    # min h + w T and shifted to a minimum of 0 so that messages stay bounded; to_up
    # is the other colour's from-below slot, and so on. The forward pass leaves its
    # values where the messages go; the backward pass and the running minimum keep
    # their current and last level only, per thread, rather than reading a value and
    # writing it back in place (a masked store once vectorised, slow on some
    # processors). Each value gets the same float operations, in the same order and
    # types, as one pixel's messages at a time.
    levels = data.shape[2]
    top = levels - 1
    last = top % 2
    for y in prange(first, stop):
        # the row's pixels of this colour are x = 2 (j - 1) + parity, j = 1 .. count
        parity = (colour + y - 1 + row_offset) % 2
        count = (columns - parity + 1) // 2
        thread = get_thread_id()
        for j in range(1, count + 1):
            a0 = own_up[y, 0, j]
            a1 = own_down[y, 0, j]
            a2 = own_left[y, 0, j]
            a3 = own_right[y, 0, j]
            total = data[y - 1, 2 * j - 2 + parity, 0] + a0 + a1 + a2 + a3
            lowest_up[thread, 0, j] = to_up[y - 1, 0, j] = total - a0
            lowest_down[thread, 0, j] = to_down[y + 1, 0, j] = total - a1
            lowest_left[thread, 0, j] = to_left[y, 0, j - 1 + parity] = total - a2
            lowest_right[thread, 0, j] = to_right[y, 0, j + parity] = total - a3
        for d in range(1, levels):
            now = d % 2
            for j in range(1, count + 1):
                a0 = own_up[y, d, j]
                a1 = own_down[y, d, j]
                a2 = own_left[y, d, j]
                a3 = own_right[y, d, j]
                total = data[y - 1, 2 * j - 2 + parity, d] + a0 + a1 + a2 + a3
                h0 = total - a0
                h1 = total - a1
                h2 = total - a2
                h3 = total - a3
                lowest_up[thread, now, j] = min(lowest_up[thread, 1 - now, j], h0)
                lowest_down[thread, now, j] = min(lowest_down[thread, 1 - now, j], h1)
                lowest_left[thread, now, j] = min(lowest_left[thread, 1 - now, j], h2)
                lowest_right[thread, now, j] = min(lowest_right[thread, 1 - now, j], h3)
                to_up[y - 1, d, j] = min(h0, to_up[y - 1, d - 1, j] + weight_up[y, j])
                to_down[y + 1, d, j] = min(h1, to_down[y + 1, d - 1, j] + weight_down[y, j])
                to_left[y, d, j - 1 + parity] = min(
                    h2, to_left[y, d - 1, j - 1 + parity] + weight_left[y, j]
                )
                to_right[y, d, j + parity] = min(
                    h3, to_right[y, d - 1, j + parity] + weight_right[y, j]
                )
        for j in range(1, count + 1):
            backward_up[thread, last, j] = to_up[y - 1, top, j]
            backward_down[thread, last, j] = to_down[y + 1, top, j]
            backward_left[thread, last, j] = to_left[y, top, j - 1 + parity]
            backward_right[thread, last, j] = to_right[y, top, j + parity]
        # the backward pass writes each level's message once the level above is final
        for d in range(top - 1, -1, -1):
            now = d % 2
            for j in range(1, count + 1):
                b0 = backward_up[thread, 1 - now, j]
                b1 = backward_down[thread, 1 - now, j]
                b2 = backward_left[thread, 1 - now, j]
                b3 = backward_right[thread, 1 - now, j]
                backward_up[thread, now, j] = min(to_up[y - 1, d, j], b0 + weight_up[y, j])
                backward_down[thread, now, j] = min(to_down[y + 1, d, j], b1 + weight_down[y, j])
                backward_left[thread, now, j] = min(
                    to_left[y, d, j - 1 + parity], b2 + weight_left[y, j]
                )
                backward_right[thread, now, j] = min(
                    to_right[y, d, j + parity], b3 + weight_right[y, j]
                )
                to_up[y - 1, d + 1, j] = min(
                    b0 - lowest_up[thread, last, j], weight_up[y, j] * truncation
                )
                to_down[y + 1, d + 1, j] = min(
                    b1 - lowest_down[thread, last, j], weight_down[y, j] * truncation
                )
                to_left[y, d + 1, j - 1 + parity] = min(
                    b2 - lowest_left[thread, last, j], weight_left[y, j] * truncation
                )
                to_right[y, d + 1, j + parity] = min(
                    b3 - lowest_right[thread, last, j], weight_right[y, j] * truncation
                )
        for j in range(1, count + 1):
            to_up[y - 1, 0, j] = min(
                backward_up[thread, 0, j] - lowest_up[thread, last, j],
                weight_up[y, j] * truncation,
            )
            to_down[y + 1, 0, j] = min(
                backward_down[thread, 0, j] - lowest_down[thread, last, j],
                weight_down[y, j] * truncation,
            )
            to_left[y, 0, j - 1 + parity] = min(
                backward_left[thread, 0, j] - lowest_left[thread, last, j],
                weight_left[y, j] * truncation,
            )
            to_right[y, 0, j + parity] = min(
                backward_right[thread, 0, j] - lowest_right[thread, last, j],
                weight_right[y, j] * truncation,
            )


@njit(cache=True, nogil=True)
def _iterate(
    data, messages, weights, truncation, iterations, row_offset, first, stop, columns, threads
):
    # Checkerboard schedule: half-sweep k updates the pixels of colour k % 2 (in image
    # coordinates: row_offset is the image row of the band's row 0), which read only
    # their own slots, written by the other colour in the previous half-sweep, and
    # write only into the other colour's slots, so every row runs in parallel.
    # Half-sweep k updates only band rows first - k .. stop - k - 1 (0 .. rows - 1 with
    # first <= 0 and stop >= rows + iterations): a staircase whose rows above have had
    # one half-sweep more than the rows below, which is all that a row's update needs
    # (its neighbours' previous half-sweep, not yet their next one), so a level can be
    # swept a band at a time, each row updated once per half-sweep (see _Level).
    rows, width = data.shape[0], messages[0].shape[2]
    # each thread's running minima and backward values, this level's and the last's
    scratch = [np.empty((threads, 2, width), np.float32) for _ in range(8)]
    for iteration in range(iterations):
        colour = iteration % 2
        own = 4 * colour
        other = 4 * (1 - colour)
        begin = max(0, first - iteration)
        end = min(rows, stop - iteration)
        if begin < end:
            _half_sweep(
                data,
                messages[own + _FROM_UP],
                messages[own + _FROM_DOWN],
                messages[own + _FROM_LEFT],
                messages[own + _FROM_RIGHT],
                messages[other + _FROM_DOWN],
                messages[other + _FROM_UP],
                messages[other + _FROM_RIGHT],
                messages[other + _FROM_LEFT],
                weights[own + _FROM_UP],
                weights[own + _FROM_DOWN],
                weights[own + _FROM_LEFT],
                weights[own + _FROM_RIGHT],
                scratch[0],
                scratch[1],
                scratch[2],
                scratch[3],
                scratch[4],
                scratch[5],
                scratch[6],
                scratch[7],
                truncation,
                colour,
                row_offset,
                begin + 1,
                end + 1,
                columns,
            )


@njit(cache=True, nogil=True)
def _weights_by_colour(right, down):
    # Each pixel's weights towards its four neighbours, zero where the grid has none,
    # in the layout of the sweeps (index 4 * colour + slot) for the whole level: a
    # band's are its rows, the edge rows of a band that is not the grid's never being
    # updated (see _Level).
    rows, columns = down.shape[0] + 1, down.shape[1]
    weights = [np.zeros((rows + 2, columns // 2 + 2), np.float32) for _ in range(8)]
    for y in range(rows):
        for x in range(columns):
            colour = 4 * ((x + y) % 2)
            j = x // 2 + 1
            if y > 0:
                weights[colour + _FROM_UP][y + 1, j] = down[y - 1, x]
            if y < rows - 1:
                weights[colour + _FROM_DOWN][y + 1, j] = down[y, x]
            if x > 0:
                weights[colour + _FROM_LEFT][y + 1, j] = right[y, x - 1]
            if x < columns - 1:
                weights[colour + _FROM_RIGHT][y + 1, j] = right[y, x]
    return weights


@njit(cache=True, nogil=True, parallel=True)
def _finer_messages(coarse, coarse_first, fine, fine_first, begin, end, columns):
    # each pixel of image rows begin .. end - 1 starts from the messages its 2x2 block
    # received; coarse_first and fine_first are the image rows of the two bands' row 0
    levels = fine[0].shape[1]
    for y in prange(begin, end):
        block = y // 2
        at, source_row = y - fine_first + 1, block - coarse_first + 1
        for colour in range(2):
            count = (columns - (colour + y) % 2 + 1) // 2
            # pixel j (x // 2 = j - 1) lies in block column j - 1, which has colour
            # (j - 1 + block) % 2 and sits at (j - 1) // 2 + 1 of its row
            for slot in range(4):
                into = fine[4 * colour + slot]
                for step in range(2):
                    source = coarse[4 * ((step + block) % 2) + slot]
                    for d in range(levels):
                        for i in range((count - step + 1) // 2):
                            into[at, d, 2 * i + step + 1] = source[source_row, d, i + 1]
    return fine


@njit(cache=True, nogil=True, parallel=True)
def _beliefs(data, messages, first, row_offset, beliefs):
    # the beliefs of image rows row_offset .. from their data costs, both of shape
    # (rows, columns, levels), and the messages of a band whose row 0 is image row
    # first: summed a row's pixels of one colour at a time, side by side, then laid out
    # a pixel at a time; each element of data is read before it is written, so beliefs
    # may be data itself
    rows, columns, levels = data.shape
    for y in prange(rows):
        at = y + row_offset - first + 1
        summed = np.empty((levels, messages[0].shape[2]), np.float32)
        for parity in range(2):
            colour = 4 * ((parity + y + row_offset) % 2)
            up, down = messages[colour + _FROM_UP], messages[colour + _FROM_DOWN]
            left, right = messages[colour + _FROM_LEFT], messages[colour + _FROM_RIGHT]
            count = (columns - parity + 1) // 2
            for d in range(levels):
                for j in range(1, count + 1):
                    summed[d, j] = (
                        data[y, 2 * j - 2 + parity, d]
                        + up[at, d, j]
                        + down[at, d, j]
                        + left[at, d, j]
                        + right[at, d, j]
                    )
            for x in range(parity, columns, 2):
                for d in range(levels):
                    beliefs[y, x, d] = summed[d, x // 2 + 1]
    return beliefs


@njit(cache=True, nogil=True, parallel=True)
def _block_sums(costs):
    # The coarser level's data costs: each 2x2 block of pixels summed, level by level,
    # a block cut by the grid's edge over the pixels it has; as _pair_sum along the
    # rows and then along the columns adds them, so the same float32 values.
    rows, columns, levels = costs.shape
    zero = np.float32(0)
    sums = np.empty(((rows + 1) // 2, (columns + 1) // 2, levels), np.float32)
    for y in prange(sums.shape[0]):
        below = 2 * y + 1 < rows
        for x in range(sums.shape[1]):
            beside = 2 * x + 1 < columns
            for d in range(levels):
                first = costs[2 * y, 2 * x, d] + (costs[2 * y + 1, 2 * x, d] if below else zero)
                second = zero
                if beside:
                    second = costs[2 * y, 2 * x + 1, d] + (
                        costs[2 * y + 1, 2 * x + 1, d] if below else zero
                    )
                sums[y, x, d] = first + second
    return sums


def _pair_sum(array: np.ndarray, axis: int) -> np.ndarray:
    # sum of consecutive pairs along an axis, an odd last element standing alone
    if array.shape[axis] % 2:
        pad = [(0, 0)] * array.ndim
        pad[axis] = (0, 1)
        array = np.pad(array, pad)
    shape = array.shape[:axis] + (array.shape[axis] // 2, 2) + array.shape[axis + 1 :]
    return array.reshape(shape).sum(axis=axis + 1)


def _check_options(truncation, scales, iterations):
    if truncation < 1 or scales < 1 or iterations < 1:
        raise ValueError(
            f"truncation, scales and iterations must be at least 1, got "
            f"{truncation}, {scales}, {iterations}"
        )


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
        lost. Beside the costs and the beliefs, only bands of rows of messages and of
        summed costs are alive (the sweeps of :func:`bp_strips`).

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
    _check_options(truncation, scales, iterations)
    beliefs = cost if overwrite else np.empty_like(cost)
    for _ in _belief_strips(
        cost, right, down, truncation, scales, iterations, _STRIP_ROWS, beliefs
    ):
        pass
    return beliefs


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
    strip_rows: int = _STRIP_ROWS,
):
    """The ``bp`` method's volume (its beliefs) a strip of rows at a time, top to bottom.

    Every level is swept top to bottom a band of rows at a time, as far as the finest
    strip asked for needs, each row updated once per half-sweep (a staircase of
    half-sweeps, see :class:`_Level`), its messages started from the level above's as
    soon as those are final: the strips' messages and beliefs are those of the whole
    frame, bit for bit, for the work of one frame. Beside the costs only a few rows of
    messages and of summed costs per level are kept, instead of the beliefs of the
    whole frame.

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
    _check_options(truncation, scales, iterations)
    yield from _belief_strips(cost, right, down, truncation, scales, iterations, strip_rows)


def _belief_strips(cost, right, down, truncation, scales, iterations, strip_rows, beliefs=None):
    # (y0, beliefs of rows y0 .. y0 + strip_rows - 1), written into beliefs when given
    rows, cols, _levels = cost.shape
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
        finest.final(y0, y1)
        strip = (
            np.empty((y1 - y0,) + cost.shape[1:], np.float32) if beliefs is None else beliefs[y0:y1]
        )
        yield y0, _beliefs(cost[y0:y1], finest.messages, finest.start, y0, strip)


def bp_winners(
    cost: np.ndarray,
    guide: np.ndarray,
    *,
    min_disparity: int = 0,
    strip_rows: int = _STRIP_ROWS,
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
    # the finer level's rows, a 2x2 block of pixels into one. Two readers walk down each
    # coarse level, its own sweep (_Level) and the summing of the level below it, each
    # asking for rows no higher than it asked last; the rows above both are dropped.
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
            chunks.append((held, _block_sums(finer)))
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
    # coarser level's final ones (zero at the coarsest level). A band's first and last
    # rows are only updated where they are the grid's (its staircase starts below the
    # first and stops above the last), so the level's weights serve every band.
    def __init__(self, level, data, weights, coarser, truncation, iterations):
        self.level, self.data, self.coarser = level, data, coarser
        self.weights = tuple(_weights_by_colour(*weights))
        self.rows, self.cols = data.shapes[level]
        self.truncation, self.iterations = truncation, iterations
        self.front, self.start = -iterations, 0
        shape = (2, data.cost.shape[2], self.cols // 2 + 2)
        self.messages = tuple(np.empty(shape, np.float32) for _ in range(8))

    def final(self, a, b):
        # Make the messages of rows a .. b - 1 final, a and b no lower than in the last
        # call: then self.messages holds them, in the layout of the sweeps, in a band of
        # rows from image row self.start on.
        if b > self.front:
            start = max(0, min(a, self.front))
            end = min(self.rows, b + self.iterations + 1)
            kept = self.start + self.messages[0].shape[0] - 2
            # the band moves down: its kept rows go up in place when its size stays (the
            # finest level's strips), so that no second band is alive meanwhile
            shape = (end - start + 2,) + self.messages[0].shape[1:]
            messages = (
                self.messages
                if self.messages[0].shape == shape
                else tuple(np.empty(shape, np.float32) for _ in range(8))
            )
            for rows, kept_rows in zip(messages, self.messages):
                rows[1 : 1 + kept - start] = kept_rows[
                    1 + start - self.start : 1 + kept - self.start
                ]
            if self.coarser is None:
                for rows in messages:
                    rows[1 + kept - start : 1 + end - start] = 0
            else:
                coarser = self.coarser
                coarser.final(kept // 2, (end - 1) // 2 + 1)
                _finer_messages(
                    coarser.messages, coarser.start, messages, start, kept, end, self.cols
                )
            _iterate(
                np.ascontiguousarray(self.data.rows(self.level, start, end, reader=0)),
                messages,
                tuple(weights[start : end + 2] for weights in self.weights),
                self.truncation,
                self.iterations,
                start,
                self.front + self.iterations - start,
                b + self.iterations - start,
                self.cols,
                numba.config.NUMBA_NUM_THREADS,
            )
            self.messages, self.start, self.front = messages, start, b
