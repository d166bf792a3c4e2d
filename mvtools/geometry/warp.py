"""Forward warping of an image with its depth into another camera (z-buffer)."""

from __future__ import annotations

import numpy as np

from mvtools.geometry.camera import Camera
from mvtools.geometry.projection import pixel_grid, reproject

__all__ = ["forward_warp"]


def forward_warp(
    values,
    z,
    src: Camera,
    dst: Camera,
    *,
    depth_type: int = 0,
    out_size: tuple[int, int] | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Splat every source pixel to the nearest target pixel; the nearest surface wins.

    Each pixel of ``src`` is reprojected into ``dst`` and rounded to the nearest pixel
    (half up). Points behind ``dst``, outside the target frame or with undefined
    coordinates are dropped. Where several land on one pixel the smallest depth
    along the ``dst`` axis wins; equal depths go to the first source pixel in
    row-major order, so the result does not depend on the platform.

    Parameters
    ----------
    values : array_like, shape (H, W) or (H, W, C)
        Samples to warp (any dtype; copied as they are).
    z : array_like, shape (H, W)
        Depth of each source pixel, meaning per ``depth_type``.
    src, dst : Camera
    depth_type : {0, 1}
        0: ``z`` along the ``src`` axis; 1: ``z`` is the world z coordinate.
    out_size : (width, height) or None
        Target size; default ``dst.size``, else the source size.

    Returns
    -------
    warped : ndarray, shape (h, w) or (h, w, C), dtype of ``values``
        Zero where nothing landed.
    warped_z : ndarray of float64, shape (h, w)
        Depth along the ``dst`` axis of the winning point, ``inf`` where nothing landed.
    filled : ndarray of bool, shape (h, w)
    """
    values = np.asarray(values)
    z = np.asarray(z, dtype=np.float64)
    if values.ndim not in (2, 3):
        raise ValueError(f"values must have shape (H, W) or (H, W, C), got {values.shape}")
    if z.shape != values.shape[:2]:
        raise ValueError(f"z has shape {z.shape}, values {values.shape}: need the same (H, W)")
    height, width = z.shape
    out_width, out_height = out_size or dst.size or (width, height)
    if out_width <= 0 or out_height <= 0:
        raise ValueError(f"output size must be positive, got {out_width}x{out_height}")

    u, v = pixel_grid(width, height)
    u2, v2, z2 = reproject(src, dst, u, v, z, depth_type=depth_type)
    column = np.floor(u2.ravel() + 0.5)
    row = np.floor(v2.ravel() + 0.5)
    with np.errstate(invalid="ignore"):
        lands = (
            (z2.ravel() > 0)
            & (column >= 0)
            & (column < out_width)
            & (row >= 0)
            & (row < out_height)
        )
    source = np.flatnonzero(lands)
    target = row[source].astype(np.intp) * out_width + column[source].astype(np.intp)
    depth = z2.ravel()[source]

    # lexsort is stable: after sorting by target then depth, equal depths keep the
    # row-major source order, and the first entry of each target is the winner.
    order = np.lexsort((depth, target))
    sorted_target = target[order]
    first = np.ones(sorted_target.size, dtype=bool)
    first[1:] = sorted_target[1:] != sorted_target[:-1]
    winners = order[first]
    target = target[winners]

    channels = values.shape[2:]
    warped = np.zeros((out_height * out_width,) + channels, dtype=values.dtype)
    warped[target] = values.reshape((height * width,) + channels)[source[winners]]
    warped_z = np.full(out_height * out_width, np.inf)
    warped_z[target] = depth[winners]
    filled = np.zeros(out_height * out_width, dtype=bool)
    filled[target] = True
    return (
        warped.reshape((out_height, out_width) + channels),
        warped_z.reshape(out_height, out_width),
        filled.reshape(out_height, out_width),
    )
