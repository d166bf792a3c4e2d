"""The depth convention of MPEG depth maps: validation, value <-> z <-> disparity.

Every program reads and writes depth through this module, so there is one rule.

MPEG depth maps store a value ``v`` in ``0..vmax`` (``vmax = 2**bits - 1``) linear in
inverse depth, ``vmax`` being the nearest (eq. 1.6 of the chapter "Multiview video:
acquisition, processing, compression, and virtual view rendering")::

    1/z = (v / vmax) * (1/Znear - 1/Zfar) + 1/Zfar

which is the normalised disparity of eq. 1.5 with disparity ``1/z`` and range
``[1/Zfar, 1/Znear]``. Rectified pairs relate disparity and depth by
``z = f B / d`` (eq. 1.4). DERS writes disparity ``d`` (pixels) as
``v = round(vmax (d - dmin) / (dmax - dmin))`` and reports the matching
``Znear = f B / (dmax + off)``, ``Zfar = f B / (dmin + off)``.

Signs. ``z`` is signed as the files mean it, with the algebra of VSRS:

- ``DepthType 0`` (``z`` along the camera's axis): Znear and Zfar have one sign.
  A negative range (every Poznan sequence) says that the cameras' projective scale
  has the other sign: ``P`` and ``-P`` project alike, so the scene lies on the
  cameras' ``-z`` side. :func:`facing_camera` turns such a camera round
  (``R -> -R``, the same pixels, the same centre) so that its depths are positive.
- ``DepthType 1`` (``z`` is the world z coordinate): any sign; the cameras may look
  along world ``-z`` (Newspaper, Lovebird: ``R = diag(1, -1, -1)``). A range may
  also pass through ``1/z = 0`` (Big Buck Bunny butterfly: Znear 0.46, Zfar -2.42):
  it is used as VSRS uses it, ``1/z`` linear in ``v`` through zero, and the points
  it puts behind a camera are not warped.
- Nearer is larger ``|1/z|``: ``|Znear| < |Zfar|`` when both have one sign, and the
  larger depth value is the nearer surface.

Rounding to integers is half up (``floor(x + 0.5)``) and then clipped to
``0..vmax``.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from mvtools.geometry.camera import Camera
from mvtools.geometry.projection import depth_along_axis

__all__ = [
    "DepthCoding",
    "check_depth_range",
    "check_stereo",
    "depth_sign",
    "depth_to_z",
    "depth_value_to_disparity",
    "ders_depth_range",
    "disparity_1d",
    "disparity_to_depth_value",
    "disparity_to_z",
    "facing_camera",
    "inverse_depth_step",
    "max_depth_value",
    "normalized_disparity",
    "z_to_depth",
    "z_to_disparity",
]


def max_depth_value(bits: int) -> int:
    """``2**bits - 1`` for depth maps of 8 to 16 bits."""
    if not isinstance(bits, (int, np.integer)) or not 8 <= bits <= 16:
        raise ValueError(f"depth maps have 8 to 16 bits, got {bits!r}")
    return (1 << int(bits)) - 1


def check_depth_range(znear: float, zfar: float, *, depth_type: int = 0) -> None:
    """Raise ValueError, saying why, unless ``(znear, zfar)`` is a depth range.

    Parameters
    ----------
    znear, zfar : float
        The depths of values ``vmax`` and 0. ``zfar`` may be infinite.
    depth_type : {0, 1}
        0: depth along the camera axis, which cannot change sign within a range;
        1: world z, whose range may pass through ``1/z = 0``.

    Examples
    --------
    >>> check_depth_range(-23.39, -172.53)          # Poznan Hall 2
    >>> check_depth_range(0.464901, -2.424092, depth_type=1)   # Big Buck Bunny arc
    >>> check_depth_range(172.53, 23.39)
    Traceback (most recent call last):
    ...
    ValueError: Znear 172.53 is farther than Zfar 23.39: need |Znear| < |Zfar|
    """
    if depth_type not in (0, 1):
        raise ValueError(f"depth_type must be 0 or 1, got {depth_type!r}")
    if not (np.isfinite(znear) and znear != 0):
        raise ValueError(f"Znear must be finite and not 0, got {znear:g}")
    if np.isnan(zfar) or zfar == 0:
        raise ValueError(f"Zfar must not be 0 or NaN, got {zfar:g}")
    if (znear > 0) == (zfar > 0):
        if not abs(znear) < abs(zfar):
            raise ValueError(
                f"Znear {znear:g} is farther than Zfar {zfar:g}: need |Znear| < |Zfar|"
            )
    elif depth_type == 0:
        raise ValueError(
            f"Znear {znear:g} and Zfar {zfar:g} have opposite signs: depth "
            "along the camera axis (DepthType 0) keeps one sign"
        )


def depth_sign(znear: float, zfar: float) -> int:
    """+1 or -1: the sign of the depths of a range (of Znear where it changes sign)."""
    return 1 if znear > 0 else -1


def inverse_depth_step(depth_range: tuple[float, float]) -> float:
    """``|1/Znear - 1/Zfar| / 255``: the inverse depth of one 8-bit depth-value step.

    Tolerances given in 8-bit depth-value units (VSRS ``DepthBlendDifference``,
    ``DepthThreshold``) are multiplied by this to compare ``1/z`` of two views.
    """
    znear, zfar = (float(value) for value in depth_range)
    return abs(1.0 / znear - 1.0 / zfar) / 255.0


class DepthCoding:
    """Depth-map samples <-> depth, for one range, bit depth and DepthType.

    The depths are those the cameras of :func:`facing_camera` take: along the
    camera axis and positive for DepthType 0 (the file's z times
    :func:`depth_sign`), world z for DepthType 1.

    Parameters
    ----------
    depth_range : (znear, zfar)
        As the file or configuration gives them (:func:`check_depth_range`).
    bits : int
        Bit depth of the depth maps, 8 to 16.
    depth_type : {0, 1}

    Raises
    ------
    ValueError
        A pair that is not a depth range.

    Examples
    --------
    >>> coding = DepthCoding((-23.39, -172.53), 8, depth_type=0)
    >>> coding.z(np.array([255, 0], np.uint8))
    array([ 23.39, 172.53])
    >>> coding.values(np.array([23.39, 172.53]))
    array([255,   0], dtype=uint8)
    """

    def __init__(self, depth_range: tuple[float, float], bits: int, *, depth_type: int = 0):
        znear, zfar = (float(value) for value in depth_range)
        check_depth_range(znear, zfar, depth_type=depth_type)
        self.depth_range = (znear, zfar)
        self.bits = bits
        self.depth_type = depth_type
        # Working depths are the file's times `sign`: positive along facing cameras.
        self.sign = depth_sign(znear, zfar) if depth_type == 0 else 1
        self.inverse_range = (self.sign / zfar, self.sign / znear)
        values = np.arange(max_depth_value(bits) + 1)
        with np.errstate(divide="ignore"):
            # One division per possible value, then a look-up per pixel.
            self.table = 1.0 / depth_value_to_disparity(values, *self.inverse_range, bits=bits)

    def z(self, values: np.ndarray) -> np.ndarray:
        """Depth of depth-map samples, float64 of their shape."""
        return self.table[values]

    def values(self, z: np.ndarray) -> np.ndarray:
        """Depth-map samples of depths; non-finite depths (nothing seen) give 0."""
        z = np.asarray(z, dtype=np.float64)
        finite = np.isfinite(z) & (z != 0)
        inverse = np.divide(1.0, z, out=np.full_like(z, self.inverse_range[0]), where=finite)
        return disparity_to_depth_value(inverse, *self.inverse_range, bits=self.bits)

    @property
    def inverse_step(self) -> float:
        """:func:`inverse_depth_step` of the range."""
        return inverse_depth_step(self.depth_range)


def facing_camera(
    camera: Camera, depth_range: tuple[float, float], *, depth_type: int = 0
) -> Camera:
    """``camera``, turned round (``R -> -R``) when the depths of ``depth_range`` lie behind it.

    ``P = K [R | -R t]`` and ``-P`` project every point to the same pixel, so the
    turned camera sees the same picture from the same centre, with depths along its
    axis of the other sign. Behind: for DepthType 0 a negative range; for DepthType 1
    the plane ``Z = Znear`` meeting the ray of the principal point behind the
    camera. Reference and virtual cameras of one view set are turned with the same
    range, so that all of them face the scene.

    Returns
    -------
    Camera
        ``camera`` itself when it faces the range already, else a turned copy.
    """
    znear, zfar = depth_range
    check_depth_range(znear, zfar, depth_type=depth_type)
    if depth_type == 0:
        behind = depth_sign(znear, zfar) < 0
    else:
        with np.errstate(divide="ignore", invalid="ignore"):
            axis_depth = depth_along_axis(camera, camera.cx, camera.cy, znear, depth_type=1)
        behind = bool(axis_depth < 0)
    return dataclasses.replace(camera, R=-camera.R) if behind else camera


def _check_disparity_range(dmin: float, dmax: float) -> None:
    # dmin > dmax is a mapping too: inverse depths of negative ranges decrease to vmax.
    if not (np.isfinite(dmin) and np.isfinite(dmax) and dmin != dmax):
        raise ValueError(f"need finite dmin != dmax, got dmin={dmin}, dmax={dmax}")


def _positive(z, what: str = "z") -> np.ndarray:
    z = np.asarray(z, dtype=np.float64)
    if not np.all(z > 0):
        raise ValueError(f"{what} must be positive (and not NaN)")
    return z


def _nonzero(z) -> np.ndarray:
    z = np.asarray(z, dtype=np.float64)
    if np.any(np.isnan(z)) or np.any(z == 0):
        raise ValueError("z must not be 0 or NaN")
    return z


def _quantize(values: np.ndarray, bits: int) -> np.ndarray:
    vmax = max_depth_value(bits)
    dtype = np.uint8 if bits <= 8 else np.uint16
    return np.clip(np.floor(values + 0.5), 0, vmax).astype(dtype)


def normalized_disparity(disparity, dmin: float, dmax: float, *, bits: int = 8) -> np.ndarray:
    """Map disparities ``[dmin, dmax]`` linearly to ``[0, vmax]`` (eq. 1.5 of the chapter), unrounded.

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
        raise ValueError(
            f"depth values must lie in 0..{vmax} for {bits} bits, "
            f"got {values.min()}..{values.max()}"
        )
    if np.issubdtype(values.dtype, np.integer):
        # One division per possible value instead of one per pixel.
        table = dmin + np.arange(vmax + 1, dtype=np.float64) / vmax * (dmax - dmin)
        return table[values]
    return dmin + values.astype(np.float64) / vmax * (dmax - dmin)


