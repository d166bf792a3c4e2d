"""VSRS 1D (parallel) mode: warping along rows of rectified linear camera arrays.

In a rectified array every camera shares the image plane orientation and the
cameras sit on a line along x, so a reference pixel moves along its row only, by
the disparity (:func:`mvtools.geometry.depth.disparity_1d`)::

    d = fx_left * (tx_virtual - tx_ref) / z - (cx_virtual - cx_ref),   u_virtual = u_ref - d

with ``fx`` of the LEFT camera for both references, as VSRS does. Depth along the
common camera axis is the same in every camera, so a warped pixel keeps its ``z``.

Warping one row (:class:`OneDWarper`):

- Neighbouring reference pixels whose disparities differ by at most
  :data:`SURFACE_JUMP` pixel are one surface; a larger step is a depth discontinuity,
  and a step above :data:`EDGE_FRACTION` of the frame's disparity range (at least
  :data:`SURFACE_JUMP`) a strong depth edge, as VSRS's 15 % rule.
- Splatting (``SplattingOption``): a splatted pixel's footprint reaches halfway to
  each neighbour of its surface (half a pixel beyond it at a discontinuity), and each
  virtual pixel under it takes the reference position that maps exactly onto it
  (positions and inverse depths are linear between neighbours), so a stretched surface
  leaves no crack. An unsplatted pixel keeps one pixel's width around where it lands,
  as VSRS rounds it without splatting, and a stretched surface cracks where the gaps
  between its pixels pass a virtual pixel centre. ``SplattingOption`` 1 splats every
  pixel, 2 only the pixels within ``BoundaryGrowth`` pixels of a strong edge (VSRS's
  boundary band), 0 none. Under a constant disparity both give the same picture.
- The nearest surface wins (z-buffer; equal depths keep the leftmost reference pixel),
  and the colour is fetched from the reference at the winning position rounded to
  1/``precision`` pixel with ``filter``: the taps and rounding of the general mode
  (:mod:`mvtools.synthesis.sampling`), so the two modes agree on rectified cameras.
- ``CleanNoiseOption``: the two pixels on the background side of every strong edge
  are not warped; their colour is often a mix with the foreground (the depth edge and
  the texture edge do not coincide), and the other view or the hole filling replaces
  them.
- ``WarpEnhancementOption``: a one-pixel crack between two virtual pixels of one
  surface (a hole, or a farther surface showing through) takes their mean.

VSRS renders into a virtual row ``precision`` times as wide and scales it down with a
[1 2 1] filter, which blurs; here the virtual row has its own size and only the fetch
is sub-pixel. VSRS's hole-count window is 7x7 (its ``HoleCountThreshold`` range is
0-49), counted here at the output resolution. Every loop over pixels is a numba kernel
over rows.
"""

from __future__ import annotations

import cv2
import numba
import numpy as np

from mvtools.geometry.camera import Camera
from mvtools.geometry.depth import inverse_depth_step
from mvtools.synthesis.sampling import tap_table
from mvtools.synthesis.views import ReferenceView, WarpedView

__all__ = [
    "CLEAN_NOISE_WIDTH",
    "EDGE_FRACTION",
    "HOLE_COUNT_RADIUS",
    "SURFACE_JUMP",
    "OneDWarper",
    "merge_1d",
    "warp_1d",
]

SURFACE_JUMP = 1.0
"""Largest disparity step (pixels) between neighbouring pixels of one surface."""

EDGE_FRACTION = 0.15
"""Strong depth edges step by more than this fraction of the frame's disparity range."""

CLEAN_NOISE_WIDTH = 2
"""Background pixels next to a strong edge that ``clean_noise`` does not warp."""

HOLE_COUNT_RADIUS = 3
"""``merge_1d`` counts holes in the (2r+1) x (2r+1) window around each pixel."""

# Finite stand-in for the depth of points at infinity (depth value 0 with Zfar = inf):
# inf marks a hole in a WarpedView.
_FARTHEST = 1e150  # products of two still finite


