"""Multi-camera plane sweeping: matching costs of a center view against any number of
neighbour views over planes of constant depth, for any camera layout.

Each neighbour is warped into the center camera by the homography of each plane
(:func:`mvtools.geometry.homography.plane_homography`); for rectified cameras that is a
horizontal shift, the disparity search of DERS's MatchingMethod 0/1, and in general it is
DERS's MatchingMethod 2 (homography) and 4 (epipolar search along the same lines). The
cost of a neighbour is AD-census: the absolute colour difference to the neighbour's
colour interpolated bilinearly at the exact sub-pixel position, and the Hamming distance
to its census signature at the nearest sub-pixel position of a grid (DERS's Precision); the costs of the neighbours that see
the pixel are combined by their minimum, DERS's occlusion-aware rule: a point hidden from
one side is usually visible from the other.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import NamedTuple

import cv2
import numpy as np
from numba import njit, prange

from mvtools.depth.cost import (
    CENSUS_TOLERANCE,
    CENSUS_WINDOW,
    LAMBDA_CENSUS,
    LAMBDA_COLOUR,
    OUTSIDE_COST,
    census_transform,
    popcount,
)
from mvtools.geometry.camera import Camera
from mvtools.geometry.homography import plane_homography

__all__ = ["PlaneSweep", "plane_sweep_cost", "sweep_homographies"]

_FILTERS = {"linear": cv2.INTER_LINEAR, "cubic": cv2.INTER_CUBIC}


class PlaneSweep(NamedTuple):
    """Costs of a plane sweep.

    Which neighbour sees which point is not stored (it would be a volume of its own):
    :meth:`seen_at` works it out for the planes asked about, from the homographies.

    Attributes
    ----------
    cost : ndarray of float32, shape (H, W, D)
        Least cost over the neighbours that see the pixel's point on plane ``k``, in
        [0, 2]; ``outside_cost`` where none does.
    homographies : tuple of ndarray, each shape (D, 3, 3)
        Each neighbour's plane homographies (:func:`sweep_homographies`).
    sizes : tuple of (int, int)
        Each neighbour's (height, width).
    """

    cost: np.ndarray
    homographies: tuple
    sizes: tuple

    def seen_at(self, levels: np.ndarray) -> np.ndarray:
        """Whether any neighbour sees each pixel's point on its plane ``levels[y, x]``
        (it projects within half a pixel of the neighbour's picture, in front of the
        camera), bool of shape (H, W)."""
        levels = np.ascontiguousarray(levels, np.int64)
        seen = np.zeros(levels.shape, bool)
        for homographies, (height, width) in zip(self.homographies, self.sizes):
            _mark_seen(homographies, height, width, levels, seen)
        return seen

    @property
    def seen(self) -> np.ndarray:
        """:meth:`seen_at` of every plane, bool of shape (H, W, D): a volume, for
        inspection."""
        rows, cols, count = self.cost.shape
        return np.stack(
            [self.seen_at(np.full((rows, cols), k, np.int64)) for k in range(count)], axis=2
        )


def sweep_homographies(
    center: Camera, neighbour: Camera, inverse_depths, *, depth_type: int = 0
) -> np.ndarray:
    """Homographies from center pixels to neighbour pixels, one per plane.

    Parameters
    ----------
    center, neighbour : Camera
    inverse_depths : array_like, shape (D,)
        ``1/z`` of the planes. ``depth_type=0``: fronto-parallel planes of the center
        camera, ``1/z >= 0`` (0 is the plane at infinity, the disparity-0 plane of a
        DERS disparity range with no principal-point offset). ``depth_type=1``: world
        planes ``Z = z``, ``1/z`` nonzero.
    depth_type : {0, 1}

    Returns
    -------
    ndarray of float64, shape (D, 3, 3)
        ``[u', v', 1] ~ H [u, v, 1]``.
    """
    inverse = np.asarray(inverse_depths, dtype=np.float64).reshape(-1)
    if depth_type == 0:
        if not np.all(np.isfinite(inverse) & (inverse >= 0)):
            raise ValueError("inverse depths of camera planes must be finite and >= 0")
        # H is affine in 1/z for camera planes: H(w) = A + w C, exact from two planes,
        # and A, the homography at infinity, takes w = 0 without a special case.
        at_1, at_2 = plane_homography(center, neighbour, np.array([1.0, 2.0]))
        at_infinity = 2.0 * at_2 - at_1
        return at_infinity + inverse[:, None, None] * (at_1 - at_infinity)
    if depth_type == 1:
        if not np.all(np.isfinite(inverse) & (inverse != 0)):
            raise ValueError("inverse depths of world planes must be finite and nonzero")
        return plane_homography(center, neighbour, 1.0 / inverse, depth_type=1)
    raise ValueError(f"depth_type must be 0 or 1, got {depth_type!r}")


def plane_sweep_cost(
    center: np.ndarray,
    neighbours: Sequence[np.ndarray],
    center_camera: Camera,
    neighbour_cameras: Sequence[Camera],
    inverse_depths,
    *,
    depth_type: int = 0,
    precision: tuple[int, int] = (4, 1),
    filter: str = "cubic",
    block: int = 1,
    census_window: tuple[int, int] = CENSUS_WINDOW,
    lambda_census: float = LAMBDA_CENSUS,
    lambda_colour: float = LAMBDA_COLOUR,
    outside_cost: float = OUTSIDE_COST,
) -> PlaneSweep:
    """AD-census plane-sweep cost volume of ``center`` against its neighbours.

    Parameters
    ----------
    center : ndarray, shape (H, W, 3)
        The view whose depth is sought, colour on an 8-bit scale (0..255; float allowed).
    neighbours : sequence of ndarray, each shape (H', W', 3)
        The other views, same scale; sizes may differ from the center's.
    center_camera : Camera
    neighbour_cameras : sequence of Camera
        One per neighbour.
    inverse_depths : array_like, shape (D,)
        ``1/z`` of the planes (see :func:`sweep_homographies`); level ``k`` of the volume
        is plane ``k``. Uniform steps in ``1/z`` are uniform disparity steps.
    depth_type : {0, 1}
        Camera planes (0) or world planes ``Z = z`` (1).
    precision : (int, int)
        Horizontal and vertical sub-pixel steps of the census signatures (DERS's
        Precision and VerticalPrecision): each neighbour's census is computed on copies
        shifted by every fraction ``(i / precision[0], j / precision[1])`` and read at the
        nearest such position. The colour term is interpolated bilinearly at the exact
        position.
    filter : {"linear", "cubic"}
        Interpolation of the shifted copies (DERS's Filter: bilinear, or bicubic for
        both bicubic and the AVC 6-tap filter).
    block : {1, 3}
        1: per-pixel costs; 3: each neighbour's costs averaged over 3x3 blocks before
        the neighbours are compared (DERS's MatchingBlock).
    census_window : (int, int)
        Odd census window height and width.
    lambda_census, lambda_colour : float
        Hamming distance and mean absolute colour difference at which each term of
        ``cost = 2 - exp(-hamming / lambda_census) - exp(-colour / lambda_colour)``
        reaches 1 - 1/e.
    outside_cost : float
        Cost where no neighbour sees the point: below a typical mismatch, so that the
        smoothness of a global method carries the depth of the interior there.

    Returns
    -------
    PlaneSweep
        ``cost`` and ``seen``, shape (H, W, D).
    """
    center = np.asarray(center, np.float32)
    if center.ndim != 3 or center.shape[2] != 3:
        raise ValueError(f"center must be an (H, W, 3) image, got shape {center.shape}")
    if len(neighbours) == 0:
        raise ValueError("plane sweeping needs at least one neighbour view")
    if len(neighbours) != len(neighbour_cameras):
        raise ValueError(f"{len(neighbours)} neighbour views but {len(neighbour_cameras)} cameras")
    if filter not in _FILTERS:
        raise ValueError(f"filter must be one of {sorted(_FILTERS)}, got {filter!r}")
    if len(precision) != 2 or not all(isinstance(p, int) and p >= 1 for p in precision):
        raise ValueError(f"precision must be two positive integers, got {precision!r}")
    if block not in (1, 3):
        raise ValueError(f"block must be 1 or 3, got {block!r}")
    inverse = np.asarray(inverse_depths, np.float64).reshape(-1)
    if inverse.size == 0:
        raise ValueError("no depth planes to sweep")
    rows, cols = center.shape[:2]
    census_table = (1.0 - np.exp(-np.arange(65) / lambda_census)).astype(np.float32)
    center_census = census_transform(
        center.mean(axis=2), window=census_window, tolerance=CENSUS_TOLERANCE
    )
    # NaN until a neighbour sees the point: the kernels keep the least cost of those that do
    cost = np.full((rows, cols, inverse.size), np.nan, np.float32)
    all_homographies, sizes = [], []
    for image, camera in zip(neighbours, neighbour_cameras):
        image = np.ascontiguousarray(image, np.float32)
        if image.ndim != 3 or image.shape[2] != 3:
            raise ValueError(
                f"neighbour {camera.name!r} must be an (H, W, 3) image, got shape {image.shape}"
            )
        homographies = sweep_homographies(center_camera, camera, inverse, depth_type=depth_type)
        all_homographies.append(homographies)
        sizes.append(image.shape[:2])
        census = _shifted_census(image.mean(axis=2), precision, _FILTERS[filter], census_window)
        if block == 1:
            _sweep(homographies)(
                center_census,
                center,
                census,
                image,
                homographies,
                census_table,
                np.float32(1.0 / (3.0 * lambda_colour)),
                cost,
            )
        else:
            own = np.full_like(cost, np.nan)
            _sweep(homographies)(
                center_census,
                center,
                census,
                image,
                homographies,
                census_table,
                np.float32(1.0 / (3.0 * lambda_colour)),
                own,
            )
            own_seen = ~np.isnan(own)
            own[~own_seen] = outside_cost
            # 3x3 means per plane (cv2 filters up to 512 channels at once)
            for first in range(0, inverse.size, 512):
                own[..., first : first + 512] = cv2.blur(
                    own[..., first : first + 512], (3, 3), borderType=cv2.BORDER_REPLICATE
                )
            better = own_seen & (np.isnan(cost) | (own < cost))
            cost[better] = own[better]
            del own, own_seen, better
    _replace_nan(cost, np.float32(outside_cost))
    return PlaneSweep(cost, tuple(all_homographies), tuple(sizes))


def _sweep(homographies: np.ndarray):
    """The kernel for a neighbour: :func:`_sweep_along_rows` when every plane's homography
    is exactly a shift along the rows (rectified cameras), which gives the same costs
    with a third of the arithmetic, else :func:`_sweep_neighbour`."""
    translation = np.broadcast_to(np.eye(3), homographies.shape).copy()
    translation[:, 0, 2] = homographies[:, 0, 2]
    if np.array_equal(homographies, translation):
        return _sweep_along_rows
    return _sweep_neighbour


def _shifted_census(
    grey: np.ndarray, precision: tuple[int, int], interpolation: int, window: tuple[int, int]
) -> np.ndarray:
    """Census signatures at sub-pixel positions: ``[j, i, y, x]`` is the signature at
    ``(x + i / precision[0], y + j / precision[1])``, shape (P_v, P_h, H, W)."""
    steps_x, steps_y = precision
    signatures = np.empty((steps_y, steps_x) + grey.shape, np.uint64)
    for j in range(steps_y):
        for i in range(steps_x):
            # WARP_INVERSE_MAP: shifted(x, y) = grey(x + i / P_h, y + j / P_v)
            shift = np.array([[1.0, 0.0, i / steps_x], [0.0, 1.0, j / steps_y]])
            shifted = cv2.warpAffine(
                grey,
                shift,
                grey.shape[::-1],
                flags=interpolation | cv2.WARP_INVERSE_MAP,
                borderMode=cv2.BORDER_REPLICATE,
            )
            signatures[j, i] = census_transform(shifted, window=window, tolerance=CENSUS_TOLERANCE)
    return signatures


@njit(cache=True, nogil=True, parallel=True)
def _sweep_neighbour(
    center_census, center, census, image, homographies, census_table, colour_scale, cost
):
    # One pass per neighbour, planes innermost: the volume is written in memory order.
    rows, cols = center_census.shape
    steps_y, steps_x, height, width = census.shape
    for y in prange(rows):
        for x in range(cols):
            for k in range(homographies.shape[0]):
                h = homographies[k]
                w = h[2, 0] * x + h[2, 1] * y + h[2, 2]
                u = (h[0, 0] * x + h[0, 1] * y + h[0, 2]) / w
                v = (h[1, 0] * x + h[1, 1] * y + h[1, 2]) / w
                # in front of the neighbour and within half a pixel of its picture
                if not (w > 0 and -0.5 <= u <= width - 0.5 and -0.5 <= v <= height - 0.5):
                    continue
                # bilinear colour, edge-clamped within the half-pixel border
                u0 = min(max(int(np.floor(u)), 0), width - 2) if width > 1 else 0
                v0 = min(max(int(np.floor(v)), 0), height - 2) if height > 1 else 0
                fu = min(max(u - u0, 0.0), 1.0)
                fv = min(max(v - v0, 0.0), 1.0)
                u1 = min(u0 + 1, width - 1)
                v1 = min(v0 + 1, height - 1)
                colour = 0.0
                for c in range(3):
                    top = image[v0, u0, c] + fu * (image[v0, u1, c] - image[v0, u0, c])
                    bottom = image[v1, u0, c] + fu * (image[v1, u1, c] - image[v1, u0, c])
                    colour += abs(center[y, x, c] - (top + fv * (bottom - top)))
                # census at the nearest sub-pixel position, clamped to the picture
                column = min(max(int(np.rint(u * steps_x)), 0), (width - 1) * steps_x)
                row = min(max(int(np.rint(v * steps_y)), 0), (height - 1) * steps_y)
                signature = census[
                    row % steps_y, column % steps_x, row // steps_y, column // steps_x
                ]
                value = (
                    census_table[popcount(center_census[y, x] ^ signature)]
                    + np.float32(1.0)
                    - np.float32(np.exp(-colour * colour_scale))
                )
                # NaN (no neighbour yet) compares false: the first that sees it writes
                if not value >= cost[y, x, k]:
                    cost[y, x, k] = value


@njit(cache=True, nogil=True, parallel=True)
def _sweep_along_rows(
    center_census, center, census, image, homographies, census_table, colour_scale, cost
):
    # _sweep_neighbour for homographies that are shifts along the rows, u = x + shift,
    # v = y: the same operations on the same values, with the row's terms taken once.
    rows, cols = center_census.shape
    steps_y, steps_x, height, width = census.shape
    shifts = homographies[:, 0, 2].copy()
    for y in prange(rows):
        v = np.float64(y)
        if not (-0.5 <= v <= height - 0.5):
            continue
        v0 = min(max(int(np.floor(v)), 0), height - 2) if height > 1 else 0
        fv = min(max(v - v0, 0.0), 1.0)
        v1 = min(v0 + 1, height - 1)
        row = min(max(int(np.rint(v * steps_y)), 0), (height - 1) * steps_y)
        row_phase, row_index = row % steps_y, row // steps_y
        for x in range(cols):
            for k in range(shifts.shape[0]):
                u = x + shifts[k]
                if not (-0.5 <= u <= width - 0.5):
                    continue
                u0 = min(max(int(np.floor(u)), 0), width - 2) if width > 1 else 0
                fu = min(max(u - u0, 0.0), 1.0)
                u1 = min(u0 + 1, width - 1)
                colour = 0.0
                for c in range(3):
                    top = image[v0, u0, c] + fu * (image[v0, u1, c] - image[v0, u0, c])
                    # on a row of the neighbour (fv 0, every row but the last) the row
                    # below adds exactly nothing: not read
                    if fv != 0.0:
                        bottom = image[v1, u0, c] + fu * (image[v1, u1, c] - image[v1, u0, c])
                        top = top + fv * (bottom - top)
                    colour += abs(center[y, x, c] - top)
                column = min(max(int(np.rint(u * steps_x)), 0), (width - 1) * steps_x)
                signature = census[row_phase, column % steps_x, row_index, column // steps_x]
                value = (
                    census_table[popcount(center_census[y, x] ^ signature)]
                    + np.float32(1.0)
                    - np.float32(np.exp(-colour * colour_scale))
                )
                # NaN (no neighbour yet) compares false: the first that sees it writes
                if not value >= cost[y, x, k]:
                    cost[y, x, k] = value


@njit(cache=True, nogil=True, parallel=True)
def _mark_seen(homographies, height, width, levels, seen):
    # the test of the sweep kernels, for one plane per pixel
    rows, cols = levels.shape
    for y in prange(rows):
        for x in range(cols):
            h = homographies[levels[y, x]]
            w = h[2, 0] * x + h[2, 1] * y + h[2, 2]
            u = (h[0, 0] * x + h[0, 1] * y + h[0, 2]) / w
            v = (h[1, 0] * x + h[1, 1] * y + h[1, 2]) / w
            if w > 0 and -0.5 <= u <= width - 0.5 and -0.5 <= v <= height - 0.5:
                seen[y, x] = True


@njit(cache=True, nogil=True, parallel=True)
def _replace_nan(volume, value):
    rows, cols, count = volume.shape
    for y in prange(rows):
        for x in range(cols):
            for k in range(count):
                if np.isnan(volume[y, x, k]):
                    volume[y, x, k] = value
