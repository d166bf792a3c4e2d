"""Peak signal-to-noise ratio of planes and of whole YUV frames.

A frame is a tuple of 2-D planes, ``(Y,)`` or ``(Y, U, V)``; chroma planes may be
subsampled (4:2:0 or 4:2:2: each chroma sample covers a 2x2 or 2x1 block of luma
samples, the last block cut short when a luma dimension is odd).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

# MPEG convention for a single YUV-PSNR figure (e.g. the VVC/HEVC common test
# conditions): luma counts six times as much as each chroma plane.
YUV_PSNR_WEIGHTS = (6, 1, 1)


def psnr(
    ref: np.ndarray, test: np.ndarray, *, max_value: float, mask: np.ndarray | None = None
) -> float:
    """PSNR of one plane, in dB.

    ``PSNR = 10 log10(max_value**2 / MSE)`` with ``MSE`` the mean of the squared
    differences over the scored samples (all of them, or those where ``mask`` is
    true). Identical planes give ``inf``.

    Parameters
    ----------
    ref, test : ndarray, shape (H, W)
        Reference and test plane, any numeric dtype (differences are taken in
        float64, so unsigned integers do not wrap).
    max_value : float
        Peak value, ``2**bits - 1`` for integer video samples.
    mask : ndarray of bool, shape (H, W), optional
        Samples to score; the MSE is averaged over the true ones only.

    Returns
    -------
    float
        PSNR in dB, ``inf`` when the scored samples are identical.
    """
    ref, test = plane_pair(ref, test, max_value)
    if mask is not None:
        mask = np.asarray(mask, dtype=bool)
        if mask.shape != ref.shape:
            raise ValueError(f"mask shape {mask.shape} differs from plane shape {ref.shape}")
        if not mask.any():
            raise ValueError("mask selects no sample: PSNR is undefined")
    mse = _sum_squared_difference(ref, test, mask) / (
        ref.size if mask is None else np.count_nonzero(mask)
    )
    if mse == 0.0:
        return float("inf")
    return float(10.0 * np.log10(float(max_value) ** 2 / mse))


def plane_pair(ref, test, max_value: float) -> tuple[np.ndarray, np.ndarray]:
    """``ref`` and ``test`` as arrays, checked to be planes of one shape with a positive peak."""
    ref = np.asarray(ref)
    test = np.asarray(test)
    if ref.shape != test.shape:
        raise ValueError(f"reference shape {ref.shape} differs from test shape {test.shape}")
    if ref.ndim != 2:
        raise ValueError(f"a plane must be 2-D, got shape {ref.shape}")
    if not max_value > 0:
        raise ValueError(f"max_value must be positive, got {max_value}")
    return ref, test


def _sum_squared_difference(ref: np.ndarray, test: np.ndarray, mask: np.ndarray | None) -> float:
    # Video samples (uint8/uint16 of one dtype) go through OpenCV's vectorised norm, a
    # hundred times faster than numpy here; it sums in float64 like the fallback (the two
    # differ by a few ulps, far below what a PSNR shows). Imported here, so that
    # importing the metrics does not load OpenCV.
    if ref.dtype == test.dtype and ref.dtype in (np.uint8, np.uint16):
        import cv2

        cv_mask = None if mask is None else mask.view(np.uint8)
        return float(
            cv2.norm(
                np.ascontiguousarray(ref), np.ascontiguousarray(test), cv2.NORM_L2SQR, mask=cv_mask
            )
        )
    diff = ref.astype(np.float64) - test.astype(np.float64)
    if mask is not None:
        diff = diff[mask]
    return float(np.sum(np.square(diff)))


def subsampling_factors(
    luma_shape: tuple[int, int], plane_shape: tuple[int, int]
) -> tuple[int, int]:
    """Vertical and horizontal subsampling of a plane relative to luma.

    Each factor is 1 or 2, and the plane size must be ``ceil(luma / factor)``.

    Raises
    ------
    ValueError
        When the plane is not a 4:4:4, 4:2:2 or 4:2:0 companion of the luma plane.
    """
    factors = []
    for luma, size in zip(luma_shape, plane_shape):
        factor = next((f for f in (1, 2) if -(-luma // f) == size), None)
        if factor is None:
            raise ValueError(
                f"plane shape {plane_shape} is not a 4:4:4, 4:2:2 or 4:2:0 "
                f"chroma plane of luma shape {luma_shape}"
            )
        factors.append(factor)
    return factors[0], factors[1]


def _mask_for_plane(mask: np.ndarray, plane_shape: tuple[int, int]) -> np.ndarray:
    """Luma-resolution mask reduced to a (possibly subsampled) plane.

    A chroma sample is scored only when every luma sample it covers is scored:
    a chroma sample that also covers a masked-out luma sample (e.g. a hole in a
    synthesized view) is not a reliable sample of the scored region.
    """
    fy, fx = subsampling_factors(mask.shape, plane_shape)
    if (fy, fx) == (1, 1):
        return mask
    h, w = plane_shape
    padded = np.pad(mask, ((0, h * fy - mask.shape[0]), (0, w * fx - mask.shape[1])), mode="edge")
    return padded.reshape(h, fy, w, fx).all(axis=(1, 3))


def _check_frames(
    ref_planes: Sequence[np.ndarray], test_planes: Sequence[np.ndarray], bits: int
) -> None:
    if len(ref_planes) != len(test_planes):
        raise ValueError(f"reference has {len(ref_planes)} planes, test has {len(test_planes)}")
    if len(ref_planes) not in (1, 3):
        raise ValueError(f"a frame has 1 or 3 planes, got {len(ref_planes)}")
    if not 1 <= bits <= 16:
        raise ValueError(f"bits must be in 1..16, got {bits}")


def plane_psnr(
    ref_planes: Sequence[np.ndarray],
    test_planes: Sequence[np.ndarray],
    *,
    bits: int,
    mask: np.ndarray | None = None,
) -> tuple[float, ...]:
    """PSNR of each plane of a frame, peak ``2**bits - 1``.

    Parameters
    ----------
    ref_planes, test_planes : sequence of ndarray
        ``(Y,)`` or ``(Y, U, V)``; chroma planes may be subsampled.
    bits : int
        Sample bit depth.
    mask : ndarray of bool, shape of the luma plane, optional
        Luma samples to score. For a subsampled chroma plane a chroma sample is
        scored when all the luma samples it covers are.

    Returns
    -------
    tuple of float
        One PSNR per plane, in dB (``inf`` for identical planes).
    """
    _check_frames(ref_planes, test_planes, bits)
    max_value = 2**bits - 1
    if mask is not None:
        mask = np.asarray(mask, dtype=bool)
        if mask.shape != np.shape(ref_planes[0]):
            raise ValueError(
                f"mask shape {mask.shape} differs from luma shape {np.shape(ref_planes[0])}"
            )
    return tuple(
        psnr(
            ref,
            test,
            max_value=max_value,
            mask=None if mask is None else _mask_for_plane(mask, np.shape(ref)),
        )
        for ref, test in zip(ref_planes, test_planes)
    )


def yuv_psnr(
    ref_planes: Sequence[np.ndarray],
    test_planes: Sequence[np.ndarray],
    *,
    bits: int,
    mask: np.ndarray | None = None,
) -> float:
    """Weighted YUV-PSNR ``(6 PSNR_Y + PSNR_U + PSNR_V) / 8`` of a frame, in dB.

    The 6:1:1 weighting is the MPEG convention (JVET/JCT-VC common test
    conditions). Parameters as :func:`plane_psnr`; the frame must have three
    planes. ``inf`` as soon as one plane is identical.
    """
    if len(ref_planes) != 3:
        raise ValueError(f"YUV-PSNR needs three planes, got {len(ref_planes)}")
    values = plane_psnr(ref_planes, test_planes, bits=bits, mask=mask)
    return float(np.dot(YUV_PSNR_WEIGHTS, values) / sum(YUV_PSNR_WEIGHTS))
