"""YUV (Y'CbCr) <-> RGB conversion and chroma resampling.

Conventions
-----------
- Matrices: ITU-R BT.601 (the MPEG reference programs' assumption), BT.709 and
  BT.2020 (non-constant luminance), from their ``Kr``/``Kb`` luma weights, in
  floating point; results are rounded to nearest (halves up) and clipped.
- Limited ("video", "TV") range: at 8 bits Y in 16..235 and Cb/Cr in 16..240;
  at ``bits`` bits these are scaled by ``2**(bits-8)`` (ITU-R BT.2100/H.273).
  Full range: Y in ``0..2**bits-1``, chroma centred on ``2**(bits-1)``.
  Red ``(255, 0, 0)`` in BT.601 limited range is ``Y = 16 + 219 * 0.299 =
  81.48 -> 81``, ``U = 90``, ``V = 240`` (the 8-bit integer approximation
  ``(66 R + 129 G + 25 B + 128) >> 8`` some programs use gives Y 82).
- Chroma siting: centred (JPEG/MPEG-1, the ``C420jpeg`` of the Y4M files we
  write): a 4:2:0 chroma sample sits at the centre of its 2x2 luma block.
  :func:`downsample_chroma` averages each 2x2 block (horizontal pairs for 4:2:2)
  and :func:`upsample_chroma` interpolates bilinearly at the matching positions,
  i.e. weights 3/4 and 1/4 of the two nearest chroma samples along each
  subsampled axis. Odd sizes replicate the last row/column. Chroma planes of
  4:2:0 are ``(ceil(H/2), ceil(W/2))``.

Planes are 2-D arrays ``(Y, U, V)`` (or ``(Y,)`` for grey) of uint8 (8 bits) or
uint16 (more bits), as :mod:`mvtools.io.yuv` reads and writes them.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from mvtools.io.chroma import CHROMA_FORMATS

__all__ = [
    "MATRICES",
    "downsample_chroma",
    "rgb_to_yuv",
    "rgb_to_yuv_matrix",
    "upsample_chroma",
    "yuv_to_rgb",
]

# Luma weights (Kr, Kb) of each standard; Kg = 1 - Kr - Kb.
MATRICES = {"bt601": (0.299, 0.114), "bt709": (0.2126, 0.0722), "bt2020": (0.2627, 0.0593)}
_BIT_DEPTHS = range(8, 17)


def rgb_to_yuv_matrix(matrix: str = "bt601") -> np.ndarray:
    """3x3 matrix taking normalised R'G'B' in [0, 1] to (Y' in [0, 1], Pb, Pr in [-0.5, 0.5]).

    Raises
    ------
    ValueError
        For an unknown matrix name.
    """
    if matrix not in MATRICES:
        raise ValueError(f"unknown colour matrix {matrix!r}; use one of {', '.join(MATRICES)}")
    kr, kb = MATRICES[matrix]
    kg = 1.0 - kr - kb
    return np.array(
        [
            [kr, kg, kb],
            [-0.5 * kr / (1 - kb), -0.5 * kg / (1 - kb), 0.5],
            [0.5, -0.5 * kg / (1 - kr), -0.5 * kb / (1 - kr)],
        ]
    )


def _check_bits(bits: int) -> None:
    if bits not in _BIT_DEPTHS:
        raise ValueError(f"bits must be an integer in 8..16, got {bits!r}")


def _quantisation(bits: int, full_range: bool) -> tuple[float, float, float, float]:
    """(luma scale, luma offset, chroma scale, chroma offset) from normalised to codes."""
    if full_range:
        top = 2.0**bits - 1
        return top, 0.0, top, 2.0 ** (bits - 1)
    step = 2.0 ** (bits - 8)
    return 219 * step, 16 * step, 224 * step, 128 * step


def _to_codes(values: np.ndarray, bits: int) -> np.ndarray:
    """Round to nearest (halves up, like ``(int)(x + 0.5)``), clip, uint8/uint16."""
    dtype = np.uint8 if bits == 8 else np.uint16
    return np.clip(np.floor(values + 0.5), 0, 2**bits - 1).astype(dtype)


def _subsampling(luma_shape: tuple[int, int], chroma_shape: tuple[int, int]) -> tuple[bool, bool]:
    """(vertical, horizontal) halving between a luma and a chroma plane shape."""
    halved = []
    for axis, (full, part) in enumerate(zip(luma_shape, chroma_shape)):
        if part == full:
            halved.append(False)
        elif part == -(-full // 2):
            halved.append(True)
        else:
            raise ValueError(
                f"chroma plane shape {chroma_shape} does not match luma {luma_shape} "
                f"(expected full or ceil-half size along axis {axis})"
            )
    return halved[0], halved[1]


def downsample_chroma(
    plane: np.ndarray, *, chroma: str = "420", bits: int | None = None
) -> np.ndarray:
    """Halve a full-size chroma plane by averaging (centred siting).

    Parameters
    ----------
    plane : ndarray, shape (H, W)
    chroma : {"420", "422"}
        "420" averages 2x2 blocks, "422" horizontal pairs. An odd last row or
        column is replicated (so it is averaged with itself).
    bits : int, optional
        Round the means to sample codes of this many bits (half up, clipped; uint8 for
        8 bits, else uint16), whatever the input's dtype.

    Returns
    -------
    ndarray
        ``(ceil(H/2), ceil(W/2))`` for 4:2:0, ``(H, ceil(W/2))`` for 4:2:2: codes of
        ``bits`` bits when given, else float64 for float input and otherwise rounded
        to nearest in the input dtype.

    Examples
    --------
    >>> downsample_chroma(np.array([[1, 2, 10], [3, 6, 20]], dtype=np.uint8)).tolist()
    [[3, 15]]
    """
    plane = np.asarray(plane)
    if plane.ndim != 2:
        raise ValueError(f"a chroma plane must be 2-D, got shape {plane.shape}")
    if chroma not in ("420", "422"):
        raise ValueError(f"chroma must be '420' or '422', got {chroma!r}")
    halved_rows = chroma == "420"
    rows, cols = plane.shape
    shape = (-(-rows // 2) if halved_rows else rows, -(-cols // 2))
    if bits is not None:
        _check_bits(bits)
        out = np.empty(shape, np.uint8 if bits == 8 else np.uint16)
        low, high = 0, 2**bits - 1
    elif plane.dtype.kind == "f":
        out = np.empty(shape)
        low, high = 1, 0  # no rounding
    else:
        out = np.empty(shape, plane.dtype)
        low, high = np.iinfo(plane.dtype).min, np.iinfo(plane.dtype).max
    from mvtools.color.chroma_kernels import downsample_mean

    downsample_mean(plane, halved_rows, float(low), float(high), out)
    return out


def _upsample_nearest(values: np.ndarray, size: int, axis: int) -> np.ndarray:
    """Double ``values`` along ``axis`` to ``size`` samples, each repeated."""
    return np.take(np.repeat(values, 2, axis=axis), np.arange(size), axis=axis)


def upsample_chroma(
    planes: Sequence[np.ndarray],
    *,
    method: str = "bilinear",
    out: tuple[np.ndarray, np.ndarray] | None = None,
) -> tuple[np.ndarray, ...]:
    """Bring 4:2:0 or 4:2:2 chroma to the luma size.

    Parameters
    ----------
    planes : (Y, U, V)
        Y of shape (H, W); U and V full size or ceil-halved along either axis.
    method : {"bilinear", "nearest"}
        "bilinear": centred siting, weights 3/4, 1/4 (edges replicated);
        "nearest": each chroma sample repeated over its 2x2 (or 2x1) block.
    out : (U, V) of float ndarray of shape (H, W), optional
        Arrays (views of a larger image, say) that get the upsampled chroma, unrounded
        whatever the input's dtype; returned in place of new arrays.

    Returns
    -------
    (Y, U, V)
        All of shape (H, W); Y unchanged, chroma rounded to nearest in the input
        dtype (float input stays float64).
    """
    if len(planes) != 3:
        raise ValueError(f"upsample_chroma needs (Y, U, V), got {len(planes)} planes")
    if method not in ("bilinear", "nearest"):
        raise ValueError(f"method must be 'bilinear' or 'nearest', got {method!r}")
    luma = np.asarray(planes[0])
    if luma.ndim != 2:
        raise ValueError(f"planes must be 2-D, got Y of shape {luma.shape}")
    result = [luma]
    for index, plane in enumerate(planes[1:]):
        plane = np.asarray(plane)
        if plane.ndim != 2:
            raise ValueError(f"planes must be 2-D, got chroma of shape {plane.shape}")
        halved = _subsampling(luma.shape, plane.shape)
        if out is not None and (out[index].dtype.kind != "f" or out[index].shape != luma.shape):
            raise ValueError("out takes float arrays of the luma's shape")
        if method == "bilinear":
            from mvtools.color.chroma_kernels import upsample_bilinear

            values = np.empty(luma.shape) if out is None else out[index]
            upsample_bilinear(plane, halved[0], halved[1], values)
        else:
            values = plane.astype(np.float64)
            for axis in (0, 1):
                if halved[axis]:
                    values = _upsample_nearest(values, luma.shape[axis], axis)
        if plane.dtype.kind == "f" or out is not None:
            result.append(values)
        else:
            result.append(
                np.clip(
                    np.floor(values + 0.5), np.iinfo(plane.dtype).min, np.iinfo(plane.dtype).max
                ).astype(plane.dtype)
            )
    return tuple(result)


def rgb_to_yuv(
    rgb: np.ndarray,
    *,
    chroma: str = "420",
    bits: int = 8,
    matrix: str = "bt601",
    full_range: bool = False,
    rgb_bits: int | None = None,
) -> tuple[np.ndarray, ...]:
    """Convert an RGB image to YUV planes.

    Parameters
    ----------
    rgb : ndarray, shape (H, W, 3)
        Integer samples in ``0 .. 2**rgb_bits - 1`` or floats in [0, 1].
    chroma : {"420", "422", "444", "400"}
        Output subsampling; chroma is computed at full size, then averaged
        (:func:`downsample_chroma`) before rounding; "400" returns ``(Y,)``.
    bits : int
        Output bit depth, 8..16.
    matrix : {"bt601", "bt709", "bt2020"}
    full_range : bool
        Full-range codes instead of limited (video) range.
    rgb_bits : int, optional
        Bit depth of integer ``rgb``; default 8 for uint8 input, ``bits`` otherwise.

    Returns
    -------
    tuple of ndarray
        ``(Y, U, V)`` or ``(Y,)``; uint8 for 8 bits, uint16 above; Y of shape
        (H, W), chroma as :attr:`mvtools.io.yuv.YuvFormat.plane_shapes`.
    """
    rgb = np.asarray(rgb)
    if rgb.ndim != 3 or rgb.shape[2] != 3:
        raise ValueError(f"rgb must have shape (H, W, 3), got {rgb.shape}")
    if chroma not in CHROMA_FORMATS:
        formats = ", ".join(map(repr, CHROMA_FORMATS))
        raise ValueError(f"chroma must be one of {formats}, got {chroma!r}")
    _check_bits(bits)
    if rgb.dtype.kind == "f":
        normalised = rgb.astype(np.float64)
    elif rgb.dtype.kind in "ui":
        rgb_bits = rgb_bits if rgb_bits is not None else (8 if rgb.dtype == np.uint8 else bits)
        _check_bits(rgb_bits)
        normalised = rgb.astype(np.float64) / (2**rgb_bits - 1)
    else:
        raise ValueError(f"rgb must be an integer or float array, got dtype {rgb.dtype}")
    ypbpr = normalised @ rgb_to_yuv_matrix(matrix).T
    y_scale, y_offset, c_scale, c_offset = _quantisation(bits, full_range)
    luma = _to_codes(ypbpr[..., 0] * y_scale + y_offset, bits)
    if chroma == "400":
        return (luma,)
    planes = [luma]
    for index in (1, 2):
        values = ypbpr[..., index] * c_scale + c_offset
        if chroma != "444":
            values = downsample_chroma(values, chroma=chroma)
        planes.append(_to_codes(values, bits))
    return tuple(planes)


def yuv_to_rgb(
    planes: Sequence[np.ndarray],
    *,
    bits: int = 8,
    matrix: str = "bt601",
    full_range: bool = False,
    upsampling: str = "bilinear",
) -> np.ndarray:
    """Convert YUV planes to an RGB image.

    Parameters
    ----------
    planes : (Y, U, V) or (Y,)
        Y of shape (H, W); chroma full size, 4:2:2 or 4:2:0 (upsampled with
        :func:`upsample_chroma`); ``(Y,)`` gives grey RGB (R = G = B).
    bits : int
        Bit depth of the samples, 8..16; also of the output.
    matrix : {"bt601", "bt709", "bt2020"}
    full_range : bool
    upsampling : {"bilinear", "nearest"}

    Returns
    -------
    ndarray, shape (H, W, 3)
        RGB in ``0 .. 2**bits - 1``, rounded and clipped, dtype of Y (uint8 for 8
        bits, uint16 above when Y is floating point).
    """
    _check_bits(bits)
    if len(planes) not in (1, 3):
        raise ValueError(f"planes must be (Y,) or (Y, U, V), got {len(planes)} planes")
    y_scale, y_offset, c_scale, c_offset = _quantisation(bits, full_range)
    luma = np.asarray(planes[0])
    dtype = luma.dtype if luma.dtype.kind == "u" else np.dtype(np.uint8 if bits == 8 else np.uint16)
    if np.iinfo(dtype).max < 2**bits - 1:
        raise ValueError(f"{bits}-bit samples do not fit the planes' dtype {dtype}")
    ypbpr = np.zeros(luma.shape + (3,))
    ypbpr[..., 0] = (luma.astype(np.float64) - y_offset) / y_scale
    if len(planes) == 3:
        _, u, v = upsample_chroma(
            [luma] + [np.asarray(p, dtype=np.float64) for p in planes[1:]], method=upsampling
        )
        ypbpr[..., 1] = (u - c_offset) / c_scale
        ypbpr[..., 2] = (v - c_offset) / c_scale
    normalised = ypbpr @ np.linalg.inv(rgb_to_yuv_matrix(matrix)).T
    return _to_codes(normalised * (2**bits - 1), bits).astype(dtype, copy=False)