def depth_to_z(
    values, znear: float, zfar: float, *, bits: int = 8, depth_type: int = 0
) -> np.ndarray:
    """Depth ``z`` of depth map values (``vmax`` = ``znear``, 0 = ``zfar``), signed as the
    range is.

    Parameters
    ----------
    values : array_like of int or float
        Depth map samples in ``0..vmax``.
    znear, zfar : float
        A range of :func:`check_depth_range`; ``zfar`` may be infinite.
    bits : int
        Bit depth of the depth map (8 to 16).
    depth_type : {0, 1}
        Which ranges are allowed (:func:`check_depth_range`).

    Returns
    -------
    ndarray of float64, the shape of ``values``
    """
    check_depth_range(znear, zfar, depth_type=depth_type)
    inverse = depth_value_to_disparity(values, 1.0 / zfar, 1.0 / znear, bits=bits)
    with np.errstate(divide="ignore"):
        return 1.0 / inverse


def z_to_depth(z, znear: float, zfar: float, *, bits: int = 8, depth_type: int = 0) -> np.ndarray:
    """Depth map values of depths ``z``, rounded and clipped to ``0..vmax``.

    Parameters
    ----------
    z : array_like
        Depths of the range's sign, not 0 (``inf`` maps to 0 when ``zfar`` is finite).
    znear, zfar : float
        A range of :func:`check_depth_range`; ``zfar`` may be infinite.
    bits : int
        8 to 16.
    depth_type : {0, 1}

    Returns
    -------
    ndarray of uint8 (``bits <= 8``) or uint16
    """
    check_depth_range(znear, zfar, depth_type=depth_type)
    return disparity_to_depth_value(1.0 / _nonzero(z), 1.0 / zfar, 1.0 / znear, bits=bits)


