"""Filling the disocclusions that no reference view saw.

A hole left after merging is background that the foreground hid from every
reference, so it must be filled from the background around it, never from the
object next to it. The depth of a hole is always filled by the background rule
(below); the methods differ in the colour:

- ``"background"`` (``IvsrsInpaint 1``): each run of holes along a row takes the
  colour and depth of the run's end neighbour with the larger depth (the
  background side); runs spanning a whole row are then filled the same way along
  columns.
- ``"inpaint"`` (``IvsrsInpaint 0``): plain image inpainting (OpenCV's Telea
  method, every known pixel a source, foreground included).
- ``"background-diffusion"``: the depth as ``"background"``; the colour of each
  hole pixel is the inverse-distance weighted mean of the nearest known pixels
  left, right, above and below it that are not nearer than the hole's background
  (its filled depth, within 5 %), smoothed by four diffusion sweeps over the hole
  in which nearer pixels take no part. The foreground stays out of the hole, and
  the streaks of the row rule go.

Measured PSNR (Y for Cones, R for the RGB scene) on the interior disocclusions of
single-view synthesis (holes not touching the picture border), "background" / "inpaint" /
"background-diffusion": Cones im4 from im2 18.98 / 19.82 / 20.26 dB, from im6
19.53 / 19.26 / 20.59 dB; synthetic scene (:func:`mvtools.scene.default_scene`,
line rig) camera 2 from 0: 18.79 / 17.42 / 19.35, from 4: 19.52 / 16.17 / 19.52,
camera 1 from 0: 20.75 / 18.25 / 21.15, from 3: 23.03 / 16.44 / 20.49 (regular
bricks, which the row rule continues best). Two-view Cones leaves few holes and
the three differ by less than 0.1 dB overall.
"""

from __future__ import annotations

import cv2
import numba
import numpy as np

from mvtools.synthesis.views import HOLE_FILLING

__all__ = ["fill_holes"]

# A known pixel is background for a hole when its inverse depth exceeds the hole's
# background inverse depth by at most this fraction (a 5 % nearer surface is the same
# background, e.g. a slanted floor; an object in front is far more than that).
_BACKGROUND_TOLERANCE = 0.05
_DIFFUSION_SWEEPS = 4
_INPAINT_RADIUS = 3


def fill_holes(
    color: np.ndarray,
    z: np.ndarray,
    holes: np.ndarray,
    *,
    method: str = "background",
    overwrite: bool = False,
) -> tuple[np.ndarray, np.ndarray]:
    """Fill the ``holes`` of a merged view (module docstring for the methods).

    Parameters
    ----------
    color : ndarray of float32, shape (H, W, 3)
        Merged image; values at holes are ignored.
    z : ndarray of float64, shape (H, W)
        Merged depth; values at holes are ignored.
    holes : ndarray of bool, shape (H, W)
        Pixels to fill.
    method : {"background", "inpaint", "background-diffusion"}
    overwrite : bool
        Fill ``color`` and ``z`` themselves (then C-contiguous float32 and float64)
        instead of copies.

    Returns
    -------
    color : ndarray of float32, shape (H, W, 3)
    z : ndarray of float64, shape (H, W)
        All ``inf`` (and colour 0) when every pixel is a hole.
    """
    if method not in HOLE_FILLING:
        raise ValueError(f"method must be one of {', '.join(HOLE_FILLING)}, got {method!r}")
    holes = np.ascontiguousarray(holes, dtype=bool)
    if z.shape != holes.shape or color.shape != holes.shape + (3,):
        raise ValueError(
            f"color {color.shape}, z {z.shape} and holes {holes.shape} must "
            f"share (H, W) (color with 3 channels)"
        )
    if overwrite:
        if not (
            color.dtype == np.float32
            and z.dtype == np.float64
            and color.flags.c_contiguous
            and z.flags.c_contiguous
        ):
            raise ValueError("overwrite needs C-contiguous float32 colour and float64 depth")
        filled_color, filled_z = color, z
    else:
        filled_color = np.array(color, dtype=np.float32, order="C")
        filled_z = np.array(z, dtype=np.float64, order="C")
    if not holes.any():
        return filled_color, filled_z
    np.copyto(filled_z, np.inf, where=holes)
    if holes.all():
        filled_color[:] = 0.0
        return filled_color, filled_z
    _fill_from_background(filled_color, filled_z)
    if method == "background-diffusion":
        _interpolate_from_background(
            filled_color, filled_z, holes, _BACKGROUND_TOLERANCE, _DIFFUSION_SWEEPS
        )
    elif method == "inpaint":
        # Telea reads only the pixels outside the mask.
        mask = holes.view(np.uint8)
        for channel in range(3):
            filled_color[..., channel] = cv2.inpaint(
                filled_color[..., channel], mask, _INPAINT_RADIUS, cv2.INPAINT_TELEA
            )
    return filled_color, filled_z


