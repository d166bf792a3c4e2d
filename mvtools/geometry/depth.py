"""Depth map values, depth ``z`` and disparity.

MPEG depth maps store a value ``v`` in ``0..vmax`` (``vmax = 2**bits - 1``) linear in
inverse depth, ``vmax`` being the nearest (seed eq. 1.6)::

    1/z = (v / vmax) * (1/Znear - 1/Zfar) + 1/Zfar

which is the normalised disparity of seed eq. 1.5 with disparity ``1/z`` and range
``[1/Zfar, 1/Znear]``. Rectified pairs relate disparity and depth by
``z = f B / d`` (seed eq. 1.4). DERS writes disparity ``d`` (pixels) as
``v = round(vmax (d - dmin) / (dmax - dmin))`` and reports the matching
``Znear = f B / (dmax + off)``, ``Zfar = f B / (dmin + off)``.

Rounding to integers is half up (``floor(x + 0.5)``) and then clipped to
``0..vmax``.
"""

from __future__ import annotations

import numpy as np

__all__ = ["max_depth_value", "depth_to_z", "z_to_depth", "disparity_to_z", "z_to_disparity",
           "normalized_disparity", "disparity_to_depth_value", "depth_value_to_disparity",
           "ders_depth_range", "disparity_1d"]


def max_depth_value(bits: int) -> int:
    """``2**bits - 1`` for depth maps of 8 to 16 bits."""
    if not isinstance(bits, (int, np.integer)) or not 8 <= bits <= 16:
        raise ValueError(f"depth maps have 8 to 16 bits, got {bits!r}")
    return (1 << int(bits)) - 1


def _check_depth_range(znear: float, zfar: float) -> None:
    if not (np.isfinite(znear) and 0 < znear < zfar):
        raise ValueError(f"need 0 < znear < zfar (zfar may be inf), got znear={znear}, "
                         f"zfar={zfar}")


def _check_disparity_range(dmin: float, dmax: float) -> None:
    if not (np.isfinite(dmin) and np.isfinite(dmax) and dmin < dmax):
        raise ValueError(f"need finite dmin < dmax, got dmin={dmin}, dmax={dmax}")


def _positive(z, what: str = "z") -> np.ndarray:
    z = np.asarray(z, dtype=np.float64)
    if not np.all(z > 0):
        raise ValueError(f"{what} must be positive (and not NaN)")
    return z


def _quantize(values: np.ndarray, bits: int) -> np.ndarray:
    vmax = max_depth_value(bits)
    dtype = np.uint8 if bits <= 8 else np.uint16
    return np.clip(np.floor(values + 0.5), 0, vmax).astype(dtype)


def normalized_disparity(disparity, dmin: float, dmax: float, *, bits: int = 8) -> np.ndarray:
    """Map disparities ``[dmin, dmax]`` linearly to ``[0, vmax]`` (seed eq. 1.5), unrounded.

    Parameters
    ----------
    disparity : array_like
    dmin, dmax : float
        The disparities that map to 0 and ``vmax``.
    bits : int
        Bit depth, ``vmax = 2**bits - 1``.

    Returns
    -------
    ndarray of float64, the shape of ``disparity``
    """
    _check_disparity_range(dmin, dmax)
    vmax = max_depth_value(bits)
    return vmax * (np.asarray(disparity, dtype=np.float64) - dmin) / (dmax - dmin)


def disparity_to_depth_value(disparity, dmin: float, dmax: float, *, bits: int = 8) -> np.ndarray:
    """The DERS mapping ``v = round(vmax (d - dmin) / (dmax - dmin))``, clipped.

    Returns
    -------
    ndarray of uint8 (``bits <= 8``) or uint16, the shape of ``disparity``
    """
    return _quantize(normalized_disparity(disparity, dmin, dmax, bits=bits), bits)


def depth_value_to_disparity(values, dmin: float, dmax: float, *, bits: int = 8) -> np.ndarray:
    """Inverse of :func:`normalized_disparity`: ``d = dmin + v / vmax (dmax - dmin)``.

    Raises
    ------
    ValueError
        Values outside ``0..vmax``.
    """
    _check_disparity_range(dmin, dmax)
    vmax = max_depth_value(bits)
    values = np.asarray(values)
    if values.size and (values.min() < 0 or values.max() > vmax):
        raise ValueError(f"depth values must lie in 0..{vmax} for {bits} bits, "
                         f"got {values.min()}..{values.max()}")
    if np.issubdtype(values.dtype, np.integer):
        # One division per possible value instead of one per pixel.
        table = dmin + np.arange(vmax + 1, dtype=np.float64) / vmax * (dmax - dmin)
        return table[values]
    return dmin + values.astype(np.float64) / vmax * (dmax - dmin)


