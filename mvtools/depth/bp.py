"""Hierarchical min-sum belief propagation (Felzenszwalb & Huttenlocher 2006) on the
4-connected grid: truncated linear smoothness with per-edge weights from
:func:`mvtools.depth.graphcut.smoothness_weights` (the energy the ``graphcut`` method
minimises), O(D) messages by a distance transform, checkerboard updates, coarse-to-fine
message initialisation."""

from __future__ import annotations

import numpy as np
from numba import njit, prange

from mvtools.depth.graphcut import smoothness_weights

__all__ = ["belief_propagation", "bp_volume"]

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
def _iterate(data, right, down, messages, truncation, iterations):
    # Checkerboard schedule: a pixel of one parity reads only its own slots, written
    # by the other parity in the previous half-sweep, and writes only into its
    # neighbours' slots, so every row runs in parallel.
    rows, cols, levels = data.shape
    for iteration in range(iterations):
        for y in prange(rows):
            total = np.empty(levels, np.float32)
            for x in range((y + iteration) % 2, cols, 2):
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
def _finer_messages(coarse, rows, cols):
    # each pixel starts from the messages its 2x2 block received, written straight into
    # the finer array (no repeated intermediate copies)
    fine = np.empty((coarse.shape[0], rows, cols, coarse.shape[3]), np.float32)
    for y in prange(rows):
        for s in range(coarse.shape[0]):
            for x in range(cols):
                fine[s, y, x, :] = coarse[s, y // 2, x // 2, :]
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
    scales: int = 5,
    iterations: int = 5,
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
    pyramid = [(cost, np.asarray(right, np.float32), np.asarray(down, np.float32))]
    while len(pyramid) < scales and min(pyramid[-1][0].shape[:2]) > 1:
        pyramid.append(_coarser(*pyramid[-1]))
    messages = None
    while pyramid:
        # the coarser levels are dropped as soon as the finer one starts
        data, level_right, level_down = pyramid.pop()
        if messages is None:
            messages = np.zeros((4,) + data.shape, np.float32)
        else:
            messages = _finer_messages(messages, data.shape[0], data.shape[1])
        _iterate(
            np.ascontiguousarray(data),
            np.ascontiguousarray(level_right),
            np.ascontiguousarray(level_down),
            messages,
            np.float32(truncation),
            iterations,
        )
        del data, level_right, level_down
    return _beliefs(cost, messages, cost if overwrite else np.empty_like(cost))


def bp_volume(
    cost: np.ndarray,
    guide: np.ndarray,
    *,
    smoothing: float = 16.0,
    smoothing2: float = 0.3,
    truncation: float = 4.0,
    colour_scale: float = 10.0,
    scales: int = 5,
    iterations: int = 5,
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
