"""Colour-chart correction: the colorimetry, ColorChecker detection and sampling, and a
fitted per-channel tone curve plus colour-correction matrix.

Conventions
-----------
- Colours are row vectors in arrays of shape ``(..., 3)``; a matrix ``M`` acts as
  ``colours @ M`` (as OpenCV's ``ccm``), except the 3x3 colorimetric matrices of the
  literature (:data:`SRGB_TO_XYZ`, :func:`bradford_matrix`), which act on column
  vectors, ``xyz = SRGB_TO_XYZ @ rgb``, i.e. ``rgb @ SRGB_TO_XYZ.T`` for arrays.
- Display RGB is in [0, 1] (8-bit codes divided by 255). Linear RGB has the sRGB
  primaries and D65 white (IEC 61966-2-1); XYZ is scaled so that the white has Y = 1.
- White points (CIE 1931 observer): D65 is the ASTM E308 ``(0.95047, 1, 1.08883)``,
  which makes :data:`SRGB_TO_XYZ` the published ``[[0.4124564, 0.3575761, 0.1804375],
  ...]``; D50 is that of the CIE 15 chromaticity (0.34567, 0.35850). These are the
  whites of OpenCV's ``ccm`` module: with Bradford adaptation, the ColorChecker's
  CIELAB (D50) gives its linear sRGB references to 1e-8.
- Charts: the ColorChecker 24 seen upright has 6 columns and 4 rows of patches,
  numbered row by row from the top-left (dark skin, light skin, ...); the bottom row
  is the grey scale, white to black (patches 18..23). Its *patch area* is bounded by
  the outer corners of the four corner patches. Image points are (x, y) pixels with
  pixel centres at integer coordinates (OpenCV's convention).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import cv2
import numpy as np
import scipy.optimize

from mvtools.errors import DataError

__all__ = [
    "BRADFORD",
    "GREY_PATCHES",
    "SRGB_TO_XYZ",
    "WHITE_D50",
    "WHITE_D65",
    "XYZ_TO_SRGB",
    "ChartCorrection",
    "bradford_matrix",
    "delta_e_2000",
    "detect_chart",
    "fit_chart_correction",
    "gamma_to_linear",
    "lab_to_linear_rgb",
    "lab_to_xyz",
    "linear_rgb_to_lab",
    "linear_to_gamma",
    "linear_to_srgb",
    "sample_patches",
    "srgb_to_linear",
    "xy_to_xyz",
    "xyz_to_lab",
]

WHITE_D65 = np.array([0.95047, 1.0, 1.08883])
WHITE_D50 = np.array([0.34567 / 0.35850, 1.0, (1.0 - 0.34567 - 0.35850) / 0.35850])

# Lam's cone-response matrix of the Bradford transform (column vectors: lms = BRADFORD @ xyz).
BRADFORD = np.array(
    [[0.8951, 0.2664, -0.1614], [-0.7502, 1.7135, 0.0367], [0.0389, -0.0685, 1.0296]]
)

# Chromaticities of the sRGB (ITU-R BT.709) red, green and blue primaries.
_SRGB_PRIMARIES = ((0.64, 0.33), (0.30, 0.60), (0.15, 0.06))

# The ColorChecker 24: grid, grey-scale patches and the patches used to recognise it.
_CHART_LAYOUT = (6, 4)
GREY_PATCHES = tuple(range(18, 24))
_BLUE, _GREEN, _RED = 12, 13, 14

# CIELAB's linear segment below (6/29)^3 (CIE 15:2004).
_LAB_DELTA = 6.0 / 29.0


def _colours(values, name: str) -> np.ndarray:
    values = np.asarray(values, dtype=np.float64)
    if values.ndim == 0 or values.shape[-1] != 3:
        raise ValueError(f"{name} must have shape (..., 3), got {values.shape}")
    return values


def srgb_to_linear(values) -> np.ndarray:
    """Decode sRGB display values (IEC 61966-2-1): ``v / 12.92`` up to 0.04045, else
    ``((v + 0.055) / 1.055) ** 2.4``; negative values mirror the positive ones.

    Parameters
    ----------
    values : array_like
        Display values, nominally in [0, 1], any shape.

    Returns
    -------
    ndarray
        Linear values, float64, same shape.
    """
    values = np.asarray(values, dtype=np.float64)
    size = np.abs(values)
    linear = np.where(size <= 0.04045, size / 12.92, ((size + 0.055) / 1.055) ** 2.4)
    return np.copysign(linear, values)


def linear_to_srgb(values) -> np.ndarray:
    """Encode linear values as sRGB (the inverse of :func:`srgb_to_linear`): ``12.92 v``
    up to 0.0031308, else ``1.055 v ** (1 / 2.4) - 0.055``; negatives mirrored."""
    values = np.asarray(values, dtype=np.float64)
    size = np.abs(values)
    encoded = np.where(size <= 0.0031308, 12.92 * size, 1.055 * size ** (1 / 2.4) - 0.055)
    return np.copysign(encoded, values)


def _check_gamma(gamma: float) -> float:
    if not np.isfinite(gamma) or gamma <= 0:
        raise ValueError(f"gamma must be a finite number > 0, got {gamma!r}")
    return float(gamma)


def gamma_to_linear(values, *, gamma: float = 2.2) -> np.ndarray:
    """Plain power-law decoding ``sign(v) |v| ** gamma`` (OpenCV's ``LINEARIZATION_GAMMA``,
    whose default gamma is 2.2); same shape, float64."""
    gamma = _check_gamma(gamma)
    values = np.asarray(values, dtype=np.float64)
    return np.copysign(np.abs(values) ** gamma, values)


def linear_to_gamma(values, *, gamma: float = 2.2) -> np.ndarray:
    """The inverse of :func:`gamma_to_linear`: ``sign(v) |v| ** (1 / gamma)``."""
    gamma = _check_gamma(gamma)
    values = np.asarray(values, dtype=np.float64)
    return np.copysign(np.abs(values) ** (1.0 / gamma), values)


def xy_to_xyz(xy) -> np.ndarray:
    """Tristimulus values with Y = 1 of chromaticity ``(x, y)``: ``(x / y, 1, (1 - x - y) / y)``.

    Parameters
    ----------
    xy : array_like, shape (..., 2)

    Returns
    -------
    ndarray, shape (..., 3)
    """
    xy = np.asarray(xy, dtype=np.float64)
    if xy.ndim == 0 or xy.shape[-1] != 2:
        raise ValueError(f"xy must have shape (..., 2), got {xy.shape}")
    x, y = xy[..., 0], xy[..., 1]
    if np.any(y <= 0):
        raise ValueError("chromaticity y must be > 0")
    return np.stack([x / y, np.ones_like(x), (1.0 - x - y) / y], axis=-1)


def _rgb_to_xyz_matrix(primaries, white: np.ndarray) -> np.ndarray:
    """Columns: the XYZ of each primary, scaled so that R = G = B = 1 gives ``white``."""
    unscaled = xy_to_xyz(np.asarray(primaries)).T
    return unscaled * np.linalg.solve(unscaled, white)


SRGB_TO_XYZ = _rgb_to_xyz_matrix(_SRGB_PRIMARIES, WHITE_D65)
XYZ_TO_SRGB = np.linalg.inv(SRGB_TO_XYZ)


def _white(white, name: str = "white") -> np.ndarray:
    white = np.asarray(white, dtype=np.float64)
    if white.shape != (3,) or not np.all(np.isfinite(white)) or np.any(white <= 0):
        raise ValueError(f"{name} must be 3 positive tristimulus values, got {white!r}")
    return white


def bradford_matrix(source_white, target_white) -> np.ndarray:
    """Bradford chromatic adaptation from ``source_white`` to ``target_white``.

    ``M = B^-1 diag(B w_t / B w_s) B`` with :data:`BRADFORD` ``B``, for column vectors:
    ``xyz_target = M @ xyz_source`` (``xyz @ M.T`` for arrays of colours).

    Parameters
    ----------
    source_white, target_white : array_like, shape (3,)
        Tristimulus values of the two whites.

    Returns
    -------
    ndarray, shape (3, 3)
    """
    source = BRADFORD @ _white(source_white, "source_white")
    target = BRADFORD @ _white(target_white, "target_white")
    return np.linalg.inv(BRADFORD) @ np.diag(target / source) @ BRADFORD


def xyz_to_lab(xyz, *, white=WHITE_D50) -> np.ndarray:
    """CIE XYZ to CIELAB (CIE 15:2004) relative to ``white``.

    Parameters
    ----------
    xyz : array_like, shape (..., 3)
    white : array_like, shape (3,)
        Tristimulus values of the reference white (Y = 1 scale as ``xyz``).

    Returns
    -------
    ndarray, shape (..., 3)
        (L*, a*, b*).
    """
    ratio = _colours(xyz, "xyz") / _white(white)
    f = np.where(ratio > _LAB_DELTA**3, np.cbrt(ratio), ratio / (3 * _LAB_DELTA**2) + 4.0 / 29.0)
    return np.stack(
        [
            116.0 * f[..., 1] - 16.0,
            500.0 * (f[..., 0] - f[..., 1]),
            200.0 * (f[..., 1] - f[..., 2]),
        ],
        axis=-1,
    )


def lab_to_xyz(lab, *, white=WHITE_D50) -> np.ndarray:
    """CIELAB relative to ``white`` back to CIE XYZ (the inverse of :func:`xyz_to_lab`)."""
    lab = _colours(lab, "lab")
    fy = (lab[..., 0] + 16.0) / 116.0
    f = np.stack([fy + lab[..., 1] / 500.0, fy, fy - lab[..., 2] / 200.0], axis=-1)
    ratio = np.where(f > _LAB_DELTA, f**3, 3 * _LAB_DELTA**2 * (f - 4.0 / 29.0))
    return ratio * _white(white)


def linear_rgb_to_lab(rgb, *, white=WHITE_D50) -> np.ndarray:
    """Linear sRGB (D65) to CIELAB relative to ``white``, adapting D65 to it by Bradford.

    Parameters
    ----------
    rgb : array_like, shape (..., 3)
        Linear RGB, white = (1, 1, 1); values outside [0, 1] are converted as they are.
    white : array_like, shape (3,)

    Returns
    -------
    ndarray, shape (..., 3)
    """
    matrix = bradford_matrix(WHITE_D65, white) @ SRGB_TO_XYZ
    return xyz_to_lab(_colours(rgb, "rgb") @ matrix.T, white=white)


def lab_to_linear_rgb(lab, *, white=WHITE_D50) -> np.ndarray:
    """CIELAB relative to ``white`` to linear sRGB (D65), the inverse of
    :func:`linear_rgb_to_lab`; colours outside the sRGB gamut get values outside [0, 1]."""
    matrix = XYZ_TO_SRGB @ bradford_matrix(white, WHITE_D65)
    return lab_to_xyz(lab, white=white) @ matrix.T


def delta_e_2000(lab1, lab2) -> np.ndarray:
    """CIEDE2000 colour difference (k_L = k_C = k_H = 1), as Sharma, Wu and Dalal,
    Color Res. Appl. 30(1), 2005, specify it (hue differences and means taken across
    the 0/360 degree cut, hue 0 for neutral colours).

    Parameters
    ----------
    lab1, lab2 : array_like, shape (..., 3)
        CIELAB colours; the shapes broadcast.

    Returns
    -------
    ndarray, shape (...)
    """
    lab1, lab2 = np.broadcast_arrays(_colours(lab1, "lab1"), _colours(lab2, "lab2"))
    lightness1, a1, b1 = np.moveaxis(lab1, -1, 0)
    lightness2, a2, b2 = np.moveaxis(lab2, -1, 0)
    chroma_mean7 = (0.5 * (np.hypot(a1, b1) + np.hypot(a2, b2))) ** 7
    g = 0.5 * (1.0 - np.sqrt(chroma_mean7 / (chroma_mean7 + 25.0**7)))
    a1, a2 = (1.0 + g) * a1, (1.0 + g) * a2
    chroma1, chroma2 = np.hypot(a1, b1), np.hypot(a2, b2)
    hue1 = np.degrees(np.arctan2(b1, a1)) % 360.0
    hue2 = np.degrees(np.arctan2(b2, a2)) % 360.0
    chromatic = chroma1 * chroma2 != 0
    hue_step = hue2 - hue1
    hue_step = np.where(
        hue_step > 180.0, hue_step - 360.0, np.where(hue_step < -180.0, hue_step + 360.0, hue_step)
    )
    hue_step = np.where(chromatic, hue_step, 0.0)
    delta_hue = 2.0 * np.sqrt(chroma1 * chroma2) * np.sin(np.radians(hue_step) / 2.0)
    hue_sum = hue1 + hue2
    hue_mean = np.where(
        np.abs(hue1 - hue2) <= 180.0,
        hue_sum / 2.0,
        np.where(hue_sum < 360.0, (hue_sum + 360.0) / 2.0, (hue_sum - 360.0) / 2.0),
    )
    hue_mean = np.where(chromatic, hue_mean, hue_sum)
    lightness_mean = 0.5 * (lightness1 + lightness2)
    chroma_mean = 0.5 * (chroma1 + chroma2)
    h = np.radians(hue_mean)
    t = (
        1.0
        - 0.17 * np.cos(h - np.radians(30.0))
        + 0.24 * np.cos(2.0 * h)
        + 0.32 * np.cos(3.0 * h + np.radians(6.0))
        - 0.20 * np.cos(4.0 * h - np.radians(63.0))
    )
    rotation = np.radians(30.0) * np.exp(-(((hue_mean - 275.0) / 25.0) ** 2))
    chroma_mean7 = chroma_mean**7
    r_t = -2.0 * np.sqrt(chroma_mean7 / (chroma_mean7 + 25.0**7)) * np.sin(2.0 * rotation)
    offset2 = (lightness_mean - 50.0) ** 2
    term_l = (lightness2 - lightness1) / (1.0 + 0.015 * offset2 / np.sqrt(20.0 + offset2))
    term_c = (chroma2 - chroma1) / (1.0 + 0.045 * chroma_mean)
    term_h = delta_hue / (1.0 + 0.015 * chroma_mean * t)
    return np.sqrt(term_l**2 + term_c**2 + term_h**2 + r_t * term_c * term_h)


def _layout(layout) -> tuple[int, int]:
    values = tuple(layout)
    if len(values) != 2 or not all(isinstance(n, (int, np.integer)) and n > 0 for n in values):
        raise ValueError(f"layout must be two positive integers (columns, rows), got {layout!r}")
    return int(values[0]), int(values[1])


def _image(image) -> np.ndarray:
    """The image as (H, W, C)."""
    image = np.asarray(image)
    if image.ndim == 2:
        image = image[..., None]
    if image.ndim != 3 or image.shape[0] < 1 or image.shape[1] < 1 or image.shape[2] < 1:
        raise ValueError(f"image must have shape (H, W) or (H, W, C), got {image.shape}")
    if image.dtype.kind not in "uif":
        raise ValueError(f"image must be an integer or float array, got dtype {image.dtype}")
    return image


def _square(half: float) -> np.ndarray:
    """Corners of the square of half-side ``half`` about the origin, clockwise in the image."""
    return np.array([[-half, -half], [half, -half], [half, half], [-half, half]])


def _transform(homography: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Points (..., 2) through a 3x3 homography."""
    mapped = points @ homography[:, :2].T + homography[:, 2]
    return mapped[..., :2] / mapped[..., 2:]


