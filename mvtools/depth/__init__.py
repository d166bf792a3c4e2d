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

from mvtools.depth.bp import bp_volume
from mvtools.depth.cost import ad_census_cost
from mvtools.depth.graphcut import graphcut_volume
from mvtools.depth.local import local_volume
from mvtools.depth.patchmatch import patchmatch_planes, plane_disparity
from mvtools.depth.refine import clean_up, refine_subpixel
from mvtools.depth.segment import segment_image
from mvtools.depth.sgm import sgm_volume, winner_takes_all

__all__ = ["estimate_disparity", "METHODS", "PAIR_METHODS"]

#: name -> ``method(cost, guide) -> volume``: ``cost`` of shape (H, W, D) float32, ``guide``
#: the view the costs belong to, (H, W, 3) float32 RGB; the returned (H, W, D) float32
#: volume is minimal at each pixel's chosen level.
METHODS: dict[str, Callable[[np.ndarray, np.ndarray], np.ndarray]] = {
    "sgm": sgm_volume, "local": local_volume, "graphcut": graphcut_volume, "bp": bp_volume}

#: methods of :func:`estimate_disparity`: those of :data:`METHODS` and PatchMatch stereo,
#: which optimises disparity planes rather than a cost volume.
PAIR_METHODS: tuple[str, ...] = (*METHODS, "patchmatch")


def estimate_disparity(left: np.ndarray, right: np.ndarray, *, max_disparity: int,
                       min_disparity: int = 0, method: str = "bp",
                       segmentation: bool = False, subpixel: bool = False) -> np.ndarray:
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
        One of :data:`PAIR_METHODS`: a key of :data:`METHODS`, or ``"patchmatch"``:
        PatchMatch stereo with slanted support windows
        (:func:`mvtools.depth.patchmatch.patchmatch_planes`) started from the ``sgm``
        disparities of both views, the rest of the chain unchanged.
    segmentation : bool
        Fill the pixels that fail the left-right check from robust disparity planes of
        colour segments of the left view where a plane explains the segment's checked
        pixels (:mod:`mvtools.depth.segment`), else from the background as without it.
    subpixel : bool
        Sub-pixel values; otherwise the nearest integer level of the winner, which
        scores better on the bad 1.0 measure (see Notes).

    Returns
    -------
    ndarray of float32, shape (H, W)
        Sub-pixel disparity with ``x_right = x_left - d``; NaN where no value could be
        filled in.

    Notes
    -----
    Bad 1.0 (%, Middlebury protocol: all known pixels of Tsukuba and Venus, non-occluded
    ones of Teddy, Cones, Art, Dolls, Moebius), seconds for all seven pairs on two
    cores, and Y-PSNR (dB) of Cones im4 synthesized in general mode from the depth of
    im2 and im6 estimated from that pair:

    ==========================  =======  =====  =====  =====  =====  =====  =======  ====  =====
    method, options             Tsukuba  Venus  Teddy  Cones  Art    Dolls  Moebius  s     im4
    ==========================  =======  =====  =====  =====  =====  =====  =======  ====  =====
    ``bp`` (the default)        2.61     2.16   7.05   2.71   7.07   3.96   7.46     9.2   30.40
    ``bp``, sub-pixel           8.01     1.78   7.27   2.67   7.96   5.13   7.93     9.8   30.39
    ``bp``, segmentation        3.19     1.60   6.72   2.68   6.77   4.16   7.47     11.7  30.22
    ``sgm``                     2.68     1.88   6.55   2.85   7.11   4.75   8.28     1.3   30.15
    ``sgm``, sub-pixel          4.41     1.82   6.67   2.83   8.00   5.77   8.76     1.4   30.18
    ``sgm``, both options       4.20     1.25   6.19   2.88   6.96   4.97   8.27     2.6   30.06
    ``graphcut``                2.50     3.16   8.65   2.82   7.15   4.02   6.74     26.2  30.17
    ``patchmatch``              2.23     0.87   5.46   2.34   6.28   3.85   8.40     43.9  30.70
    ``patchmatch``, sub-pixel   3.85     1.22   5.73   2.46   6.89   4.68   8.97     ~44
    OpenCV StereoSGBM           5.66     3.06   15.3   7.22   16.5   10.8   10.8     0.5   28.49
    ==========================  =======  =====  =====  =====  =====  =====  =======  ====  =====

    Of the volume methods, ``bp`` with integer levels has the lowest mean (4.72 against
    4.87 for ``sgm``) and the best synthesized view, so it is the default; ``sgm`` is
    seven times faster for 0.15 point more. Sub-pixel values lower the mean absolute
    error (Venus 0.28 to 0.19 px over the pixels within 1 px) but push pixels whose
    integer level is one off beyond 1 px; the synthesized view hardly changes, as the
    8-bit depth maps hold quarter pixels. ``patchmatch`` (slanted planes,
    :mod:`mvtools.depth.patchmatch`) has the lowest mean, 4.21, and the best scores on
    all pairs but Moebius, whose large uniform background its windows fatten into; it
    takes 7.0 s per Cones pair on an otherwise idle machine, and gives the best
    synthesized view.
    """
    if method not in PAIR_METHODS:
        raise ValueError(f"{method!r} method is invalid, it must be one of "
                         f"{sorted(PAIR_METHODS)}")
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
    volume = METHODS["sgm" if method == "patchmatch" else method](cost, _rgb(left))
    grey_left, grey_right = (_rgb(view).mean(axis=2) for view in (left, right))
    disparity_left = winner_takes_all(volume) + min_disparity
    disparity_right = winner_takes_all(volume, right_view=True,
                                       min_disparity=min_disparity) + min_disparity
    if method == "patchmatch":
        planes = patchmatch_planes(left, right, min_disparity=min_disparity,
                                   max_disparity=max_disparity,
                                   initial=(disparity_left, disparity_right))
        disparity_left, disparity_right = (plane_disparity(view) for view in planes)
        if not subpixel:
            disparity_left = np.rint(disparity_left)
    else:
        disparity_left = (refine_subpixel(disparity_left, grey_left, grey_right) if subpixel
                          else np.rint(disparity_left))
    segments = segment_image(left, scale=120.0, min_size=20) if segmentation else None
    return clean_up(disparity_left, disparity_right, left, segments=segments)


def _rgb(view: np.ndarray) -> np.ndarray:
    view = np.asarray(view, np.float32)
    return np.repeat(view[:, :, None], 3, axis=2) if view.ndim == 2 else view