def depth_to_z(values, znear: float, zfar: float, *, bits: int = 8) -> np.ndarray:
    """Depth ``z`` of depth map values (``vmax`` = ``znear``, 0 = ``zfar``).

    Parameters
    ----------
    values : array_like of int or float
        Depth map samples in ``0..vmax``.
    znear, zfar : float
        ``0 < znear < zfar``; ``zfar`` may be ``inf``.
    bits : int
        Bit depth of the depth map (8 to 16).

    Returns
    -------
    ndarray of float64, the shape of ``values``
    """
    _check_depth_range(znear, zfar)
    inverse = depth_value_to_disparity(values, 1.0 / zfar, 1.0 / znear, bits=bits)
    with np.errstate(divide="ignore"):
        return 1.0 / inverse


def z_to_depth(z, znear: float, zfar: float, *, bits: int = 8) -> np.ndarray:
    """Depth map values of depths ``z``, rounded and clipped to ``0..vmax``.

    Parameters
    ----------
    z : array_like
        Positive depths (``inf`` maps to 0 when ``zfar`` is finite).
    znear, zfar : float
        ``0 < znear < zfar``; ``zfar`` may be ``inf``.
    bits : int
        8 to 16.

    Returns
    -------
    ndarray of uint8 (``bits <= 8``) or uint16
    """
    _check_depth_range(znear, zfar)
    return disparity_to_depth_value(1.0 / _positive(z), 1.0 / zfar, 1.0 / znear, bits=bits)


def disparity_to_z(disparity, focal: float, baseline: float) -> np.ndarray:
    """``z = focal * baseline / disparity`` (seed eq. 1.4); zero disparity gives ``inf``.

    Parameters
    ----------
    disparity : array_like
        Positive or zero disparities in pixels.
    focal : float
        Focal length in pixels, positive.
    baseline : float
        Distance between the camera centres, positive (any length unit; ``z`` has it).
    """
    _check_stereo(focal, baseline)
    disparity = np.asarray(disparity, dtype=np.float64)
    if not np.all(disparity >= 0):
        raise ValueError("disparity must be >= 0 (and not NaN)")
    with np.errstate(divide="ignore"):
        return focal * baseline / disparity


def z_to_disparity(z, focal: float, baseline: float) -> np.ndarray:
    """``disparity = focal * baseline / z``; ``z = inf`` gives 0."""
    _check_stereo(focal, baseline)
    return focal * baseline / _positive(z)


def _check_stereo(focal: float, baseline: float) -> None:
    if not (np.isfinite(focal) and focal > 0 and np.isfinite(baseline) and baseline > 0):
        raise ValueError(f"focal and baseline must be positive and finite, got "
                         f"focal={focal}, baseline={baseline}")


def ders_depth_range(focal: float, baseline: float, dmin: float, dmax: float, *,
                     offset: float = 0.0) -> tuple[float, float]:
    """``(Znear, Zfar)`` that DERS reports for the disparity range ``[dmin, dmax]``.

    ``Znear = f B / (dmax + off)``, ``Zfar = f B / (dmin + off)`` with
    ``off = cx_center - cx_left``; ``Zfar`` is ``inf`` when ``dmin + off = 0``.
    With these, :func:`z_to_depth` of ``z = f B / (d + off)`` equals
    :func:`disparity_to_depth_value` of ``d``.
    """
    _check_stereo(focal, baseline)
    _check_disparity_range(dmin, dmax)
    if dmin + offset < 0:
        raise ValueError(f"dmin + offset must be >= 0 (else Zfar is behind the cameras), "
                         f"got {dmin} + {offset}")
    zfar = np.inf if dmin + offset == 0 else focal * baseline / (dmin + offset)
    return focal * baseline / (dmax + offset), float(zfar)


def disparity_1d(z, *, focal: float, tx_ref: float, tx_virtual: float,
                 cx_ref: float = 0.0, cx_virtual: float = 0.0) -> np.ndarray:
    """Disparity of the VSRS 1D (parallel) mode, ``u_virtual = u_ref - d``.

    ``d = focal * (tx_virtual - tx_ref) / z - (cx_virtual - cx_ref)``, with ``t`` the
    camera centres' x coordinates. VSRS uses ``fx`` of the left camera for both
    views; the caller chooses ``focal``.

    Parameters
    ----------
    z : array_like
        Positive depth along the (common) camera axis.
    focal : float
        Focal length in pixels.
    tx_ref, tx_virtual : float
        x of the reference and virtual camera centres.
    cx_ref, cx_virtual : float
        Their horizontal principal points.

    Returns
    -------
    ndarray of float64, the shape of ``z``
    """
    return focal * (tx_virtual - tx_ref) / _positive(z) - (cx_virtual - cx_ref)