class OneDWarper:
    """Warps reference views of one rectified camera into the virtual camera.

    Parameters
    ----------
    reference_camera, virtual_camera : Camera
        Rectified: only the baseline along the left camera's x axis and the
        principal points' ``cx`` are used (the centres' x coordinates for VSRS's
        ``R = I``; a camera turned to face a negative depth range has its x axis,
        and so its baselines, reversed).
    size : (width, height)
        Size of the virtual view; the references must have its height.
    left_camera : Camera
        The left reference, whose ``fx`` serves both references (VSRS).
    """

    def __init__(
        self,
        reference_camera: Camera,
        virtual_camera: Camera,
        *,
        size: tuple[int, int],
        left_camera: Camera,
    ):
        width, height = (int(value) for value in size)
        if width <= 0 or height <= 0:
            raise ValueError(f"size must be positive, got {size}")
        self.size = (width, height)
        self.reference_camera = reference_camera
        # d = scale / z - offset
        baseline = left_camera.R[0] @ (virtual_camera.t - reference_camera.t)
        self.scale = float(left_camera.fx * baseline)
        self.offset = float(virtual_camera.cx - reference_camera.cx)
        if not (np.isfinite(self.scale) and np.isfinite(self.offset)):
            raise ValueError("camera parameters must be finite")

    def warp(
        self,
        view: ReferenceView,
        *,
        precision: int = 2,
        filter: str = "bicubic",
        splatting: int = 2,
        boundary_growth: int = 40,
        warp_enhancement: bool = True,
        clean_noise: bool = True,
        out: WarpedView | None = None,
    ) -> WarpedView:
        """Forward-warp one reference view along its rows.

        Parameters
        ----------
        view : ReferenceView
            ``color`` (H, Wr, 3) and ``z`` (H, Wr), ``H`` the virtual height.
        precision : {1, 2, 4, 8, 16}
            Colour is fetched at positions rounded to 1/``precision`` pixel (8 and 16
            are mvtools extensions of VSRS ``Precision``). Each row is upsampled to
            all its phases, a cost that grows with ``precision`` (Kendo 1024x768,
            whole 1D synthesis: about +15 % at 8 and +35 % at 16 over 2).
        filter : {"bilinear", "bicubic", "avc6"}
            Sub-pixel interpolation filter.
        splatting : {0, 1, 2}
            ``SplattingOption``: none, every pixel, pixels near strong edges.
        boundary_growth : int
            ``BoundaryGrowth``: half-width (reference pixels) of the band around strong
            edges that ``splatting=2`` splats.
        warp_enhancement : bool
            ``WarpEnhancementOption``: fill one-pixel cracks.
        clean_noise : bool
            ``CleanNoiseOption``: do not warp the background side of strong edges.
        out : WarpedView, optional
            Arrays of the result's shapes and dtypes to write into and return: a caller
            running frame after frame saves fresh allocations, whose first touch costs
            more than the warp on some machines.

        Returns
        -------
        WarpedView
            ``color`` (H, W, 3) float32 (0 in holes) and ``z`` (H, W) float64, ``inf``
            where the reference gives nothing.
        """
        if splatting not in (0, 1, 2):
            raise ValueError(f"splatting must be 0, 1 or 2, got {splatting!r}")
        if not boundary_growth >= 0:
            raise ValueError(f"boundary_growth must be >= 0, got {boundary_growth!r}")
        width, height = self.size
        z = np.ascontiguousarray(view.z, dtype=np.float64)
        color = np.ascontiguousarray(view.color, dtype=np.float32)
        if z.ndim != 2 or z.shape[0] != height or color.shape != z.shape + (3,):
            raise ValueError(
                f"reference colour {color.shape} and depth {z.shape} must be "
                f"(H, W, 3) and (H, W) with H = {height}"
            )
        z_min, z_max = z.min(), z.max()
        if not z_min > 0:
            raise ValueError("reference depths must be positive (and not NaN)")
        edge_jump = max(SURFACE_JUMP, EDGE_FRACTION * abs(self.scale) * (1.0 / z_min - 1.0 / z_max))
        taps = _six_taps(filter, precision)  # checks precision and filter
        out = _output(out, (height, width))
        shift = int(precision).bit_length() - 1  # precision == 1 << shift
        _warp_rows(
            color,
            z,
            self.scale,
            self.offset,
            shift,
            taps,
            int(splatting),
            int(boundary_growth),
            edge_jump,
            bool(clean_noise),
            bool(warp_enhancement),
            out.color,
            out.z,
        )
        return out


