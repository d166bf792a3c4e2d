"""Local matching by guided-filter cost aggregation (Hosni, Rhemann, Bleyer, Rother &
Gelautz 2011): every cost slice is filtered with the colour guided filter of He, Sun &
Tang (2010), an edge-preserving average whose support follows the guide's colour
regions, so windows do not straddle depth edges the way plain boxes do."""

from __future__ import annotations

from collections.abc import Callable, Iterator

import cv2
import numpy as np
from numba import njit, prange

__all__ = [
    "LevelSlices",
    "guided_filter",
    "guided_filter_levels",
    "local_levels",
    "local_volume",
    "soft_segment_aggregate",
]

# OpenCV (5) filters images of at most 128 channels.
_CHANNELS = 128

#: Bytes of one level chunk of :func:`guided_filter` (a few levels of a large frame).
_CHUNK_BYTES = 1 << 24


def _box(image: np.ndarray, radius: int) -> np.ndarray:
    # normalised (2r+1)^2 mean, borders reflected; every level of a volume at once
    size = (2 * radius + 1, 2 * radius + 1)
    if image.ndim < 3 or image.shape[2] <= _CHANNELS:
        # (OpenCV drops a single channel's axis)
        return cv2.boxFilter(image, -1, size, borderType=cv2.BORDER_REFLECT).reshape(image.shape)
    return np.concatenate(
        [
            cv2.boxFilter(
                np.ascontiguousarray(image[:, :, start : start + _CHANNELS]),
                -1,
                size,
                borderType=cv2.BORDER_REFLECT,
            )
            for start in range(0, image.shape[2], _CHANNELS)
        ],
        axis=2,
    )


#: ``levels(start, stop)``: the (H, W, stop - start) float32 slices of levels ``start`` to
#: ``stop`` of a volume, e.g. ``lambda start, stop: volume[:, :, start:stop]``.
LevelSlices = Callable[[int, int], np.ndarray]


