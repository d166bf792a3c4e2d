"""Sample-level conversions: bit depth, chroma layout, and depth-map previews."""

from __future__ import annotations

from collections.abc import Sequence
from functools import cache

import numpy as np

from mvtools.color.space import downsample_chroma, upsample_chroma
from mvtools.io.chroma import chroma_plane_shape

__all__ = ["convert_planes", "depth_preview", "requantize"]


def _dtype(bits: int) -> np.dtype:
    return np.dtype(np.uint8 if bits == 8 else np.uint16)


def requantize(
    plane: np.ndarray, from_bits: int, to_bits: int, *, full_scale: bool = False
) -> np.ndarray:
    """Change the bit depth of integer samples.

    Parameters
    ----------
    plane : ndarray of uint8 or uint16
        ``(H, W)``, or ``(H, W, C)`` (each of the C channels as one plane).
    from_bits, to_bits : int
        Bit depths, 8..16.
    full_scale : bool
        False (texture, the video convention, as ffmpeg's swscale scales limited-range
        video): to more bits, shift left, i.e. multiply by ``2**(to_bits - from_bits)``
        (8-bit 235 is 10-bit 940), which keeps every sample: back to fewer bits gives
        it again. To fewer bits, add swscale's ordered dither (:func:`_dither`) and
        shift right, so that ffmpeg and mvtools write the same bytes.
        True (depth maps): keep ``v / vmax``, i.e. ``v * (2**to_bits - 1) / (2**from_bits - 1)``
        rounded to nearest, so a depth value keeps its meaning for the same Znear, Zfar
        (8-bit 255 is 16-bit 65535).

    Returns
    -------
    ndarray
        uint8 for 8 bits, uint16 above.

    Raises
    ------
    ValueError
        A bit depth outside 8..16, or a sample above ``2**from_bits - 1``.
    """
    for bits in (from_bits, to_bits):
        if not 8 <= bits <= 16:
            raise ValueError(f"bit depths must be 8..16, got {bits}")
    plane = np.asarray(plane)
    top = 2**from_bits - 1
    if (
        plane.size
        and plane.dtype.kind in "iu"
        and np.iinfo(plane.dtype).max > top
        and int(plane.max()) > top
    ):
        raise ValueError(
            f"sample value {int(plane.max())} is above the {from_bits}-bit maximum {top}"
        )
    if full_scale:
        values = plane * ((2**to_bits - 1) / top)
        return np.clip(np.floor(values + 0.5), 0, 2**to_bits - 1).astype(_dtype(to_bits))
    values = plane.astype(np.int64)
    if to_bits >= from_bits:
        return (values << (to_bits - from_bits)).astype(_dtype(to_bits))
    shift = from_bits - to_bits
    height, width = plane.shape[:2]
    dither = np.tile(_dither(shift), (-(-height // 8), -(-width // 8)))[:height, :width]
    shifted = (values + dither.reshape(dither.shape + (1,) * (plane.ndim - 2))) >> shift
    # the dither may carry the top samples one past the maximum: swscale takes them back
    return (shifted - (shifted >> to_bits)).astype(_dtype(to_bits))


@cache
def _dither(shift: int) -> np.ndarray:
    """The 8x8 ordered dither swscale adds to samples before dropping ``shift`` bits
    (1..8), anchored at the plane's top-left sample.

    Each matrix is the one for a bit less, doubled, plus one bit in a pattern of
    2^k x 2^k squares: a checkerboard of them or alternate columns of them.
    """
    rows, columns = np.indices((8, 8))

    def checkerboard(k: int) -> np.ndarray:
        return ((columns >> k) ^ (rows >> k)) & 1

    def stripes(k: int) -> np.ndarray:
        return (columns >> k) & 1

    matrices = [checkerboard(0)]
    for extra in (1 - stripes(0), checkerboard(1), stripes(1), 1 - checkerboard(2), stripes(2)):
        matrices.append(2 * matrices[-1] + extra)
    matrices += [matrices[5], 2 * matrices[5]]  # 7 bits reuse the 6-bit one, 8 double it
    matrix = matrices[shift - 1].astype(np.int64)
    matrix.flags.writeable = False
    return matrix


def convert_planes(
    planes: Sequence[np.ndarray], *, bits: int, to_chroma: str, to_bits: int, depth: bool = False
) -> tuple[np.ndarray, ...]:
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
        Chroma already in the ``to_chroma`` layout is only requantised, so a frame
        whose bit depth does not change comes out as it went in; other layouts are
        resampled (:func:`mvtools.color.space.upsample_chroma`, then
        :func:`mvtools.color.space.downsample_chroma`).

    Raises
    ------
    ValueError
        As :func:`requantize`: a sample above the ``bits``-bit maximum.
    """
    luma = requantize(planes[0], bits, to_bits, full_scale=depth)
    if to_chroma == "400":
        return (luma,)
    shape = chroma_plane_shape(luma.shape, to_chroma)
    if depth or len(planes) == 1:
        mid = np.full(shape, 2 ** (to_bits - 1), dtype=_dtype(to_bits))
        return (luma, mid, mid.copy())
    chroma = [requantize(plane, bits, to_bits) for plane in planes[1:]]
    if chroma[0].shape == shape:
        return (luma, *chroma)
    full = upsample_chroma((luma, *chroma))[1:]
    if to_chroma != "444":
        full = [downsample_chroma(plane, chroma=to_chroma) for plane in full]
    return (luma, *full)


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
    import cv2  # here: a program that draws no preview does not load OpenCV

    return cv2.applyColorMap(scaled, cv2.COLORMAP_TURBO)[..., ::-1].copy()