def _six_taps(filter: str, precision: int) -> np.ndarray:
    """:func:`mvtools.synthesis.sampling.tap_table` padded to the offsets -2 .. 3."""
    weights, first = tap_table(filter, precision)
    six = np.zeros((precision, 6), dtype=np.float32)
    six[:, first + 2 : first + 2 + weights.shape[1]] = weights
    return six


def warp_1d(
    view: ReferenceView,
    virtual_camera: Camera,
    *,
    left_camera: Camera,
    size: tuple[int, int],
    **options,
) -> WarpedView:
    """One-shot :meth:`OneDWarper.warp` of ``view`` into ``virtual_camera``.

    ``options`` are those of :meth:`OneDWarper.warp`.
    """
    warper = OneDWarper(view.camera, virtual_camera, size=size, left_camera=left_camera)
    return warper.warp(view, **options)


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _draw_half(x, u_middle, u_end, rate, inv_middle, inv_end, nearness, position):
    """Z-buffer the virtual pixels between ``u_middle`` and ``u_end`` (either order).

    Half a footprint of reference pixel x: positions ``x .. x -+ 1/2`` and inverse
    depths ``inv_middle .. inv_end`` map linearly onto ``u_middle .. u_end``,
    ``rate = 1/2 / |u_end - u_middle|`` reference pixels per virtual pixel. Covered
    are the pixels ``u_middle <= v < u_end`` (right half) or ``u_end <= v < u_middle``
    (left half). ``nearness`` is the row's inverse-depth buffer (-1 where empty): the
    larger wins, the earlier on equality.
    """
    if u_end > u_middle:
        lowest = max(np.ceil(u_middle), 0.0)
        highest = min(np.ceil(u_end) - 1.0, nearness.size - 1.0)
        inv_slope = 2.0 * (inv_end - inv_middle) * rate
    else:
        lowest = max(np.ceil(u_end), 0.0)
        highest = min(np.ceil(u_middle) - 1.0, nearness.size - 1.0)
        inv_slope = 2.0 * (inv_middle - inv_end) * rate
    if not lowest <= highest:
        return
    for v in range(int(lowest), int(highest) + 1):
        along = v - u_middle
        inv = inv_middle + along * inv_slope
        if inv > nearness[v]:
            nearness[v] = inv
            position[v] = x + along * rate


