"""The camera model shared by every program.

Convention (VSRS 4.x, DERS 6.1): ``t`` is the camera centre in world coordinates
and ``R`` rotates world into camera coordinates, ``x_cam = R (X - t)``. The camera
looks along its +z axis, x to the right and y down in the image.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np


@dataclass(eq=False)
class Camera:
    """A pinhole camera with optional lens distortion.

    Attributes
    ----------
    name : str
        The camera's name as in the camera parameter file.
    K : ndarray, shape (3, 3)
        Intrinsic matrix ``[[fx, s, cx], [0, fy, cy], [0, 0, 1]]`` in pixels.
    R : ndarray, shape (3, 3)
        Rotation from world to camera coordinates.
    t : ndarray, shape (3,)
        Camera centre in world coordinates.
    distortion : ndarray, shape (n,)
        Brown-Conrady coefficients in OpenCV order ``(k1, k2, p1, p2, k3)``;
        shorter arrays mean the missing ones are zero. MPEG files store k1, k2.
    size : tuple of int or None
        ``(width, height)`` in pixels when known.
    depth_range : tuple of float or None
        ``(z_near, z_far)`` when the file gives it (MPEG-I JSON).
    """

    name: str
    K: np.ndarray
    R: np.ndarray = field(default_factory=lambda: np.eye(3))
    t: np.ndarray = field(default_factory=lambda: np.zeros(3))
    distortion: np.ndarray = field(default_factory=lambda: np.zeros(2))
    size: tuple[int, int] | None = None
    depth_range: tuple[float, float] | None = None

    def __post_init__(self):
        self.K = np.asarray(self.K, dtype=np.float64).reshape(3, 3)
        self.R = np.asarray(self.R, dtype=np.float64).reshape(3, 3)
        self.t = np.asarray(self.t, dtype=np.float64).reshape(3)
        self.distortion = np.asarray(self.distortion, dtype=np.float64).reshape(-1)

    @property
    def fx(self) -> float:
        return float(self.K[0, 0])

    @property
    def fy(self) -> float:
        return float(self.K[1, 1])

    @property
    def cx(self) -> float:
        return float(self.K[0, 2])

    @property
    def cy(self) -> float:
        return float(self.K[1, 2])

    @property
    def translation(self) -> np.ndarray:
        """The extrinsic translation ``-R t`` (OpenCV's ``tvec``), shape (3,)."""
        return -self.R @ self.t

    @property
    def extrinsic(self) -> np.ndarray:
        """``[R | -R t]``, shape (3, 4)."""
        return np.hstack([self.R, self.translation[:, None]])

    @property
    def projection(self) -> np.ndarray:
        """``P = K [R | -R t]``, shape (3, 4)."""
        return self.K @ self.extrinsic

    @property
    def optical_axis(self) -> np.ndarray:
        """The viewing direction in world coordinates, shape (3,)."""
        return self.R[2].copy()

    def __repr__(self) -> str:
        return (
            f"Camera(name={self.name!r}, fx={self.fx:g}, fy={self.fy:g}, cx={self.cx:g}, "
            f"cy={self.cy:g}, t={self.t.tolist()}, size={self.size})"
        )


def same_camera(first: Camera, second: Camera) -> bool:
    """True when the two cameras have exactly the same ``K``, ``R`` and ``t`` (they see
    the same picture, whatever their names)."""
    return (
        np.array_equal(first.K, second.K)
        and np.array_equal(first.R, second.R)
        and np.array_equal(first.t, second.t)
    )


def turn_world(cameras, rotation: np.ndarray) -> list[Camera]:
    """The same cameras described in a world frame turned by ``rotation``.

    New world coordinates are ``X' = rotation @ X``; each camera sees exactly what it saw
    (``R' = R rotation^T``, ``t' = rotation t``), and depth along each camera's axis is
    unchanged. Rectified arrays take their common orientation as the world's, so that
    their rotations are the identity and the baseline lies along x, as the 1D modes of
    the reference programs read it.

    Parameters
    ----------
    cameras : iterable of Camera
    rotation : ndarray, shape (3, 3)
        A rotation (orthonormal, determinant 1).

    Returns
    -------
    list of Camera
    """
    rotation = np.asarray(rotation, dtype=np.float64)
    if (
        rotation.shape != (3, 3)
        or not np.allclose(rotation @ rotation.T, np.eye(3), atol=1e-9)
        or np.linalg.det(rotation) < 0
    ):
        raise ValueError(f"rotation must be a 3x3 rotation matrix, got {rotation.tolist()}")
    turned = []
    for camera in cameras:
        R = camera.R @ rotation.T
        # A camera whose orientation the world takes gets the exact identity that files
        # of rectified arrays show, not one with rounding noise.
        if np.allclose(R, np.eye(3), rtol=0.0, atol=1e-12):
            R = np.eye(3)
        turned.append(replace(camera, R=R, t=rotation @ camera.t))
    return turned
