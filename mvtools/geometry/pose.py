"""Camera poses for free navigation: rotations as quaternions, smooth paths, stereo eyes.

A virtual camera moving through a scene is a sequence of :class:`Camera` s whose centres
follow a smooth curve and whose orientations turn smoothly between given keyframes
(slerp: K. Shoemake, "Animating rotation with quaternion curves", SIGGRAPH 1985;
matrix to quaternion: S. W. Shepperd, "Quaternion from rotation matrix", Journal of
Guidance and Control 1(3), 1978).

Quaternions are ``(w, x, y, z)`` with ``w >= 0`` for the rotation matrix ``R`` acting on
column vectors (``v' = R v``); the rotation by angle ``a`` about the unit axis ``n`` is
``(cos(a/2), sin(a/2) n)``. Both ``q`` and ``-q`` stand for the same rotation.

Examples
--------
A quarter turn about z, and halfway to it:

>>> import numpy as np
>>> from mvtools.geometry.pose import quaternion_from_rotation, slerp
>>> quarter = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
>>> q = quaternion_from_rotation(quarter)
>>> print(np.round(q, 6))
[0.707107 0.       0.       0.707107]
>>> eighth = slerp(np.array([1.0, 0.0, 0.0, 0.0]), q, 0.5)
>>> print(np.round(np.degrees(2 * np.arccos(eighth[0])), 6))
45.0
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Sequence
from dataclasses import replace

import numpy as np

from mvtools.geometry.camera import Camera

__all__ = [
    "camera_path",
    "eye_cameras",
    "quaternion_from_rotation",
    "rotation_from_quaternion",
    "slerp",
]

# Above this |q0 . q1| the two rotations are within ~1e-4 degrees: slerp's sin(theta)
# divides by almost zero, and the normalised linear blend is exact to rounding.
_NEARLY_PARALLEL = 1.0 - 1e-12


def quaternion_from_rotation(R: np.ndarray) -> np.ndarray:
    """The unit quaternion of a rotation matrix (Shepperd's method).

    Parameters
    ----------
    R : ndarray, shape (3, 3)
        A rotation matrix (orthonormal, determinant 1).

    Returns
    -------
    ndarray, shape (4,)
        ``(w, x, y, z)`` with ``w >= 0`` (when ``w == 0``, a half turn, the first
        non-zero of x, y, z is positive).

    Raises
    ------
    ValueError
        ``R`` is not a finite 3x3 matrix.

    Examples
    --------
    >>> quaternion_from_rotation(np.eye(3))
    array([1., 0., 0., 0.])
    """
    r = np.asarray(R, dtype=np.float64)
    if r.shape != (3, 3) or not np.all(np.isfinite(r)):
        raise ValueError(f"need a finite 3x3 rotation matrix, got shape {r.shape}")
    trace = r[0, 0] + r[1, 1] + r[2, 2]
    # Divide by the largest of 4w^2, 4x^2, 4y^2, 4z^2 for accuracy.
    diagonal = (trace, r[0, 0], r[1, 1], r[2, 2])
    k = int(np.argmax(diagonal))
    if k == 0:
        s = 2.0 * math.sqrt(1.0 + trace)
        q = [s / 4.0, (r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s, (r[1, 0] - r[0, 1]) / s]
    elif k == 1:
        s = 2.0 * math.sqrt(max(1.0 + r[0, 0] - r[1, 1] - r[2, 2], 0.0))
        q = [(r[2, 1] - r[1, 2]) / s, s / 4.0, (r[0, 1] + r[1, 0]) / s, (r[0, 2] + r[2, 0]) / s]
    elif k == 2:
        s = 2.0 * math.sqrt(max(1.0 - r[0, 0] + r[1, 1] - r[2, 2], 0.0))
        q = [(r[0, 2] - r[2, 0]) / s, (r[0, 1] + r[1, 0]) / s, s / 4.0, (r[1, 2] + r[2, 1]) / s]
    else:
        s = 2.0 * math.sqrt(max(1.0 - r[0, 0] - r[1, 1] + r[2, 2], 0.0))
        q = [(r[1, 0] - r[0, 1]) / s, (r[0, 2] + r[2, 0]) / s, (r[1, 2] + r[2, 1]) / s, s / 4.0]
    q = np.array(q, dtype=np.float64)
    q /= np.linalg.norm(q)
    return _canonical(q)


def _canonical(q: np.ndarray) -> np.ndarray:
    """``q`` or ``-q``, whichever has ``w > 0`` (or its first non-zero entry > 0)."""
    nonzero = np.flatnonzero(q)
    if nonzero.size and q[nonzero[0]] < 0:
        q = -q
    return q + 0.0  # no negative zeros


def rotation_from_quaternion(q: np.ndarray) -> np.ndarray:
    """The rotation matrix of a quaternion (normalised first).

    Parameters
    ----------
    q : ndarray, shape (4,)
        ``(w, x, y, z)``, any non-zero length.

    Returns
    -------
    ndarray, shape (3, 3)

    Raises
    ------
    ValueError
        ``q`` is not 4 finite numbers or is zero.

    Examples
    --------
    >>> half = np.sqrt(0.5)
    >>> print(np.round(rotation_from_quaternion([half, half, 0.0, 0.0]), 6) + 0.0)
    [[ 1.  0.  0.]
     [ 0.  0. -1.]
     [ 0.  1.  0.]]
    """
    q = np.asarray(q, dtype=np.float64).reshape(-1)
    norm = float(np.linalg.norm(q)) if q.shape == (4,) else 0.0
    if q.shape != (4,) or not math.isfinite(norm) or norm == 0.0:
        raise ValueError(f"need a non-zero finite quaternion (w, x, y, z), got {q.tolist()}")
    w, x, y, z = q / norm
    return np.array(
        [
            [1.0 - 2.0 * (y * y + z * z), 2.0 * (x * y - w * z), 2.0 * (x * z + w * y)],
            [2.0 * (x * y + w * z), 1.0 - 2.0 * (x * x + z * z), 2.0 * (y * z - w * x)],
            [2.0 * (x * z - w * y), 2.0 * (y * z + w * x), 1.0 - 2.0 * (x * x + y * y)],
        ]
    )


def slerp(q0: np.ndarray, q1: np.ndarray, s: float) -> np.ndarray:
    """Spherical linear interpolation along the shorter arc from ``q0`` to ``q1``.

    The rotation turns at constant angular speed about one axis: ``s = 0`` gives ``q0``,
    ``s = 1`` the rotation of ``q1`` (possibly as ``-q1``), values outside [0, 1]
    continue the same turn (extrapolation).

    Parameters
    ----------
    q0, q1 : ndarray, shape (4,)
        Quaternions ``(w, x, y, z)``; normalised first.
    s : float

    Returns
    -------
    ndarray, shape (4,)
        A unit quaternion (its sign is not made canonical).

    Raises
    ------
    ValueError
        A quaternion is zero or not finite, or ``s`` is not finite.
    """
    q0 = _unit(q0)
    q1 = _unit(q1)
    if not math.isfinite(s):
        raise ValueError(f"slerp parameter must be finite, got {s}")
    dot = float(q0 @ q1)
    if dot < 0.0:  # the same rotation as -q1, by the shorter way
        q1, dot = -q1, -dot
    if dot > _NEARLY_PARALLEL:
        q = (1.0 - s) * q0 + s * q1
    else:
        theta = math.acos(min(dot, 1.0))
        q = (math.sin((1.0 - s) * theta) * q0 + math.sin(s * theta) * q1) / math.sin(theta)
    return q / np.linalg.norm(q)


def _unit(q) -> np.ndarray:
    q = np.asarray(q, dtype=np.float64).reshape(-1)
    norm = float(np.linalg.norm(q)) if q.shape == (4,) else 0.0
    if q.shape != (4,) or not math.isfinite(norm) or norm == 0.0:
        raise ValueError(f"need a non-zero finite quaternion (w, x, y, z), got {q.tolist()}")
    return q / norm


def camera_path(
    keyframes: Sequence[Camera], frames: int, *, extend: float = 0.0, name: str = "path"
) -> list[Camera]:
    """``frames`` cameras moving smoothly through ``keyframes`` in order.

    The path is parametrised by the keyframe index ``u`` (keyframe ``i`` at ``u = i``)
    and sampled at ``frames`` evenly spaced values from ``-extend`` to
    ``n - 1 + extend`` (``n`` keyframes): with ``extend == 0`` the first camera is
    keyframe 0 and the last the last keyframe; ``extend = 0.5`` starts half a keyframe
    interval before the first and ends half an interval after the last.

    - Centres: a cubic spline through the keyframe centres over ``u``
      (``scipy.interpolate.CubicSpline``, not-a-knot ends, continued by its end
      cubics); two keyframes give the straight line at uniform speed. Collinear
      evenly spaced centres stay on their line; centres on a circle stay on it to the
      spline's accuracy (about 1e-5 of the radius for 5 degree steps).
    - Rotations: slerp between keyframes ``i`` and ``i + 1`` with ``s = u - i``,
      ``i = clip(floor(u), 0, n - 2)``, so beyond the ends the first or last turn is
      continued (``s`` outside [0, 1]). Equal neighbouring rotations are kept exactly.
    - Intrinsics: ``K`` blended linearly with the same ``s`` (equal ``K`` s kept exactly).
    - ``size`` and ``distortion`` of keyframe 0; ``depth_range`` the union (smallest
      near, largest far) of the keyframes that have one, else None.

    Centres move at a speed that follows the keyframes' spacing: evenly spaced keyframes
    give an even speed.

    Parameters
    ----------
    keyframes : sequence of Camera
        At least one; a single keyframe gives ``frames`` copies of it (nothing to move
        along, ``extend`` is ignored).
    frames : int
        Number of cameras, >= 2 (>= 1 for a single keyframe).
    extend : float
        Keyframe intervals added beyond each end, >= 0.
    name : str
        Camera ``k`` is named ``f"{name}{k:03d}"``.

    Returns
    -------
    list of Camera

    Raises
    ------
    ValueError
        No keyframes, too few frames, a negative or non-finite ``extend``.

    Examples
    --------
    Halfway along two cameras 1 m apart, and half an interval beyond each:

    >>> from mvtools.geometry import Camera
    >>> K = np.diag([100.0, 100.0, 1.0])
    >>> keys = [Camera("a", K, t=[0.0, 0.0, 0.0]), Camera("b", K, t=[1.0, 0.0, 0.0])]
    >>> [float(c.t[0]) for c in camera_path(keys, 3)]
    [0.0, 0.5, 1.0]
    >>> [(c.name, float(c.t[0])) for c in camera_path(keys, 3, extend=0.5, name="v")]
    [('v000', -0.5), ('v001', 0.5), ('v002', 1.5)]
    """
    keyframes = list(keyframes)
    n = len(keyframes)
    if n == 0:
        raise ValueError("a camera path needs at least one keyframe")
    if not (_real(extend) and math.isfinite(extend) and extend >= 0):
        raise ValueError(f"extend must be a finite number >= 0, got {extend!r}")
    least = 1 if n == 1 else 2
    if isinstance(frames, bool) or not isinstance(frames, (int, np.integer)) or frames < least:
        raise ValueError(f"a path through {n} keyframe(s) needs frames >= {least}, got {frames!r}")
    first = keyframes[0]
    ranges = [k.depth_range for k in keyframes if k.depth_range is not None]
    depth_range = (
        (min(float(r[0]) for r in ranges), max(float(r[1]) for r in ranges)) if ranges else None
    )
    if n == 1:
        return [
            replace(
                first,
                name=f"{name}{k:03d}",
                K=first.K.copy(),
                R=first.R.copy(),
                t=first.t.copy(),
                distortion=first.distortion.copy(),
                depth_range=depth_range,
            )
            for k in range(frames)
        ]
    params = np.linspace(-extend, n - 1 + extend, frames)
    if extend == 0:
        params[-1] = n - 1  # exactly the last keyframe
    centres = np.stack([k.t for k in keyframes])
    if n == 2:
        positions = centres[0] + params[:, None] * (centres[1] - centres[0])
    else:
        from scipy.interpolate import CubicSpline

        positions = CubicSpline(np.arange(n), centres, axis=0, bc_type="not-a-knot")(params)
    quaternions = [quaternion_from_rotation(k.R) for k in keyframes]
    path = []
    for k, u in enumerate(params):
        i = int(min(max(math.floor(u), 0), n - 2))
        s = float(u - i)
        a, b = keyframes[i], keyframes[i + 1]
        if s == 0.0:
            t = a.t.copy()
        elif s == 1.0:
            t = b.t.copy()
        else:
            t = positions[k]
        path.append(
            Camera(
                name=f"{name}{k:03d}",
                K=_blend(a.K, b.K, s),
                R=_turn(a.R, b.R, quaternions[i], quaternions[i + 1], s),
                t=t,
                distortion=first.distortion.copy(),
                size=first.size,
                depth_range=depth_range,
            )
        )
    return path


def _real(value) -> bool:
    return isinstance(value, numbers.Real) and not isinstance(value, bool)


def _blend(a: np.ndarray, b: np.ndarray, s: float) -> np.ndarray:
    """``(1 - s) a + s b``, exactly ``a`` or ``b`` where they agree or ``s`` is 0 or 1."""
    if s == 0.0 or np.array_equal(a, b):
        return a.copy()
    if s == 1.0:
        return b.copy()
    return (1.0 - s) * a + s * b


def _turn(ra: np.ndarray, rb: np.ndarray, qa: np.ndarray, qb: np.ndarray, s: float) -> np.ndarray:
    if s == 0.0 or np.array_equal(ra, rb):
        return ra.copy()
    if s == 1.0:
        return rb.copy()
    return rotation_from_quaternion(slerp(qa, qb, s))


def eye_cameras(camera: Camera, ipd: float) -> tuple[Camera, Camera]:
    """The left and right eyes of a viewer at ``camera``.

    The centres are moved by ``-ipd / 2`` and ``+ipd / 2`` along the camera's x axis
    (``R[0]`` in world coordinates, the image's rightward direction); rotation,
    intrinsics and the rest are the camera's (parallel eyes).

    Parameters
    ----------
    camera : Camera
    ipd : float
        Interpupillary distance, > 0, in the unit of the camera centres.

    Returns
    -------
    (Camera, Camera)
        Named ``camera.name + "_left"`` and ``camera.name + "_right"``.

    Raises
    ------
    ValueError
        ``ipd`` is not a finite number > 0.

    Examples
    --------
    >>> from mvtools.geometry import Camera
    >>> left, right = eye_cameras(Camera("c", np.eye(3), t=[1.0, 2.0, 3.0]), 0.064)
    >>> left.name, left.t.tolist(), right.t.tolist()
    ('c_left', [0.968, 2.0, 3.0], [1.032, 2.0, 3.0])
    """
    if not (_real(ipd) and 0 < ipd < math.inf):
        raise ValueError(f"the interpupillary distance must be a finite number > 0, got {ipd!r}")
    offset = 0.5 * float(ipd) * camera.R[0]
    left = replace(camera, name=camera.name + "_left", t=camera.t - offset, K=camera.K.copy())
    right = replace(camera, name=camera.name + "_right", t=camera.t + offset, K=camera.K.copy())
    return left, right