@numba.njit(cache=True, nogil=True, parallel=True, error_model="numpy")
def _warp_rows(
    color,
    z,
    scale,
    offset,
    shift,
    taps,
    splatting,
    growth,
    edge_jump,
    clean_noise,
    warp_enhancement,
    out_color,
    out_z,
):
    height, width = z.shape
    out_width = out_z.shape[1]
    for y in numba.prange(height):
        depth_row = z[y]
        inverse = np.empty(width)
        u = np.empty(width)  # virtual position of each reference pixel
        for x in range(width):
            inv = 1.0 / depth_row[x]
            inverse[x] = inv
            u[x] = x + offset - scale * inv
        # jump[x]: disparity step from pixel x to x + 1; rate[x]: reference pixels per
        # virtual pixel between them.
        jump = np.empty(width)
        rate = np.empty(width)
        next_inverse = inverse[1:]
        next_u = u[1:]
        for x in range(width - 1):
            jump[x] = abs(scale * (next_inverse[x] - inverse[x]))
            rate[x] = 1.0 / (next_u[x] - u[x])
        jump[width - 1] = np.inf
        skip = np.zeros(width, dtype=np.bool_)
        # Strong edges lie between x and x + 1 for x in edges[:count].
        edges = np.empty(width + 1, dtype=np.int64)
        count = 0
        if splatting == 2 or clean_noise:
            for x in range(width - 1):
                if jump[x] <= edge_jump:
                    continue
                edges[count] = x
                count += 1
                if clean_noise:
                    # The background side: the farther pixel and the next ones outwards.
                    if inverse[x] < inverse[x + 1]:
                        for k in range(max(x - CLEAN_NOISE_WIDTH + 1, 0), x + 1):
                            skip[k] = True
                    else:
                        for k in range(x + 1, min(x + 1 + CLEAN_NOISE_WIDTH, width)):
                            skip[k] = True
        edges[count] = 2 * width + growth + 2  # sentinel: no edge comes near

        nearness = np.full(out_width, -1.0)
        position = np.empty(out_width)
        following = 0  # index in edges of the first edge at or after x
        for x in range(width):
            while edges[following] < x:
                following += 1
            if skip[x]:
                continue
            inv = inverse[x]
            if splatting == 1 or (
                splatting == 2
                and (
                    edges[following] - x <= growth
                    or (following > 0 and x - edges[following - 1] <= growth + 1)
                )
            ):
                # The footprint reaches halfway to the neighbours of its surface.
                left = x > 0 and jump[x - 1] <= SURFACE_JUMP and not skip[x - 1]
                right = jump[x] <= SURFACE_JUMP and not skip[x + 1]
                if left:
                    _draw_half(
                        x,
                        u[x],
                        0.5 * (u[x - 1] + u[x]),
                        rate[x - 1],
                        inv,
                        0.5 * (inverse[x - 1] + inv),
                        nearness,
                        position,
                    )
                else:
                    _draw_half(x, u[x], u[x] - 0.5, 1.0, inv, inv, nearness, position)
                if right:
                    _draw_half(
                        x,
                        u[x],
                        0.5 * (u[x] + u[x + 1]),
                        rate[x],
                        inv,
                        0.5 * (inv + inverse[x + 1]),
                        nearness,
                        position,
                    )
                else:
                    _draw_half(x, u[x], u[x] + 0.5, 1.0, inv, inv, nearness, position)
            else:
                # One pixel's width around where it lands: the virtual pixel v with
                # u - 1/2 <= v < u + 1/2, at position x + v - u.
                v = np.ceil(u[x] - 0.5)
                if 0.0 <= v < out_width:
                    column = int(v)
                    if inv > nearness[column]:
                        nearness[column] = inv
                        position[column] = x + v - u[x]

        # One-pixel cracks take the mean of their neighbours once those are fetched.
        cracks = np.empty(out_width, dtype=np.int64)
        crack_count = _find_cracks(nearness, abs(scale), cracks) if warp_enhancement else 0
        for k in range(crack_count):
            v = cracks[k]
            nearness[v] = 0.5 * (nearness[v - 1] + nearness[v + 1])
            position[v] = np.nan
        depth = out_z[y]
        warped = out_color[y]
        phases = np.empty((1 << shift, 3 * width), dtype=np.float32)
        _upsample_row(color[y], taps, phases)
        for v in range(out_width):  # apart, so that it vectorises
            depth[v] = 1.0 / nearness[v]
        for v in range(out_width):
            if nearness[v] <= 0.0:
                if nearness[v] < 0.0:
                    depth[v] = np.inf
                    for c in range(3):
                        warped[v, c] = 0.0
                    continue
                depth[v] = _FARTHEST
            if position[v] == position[v]:
                _fetch(phases, position[v], shift, warped, v)
        for k in range(crack_count):
            v = cracks[k]
            for c in range(3):
                warped[v, c] = 0.5 * (warped[v - 1, c] + warped[v + 1, c])


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _find_cracks(nearness, scale, cracks):
    """Write into ``cracks`` the one-pixel cracks of a row's inverse-depth buffer.

    A crack is an empty pixel, or one farther by more than :data:`SURFACE_JUMP` of
    disparity (``scale`` times inverse depth), between two pixels whose disparities
    agree within :data:`SURFACE_JUMP`. Two cracks are never neighbours (each needs both
    neighbours on the surface), so filling them one after the other changes no
    decision. Returns their number.
    """
    count = 0
    before = nearness[:-2]  # slices indexed from 0 keep the loop branch-light
    after = nearness[2:]
    middle = nearness[1:-1]
    for k in range(middle.size):
        near_left = before[k]
        near_right = after[k]
        surface = (
            (near_left >= 0.0)
            & (near_right >= 0.0)
            & (scale * abs(near_left - near_right) <= SURFACE_JUMP)
        )
        behind = (middle[k] < 0.0) | (
            scale * (0.5 * (near_left + near_right) - middle[k]) > SURFACE_JUMP
        )
        if surface & behind:
            cracks[count] = k + 1
            count += 1
    return count


