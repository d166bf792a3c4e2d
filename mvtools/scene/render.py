"""Exact ray casting of a :class:`~mvtools.scene.content.Scene` into a camera.

Pixel ``(u, v)`` has its centre at integer coordinates (``u = 0`` is the centre of
the first column), the OpenCV convention. The ray of a pixel goes through the
*distorted* image point: the normalised coordinate is undistorted iteratively
(Newton's method run to convergence, where
``cv2.undistortPoints`` stops after a few fixed-point steps) before it is turned into a
direction, so a rendered image shows the lens distortion of the camera and the
projection of a point with :func:`project_points` lands where it is drawn.

Ray directions are scaled so that their camera-z component is 1: the ray
parameter of a hit *is* its depth along the camera axis (DepthType 0).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mvtools.geometry.camera import Camera
from mvtools.scene.content import Scene

# Rays cast per batch: bounds memory (a few arrays of (N, 3) float64) at ~100 MB.
_BATCH = 1 << 18


# --------------------------------------------------------------------------- lens model


def _coefficients(distortion) -> np.ndarray:
    coefficients = np.asarray(distortion, dtype=np.float64).reshape(-1)
    if coefficients.size > 5:
        raise ValueError(
            f"distortion has {coefficients.size} coefficients; at most 5 "
            "(k1, k2, p1, p2, k3) are supported"
        )
    return np.pad(coefficients, (0, 5 - coefficients.size))


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
    k1, k2, p1, p2, k3 = _coefficients(distortion)
    x = np.asarray(x, dtype=np.float64)
    y = np.asarray(y, dtype=np.float64)
    r2 = x * x + y * y
    radial = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3))
    xd = x * radial + 2.0 * p1 * x * y + p2 * (r2 + 2.0 * x * x)
    yd = y * radial + p1 * (r2 + 2.0 * y * y) + 2.0 * p2 * x * y
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
        r2 = x * x + y * y
        radial = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3))
        slope = k1 + r2 * (2.0 * k2 + 3.0 * k3 * r2)  # d radial / d r2
        ex = x * radial + 2.0 * p1 * x * y + p2 * (r2 + 2.0 * x * x) - xd
        ey = y * radial + p1 * (r2 + 2.0 * y * y) + 2.0 * p2 * x * y - yd
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


# --------------------------------------------------------------------------- rendering


@dataclass(eq=False)
class Rendering:
    """One rendered view with its exact ground truth.

    Attributes
    ----------
    color : ndarray, shape (H, W, 3), float64
        RGB in [0, 1], box-filtered over the pixel area.
    depth : ndarray, shape (H, W), float64
        Depth along the camera axis of the surface hit by the pixel-centre ray
        (DepthType 0), inf where the ray hits nothing.
    world_z : ndarray, shape (H, W), float64
        World z coordinate of the same point (DepthType 1).
    object_index : ndarray, shape (H, W), int16
        Index in ``scene.primitives`` of that surface, -1 for none.
    """

    color: np.ndarray
    depth: np.ndarray
    world_z: np.ndarray
    object_index: np.ndarray


def _trace(scene: Scene, origin: np.ndarray, directions: np.ndarray):
    origins = np.broadcast_to(origin, directions.shape)
    if not scene.primitives:
        return np.full(len(directions), np.inf), np.full(len(directions), -1)
    hits = np.stack([p.intersect(origins, directions) for p in scene.primitives])
    index = np.argmin(hits, axis=0)
    t = np.take_along_axis(hits, index[None], axis=0)[0]
    return t, np.where(np.isfinite(t), index, -1)


def _shade(scene: Scene, origin, directions, t, index) -> np.ndarray:
    colors = np.zeros((len(t), 3))
    for k, primitive in enumerate(scene.primitives):
        hit = index == k
        if not np.any(hit):
            continue
        points = origin + t[hit, None] * directions[hit]
        normals, uv = primitive.surface(points)
        colors[hit] = primitive.texture(uv[:, 0], uv[:, 1]) * scene.shading(normals)[:, None]
    return colors


def _cast(scene: Scene, camera: Camera, u: np.ndarray, v: np.ndarray, *, batch: int = _BATCH):
    """Colour, ray parameter (= depth), primitive index and world z for each ray."""
    n = u.size
    colors = np.empty((n, 3))
    depth = np.empty(n)
    world_z = np.empty(n)
    index = np.empty(n, dtype=np.int16)
    for start in range(0, n, batch):
        part = slice(start, start + batch)
        directions = pixel_rays(camera, u[part], v[part])
        t, hit = _trace(scene, camera.t, directions)
        colors[part] = _shade(scene, camera.t, directions, t, hit)
        depth[part] = t
        world_z[part] = camera.t[2] + t * directions[:, 2]
        index[part] = hit
    return colors, depth, world_z, index


def render(
    scene: Scene,
    camera: Camera,
    *,
    frame: int = 0,
    samples: int = 4,
    adaptive_tolerance: float | None = None,
    size: tuple[int, int] | None = None,
) -> Rendering:
    """Ray-cast one view of ``scene`` at ``frame``.

    Parameters
    ----------
    scene : Scene
    camera : Camera
        Pose, intrinsics and lens distortion of the view.
    frame : int
        Time step; moving primitives are translated by ``frame * velocity``.
    samples : int
        Colour is the mean of ``samples x samples`` rays on a regular sub-pixel
        grid (box filter over the pixel). Depth always comes from the single
        pixel-centre ray.
    adaptive_tolerance : float or None
        None supersamples every pixel. A number first casts rays through the
        pixel corners and supersamples only pixels whose four corner colours
        differ by more than this or hit different primitives, and their eight
        neighbours; the others get the corner mean. Exact for piecewise-constant
        content with features larger than a pixel (the calibration board),
        approximate for textures.
    size : (width, height) or None
        Image size; defaults to ``camera.size``.

    Returns
    -------
    Rendering
    """
    width, height = _image_size(camera, size)
    if samples < 1:
        raise ValueError(f"samples must be >= 1, got {samples}")
    scene = scene.at_frame(frame)
    v, u = np.mgrid[0:height, 0:width].astype(np.float64)
    centre_color, depth, world_z, index = _cast(scene, camera, u.ravel(), v.ravel())
    shape = (height, width)
    if samples == 1:
        color = centre_color
    else:
        color = np.empty((height * width, 3))
        if adaptive_tolerance is None:
            refine = np.arange(height * width)
        else:
            refine = _pixels_to_refine(scene, camera, width, height, adaptive_tolerance, color)
        color[refine] = _supersample(scene, camera, refine % width, refine // width, samples)
    return Rendering(
        color=color.reshape(height, width, 3),
        depth=depth.reshape(shape),
        world_z=world_z.reshape(shape),
        object_index=index.reshape(shape),
    )


def _image_size(camera: Camera, size) -> tuple[int, int]:
    if size is None:
        size = camera.size
    if size is None:
        raise ValueError(f"camera {camera.name!r} has no size; pass size=(width, height)")
    width, height = (int(s) for s in size)
    if width < 1 or height < 1:
        raise ValueError(f"image size must be positive, got {width}x{height}")
    return width, height


def _pixels_to_refine(scene, camera, width, height, tolerance, color) -> np.ndarray:
    """Flat indices of pixels whose corners disagree; fills ``color`` of the others."""
    v, u = np.mgrid[0 : height + 1, 0 : width + 1].astype(np.float64) - 0.5
    corner_color, _, _, corner_index = _cast(scene, camera, u.ravel(), v.ravel())
    corner_color = corner_color.reshape(height + 1, width + 1, 3)
    corner_index = corner_index.reshape(height + 1, width + 1)
    quads = [
        (slice(0, -1), slice(0, -1)),
        (slice(0, -1), slice(1, None)),
        (slice(1, None), slice(0, -1)),
        (slice(1, None), slice(1, None)),
    ]
    colors = np.stack([corner_color[q] for q in quads])
    indices = np.stack([corner_index[q] for q in quads])
    spread = np.max(colors.max(axis=0) - colors.min(axis=0), axis=-1)
    refine = (spread > tolerance) | np.any(indices != indices[0], axis=0)
    # A feature can poke into a pixel between its corners (the tip of a square);
    # its edges then cross a neighbouring pixel, so refine the neighbours too.
    padded = np.pad(refine, 1)
    refine = np.zeros_like(refine)
    for dy in range(3):
        for dx in range(3):
            refine |= padded[dy : dy + height, dx : dx + width]
    color[:] = colors.mean(axis=0).reshape(-1, 3)
    return np.flatnonzero(refine.ravel())


def _supersample(scene, camera, u, v, samples) -> np.ndarray:
    """Box-filtered colour of pixels ``(u, v)`` (each shape (M,)) from samples^2 rays each."""
    offsets = (np.arange(samples) + 0.5) / samples - 0.5
    du, dv = np.meshgrid(offsets, offsets)
    per_pixel = samples * samples
    out = np.empty((u.size, 3))
    pixels_per_batch = max(1, _BATCH // per_pixel)
    for start in range(0, u.size, pixels_per_batch):
        part = slice(start, start + pixels_per_batch)
        su = (u[part, None] + du.ravel()).ravel()
        sv = (v[part, None] + dv.ravel()).ravel()
        colors = _cast(scene, camera, su, sv)[0]
        out[part] = colors.reshape(-1, per_pixel, 3).mean(axis=1)
    return out


def quantize(image: np.ndarray, *, bits: int = 8) -> np.ndarray:
    """Round a [0, 1] float image to unsigned integers (uint8 for 8 bits, else uint16)."""
    if not 1 <= bits <= 16:
        raise ValueError(f"bits must be in 1..16, got {bits}")
    max_value = (1 << bits) - 1
    dtype = np.uint8 if bits <= 8 else np.uint16
    return np.rint(np.clip(image, 0.0, 1.0) * max_value).astype(dtype)
