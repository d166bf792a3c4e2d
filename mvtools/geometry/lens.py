"""The lens-distortion model and the projection through it.

The model is Brown-Conrady's (D. C. Brown, "Decentering distortion of lenses",
Photogrammetric Engineering 32(3), 1966) as OpenCV uses it: coefficients in the order
``(k1, k2, p1, p2, k3)``, at most five, missing ones zero (MPEG camera files store k1,
k2), applied to normalised camera coordinates ``x = X/Z, y = Y/Z`` with
``r^2 = x^2 + y^2``::

    x_d = x (1 + k1 r^2 + k2 r^4 + k3 r^6) + 2 p1 x y + p2 (r^2 + 2 x^2)
    y_d = y (1 + k1 r^2 + k2 r^4 + k3 r^6) + p1 (r^2 + 2 y^2) + 2 p2 x y

Pixel ``(u, v)`` has its centre at integer coordinates (``u = 0`` is the centre of the
first column), the OpenCV convention, and is ``K [x_d, y_d, 1]``. The inverse is solved
by Newton's method run to convergence, where ``cv2.undistortPoints`` stops after a few
fixed-point steps, so that :func:`pixel_rays` and :func:`project_points` are exact
inverses of each other.
"""

from __future__ import annotations

import numpy as np

from mvtools.geometry.camera import Camera

__all__ = ["distort_normalized", "pixel_rays", "project_points", "undistort_normalized"]


def _coefficients(distortion) -> np.ndarray:
    """``(k1, k2, p1, p2, k3)`` from a shorter or equal array, missing ones zero."""
    coefficients = np.asarray(distortion, dtype=np.float64).reshape(-1)
    if coefficients.size > 5:
        raise ValueError(
            f"distortion has {coefficients.size} coefficients; at most 5 "
            "(k1, k2, p1, p2, k3) are supported"
        )
    return np.pad(coefficients, (0, 5 - coefficients.size))


def _brown_conrady(x, y, k1, k2, p1, p2, k3):
    """The model's distorted point with ``r^2`` and the radial factor it was made from."""
    r2 = x * x + y * y
    radial = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3))
    xd = x * radial + 2.0 * p1 * x * y + p2 * (r2 + 2.0 * x * x)
    yd = y * radial + p1 * (r2 + 2.0 * y * y) + 2.0 * p2 * x * y
    return xd, yd, r2, radial


def distort_normalized(x: np.ndarray, y: np.ndarray, distortion) -> tuple[np.ndarray, np.ndarray]:
    """Apply the Brown-Conrady model (OpenCV order k1, k2, p1, p2, k3).

    Parameters
    ----------
    x, y : ndarray, same shape
        Undistorted normalised image coordinates ``X/Z, Y/Z``.
    distortion : array_like, shape (<= 5,)
        Coefficients; missing ones are zero.

    Returns
    -------
    xd, yd : ndarray, same shape as ``x``
    """
    x = np.asarray(x, dtype=np.float64)
    y = np.asarray(y, dtype=np.float64)
    xd, yd, _, _ = _brown_conrady(x, y, *_coefficients(distortion))
    return xd, yd


def undistort_normalized(
    xd: np.ndarray,
    yd: np.ndarray,
    distortion,
    *,
    tolerance: float = 1e-14,
    max_iterations: int = 50,
) -> tuple[np.ndarray, np.ndarray]:
    """Invert :func:`distort_normalized` by Newton's method, to convergence.

    Parameters
    ----------
    xd, yd : ndarray, same shape
        Distorted normalised coordinates.
    distortion : array_like, shape (<= 5,)
    tolerance : float
        Largest accepted residual ``|distort(x, y) - (xd, yd)|`` (normalised units).
    max_iterations : int

    Returns
    -------
    x, y : ndarray, same shape as ``xd``

    Raises
    ------
    ValueError
        If some point has no preimage on the monotonic branch of the model
        (strong distortion beyond its fold, e.g. far image corners).
    """
    coefficients = _coefficients(distortion)
    xd = np.asarray(xd, dtype=np.float64)
    yd = np.asarray(yd, dtype=np.float64)
    if not np.any(coefficients):
        return xd.copy(), yd.copy()
    k1, k2, p1, p2, k3 = coefficients
    x, y = xd.copy(), yd.copy()
    for _ in range(max_iterations):
        model_x, model_y, r2, radial = _brown_conrady(x, y, k1, k2, p1, p2, k3)
        slope = k1 + r2 * (2.0 * k2 + 3.0 * k3 * r2)  # d radial / d r2
        ex = model_x - xd
        ey = model_y - yd
        jxx = radial + 2.0 * x * x * slope + 2.0 * p1 * y + 6.0 * p2 * x
        jyy = radial + 2.0 * y * y * slope + 6.0 * p1 * y + 2.0 * p2 * x
        jxy = 2.0 * x * y * slope + 2.0 * p1 * x + 2.0 * p2 * y
        det = jxx * jyy - jxy * jxy
        if x.size == 0 or max(np.max(np.abs(ex)), np.max(np.abs(ey))) <= tolerance:
            # A root past the fold of the lens model (where the distorted radius
            # stops growing with the true one) is no ray the lens can image.
            if np.all(radial > 0) and np.all(radial + 2.0 * r2 * slope > 0) and np.all(det > 0):
                return x, y
            break
        with np.errstate(divide="ignore", invalid="ignore"):
            x, y = x - (jyy * ex - jxy * ey) / det, y - (jxx * ey - jxy * ex) / det
    raise ValueError(
        f"lens distortion {coefficients.tolist()} is not invertible over these "
        f"points (no solution before the fold within {max_iterations} Newton steps)"
    )


def project_points(camera: Camera, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Project world points into ``camera`` through its lens distortion.

    Parameters
    ----------
    camera : Camera
    points : ndarray, shape (N, 3)
        World coordinates.

    Returns
    -------
    uv : ndarray, shape (N, 2)
        Pixel coordinates (pixel centres at integers).
    z : ndarray, shape (N,)
        Depth along the camera axis; points with ``z <= 0`` are behind the camera
        and their ``uv`` is meaningless.
    """
    cam = (np.asarray(points, dtype=np.float64).reshape(-1, 3) - camera.t) @ camera.R.T
    z = cam[:, 2]
    with np.errstate(divide="ignore", invalid="ignore"):
        xd, yd = distort_normalized(cam[:, 0] / z, cam[:, 1] / z, camera.distortion)
    homogeneous = np.stack([xd, yd, np.ones_like(xd)], axis=-1) @ camera.K.T
    return homogeneous[:, :2], z


def pixel_rays(camera: Camera, u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """World directions of the rays through pixel positions ``(u, v)``.

    Parameters
    ----------
    camera : Camera
    u, v : ndarray, shape (N,)
        Pixel coordinates in the (distorted) image.

    Returns
    -------
    ndarray, shape (N, 3)
        Directions from ``camera.t`` whose camera-z component is 1, so that the
        point at ray parameter ``s`` has depth ``s`` along the camera axis.
    """
    K = camera.K
    yd = (np.asarray(v, dtype=np.float64) - K[1, 2]) / K[1, 1]
    xd = (np.asarray(u, dtype=np.float64) - K[0, 2] - K[0, 1] * yd) / K[0, 0]
    x, y = undistort_normalized(xd, yd, camera.distortion)
    return np.stack([x, y, np.ones_like(x)], axis=-1) @ camera.R
