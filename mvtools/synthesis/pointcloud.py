"""Multiview video plus depth as a point cloud, and point clouds rendered into cameras.

A texture with its depth map is a coloured point cloud (section 1.4 of the chapter
"Multiview video: acquisition, processing, compression, and virtual view rendering",
fig. 1.10): each pixel with a valid depth is the world point its ray reaches at that
depth. :func:`points_from_views` makes one cloud of several views, dropping the points
that an earlier view holds already; :func:`render_point_cloud` draws a cloud into any
camera with a z-buffer and fills what no point reached from the background side
(:func:`mvtools.synthesis.holes.fill_holes`).

Merging rule. Views are taken in order. A point of view ``j`` is dropped when, for
some earlier view ``i``, it projects in front of camera ``i`` onto a pixel (the one
nearest to its projection) whose own depth ``z_i`` is valid and differs from the
point's depth along ``i``'s axis by at most ``merge_tolerance * z_i`` (0.01: one per
cent). The test uses view ``i``'s depth map, whether or not its pixel's point was kept
itself, so a surface seen by several cameras is kept once, from the first that sees
it. One view alone gives exactly one point per valid pixel.

Rendering. Each point goes to the pixel nearest to its projection; points behind the
camera (depth along its axis <= 0) are dropped; the nearest point wins, and of equally
near ones the first in the cloud, so the result does not depend on threads. Splats:

- ``"bilinear"`` (default): that z-buffer gives each pixel its nearest depth (a pixel
  no point is nearest to takes the nearest of the points whose 2x2 neighbourhood holds
  it, closing one-pixel cracks); then each point adds its colour, with bilinear
  weights, to the 2x2 pixels around its projection whose nearest depth it is within
  :data:`BLEND_TOLERANCE` of. Resampling rather than rounding positions: what the
  warping of view synthesis does with its sub-pixel precision.
- ``"point"``: each pixel the colour of its nearest point.
- ``"spacing"``: each point covers the pixels whose centres lie within half its
  footprint of its projection, the footprint being its distance to its nearest
  neighbour in the cloud seen at its depth (at most :data:`MAX_SPLAT` pixels across).

Measured on the sample line scene, frame 0, 8-bit depth, holes filled "background"
(Y-PSNR against the real view): camera 1's cloud into camera 1 is the view (inf dB,
all three splats but "spacing", 43.3 dB: splats overlap their neighbours); into camera
2, "bilinear" 36.63 dB, "point" 34.01, "spacing" 33.69, where
:class:`~mvtools.synthesis.pipeline.Synthesizer` (general mode, one reference, default
options) gives 37.05; the five cameras' merged cloud (54 867 points, 1.12 times one
view) into camera 2: 40.75 / 38.14 / 37.53 dB. Splats growing with the spacing do not
help: the rig's cameras share one focal length and similar depths, so a point covers
about one pixel in any of them, and larger splats widen the foreground at depth edges
more than they close cracks.

Kendo (1024x768, estimated depth maps), view 1's cloud (786 432 points, 0.31 s) into
camera 3: 31.32 dB ("bilinear", 0.06 s), the synthesizer from view 1 32.05 dB. Views 1
and 3 merged (1 449 188 points) and drawn into camera 1 give 33.94 dB, not the view
itself: where the two depth maps disagree by more than the tolerance, camera 3's points
stay and some lie in front of camera 1's surface. The rule drops duplicates; it does not
arbitrate between views that contradict each other.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numba
import numpy as np

from mvtools.geometry.camera import Camera
from mvtools.geometry.projection import backproject, project
from mvtools.synthesis.holes import fill_holes

__all__ = [
    "BLEND_TOLERANCE",
    "DEFAULT_MERGE_TOLERANCE",
    "MAX_SPLAT",
    "SPLATTING",
    "PointCloud",
    "points_from_views",
    "render_point_cloud",
]

#: Relative depth difference under which a point of a later view is the point an
#: earlier view holds (1 %).
DEFAULT_MERGE_TOLERANCE = 0.01
#: The splat kinds of :func:`render_point_cloud`.
SPLATTING = ("bilinear", "point", "spacing")
#: Relative depth difference within which points blend in a pixel with ``"bilinear"``.
BLEND_TOLERANCE = 0.02
#: Largest splat footprint in pixels, so that an isolated point does not cover a region.
MAX_SPLAT = 4.0


@dataclass(eq=False)
class PointCloud:
    """Coloured points in world coordinates.

    Attributes
    ----------
    points : ndarray of float64, shape (N, 3)
        World coordinates (the cameras' world, :mod:`mvtools.geometry.camera`).
    colors : ndarray of uint8, shape (N, 3)
        RGB.
    """

    points: np.ndarray
    colors: np.ndarray

    def __post_init__(self):
        self.points = np.ascontiguousarray(self.points, dtype=np.float64)
        if self.points.ndim != 2 or self.points.shape[1] != 3:
            raise ValueError(f"points must have shape (N, 3), got {self.points.shape}")
        colors = np.asarray(self.colors)
        if colors.shape != self.points.shape:
            raise ValueError(
                f"colors must have the shape of points {self.points.shape}, got {colors.shape}"
            )
        if colors.dtype != np.uint8 and (
            colors.dtype.kind not in "iu"
            or (colors.size and (colors.min() < 0 or colors.max() > 255))
        ):
            raise ValueError("colors must be integers in 0..255")
        self.colors = np.ascontiguousarray(colors, dtype=np.uint8)

    def __len__(self) -> int:
        return len(self.points)


def _valid(z: np.ndarray) -> np.ndarray:
    with np.errstate(invalid="ignore"):
        return np.isfinite(z) & (z > 0)


def _check_view(view, index: int) -> tuple[Camera, np.ndarray, np.ndarray]:
    try:
        camera, rgb, z = view
    except (TypeError, ValueError):
        raise ValueError(f"view {index} must be (camera, rgb, z)") from None
    rgb = np.asarray(rgb)
    z = np.asarray(z, dtype=np.float64)
    if z.ndim != 2 or rgb.shape != z.shape + (3,):
        raise ValueError(f"view {index}: rgb {rgb.shape} must be (H, W, 3) and z {z.shape} (H, W)")
    if rgb.dtype != np.uint8:
        raise ValueError(f"view {index}: rgb must be uint8, got {rgb.dtype}")
    return camera, rgb, z


def points_from_views(
    views: Sequence[tuple[Camera, np.ndarray, np.ndarray]],
    *,
    merge_tolerance: float = DEFAULT_MERGE_TOLERANCE,
) -> PointCloud:
    """One point cloud of the valid pixels of ``views`` (module docstring for the rule).

    Parameters
    ----------
    views : sequence of (Camera, rgb, z)
        ``rgb`` uint8 of shape (H, W, 3); ``z`` of shape (H, W), depth along the
        camera's axis, ``inf``, NaN or ``<= 0`` where the pixel has none. Pixel centres
        are at integer coordinates (:func:`mvtools.geometry.projection.backproject`).
    merge_tolerance : float
        Relative depth difference (0.01 = 1 %) within which a point of a later view is
        a point of an earlier one and is dropped; 0 keeps only exact coincidences.

    Returns
    -------
    PointCloud
        The points of the first view in row-major pixel order, then those of each
        further view that no earlier view holds.

    Examples
    --------
    >>> camera = Camera("c", [[2, 0, 0.5], [0, 2, 0.5], [0, 0, 1]])
    >>> rgb = np.full((2, 2, 3), 200, np.uint8)
    >>> z = np.array([[2.0, 2.0], [np.inf, 4.0]])
    >>> cloud = points_from_views([(camera, rgb, z)])
    >>> cloud.points.tolist()
    [[-0.5, -0.5, 2.0], [0.5, -0.5, 2.0], [1.0, 1.0, 4.0]]
    """
    if not np.isfinite(merge_tolerance) or merge_tolerance < 0:
        raise ValueError(f"merge_tolerance must be >= 0, got {merge_tolerance}")
    checked = [_check_view(view, index) for index, view in enumerate(views)]
    if not checked:
        raise ValueError("need at least one view")
    points, colors = [], []
    for j, (camera, rgb, z) in enumerate(checked):
        valid = _valid(z)
        rows, columns = np.nonzero(valid)
        world = backproject(
            camera, columns.astype(np.float64), rows.astype(np.float64), z[rows, columns]
        )
        keep = np.ones(len(world), dtype=bool)
        for earlier, _, earlier_z in checked[:j]:
            keep[keep] = ~_held_by(earlier, earlier_z, world[keep], merge_tolerance)
        points.append(world[keep])
        colors.append(rgb[rows[keep], columns[keep]])
    return PointCloud(np.concatenate(points), np.concatenate(colors))


def _held_by(camera: Camera, z: np.ndarray, world: np.ndarray, tolerance: float) -> np.ndarray:
    """Which ``world`` points camera's depth map ``z`` holds already (bool, shape (N,))."""
    height, width = z.shape
    uv, depth = project(camera, world)
    with np.errstate(invalid="ignore"):
        column = np.floor(uv[:, 0] + 0.5)
        row = np.floor(uv[:, 1] + 0.5)
        inside = (depth > 0) & (column >= 0) & (column < width) & (row >= 0) & (row < height)
    held = np.zeros(len(world), dtype=bool)
    index = np.flatnonzero(inside)
    own = z[row[index].astype(np.intp), column[index].astype(np.intp)]
    with np.errstate(invalid="ignore"):
        held[index] = _valid(own) & (np.abs(depth[index] - own) <= tolerance * own)
    return held


def _nearest_neighbour_distance(points: np.ndarray) -> np.ndarray:
    """Distance of each point to its nearest other point (inf for a lone point)."""
    from scipy.spatial import cKDTree

    if len(points) < 2:
        return np.full(len(points), np.inf)
    distance, _ = cKDTree(points).query(points, k=2)
    return distance[:, 1]


def render_point_cloud(
    cloud: PointCloud,
    camera: Camera,
    *,
    size: tuple[int, int],
    hole_filling: str | None = "background",
    splatting: str = "bilinear",
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Draw ``cloud`` into ``camera`` with a z-buffer and fill the holes.

    Parameters
    ----------
    cloud : PointCloud
    camera : Camera
    size : (width, height)
    hole_filling : str or None
        A method of :func:`mvtools.synthesis.holes.fill_holes`, or None to leave the
        holes (colour 0, depth ``inf``).
    splatting : {"point", "spacing"}
        Each point on one pixel, or on the square of its footprint (module docstring).

    Returns
    -------
    rgb : ndarray of float32, shape (H, W, 3)
        RGB in 0..255, unrounded where holes were filled.
    z : ndarray of float64, shape (H, W)
        Depth along the camera's axis (of the filling background at holes; ``inf``
        everywhere when no point is seen).
    holes : ndarray of bool, shape (H, W)
        The pixels no point reached, before filling.

    Examples
    --------
    >>> camera = Camera("c", [[2, 0, 0.5], [0, 2, 0.5], [0, 0, 1]])
    >>> cloud = PointCloud([[-0.5, -0.5, 2.0], [1.0, 1.0, 4.0], [0, 0, -1]],
    ...                    [[10, 20, 30], [40, 50, 60], [255, 255, 255]])
    >>> rgb, z, holes = render_point_cloud(cloud, camera, size=(2, 2), hole_filling=None)
    >>> holes.tolist(), float(z[0, 0]), rgb[1, 1].tolist()
    ([[False, True], [True, False]], 2.0, [40.0, 50.0, 60.0])
    """
    width, height = (int(value) for value in size)
    if width <= 0 or height <= 0:
        raise ValueError(f"image size must be positive, got {width}x{height}")
    if splatting not in SPLATTING:
        raise ValueError(f"splatting must be one of {', '.join(SPLATTING)}, got {splatting!r}")
    uv, depth = project(camera, cloud.points)
    if splatting == "spacing":
        focal = np.sqrt(abs(camera.fx * camera.fy))
        with np.errstate(divide="ignore", invalid="ignore"):
            footprint = _nearest_neighbour_distance(cloud.points) * focal / depth
        half = 0.5 * np.minimum(np.nan_to_num(footprint, nan=0.0, posinf=MAX_SPLAT), MAX_SPLAT)
    else:
        half = np.zeros(len(cloud))
    nearest = np.full((height, width), np.inf)
    index = np.full((height, width), -1, dtype=np.int64)
    u = np.ascontiguousarray(uv[:, 0])
    v = np.ascontiguousarray(uv[:, 1])
    depth = np.ascontiguousarray(depth)
    _z_buffer(u, v, depth, np.ascontiguousarray(half), nearest, index)
    if splatting == "bilinear":
        rgb = np.zeros((height, width, 3), dtype=np.float32)
        _bilinear_splats(u, v, depth, cloud.colors, BLEND_TOLERANCE, nearest, rgb)
        holes = ~np.isfinite(nearest)
    else:
        holes = index < 0
        rgb = np.zeros((height, width, 3), dtype=np.float32)
        rgb[~holes] = cloud.colors[index[~holes]]
    if hole_filling is not None:
        rgb, nearest = fill_holes(rgb, nearest, holes, method=hole_filling, overwrite=True)
    return rgb, nearest, holes


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _z_buffer(u, v, z, half, nearest, index):
    """Splat point ``k`` on the pixel nearest to ``(u[k], v[k])`` and on those whose
    centres lie within ``half[k]`` of it along both axes; keep the nearest ``z``
    (strictly nearer replaces, so the first of equals stays). Serial: deterministic."""
    height, width = nearest.shape
    for k in range(len(z)):
        depth = z[k]
        if not (depth > 0.0 and np.isfinite(u[k]) and np.isfinite(v[k])):
            continue
        centre_x = np.floor(u[k] + 0.5)
        centre_y = np.floor(v[k] + 0.5)
        reach = half[k]
        x0 = min(centre_x, np.ceil(u[k] - reach))
        x1 = max(centre_x, np.floor(u[k] + reach))
        y0 = min(centre_y, np.ceil(v[k] - reach))
        y1 = max(centre_y, np.floor(v[k] + reach))
        if x1 < 0 or y1 < 0 or x0 > width - 1 or y0 > height - 1:
            continue
        for y in range(int(max(y0, 0.0)), int(min(y1, height - 1.0)) + 1):
            for x in range(int(max(x0, 0.0)), int(min(x1, width - 1.0)) + 1):
                if depth < nearest[y, x]:
                    nearest[y, x] = depth
                    index[y, x] = k


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _bilinear_splats(u, v, z, colors, tolerance, nearest, rgb):
    """Colours as the bilinear-weighted mean of the points within ``tolerance`` (relative)
    of each pixel's nearest depth ``nearest`` (from :func:`_z_buffer`), over the 2x2
    pixels around each projection; pixels no point is nearest to first take the nearest
    depth of the points around them (closing one-pixel cracks). Serial: deterministic."""
    height, width = nearest.shape
    count = len(z)
    # Cracks: pixels that no point is nearest to take the nearest of the points around.
    crack = np.full((height, width), np.inf)
    for k in range(count):
        depth = z[k]
        if not (depth > 0.0 and np.isfinite(u[k]) and np.isfinite(v[k])):
            continue
        x0 = np.floor(u[k])
        y0 = np.floor(v[k])
        for dy in range(2):
            y = y0 + dy
            if y < 0 or y > height - 1:
                continue
            for dx in range(2):
                x = x0 + dx
                if x < 0 or x > width - 1:
                    continue
                iy = int(y)
                ix = int(x)
                if nearest[iy, ix] == np.inf and depth < crack[iy, ix]:
                    crack[iy, ix] = depth
    for y in range(height):
        for x in range(width):
            if nearest[y, x] == np.inf:
                nearest[y, x] = crack[y, x]
    weight = np.zeros((height, width))
    total = np.zeros((height, width, 3))
    for k in range(count):
        depth = z[k]
        if not (depth > 0.0 and np.isfinite(u[k]) and np.isfinite(v[k])):
            continue
        x0 = np.floor(u[k])
        y0 = np.floor(v[k])
        fx = u[k] - x0
        fy = v[k] - y0
        for dy in range(2):
            y = y0 + dy
            if y < 0 or y > height - 1:
                continue
            wy = fy if dy else 1.0 - fy
            for dx in range(2):
                x = x0 + dx
                if x < 0 or x > width - 1:
                    continue
                iy = int(y)
                ix = int(x)
                if depth > nearest[iy, ix] * (1.0 + tolerance):
                    continue
                w = wy * (fx if dx else 1.0 - fx)
                weight[iy, ix] += w
                for c in range(3):
                    total[iy, ix, c] += w * colors[k, c]
    for y in range(height):
        for x in range(width):
            if weight[y, x] > 0.0:
                for c in range(3):
                    rgb[y, x, c] = total[y, x, c] / weight[y, x]
            elif nearest[y, x] < np.inf:
                # Only zero-weight splats (a projection exactly on a neighbour): the
                # pixel is a hole.
                nearest[y, x] = np.inf
