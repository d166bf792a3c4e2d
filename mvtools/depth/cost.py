"""Pixel-wise matching costs of a rectified pair: census transform (Hamming distance)
combined with the mean absolute colour difference, AD-census style."""

from __future__ import annotations

import numpy as np
import llvmlite.ir as ir
from numba import njit, prange, types
from numba.extending import intrinsic

__all__ = ["census_transform", "ad_census_cost", "as_colour", "check_pair", "popcount"]


def census_transform(grey: np.ndarray, *, window: tuple[int, int] = (7, 9)) -> np.ndarray:
    """Census signature of every pixel: one bit per window neighbour darker than the centre.

    Parameters
    ----------
    grey : ndarray, shape (H, W)
    window : (int, int)
        Odd window height and width; at most 64 neighbours (bits).

    Returns
    -------
    ndarray of uint64, shape (H, W)
        Border pixels compare against the edge-replicated image.
    """
    height, width = window
    if height % 2 == 0 or width % 2 == 0 or height * width - 1 > 64:
        raise ValueError(f"census window must be odd-sized with at most 65 pixels, got {window}")
    padded = np.pad(np.asarray(grey, dtype=np.float32), ((height // 2,) * 2, (width // 2,) * 2),
                    mode="edge")
    return _census(padded, height, width)


@njit(cache=True, nogil=True, parallel=True)
def _census(padded, height, width):
    rows, cols = padded.shape[0] - height + 1, padded.shape[1] - width + 1
    ry, rx = height // 2, width // 2
    signature = np.zeros((rows, cols), np.uint64)
    for y in prange(rows):
        for x in range(cols):
            centre = padded[y + ry, x + rx]
            bits = np.uint64(0)
            for dy in range(height):
                for dx in range(width):
                    if dy != ry or dx != rx:
                        bits = (bits << np.uint64(1)) | np.uint64(padded[y + dy, x + dx] < centre)
            signature[y, x] = bits
    return signature


@intrinsic
def popcount(typing_context, value):
    # LLVM's population count: one machine instruction where the CPU has it.
    def codegen(context, builder, signature, args):
        function = builder.module.declare_intrinsic("llvm.ctpop", [ir.IntType(64)])
        return builder.call(function, args)
    return types.uint64(types.uint64), codegen


@njit(cache=True, nogil=True, parallel=True)
def _ad_census_volume(census_left, census_right, colour_left, colour_right, min_disparity,
                      levels, census_table, colour_table, outside_cost):
    rows, cols, _ = colour_left.shape
    volume = np.empty((rows, cols, levels), np.float32)
    for y in prange(rows):
        for x in range(cols):
            signature = census_left[y, x]
            red, green, blue = colour_left[y, x, 0], colour_left[y, x, 1], colour_left[y, x, 2]
            for k in range(levels):
                xr = x - (min_disparity + k)
                if xr < 0 or xr >= cols:
                    volume[y, x, k] = outside_cost
                    continue
                colour = (abs(red - colour_right[y, xr, 0]) + abs(green - colour_right[y, xr, 1])
                          + abs(blue - colour_right[y, xr, 2]))
                volume[y, x, k] = (census_table[popcount(signature ^ census_right[y, xr])]
                                   + colour_table[colour])
    return volume


def check_pair(left: np.ndarray, right: np.ndarray, *, min_disparity: int,
               max_disparity: int) -> tuple[np.ndarray, np.ndarray]:
    """The views of a rectified pair as arrays, checked for what every matcher needs.

    Raises
    ------
    ValueError
        Views of different shapes or neither (H, W) nor (H, W, 3), an empty disparity
        range, or one at least as wide as the views.
    """
    left = np.asarray(left)
    right = np.asarray(right)
    if left.shape != right.shape or left.ndim not in (2, 3) or (
            left.ndim == 3 and left.shape[2] != 3):
        raise ValueError(f"views must be (H, W) or (H, W, 3) arrays of the same shape, got "
                         f"{left.shape} and {right.shape}")
    if min_disparity > max_disparity:
        raise ValueError(f"min_disparity {min_disparity} exceeds max_disparity "
                         f"{max_disparity}")
    if max_disparity - min_disparity >= left.shape[1]:
        raise ValueError(f"disparity range {min_disparity}..{max_disparity} is not narrower "
                         f"than the image width {left.shape[1]}")
    return left, right


def ad_census_cost(left: np.ndarray, right: np.ndarray, *, min_disparity: int, levels: int,
                   census_window: tuple[int, int] = (7, 9), lambda_census: float = 30.0,
                   lambda_colour: float = 20.0, outside_cost: float = 0.7) -> np.ndarray:
    """AD-census matching cost volume of the left view (Mei et al. 2011).

    ``cost = 2 - exp(-hamming / lambda_census) - exp(-colour / lambda_colour)``: each term
    saturates, so neither a census flip on a repetitive texture nor a colour bias between
    the cameras dominates.

    Parameters
    ----------
    left, right : ndarray, shape (H, W, 3) or (H, W)
        Rectified views, non-negative integer values (others are rounded).
    min_disparity, levels : int
        Disparities ``min_disparity .. min_disparity + levels - 1``; ``x_right = x_left - d``.

    outside_cost : float
        Cost where ``x - d`` falls outside the right image. Below a typical mismatch,
        it lets the smoothness carry the disparity of the interior to the left border
        (whose points the right view does not see) instead of pinning it at small values.

    Returns
    -------
    ndarray of float32, shape (H, W, levels)
        Costs in [0, 2].
    """
    colour_left = as_colour(left)
    colour_right = as_colour(right)
    census_left = census_transform(colour_left.mean(axis=2), window=census_window)
    census_right = census_transform(colour_right.mean(axis=2), window=census_window)
    # Both terms tabulated over their integer arguments: the Hamming distance and the
    # sum of the channels' absolute differences.
    census_table = 1.0 - np.exp(-np.arange(65) / lambda_census)
    largest = int(max(colour_left.max(), colour_right.max(), 0))
    colour_table = 1.0 - np.exp(-np.arange(3 * largest + 1) / 3 / lambda_colour)
    return _ad_census_volume(census_left, census_right, colour_left, colour_right,
                             int(min_disparity), int(levels),
                             census_table.astype(np.float32), colour_table.astype(np.float32),
                             np.float32(outside_cost))


def as_colour(image: np.ndarray) -> np.ndarray:
    """An (H, W, 3) or (H, W) view as contiguous (H, W, 3) int32, rounded, grey repeated in
    three equal channels: one kernel then serves colour and grey views."""
    image = np.rint(np.asarray(image)).astype(np.int32)
    return np.ascontiguousarray(np.repeat(image[:, :, None], 3, axis=2) if image.ndim == 2
                                else image)
