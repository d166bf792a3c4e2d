"""Merging warped views: distance weights and depth-aware blending.

Two warped views of one virtual pixel either show the same surface (their depths
agree) and are blended with the distance weights of the chapter's eq. 1.20, or show
different surfaces, and then the nearer one is the visible one. Depths are
compared in inverse depth, the quantity depth maps are linear in, with the
tolerance ``DepthBlendDifference`` given in 8-bit depth-value units of ONE common
range ``(znear, zfar)``: VSRS re-quantises each warped depth with its own view's
range, so its comparison goes wrong when the two ranges differ.
"""

from __future__ import annotations

from collections.abc import Sequence

import numba
import numpy as np

from mvtools.geometry.camera import Camera
from mvtools.geometry.depth import inverse_depth_step
from mvtools.synthesis.views import WarpedView

__all__ = ["at_virtual_camera", "merge_views", "view_weights"]


def view_weights(virtual_camera: Camera, reference_cameras: Sequence[Camera]) -> np.ndarray:
    """Blending weight of each reference view (the chapter's eq. 1.20).

    For two views ``w_left = |t_v - t_right| / (|t_v - t_left| + |t_v - t_right|)``:
    the nearer camera weighs more; these are the normalised inverse distances
    ``(1 / d_i) / sum_j (1 / d_j)``. With more views only the two nearest (and any
    as near as the second) are weighted so; the others get 0, and
    :func:`merge_views` uses them only where the weighted views see nothing (on the
    synthetic scene blending in a view twice as far away, even at a small weight,
    costs about 1 dB). A reference at the virtual camera's position takes all the
    weight (shared equally when several coincide).

    Parameters
    ----------
    virtual_camera : Camera
    reference_cameras : sequence of Camera, length N >= 1

    Returns
    -------
    ndarray of float64, shape (N,)
        Non-negative, summing to 1.
    """
    distances = _distances(virtual_camera, reference_cameras)
    coincident = at_virtual_camera(virtual_camera, reference_cameras)
    if coincident.any():
        return coincident / np.count_nonzero(coincident)
    nearest = distances <= np.sort(distances)[min(1, len(distances) - 1)]
    inverse = np.where(nearest, 1.0 / distances, 0.0)
    return inverse / inverse.sum()


def at_virtual_camera(virtual_camera: Camera, reference_cameras: Sequence[Camera]) -> np.ndarray:
    """Which references sit at the virtual camera's centre, bool array of shape (N,).

    Camera files print centres with a few decimals: "the same place" allows a
    relative 1e-9 of the largest distance.
    """
    distances = _distances(virtual_camera, reference_cameras)
    return distances <= 1e-9 * max(distances.max(), 1.0)


def _distances(virtual_camera: Camera, reference_cameras: Sequence[Camera]) -> np.ndarray:
    if len(reference_cameras) == 0:
        raise ValueError("need at least one reference camera")
    distances = np.array(
        [np.linalg.norm(camera.t - virtual_camera.t) for camera in reference_cameras]
    )
    if not np.all(np.isfinite(distances)):
        raise ValueError("camera centres must be finite")
    return distances


def merge_views(
    warped: Sequence[WarpedView],
    weights,
    *,
    view_blending: bool = False,
    depth_blend_difference: float = 5.0,
    depth_range: tuple[float, float],
    overwrite: bool = False,
) -> WarpedView:
    """Merge N views warped into the same virtual camera.

    Blending (``view_blending=False``, VSRS ``ViewBlending 0``): at each pixel the
    nearest surface any view shows wins; every view whose depth lies within
    ``depth_blend_difference`` of it (strictly less, 8-bit depth-value units of
    ``depth_range``) sees that same surface and is blended with its weight; the
    others are hidden behind it. Views that hold nothing at a pixel (``z = inf``)
    do not take part there, so holes of one view are filled from the others.
    Zero-weight views (with :func:`view_weights`: references beyond the two
    nearest, or all others when one sits at the virtual camera) only fill what the
    weighted views do not see, blended among themselves with equal weights.

    ``view_blending=True`` (``ViewBlending 1``): each pixel comes from the view with
    the largest weight (the nearest camera; the first in ``warped`` order on ties)
    where it holds something, else from the next one, and so on.

    The merged depth is that of the view taken (``view_blending``) or the nearest of
    the blended ones.

    Parameters
    ----------
    warped : sequence of WarpedView, length N >= 1
        Images (H, W, 3) float32 and depths (H, W) along the virtual camera's axis.
    weights : array_like, shape (N,)
        Non-negative, not all zero, e.g. :func:`view_weights`.
    view_blending : bool
    depth_blend_difference : float
        Tolerance, >= 0, in depth-value units of the 8-bit map of ``depth_range``.
    depth_range : (znear, zfar)
        The common range the tolerance refers to.
    overwrite : bool
        The merged view may be written into the arrays of the views (C-contiguous
        float32 colour, float64 depth), which are then undefined; saves the memory
        of a merged view.

    Returns
    -------
    WarpedView
        ``z = inf`` where no view holds anything.
    """
    if len(warped) == 0:
        raise ValueError("need at least one warped view")
    weights = np.asarray(weights, dtype=np.float64)
    if weights.shape != (len(warped),) or not (np.all(weights >= 0) and weights.sum() > 0):
        raise ValueError(f"need {len(warped)} non-negative weights, not all zero, got {weights}")
    if not depth_blend_difference >= 0:
        raise ValueError(f"depth_blend_difference must be >= 0, got {depth_blend_difference}")
    shape = warped[0].z.shape
    for view in warped:
        if view.z.shape != shape or view.color.shape != shape + (3,):
            raise ValueError(
                f"warped views differ in size: depth {view.z.shape}, colour "
                f"{view.color.shape}, first depth {shape}"
            )
    warped = [
        WarpedView(
            np.ascontiguousarray(view.color, dtype=np.float32),
            np.ascontiguousarray(view.z, dtype=np.float64),
        )
        for view in warped
    ]
    if view_blending:
        priority = np.argsort(-weights, kind="stable")
        return _merge_by_priority([warped[i] for i in priority], overwrite)
    tolerance = depth_blend_difference * inverse_depth_step(depth_range)
    weighted = weights > 0
    if weighted.all():
        return _blend(warped, weights, tolerance, overwrite)
    # What the weighted views show is the visible surface (a reference at the
    # virtual camera sees exactly that); the zero-weight views only fill the rest.
    primary = _blend(
        [view for view, w in zip(warped, weighted) if w], weights[weighted], tolerance, overwrite
    )
    others = [view for view, w in zip(warped, weighted) if not w]
    return _merge_by_priority(
        [primary, _blend(others, np.ones(len(others)), tolerance, overwrite)], overwrite
    )