def _jacobian_determinant(homography: np.ndarray, points: np.ndarray) -> np.ndarray:
    """The determinant of the homography's Jacobian at ``points`` (..., 2): det(H) / w**3."""
    w = points @ homography[2, :2] + homography[2, 2]
    return np.linalg.det(homography) / w**3


def _lattice_homography(corners, layout: tuple[int, int]) -> np.ndarray:
    """The homography from lattice coordinates (patch (c, r) centred at (c, r), one cell
    a unit) to the image, for the outer corners of the patch area."""
    corners = np.asarray(corners, dtype=np.float64)
    if corners.shape != (4, 2) or not np.all(np.isfinite(corners)):
        raise ValueError(f"corners must be 4 finite (x, y) points, got shape {corners.shape}")
    edges = np.roll(corners, -1, axis=0) - corners
    following = np.roll(edges, -1, axis=0)
    # Clockwise in the image (y down) means positive turns at every corner.
    if np.any(edges[:, 0] * following[:, 1] - edges[:, 1] * following[:, 0] <= 0):
        raise ValueError(
            "corners must form a convex quadrilateral in the order top-left, "
            "top-right, bottom-right, bottom-left (clockwise in the image)"
        )
    columns, rows = layout
    lattice = np.array(
        [[-0.5, -0.5], [columns - 0.5, -0.5], [columns - 0.5, rows - 0.5], [-0.5, rows - 0.5]]
    )
    homography, _ = cv2.findHomography(lattice, corners, 0)
    return homography


