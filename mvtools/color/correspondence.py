"""Samples of two views that show the same scene point, for colour tables.

Only pixels that project onto each other and are visible in both count: the depth at
which the target pixel's point lands in the other view must agree with that view's own
depth there (else something in front hides it), and pixels at depth edges, which mix
two surfaces, are left out.
"""

from __future__ import annotations

from dataclasses import replace

import cv2
import numpy as np

from mvtools.geometry.camera import Camera
from mvtools.geometry.projection import pixel_grid, reproject
from mvtools.metrics import psnr

__all__ = [
    "common_view",
    "common_view_samples",
    "corresponding_samples",
    "disparity_samples",
    "overlap_samples",
    "warp_to_target",
    "warped_psnr",
]


def _smooth_depth(z: np.ndarray, tolerance: float) -> np.ndarray:
    """Pixels whose 3x3 neighbourhood lies within ``tolerance`` (relative) of them."""
    z = np.asarray(z, dtype=np.float32)
    kernel = np.ones((3, 3), np.uint8)
    spread = cv2.dilate(z, kernel) - cv2.erode(z, kernel)
    with np.errstate(invalid="ignore"):
        return np.isfinite(z) & (z > 0) & (spread <= tolerance * z)


def _check_pair(view, view_z, target, target_z, tolerance, depth_type):
    view, target = np.asarray(view), np.asarray(target)
    for name, image, z in (("view", view, view_z), ("target", target, target_z)):
        if np.shape(z) != image.shape[:2]:
            raise ValueError(f"{name}_z has shape {np.shape(z)}, the {name} {image.shape[:2]}")
    if view.ndim != target.ndim or view.shape[2:] != target.shape[2:]:
        raise ValueError(
            f"view and target must have the same channels, got {view.shape} and {target.shape}"
        )
    if not tolerance > 0:
        raise ValueError(f"tolerance must be positive, got {tolerance}")
    if depth_type != 0:
        raise ValueError("only depth along each camera's axis (DepthType 0) is supported")
    return view, target


def _visible_matches(
    view_shape, view_camera, view_z, target_shape, target_camera, target_z, tolerance
):
    """Target pixels (flat indices) at smooth depths whose points ``view`` sees, and
    where in ``view`` they land (fractional ``u, v``)."""
    height, width = view_shape
    trusted = np.flatnonzero(_smooth_depth(target_z, tolerance))
    u, v = pixel_grid(target_shape[1], target_shape[0])
    u, v = u.ravel()[trusted], v.ravel()[trusted]
    z = np.asarray(target_z, np.float64).ravel()[trusted]
    u2, v2, z2 = reproject(target_camera, view_camera, u, v, z)
    column, row = np.round(u2), np.round(v2)
    with np.errstate(invalid="ignore"):
        inside = (z2 > 0) & (column >= 0) & (column <= width - 1) & (row >= 0) & (row <= height - 1)
    column, row = column[inside].astype(np.intp), row[inside].astype(np.intp)
    seen = np.asarray(view_z, np.float64)[row, column]
    visible = _smooth_depth(view_z, tolerance)[row, column] & (
        np.abs(seen - z2[inside]) <= tolerance * z2[inside]
    )
    return trusted[inside][visible], u2[inside][visible], v2[inside][visible]


def corresponding_samples(
    view: np.ndarray,
    view_camera: Camera,
    view_z: np.ndarray,
    target: np.ndarray,
    target_camera: Camera,
    target_z: np.ndarray,
    *,
    tolerance: float = 0.01,
    depth_type: int = 0,
) -> tuple[np.ndarray, np.ndarray]:
    """Codes of ``view`` and ``target`` at the scene points both see.

    Every target pixel at a smooth depth is carried into ``view`` by the cameras; it
    counts when it lands inside, on a smooth depth of ``view`` within ``tolerance`` of
    its own. ``view`` is sampled at the nearest pixel, so that its codes stay codes;
    ``target`` gives its own pixel.

    Parameters
    ----------
    view, target : ndarray, shape (H, W, C) or (H, W), integer codes
        The two pictures (any sizes), in the same colour space.
    view_camera, target_camera : Camera
    view_z, target_z : ndarray, shape (H, W) of the picture
        Depth of every pixel (metres, ``inf`` or 0 for none).
    tolerance : keyword-only float
        Relative depth agreement that counts as the same surface.
    depth_type : keyword-only {0}
        Depth along each camera's own axis, the only kind supported.

    Returns
    -------
    view_codes, target_codes : ndarray, shape (N, C)
    """
    view, target = _check_pair(view, view_z, target, target_z, tolerance, depth_type)
    pixels, u, v = _visible_matches(
        view.shape[:2], view_camera, view_z, target.shape[:2], target_camera, target_z, tolerance
    )
    channels = 1 if view.ndim == 2 else view.shape[2]
    view_pixels = view[np.round(v).astype(np.intp), np.round(u).astype(np.intp)]
    return (view_pixels.reshape(-1, channels), target.reshape(-1, channels)[pixels])