def _blend(
    warped: list[WarpedView], weights: np.ndarray, tolerance: float, overwrite: bool
) -> WarpedView:
    # Safe into the first view: the kernel reads each row of every view before writing it.
    merged = warped[0] if overwrite else _empty_like(warped[0])
    _blend_kernel(
        tuple(view.color for view in warped),
        tuple(view.z for view in warped),
        weights,
        tolerance,
        merged.color,
        merged.z,
    )
    return merged


def _merge_by_priority(warped: list[WarpedView], overwrite: bool) -> WarpedView:
    # Safe into the first view (the first priority): the kernel starts from it.
    merged = warped[0] if overwrite else _empty_like(warped[0])
    _priority_kernel(
        tuple(view.color for view in warped),
        tuple(view.z for view in warped),
        merged.color,
        merged.z,
    )
    return merged


def _empty_like(view: WarpedView) -> WarpedView:
    return WarpedView(np.empty_like(view.color), np.empty_like(view.z))


# Indexing the tuple of views with a variable is slow in numba: the kernels index it
# once per row (copying the row of each view into a small buffer, or walking the
# row view by view), not once per pixel.


@numba.njit(cache=True, nogil=True, parallel=True)
def _blend_kernel(colors, depths, weights, tolerance, color, z):
    count = len(depths)
    height, width = depths[0].shape
    weights = weights.astype(np.float32)
    for y in numba.prange(height):
        row_depths = np.empty((count, width))
        row_colors = np.empty((count, width, 3), dtype=np.float32)
        for i in range(count):
            row_depths[i] = depths[i][y]
            row_colors[i] = colors[i][y]
        for x in range(width):
            nearest = np.inf
            for i in range(count):
                nearest = min(nearest, row_depths[i, x])
            z[y, x] = nearest
            total = np.float32(0.0)
            c0 = np.float32(0.0)
            c1 = np.float32(0.0)
            c2 = np.float32(0.0)
            if nearest < np.inf:
                bound = tolerance * nearest
                for i in range(count):
                    d = row_depths[i, x]
                    # 1/nearest - 1/d < tolerance without dividing; the nearest views
                    # themselves always take part (tolerance 0).
                    if d - nearest < bound * d or d == nearest:
                        w = weights[i]
                        total += w
                        c0 += w * row_colors[i, x, 0]
                        c1 += w * row_colors[i, x, 1]
                        c2 += w * row_colors[i, x, 2]
            if total > 0.0:
                scale = np.float32(1.0) / total
                c0 *= scale
                c1 *= scale
                c2 *= scale
            color[y, x, 0] = c0
            color[y, x, 1] = c1
            color[y, x, 2] = c2


@numba.njit(cache=True, nogil=True, parallel=True)
def _priority_kernel(colors, depths, color, z):
    width = z.shape[1]
    for y in numba.prange(z.shape[0]):
        taken = z[y]
        out = color[y]
        # The first view's row (a no-op when writing into it), then each pixel it
        # lacks from the first view after it that holds something.
        taken[:] = depths[0][y]
        out[:] = colors[0][y]
        for i in range(1, len(depths)):
            depth = depths[i][y]
            source = colors[i][y]
            for x in range(width):
                if not taken[x] < np.inf and depth[x] < np.inf:
                    taken[x] = depth[x]
                    for c in range(3):
                        out[x, c] = source[x, c]
        for x in range(width):
            if not taken[x] < np.inf:
                for c in range(3):
                    out[x, c] = 0.0
