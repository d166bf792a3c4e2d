"""Matching costs of a rectified pair, chosen by name from :data:`COSTS`: AD-census (the
census transform's Hamming distance with the colour difference), and a sparse census
whose bits are weighted by colour similarity (adaptive support weights) with the
difference of the intensity gradients."""

from __future__ import annotations

from collections.abc import Callable

import cv2
import llvmlite.ir as ir
import numpy as np
from numba import njit, prange, types
from numba.extending import intrinsic

__all__ = [
    "COSTS",
    "ad_census_cost",
    "ad_census_levels",
    "ad_census_signatures",
    "as_colour",
    "census_gradient_cost",
    "census_gradient_levels",
    "census_transform",
    "check_pair",
    "like_colour_masks",
    "mirror_costs",
    "popcount",
    "support_weights",
]


def _neighbour_offsets(window: tuple[int, int], step: int) -> list[tuple[int, int]]:
    # The census neighbours in row-major order, the first one the signature's highest bit.
    height, width = window
    if height % 2 == 0 or width % 2 == 0 or step < 1 or (height // 2) % step or (width // 2) % step:
        raise ValueError(
            f"census window must be odd-sized with half sizes divisible by the "
            f"step, got {window} with step {step}"
        )
    offsets = [
        (dy, dx)
        for dy in range(-(height // 2), height // 2 + 1, step)
        for dx in range(-(width // 2), width // 2 + 1, step)
        if (dy, dx) != (0, 0)
    ]
    if len(offsets) > 64:
        raise ValueError(
            f"census window {window} with step {step} has {len(offsets)} "
            f"neighbours, more than the 64 bits of a signature"
        )
    return offsets


def census_transform(
    grey: np.ndarray, *, window: tuple[int, int] = (7, 9), step: int = 1, tolerance: float = 0.0
) -> np.ndarray:
    """Census signature of every pixel: one bit per window neighbour darker than the centre
    by more than ``tolerance``.

    Parameters
    ----------
    grey : ndarray, shape (H, W)
    window : (int, int)
        Odd window height and width.
    step : int
        Spacing of the compared neighbours (a sparse census for ``step > 1``); it must
        divide the window's half sizes, and there may be at most 64 neighbours (bits).
    tolerance : float
        Difference (grey units) within which a neighbour counts as no darker: a dead
        zone that keeps values equal up to a coding's rounding from flipping bits.

    Returns
    -------
    ndarray of uint64, shape (H, W)
        Neighbours in row-major order, the first in the highest used bit. Border pixels
        compare against the edge-replicated image.
    """
    _neighbour_offsets(window, step)
    height, width = window
    padded = np.pad(
        np.asarray(grey, dtype=np.float32), ((height // 2,) * 2, (width // 2,) * 2), mode="edge"
    )
    return _census(padded, height, width, step, np.float32(tolerance))


@njit(cache=True, nogil=True, parallel=True)
def _census(padded, height, width, step, tolerance):
    # a row's signatures a neighbour at a time, along the row: the comparisons of
    # neighbouring pixels are independent and run in vector lanes, where a pixel's
    # neighbours one after the other are a chain of shifts
    rows, cols = padded.shape[0] - height + 1, padded.shape[1] - width + 1
    ry, rx = height // 2, width // 2
    signature = np.zeros((rows, cols), np.uint64)
    for y in prange(rows):
        darker = padded[y + ry, rx : rx + cols] - tolerance
        bits = signature[y]
        for dy in range(0, height, step):
            for dx in range(0, width, step):
                if dy != ry or dx != rx:
                    neighbours = padded[y + dy, dx : dx + cols]
                    for x in range(cols):
                        bits[x] = (bits[x] << np.uint64(1)) | np.uint64(neighbours[x] < darker[x])
    return signature


def like_colour_masks(
    colour: np.ndarray, *, window: tuple[int, int] = (7, 9), step: int = 1, tolerance: int
) -> np.ndarray:
    """Which census neighbours are like the centre in colour: one bit per neighbour, in
    the order of :func:`census_transform`'s, set where the sum of the channels' absolute
    differences is at most ``tolerance``.

    Parameters
    ----------
    colour : ndarray, shape (H, W, 3) or (H, W)
        Non-negative integer values (others are rounded).
    window, step : see :func:`census_transform`
    tolerance : int
        Largest colour difference (8-bit levels summed over the channels) of a like
        neighbour.

    Returns
    -------
    ndarray of uint64, shape (H, W)
        Border pixels compare against the edge-replicated view, as the census does.

    Examples
    --------
    The right column of a 3x3 window is unlike its centre: the neighbours, row by row,
    are like, like, unlike; like, unlike; like, like, unlike.

    >>> colour = np.zeros((3, 3, 3), np.uint8)
    >>> colour[:, 2] = 200
    >>> bin(int(like_colour_masks(colour, window=(3, 3), tolerance=30)[1, 1]))
    '0b11010110'
    """
    _neighbour_offsets(window, step)
    height, width = window
    # channel planes, so that a row's neighbours sit side by side in vector lanes
    planes = np.ascontiguousarray(as_colour(colour).transpose(2, 0, 1))
    padded = np.pad(planes, ((0, 0), (height // 2,) * 2, (width // 2,) * 2), "edge")
    return _like_colour(padded, height, width, step, np.int32(tolerance))


@njit(cache=True, nogil=True, parallel=True)
def _like_colour(padded, height, width, step, tolerance):
    # a row's masks a neighbour at a time along the row, as _census builds its signatures
    rows, cols = padded.shape[1] - height + 1, padded.shape[2] - width + 1
    ry, rx = height // 2, width // 2
    masks = np.zeros((rows, cols), np.uint64)
    for y in prange(rows):
        red = padded[0, y + ry, rx : rx + cols]
        green = padded[1, y + ry, rx : rx + cols]
        blue = padded[2, y + ry, rx : rx + cols]
        bits = masks[y]
        for dy in range(0, height, step):
            for dx in range(0, width, step):
                if dy != ry or dx != rx:
                    other_red = padded[0, y + dy, dx : dx + cols]
                    other_green = padded[1, y + dy, dx : dx + cols]
                    other_blue = padded[2, y + dy, dx : dx + cols]
                    for x in range(cols):
                        difference = (
                            abs(other_red[x] - red[x])
                            + abs(other_green[x] - green[x])
                            + abs(other_blue[x] - blue[x])
                        )
                        bits[x] = (bits[x] << np.uint64(1)) | np.uint64(difference <= tolerance)
    return masks


def support_weights(
    colour: np.ndarray, *, window: tuple[int, int] = (7, 9), step: int = 1, gamma: float = 15.0
) -> np.ndarray:
    """Weight of each census neighbour: its colour similarity to the centre,
    ``exp(-mean_c |I_c(q) - I_c(p)| / gamma)`` (Yoon & Kweon's adaptive support weights).

    Parameters
    ----------
    colour : ndarray, shape (H, W, 3)
    window, step : see :func:`census_transform`
    gamma : float
        Colour difference (8-bit levels) that lowers a weight by a factor e.

    Returns
    -------
    ndarray of float32, shape (H, W, N)
        The N neighbours in the order of the census bits; 0 for neighbours outside
        the view, whose census bits compare against replicated border pixels.
    """
    colour = as_colour(colour)
    table = _weight_table(colour, gamma)
    offsets = np.array(_neighbour_offsets(window, step), np.int64).reshape(-1, 2)
    return _support_weights(colour, offsets, table)


def _weight_table(colour, gamma):
    # the weights tabulated over the integer sum of the channels' absolute differences
    if gamma <= 0:
        raise ValueError(f"gamma must be positive, got {gamma}")
    largest = 3 * max(int(colour.max(initial=0)) - int(colour.min(initial=0)), 0)
    return np.exp(-np.arange(largest + 1) / 3 / gamma).astype(np.float32)


@njit(cache=True, nogil=True, parallel=True)
def _support_weights(colour, offsets, table):
    rows, cols, _ = colour.shape
    weights = np.empty((rows, cols, offsets.shape[0]), np.float32)
    for y in prange(rows):
        _row_weights(colour, offsets, table, y, weights[y])
    return weights


@njit(cache=True, nogil=True)
def _row_weights(colour, offsets, table, y, weights):
    # row y of support_weights into weights, (W, N): the census-gradient cost makes its
    # weights a row at a time with it rather than holding them for the whole view
    rows, cols, _ = colour.shape
    for x in range(cols):
        for index in range(offsets.shape[0]):
            qy, qx = y + offsets[index, 0], x + offsets[index, 1]
            if 0 <= qy < rows and 0 <= qx < cols:
                difference = 0
                for c in range(3):
                    difference += abs(colour[qy, qx, c] - colour[y, x, c])
                weights[x, index] = table[difference]
            else:
                weights[x, index] = 0.0


@intrinsic
def popcount(typing_context, value):
    # LLVM's population count: one machine instruction where the CPU has it.
    def codegen(context, builder, signature, args):
        function = builder.module.declare_intrinsic("llvm.ctpop", [ir.IntType(64)])
        return builder.call(function, args)

    return types.uint64(types.uint64), codegen


@njit(cache=True, nogil=True, parallel=True)
def _ad_census_volume(
    census_left,
    census_right,
    colour_left,
    colour_right,
    census_table,
    fewest_like,
    colour_table,
    min_disparity,
    levels,
    outside_cost,
):
    # census_* are (H, W, 2): the signatures and the like-colour masks
    rows, cols, _ = colour_left.shape
    volume = np.empty((rows, cols, levels), np.float32)
    for y in prange(rows):
        for x in range(cols):
            signature, like_left = census_left[y, x, 0], census_left[y, x, 1]
            red, green, blue = colour_left[y, x, 0], colour_left[y, x, 1], colour_left[y, x, 2]
            for k in range(levels):
                xr = x - (min_disparity + k)
                if xr < 0 or xr >= cols:
                    volume[y, x, k] = outside_cost
                    continue
                colour = (
                    abs(red - colour_right[y, xr, 0])
                    + abs(green - colour_right[y, xr, 1])
                    + abs(blue - colour_right[y, xr, 2])
                )
                differing = signature ^ census_right[y, xr, 0]
                like = like_left & census_right[y, xr, 1]
                if popcount(like) >= fewest_like:
                    differing &= like
                volume[y, x, k] = census_table[popcount(differing)] + colour_table[colour]
    return volume


@njit(cache=True, nogil=True, parallel=True)
def _census_gradient_volume(
    signature_left,
    signature_right,
    colour_left,
    colour_right,
    offsets,
    table_left,
    table_right,
    gradient_left,
    gradient_right,
    min_disparity,
    lambda_census,
    lambda_gradient,
    outside_cost,
    volume,
):
    # The census bits and support weights of both views a row at a time (the row's
    # matches lie on the same row of the other view): held for whole views they would
    # take 48 bytes of bits and 192 of weights per pixel and view, half a volume at
    # 256 levels, beside the volume.
    rows, cols, _ = volume.shape
    neighbours = offsets.shape[0]
    for y in prange(rows):
        bits_left = np.empty((cols, neighbours), np.uint8)
        bits_right = np.empty((cols, neighbours), np.uint8)
        weights_left = np.empty((cols, neighbours), np.float32)
        weights_right = np.empty((cols, neighbours), np.float32)
        _row_bits(signature_left, y, bits_left)
        _row_bits(signature_right, y, bits_right)
        _row_weights(colour_left, offsets, table_left, y, weights_left)
        _row_weights(colour_right, offsets, table_right, y, weights_right)
        _census_gradient_row(
            bits_left,
            bits_right,
            weights_left,
            weights_right,
            gradient_left[y],
            gradient_right[y],
            min_disparity,
            lambda_census,
            lambda_gradient,
            outside_cost,
            volume[y],
        )
    return volume


@njit(cache=True, nogil=True)
def _row_bits(signature, y, bits):
    # row y's census signatures as one byte per neighbour, highest bit first, as the
    # support weights are ordered: bits of (W, N)
    cols, neighbours = bits.shape
    for x in range(cols):
        for index in range(neighbours):
            bits[x, index] = (signature[y, x] >> np.uint64(neighbours - 1 - index)) & np.uint64(1)


# fastmath lets the sums over the neighbours run in SIMD lanes; the order of the
# additions is fixed by the compiled code, so the result stays deterministic.
@njit(cache=True, nogil=True, fastmath=True)
def _census_gradient_row(
    bits_left,
    bits_right,
    weights_left,
    weights_right,
    gradient_left,
    gradient_right,
    min_disparity,
    lambda_census,
    lambda_gradient,
    outside_cost,
    costs,
):
    # the costs (W, levels) of one row from its bits and weights (W, N) and gradients
    # (W, 2) in both views
    cols, levels = costs.shape
    neighbours = weights_left.shape[1]
    for x in range(cols):
        for k in range(levels):
            xr = x - (min_disparity + k)
            if xr < 0 or xr >= cols:
                costs[x, k] = outside_cost
                continue
            total = np.float32(0.0)
            mismatch = np.float32(0.0)
            for b in range(neighbours):
                weight = weights_left[x, b] * weights_right[xr, b]
                total += weight
                mismatch += weight * np.float32(bits_left[x, b] ^ bits_right[xr, b])
            gradient = abs(gradient_left[x, 0] - gradient_right[xr, 0]) + abs(
                gradient_left[x, 1] - gradient_right[xr, 1]
            )
            # no neighbour inside both views (a view of one pixel): no census evidence
            fraction = mismatch / total if total > 0 else np.float32(0.0)
            costs[x, k] = (
                2.0 - np.exp(-fraction / lambda_census) - np.exp(-gradient / lambda_gradient)
            )


def check_pair(
    left: np.ndarray, right: np.ndarray, *, min_disparity: int, max_disparity: int
) -> tuple[np.ndarray, np.ndarray]:
    """The views of a rectified pair as arrays, checked for what every matcher needs.

    Raises
    ------
    ValueError
        Views of different shapes or neither (H, W) nor (H, W, 3), an empty disparity
        range, or one at least as wide as the views.
    """
    left = np.asarray(left)
    right = np.asarray(right)
    if (
        left.shape != right.shape
        or left.ndim not in (2, 3)
        or (left.ndim == 3 and left.shape[2] != 3)
    ):
        raise ValueError(
            f"views must be (H, W) or (H, W, 3) arrays of the same shape, got "
            f"{left.shape} and {right.shape}"
        )
    if min_disparity > max_disparity:
        raise ValueError(f"min_disparity {min_disparity} exceeds max_disparity {max_disparity}")
    if max_disparity - min_disparity >= left.shape[1]:
        raise ValueError(
            f"disparity range {min_disparity}..{max_disparity} is not narrower "
            f"than the image width {left.shape[1]}"
        )
    return left, right


#: AD-census's settings, shared by the rectified pair's costs and the plane sweep
#: (:func:`ad_census_cost`): the census window (height, width), the Hamming distance and
#: colour difference at which each term reaches 1 - 1/e, the cost where nothing matches.
CENSUS_WINDOW = (7, 9)
#: AD-census's census tolerance (:func:`census_transform`): half a grey level, the rounding
#: of an 8-bit coding, so that pictures that went through YUV (whose RGB comes back off
#: by up to a level, and interpolated where the chroma was subsampled) keep the census
#: signatures of their near-flat regions. ``bp`` with the stereo-pair mode's chain, bad
#: 1.0 % of Tsukuba, Venus, Teddy, Cones, Art, Dolls, Moebius, without and with it: from
#: the RGB pictures 1.68, 0.53, 5.08, 2.47, 6.83, 3.74, 7.31 (mean 3.95) and 1.56, 0.48,
#: 5.19, 2.48, 6.85, 3.70, 7.18 (3.92); from the same pictures through YUV 4:2:0 2.17,
#: -, 4.51, 2.99, 7.40, 4.39, 8.65 and 1.82, -, 4.53, 2.96, 7.16, 3.98, 8.22; through the
#: DERS cases (:mod:`mvtools.depth.ders`) mean 4.05 and 3.97. A tolerance of one level
#: was worse (DERS cases 4.04). The census-gradient cost keeps none: its weighted census
#: lost by it on the RGB pictures (Moebius 5.06 to 5.75).
CENSUS_TOLERANCE = 0.5
#: AD-census's like neighbours (:func:`like_colour_masks`): the census counts only the
#: differing neighbours whose colour is within CENSUS_LIKE_COLOUR (8-bit levels summed
#: over the channels) of the centre's in both views, when at least CENSUS_FEWEST_LIKE
#: are; with fewer, the whole window. See :func:`ad_census_cost`. Chosen on every
#: Middlebury pair, Tsukuba's five views and the synthetic dense line together (the
#: figures with every neighbour counted that is like in both views, however few): a
#: colour tolerance of 30 lost Cones (3.17 % bad 1.0 against 2.26), 45 did as well
#: overall but lost Venus, Teddy and the dense line's 17 views (90 bad pixels against
#: 82), 90 lost Tsukuba's pair and five views (1.36 and 1.20 % against 1.45 and 1.18).
#: Without the floor of 12 like neighbours (or with 6 or 9), a texture of fine,
#: contrasting colours (blurred noise) left its like neighbours too few to tell a
#: one-pixel shift, and the disparity of the columns whose match lies outside the other
#: view, carried there by the smoothness, came out a pixel off (up to 164 pixels of
#: 5400); 20 lost Tsukuba's five views (1.24 %). The DERS mode's plane
#: sweep (:mod:`mvtools.depth.planesweep`) still compares the whole window: it warps
#: each view by the plane's homography at sub-pixel positions, and the rule is not yet
#: carried over and measured there.
CENSUS_LIKE_COLOUR = 60
CENSUS_FEWEST_LIKE = 12
LAMBDA_CENSUS = 30.0
LAMBDA_COLOUR = 20.0
OUTSIDE_COST = 0.7


def ad_census_cost(
    left: np.ndarray,
    right: np.ndarray,
    *,
    min_disparity: int,
    levels: int,
    census_window: tuple[int, int] = CENSUS_WINDOW,
    lambda_census: float = LAMBDA_CENSUS,
    lambda_colour: float = LAMBDA_COLOUR,
    outside_cost: float = OUTSIDE_COST,
    signatures: tuple[np.ndarray, np.ndarray] | None = None,
) -> np.ndarray:
    """AD-census matching cost volume of the left view (Mei et al. 2011).

    ``cost = 2 - exp(-hamming / lambda_census) - exp(-colour / lambda_colour)``: each term
    saturates, so neither a census flip on a repetitive texture nor a colour bias between
    the cameras dominates.

    The Hamming distance counts only the neighbours like the centre in colour in both
    views (:func:`like_colour_masks` with :data:`CENSUS_LIKE_COLOUR`): a binary,
    two-view form of the support weights of Yoon and Kweon ("Adaptive support-weight
    approach for correspondence search", IEEE TPAMI 28(4), 2006). A neighbour of
    another colour most likely lies on another surface, at another disparity, and its
    comparison would pull a pixel near a depth step towards that surface's match: the
    foreground fattening of window costs. A pixel with few like neighbours gets a
    census term that can say little, and the colour term and the smoothness decide it;
    with fewer than :data:`CENSUS_FEWEST_LIKE` (a fine texture of contrasting colours,
    where no surface around the pixel shares its colour) the whole window counts.
    Against the whole window's census (:mod:`benchmarks.bench_depth`), bad 1.0 % of the
    seven Middlebury pairs, mean: ``bp`` 3.92 to 3.70 (Tsukuba 1.56 to 1.29, Teddy 5.19
    to 4.84, Cones 2.48 to 2.27, Art 6.85 to 6.26, Moebius 7.18 to 6.94; Venus 0.48 to
    0.54, Dolls 3.70 to 3.73), ``sgm`` 4.13 to 3.73, ``graphcut`` 4.43 to 4.08,
    ``local`` 4.84 to 4.57; Cones im4 synthesized from ``bp``'s depth 30.32 to 30.47 dB
    (1D mode 30.31 to 30.60), from every other method's higher too. It loses where a
    surface's own texture has strong colour edges: the synthetic scene's brick wall,
    whose mortar joints have few like neighbours (the dense line's pair 0.46 to 0.48 %
    bad 1.0). Counting the like neighbours' differences scaled to the whole window's
    count instead lost the synthesized im4 0.5 dB, a thin object's few like neighbours
    then weighing as much as a whole window; counting, besides, the neighbours like the
    centre in one view only as differing won on the synthetic scene and lost the gains
    on the Middlebury pairs.

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
    signatures : (ndarray, ndarray) of uint64, optional
        The views' census signatures (:func:`ad_census_signatures` with this
        ``census_window``) when the caller has them, as a view matched with several
        others is transformed once; for a mirrored pair, those of the views before the
        mirroring, mirrored alike: a mirrored view's signatures are those of the view
        with their bits reordered, the same for both views, which keeps every Hamming
        distance.

    Returns
    -------
    ndarray of float32, shape (H, W, levels)
        Costs in [0, 2].

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> left = rng.integers(0, 256, (6, 12, 3)).astype(np.uint8)
    >>> right = np.roll(left, -2, axis=1)
    >>> mirrored = [np.ascontiguousarray(view[:, ::-1]) for view in (right, left)]
    >>> signatures = [ad_census_signatures(view)[:, ::-1] for view in (right, left)]
    >>> bool(np.array_equal(
    ...     ad_census_cost(*mirrored, min_disparity=0, levels=4),
    ...     ad_census_cost(*mirrored, min_disparity=0, levels=4, signatures=signatures),
    ... ))
    True
    """
    return _ad_census_volume(
        *_ad_census_inputs(left, right, census_window, lambda_census, lambda_colour, signatures),
        int(min_disparity),
        int(levels),
        np.float32(outside_cost),
    )


def ad_census_signatures(
    view: np.ndarray, *, census_window: tuple[int, int] = CENSUS_WINDOW
) -> np.ndarray:
    """The census signatures :func:`ad_census_cost` compares, with the neighbours like the
    centre in colour: :func:`census_transform` of the view's mean over its channels, with
    :data:`CENSUS_TOLERANCE`, and :func:`like_colour_masks` with
    :data:`CENSUS_LIKE_COLOUR`.

    Parameters
    ----------
    view : ndarray, shape (H, W, 3) or (H, W)
        Non-negative integer values (others are rounded).
    census_window : (int, int)
        As for :func:`ad_census_cost`.

    Returns
    -------
    ndarray of uint64, shape (H, W, 2)
        The signatures, then the like-colour masks.
    """
    return _colour_signatures(as_colour(view), census_window)


def _colour_signatures(colour, census_window):
    # ad_census_signatures of a view already as_colour; its mean over the channels from
    # their integer sum (exact), the same values as colour.mean(axis=2) ten times faster
    grey = (colour[:, :, 0] + colour[:, :, 1] + colour[:, :, 2]) / 3
    return np.stack(
        [
            census_transform(grey, window=census_window, tolerance=CENSUS_TOLERANCE),
            like_colour_masks(colour, window=census_window, tolerance=CENSUS_LIKE_COLOUR),
        ],
        axis=2,
    )


def _ad_census_inputs(left, right, census_window, lambda_census, lambda_colour, signatures=None):
    # the census signatures and colours of both views, and both terms' tables
    colour_left = as_colour(left)
    colour_right = as_colour(right)
    if signatures is None:
        signatures = [
            _colour_signatures(colour, census_window) for colour in (colour_left, colour_right)
        ]
    census_left, census_right = (
        np.ascontiguousarray(signature, np.uint64) for signature in signatures
    )
    fitting = [(*colour.shape[:2], 2) for colour in (colour_left, colour_right)]
    if [census_left.shape, census_right.shape] != fitting:
        raise ValueError(
            f"census signatures of shapes {census_left.shape} and {census_right.shape} do "
            f"not fit views of {colour_left.shape[:2]} and {colour_right.shape[:2]}"
        )
    # Both terms tabulated over their integer arguments: the Hamming distance over the
    # like neighbours and the sum of the channels' absolute differences.
    census_table = 1.0 - np.exp(-np.arange(65) / lambda_census)
    largest = int(max(colour_left.max(), colour_right.max(), 0))
    colour_table = 1.0 - np.exp(-np.arange(3 * largest + 1) / 3 / lambda_colour)
    return (
        census_left,
        census_right,
        colour_left,
        colour_right,
        census_table.astype(np.float32),
        np.int64(CENSUS_FEWEST_LIKE),
        colour_table.astype(np.float32),
    )


def ad_census_levels(
    left: np.ndarray,
    right: np.ndarray,
    *,
    min_disparity: int,
    levels: int,
    census_window: tuple[int, int] = CENSUS_WINDOW,
    lambda_census: float = LAMBDA_CENSUS,
    lambda_colour: float = LAMBDA_COLOUR,
    outside_cost: float = OUTSIDE_COST,
    signatures: tuple[np.ndarray, np.ndarray] | None = None,
) -> Callable[[int], np.ndarray]:
    """The levels of :func:`ad_census_cost` one at a time, without the volume.

    Parameters
    ----------
    left, right, min_disparity, levels, census_window, lambda_census, lambda_colour
        As for :func:`ad_census_cost`.
    outside_cost, signatures
        As for :func:`ad_census_cost`.

    Returns
    -------
    callable
        ``level(k)``: the (H, W) float32 costs of disparity ``min_disparity + k``, equal
        to ``ad_census_cost(...)[:, :, k]``.

    Examples
    --------
    >>> left = np.array([[[0], [10], [20], [60]]] * 3, np.uint8).repeat(3, axis=2)
    >>> right = np.roll(left, -1, axis=1)
    >>> level = ad_census_levels(left, right, min_disparity=0, levels=2)
    >>> volume = ad_census_cost(left, right, min_disparity=0, levels=2)
    >>> bool(np.array_equal(level(1), volume[:, :, 1]))
    True
    """
    inputs = _ad_census_inputs(left, right, census_window, lambda_census, lambda_colour, signatures)

    def level(k: int) -> np.ndarray:
        if not 0 <= k < levels:
            raise ValueError(f"level {k} is not in 0..{levels - 1}")
        return _ad_census_volume(
            *inputs,
            int(min_disparity) + int(k),
            1,
            np.float32(outside_cost),
        )[:, :, 0]

    return level


#: The census-gradient cost's settings, shared by the volume and its levels
#: (:func:`census_gradient_cost`): the sparse census's window (height, width) and step,
#: the colour scale of its weights, the scales of the weighted fraction of differing bits
#: and of the gradient difference, the cost where nothing matches.
GRADIENT_CENSUS_WINDOW = (13, 13)
GRADIENT_CENSUS_STEP = 2
GAMMA = 15.0
GRADIENT_LAMBDA_CENSUS = 30 / 63
LAMBDA_GRADIENT = 15.0
GRADIENT_OUTSIDE_COST = 0.8

#: levels that census_gradient_levels computes together
_LEVEL_BLOCK = 16


def census_gradient_cost(
    left: np.ndarray,
    right: np.ndarray,
    *,
    min_disparity: int,
    levels: int,
    census_window: tuple[int, int] = GRADIENT_CENSUS_WINDOW,
    census_step: int = GRADIENT_CENSUS_STEP,
    gamma: float = GAMMA,
    lambda_census: float = GRADIENT_LAMBDA_CENSUS,
    lambda_gradient: float = LAMBDA_GRADIENT,
    outside_cost: float = GRADIENT_OUTSIDE_COST,
) -> np.ndarray:
    """Matching cost volume of the left view: weighted sparse census plus gradients.

    ``cost = 2 - exp(-census / lambda_census) - exp(-gradient / lambda_gradient)``, each
    term saturating as in AD-census (Mei et al. 2011), so that neither a census flip on a
    repetitive texture nor a gradient outlier dominates:

    - ``census`` is the weighted fraction of differing census bits
      (:func:`census_transform`), the weight of a neighbour being the product of its
      :func:`support_weights` in both views. Neighbours of another colour than the
      centre, likely on another surface, hardly count, so a window straddling a depth
      edge does not carry the foreground's disparity onto the untextured background
      beside it; that lets the window be larger.
    - ``gradient`` is ``|dI/dx_left - dI/dx_right| + |dI/dy_left - dI/dy_right|``, the
      Sobel derivatives of the mean of the channels per pixel. Unlike the colour
      difference it ignores brightness offsets between the views, such as the
      highlights of glossy surfaces (Hirschmüller & Scharstein 2009 found census and
      gradient costs the robust ones under radiometric differences).

    Parameters
    ----------
    left, right, min_disparity, levels
        As for :func:`ad_census_cost`.
    census_window, census_step : (int, int), int
        Extent and spacing of the census neighbours (48 of a 13x13 window by default).
    gamma : float
        Colour scale of the support weights.
    lambda_census : float
        Scale of the weighted fraction of differing bits: Mei et al.'s 30 of 63 bits.
    lambda_gradient : float
        Scale of the gradient difference, in 8-bit levels per pixel.
    outside_cost : float
        As for :func:`ad_census_cost`; chosen for this cost (see Notes).

    Returns
    -------
    ndarray of float32, shape (H, W, levels)
        Costs in [0, 2].

    Notes
    -----
    Bad 1.0 (%, the Middlebury protocol of :func:`mvtools.depth.estimate_disparity`) of
    the ``bp`` method with segment planes on the seven Middlebury pairs, and on Aloe
    (2006) at a third of its size over all known pixels as a check on a pair not used
    for the choices; "weighted" is the census of this function, the unweighted ones
    compare all bits alike:

    =====================================  ====  =====  =====  =====  ====  =====  ====  ====  ====
    census, pixel term                     Tsu.  Venus  Teddy  Cones  Art   Dolls  Moeb  mean  Aloe
    =====================================  ====  =====  =====  =====  ====  =====  ====  ====  ====
    7x9, colour (``ad-census``)            1.68  0.53   5.08   2.47   6.83  3.74   7.31  3.95  6.85
    7x9 weighted, colour                   2.27  0.55   4.88   2.59   5.87  3.51   6.31  3.71  6.63
    11x15 step 2 weighted, colour          1.80  0.39   5.30   2.78   6.77  3.41   5.88  3.76  6.85
    11x15 step 2 weighted, gradient        1.82  0.39   5.63   2.71   7.06  3.35   5.37  3.76  6.94
    13x13 step 2 unweighted, gradient      2.35  0.54   5.72   3.08   8.14  4.05   6.73  4.37
    13x13 step 2 weighted, gradient        1.87  0.42   4.80   2.65   6.42  3.42   4.99  3.51  6.84
    the same, outside cost 0.8 (default)   1.87  0.41   4.89   2.35   6.46  3.26   5.06  3.47  6.62
    =====================================  ====  =====  =====  =====  ====  =====  ====  ====  ====

    All rows but the last have an outside cost of 0.7 and edge-replicated neighbours
    weighted like the others (the last gives neighbours outside the view no weight).
    Around the default the mean stays within 3.52-3.56 for ``gamma`` 10 and 20 and
    ``lambda_gradient`` 21; ``lambda_gradient`` 10 gives 3.72 (Cones 3.06).
    Moebius gains most: its glossy green facet is up to 45 levels brighter in the right
    view, and its plain wall beside the pink star took the star's disparity through
    the unweighted windows.

    The synthesized view pays for it: Cones im4 from the estimated depth of im2 and
    im6 (:mod:`benchmarks.bench_depth`) drops from 30.35 dB Y-PSNR with ``ad-census``
    to 30.08 dB (outside costs 0.6, 0.7, 0.9: 29.39, 29.85, 29.95 dB). The colour
    weights cost it, not the window or the gradients (the unweighted 13x13 census with
    gradients gives 30.10 dB, the weighted 7x9 with colour 29.67 dB, both at 0.7): the
    thin light sticks in front of the light cloth lose their disparity and are doubled.
    That is why ``ad-census`` stays the default of
    :func:`mvtools.depth.estimate_disparity`. The table and these figures are from
    before AD-census counted only the neighbours like the centre in colour
    (:func:`ad_census_cost`), which took its row to 1.29, 0.54, 4.84, 2.27, 6.26, 3.73,
    6.94 (mean 3.70) and its Cones im4 to 30.47 dB (1D mode 30.60).
    """
    inputs = _census_gradient_inputs(left, right, census_window, census_step, gamma)
    volume = np.empty((*inputs[2].shape[:2], int(levels)), np.float32)
    return _census_gradient_volume(
        *inputs,
        int(min_disparity),
        np.float32(lambda_census),
        np.float32(lambda_gradient),
        np.float32(outside_cost),
        volume,
    )


def census_gradient_levels(
    left: np.ndarray,
    right: np.ndarray,
    *,
    min_disparity: int,
    levels: int,
    census_window: tuple[int, int] = GRADIENT_CENSUS_WINDOW,
    census_step: int = GRADIENT_CENSUS_STEP,
    gamma: float = GAMMA,
    lambda_census: float = GRADIENT_LAMBDA_CENSUS,
    lambda_gradient: float = LAMBDA_GRADIENT,
    outside_cost: float = GRADIENT_OUTSIDE_COST,
) -> Callable[[int], np.ndarray]:
    """The levels of :func:`census_gradient_cost` one at a time, without the volume.

    Parameters
    ----------
    left, right, min_disparity, levels
        As for :func:`census_gradient_cost`.
    census_window, census_step, gamma, lambda_census, lambda_gradient, outside_cost
        As for :func:`census_gradient_cost`.

    Returns
    -------
    callable
        ``level(k)``: the (H, W) float32 costs of disparity ``min_disparity + k``, equal
        to ``census_gradient_cost(...)[:, :, k]``.

    Examples
    --------
    >>> texture = np.random.default_rng(0).integers(0, 256, (9, 12, 3), np.uint8)
    >>> left, right = texture[:, :-2], texture[:, 2:]
    >>> level = census_gradient_levels(left, right, min_disparity=0, levels=3)
    >>> volume = census_gradient_cost(left, right, min_disparity=0, levels=3)
    >>> bool(np.array_equal(level(2), volume[:, :, 2]))
    True
    """
    inputs = _census_gradient_inputs(left, right, census_window, census_step, gamma)
    rows, cols = inputs[2].shape[:2]
    # The volume's kernel on a block of levels at a time: it makes the bits and weights
    # of a row again at each call, which costs about six levels' worth, so a block of
    # consecutive levels (graphcut asks for them in order) shares them.
    block = {"start": 0, "costs": np.empty((rows, cols, 0), np.float32)}

    def level(k: int) -> np.ndarray:
        if not 0 <= k < levels:
            raise ValueError(f"level {k} is not in 0..{levels - 1}")
        if not block["start"] <= k < block["start"] + block["costs"].shape[2]:
            block["costs"] = None  # freed before the next block is made
            block["start"] = k
            block["costs"] = _census_gradient_volume(
                *inputs,
                int(min_disparity) + int(k),
                np.float32(lambda_census),
                np.float32(lambda_gradient),
                np.float32(outside_cost),
                np.empty((rows, cols, min(_LEVEL_BLOCK, levels - k)), np.float32),
            )
        # a copy, so that no caller can change the block's other levels
        return block["costs"][:, :, k - block["start"]].copy()

    return level


def _census_gradient_inputs(left, right, census_window, census_step, gamma):
    # the census signatures, colours, weight tables and gradients of both views and the
    # census neighbours: what _census_gradient_volume makes a row's bits and weights of
    colour_left = as_colour(left)
    colour_right = as_colour(right)
    offsets = np.array(_neighbour_offsets(census_window, census_step), np.int64).reshape(-1, 2)
    signatures, gradients = [], []
    for colour in (colour_left, colour_right):
        grey = colour.mean(axis=2, dtype=np.float32)
        signatures.append(census_transform(grey, window=census_window, step=census_step))
        # Sobel / 8: the derivative in levels per pixel
        gradients.append(
            np.ascontiguousarray(
                np.stack(
                    [
                        cv2.Sobel(grey, cv2.CV_32F, 1, 0, ksize=3, borderType=cv2.BORDER_REPLICATE)
                        / 8,
                        cv2.Sobel(grey, cv2.CV_32F, 0, 1, ksize=3, borderType=cv2.BORDER_REPLICATE)
                        / 8,
                    ],
                    axis=2,
                )
            )
        )
    return (
        *signatures,
        colour_left,
        colour_right,
        offsets,
        _weight_table(colour_left, gamma),
        _weight_table(colour_right, gamma),
        *gradients,
    )


def as_colour(image: np.ndarray) -> np.ndarray:
    """An (H, W, 3) or (H, W) view as contiguous (H, W, 3) int32, rounded, grey repeated in
    three equal channels: one kernel then serves colour and grey views."""
    image = np.asarray(image)
    # rounding an integer image would only pass it through a float copy
    image = (image if np.issubdtype(image.dtype, np.integer) else np.rint(image)).astype(np.int32)
    return np.ascontiguousarray(
        np.repeat(image[:, :, None], 3, axis=2) if image.ndim == 2 else image
    )


def mirror_costs(volume: np.ndarray, *, min_disparity: int) -> np.ndarray:
    """Turn, in place, the left view's cost volume of a pair into that of the mirrored,
    swapped pair (``right[:, ::-1]`` as the left view, ``left[:, ::-1]`` as the right).

    The mirrored pair's cost at ``(y, x, k)`` compares the right view's column
    ``W - 1 - x`` with the left view's ``W - 1 - x + d``, which is the pair's own cost at
    ``(y, W - 1 - x + d, k)`` when the cost is symmetric in its two views and the same
    for mirrored views: so for :func:`ad_census_cost` (colour differences; census
    signatures of a mirrored image hold the same comparisons in another bit order, and
    Hamming distances ignore the order), bit for bit. Not so for
    :func:`census_gradient_cost`, whose weighted sums run in bit order. Levels whose
    match falls outside the image take the pair's own outside cost.

    Parameters
    ----------
    volume : ndarray of float32, shape (H, W, D), contiguous
        Costs of the disparities ``min_disparity .. min_disparity + D - 1``; overwritten.
    min_disparity : int

    Returns
    -------
    ndarray of float32, shape (H, W, D)
        ``volume``.

    Examples
    --------
    >>> left = np.array([[[0], [10], [20], [60]]] * 3, np.uint8).repeat(3, axis=2)
    >>> right = np.roll(left, -1, axis=1)
    >>> costs = ad_census_cost(left, right, min_disparity=0, levels=2)
    >>> mirrored = ad_census_cost(right[:, ::-1], left[:, ::-1], min_disparity=0, levels=2)
    >>> bool(np.array_equal(mirror_costs(costs, min_disparity=0), mirrored))
    True
    """
    if volume.ndim != 3 or volume.dtype != np.float32 or not volume.flags.c_contiguous:
        raise ValueError("volume must be a contiguous (H, W, D) float32 array")
    _mirror_rows(volume, int(min_disparity))
    return volume


@njit(cache=True, nogil=True, parallel=True)
def _mirror_rows(volume, min_disparity):
    rows, cols, levels = volume.shape
    for y in prange(rows):
        row = volume[y].copy()
        for x in range(cols):
            for k in range(levels):
                d = min_disparity + k
                source = cols - 1 - x + d
                if 0 <= source < cols:
                    volume[y, x, k] = row[source, k]
                else:
                    # outside: the pair's own outside entry of this level (x - d leaves
                    # the image at column 0 for d > 0, at column W - 1 for d < 0)
                    volume[y, x, k] = row[0, k] if d > 0 else row[cols - 1, k]


#: name -> ``cost(left, right, *, min_disparity, levels) -> (H, W, levels) float32``,
#: the matching costs that :func:`mvtools.depth.estimate_disparity` can optimise.
COSTS = {"ad-census": ad_census_cost, "census-gradient": census_gradient_cost}