def _fill_from_background(color: np.ndarray, z: np.ndarray) -> None:
    """The background rule in place: rows first, columns for rows with nothing known."""
    if _fill_runs_along_rows(color, z):
        _fill_runs_along_rows(color.transpose(1, 0, 2), z.T)


@numba.njit(cache=True, nogil=True)
def _fill_runs_along_rows(color, z):
    """Fill each run of ``inf`` depths from its end with the larger depth; returns
    whether a row had nothing to fill from."""
    rows, columns = z.shape
    unfilled = False
    for y in range(rows):
        x = 0
        while x < columns:
            if z[y, x] < np.inf:
                x += 1
                continue
            start = x
            while x < columns and not z[y, x] < np.inf:
                x += 1
            source = -1
            if start > 0:
                source = start - 1
            if x < columns and (source < 0 or z[y, x] > z[y, source]):
                source = x
            if source < 0:
                unfilled = True
                continue
            for k in range(start, x):
                z[y, k] = z[y, source]
                for c in range(3):
                    color[y, k, c] = color[y, source, c]
    return unfilled


@numba.njit(cache=True, nogil=True)
def _interpolate_from_background(color, z, holes, tolerance, sweeps):
    """Inverse-distance interpolation from the background pixels nearest to each hole
    pixel in the four axis directions, then diffusion sweeps over the holes.

    ``z`` and ``color`` hold the background rule's fill of the ``holes``; the fill
    stays where no background pixel is found.
    """
    rows, columns = z.shape
    count = 0
    for y in range(rows):
        for x in range(columns):
            count += holes[y, x]
    hole_y = np.empty(count, dtype=np.int32)
    hole_x = np.empty(count, dtype=np.int32)
    up = np.full(columns, -1, dtype=np.int32)
    candidates_y = np.empty((count, 4), dtype=np.int32)
    candidates_x = np.empty((count, 4), dtype=np.int32)
    # Top-down: left and right ends of the row run, nearest known pixel above.
    n = 0
    for y in range(rows):
        x = 0
        while x < columns:
            if not holes[y, x]:
                up[x] = y
                x += 1
                continue
            start = x
            while x < columns and holes[y, x]:
                x += 1
            for k in range(start, x):
                hole_y[n] = y
                hole_x[n] = k
                candidates_y[n, 0] = y
                candidates_x[n, 0] = start - 1  # -1: none
                candidates_y[n, 1] = y
                candidates_x[n, 1] = x if x < columns else -1
                candidates_y[n, 2] = up[k]
                candidates_x[n, 2] = k if up[k] >= 0 else -1
                n += 1
    # Bottom-up: nearest known pixel below, visiting the holes in reverse order.
    down = np.full(columns, -1, dtype=np.int32)
    n = count - 1
    for y in range(rows - 1, -1, -1):
        for x in range(columns - 1, -1, -1):
            if not holes[y, x]:
                down[x] = y
            else:
                candidates_y[n, 3] = down[x]
                candidates_x[n, 3] = x if down[x] >= 0 else -1
                n -= 1
    for n in range(count):
        y = hole_y[n]
        x = hole_x[n]
        # Candidates on the hole's background surface (the row rule's depth), or farther.
        limit = (1.0 + tolerance) / z[y, x]
        total = 0.0
        c0 = 0.0
        c1 = 0.0
        c2 = 0.0
        for j in range(4):
            cy = candidates_y[n, j]
            cx = candidates_x[n, j]
            if cx >= 0 and 1.0 / z[cy, cx] <= limit:
                w = 1.0 / (abs(cy - y) + abs(cx - x))
                total += w
                c0 += w * color[cy, cx, 0]
                c1 += w * color[cy, cx, 1]
                c2 += w * color[cy, cx, 2]
        if total > 0.0:
            color[y, x, 0] = c0 / total
            color[y, x, 1] = c1 / total
            color[y, x, 2] = c2 / total
    # Diffusion: each hole pixel becomes the mean of its 4-neighbours that are holes or
    # background for it (not nearer than its filled depth allows); Gauss-Seidel order.
    for sweep in range(sweeps):
        for m in range(count):
            n = m if sweep % 2 == 0 else count - 1 - m
            y = hole_y[n]
            x = hole_x[n]
            limit = (1.0 + tolerance) / z[y, x]
            total = 0.0
            c0 = 0.0
            c1 = 0.0
            c2 = 0.0
            for j in range(4):
                ny = y + (j == 2) - (j == 3)
                nx = x + (j == 0) - (j == 1)
                if ny < 0 or ny >= rows or nx < 0 or nx >= columns:
                    continue
                if not holes[ny, nx] and 1.0 / z[ny, nx] > limit:
                    continue
                total += 1.0
                c0 += color[ny, nx, 0]
                c1 += color[ny, nx, 1]
                c2 += color[ny, nx, 2]
            if total > 0.0:
                color[y, x, 0] = c0 / total
                color[y, x, 1] = c1 / total
                color[y, x, 2] = c2 / total
