"""Colorimetry: transfer functions, white points, the sRGB matrices, chromatic
adaptation, CIELAB and the CIEDE2000 colour difference.

Conventions
-----------
- Colours are row vectors in arrays of shape ``(..., 3)``, except for the 3x3 matrices
  of the literature (:data:`SRGB_TO_XYZ`, :func:`bradford_matrix`), which act on column
  vectors, ``xyz = SRGB_TO_XYZ @ rgb``, i.e. ``rgb @ SRGB_TO_XYZ.T`` for arrays.
- Display RGB is in [0, 1] (8-bit codes divided by 255). Linear RGB has the sRGB
  primaries and D65 white (IEC 61966-2-1); XYZ is scaled so that the white has Y = 1.
- White points (CIE 1931 observer): D65 is the ASTM E308 ``(0.95047, 1, 1.08883)``,
  which makes :data:`SRGB_TO_XYZ` the published ``[[0.4124564, 0.3575761, 0.1804375],
  ...]``; D50 is that of the CIE 15 chromaticity (0.34567, 0.35850). These are the
  whites of OpenCV's ``ccm`` module: with Bradford adaptation, the ColorChecker's
  CIELAB (D50) gives its linear sRGB references to 1e-8.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "BRADFORD",
    "SRGB_TO_XYZ",
    "WHITE_D50",
    "WHITE_D65",
    "XYZ_TO_SRGB",
    "bradford_matrix",
    "delta_e_2000",
    "gamma_to_linear",
    "lab_to_linear_rgb",
    "lab_to_xyz",
    "linear_rgb_to_lab",
    "linear_to_gamma",
    "linear_to_srgb",
    "srgb_to_linear",
    "xy_to_xyz",
    "xyz_to_lab",
]

WHITE_D65 = np.array([0.95047, 1.0, 1.08883])
WHITE_D50 = np.array([0.34567 / 0.35850, 1.0, (1.0 - 0.34567 - 0.35850) / 0.35850])

# Lam's cone-response matrix of the Bradford transform (column vectors: lms = BRADFORD @ xyz).
BRADFORD = np.array(
    [[0.8951, 0.2664, -0.1614], [-0.7502, 1.7135, 0.0367], [0.0389, -0.0685, 1.0296]]
)

# Chromaticities of the sRGB (ITU-R BT.709) red, green and blue primaries.
_SRGB_PRIMARIES = ((0.64, 0.33), (0.30, 0.60), (0.15, 0.06))

# CIELAB's linear segment below (6/29)^3 (CIE 15:2004).
_LAB_DELTA = 6.0 / 29.0


def _colours(values, name: str) -> np.ndarray:
    values = np.asarray(values, dtype=np.float64)
    if values.ndim == 0 or values.shape[-1] != 3:
        raise ValueError(f"{name} must have shape (..., 3), got {values.shape}")
    return values


def srgb_to_linear(values) -> np.ndarray:
    """Decode sRGB display values (IEC 61966-2-1): ``v / 12.92`` up to 0.04045, else
    ``((v + 0.055) / 1.055) ** 2.4``; negative values mirror the positive ones.

    Parameters
    ----------
    values : array_like
        Display values, nominally in [0, 1], any shape.

    Returns
    -------
    ndarray
        Linear values, float64, same shape.
    """
    values = np.asarray(values, dtype=np.float64)
    size = np.abs(values)
    linear = np.where(size <= 0.04045, size / 12.92, ((size + 0.055) / 1.055) ** 2.4)
    return np.copysign(linear, values)


def linear_to_srgb(values) -> np.ndarray:
    """Encode linear values as sRGB (the inverse of :func:`srgb_to_linear`): ``12.92 v``
    up to 0.0031308, else ``1.055 v ** (1 / 2.4) - 0.055``; negatives mirrored."""
    values = np.asarray(values, dtype=np.float64)
    size = np.abs(values)
    encoded = np.where(size <= 0.0031308, 12.92 * size, 1.055 * size ** (1 / 2.4) - 0.055)
    return np.copysign(encoded, values)


def _check_gamma(gamma: float) -> float:
    if not np.isfinite(gamma) or gamma <= 0:
        raise ValueError(f"gamma must be a finite number > 0, got {gamma!r}")
    return float(gamma)


def gamma_to_linear(values, *, gamma: float = 2.2) -> np.ndarray:
    """Plain power-law decoding ``sign(v) |v| ** gamma`` (OpenCV's ``LINEARIZATION_GAMMA``,
    whose default gamma is 2.2); same shape, float64."""
    gamma = _check_gamma(gamma)
    values = np.asarray(values, dtype=np.float64)
    return np.copysign(np.abs(values) ** gamma, values)


def linear_to_gamma(values, *, gamma: float = 2.2) -> np.ndarray:
    """The inverse of :func:`gamma_to_linear`: ``sign(v) |v| ** (1 / gamma)``."""
    gamma = _check_gamma(gamma)
    values = np.asarray(values, dtype=np.float64)
    return np.copysign(np.abs(values) ** (1.0 / gamma), values)


def xy_to_xyz(xy) -> np.ndarray:
    """Tristimulus values with Y = 1 of chromaticity ``(x, y)``: ``(x / y, 1, (1 - x - y) / y)``.

    Parameters
    ----------
    xy : array_like, shape (..., 2)

    Returns
    -------
    ndarray, shape (..., 3)
    """
    xy = np.asarray(xy, dtype=np.float64)
    if xy.ndim == 0 or xy.shape[-1] != 2:
        raise ValueError(f"xy must have shape (..., 2), got {xy.shape}")
    x, y = xy[..., 0], xy[..., 1]
    if np.any(y <= 0):
        raise ValueError("chromaticity y must be > 0")
    return np.stack([x / y, np.ones_like(x), (1.0 - x - y) / y], axis=-1)


def _rgb_to_xyz_matrix(primaries, white: np.ndarray) -> np.ndarray:
    """Columns: the XYZ of each primary, scaled so that R = G = B = 1 gives ``white``."""
    unscaled = xy_to_xyz(np.asarray(primaries)).T
    return unscaled * np.linalg.solve(unscaled, white)


SRGB_TO_XYZ = _rgb_to_xyz_matrix(_SRGB_PRIMARIES, WHITE_D65)
XYZ_TO_SRGB = np.linalg.inv(SRGB_TO_XYZ)


def _white(white, name: str = "white") -> np.ndarray:
    white = np.asarray(white, dtype=np.float64)
    if white.shape != (3,) or not np.all(np.isfinite(white)) or np.any(white <= 0):
        raise ValueError(f"{name} must be 3 positive tristimulus values, got {white!r}")
    return white


def bradford_matrix(source_white, target_white) -> np.ndarray:
    """Bradford chromatic adaptation from ``source_white`` to ``target_white``.

    ``M = B^-1 diag(B w_t / B w_s) B`` with :data:`BRADFORD` ``B``, for column vectors:
    ``xyz_target = M @ xyz_source`` (``xyz @ M.T`` for arrays of colours).

    Parameters
    ----------
    source_white, target_white : array_like, shape (3,)
        Tristimulus values of the two whites.

    Returns
    -------
    ndarray, shape (3, 3)
    """
    source = BRADFORD @ _white(source_white, "source_white")
    target = BRADFORD @ _white(target_white, "target_white")
    return np.linalg.inv(BRADFORD) @ np.diag(target / source) @ BRADFORD


def xyz_to_lab(xyz, *, white=WHITE_D50) -> np.ndarray:
    """CIE XYZ to CIELAB (CIE 15:2004) relative to ``white``.

    Parameters
    ----------
    xyz : array_like, shape (..., 3)
    white : array_like, shape (3,)
        Tristimulus values of the reference white (Y = 1 scale as ``xyz``).

    Returns
    -------
    ndarray, shape (..., 3)
        (L*, a*, b*).
    """
    ratio = _colours(xyz, "xyz") / _white(white)
    f = np.where(ratio > _LAB_DELTA**3, np.cbrt(ratio), ratio / (3 * _LAB_DELTA**2) + 4.0 / 29.0)
    return np.stack(
        [
            116.0 * f[..., 1] - 16.0,
            500.0 * (f[..., 0] - f[..., 1]),
            200.0 * (f[..., 1] - f[..., 2]),
        ],
        axis=-1,
    )


def lab_to_xyz(lab, *, white=WHITE_D50) -> np.ndarray:
    """CIELAB relative to ``white`` back to CIE XYZ (the inverse of :func:`xyz_to_lab`)."""
    lab = _colours(lab, "lab")
    fy = (lab[..., 0] + 16.0) / 116.0
    f = np.stack([fy + lab[..., 1] / 500.0, fy, fy - lab[..., 2] / 200.0], axis=-1)
    ratio = np.where(f > _LAB_DELTA, f**3, 3 * _LAB_DELTA**2 * (f - 4.0 / 29.0))
    return ratio * _white(white)


def linear_rgb_to_lab(rgb, *, white=WHITE_D50) -> np.ndarray:
    """Linear sRGB (D65) to CIELAB relative to ``white``, adapting D65 to it by Bradford.

    Parameters
    ----------
    rgb : array_like, shape (..., 3)
        Linear RGB, white = (1, 1, 1); values outside [0, 1] are converted as they are.
    white : array_like, shape (3,)

    Returns
    -------
    ndarray, shape (..., 3)
    """
    matrix = bradford_matrix(WHITE_D65, white) @ SRGB_TO_XYZ
    return xyz_to_lab(_colours(rgb, "rgb") @ matrix.T, white=white)


def lab_to_linear_rgb(lab, *, white=WHITE_D50) -> np.ndarray:
    """CIELAB relative to ``white`` to linear sRGB (D65), the inverse of
    :func:`linear_rgb_to_lab`; colours outside the sRGB gamut get values outside [0, 1]."""
    matrix = XYZ_TO_SRGB @ bradford_matrix(white, WHITE_D65)
    return lab_to_xyz(lab, white=white) @ matrix.T


def delta_e_2000(lab1, lab2) -> np.ndarray:
    """CIEDE2000 colour difference (k_L = k_C = k_H = 1), as Sharma, Wu and Dalal,
    Color Res. Appl. 30(1), 2005, specify it (hue differences and means taken across
    the 0/360 degree cut, hue 0 for neutral colours).

    Parameters
    ----------
    lab1, lab2 : array_like, shape (..., 3)
        CIELAB colours; the shapes broadcast.

    Returns
    -------
    ndarray, shape (...)
    """
    lab1, lab2 = np.broadcast_arrays(_colours(lab1, "lab1"), _colours(lab2, "lab2"))
    lightness1, a1, b1 = np.moveaxis(lab1, -1, 0)
    lightness2, a2, b2 = np.moveaxis(lab2, -1, 0)
    chroma_mean7 = (0.5 * (np.hypot(a1, b1) + np.hypot(a2, b2))) ** 7
    g = 0.5 * (1.0 - np.sqrt(chroma_mean7 / (chroma_mean7 + 25.0**7)))
    a1, a2 = (1.0 + g) * a1, (1.0 + g) * a2
    chroma1, chroma2 = np.hypot(a1, b1), np.hypot(a2, b2)
    hue1 = np.degrees(np.arctan2(b1, a1)) % 360.0
    hue2 = np.degrees(np.arctan2(b2, a2)) % 360.0
    chromatic = chroma1 * chroma2 != 0
    hue_step = hue2 - hue1
    hue_step = np.where(
        hue_step > 180.0, hue_step - 360.0, np.where(hue_step < -180.0, hue_step + 360.0, hue_step)
    )
    hue_step = np.where(chromatic, hue_step, 0.0)
    delta_hue = 2.0 * np.sqrt(chroma1 * chroma2) * np.sin(np.radians(hue_step) / 2.0)
    hue_sum = hue1 + hue2
    hue_mean = np.where(
        np.abs(hue1 - hue2) <= 180.0,
        hue_sum / 2.0,
        np.where(hue_sum < 360.0, (hue_sum + 360.0) / 2.0, (hue_sum - 360.0) / 2.0),
    )
    hue_mean = np.where(chromatic, hue_mean, hue_sum)
    lightness_mean = 0.5 * (lightness1 + lightness2)
    chroma_mean = 0.5 * (chroma1 + chroma2)
    h = np.radians(hue_mean)
    t = (
        1.0
        - 0.17 * np.cos(h - np.radians(30.0))
        + 0.24 * np.cos(2.0 * h)
        + 0.32 * np.cos(3.0 * h + np.radians(6.0))
        - 0.20 * np.cos(4.0 * h - np.radians(63.0))
    )
    rotation = np.radians(30.0) * np.exp(-(((hue_mean - 275.0) / 25.0) ** 2))
    chroma_mean7 = chroma_mean**7
    r_t = -2.0 * np.sqrt(chroma_mean7 / (chroma_mean7 + 25.0**7)) * np.sin(2.0 * rotation)
    offset2 = (lightness_mean - 50.0) ** 2
    term_l = (lightness2 - lightness1) / (1.0 + 0.015 * offset2 / np.sqrt(20.0 + offset2))
    term_c = (chroma2 - chroma1) / (1.0 + 0.045 * chroma_mean)
    term_h = delta_hue / (1.0 + 0.015 * chroma_mean * t)
    return np.sqrt(term_l**2 + term_c**2 + term_h**2 + r_t * term_c * term_h)
