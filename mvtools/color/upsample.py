"""The kernel of bilinear chroma upsampling (:func:`mvtools.color.space.upsample_chroma`).

One pass over the output: each sample interpolates the two nearest chroma rows of the
two nearest chroma columns, weights 3/4 and 1/4 (centred siting, edges replicated),
in float64, with the same operations in the same order as one axis after the other,
so the result does not depend on how it is computed. numba, as it runs in every
synthesized frame; :mod:`mvtools.color.space` imports it when it first upsamples, so
importing the colour conversions costs no numba.
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