def disparity_to_z(disparity, focal: float, baseline: float) -> np.ndarray:
    """``z = focal * baseline / disparity`` (eq. 1.4 of the chapter); zero disparity gives ``inf``.

    Parameters
    ----------
    disparity : array_like
        Positive or zero disparities in pixels.
    focal : float
        Focal length in pixels, positive.
    baseline : float
        Distance between the camera centres, positive (any length unit; ``z`` has it).
    """
    check_stereo(focal, baseline)
    disparity = np.asarray(disparity, dtype=np.float64)
    if not np.all(disparity >= 0):
        raise ValueError("disparity must be >= 0 (and not NaN)")
    with np.errstate(divide="ignore"):
        return focal * baseline / disparity


def z_to_disparity(z, focal: float, baseline: float) -> np.ndarray:
    """``disparity = focal * baseline / z``; ``z = inf`` gives 0."""
    check_stereo(focal, baseline)
    return focal * baseline / _positive(z)


def check_stereo(focal: float, baseline: float) -> None:
    """ValueError unless the focal length (pixels) and the baseline are positive and
    finite: the rule of every disparity <-> depth formula here."""
    if not (np.isfinite(focal) and focal > 0 and np.isfinite(baseline) and baseline > 0):
        raise ValueError(
            f"focal and baseline must be positive and finite, got "
            f"focal={focal}, baseline={baseline}"
        )


def ders_depth_range(
    focal: float, baseline: float, dmin: float, dmax: float, *, offset: float = 0.0
) -> tuple[float, float]:
    """``(Znear, Zfar)`` that DERS reports for the disparity range ``[dmin, dmax]``.

    ``Znear = f B / (dmax + off)``, ``Zfar = f B / (dmin + off)`` with
    ``off = cx_center - cx_left``; ``Zfar`` is ``inf`` when ``dmin + off = 0``.
    With these, :func:`z_to_depth` of ``z = f B / (d + off)`` equals
    :func:`disparity_to_depth_value` of ``d``.
    """
    check_stereo(focal, baseline)
    if not (np.isfinite(dmin) and np.isfinite(dmax) and dmin < dmax):
        raise ValueError(f"need finite dmin < dmax, got dmin={dmin}, dmax={dmax}")
    if dmin + offset < 0:
        raise ValueError(
            f"dmin + offset must be >= 0 (else Zfar is behind the cameras), got {dmin} + {offset}"
        )
    zfar = np.inf if dmin + offset == 0 else focal * baseline / (dmin + offset)
    return focal * baseline / (dmax + offset), float(zfar)


def disparity_1d(
    z,
    *,
    focal: float,
    tx_ref: float,
    tx_virtual: float,
    cx_ref: float = 0.0,
    cx_virtual: float = 0.0,
) -> np.ndarray:
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