def warp_to_target(
    view: np.ndarray,
    view_camera: Camera,
    view_z: np.ndarray,
    target_shape: tuple[int, int],
    target_camera: Camera,
    target_z: np.ndarray,
    *,
    tolerance: float = 0.01,
) -> tuple[np.ndarray, np.ndarray]:
    """``view`` as the target camera sees it, where the target sees what ``view`` sees.

    The target pixels of :func:`corresponding_samples` take ``view`` interpolated
    bilinearly at their positions in it, so that a comparison with the target
    measures colour, not resampling.

    Parameters
    ----------
    view : ndarray, shape (H, W, C) or (H, W)
    view_camera, target_camera : Camera
    view_z : ndarray, shape (H, W)
    target_shape : (rows, columns)
    target_z : ndarray, shape ``target_shape``
    tolerance : keyword-only float

    Returns
    -------
    warped : ndarray of float32, shape ``target_shape`` (+ channels), NaN where not seen
    seen : ndarray of bool, shape ``target_shape``
    """
    view = np.asarray(view)
    if np.shape(view_z) != view.shape[:2] or np.shape(target_z) != tuple(target_shape):
        raise ValueError("depth maps must have their pictures' shapes")
    pixels, u, v = _visible_matches(
        view.shape[:2], view_camera, view_z, tuple(target_shape), target_camera, target_z, tolerance
    )
    channels = 1 if view.ndim == 2 else view.shape[2]
    warped = np.full((int(np.prod(target_shape)), channels), np.nan, np.float32)
    if len(pixels):  # OpenCV refuses empty maps
        warped[pixels] = cv2.remap(
            np.asarray(view, np.float32),
            u.astype(np.float32)[:, None],
            v.astype(np.float32)[:, None],
            interpolation=cv2.INTER_LINEAR,
            borderMode=cv2.BORDER_REPLICATE,
        ).reshape(-1, channels)
    seen = np.zeros(int(np.prod(target_shape)), bool)
    seen[pixels] = True
    shape = tuple(target_shape) + ((channels,) if view.ndim == 3 else ())
    return warped.reshape(shape), seen.reshape(target_shape)


def warped_psnr(
    view: np.ndarray,
    view_camera: Camera,
    view_z: np.ndarray,
    target: np.ndarray,
    target_camera: Camera,
    target_z: np.ndarray,
    *,
    max_value: float,
    tolerance: float = 0.01,
) -> float:
    """PSNR (dB) of a plane of ``view`` warped into the target camera
    (:func:`warp_to_target`) against ``target``, over the pixels where the target sees
    what ``view`` sees: how far the colours of two views agree, resampling aside.

    Parameters
    ----------
    view, target : ndarray, shape (H, W)
        One plane of each picture (any sizes).
    view_camera, target_camera : Camera
    view_z, target_z : ndarray, shapes of the planes
    max_value : keyword-only float
        Peak value, ``2**bits - 1``.
    tolerance : keyword-only float

    Raises
    ------
    ValueError
        No target pixel sees what ``view`` sees.
    """
    target = np.asarray(target)
    warped, seen = warp_to_target(
        view, view_camera, view_z, target.shape, target_camera, target_z, tolerance=tolerance
    )
    if not seen.any():
        raise ValueError(
            f"camera {target_camera.name!r} sees none of the points of camera "
            f"{view_camera.name!r} at the depths given"
        )
    return psnr(target, np.nan_to_num(warped), max_value=max_value, mask=seen)


