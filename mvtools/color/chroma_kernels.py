"""The kernels of chroma resampling (:func:`mvtools.color.space.upsample_chroma` and
:func:`mvtools.color.space.downsample_chroma`).

Upsampling is one pass over the output: each sample interpolates the two nearest chroma
rows of the two nearest chroma columns, weights 3/4 and 1/4 (centred siting, edges
replicated). Downsampling averages each 2x2 block (or horizontal pair) and may round
straight into sample codes. Both work in float64 with the same operations in the same
order as one axis after the other, so the result does not depend on how it is computed.
numba, as they run in every synthesized frame; :mod:`mvtools.color.space` imports them
when it first resamples, so importing the colour conversions costs no numba.
"""

from __future__ import annotations

import numba
import numpy as np


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _taps(size: int, halved: bool, count: int):
    """Lower index, upper index and upper weight of each output sample along an axis."""
    lower = np.empty(size, np.int64)
    upper = np.empty(size, np.int64)
    weight = np.zeros(size)
    for x in range(size):
        if not halved:
            lower[x] = upper[x] = x
            continue
        # Output sample x sits at chroma coordinate (x - 0.5) / 2.
        position = (x - 0.5) / 2
        below = int(np.floor(position))
        weight[x] = position - below
        lower[x] = min(max(below, 0), count - 1)
        upper[x] = min(max(below + 1, 0), count - 1)
    return lower, upper, weight


@numba.njit(cache=True, nogil=True, error_model="numpy")
def upsample_bilinear(values, halved_rows: bool, halved_cols: bool, out) -> None:
    """Write into ``out`` (H, W) the bilinear upsampling of ``values`` along the halved
    axes (``values`` of shape (ceil(H/2) or H, ceil(W/2) or W))."""
    rows, cols = out.shape
    top, bottom, down = _taps(rows, halved_rows, values.shape[0])
    left, right, across = _taps(cols, halved_cols, values.shape[1])
    line = np.empty(values.shape[1])
    for y in range(rows):
        a, b, wy = top[y], bottom[y], down[y]
        for c in range(values.shape[1]):
            upper = np.float64(values[a, c])
            if halved_rows:
                line[c] = upper * (1 - wy) + np.float64(values[b, c]) * wy
            else:
                line[c] = upper
        for x in range(cols):
            if halved_cols:
                wx = across[x]
                out[y, x] = line[left[x]] * (1 - wx) + line[right[x]] * wx
            else:
                out[y, x] = line[x]


@numba.njit(cache=True, nogil=True, error_model="numpy")
def downsample_mean(values, halved_rows: bool, low: float, high: float, out) -> None:
    """Write into ``out`` the mean of each 2x2 block (``halved_rows``) or horizontal pair
    of ``values`` (H, W), an odd last row or column averaged with itself: rows first, then
    columns. Rounded half up and clipped to ``low .. high`` when ``low <= high``."""
    rows, cols = values.shape
    for i in range(out.shape[0]):
        top = 2 * i if halved_rows else i
        bottom = min(top + 1, rows - 1) if halved_rows else top
        for j in range(out.shape[1]):
            left = 2 * j
            right = min(left + 1, cols - 1)
            if halved_rows:
                first = 0.5 * (np.float64(values[top, left]) + np.float64(values[bottom, left]))
                second = 0.5 * (np.float64(values[top, right]) + np.float64(values[bottom, right]))
            else:
                first = np.float64(values[top, left])
                second = np.float64(values[top, right])
            mean = 0.5 * (first + second)
            if low <= high:
                mean = min(max(np.floor(mean + 0.5), low), high)
            out[i, j] = mean
