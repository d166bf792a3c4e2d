"""Exact ray casting of a :class:`~mvtools.scene.content.Scene` into a camera.

The ray of a pixel goes through the *distorted* image point
(:func:`mvtools.geometry.lens.pixel_rays`, pixel centres at integers), so a rendered image
shows the lens distortion of the camera and the projection of a point with
:func:`mvtools.geometry.lens.project_points` lands where it is drawn.

Ray directions are scaled so that their camera-z component is 1: the ray
parameter of a hit *is* its depth along the camera axis (DepthType 0).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mvtools.geometry.camera import Camera
from mvtools.geometry.lens import pixel_rays
from mvtools.scene.content import Scene

# Rays cast per batch: bounds memory (a few arrays of (N, 3) float64) at ~100 MB.
_BATCH = 1 << 18


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
