"""IV-PSNR, MPEG's quality metric for synthesized (immersive) video.

A. Dziembowski, D. Mieloch, J. Stankowski and A. Grzelka, "IV-PSNR - the
objective quality metric for immersive video applications", IEEE Transactions on
Circuits and Systems for Video Technology 32(11):7575-7591, 2022,
doi:10.1109/TCSVT.2022.3179575.

This module follows the reference software of Poznan University of Technology
(J. Stankowski, A. Dziembowski, "IV-PSNR: Software for immersive video objective
quality evaluation", SoftwareX 24, 2023; github.com/jstankowski/ivpsnr, IVPSNR
v7.0, default "conformance" settings), re-implemented with whole-image numpy
operations.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from mvtools.metrics.psnr import subsampling_factors

SEARCH_RANGE = 2  # +-2 pixels: a 5x5 window
COMPONENT_WEIGHTS = (4, 1, 1)  # Y:U:V, for both the search and the final average
UNNOTICEABLE_FRACTION = 0.01  # color shift limit, fraction of the sample range


def iv_psnr(
    ref_planes: Sequence[np.ndarray], test_planes: Sequence[np.ndarray], *, bits: int
) -> float:
    """IV-PSNR of one frame, in dB, as computed by the MPEG reference software.

    Steps (reference software IVPSNR v7.0, default settings):

    1. Chroma planes are brought to luma size by sample replication (each
       4:2:0 chroma sample fills its 2x2 luma block; 4:2:2 its 2x1 block). All
       computation stays on the integer samples at their own bit depth.
    2. Global color shift, per component ``c``::

           g_c = clip(rint(mean(test_c - ref_c)), -CSE_c, CSE_c)
           CSE_c = rint(0.01 * (2**bits - 1))      # 3 for 8 bits, 10 for 10 bits

       (``rint`` rounds half to even, as the reference's SSE build does).
    3. Corresponding-pixel search, "ref to test": every reference pixel
       ``p = ref(x, y) + g`` is compared with the 25 test pixels of the 5x5
       window around ``(x, y)`` (picture borders extended by edge replication)
       and the best match ``q`` minimises ``4 dY^2 + dU^2 + dV^2`` with
       ``d = p - q``, all components jointly; the first minimum in raster order
       of the window (top row first, left to right) wins ties. The squared
       differences of that match are summed per component over the frame::

           SSD_c = sum over (x, y) of (p_c - q_c)^2
           PSNR_c = 10 log10((2**bits - 1)^2 * W * H / max(SSD_c, 1))
           Q = (4 PSNR_Y + PSNR_U + PSNR_V) / 6

       An error-free component counts as ``SSD_c = 1``, as in the reference, so
       frames that match after the colour shift and window search give
       ``10 log10((2**bits - 1)^2 W H)``. Identical frames are the one exception:
       their IV-PSNR is ``inf`` (the reference prints the same cap for them).
    4. "Test to reference": the same with the roles swapped (test pixels shifted
       by ``-g`` searched in the reference).
    5. ``IV-PSNR = min(Q_ref_to_test, Q_test_to_ref)``.

    A sequence's IV-PSNR is the arithmetic mean of its frames' values (as the
    reference software reports it).

    Parameters
    ----------
    ref_planes, test_planes : sequence of three ndarray
        ``(Y, U, V)`` integer planes, chroma 4:4:4, 4:2:2 or 4:2:0 (chroma
        ``(ceil(H/2), ceil(W/2))`` for 4:2:0), samples in ``0 .. 2**bits - 1``.
    bits : int
        Sample bit depth.

    Returns
    -------
    float
        IV-PSNR in dB.
    """
    if len(ref_planes) != 3 or len(test_planes) != 3:
        raise ValueError(
            f"IV-PSNR needs (Y, U, V) frames, got {len(ref_planes)} and {len(test_planes)} planes"
        )
    if not 1 <= bits <= 16:
        raise ValueError(f"bits must be in 1..16, got {bits}")
    max_value = 2**bits - 1
    ref = _to_444(ref_planes, max_value, "reference")
    test = _to_444(test_planes, max_value, "test")
    if ref.shape != test.shape:
        raise ValueError(
            f"reference frame {ref.shape[2]}x{ref.shape[1]} differs from test "
            f"frame {test.shape[2]}x{test.shape[1]}"
        )

    if np.array_equal(ref, test):
        # Identical frames have no error at all; the reference's floor of SSD 1 (step 3)
        # is kept for every other case so that its values are reproduced exactly.
        return math.inf
    shift = global_color_shift(ref, test, bits=bits).astype(ref.dtype)[:, None, None]
    ref_to_test = _asymmetric_quality(ref + shift, test, max_value)
    test_to_ref = _asymmetric_quality(test - shift, ref, max_value)
    return min(ref_to_test, test_to_ref)


def global_color_shift(ref: np.ndarray, test: np.ndarray, *, bits: int) -> np.ndarray:
    """Per-component global color shift ``g`` that best maps ``ref`` onto ``test``.

    ``g_c = clip(rint(mean(test_c - ref_c)), -CSE_c, CSE_c)`` with the
    unnoticeable color difference ``CSE_c = rint(0.01 * (2**bits - 1))``
    (computed in float32 as in the reference: 3 for 8 bits, 10 for 10 bits).

    Parameters
    ----------
    ref, test : ndarray, shape (C, H, W)
        Integer planes of equal size (chroma already at luma size).
    bits : int
        Sample bit depth.

    Returns
    -------
    ndarray of int64, shape (C,)
    """
    limit = int(np.rint(np.float32(UNNOTICEABLE_FRACTION) * np.float32(2**bits - 1)))
    mean_diff = (test.astype(np.int64) - ref.astype(np.int64)).sum(axis=(1, 2)) / (
        ref.shape[1] * ref.shape[2]
    )
    return np.clip(np.rint(mean_diff), -limit, limit).astype(np.int64)


def _to_444(planes: Sequence[np.ndarray], max_value: int, which: str) -> np.ndarray:
    """Stack (Y, U, V) into one (3, H, W) signed array, chroma replicated to luma size."""
    luma_shape = np.shape(planes[0])
    if len(luma_shape) != 2:
        raise ValueError(f"{which} luma plane must be 2-D, got shape {luma_shape}")
    # The weighted error 6 * (max_value + CSE)^2 fits int32 up to 14 bits (as in the
    # reference); wider samples need int64.
    dtype = np.int32 if max_value < 2**14 else np.int64
    stacked = np.empty((3,) + luma_shape, dtype=dtype)
    for index, plane in enumerate(planes):
        plane = np.asarray(plane)
        if not np.issubdtype(plane.dtype, np.integer):
            raise ValueError(
                f"{which} plane {index} has dtype {plane.dtype}; IV-PSNR works on integer samples"
            )
        if plane.size and (plane.min() < 0 or plane.max() > max_value):
            raise ValueError(f"{which} plane {index} has samples outside 0..{max_value}")
        fy, fx = subsampling_factors(luma_shape, plane.shape)
        stacked[index] = np.repeat(np.repeat(plane, fy, axis=0), fx, axis=1)[
            : luma_shape[0], : luma_shape[1]
        ]
    return stacked


def _asymmetric_quality(source: np.ndarray, target: np.ndarray, max_value: int) -> float:
    """Weighted PSNR of ``source`` against its best matches in ``target``.

    For each of the ``(2 r + 1)^2`` window offsets the whole padded target is
    shifted once; a running minimum of the weighted error keeps, per pixel, the
    squared differences of the first best offset in raster order (strict ``<``).
    """
    r = SEARCH_RANGE
    _, height, width = source.shape
    w_y, w_u, w_v = COMPONENT_WEIGHTS
    padded = np.pad(target, ((0, 0), (r, r), (r, r)), mode="edge")
    best_error = np.full((height, width), np.iinfo(source.dtype).max, dtype=source.dtype)
    best_squares = np.zeros_like(source)
    squares = np.empty_like(source)
    for dy in range(-r, r + 1):
        for dx in range(-r, r + 1):
            candidate = padded[:, r + dy : r + dy + height, r + dx : r + dx + width]
            np.subtract(source, candidate, out=squares)
            np.square(squares, out=squares)
            error = w_y * squares[0] + w_u * squares[1] + w_v * squares[2]
            better = error < best_error
            np.copyto(best_error, error, where=better)
            np.copyto(best_squares, squares, where=better)
    ssd = best_squares.sum(axis=(1, 2), dtype=np.int64).astype(np.float64)
    component_psnr = 10.0 * np.log10(float(max_value) ** 2 * height * width / np.maximum(ssd, 1.0))
    return float(np.dot(COMPONENT_WEIGHTS, component_psnr) / sum(COMPONENT_WEIGHTS))
