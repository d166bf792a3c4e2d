"""Camera rigs for the synthetic scene, and per-camera colour mismatch.

Cameras follow :class:`mvtools.geometry.camera.Camera`: ``x_cam = R (X - t)``,
``t`` the centre, x right, y down, z forward. Camera 0 is the leftmost.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np

from mvtools.geometry.camera import Camera


def intrinsics(*, fx: float, fy: float | None = None, cx: float, cy: float) -> np.ndarray:
    """The 3x3 intrinsic matrix ``[[fx, 0, cx], [0, fy, cy], [0, 0, 1]]`` (fy defaults to fx)."""
    return np.array([[fx, 0.0, cx], [0.0, fx if fy is None else fy, cy], [0.0, 0.0, 1.0]])


def _per_camera(value, n: int, what: str) -> list:
    """``value`` repeated for n cameras, or checked to hold one entry per camera."""
    if value is None:
        return [None] * n
    array = np.asarray(value, dtype=np.float64)
    if array.ndim <= 1:
        return [array] * n
    if len(array) != n:
        raise ValueError(f"{what} has {len(array)} entries for {n} cameras")
    return list(array)


def _names(names, n: int) -> list[str]:
    names = [f"cam{i}" for i in range(n)] if names is None else list(names)
    if len(names) != n or len(set(names)) != n:
        raise ValueError(f"need {n} distinct camera names, got {names}")
    return names


def linear_rig(
    n: int,
    *,
    baseline: float,
    K: np.ndarray,
    size: tuple[int, int],
    center=(0.0, 0.0, 0.0),
    distortion=None,
    depth_range=None,
    names: Sequence[str] | None = None,
) -> list[Camera]:
    """``n`` parallel cameras on the world x axis, like the MPEG 1D sequences.

    Parameters
    ----------
    n : int
        Number of cameras.
    baseline : float
        Distance between neighbours (metres); camera ``i`` is at
        ``center + ((i - (n - 1) / 2) * baseline, 0, 0)``, all with ``R = I``.
    K : ndarray, shape (3, 3) or (n, 3, 3)
        Intrinsics, shared or per camera.
    size : (width, height)
    center : array_like, shape (3,)
        Middle of the rig.
    distortion : array_like, shape (k,) or (n, k), optional
        Lens distortion (k1, k2, ...), shared or per camera.
    depth_range : (znear, zfar), optional
    names : sequence of str, optional
        Defaults to ``cam0 .. cam{n-1}``.

    Returns
    -------
    list of Camera
    """
    if n < 1 or baseline <= 0:
        raise ValueError(f"need n >= 1 and baseline > 0, got n={n}, baseline={baseline}")
    offsets = (np.arange(n) - (n - 1) / 2.0) * baseline
    centers = np.asarray(center, dtype=np.float64) + offsets[:, None] * np.array([1.0, 0.0, 0.0])
    return _cameras(names, K, [np.eye(3)] * n, centers, size, distortion, depth_range)


def rotation_about_y(angle_degrees: float) -> np.ndarray:
    """World-to-camera rotation of a camera turned by ``angle`` about the vertical (y)
    axis; positive angles turn the view towards +x (to the right)."""
    a = np.radians(angle_degrees)
    # Rows are the camera axes in world coordinates: x right, y down, z forward.
    forward = np.array([np.sin(a), 0.0, np.cos(a)])
    down = np.array([0.0, 1.0, 0.0])
    return np.stack([np.cross(down, forward), down, forward])


def arc_rig(
    n: int,
    *,
    radius: float,
    angle_step: float,
    K: np.ndarray,
    size: tuple[int, int],
    target=(0.0, 0.0, 4.5),
    distortion=None,
    depth_range=None,
    names: Sequence[str] | None = None,
) -> list[Camera]:
    """``n`` cameras on a horizontal arc, all looking at ``target``.

    Camera ``i`` sits at angle ``a_i = (i - (n - 1) / 2) * angle_step`` (degrees) on
    the circle of ``radius`` about the vertical axis through ``target``:
    ``t = target + radius * (sin a_i, 0, -cos a_i)``, turned by ``-a_i`` about y so
    that its optical axis passes through ``target``. Camera 0 is at the left.

    Parameters are those of :func:`linear_rig`, with ``radius`` (metres) and
    ``angle_step`` (degrees) instead of ``baseline``.
    """
    if n < 1 or radius <= 0:
        raise ValueError(f"need n >= 1 and radius > 0, got n={n}, radius={radius}")
    angles = (np.arange(n) - (n - 1) / 2.0) * angle_step
    a = np.radians(angles)
    centers = np.asarray(target, dtype=np.float64) + radius * np.stack(
        [np.sin(a), np.zeros(n), -np.cos(a)], axis=-1
    )
    rotations = [rotation_about_y(-angle) for angle in angles]
    return _cameras(names, K, rotations, centers, size, distortion, depth_range)


def _cameras(names, K, rotations, centers, size, distortion, depth_range) -> list[Camera]:
    n = len(centers)
    Ks = np.broadcast_to(np.asarray(K, dtype=np.float64), (n, 3, 3))
    distortions = _per_camera(distortion, n, "distortion")
    return [
        Camera(
            name=name,
            K=Ks[i].copy(),
            R=rotations[i],
            t=centers[i],
            distortion=np.zeros(2) if distortions[i] is None else distortions[i],
            size=(int(size[0]), int(size[1])),
            depth_range=None if depth_range is None else tuple(map(float, depth_range)),
        )
        for i, name in enumerate(_names(names, n))
    ]


def axis_angle_rotation(axis, angle_degrees: float) -> np.ndarray:
    """Rotation matrix by ``angle`` (degrees, right-handed) about ``axis`` (Rodrigues)."""
    axis = np.asarray(axis, dtype=np.float64).reshape(3)
    axis = axis / np.linalg.norm(axis)
    cross = np.array([[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]], [-axis[1], axis[0], 0.0]])
    a = np.radians(angle_degrees)
    return np.eye(3) + np.sin(a) * cross + (1.0 - np.cos(a)) * cross @ cross


def _small_rotation(rng: np.random.Generator, max_degrees: float) -> np.ndarray:
    """Rotation by a uniform angle in [0, max] about a uniformly random axis."""
    return axis_angle_rotation(rng.normal(size=3), rng.uniform(0.0, max_degrees))


def perturb_rig(
    cameras: Sequence[Camera],
    *,
    seed: int,
    rotation_degrees: float = 0.0,
    principal_point_pixels: float = 0.0,
    focal_fraction: float = 0.0,
    k1_range: tuple[float, float] | None = None,
    k2_range: tuple[float, float] | None = None,
) -> list[Camera]:
    """Imperfect copies of ``cameras``: the rig as built rather than as designed.

    Each camera is independently turned by up to ``rotation_degrees`` about a
    random axis (centre unchanged), its principal point moved by up to
    ``principal_point_pixels`` per coordinate, fx scaled by ``1 ± focal_fraction``
    and fy by a further ``± focal_fraction / 10`` (fx close to fy), and given
    lens distortion k1, k2 drawn uniformly from the ranges (kept as they were
    when a range is None). Deterministic for a given ``seed``.

    Returns
    -------
    list of Camera
    """
    rng = np.random.default_rng(seed)
    out = []
    for camera in cameras:
        turn = _small_rotation(rng, rotation_degrees)
        K = camera.K.copy()
        K[0, 0] *= 1.0 + rng.uniform(-focal_fraction, focal_fraction)
        K[1, 1] = K[0, 0] * (1.0 + rng.uniform(-focal_fraction, focal_fraction) / 10.0)
        K[0, 2] += rng.uniform(-principal_point_pixels, principal_point_pixels)
        K[1, 2] += rng.uniform(-principal_point_pixels, principal_point_pixels)
        distortion = np.zeros(2)
        distortion[: min(2, camera.distortion.size)] = camera.distortion[:2]
        for k, bounds in enumerate((k1_range, k2_range)):
            if bounds is not None:
                distortion[k] = rng.uniform(*bounds)
        out.append(replace(camera, K=K, R=turn @ camera.R, distortion=distortion))
    return out


@dataclass(frozen=True)
class ColorMismatch:
    """A camera's colour response relative to the ideal one, per RGB channel.

    ``out = clip(gain * in ** gamma + offset, 0, 1)`` on [0, 1] values, applied to
    the rendered RGB (display values, before quantisation).

    Attributes
    ----------
    gain, offset, gamma : tuple of 3 float
    """

    gain: tuple[float, float, float] = (1.0, 1.0, 1.0)
    offset: tuple[float, float, float] = (0.0, 0.0, 0.0)
    gamma: tuple[float, float, float] = (1.0, 1.0, 1.0)

    def __post_init__(self):
        for key in ("gain", "offset", "gamma"):
            value = tuple(float(x) for x in np.asarray(getattr(self, key)).reshape(-1))
            if len(value) != 3:
                raise ValueError(f"{key} needs 3 values (R, G, B), got {len(value)}")
            object.__setattr__(self, key, value)
        if min(self.gain) <= 0 or min(self.gamma) <= 0:
            raise ValueError("gain and gamma must be > 0")

    def apply(self, rgb: np.ndarray) -> np.ndarray:
        """The mismatched image, shape (..., 3), from [0, 1] RGB of the same shape."""
        rgb = np.clip(np.asarray(rgb, dtype=np.float64), 0.0, 1.0)
        return np.clip(
            np.asarray(self.gain) * rgb ** np.asarray(self.gamma) + np.asarray(self.offset),
            0.0,
            1.0,
        )

    def invert(self, rgb: np.ndarray) -> np.ndarray:
        """The ideal image from a mismatched one (exact where nothing was clipped)."""
        rgb = np.asarray(rgb, dtype=np.float64)
        base = np.clip((rgb - np.asarray(self.offset)) / np.asarray(self.gain), 0.0, 1.0)
        return base ** (1.0 / np.asarray(self.gamma))


def random_color_mismatches(
    n: int,
    *,
    seed: int,
    gain: float = 0.1,
    offset: float = 0.03,
    gamma: float = 0.1,
    reference: int | None = None,
) -> list[ColorMismatch]:
    """``n`` mismatches with gain in ``1 ± gain``, offset in ``± offset``, gamma in
    ``1 ± gamma`` per channel, uniformly; camera ``reference`` (if given) is left ideal."""
    rng = np.random.default_rng(seed)
    out = []
    for i in range(n):
        draw = ColorMismatch(
            gain=1.0 + rng.uniform(-gain, gain, 3),
            offset=rng.uniform(-offset, offset, 3),
            gamma=1.0 + rng.uniform(-gamma, gamma, 3),
        )
        out.append(ColorMismatch() if i == reference else draw)
    return out


def sample_intrinsics(width: int, height: int) -> np.ndarray:
    """Intrinsics of the sample data: focal length ``0.9375 * width`` (240 px at
    width 256, a 56 degree horizontal field of view), principal point at the
    image centre ``((width - 1) / 2, (height - 1) / 2)``."""
    return intrinsics(fx=0.9375 * width, cx=(width - 1) / 2.0, cy=(height - 1) / 2.0)


def sample_rigs(
    width: int = 256, height: int = 192, *, n: int = 5, depth_range=None, seed: int = 0
) -> dict[str, list[Camera]]:
    """The rigs of the sample data, all with :func:`sample_intrinsics`.

    - ``"line"``: :func:`linear_rig`, baseline 0.1 m, centred on the origin;
    - ``"arc"``: :func:`arc_rig`, radius 4.5 m, 5 degrees apart, looking at (0, 0, 4.5);
    - ``"distorted"``: the line as built (:func:`perturb_rig`: rotations up to
      0.5 degree, principal points within 2 px, focal lengths within 1 %,
      k1 in [-0.08, 0.08], k2 in [-0.01, 0.01]), drawn with ``seed``.

    ``depth_range`` (znear, zfar) is stored in every camera.
    """
    K = sample_intrinsics(width, height)
    line = linear_rig(n, baseline=0.1, K=K, size=(width, height), depth_range=depth_range)
    arc = arc_rig(
        n,
        radius=4.5,
        angle_step=5.0,
        target=(0.0, 0.0, 4.5),
        K=K,
        size=(width, height),
        depth_range=depth_range,
    )
    distorted = perturb_rig(
        line,
        seed=seed,
        rotation_degrees=0.5,
        principal_point_pixels=2.0,
        focal_fraction=0.01,
        k1_range=(-0.08, 0.08),
        k2_range=(-0.01, 0.01),
    )
    return {"line": line, "arc": arc, "distorted": distorted}
