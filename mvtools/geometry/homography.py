"""Homographies induced by planes of constant depth (plane sweeping, DERS matching)."""

from __future__ import annotations

import numpy as np

from mvtools.geometry.camera import Camera

__all__ = ["plane_homography"]


def plane_homography(src: Camera, dst: Camera, z, *, depth_type: int = 0) -> np.ndarray:
    """Homographies mapping ``src`` pixels on a plane of constant depth to ``dst`` pixels.

    For the plane ``n^T x = d`` in ``src`` camera coordinates,
    ``H = K_dst (R_rel + t_rel n^T / d) K_src^-1`` with ``R_rel = R_dst R_src^T`` and
    ``t_rel = R_dst (t_src - t_dst)``; ``[u2, v2, 1] ~ H [u, v, 1]``.

    Parameters
    ----------
    src, dst : Camera
    z : float or array_like, shape (...)
        The planes. ``depth_type=0``: fronto-parallel planes at depth ``z > 0`` along the
        ``src`` axis (``n = (0, 0, 1)``, ``d = z``). ``depth_type=1``: world planes
        ``Z = z``, which must not contain the ``src`` camera centre.
    depth_type : {0, 1}

    Returns
    -------
    ndarray, shape (..., 3, 3)
    """
    z = np.asarray(z, dtype=np.float64)
    if depth_type == 0:
        if not np.all((z > 0) & np.isfinite(z)):
            raise ValueError("plane depth along the camera axis must be positive and finite")
        normal, distance = np.array([0.0, 0.0, 1.0]), z
    elif depth_type == 1:
        distance = z - src.t[2]
        if not np.all(np.isfinite(distance) & (distance != 0)):
            raise ValueError(
                "world plane Z = z must be finite and not pass through the "
                f"source camera centre (Z = {src.t[2]})"
            )
        # (R^T x)_z + t_z = z  <=>  R[:, 2] . x = z - t_z
        normal = src.R[:, 2]
    else:
        raise ValueError(f"depth_type must be 0 or 1, got {depth_type!r}")
    src_inverse = np.linalg.inv(src.K)
    rotation = dst.K @ dst.R @ src.R.T @ src_inverse
    translation = dst.K @ dst.R @ (src.t - dst.t)
    plane = normal @ src_inverse
    return rotation + np.outer(translation, plane) / distance[..., None, None]