def disparity_samples(
    view: np.ndarray,
    target: np.ndarray,
    target_disparity: np.ndarray,
    *,
    view_is_right: bool = True,
) -> tuple[np.ndarray, np.ndarray]:
    """Codes of the two views of a rectified pair at the pixels a disparity map pairs.

    Parameters
    ----------
    view, target : ndarray, shape (H, W, C) or (H, W), integer codes
    target_disparity : ndarray, shape (H, W)
        Disparity of the target's pixels (``x_view = x - d`` when the view is the
        right one, ``x + d`` when it is the left one); non-finite or negative where
        unknown. Pixels at disparity steps are left out.
    view_is_right : keyword-only bool

    Returns
    -------
    view_codes, target_codes : ndarray, shape (N, C)
    """
    view, target = np.asarray(view), np.asarray(target)
    disparity = np.asarray(target_disparity, dtype=np.float32)
    if view.shape != target.shape or disparity.shape != target.shape[:2]:
        raise ValueError(
            f"view {view.shape}, target {target.shape} and disparity "
            f"{disparity.shape} must share one picture size"
        )
    known = np.isfinite(disparity) & (disparity >= 0)
    filled = np.where(known, disparity, 0).astype(np.float32)
    kernel = np.ones((3, 3), np.uint8)
    smooth = known & (cv2.dilate(filled, kernel) - cv2.erode(filled, kernel) <= 1.0)
    rows, columns = np.nonzero(smooth)
    shift = -1.0 if view_is_right else 1.0
    other = np.round(columns + shift * disparity[rows, columns]).astype(np.intp)
    inside = (other >= 0) & (other < view.shape[1])
    channels = 1 if view.ndim == 2 else view.shape[2]
    return (
        view[rows[inside], other[inside]].reshape(-1, channels),
        target[rows[inside], columns[inside]].reshape(-1, channels),
    )


def common_view(camera: Camera, other: Camera, shape: tuple[int, int], z: float) -> np.ndarray:
    """Pixels of ``camera``'s picture that ``other`` also sees, for scene points at depth
    ``z`` along ``camera``'s axis: the overlapping field of view over which histograms
    of the two views are comparable when no depth map tells where each point is.

    Parameters
    ----------
    camera, other : Camera
        ``other.size`` gives its picture size.
    shape : (rows, columns)
        Size of ``camera``'s picture.
    z : float
        A depth typical of the scene (e.g. the harmonic mean of Znear and Zfar).

    Returns
    -------
    ndarray of bool, shape ``shape``
    """
    if other.size is None:
        raise ValueError(f"camera {other.name!r} needs its picture size")
    if not z > 0:
        raise ValueError(f"z must be positive, got {z}")
    u, v = pixel_grid(shape[1], shape[0])
    u2, v2, z2 = reproject(camera, other, u, v, np.full(u.shape, float(z)))
    width, height = other.size
    with np.errstate(invalid="ignore"):
        return (z2 > 0) & (u2 >= -0.5) & (u2 <= width - 0.5) & (v2 >= -0.5) & (v2 <= height - 0.5)


def common_view_samples(
    view: np.ndarray,
    view_camera: Camera,
    target: np.ndarray,
    target_camera: Camera,
    *,
    depth_range: tuple[float, float],
) -> tuple[np.ndarray, np.ndarray]:
    """Samples of two views over the field of view they share, when no depth map tells
    where each point is: the pixels of ``view`` that ``target_camera`` sees and those of
    ``target`` that ``view_camera`` sees, for scene points at the harmonic mean of Znear
    and Zfar (the middle of the range in inverse depth).

    Parameters
    ----------
    view, target : ndarray, shape (H, W, C)
        Pictures of one size; the cameras take it as theirs.
    view_camera, target_camera : Camera
    depth_range : (znear, zfar)
        Either sign, the cameras facing it
        (:func:`mvtools.geometry.depth.facing_camera`): the points lie at the positive
        depth of that magnitude.

    Returns
    -------
    view_samples, target_samples : ndarray, shapes (N, C) and (M, C)
    """
    znear, zfar = depth_range
    z = 2.0 / abs(1.0 / znear + 1.0 / zfar)
    size = (view.shape[1], view.shape[0])
    seen = common_view(view_camera, replace(target_camera, size=size), view.shape[:2], z)
    seen_back = common_view(target_camera, replace(view_camera, size=size), target.shape[:2], z)
    return view[seen], target[seen_back]


def overlap_samples(image: np.ndarray, *, columns: tuple[int, int] | None = None) -> np.ndarray:
    """All pixels of ``image`` as (N, C) samples, optionally only the columns
    ``start <= x < stop`` (the part of a rectified view its neighbour also sees)."""
    image = np.asarray(image)
    if columns is not None:
        start, stop = columns
        if not 0 <= start < stop <= image.shape[1]:
            raise ValueError(f"columns {columns} are not a range inside width {image.shape[1]}")
        image = image[:, start:stop]
    channels = 1 if image.ndim == 2 else image.shape[2]
    return image.reshape(-1, channels)