@numba.njit(cache=True, nogil=True)
def _upsample_row(row, weights, phases):
    """``phases[p]`` = ``row`` (W, 3) interpolated at ``i + p / precision``.

    The reference row upsampled by ``precision`` with 6-tap ``weights`` (offsets -2 to
    3, border pixels replicated), each phase flattened to (W * 3,): the channels are
    interleaved, so a tap of every pixel and channel is one shifted run of the
    flattened row. The runs are slices indexed from 0 (no negative-index check) so
    that the loop vectorises. Phase 0 is the row itself.
    """
    width = row.shape[0]
    flat = row.reshape(width * 3)
    # Pixels 2 .. width - 4 have all their taps inside the row.
    lowest = min(2, width)
    highest = max(width - 3, lowest)
    count = 3 * (highest - lowest)
    start = 3 * lowest
    phases[0, :] = flat
    for phase in range(1, weights.shape[0]):
        w0, w1, w2, w3, w4, w5 = weights[phase]
        out = phases[phase]
        if count > 0:
            t0 = flat[start - 6 :]
            t1 = flat[start - 3 :]
            t2 = flat[start:]
            t3 = flat[start + 3 :]
            t4 = flat[start + 6 :]
            t5 = flat[start + 9 :]
            inner = out[start:]
            for m in range(count):
                inner[m] = (
                    w0 * t0[m] + w1 * t1[m] + w2 * t2[m] + w3 * t3[m] + w4 * t4[m] + w5 * t5[m]
                )
        for i in range(width):
            if lowest <= i < highest:
                continue
            for c in range(3):
                total = np.float32(0.0)
                for j in range(6):
                    total += weights[phase, j] * row[min(max(i - 2 + j, 0), width - 1), c]
                out[3 * i + c] = total


@numba.njit(cache=True, nogil=True, inline="always")
def _fetch(phases, x, shift, out, column):
    """``out[column] =`` the sample at ``x`` of the row upsampled into ``phases``
    (:func:`_upsample_row`), ``x`` rounded half up to 1/``precision`` and clamped,
    ``precision = 1 << shift`` (as in :func:`mvtools.synthesis.sampling.sample_pixel`)."""
    width = phases.shape[1] // 3
    k = int(min(max(x, 0.0), width - 1.0) * (1 << shift) + 0.5)  # >= 0: truncation floors
    start = 3 * (k >> shift)
    phase = k & ((1 << shift) - 1)
    for c in range(3):
        out[column, c] = phases[phase, start + c]


def merge_1d(
    left: WarpedView,
    right: WarpedView,
    *,
    weights: tuple[float, float],
    merging: int = 2,
    depth_threshold: float = 75,
    hole_count_threshold: float = 30,
    depth_range: tuple[float, float],
    out: WarpedView | None = None,
) -> WarpedView:
    """Merge the left and right views warped in 1D mode (``MergingOption``).

    Where only one view holds a pixel it is taken; where both do:

    - ``merging=0`` (z-buffer): the nearer one (the left one on equal depths);
    - ``merging=1`` (averaging): the weighted mean of colours and inverse depths;
    - ``merging=2`` (adaptive): where the depth values differ by at most
      ``depth_threshold`` the two show one surface: the view with fewer holes in the
      (2r+1)-square around the pixel (r = :data:`HOLE_COUNT_RADIUS`) is taken alone
      when the counts differ by at least ``hole_count_threshold`` (its neighbourhood
      is more reliable; the left on equal counts), else the weighted mean; farther
      apart, the nearer one.

    Parameters
    ----------
    left, right : WarpedView
        Colours (H, W, 3) and depths (H, W), ``inf`` in holes.
    weights : (float, float)
        Non-negative weights of the left and right views (normalised here), e.g.
        :func:`mvtools.synthesis.blend.view_weights`.
    merging : {0, 1, 2}
    depth_threshold : float
        In 8-bit depth-value units of ``depth_range``, the same for both views
        (VSRS compares each view's own depth values, wrong when their ranges differ).
    hole_count_threshold : float
    depth_range : (znear, zfar)
    out : WarpedView, optional
        Arrays to write into and return (as in :meth:`OneDWarper.warp`), ``left`` or
        ``right`` included: each pixel is read before it is written.

    Returns
    -------
    WarpedView
        Colour 0 and ``z = inf`` where neither view holds anything.
    """
    if merging not in (0, 1, 2):
        raise ValueError(f"merging must be 0, 1 or 2, got {merging!r}")
    weights = np.asarray(weights, dtype=np.float64)
    if weights.shape != (2,) or not (np.all(weights >= 0) and weights.sum() > 0):
        raise ValueError(f"need two non-negative weights, not both zero, got {weights}")
    if not depth_threshold >= 0:
        raise ValueError(f"depth_threshold must be >= 0, got {depth_threshold!r}")
    shape = left.z.shape
    for view in (left, right):
        if view.z.shape != shape or view.color.shape != shape + (3,):
            raise ValueError(
                f"warped views differ in size: depth {view.z.shape}, colour "
                f"{view.color.shape}, left depth {shape}"
            )
    tolerance = depth_threshold * inverse_depth_step(depth_range)
    if merging == 2:
        window = (2 * HOLE_COUNT_RADIUS + 1,) * 2
        counts = [
            cv2.boxFilter(
                view.holes.view(np.uint8),
                -1,
                window,
                normalize=False,
                borderType=cv2.BORDER_CONSTANT,
            )
            for view in (left, right)
        ]
    else:
        counts = [np.zeros((1, 1), dtype=np.uint8)] * 2  # not read
    weights = weights / weights.sum()
    out = _output(out, shape)
    _merge_rows(
        np.ascontiguousarray(left.color, dtype=np.float32),
        np.ascontiguousarray(left.z, dtype=np.float64),
        np.ascontiguousarray(right.color, dtype=np.float32),
        np.ascontiguousarray(right.z, dtype=np.float64),
        counts[0],
        counts[1],
        weights[0],
        weights[1],
        merging,
        tolerance,
        float(hole_count_threshold),
        out.color,
        out.z,
    )
    return out


