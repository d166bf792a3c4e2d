"""PatchMatch stereo with slanted support windows (Bleyer, Rhemann & Rother, BMVC 2011).

Every pixel of each view carries a disparity plane ``d = a x + b y + c``. Its cost is the
sum, over a support window, of adaptive-support-weighted matching costs of the window's
pixels at the sub-pixel positions the plane gives them in the other view. Planes start
random; each iteration passes good planes to the next pixels along rows and along
columns, tries each plane's image in the other view, and perturbs the planes with
halving ranges. Rows (or columns) run in parallel, each one sequentially, and the random
numbers come from a hash of the pixel, iteration and draw, so the output does not depend
on the threads.
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

from mvtools.depth.cost import as_colour, census_transform, check_pair, popcount

__all__ = ["patchmatch_planes", "plane_disparity"]

_LEFT, _RIGHT = -1.0, 1.0  # x in the other view = x + side * d


@njit(cache=True, nogil=True, inline="always")
def _uniform(y, x, step, draw):
    # splitmix64 finaliser of the draw's coordinates: a counter-based generator, the same
    # numbers whatever thread asks for them
    h = (np.uint64(y) * np.uint64(0x9E3779B97F4A7C15)) ^ (
        np.uint64(x) * np.uint64(0xC2B2AE3D27D4EB4F)
    )
    h ^= np.uint64(step) * np.uint64(0x165667B19E3779F9) + np.uint64(draw) * np.uint64(
        0x27D4EB2F165667C5
    )
    h ^= h >> np.uint64(30)
    h *= np.uint64(0xBF58476D1CE4E5B9)
    h ^= h >> np.uint64(27)
    h *= np.uint64(0x94D049BB133111EB)
    h ^= h >> np.uint64(31)
    return np.float64(h >> np.uint64(11)) * (1.0 / 9007199254740992.0)


@njit(cache=True, nogil=True)
def _window_cost(
    image,
    other,
    census,
    other_census,
    y,
    x,
    a,
    b,
    c,
    side,
    radius,
    stride,
    weight_table,
    alpha,
    tau_colour,
    tau_gradient,
    census_table,
    bound,
):
    # Adaptive support weights exp(-|I_p - I_q|_1 / gamma) (tabulated) times the truncated
    # colour and gradient differences at q's match, linearly interpolated; stops early
    # once the sum exceeds ``bound``, all terms being non-negative. ``image`` and ``other``
    # hold red, green, blue and the horizontal grey gradient of each view; the census
    # signatures' Hamming distance at the nearest column, through ``census_table``, adds
    # a term that does not depend on the cameras' gains.
    rows, cols, _ = image.shape
    red, green, blue = image[y, x, 0], image[y, x, 1], image[y, x, 2]
    outside = (1.0 - alpha) * tau_colour + alpha * tau_gradient + census_table[-1]
    total = 0.0
    first = -(radius // stride) * stride  # the lattice through the centre
    for wy in range(first, radius + 1, stride):
        qy = y + wy
        if qy < 0 or qy >= rows:
            continue
        offset = b * qy + c
        for wx in range(first, radius + 1, stride):
            qx = x + wx
            if qx < 0 or qx >= cols:
                continue
            weight = weight_table[
                int(
                    abs(image[qy, qx, 0] - red)
                    + abs(image[qy, qx, 1] - green)
                    + abs(image[qy, qx, 2] - blue)
                )
            ]
            match = qx + side * (a * qx + offset)
            if match < 0.0 or match > cols - 1:
                total += weight * outside
                continue
            x0 = min(int(match), cols - 2)
            f = np.float32(match - x0)
            g = np.float32(1.0) - f
            difference = (
                abs(image[qy, qx, 0] - g * other[qy, x0, 0] - f * other[qy, x0 + 1, 0])
                + abs(image[qy, qx, 1] - g * other[qy, x0, 1] - f * other[qy, x0 + 1, 1])
                + abs(image[qy, qx, 2] - g * other[qy, x0, 2] - f * other[qy, x0 + 1, 2])
            )
            slope = abs(image[qy, qx, 3] - g * other[qy, x0, 3] - f * other[qy, x0 + 1, 3])
            hamming = popcount(census[qy, qx] ^ other_census[qy, x0 + int(f >= 0.5)])
            total += weight * (
                (1.0 - alpha) * min(difference, tau_colour)
                + alpha * min(slope, tau_gradient)
                + census_table[hamming]
            )
        if total > bound:
            return total
    return total


@njit(cache=True, nogil=True)
def _try(
    planes,
    costs,
    views,
    side,
    y,
    x,
    a,
    b,
    c,
    low,
    high,
    radius,
    stride,
    weight_table,
    alpha,
    tau_colour,
    tau_gradient,
    census_table,
):
    # Adopt plane (a, b, c) at (y, x) if its centre disparity is in range and it costs less.
    disparity = a * x + b * y + c
    if disparity < low or disparity > high:
        return False
    if a == planes[y, x, 0] and b == planes[y, x, 1] and c == planes[y, x, 2]:
        return False
    cost = _window_cost(
        views[0],
        views[1],
        views[2],
        views[3],
        y,
        x,
        a,
        b,
        c,
        side,
        radius,
        stride,
        weight_table,
        alpha,
        tau_colour,
        tau_gradient,
        census_table,
        costs[y, x],
    )
    if cost < costs[y, x]:
        planes[y, x, 0], planes[y, x, 1], planes[y, x, 2] = a, b, c
        costs[y, x] = cost
        return True
    return False


@njit(cache=True, nogil=True, inline="always")
def _plane_from_normal(y, x, disparity, nx, ny, nz):
    # plane through (x, y, disparity) with normal (nx, ny, nz), nz > 0
    a = -nx / nz
    b = -ny / nz
    return a, b, disparity - a * x - b * y


@njit(cache=True, nogil=True, inline="always")
def _random_plane(y, x, step, draw, low, high, min_normal_z):
    # random centre disparity and a random normal of the upper half sphere, not steeper
    # than ``min_normal_z``
    disparity = low + (high - low) * _uniform(y, x, step, draw)
    nz = min_normal_z + (1.0 - min_normal_z) * _uniform(y, x, step, draw + 1)
    angle = 2.0 * np.pi * _uniform(y, x, step, draw + 2)
    across = np.sqrt(1.0 - nz * nz)
    return _plane_from_normal(y, x, disparity, across * np.cos(angle), across * np.sin(angle), nz)


@njit(cache=True, nogil=True, parallel=True)
def _initialise(
    planes,
    costs,
    views,
    side,
    initial,
    low,
    high,
    step,
    radius,
    stride,
    weight_table,
    alpha,
    tau_colour,
    tau_gradient,
    census_table,
    min_normal_z,
):
    # a random plane, replaced by the fronto-parallel plane of the initial disparity
    # where that costs less
    rows, cols = costs.shape
    for y in prange(rows):
        for x in range(cols):
            a, b, c = _random_plane(y, x, step, 0, low, high, min_normal_z)
            planes[y, x, 0], planes[y, x, 1], planes[y, x, 2] = a, b, c
            costs[y, x] = _window_cost(
                views[0],
                views[1],
                views[2],
                views[3],
                y,
                x,
                a,
                b,
                c,
                side,
                radius,
                stride,
                weight_table,
                alpha,
                tau_colour,
                tau_gradient,
                census_table,
                np.inf,
            )
            if np.isfinite(initial[y, x]):
                _try(
                    planes,
                    costs,
                    views,
                    side,
                    y,
                    x,
                    0.0,
                    0.0,
                    initial[y, x],
                    low,
                    high,
                    radius,
                    stride,
                    weight_table,
                    alpha,
                    tau_colour,
                    tau_gradient,
                    census_table,
                )


@njit(cache=True, nogil=True)
def _refine(
    planes,
    costs,
    views,
    side,
    y,
    x,
    step,
    low,
    high,
    min_normal_z,
    radius,
    stride,
    weight_table,
    alpha,
    tau_colour,
    tau_gradient,
    census_table,
):
    # Perturb the best plane's centre disparity and normal within ranges halved each try,
    # from half the disparity range down to a tenth of a pixel.
    a, b, c = planes[y, x, 0], planes[y, x, 1], planes[y, x, 2]
    disparity_range = 0.5 * (high - low)
    normal_range = 1.0
    draw = 8
    while disparity_range >= 0.1:
        a, b, c = planes[y, x, 0], planes[y, x, 1], planes[y, x, 2]
        scale = 1.0 / np.sqrt(a * a + b * b + 1.0)
        nx = -a * scale + normal_range * (2.0 * _uniform(y, x, step, draw) - 1.0)
        ny = -b * scale + normal_range * (2.0 * _uniform(y, x, step, draw + 1) - 1.0)
        nz = scale + normal_range * (2.0 * _uniform(y, x, step, draw + 2) - 1.0)
        norm = np.sqrt(nx * nx + ny * ny + nz * nz)
        disparity = (
            a * x + b * y + c + disparity_range * (2.0 * _uniform(y, x, step, draw + 3) - 1.0)
        )
        draw += 4
        if norm > 0.0 and nz / norm >= min_normal_z:
            na, nb, nc = _plane_from_normal(y, x, disparity, nx / norm, ny / norm, nz / norm)
            _try(
                planes,
                costs,
                views,
                side,
                y,
                x,
                na,
                nb,
                nc,
                low,
                high,
                radius,
                stride,
                weight_table,
                alpha,
                tau_colour,
                tau_gradient,
                census_table,
            )
        disparity_range *= 0.5
        normal_range *= 0.5


@njit(cache=True, nogil=True, parallel=True)
def _sweep_rows(
    planes,
    costs,
    views,
    side,
    forward,
    low,
    high,
    radius,
    stride,
    weight_table,
    alpha,
    tau_colour,
    tau_gradient,
    census_table,
):
    # each row in parallel, its pixels in sweep order: the previous pixel's plane
    rows, cols = costs.shape
    dx = 1 if forward else -1
    for y in prange(rows):
        x = 0 if forward else cols - 1
        for _ in range(cols - 1):
            x += dx
            _try(
                planes,
                costs,
                views,
                side,
                y,
                x,
                planes[y, x - dx, 0],
                planes[y, x - dx, 1],
                planes[y, x - dx, 2],
                low,
                high,
                radius,
                stride,
                weight_table,
                alpha,
                tau_colour,
                tau_gradient,
                census_table,
            )


@njit(cache=True, nogil=True, parallel=True)
def _sweep_columns(
    planes,
    costs,
    views,
    side,
    forward,
    step,
    low,
    high,
    min_normal_z,
    radius,
    stride,
    weight_table,
    alpha,
    tau_colour,
    tau_gradient,
    census_table,
):
    # each column in parallel, its pixels in sweep order: the previous pixel's plane, then
    # the refinement
    rows, cols = costs.shape
    dy = 1 if forward else -1
    for x in prange(cols):
        y = 0 if forward else rows - 1
        for i in range(rows):
            if i > 0:
                _try(
                    planes,
                    costs,
                    views,
                    side,
                    y,
                    x,
                    planes[y - dy, x, 0],
                    planes[y - dy, x, 1],
                    planes[y - dy, x, 2],
                    low,
                    high,
                    radius,
                    stride,
                    weight_table,
                    alpha,
                    tau_colour,
                    tau_gradient,
                    census_table,
                )
            _refine(
                planes,
                costs,
                views,
                side,
                y,
                x,
                step,
                low,
                high,
                min_normal_z,
                radius,
                stride,
                weight_table,
                alpha,
                tau_colour,
                tau_gradient,
                census_table,
            )
            y += dy


@njit(cache=True, nogil=True, parallel=True)
def _view_propagation(
    source,
    planes,
    costs,
    views,
    side,
    low,
    high,
    radius,
    stride,
    weight_table,
    alpha,
    tau_colour,
    tau_gradient,
    census_table,
):
    # Each source pixel's plane, seen from the other view, is a candidate at its match.
    # Writes stay on the source pixel's row, visited in order.
    rows, cols = costs.shape
    for y in prange(rows):
        for x in range(cols):
            a, b, c = source[y, x, 0], source[y, x, 1], source[y, x, 2]
            # ``side`` is the target's: x_t = x - side d and d = a (x_t + side d) + b y + c
            scale = 1.0 - side * a
            if scale <= 0.1:
                continue
            match = int(np.rint(x - side * (a * x + b * y + c)))
            if match < 0 or match >= cols:
                continue
            _try(
                planes,
                costs,
                views,
                side,
                y,
                match,
                a / scale,
                b / scale,
                c / scale,
                low,
                high,
                radius,
                stride,
                weight_table,
                alpha,
                tau_colour,
                tau_gradient,
                census_table,
            )


def plane_disparity(planes: np.ndarray) -> np.ndarray:
    """Disparity of every pixel from its own plane.

    Parameters
    ----------
    planes : ndarray, shape (H, W, 3)
        ``(a, b, c)`` of ``d = a x + b y + c`` per pixel (x the column, y the row).

    Returns
    -------
    ndarray of float32, shape (H, W)
    """
    rows, cols = planes.shape[:2]
    y, x = np.mgrid[:rows, :cols]
    return (planes[..., 0] * x + planes[..., 1] * y + planes[..., 2]).astype(np.float32)


def patchmatch_planes(
    left: np.ndarray,
    right: np.ndarray,
    *,
    min_disparity: float,
    max_disparity: float,
    iterations: int = 3,
    radius: int = 18,
    stride: int = 3,
    gamma: float = 10.0,
    alpha: float = 0.9,
    tau_colour: float = 10.0,
    tau_gradient: float = 2.0,
    census_weight: float = 1.0,
    census_saturation: float = 32.0,
    max_slant: float = 45.0,
    initial: tuple[np.ndarray, np.ndarray] | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Disparity planes of both views of a rectified pair by PatchMatch stereo.

    Parameters
    ----------
    left, right : ndarray, shape (H, W, 3) or (H, W)
        Rectified views of the same size, integer values (RGB or grey).
    min_disparity, max_disparity : float
        Range of the disparity at each pixel (``x_right = x_left - d``).
    iterations : int
        Sweeps, alternately from the top left and from the bottom right.
    radius, stride : int
        The support window holds the pixels at the multiples of ``stride`` from
        ``-radius`` to ``radius`` in both directions: a sparser window costs less time.
    gamma : float
        Colour distance (L1 over the channels) at which a window pixel's weight falls to 1/e.
    alpha, tau_colour, tau_gradient : float
        Matching cost ``(1 - alpha) min(|dI|_1, tau_colour) + alpha min(|dgx|, tau_gradient)``
        of colours and horizontal grey gradients.
    census_weight, census_saturation : float
        Plus ``census_weight * min(hamming / census_saturation, 1)``, the Hamming distance
        of the 7x9 census signatures (:func:`mvtools.depth.cost.census_transform`) at the
        nearest column: robust to gain differences between the cameras.
    max_slant : float
        Largest angle, in degrees, between a plane's normal and the viewing direction.
    initial : (ndarray, ndarray), shapes (H, W), optional
        Disparities of the left and right views from another matcher (NaN where none):
        their fronto-parallel planes replace the random start where they cost less.

    Returns
    -------
    planes_left, planes_right : ndarray of float64, shape (H, W, 3)
        ``(a, b, c)`` of each pixel's plane ``d = a x + b y + c`` in its own view.

    Notes
    -----
    Bad 1.0 (%, Middlebury protocol) of :func:`mvtools.depth.estimate_disparity` with
    ``method="patchmatch"`` (started from ``sgm``, integer output after the clean-up)
    on the seven pairs together, rounding after the clean-up in this comparison:

    ===================================  =====  =====  =====  =====  ====  =====  =====  ====
    gamma, census, radius/stride         Tsuk.  Venus  Teddy  Cones  Art   Dolls  Moeb.  mean
    ===================================  =====  =====  =====  =====  ====  =====  =====  ====
    10, none, 17/2 (the paper's cost)    2.27   1.53   6.21   2.84   7.38  4.41   9.38   4.86
    20, none, 17/2                       2.40   0.89   6.02   2.73   7.74  5.31   10.66  5.11
    20, 1, 17/2                          2.44   0.98   5.04   2.50   6.73  5.05   9.61   4.62
    20, 1, 18/3                          2.32   0.72   5.18   2.46   6.83  5.01   9.68   4.60
    15, 1, 18/3                          2.30   0.77   5.20   2.34   6.65  4.40   9.24   4.42
    10, 1, 18/3 (the defaults)           2.24   0.81   5.50   2.38   6.38  3.84   8.36   4.22
    the same, 2 iterations               2.19   0.78   5.67   2.42   6.33  3.93   8.40   4.25
    the same, random start only          2.17   1.66   6.93   3.01   6.80  4.05   8.24   4.69
    20, 1, 20/4                                                                          4.93
    ===================================  =====  =====  =====  =====  ====  =====  =====  ====

    The census term is the largest gain (Teddy, Art, Moebius); every third pixel of a
    37x37 window scores as every second of a 35x35 one for half the time (about 7 s per
    Cones pair on two cores). Slants beyond 45 degrees (``max_slant`` 80) find
    degenerate planes that squeeze the window onto a few pixels of uniform colour:
    Teddy 9.60 instead of 8.63 without the sgm start. Filling rejected pixels from the
    neighbours' planes rather than their values scored worse on five of the seven
    pairs (Venus 0.81 to 1.60), so the fill takes values as for the other methods.
    """
    left, right = check_pair(left, right, min_disparity=min_disparity, max_disparity=max_disparity)
    if iterations < 1 or radius < 0 or stride < 1:
        raise ValueError(
            f"iterations and stride must be positive and radius non-negative, got "
            f"{iterations}, {stride} and {radius}"
        )
    if not 0.0 <= max_slant < 90.0:
        raise ValueError(f"max_slant must be in [0, 90) degrees, got {max_slant}")
    # integer-valued floats, for the colour weight table
    colours = [as_colour(view).astype(np.float32) for view in (left, right)]
    images = [
        np.ascontiguousarray(
            np.dstack([colour, np.gradient(colour.mean(axis=2), axis=1)]), np.float32
        )
        for colour in colours
    ]
    largest = int(max(colours[0].max(), colours[1].max(), 0))
    weight_table = np.exp(-np.arange(3 * largest + 1) / gamma)
    min_normal_z = float(np.cos(np.radians(max_slant)))
    low, high = float(min_disparity), float(max_disparity)
    census_table = census_weight * np.minimum(np.arange(65) / census_saturation, 1.0)
    options = (
        int(radius),
        int(stride),
        weight_table,
        float(alpha),
        float(tau_colour),
        float(tau_gradient),
        census_table,
    )
    rows, cols = left.shape[:2]
    planes = [np.empty((rows, cols, 3)) for _ in range(2)]
    costs = [np.empty((rows, cols)) for _ in range(2)]
    sides = (_LEFT, _RIGHT)
    census = [census_transform(colour.mean(axis=2)) for colour in colours]
    views = [(images[v], images[1 - v], census[v], census[1 - v]) for v in range(2)]
    if initial is None:
        initial = (np.full((rows, cols), np.nan),) * 2
    elif len(initial) != 2 or any(np.shape(start) != (rows, cols) for start in initial):
        raise ValueError(f"initial must be two ({rows}, {cols}) disparity maps")
    for v in range(2):
        _initialise(
            planes[v],
            costs[v],
            views[v],
            sides[v],
            np.ascontiguousarray(initial[v], np.float64),
            low,
            high,
            v,
            *options,
            min_normal_z,
        )
    for iteration in range(iterations):
        forward = iteration % 2 == 0
        for v in range(2):
            step = 2 + 2 * iteration + v
            _sweep_rows(planes[v], costs[v], views[v], sides[v], forward, low, high, *options)
            _sweep_columns(
                planes[v],
                costs[v],
                views[v],
                sides[v],
                forward,
                step,
                low,
                high,
                min_normal_z,
                *options,
            )
            _view_propagation(
                planes[v],
                planes[1 - v],
                costs[1 - v],
                views[1 - v],
                sides[1 - v],
                low,
                high,
                *options,
            )
    return planes[0], planes[1]
