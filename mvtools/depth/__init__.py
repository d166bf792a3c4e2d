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
from mvtools.depth.refine import clean_up, left_right_consistent, refine_subpixel
from mvtools.depth.segment import segment_image, select_segment_planes, trim_fattening
from mvtools.depth.sgm import sgm_volume, winner_takes_all

__all__ = ["estimate_disparity", "METHODS"]

#: name -> ``method(cost, guide) -> volume``: ``cost`` of shape (H, W, D) float32, ``guide``
#: the view the costs belong to, (H, W, 3) float32 RGB; the returned (H, W, D) float32
#: volume is minimal at each pixel's chosen level.
METHODS: dict[str, Callable[[np.ndarray, np.ndarray], np.ndarray]] = {
    "sgm": sgm_volume, "local": local_volume, "graphcut": graphcut_volume, "bp": bp_volume}


def estimate_disparity(left: np.ndarray, right: np.ndarray, *, max_disparity: int,
                       min_disparity: int = 0, method: str = "bp",
                       segment_planes: bool = True, segmentation: bool = False,
                       subpixel: bool = False) -> np.ndarray:
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
    segment_planes : bool
        Colour segments of the left view whose robust disparity plane matches about as
        well as the method's disparities (AD-census costs at most 10 % higher) take the
        plane (:func:`mvtools.depth.segment.select_segment_planes`), and pixels within
        two columns of a depth step that lie in front of their segment's plane take it
        (:func:`mvtools.depth.segment.trim_fattening`), before the clean-up.
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
    ones of Teddy, Cones, Art, Dolls, Moebius), seconds for the Cones pair (the least of
    three runs on two cores shared with other jobs, which made single runs up to 25
    times slower), and Y-PSNR (dB) of Cones im4 synthesized in general mode from the
    depth of im2 and im6 estimated from that pair:

    ==========================  =======  =====  =====  =====  =====  =====  =======  ====  =====
    method, options             Tsukuba  Venus  Teddy  Cones  Art    Dolls  Moebius  s     im4
    ==========================  =======  =====  =====  =====  =====  =====  =======  ====  =====
    ``bp`` (the default)        1.73     0.54   5.59   2.45   6.85   3.75   7.35     2.5   30.31
    ``bp``, no segment planes   2.61     2.16   7.05   2.71   7.07   3.96   7.46     1.7   30.40
    ``bp``, sub-pixel           6.53     0.35   5.93   2.98   7.37   5.04   7.82     1.6   30.22
    ``bp``, segmentation        2.23     0.57   5.47   2.55   6.71   3.98   7.34     1.9   30.15
    ``sgm``                     2.27     0.50   5.31   2.73   6.36   4.37   8.38     0.64  30.14
    ``sgm``, no segment planes  2.68     1.88   6.55   2.85   7.11   4.75   8.28     0.66  30.15
    ``sgm``, sub-pixel and seg. 4.49     0.32   5.46   3.02   7.32   5.70   8.22     0.86  30.07
    ``graphcut``                2.06     0.64   8.08   2.51   6.87   3.77   6.40     8.8   30.11
    ``local``                   2.83     0.84   6.51   3.04   8.22   5.12   8.44     0.89  29.98
    OpenCV StereoSGBM           5.66     3.06   15.3   7.22   16.5   10.8   10.8     0.05  28.49
    ==========================  =======  =====  =====  =====  =====  =====  =======  ====  =====

    ``bp`` with integer levels and segment planes has the lowest mean (4.04 against
    4.28 for ``sgm``, 4.72 for ``bp`` without the planes), so it is the default; the
    plane selection and fattening trim add about 0.7 s per Cones pair (segmentation
    0.3 s, the two plane steps 0.3 s). They lower every set with ``bp`` and all but
    Moebius with ``sgm`` (+0.1); Moebius keeps most of its errors, on untextured facets
    and dark background where the planes are fitted to wrong disparities. The
    synthesized view loses 0.1 dB. Their parameters were chosen
    on all seven sets together: a plane margin of 7.5, 10 and 12.5 % gives a mean of
    4.21, 4.15 and 4.20 without the trim; the trim reach of 1, 2 or 3 columns 4.06,
    4.07, 4.08 without its cost test, 4.04 with it. Sub-pixel values lower the mean
    absolute error (Venus 0.28 to 0.19 px over the pixels within 1 px, without the
    planes) but push pixels whose integer level is one off beyond 1 px; the
    synthesized view hardly changes, as the 8-bit depth maps hold quarter pixels.
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
    disparity_left = winner_takes_all(volume) + min_disparity
    disparity_left = (refine_subpixel(disparity_left, grey_left, grey_right) if subpixel
                      else np.rint(disparity_left))
    disparity_right = winner_takes_all(volume, right_view=True,
                                       min_disparity=min_disparity) + min_disparity
    valid = left_right_consistent(disparity_left, disparity_right)
    segments = (segment_image(left, scale=120.0, min_size=20)
                if segment_planes or segmentation else None)
    if segment_planes:
        disparity_left, valid = select_segment_planes(disparity_left, valid, segments, cost,
                                                      left, min_disparity=min_disparity)
        disparity_left = trim_fattening(disparity_left, valid, segments, cost, left,
                                        min_disparity=min_disparity)
        if not subpixel:
            disparity_left = np.rint(disparity_left)
    return clean_up(disparity_left, disparity_right, left, valid=valid,
                    segments=segments if segmentation else None)


def _rgb(view: np.ndarray) -> np.ndarray:
    view = np.asarray(view, np.float32)
    return np.repeat(view[:, :, None], 3, axis=2) if view.ndim == 2 else view
