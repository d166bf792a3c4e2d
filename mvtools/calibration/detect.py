"""Checkerboard corners in one image: found, refined, put in a canonical order, checked.

Corners come out in the order of :meth:`Board.object_points` (row by row, the
first inner corner at the board origin), with pixel centres at integer
coordinates (OpenCV's convention, that of :mod:`mvtools.geometry.lens`).
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

from mvtools.scene.checkerboard import Checkerboard

__all__ = ["Board", "Detection", "detect_board", "grid_defect"]

_SECTOR_FLAGS = cv2.CALIB_CB_NORMALIZE_IMAGE | cv2.CALIB_CB_EXHAUSTIVE | cv2.CALIB_CB_ACCURACY
_CLASSIC_FLAGS = cv2.CALIB_CB_ADAPTIVE_THRESH | cv2.CALIB_CB_NORMALIZE_IMAGE
_SUBPIXEL_CRITERIA = (cv2.TERM_CRITERIA_EPS | cv2.TERM_CRITERIA_COUNT, 100, 1e-6)
# Fraction of the board's median dark-light gap below which a corner is no crossing.
_MIN_CROSSING_CONTRAST = 0.25


@dataclass(frozen=True)
class Board:
    """A planar checkerboard target.

    Attributes
    ----------
    inner_corners : (columns, rows)
        Inner corners per row and per column, OpenCV's ``patternSize``, e.g. ``(9, 6)``.
    square_size : float
        Side of a square (metres); it sets the scale of the calibrated rig.
    """

    inner_corners: tuple[int, int]
    square_size: float

    def __post_init__(self):
        corners = tuple(self.inner_corners)
        if len(corners) != 2 or any(int(n) != n or n < 2 for n in corners):
            raise ValueError(
                f"inner_corners must be two integers >= 2 (columns, rows), "
                f"got {self.inner_corners!r}"
            )
        if not self.square_size > 0:
            raise ValueError(f"square_size must be positive, got {self.square_size!r}")
        object.__setattr__(self, "inner_corners", tuple(int(n) for n in corners))
        object.__setattr__(self, "square_size", float(self.square_size))

    @property
    def corner_count(self) -> int:
        return self.inner_corners[0] * self.inner_corners[1]

    def object_points(self) -> np.ndarray:
        """Inner corners in board coordinates (z = 0), row by row, shape (N, 3) float64."""
        return Checkerboard(self.inner_corners, self.square_size).object_points()


@dataclass(frozen=True)
class Detection:
    """The outcome of :func:`detect_board` on one image.

    Attributes
    ----------
    corners : ndarray, shape (N, 2), float64, or None
        Sub-pixel corners in :meth:`Board.object_points` order; None if rejected.
    method : str or None
        ``"sector"`` (``cv2.findChessboardCornersSB``) or ``"classic"``
        (``cv2.findChessboardCorners``) for the grid that was found, None if none was.
    reason : str or None
        Why the image gave no corners: ``"board not found"`` or the defect of the grid.
    """

    corners: np.ndarray | None
    method: str | None
    reason: str | None


def detect_board(image: np.ndarray, board: Board, *, max_grid_residual: float = 1.0) -> Detection:
    """Find the inner corners of ``board`` in ``image``.

    The sector-based detector (``findChessboardCornersSB``, exhaustive, accurate)
    runs first, the classic one as the fallback when it finds nothing or a
    defective grid. Both grids are refined by ``cv2.cornerSubPix``: on exact
    synthetic renderings it halves the sector detector's own error (RMS 0.10 to
    0.056 px).

    The corners are put in a canonical order, the same in every camera and
    capture: of the labellings the grid's symmetry allows (two for a board with
    unequal sides, four for a square one), one of those seen from the board's front
    (its columns a quarter turn clockwise of its rows in the picture), the one whose
    rows run nearest to the picture's diagonal from top-left to bottom-right (for a
    square board: nearest to left to right). A board held upright starts at its
    top-left corner, one held in portrait at its top-right corner, and the cameras
    of a roughly upright rig agree: the choice only flips for boards turned about
    45 degrees from either. (The corner nearest to the picture's top-left is no such
    rule: OpenCV's stereo pair 02, a board in portrait, has it at opposite ends of
    the board in the two cameras.)

    Parameters
    ----------
    image : ndarray, shape (H, W) or (H, W, 3), uint8
        Grey or RGB.
    board : Board
    max_grid_residual : float
        Largest accepted residual of the local homography fits of :func:`grid_defect` (px).

    Returns
    -------
    Detection
    """
    grey = _grey(image)
    if not max_grid_residual > 0:
        raise ValueError(f"max_grid_residual must be positive, got {max_grid_residual!r}")
    pattern = board.inner_corners
    first_rejection = None
    for method in ("sector", "classic"):
        if method == "sector":
            found, corners = cv2.findChessboardCornersSB(grey, pattern, flags=_SECTOR_FLAGS)
        else:
            found, corners = cv2.findChessboardCorners(grey, pattern, flags=_CLASSIC_FLAGS)
        if not found:
            continue
        corners = _canonical_order(_refine(grey, corners.reshape(-1, 2), pattern), pattern)
        reason = grid_defect(grey, corners, board, max_residual=max_grid_residual)
        if reason is None:
            return Detection(corners=corners, method=method, reason=None)
        first_rejection = first_rejection or Detection(corners=None, method=method, reason=reason)
    return first_rejection or Detection(corners=None, method=None, reason="board not found")


def grid_defect(
    image: np.ndarray, corners: np.ndarray, board: Board, *, max_residual: float = 1.0
) -> str | None:
    """Why detected corners are unfit for calibration, or None if they are fit.

    Three checks, in order:

    - every corner is finite and inside the image;
    - every corner is a crossing of dark and light squares: of the four squares
      around it (sampled a quarter of the grid steps from it along both, which stays
      inside outer squares printed narrower than the others), the two on one
      diagonal are both lighter than the two on the other, by at least a quarter of
      the median such gap over the board (measured: 0.7 of it at worst on OpenCV's
      stereo set). The sector detector sometimes takes the points where the outer
      squares meet the board's light margin for a row or column of inner corners
      when the far side of the board is cut off by the image border: the grid is
      then regular, one square off, and only other cameras could tell;
    - the corners of every 3 x 3 block of the grid are a perspective image of a square
      grid: the RMS residual of the homography fitted to the block
      (``cv2.findHomography`` from the board's plane) is at most ``max_residual``.
      Blocks, not the whole board, because lens distortion bends the rows of a whole
      board far from any homography (2.3 px RMS over OpenCV's stereo set, k1 = -0.29),
      while its blocks stay within 0.4 px (0.1 px on exact synthetic renderings, k1 up
      to 0.1). A corner moved by d pixels raises its blocks' residual by about 0.3 d
      (0.2 d at the board's corners): at 1 px, moves beyond 3.5 px (5 px) are caught.

    Parameters
    ----------
    image : ndarray, shape (H, W) or (H, W, 3), uint8
    corners : ndarray, shape (N, 2)
        In :meth:`Board.object_points` order.
    board : Board
    max_residual : float
        Pixels.

    Returns
    -------
    str or None
        E.g. ``"corner grid irregular (homography residual 2.3 px around corner 17)"``.
    """
    grey = _grey(image)
    corners = np.asarray(corners, dtype=np.float64)
    if corners.shape != (board.corner_count, 2):
        raise ValueError(
            f"corners must have shape ({board.corner_count}, 2) for a "
            f"{board.inner_corners} board, got {corners.shape}"
        )
    height, width = grey.shape
    if not np.all(np.isfinite(corners)):
        return "corners not finite"
    outside = np.flatnonzero(
        (corners[:, 0] < 0)
        | (corners[:, 0] > width - 1)
        | (corners[:, 1] < 0)
        | (corners[:, 1] > height - 1)
    )
    if outside.size:
        return f"corners outside the {width}x{height} image ({outside.size} of {len(corners)})"
    columns, rows = board.inner_corners
    grid = corners.reshape(rows, columns, 2)
    gaps = _crossing_gaps(grey, grid)
    weak = np.flatnonzero(gaps < _MIN_CROSSING_CONTRAST * np.median(gaps))
    if weak.size:
        return (
            f"corner grid off the board's crossings ({weak.size} of {len(corners)} corners "
            f"are no crossing of dark and light squares, the first corner {weak[0]})"
        )
    plane = board.object_points()[:, :2].reshape(rows, columns, 2)
    block_rows, block_columns = min(3, rows), min(3, columns)
    worst, worst_corner = 0.0, 0
    for top in range(rows - block_rows + 1):
        for left in range(columns - block_columns + 1):
            window = np.s_[top : top + block_rows, left : left + block_columns]
            source = plane[window].reshape(-1, 2)
            target = grid[window].reshape(-1, 2)
            homography, _ = cv2.findHomography(source, target, 0)
            if homography is None:
                return "corner grid degenerate (no homography fits)"
            fitted = cv2.perspectiveTransform(source[None], homography)[0]
            residual = float(np.sqrt(np.mean(np.sum((fitted - target) ** 2, axis=1))))
            if residual > worst:
                worst = residual
                worst_corner = (top + block_rows // 2) * columns + left + block_columns // 2
    if worst > max_residual:
        return (
            f"corner grid irregular (homography residual {worst:.1f} px around corner "
            f"{worst_corner})"
        )
    return None


def _crossing_gaps(grey: np.ndarray, grid: np.ndarray) -> np.ndarray:
    """Per corner, how much lighter the lighter diagonal pair of its four squares is than
    the darker pair (grey levels; <= 0 where the pairs do not separate), shape (N,)."""
    along_rows = np.gradient(grid, axis=1)
    along_columns = np.gradient(grid, axis=0)
    centres = [
        grid + 0.25 * (sign_row * along_rows + sign_column * along_columns)
        for sign_row, sign_column in ((1, 1), (-1, -1), (1, -1), (-1, 1))
    ]
    points = np.stack(centres).reshape(-1, 2).astype(np.float32)
    samples = cv2.remap(
        grey.astype(np.float32),
        points[:, :1],
        points[:, 1:],
        cv2.INTER_LINEAR,
        borderMode=cv2.BORDER_REPLICATE,
    )
    first, second, third, fourth = samples.reshape(4, -1)
    one_diagonal = np.minimum(first, second) - np.maximum(third, fourth)
    other_diagonal = np.minimum(third, fourth) - np.maximum(first, second)
    return np.maximum(one_diagonal, other_diagonal)


def _grey(image: np.ndarray) -> np.ndarray:
    image = np.asarray(image)
    if image.dtype != np.uint8:
        raise ValueError(f"image must be uint8, got {image.dtype}")
    if image.ndim == 3 and image.shape[2] == 3:
        return cv2.cvtColor(image, cv2.COLOR_RGB2GRAY)
    if image.ndim != 2:
        raise ValueError(f"image must have shape (H, W) or (H, W, 3), got {image.shape}")
    return image


def _refine(grey: np.ndarray, corners: np.ndarray, pattern: tuple[int, int]) -> np.ndarray:
    """``cornerSubPix`` with a half-window of 0.3 of the shortest corner spacing (2 to
    15 px): wide enough to average noise, narrow enough to stay inside the squares
    around the corner. The 11 px of OpenCV's samples reaches past the outer squares
    on OpenCV's stereo set, into the board's margin: RMS 0.41 px against 0.18 px."""
    columns, rows = pattern
    grid = corners.reshape(rows, columns, 2)
    spacing = min(
        np.linalg.norm(np.diff(grid, axis=0), axis=-1).min(),
        np.linalg.norm(np.diff(grid, axis=1), axis=-1).min(),
    )
    half = int(np.clip(round(0.3 * spacing), 2, 15))
    refined = cv2.cornerSubPix(
        grey,
        corners.astype(np.float32).reshape(-1, 1, 2),
        (half, half),
        (-1, -1),
        _SUBPIXEL_CRITERIA,
    )
    return refined.reshape(-1, 2).astype(np.float64)


def _canonical_order(corners: np.ndarray, pattern: tuple[int, int]) -> np.ndarray:
    columns, rows = pattern
    grid = corners.reshape(rows, columns, 2)
    along_rows = (grid[:, -1] - grid[:, 0]).mean(axis=0)
    along_columns = (grid[-1] - grid[0]).mean(axis=0)
    # Image y points down: seen from the front, the columns run clockwise of the rows.
    if along_rows[0] * along_columns[1] - along_rows[1] * along_columns[0] < 0:
        grid = grid[:, ::-1]
    # The labelling whose rows run nearest to a preferred image direction. The
    # boundaries between the choices fall 45 degrees either side of it; upright and
    # portrait boards keep a 45 degree margin from them, so the cameras of a rig,
    # which see the board turned alike, agree. A square board has four labellings a
    # quarter turn apart: the rows nearest to left-to-right. A board with unequal
    # sides has two, half a turn apart: the rows nearest to top-left to bottom-right
    # (left to right, preferred, would leave a portrait board on the boundary).
    if rows == columns:
        turns, preferred = (0, 1, 2, 3), np.array([1.0, 0.0])
    else:
        turns, preferred = (0, 2), np.array([1.0, 1.0])
    labellings = [np.rot90(grid, turn, axes=(0, 1)) for turn in turns]
    alignments = []
    for labelling in labellings:
        along_rows = (labelling[:, -1] - labelling[:, 0]).mean(axis=0)
        alignments.append(along_rows @ preferred / np.linalg.norm(along_rows))
    return np.ascontiguousarray(labellings[int(np.argmax(alignments))]).reshape(-1, 2)