def guided_filter_levels(
    levels: LevelSlices, count: int, guide: np.ndarray, *, radius: int, epsilon: float
) -> Iterator[tuple[int, np.ndarray]]:
    """Colour guided filter of the slices of a volume given a few levels at a time.

    ``q = mean(a) . I + mean(b)`` with, per window, ``a = (Sigma + epsilon Id)^-1
    cov(I, p)`` and ``b = mean(p) - a . mean(I)``.

    Parameters
    ----------
    levels : callable
        ``levels(start, stop)`` gives the slices ``p`` of levels ``start`` to ``stop``,
        shape (H, W, stop - start) (:data:`LevelSlices`).
    count : int
        Number of levels D.
    guide : ndarray of float32, shape (H, W, 3)
        Colour guide ``I``, values in [0, 1].
    radius : int
        Window half size, at least 1.
    epsilon : float
        Regularisation of the colour covariance ``Sigma``: colour variations well below
        ``sqrt(epsilon)`` are treated as flat, so the filter averages there; positive.

    Returns
    -------
    iterator of (int, ndarray of float32, shape (H, W, n))
        The first level of each chunk and its filtered slices, in order of level; the
        guide's statistics are computed before the first chunk.
    """
    if radius < 1 or epsilon <= 0:
        raise ValueError(
            f"guided filter needs radius >= 1 and epsilon > 0, got {radius} and {epsilon}"
        )
    guide = np.ascontiguousarray(guide, dtype=np.float32)
    mean_guide = _box(guide, radius)
    covariance = np.empty(guide.shape[:2] + (3, 3), np.float32)
    for i in range(3):
        for j in range(i, 3):
            covariance[:, :, i, j] = covariance[:, :, j, i] = (
                _box(guide[:, :, i] * guide[:, :, j], radius)
                - mean_guide[:, :, i] * mean_guide[:, :, j]
            )
    inverse = np.linalg.inv(covariance + epsilon * np.eye(3, dtype=np.float32))
    # A few levels at a time: every step is per level, so the filtered levels are the
    # same whatever the chunk, and the temporaries stay small beside the volume.
    chunk = min(_CHANNELS, max(1, _CHUNK_BYTES // max(1, guide.shape[0] * guide.shape[1] * 4)))

    def chunks():
        for start in range(0, count, chunk):
            part = np.ascontiguousarray(levels(start, min(start + chunk, count)), np.float32)
            mean_volume = _box(part, radius)
            cross = [
                _box(guide[:, :, [i]] * part, radius) - mean_guide[:, :, [i]] * mean_volume
                for i in range(3)
            ]
            offset = mean_volume
            filtered = np.zeros_like(part)
            for i in range(3):
                slope = sum(inverse[:, :, i, [j]] * cross[j] for j in range(3))
                offset = offset - slope * mean_guide[:, :, [i]]
                filtered += _box(slope, radius) * guide[:, :, [i]]
            yield start, filtered + _box(offset, radius)

    return chunks()


def guided_filter(
    volume: np.ndarray,
    guide: np.ndarray,
    *,
    radius: int,
    epsilon: float,
    out: np.ndarray | None = None,
) -> np.ndarray:
    """Colour guided filter of every slice of a volume (:func:`guided_filter_levels`).

    Parameters
    ----------
    volume : ndarray of float32, shape (H, W, D)
        Slices ``p`` to filter.
    guide : ndarray of float32, shape (H, W, 3)
        Colour guide ``I``, values in [0, 1].
    radius, epsilon
        As for :func:`guided_filter_levels`.
    out : ndarray of float32, shape (H, W, D), optional
        Where to write the result; it may be ``volume`` itself (in place), as the
        levels are filtered a few at a time.

    Returns
    -------
    ndarray of float32, shape (H, W, D)
        ``out`` if given.
    """
    volume = np.ascontiguousarray(volume, dtype=np.float32)
    result = np.empty_like(volume) if out is None else out
    for start, filtered in guided_filter_levels(
        lambda start, stop: volume[:, :, start:stop],
        volume.shape[2],
        guide,
        radius=radius,
        epsilon=epsilon,
    ):
        result[:, :, start : start + filtered.shape[2]] = filtered
    return result


def local_levels(
    levels: LevelSlices,
    count: int,
    guide: np.ndarray,
    *,
    radius: int = 8,
    epsilon: float = 1e-4,
) -> Iterator[tuple[int, np.ndarray]]:
    """The ``local`` method's volume a few levels at a time, from costs given a few levels
    at a time, so that neither is held whole: the chunks of :func:`local_volume`.

    Parameters
    ----------
    levels : callable
        ``levels(start, stop)``: the matching costs of levels ``start`` to ``stop``
        (:data:`LevelSlices`).
    count : int
        Number of levels D.
    guide, radius, epsilon
        As for :func:`local_volume`.

    Returns
    -------
    iterator of (int, ndarray of float32, shape (H, W, n))
        The first level of each chunk and its aggregated costs, in order of level.
    """
    return guided_filter_levels(levels, count, _unit_guide(guide), radius=radius, epsilon=epsilon)


def _unit_guide(guide: np.ndarray) -> np.ndarray:
    # the guided filter's epsilon is stated for colours in [0, 1]
    return np.asarray(guide, np.float32) / 255.0


def local_volume(
    cost: np.ndarray,
    guide: np.ndarray,
    *,
    radius: int = 8,
    epsilon: float = 1e-4,
    overwrite: bool = False,
) -> np.ndarray:
    """The ``local`` method: the cost volume aggregated by the guided filter.

    Parameters
    ----------
    cost : ndarray of float32, shape (H, W, D)
        Matching costs, e.g. AD-census in [0, 2].
    guide : ndarray, shape (H, W, 3)
        The view the costs belong to, values in [0, 255].
    radius : int
        Window half size.
    epsilon : float
        Guided filter regularisation, for colours in [0, 1].
    overwrite : bool
        Write the result into ``cost`` (a contiguous float32 volume), which is then lost:
        one volume in memory instead of two.

    Returns
    -------
    ndarray of float32, shape (H, W, D)
        Aggregated costs; their per-pixel minimum is the winner-takes-all level.
    """
    cost = np.ascontiguousarray(cost, dtype=np.float32)
    return guided_filter(
        cost,
        _unit_guide(guide),
        radius=radius,
        epsilon=epsilon,
        out=cost if overwrite else None,
    )


@njit(cache=True, nogil=True, parallel=True)
def _soft_segment(cost, colour, up, down, left, right, distance_coeff, colour_coeff):
    rows, cols, levels = cost.shape
    result = np.empty_like(cost)
    for y in prange(rows):
        sums = np.empty(levels, np.float64)
        for x in range(cols):
            sums[:] = 0.0
            total = 0.0
            for qy in range(max(0, y - up), min(rows, y + down + 1)):
                for qx in range(max(0, x - left), min(cols, x + right + 1)):
                    difference = (
                        abs(colour[qy, qx, 0] - colour[y, x, 0])
                        + abs(colour[qy, qx, 1] - colour[y, x, 1])
                        + abs(colour[qy, qx, 2] - colour[y, x, 2])
                    ) / 3.0
                    distance = np.sqrt((qy - y) ** 2 + (qx - x) ** 2)
                    weight = np.exp(-distance / distance_coeff - difference / colour_coeff)
                    total += weight
                    for k in range(levels):
                        sums[k] += weight * cost[qy, qx, k]
            for k in range(levels):
                result[y, x, k] = sums[k] / total
    return result


def soft_segment_aggregate(
    cost: np.ndarray,
    guide: np.ndarray,
    *,
    block: tuple[int, int] = (3, 3),
    distance_coeff: float = 20.0,
    colour_coeff: float = 20.0,
) -> np.ndarray:
    """DERS's soft-segment matching (MatchingMethod 3): each pixel's costs averaged over
    a block with adaptive support weights ``exp(-distance / distance_coeff -
    colour / colour_coeff)``, so that pixels of another colour, likely on another
    surface, count less.

    Parameters
    ----------
    cost : ndarray, shape (H, W, D)
        Matching costs.
    guide : ndarray, shape (H, W, 3)
        The view the costs belong to; ``colour`` is its mean absolute channel
        difference to the block's centre.
    block : (int, int)
        Block width and height (SoftBlockWidth, SoftBlockHeight), around the pixel;
        even sizes reach one pixel further to the right and bottom.
    distance_coeff, colour_coeff : float
        SoftDistanceCoeff (pixels) and SoftColorCoeff (grey levels), positive.

    Returns
    -------
    ndarray of float32, shape (H, W, D)
    """
    width, height = block
    if width < 1 or height < 1 or distance_coeff <= 0 or colour_coeff <= 0:
        raise ValueError(
            f"need a block of at least 1x1 and positive coefficients, got "
            f"{block}, {distance_coeff}, {colour_coeff}"
        )
    cost = np.ascontiguousarray(cost, np.float32)
    guide = np.ascontiguousarray(guide, np.float32)
    if cost.ndim != 3 or guide.shape != cost.shape[:2] + (3,):
        raise ValueError(
            f"cost must be (H, W, D) and guide (H, W, 3) of the same H, W, got "
            f"{cost.shape} and {guide.shape}"
        )
    return _soft_segment(
        cost,
        guide,
        (height - 1) // 2,
        height // 2,
        (width - 1) // 2,
        width // 2,
        float(distance_coeff),
        float(colour_coeff),
    )