def _output(out: WarpedView | None, shape: tuple[int, int]) -> WarpedView:
    """``out`` checked for ``shape`` (H, W), or new arrays."""
    if out is None:
        return WarpedView(np.empty(shape + (3,), dtype=np.float32), np.empty(shape))
    if (
        out.color.shape != shape + (3,)
        or out.color.dtype != np.float32
        or out.z.shape != shape
        or out.z.dtype != np.float64
        or not (out.color.flags.c_contiguous and out.z.flags.c_contiguous)
    ):
        raise ValueError(
            f"out must hold C-contiguous float32 colour {shape + (3,)} and float64 depth {shape}"
        )
    return out


# serial, as the temporal filter's kernels (mvtools/synthesis/temporal.py say why)
@numba.njit(cache=True, nogil=True)
def _merge_rows(
    color_left,
    z_left,
    color_right,
    z_right,
    holes_left,
    holes_right,
    weight_left,
    weight_right,
    merging,
    tolerance,
    hole_threshold,
    color,
    z,
):
    height, width = z.shape
    for y in range(height):
        for x in range(width):
            zl = z_left[y, x]
            zr = z_right[y, x]
            take = 0  # 0 nothing, 1 left, 2 right, 3 weighted mean
            if zl < np.inf and zr < np.inf:
                if merging == 1:
                    take = 3
                # |1/zl - 1/zr| <= tolerance, without divisions.
                elif merging == 2 and abs(zr - zl) <= tolerance * zl * zr:
                    difference = float(holes_left[y, x]) - float(holes_right[y, x])
                    take = 3 if abs(difference) < hole_threshold else 1 if difference <= 0.0 else 2
                else:
                    take = 1 if zl <= zr else 2
            elif zl < np.inf:
                take = 1
            elif zr < np.inf:
                take = 2
            if take == 1:
                z[y, x] = zl
                for c in range(3):
                    color[y, x, c] = color_left[y, x, c]
            elif take == 2:
                z[y, x] = zr
                for c in range(3):
                    color[y, x, c] = color_right[y, x, c]
            elif take == 3:
                # The weighted mean of the inverse depths.
                z[y, x] = zl * zr / (weight_left * zr + weight_right * zl)
                for c in range(3):
                    color[y, x, c] = (
                        weight_left * color_left[y, x, c] + weight_right * color_right[y, x, c]
                    )
            else:
                z[y, x] = np.inf
                for c in range(3):
                    color[y, x, c] = 0.0
