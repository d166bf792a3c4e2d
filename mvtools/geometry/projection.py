"""Projection of world points into cameras and back, vectorised over whole images.

Pixel ``(u, v)`` is column ``u``, row ``v``; integer coordinates are pixel centres.
A camera point ``x_cam = R (X - t)`` projects to ``K x_cam / z`` with ``z`` its
coordinate along the camera's axis. Lens distortion is ignored, as the MPEG
reference programs do.

A depth map gives each pixel a ``z`` whose meaning is the ``DepthType`` of VSRS and
DERS:

- ``depth_type=0``: ``z`` is measured along the camera's own axis.
- ``depth_type=1``: ``z`` is the world z coordinate of the point; the point is where
  the pixel's ray meets the world plane ``Z = z``. This is the intersection VSRS
  computes, including its sign: when the plane lies behind the camera the point
  lies behind it too (negative depth along the axis).
"""

from __future__ import annotations

import numpy as np

from mvtools.geometry.camera import Camera

__all__ = ["backproject", "depth_along_axis", "pixel_grid", "project", "reproject"]


def pixel_grid(width: int, height: int) -> tuple[np.ndarray, np.ndarray]:
    """Column and row coordinates of every pixel, each float64 of shape (height, width)."""
    if width <= 0 or height <= 0:
        raise ValueError(f"image size must be positive, got {width}x{height}")
    u, v = np.meshgrid(np.arange(width, dtype=np.float64), np.arange(height, dtype=np.float64))
    return u, v


def _affine_rows(matrix: np.ndarray, u: np.ndarray, v: np.ndarray) -> list[np.ndarray]:
    """The three rows of ``matrix @ [u, v, 1]`` as separate arrays (no (..., 3) stack)."""
    return [matrix[i, 0] * u + matrix[i, 1] * v + matrix[i, 2] for i in range(3)]


def _check_depth_type(depth_type: int) -> None:
    if depth_type not in (0, 1):
        raise ValueError(
            f"depth_type must be 0 (along the camera axis) or 1 (world z), got {depth_type!r}"
        )


def project(camera: Camera, points) -> tuple[np.ndarray, np.ndarray]:
    """Project world points into ``camera``.

    Parameters
    ----------
    camera : Camera
    points : array_like, shape (..., 3)
        World coordinates.

    Returns
    -------
    uv : ndarray, shape (..., 2)
        Pixel coordinates (non-finite for points in the camera's centre plane).
    z : ndarray, shape (...)
        Coordinate along the camera's axis; negative behind the camera.
    """
    points = np.asarray(points, dtype=np.float64)
    if points.shape[-1:] != (3,):
        raise ValueError(f"points must have shape (..., 3), got {points.shape}")
    camera_points = (points - camera.t) @ camera.R.T
    homogeneous = camera_points @ camera.K.T
    with np.errstate(divide="ignore", invalid="ignore"):
        uv = homogeneous[..., :2] / homogeneous[..., 2:]
    return uv, camera_points[..., 2]


def depth_along_axis(camera: Camera, u, v, z, *, depth_type: int = 0) -> np.ndarray:
    """The depth along the camera axis of pixels whose depth is given as ``depth_type``.

    Parameters
    ----------
    camera : Camera
    u, v : array_like
        Pixel coordinates, broadcastable with ``z``.
    z : array_like
        Depth per ``depth_type``: positive (``inf`` allowed) for 0, any non-NaN for 1.
    depth_type : {0, 1}

    Returns
    -------
    ndarray
        Depth along the axis, the broadcast shape of ``u, v, z``.
    """
    _check_depth_type(depth_type)
    z = np.asarray(z, dtype=np.float64)
    if depth_type == 0:
        if not np.all(z > 0):
            raise ValueError("depth along the camera axis must be positive (and not NaN)")
        return np.broadcast_to(z, np.broadcast_shapes(np.shape(u), np.shape(v), z.shape))
    if np.any(np.isnan(z)):
        raise ValueError("world z must not be NaN")
    # The ray K^-1 [u, v, 1] has unit depth along the axis; its world z step is
    # (R^T K^-1)[2] . [u, v, 1], so the ray parameter that reaches Z = z is the depth.
    ray_to_world = camera.R.T @ np.linalg.inv(camera.K)
    step = ray_to_world[2, 0] * u + ray_to_world[2, 1] * v + ray_to_world[2, 2]
    with np.errstate(divide="ignore", invalid="ignore"):
        return (z - camera.t[2]) / step


def backproject(camera: Camera, u, v, z, *, depth_type: int = 0) -> np.ndarray:
    """World points of pixels ``(u, v)`` at depth ``z``.

    Parameters
    ----------
    camera : Camera
    u, v, z : array_like
        Broadcastable pixel coordinates and depths (meaning set by ``depth_type``).
    depth_type : {0, 1}
        0: ``z`` along the camera axis; 1: ``z`` is the world z coordinate.

    Returns
    -------
    ndarray, shape (..., 3)
        World coordinates.
    """
    depth = depth_along_axis(camera, u, v, z, depth_type=depth_type)
    rays = _affine_rows(
        camera.R.T @ np.linalg.inv(camera.K), np.asarray(u, np.float64), np.asarray(v, np.float64)
    )
    return np.stack([depth * ray + centre for ray, centre in zip(rays, camera.t)], axis=-1)


def reproject(
    src: Camera, dst: Camera, u, v, z, *, depth_type: int = 0
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Where pixels of ``src`` at depth ``z`` appear in ``dst``.

    Parameters
    ----------
    src, dst : Camera
    u, v, z : array_like
        Broadcastable pixel coordinates in ``src`` and their depths.
    depth_type : {0, 1}
        Meaning of ``z`` (module docstring).

    Returns
    -------
    u2, v2 : ndarray
        Pixel coordinates in ``dst`` (non-finite when undefined).
    z2 : ndarray
        Depth along the axis of ``dst``; negative behind it.
    """
    depth = depth_along_axis(src, u, v, z, depth_type=depth_type)
    # x_dst = R_d (X - C_d) with X = C_s + depth * R_s^T K_s^-1 [u, v, 1]
    to_dst = dst.R @ src.R.T @ np.linalg.inv(src.K)
    offset = dst.R @ (src.t - dst.t)
    with np.errstate(invalid="ignore"):
        rays = _affine_rows(to_dst, np.asarray(u, np.float64), np.asarray(v, np.float64))
        x, y, z2 = (depth * ray + shift for ray, shift in zip(rays, offset))
        k = dst.K
        w = k[2, 0] * x + k[2, 1] * y + k[2, 2] * z2
        with np.errstate(divide="ignore"):
            u2 = (k[0, 0] * x + k[0, 1] * y + k[0, 2] * z2) / w
            v2 = (k[1, 0] * x + k[1, 1] * y + k[1, 2] * z2) / w
    return u2, v2, z2
