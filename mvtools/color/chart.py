"""The ColorChecker 24: its layout, its detection in a picture and the sampling of its
patches.

The chart seen upright has 6 columns and 4 rows of patches, numbered row by row from
the top-left (dark skin, light skin, ...); the bottom row is the grey scale, white to
black (patches 18..23). Its *patch area* is bounded by the outer corners of the four
corner patches. Image points are (x, y) pixels with pixel centres at integer
coordinates (OpenCV's convention).
"""

from __future__ import annotations

import cv2
import numpy as np

__all__ = ["GREY_PATCHES", "detect_chart", "sample_patches"]

# The ColorChecker 24: grid, grey-scale patches and the patches used to recognise it.
_CHART_LAYOUT = (6, 4)
GREY_PATCHES = tuple(range(18, 24))
_BLUE, _GREEN, _RED = 12, 13, 14


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