def _sample_outlines(to_image: np.ndarray, layout: tuple[int, int], fraction: float) -> np.ndarray:
    """Image corners (N, 4, 2) of the central square of side ``fraction`` of each cell."""
    columns, rows = layout
    centres = np.stack(np.meshgrid(np.arange(columns), np.arange(rows)), -1).reshape(-1, 1, 2)
    return _transform(to_image, centres + _square(fraction / 2.0))


def _inside(outlines: np.ndarray, shape) -> bool:
    """Whether the outlines lie within the image's pixels (their outer edges)."""
    return bool(
        np.all(outlines >= -0.5)
        and np.all(outlines[..., 0] <= shape[1] - 0.5)
        and np.all(outlines[..., 1] <= shape[0] - 0.5)
    )


def _patch_means(
    image: np.ndarray, to_image: np.ndarray, layout: tuple[int, int], fraction: float
) -> np.ndarray:
    """Mean of the pixels whose centres map inside the central square of each cell."""
    outlines = _sample_outlines(to_image, layout, fraction)
    if not _inside(outlines, image.shape):
        outside = [k for k, outline in enumerate(outlines) if not _inside(outline, image.shape)]
        raise ValueError(
            f"patches {outside} lie (partly) outside the {image.shape[1]}x{image.shape[0]} image"
        )
    columns = layout[0]
    inverse = np.linalg.inv(to_image)
    means = np.empty((len(outlines), image.shape[2]))
    for index, outline in enumerate(outlines):
        low = np.ceil(outline.min(axis=0)).astype(int)
        high = np.floor(outline.max(axis=0)).astype(int)
        ys, xs = np.mgrid[low[1] : high[1] + 1, low[0] : high[0] + 1]
        lattice = _transform(inverse, np.stack([xs, ys], axis=-1).astype(np.float64))
        centre = np.array([index % columns, index // columns])
        inside = np.all(np.abs(lattice - centre) <= fraction / 2.0, axis=-1)
        if not inside.any():
            raise ValueError(
                f"the sampled square of patch {index} holds no pixel centre; "
                "the chart is too small or fraction too low"
            )
        means[index] = image[ys[inside], xs[inside]].mean(axis=0)
    return means


def sample_patches(
    image, corners, *, layout: tuple[int, int] = _CHART_LAYOUT, fraction: float = 0.5
) -> np.ndarray:
    """Mean colour of each patch of a chart.

    The patch area (bounded by ``corners``) is divided into ``layout`` equal cells by
    the homography of its corners, so perspective is followed exactly; each patch is
    the mean of the pixels whose centres map into the central square of its cell, of
    side ``fraction`` of the cell's. As the area ends at the outer patches' edges, not
    in the gaps' middle, a cell's centre is off its patch's by up to 5/12 of a gap
    (towards the chart's middle): at the default fraction the squares stay well inside
    patches with gaps up to a quarter of their side.

    Parameters
    ----------
    image : ndarray, shape (H, W) or (H, W, C)
    corners : array_like, shape (4, 2)
        Outer corners of the patch area, (x, y) pixels: top-left, top-right,
        bottom-right, bottom-left of the chart upright, as :func:`detect_chart`
        returns them.
    layout : (int, int)
        (columns, rows) of patches; (6, 4) for the ColorChecker 24.
    fraction : float
        In (0, 1]: the side of the averaged square relative to the cell's.

    Returns
    -------
    ndarray, shape (columns * rows, C)
        float64 means in the image's units, patches row by row from the top-left.

    Raises
    ------
    ValueError
        Corners that are not a convex quadrilateral clockwise from the top-left, a bad
        layout or fraction, or a patch outside the image or too small for a pixel.
    """
    image = _image(image)
    layout = _layout(layout)
    if not 0 < fraction <= 1:
        raise ValueError(f"fraction must be in (0, 1], got {fraction!r}")
    return _patch_means(image, _lattice_homography(corners, layout), layout, float(fraction))


# Patch candidates: smallest area in pixels, largest share of the image, least
# solidity (area over convex hull) and least ratio of the shortest side to the longest.
_MIN_PATCH_AREA = 40
_MAX_PATCH_SHARE = 1.0 / 30.0
_MIN_SOLIDITY = 0.9
_MIN_SIDE_RATIO = 0.4
# Lattice steps: at most this many cells, within this fraction of a cell of a lattice
# point, between candidates whose areas differ by less than this factor; a chart needs
# this many patches found.
_MAX_STEP = 2
_STEP_TOLERANCE = 0.3
_AREA_FACTOR = 2.0
_MIN_PATCHES = 10
# Refinement: patches need this contrast (RGB distance in [0, 1] units) with the chart
# body to be located, and must then sit within this fraction of a pitch of the grid.
_MIN_CONTRAST = 0.08
_MAX_RESIDUAL = 0.1
_REFINEMENTS = 3
# Colours for the orientation test are averaged over this fraction of each cell.
_TEST_FRACTION = 0.4


def _unit_rgb(image) -> np.ndarray:
    image = _image(image)
    if image.shape[2] != 3:
        raise ValueError(f"detect_chart needs an RGB image (H, W, 3), got {image.shape}")
    if image.dtype.kind == "f":
        return image.astype(np.float32)
    if image.dtype.kind != "u":
        raise ValueError(f"detect_chart needs unsigned integer or float samples, got {image.dtype}")
    return (image / np.iinfo(image.dtype).max).astype(np.float32)


def _patch_candidates(rgb: np.ndarray):
    """Uniform, convex, four-sided regions: centres (K, 2), edge bases (K, 2, 2) whose
    columns are the mean vectors along the two pairs of opposite sides, and areas (K,)."""
    smooth = cv2.GaussianBlur(rgb, (0, 0), 1.0)
    gradient = sum(cv2.Sobel(smooth, cv2.CV_32F, dx, 1 - dx, ksize=3) ** 2 for dx in (0, 1))
    magnitude = np.sqrt(gradient.sum(axis=2)) / 8.0
    # Flat means below four times the typical gradient, which is the noise's.
    threshold = max(0.01, 4.0 * float(np.median(magnitude)))
    flat = (magnitude < threshold).astype(np.uint8)
    count, labels, stats, centroids = cv2.connectedComponentsWithStats(flat, connectivity=4)
    max_area = _MAX_PATCH_SHARE * rgb.shape[0] * rgb.shape[1]
    centres, bases, areas = [], [], []
    for label in range(1, count):
        x, y, w, h, area = stats[label]
        if not _MIN_PATCH_AREA <= area <= max_area:
            continue
        mask = (labels[y : y + h, x : x + w] == label).astype(np.uint8)
        contours, _ = cv2.findContours(mask, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
        hull = cv2.convexHull(max(contours, key=cv2.contourArea))
        if area < _MIN_SOLIDITY * cv2.contourArea(hull):
            continue
        quad = cv2.approxPolyDP(hull, 0.06 * cv2.arcLength(hull, True), True).reshape(-1, 2)
        if len(quad) != 4:
            continue
        sides = np.linalg.norm(np.roll(quad, -1, axis=0) - quad, axis=1)
        if sides.min() < _MIN_SIDE_RATIO * sides.max():
            continue
        quad = quad.astype(np.float64)
        basis = (
            np.column_stack(
                [quad[1] - quad[0] + quad[2] - quad[3], quad[3] - quad[0] + quad[2] - quad[1]]
            )
            / 2.0
        )
        # A four-sided region spans about its area; a kite or a sliver does not.
        if abs(np.linalg.det(basis)) < 0.5 * area:
            continue
        centres.append(centroids[label])
        bases.append(basis)
        areas.append(float(area))
    return np.array(centres).reshape(-1, 2), np.array(bases).reshape(-1, 2, 2), np.array(areas)


def _aligned_bases(bases: np.ndarray, seed: int) -> np.ndarray:
    """Each basis with its edge vectors ordered and signed to follow the seed basis's."""
    reference = bases[seed] / np.linalg.norm(bases[seed], axis=0)
    vectors = np.concatenate([np.swapaxes(bases, 1, 2), -np.swapaxes(bases, 1, 2)], axis=1)
    cosines = (vectors / np.linalg.norm(vectors, axis=2, keepdims=True)) @ reference
    first = np.argmax(cosines[:, :, 0], axis=1)
    # The second vector is along the other pair of sides: the other parity.
    other_side = (np.arange(4)[None, :] % 2) != (first[:, None] % 2)
    second = np.argmax(np.where(other_side, cosines[:, :, 1], -np.inf), axis=1)
    rows = np.arange(len(bases))
    return np.stack([vectors[rows, first], vectors[rows, second]], axis=2)


def _pitch_ratios(centres: np.ndarray, bases: np.ndarray) -> np.ndarray:
    """Each candidate's distance to its nearest neighbour in units of its own edge
    basis: the pitch over the (shrunken) patch side, one value for all of a chart."""
    distances = np.linalg.norm(centres[None, :, :] - centres[:, None, :], axis=2)
    np.fill_diagonal(distances, np.inf)
    nearest = centres[np.argmin(distances, axis=1)] - centres
    return np.abs(np.einsum("kab,kb->ka", np.linalg.inv(bases), nearest)).max(axis=1)


def _lattice(
    centres: np.ndarray, bases: np.ndarray, areas: np.ndarray, ratios: np.ndarray, seed: int
) -> dict:
    """Integer lattice positions {candidate: (i, j)} of the candidates reachable from
    ``seed`` by steps of up to :data:`_MAX_STEP` patches, each measured in the edge basis
    of the patch it starts from, so that the lattice may bend with perspective. The
    pitch is the seed patch's, then the median of the patches so found."""
    inverses = np.linalg.inv(_aligned_bases(bases, seed))
    members = [seed]
    for _ in range(2):
        pitch = np.median(ratios[members])
        positions = {seed: (0, 0)}
        taken = {(0, 0)}
        queue = [seed]
        while queue:
            current = queue.pop(0)
            steps = (centres - centres[current]) @ inverses[current].T / pitch
            rounded = np.rint(steps)
            reach = np.abs(rounded).max(axis=1)
            near = (
                (np.abs(steps - rounded).max(axis=1) < _STEP_TOLERANCE)
                & (reach >= 1)
                & (reach <= _MAX_STEP)
                & (np.abs(np.log(areas / areas[current])) < np.log(_AREA_FACTOR))
            )
            for other in np.flatnonzero(near):
                position = (
                    positions[current][0] + int(rounded[other, 0]),
                    positions[current][1] + int(rounded[other, 1]),
                )
                if other not in positions and position not in taken:
                    positions[other] = position
                    taken.add(position)
                    queue.append(other)
        members = list(positions)
    return positions


def _affine(matrix, translation) -> np.ndarray:
    affine = np.eye(3)
    affine[:2, :2], affine[:2, 2] = matrix, translation
    return affine


# The chart upright, turned by a half turn and by either quarter turn: the map from
# chart lattice coordinates (c, r) to those of the turned chart's 6 x 4 or 4 x 6 block.
_TURNS = tuple(
    _affine(m, t)
    for m, t in (
        ([[1, 0], [0, 1]], [0, 0]),
        ([[-1, 0], [0, -1]], [5, 3]),
        ([[0, -1], [1, 0]], [3, 0]),
        ([[0, 1], [-1, 0]], [0, 5]),
    )
)


def _looks_like_colorchecker(colours: np.ndarray) -> bool:
    """The grey row darkens left to right in every channel, and the blue, green and red
    patches are bluest, greenest and reddest: true under any increasing per-channel
    response and a moderate colour cast, false for the chart turned or misplaced."""
    greys = colours[list(GREY_PATCHES)]
    blue, green, red = colours[_BLUE], colours[_GREEN], colours[_RED]
    return bool(
        np.all(np.diff(greys, axis=0) < 0)
        and blue[2] > blue[:2].max()
        and green[1] > max(green[0], green[2])
        and red[0] > red[1:].max()
    )


def _fit_grid(lattice: np.ndarray, points: np.ndarray, tolerance: float):
    """The homography taking lattice points to image points, refitted without the
    points off it by more than ``tolerance`` pitches (a reflection, an object in front of
    the chart, a square beside it), and the mask of those kept; None if fewer than
    :data:`_MIN_PATCHES` remain."""
    keep = np.ones(len(lattice), dtype=bool)
    while keep.sum() >= _MIN_PATCHES:
        homography, _ = cv2.findHomography(lattice[keep], points[keep], 0)
        if homography is None:
            return None
        pitch = np.sqrt(np.abs(_jacobian_determinant(homography, lattice)))
        residual = np.linalg.norm(_transform(homography, lattice) - points, axis=1)
        off = keep & (residual > tolerance * pitch)
        if not off.any():
            return homography, keep
        keep &= ~off
    return None


def _oriented_chart(rgb: np.ndarray, positions: dict, centres: np.ndarray):
    """The homography from chart lattice coordinates to the image for the turn and
    place of the chart in the found lattice whose colours make a ColorChecker and which
    holds the most found patches, or None."""
    found = list(positions)
    lattice = np.array([positions[k] for k in found])
    points = centres[found]
    low, high = lattice.min(axis=0), lattice.max(axis=0)
    best, most = None, 0
    for turn in _TURNS:
        block = np.rint(np.abs(turn[:2, :2] @ _CHART_LAYOUT)).astype(int)
        for top in range(low[1] - block[1] + 1, high[1] + 1):
            for left in range(low[0] - block[0] + 1, high[0] + 1):
                inside = np.all((lattice >= [left, top]) & (lattice < [left, top] + block), axis=1)
                if inside.sum() <= max(most, _MIN_PATCHES - 1):
                    continue
                fitted = _fit_grid(
                    lattice[inside].astype(np.float64), points[inside], _STEP_TOLERANCE
                )
                if fitted is None:
                    continue
                candidate = fitted[0] @ _affine(np.eye(2), [left, top]) @ turn
                outlines = _sample_outlines(candidate, _CHART_LAYOUT, _TEST_FRACTION)
                if _inside(outlines, rgb.shape) and _looks_like_colorchecker(
                    _patch_means(rgb, candidate, _CHART_LAYOUT, _TEST_FRACTION)
                ):
                    best, most = candidate, int(inside.sum())
    return best


def _refine(rgb: np.ndarray, to_image: np.ndarray):
    """Refit the chart's homography to the patches' centres, found as the centroids of
    their soft membership: the projection of each pixel's colour from the chart body's
    (the median at the junctions between patches) to the patch's. Moments are taken in
    lattice coordinates, where a patch is a square centred on its lattice point and
    whose area is its side squared. Returns (homography, patch side in pitches), or
    None when too few patches stand out or they do not sit on one grid."""
    columns, rows = _CHART_LAYOUT
    lattice = np.stack(np.meshgrid(np.arange(columns), np.arange(rows)), -1)
    lattice = lattice.reshape(-1, 2).astype(np.float64)
    junctions = np.stack(np.meshgrid(np.arange(columns - 1), np.arange(rows - 1)), -1)
    junctions = junctions.reshape(-1, 2) + 0.5
    height, width = rgb.shape[:2]
    for _ in range(_REFINEMENTS):
        if not _inside(_sample_outlines(to_image, _CHART_LAYOUT, _TEST_FRACTION), rgb.shape):
            return None
        means = _patch_means(rgb, to_image, _CHART_LAYOUT, _TEST_FRACTION)
        at = np.rint(_transform(to_image, junctions)).astype(int)
        body = np.median(
            rgb[np.clip(at[:, 1], 0, height - 1), np.clip(at[:, 0], 0, width - 1)], axis=0
        )
        inverse = np.linalg.inv(to_image)
        located, centroids, sides = [], [], []
        for index, centre in enumerate(lattice):
            direction = means[index] - body
            contrast = float(np.linalg.norm(direction))
            if contrast < _MIN_CONTRAST:
                continue
            outline = _transform(to_image, centre + _square(0.5))
            low = np.clip(np.floor(outline.min(axis=0)).astype(int), 0, [width - 1, height - 1])
            high = np.clip(np.ceil(outline.max(axis=0)).astype(int), 0, [width - 1, height - 1])
            ys, xs = np.mgrid[low[1] : high[1] + 1, low[0] : high[0] + 1]
            pixels = np.stack([xs, ys], axis=-1).astype(np.float64)
            cell = _transform(inverse, pixels)
            window = np.all(np.abs(cell - centre) <= 0.5, axis=-1)
            weight = (
                (rgb[ys, xs] - body)
                @ direction
                / contrast**2
                * np.abs(_jacobian_determinant(inverse, pixels))
            )[window]
            area = weight.sum()
            if area <= 0:
                continue
            located.append(index)
            centroids.append(_transform(to_image, weight @ cell[window] / area))
            sides.append(np.sqrt(area))
        fitted = _fit_grid(lattice[located], np.array(centroids).reshape(-1, 2), _MAX_RESIDUAL)
        if fitted is None:
            return None
        to_image, keep = fitted
    return to_image, float(np.median(np.array(sides)[keep]))


def detect_chart(image) -> np.ndarray | None:
    """Find an X-Rite ColorChecker 24 (classic) in an RGB image.

    Uniform four-sided regions are linked into a lattice of patches by steps measured
    in each patch's own edge directions, which follows perspective. The chart's turn
    (by quarter turns) and place in the lattice are those that make the bottom row a
    grey scale darkening from left to right in every channel, with the blue, green and
    red patches where they belong: tests that hold under a colour cast and another
    tone response. The patch centres are then refined to the centroids of each
    patch's soft membership against the black chart body and the chart's homography
    refitted to them; the patch side comes from the membership areas.

    Parameters
    ----------
    image : ndarray, shape (H, W, 3)
        RGB (not BGR): uint8, uint16, or float in [0, 1].

    Returns
    -------
    ndarray, shape (4, 2), or None
        The outer corners of the patch area, (x, y) pixels, as :func:`sample_patches`
        takes them: top-left (at dark skin), top-right, bottom-right (at black) and
        bottom-left of the chart upright, whatever its turn in the image; None when
        no chart is found.

    Raises
    ------
    ValueError
        For an image that is not (H, W, 3).
    """
    rgb = _unit_rgb(image)
    centres, bases, areas = _patch_candidates(rgb)
    if len(centres) < _MIN_PATCHES:
        return None
    ratios = _pitch_ratios(centres, bases)
    best: dict = {}
    linked: set = set()
    for seed in range(len(centres)):
        # A seed inside a lattice already found would only find it again.
        if seed in linked:
            continue
        positions = _lattice(centres, bases, areas, ratios, seed)
        linked.update(positions)
        if len(positions) > len(best):
            best = positions
    if len(best) < _MIN_PATCHES:
        return None
    to_image = _oriented_chart(rgb, best, centres)
    refined = None if to_image is None else _refine(rgb, to_image)
    if refined is None:
        return None
    to_image, side = refined
    columns, rows = _CHART_LAYOUT
    centre = np.array([(columns - 1) / 2.0, (rows - 1) / 2.0])
    return _transform(to_image, centre + _square(0.5) * (np.array([columns, rows]) - 1 + side))


_CURVE_CODES = np.linspace(0.0, 1.0, 256)
_LINEARIZATIONS = ("gamma", "srgb", "grey-curve")
_MODELS = {"3x3": 3, "4x3": 4}


@dataclass(frozen=True)
class ChartCorrection:
    """A colour correction fitted to a chart: per-channel tone curves to linear RGB,
    a colour-correction matrix, and sRGB encoding.

    The matrix acts on row vectors, as OpenCV's ``ccm``:
    ``corrected_linear = linear @ matrix`` (3x3), or ``[linear, 1] @ matrix`` (4x3,
    affine); the result is linear sRGB (D65).

    Attributes
    ----------
    curve : ndarray, shape (3, 256)
        The linear value of each channel at display values ``0, 1/255, ..., 1``;
        linear in between.
    matrix : ndarray, shape (3, 3) or (4, 3)
    delta_e : ndarray, shape (N,)
        CIEDE2000 of each chart patch after correction.
    used : ndarray of bool, shape (N,)
        The patches the fit used: those not saturated.
    """

    curve: np.ndarray
    matrix: np.ndarray
    delta_e: np.ndarray
    used: np.ndarray

    def apply_linear(self, rgb) -> np.ndarray:
        """Corrected linear sRGB, not clipped, shape (..., 3), of display RGB (..., 3)
        in [0, 1] (values outside take the curve's end values)."""
        return _apply_matrix(_apply_curve(self.curve, _colours(rgb, "rgb")), self.matrix)

    def apply(self, rgb) -> np.ndarray:
        """Corrected display RGB: :meth:`apply_linear` clipped to [0, 1], sRGB-encoded.

        Parameters
        ----------
        rgb : array_like, shape (..., 3)
            Display RGB in [0, 1].

        Returns
        -------
        ndarray, shape (..., 3)
            float64 in [0, 1].
        """
        return linear_to_srgb(np.clip(self.apply_linear(rgb), 0.0, 1.0))


def _apply_curve(curve: np.ndarray, rgb: np.ndarray) -> np.ndarray:
    return np.stack([np.interp(rgb[..., c], _CURVE_CODES, curve[c]) for c in range(3)], axis=-1)


def _apply_matrix(linear: np.ndarray, matrix: np.ndarray) -> np.ndarray:
    if len(matrix) == 4:
        return linear @ matrix[:3] + matrix[3]
    return linear @ matrix


def _grey_response(parameters, codes: np.ndarray) -> np.ndarray:
    gain, offset, gamma = parameters
    return srgb_to_linear(gain * np.maximum(codes - offset, 0.0) ** gamma)


def _grey_lightness_error(parameters, codes: np.ndarray, lightness: np.ndarray) -> np.ndarray:
    grey = _grey_response(parameters, codes)
    return xyz_to_lab(grey[:, None] * WHITE_D50, white=WHITE_D50)[:, 0] - lightness


def _grey_curve(
    measured: np.ndarray, reference_lab: np.ndarray, used: np.ndarray, grey_patches: Sequence[int]
) -> np.ndarray:
    """Per channel, the curve ``srgb_to_linear(a * max(v - b, 0) ** g)`` that best gives
    the unsaturated grey patches, in L*, the reference lightness as a neutral grey.

    That is the sRGB decoding after a per-channel gain, offset and gamma on display
    values: a camera whose encoding departs from sRGB by those. Three parameters, with
    ``a, g > 0``, keep the curve increasing where six points could not pin a free one.
    """
    greys = [g for g in grey_patches if used[g]]
    if len(greys) < 3:
        raise DataError(
            f"the grey-curve needs at least 3 unsaturated grey patches, got "
            f"{len(greys)} of {len(grey_patches)}"
        )
    target = reference_lab[greys, 0]
    curve = np.empty((3, _CURVE_CODES.size))
    for channel in range(3):
        values = measured[greys, channel]
        if np.ptp(values) <= 0:
            raise DataError(
                f"the grey patches all measure {values[0]:.4g} in channel "
                f"{channel}; no tone curve can be fitted"
            )
        # From the plain sRGB decoding; the offset stays below the darkest grey.
        fit = scipy.optimize.least_squares(
            _grey_lightness_error,
            x0=[1.0, min(0.0, values.min() - 1e-3), 1.0],
            args=(values, target),
            bounds=([1e-3, -1.0, 0.1], [1e3, values.min() - 1e-6, 10.0]),
        )
        curve[channel] = _grey_response(fit.x, _CURVE_CODES)
    return curve


def _mean_delta_e(parameters, linear, reference_lab, white, shape) -> float:
    corrected = _apply_matrix(linear, parameters.reshape(shape))
    return float(delta_e_2000(linear_rgb_to_lab(corrected, white=white), reference_lab).mean())


def fit_chart_correction(
    measured,
    reference_lab,
    *,
    linearization: str = "gamma",
    gamma: float = 2.2,
    model: str = "3x3",
    white=WHITE_D50,
    saturation: float = 0.98,
    grey_patches: Sequence[int] = GREY_PATCHES,
) -> ChartCorrection:
    """Fit tone curves and a colour-correction matrix that take a chart's measured
    patches to its reference colours.

    The matrix starts from the linear least-squares fit in linear RGB and is refined
    (BFGS) to minimise the mean CIEDE2000 over the patches; OpenCV's
    ``ColorCorrectionModel`` minimises their root mean square instead.

    Parameters
    ----------
    measured : array_like, shape (N, 3)
        Display RGB of the patches in [0, 1] (e.g. :func:`sample_patches` / 255).
    reference_lab : array_like, shape (N, 3)
        The patches' CIELAB relative to ``white``.
    linearization : {"gamma", "srgb", "grey-curve"}
        The per-channel tone curve to linear RGB: ``v ** gamma``
        (:func:`gamma_to_linear`), the sRGB decoding (:func:`srgb_to_linear`), or an
        increasing curve per channel fitted to the grey patches so that they come out
        neutral with the reference lightness.
    gamma : float
        The exponent of "gamma".
    model : {"3x3", "4x3"}
        A linear matrix, or an affine one (a fourth row of offsets).
    white : array_like, shape (3,)
        The white ``reference_lab`` is relative to; D50 for the published ColorChecker.
    saturation : float
        Patches with a measured channel above it are clipped: they are left out of the
        fit (OpenCV's default threshold, 0.98).
    grey_patches : sequence of int
        Indices of the grey scale for "grey-curve"; 18..23 on the ColorChecker 24.

    Returns
    -------
    ChartCorrection

    Raises
    ------
    ValueError
        Bad shapes or options, or measured values outside [0, 1].
    DataError
        Fewer unsaturated patches than the matrix has rows, or, for "grey-curve",
        fewer than 3 unsaturated greys or greys that do not vary in a channel.
    """
    measured = _colours(measured, "measured")
    reference_lab = _colours(reference_lab, "reference_lab")
    if measured.ndim != 2 or measured.shape != reference_lab.shape:
        raise ValueError(
            f"measured and reference_lab must both have shape (N, 3), got "
            f"{measured.shape} and {reference_lab.shape}"
        )
    if not np.all(np.isfinite(measured)) or measured.min() < 0 or measured.max() > 1:
        raise ValueError("measured must be display RGB in [0, 1] (8-bit codes divided by 255)")
    if not np.all(np.isfinite(reference_lab)):
        raise ValueError("reference_lab must be finite")
    if linearization not in _LINEARIZATIONS:
        raise ValueError(
            f"linearization must be one of {', '.join(_LINEARIZATIONS)}, got {linearization!r}"
        )
    if model not in _MODELS:
        raise ValueError(f"model must be one of {', '.join(_MODELS)}, got {model!r}")
    if linearization == "grey-curve" and any(not 0 <= g < len(measured) for g in grey_patches):
        raise ValueError(
            f"grey_patches must index the {len(measured)} patches, got {tuple(grey_patches)}"
        )
    white = _white(white)
    used = np.all(measured <= saturation, axis=1)
    rows = _MODELS[model]
    if used.sum() < rows:
        raise DataError(
            f"only {used.sum()} of {len(measured)} patches are at most the "
            f"saturation {saturation}; a {model} matrix needs {rows}"
        )
    if linearization == "gamma":
        curve = np.tile(gamma_to_linear(_CURVE_CODES, gamma=gamma), (3, 1))
    elif linearization == "srgb":
        curve = np.tile(srgb_to_linear(_CURVE_CODES), (3, 1))
    else:
        curve = _grey_curve(measured, reference_lab, used, grey_patches)
    linear = _apply_curve(curve, measured)
    design = linear if rows == 3 else np.column_stack([linear, np.ones(len(linear))])
    target = lab_to_linear_rgb(reference_lab, white=white)
    start, *_ = np.linalg.lstsq(design[used], target[used], rcond=None)
    fit = scipy.optimize.minimize(
        _mean_delta_e,
        start.ravel(),
        method="BFGS",
        args=(linear[used], reference_lab[used], white, start.shape),
    )
    matrix = fit.x.reshape(start.shape)
    delta_e = delta_e_2000(
        linear_rgb_to_lab(_apply_matrix(linear, matrix), white=white), reference_lab
    )
    return ChartCorrection(curve=curve, matrix=matrix, delta_e=delta_e, used=used)
