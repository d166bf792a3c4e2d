"""Sample-level conversions: bit depth, chroma layout, and depth-map previews."""

from __future__ import annotations

from typing import Sequence

import cv2
import numpy as np

from mvtools.color.space import downsample_chroma, upsample_chroma

__all__ = ["requantize", "convert_planes", "depth_preview"]


def _dtype(bits: int) -> np.dtype:
    return np.dtype(np.uint8 if bits == 8 else np.uint16)


def requantize(plane: np.ndarray, from_bits: int, to_bits: int, *, full_scale: bool = False) -> np.ndarray:
    """Change the bit depth of integer samples.

    Parameters
    ----------
    plane : ndarray of uint8 or uint16
    from_bits, to_bits : int
        Bit depths, 8..16.
    full_scale : bool
        False (texture, the video convention): multiply by ``2**(to_bits - from_bits)``,
        so limited-range levels stay limited-range (8-bit 235 is 10-bit 940).
        True (depth maps): keep ``v / vmax``, i.e. ``v * (2**to_bits - 1) / (2**from_bits - 1)``,
        so a depth value keeps its meaning for the same Znear, Zfar (8-bit 255 is 16-bit 65535).

    Returns
    -------
    ndarray
        Rounded to nearest and clipped; uint8 for 8 bits, uint16 above.
    """
    for bits in (from_bits, to_bits):
        if not 8 <= bits <= 16:
            raise ValueError(f"bit depths must be 8..16, got {bits}")
    values = np.asarray(plane, dtype=np.float64)
    if full_scale:
        values = values * ((2 ** to_bits - 1) / (2 ** from_bits - 1))
    else:
        values = values * 2.0 ** (to_bits - from_bits)
    return np.clip(np.floor(values + 0.5), 0, 2 ** to_bits - 1).astype(_dtype(to_bits))


def convert_planes(planes: Sequence[np.ndarray], *, bits: int, to_chroma: str, to_bits: int,
                   depth: bool = False) -> tuple[np.ndarray, ...]:
    """Convert a frame to another chroma layout and bit depth.

    Parameters
    ----------
    planes : (Y,) or (Y, U, V)
        Input frame of ``bits`` bits; chroma full size or subsampled.
    to_chroma : {"420", "422", "444", "400"}
    to_bits : int
    depth : bool
        The frame is a depth map: only luma means something, it is requantised at
        full scale (see :func:`requantize`) and output chroma is mid-grey.

    Returns
    -------
    tuple of ndarray
    """
    luma = requantize(planes[0], bits, to_bits, full_scale=depth)
    if to_chroma == "400":
        return (luma,)
    if depth or len(planes) == 1:
        shape = _chroma_shape(luma.shape, to_chroma)
        mid = np.full(shape, 2 ** (to_bits - 1), dtype=_dtype(to_bits))
        return (luma, mid, mid.copy())
    chroma = [requantize(plane, bits, to_bits) for plane in planes[1:]]
    full = upsample_chroma((luma, *chroma))[1:]
    if to_chroma != "444":
        full = [_round(downsample_chroma(plane.astype(np.float64), chroma=to_chroma), to_bits)
                for plane in full]
    return (luma, *full)


def _chroma_shape(luma_shape: tuple[int, int], chroma: str) -> tuple[int, int]:
    height, width = luma_shape
    half_w = (width + 1) // 2
    return {"444": (height, width), "422": (height, half_w), "420": ((height + 1) // 2, half_w)}[chroma]


def _round(values: np.ndarray, bits: int) -> np.ndarray:
    return np.clip(np.floor(values + 0.5), 0, 2 ** bits - 1).astype(_dtype(bits))


def depth_preview(values: np.ndarray, *, bits: int) -> np.ndarray:
    """Colour-mapped picture of a depth map (turbo: red near, blue far).

    Parameters
    ----------
    values : ndarray, shape (H, W)
        Depth values, ``2**bits - 1`` = nearest (MPEG convention).

    Returns
    -------
    ndarray of uint8, shape (H, W, 3), RGB
    """
    values = np.asarray(values)
    if values.ndim != 2:
        raise ValueError(f"a depth map is 2-D, got shape {values.shape}")
    scaled = requantize(values, bits, 8, full_scale=True)
    return cv2.applyColorMap(scaled, cv2.COLORMAP_TURBO)[..., ::-1].copy()
