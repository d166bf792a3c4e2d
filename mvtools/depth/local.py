"""Local matching by guided-filter cost aggregation (Hosni, Rhemann, Bleyer, Rother &
Gelautz 2011): every cost slice is filtered with the colour guided filter of He, Sun &
Tang (2010), an edge-preserving average whose support follows the guide's colour
regions, so windows do not straddle depth edges the way plain boxes do."""

from __future__ import annotations

import cv2
import numpy as np

__all__ = ["local_volume", "guided_filter"]

# OpenCV filters images of at most 512 channels.
_CHANNELS = 512


def _box(image: np.ndarray, radius: int) -> np.ndarray:
    # normalised (2r+1)^2 mean, borders reflected; every level of a volume at once
    size = (2 * radius + 1, 2 * radius + 1)
    if image.ndim < 3 or image.shape[2] <= _CHANNELS:
        return cv2.boxFilter(image, -1, size, borderType=cv2.BORDER_REFLECT)
    return np.concatenate([cv2.boxFilter(np.ascontiguousarray(image[:, :, start:start + _CHANNELS]),
                                         -1, size, borderType=cv2.BORDER_REFLECT)
                           for start in range(0, image.shape[2], _CHANNELS)], axis=2)


def guided_filter(volume: np.ndarray, guide: np.ndarray, *, radius: int,
                  epsilon: float) -> np.ndarray:
    """Colour guided filter of every slice of a volume.

    ``q = mean(a) . I + mean(b)`` with, per window, ``a = (Sigma + epsilon Id)^-1
    cov(I, p)`` and ``b = mean(p) - a . mean(I)``.

    Parameters
    ----------
    volume : ndarray of float32, shape (H, W, D)
        Slices ``p`` to filter.
    guide : ndarray of float32, shape (H, W, 3)
        Colour guide ``I``, values in [0, 1].
    radius : int
        Window half size, at least 1.
    epsilon : float
        Regularisation of the colour covariance ``Sigma``: colour variations well below
        ``sqrt(epsilon)`` are treated as flat, so the filter averages there; positive.

    Returns
    -------
    ndarray of float32, shape (H, W, D)
    """
    if radius < 1 or epsilon <= 0:
        raise ValueError(f"guided filter needs radius >= 1 and epsilon > 0, got {radius} and "
                         f"{epsilon}")
    guide = np.ascontiguousarray(guide, dtype=np.float32)
    volume = np.ascontiguousarray(volume, dtype=np.float32)
    mean_guide = _box(guide, radius)
    covariance = np.empty(guide.shape[:2] + (3, 3), np.float32)
    for i in range(3):
        for j in range(i, 3):
            covariance[:, :, i, j] = covariance[:, :, j, i] = (
                _box(guide[:, :, i] * guide[:, :, j], radius)
                - mean_guide[:, :, i] * mean_guide[:, :, j])
    inverse = np.linalg.inv(covariance + epsilon * np.eye(3, dtype=np.float32))
    mean_volume = _box(volume, radius)
    cross = [_box(guide[:, :, [i]] * volume, radius) - mean_guide[:, :, [i]] * mean_volume
             for i in range(3)]
    offset = mean_volume
    filtered = np.zeros_like(volume)
    for i in range(3):
        slope = sum(inverse[:, :, i, [j]] * cross[j] for j in range(3))
        offset = offset - slope * mean_guide[:, :, [i]]
        filtered += _box(slope, radius) * guide[:, :, [i]]
    return filtered + _box(offset, radius)


def local_volume(cost: np.ndarray, guide: np.ndarray, *, radius: int = 8,
                 epsilon: float = 1e-4) -> np.ndarray:
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

    Returns
    -------
    ndarray of float32, shape (H, W, D)
        Aggregated costs; their per-pixel minimum is the winner-takes-all level.
    """
    return guided_filter(cost, np.asarray(guide, np.float32) / 255.0, radius=radius,
                         epsilon=epsilon)
