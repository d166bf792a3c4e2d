"""Disparity of a rectified pair: the methods and :func:`estimate_disparity`."""

from __future__ import annotations

import inspect
from collections.abc import Callable

import numpy as np

from mvtools.depth.bp import bp_volume, bp_winners
from mvtools.depth.cost import (
    COSTS,
    ad_census_levels,
    census_gradient_levels,
    check_pair,
    mirror_costs,
)
from mvtools.depth.graphcut import graphcut_labels, graphcut_volume, label_energies
from mvtools.depth.local import local_volume
from mvtools.depth.oversegment import plane_segments
from mvtools.depth.patchmatch import patchmatch_planes, plane_disparity
from mvtools.depth.plane_selection import refine_on_segment_planes
from mvtools.depth.refine import fill_invalid, left_right_consistent, refine_subpixel
from mvtools.depth.sgm import sgm_volume, sgm_winners, winner_takes_all

__all__ = ["COSTS", "METHODS", "PAIR_METHODS", "checked_disparity", "estimate_disparity"]

#: name -> ``method(cost, guide, *, overwrite=False) -> volume``: ``cost`` of shape
#: (H, W, D) float32, ``guide`` the view the costs belong to, (H, W, 3) float32 RGB; the
#: returned (H, W, D) float32 volume is minimal at each pixel's chosen level. With
#: ``overwrite=True`` a method may write its result into ``cost`` (all but ``sgm`` do).
METHODS: dict[str, Callable[[np.ndarray, np.ndarray], np.ndarray]] = {
    "sgm": sgm_volume,
    "local": local_volume,
    "graphcut": graphcut_volume,
    "bp": bp_volume,
}

#: methods whose winners in both views come a strip of rows at a time, bit for bit
#: those of their volume (patchmatch starts from sgm's)
_STREAMED = {"sgm": sgm_winners, "patchmatch": sgm_winners, "bp": bp_winners}

#: costs that come one level at a time too (for graphcut's expansion, which then holds no
#: volume: with census-gradient on Aloe, 256 disparities, 1808 MB instead of over 2113)
_LEVELWISE = {"ad-census": ad_census_levels, "census-gradient": census_gradient_levels}

#: graphcut_volume's truncation, which its label energies take
_GRAPHCUT_TRUNCATION = inspect.signature(graphcut_volume).parameters["truncation"].default

#: costs whose mirrored pair's volume is a reindexing of the pair's own
#: (:func:`mvtools.depth.cost.mirror_costs`)
_MIRRORABLE = ("ad-census",)

#: ways :func:`checked_disparity` refines either view's map before the check
_REFINEMENTS = ("planes", "trim", "none")

#: methods of :func:`estimate_disparity`: those of :data:`METHODS` and PatchMatch stereo,
#: which optimises disparity planes rather than a cost volume.
PAIR_METHODS: tuple[str, ...] = (*METHODS, "patchmatch")


def estimate_disparity(
    left: np.ndarray,
    right: np.ndarray,
    *,
    max_disparity: int,
    min_disparity: int = 0,
    method: str = "bp",
    cost: str = "ad-census",
    segment_planes: bool = True,
    segmentation: bool = False,
    subpixel: bool = False,
    view: str = "left",
) -> np.ndarray:
    """Disparity of the left view of a rectified pair.

    Matching costs (AD-census by default), the method's optimisation, sub-pixel
    winner-takes-all in both views from the same volume, sub-pixel refinement of the
    left view by a windowed squared-difference fit, then
    :func:`mvtools.depth.refine.fill_invalid` of the pixels failing the left-right check
    (background fill, colour-weighted median).

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
    cost : str
        One of :data:`mvtools.depth.cost.COSTS`: ``"ad-census"``
        (:func:`~mvtools.depth.cost.ad_census_cost`), or ``"census-gradient"``
        (:func:`~mvtools.depth.cost.census_gradient_cost`), which lowers the mean bad 1.0
        of ``bp`` from 3.70 to 3.47 (Moebius 6.94 to 5.06) but the synthesized Cones im4
        from 30.47 to 30.08 dB; ``patchmatch`` uses it for its ``sgm`` start and the
        segment planes, its own window costs otherwise.
    segment_planes : bool
        Colour segments of the left view whose robust disparity plane matches about as
        well as the method's disparities (matching costs at most 10 % higher) take the
        plane (:func:`mvtools.depth.plane_selection.select_segment_planes`), and pixels within
        two columns of a depth step that lie in front of their segment's plane take it
        (:func:`mvtools.depth.plane_selection.trim_fattening`), before the clean-up.
    segmentation : bool
        Fill the pixels that fail the left-right check from robust disparity planes of
        colour segments of the left view where a plane explains the segment's checked
        pixels (:mod:`mvtools.depth.segment`), else from the background as without it.
    subpixel : bool
        Sub-pixel values; otherwise the nearest integer level of the winner, which
        scores better on the bad 1.0 measure (see Notes).
    view : {"left", "right"}
        Whose disparity: the right view's is the left view's of the mirrored, swapped
        pair (``x_left = x_right + d``), so that both views of a pair get the same
        treatment, e.g. as the two references of a synthesis.

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
    ``bp`` (the default)        1.29     0.54   4.84   2.27   6.26   3.73   6.94     0.66  30.47
    ``bp``, left view planes    1.73     0.54   5.59   2.45   6.85   3.75   7.35     0.73  30.31
    ``bp``, no segment planes   2.61     2.16   7.05   2.71   7.07   3.96   7.46     0.56  30.40
    ``bp``, sub-pixel           6.42     0.31   5.37   2.65   7.38   5.03   7.90
    ``bp``, segmentation        2.13     0.44   5.19   2.49   6.62   3.95   7.30
    ``patchmatch``              2.27     0.38   5.69   2.28   6.14   4.13   7.84     9.0   30.95
    ``patchmatch``, left planes 2.37     0.30   5.30   2.18   5.98   4.04   7.73     7.0   30.62
    ``patchmatch``, no planes   2.23     0.87   5.46   2.34   6.28   3.85   8.40     6.8   30.70
    ``sgm``                     1.62     0.37   4.53   2.39   5.78   3.88   7.56     0.48  30.44
    ``sgm``, no segment planes  2.68     1.88   6.55   2.85   7.11   4.75   8.28     0.13  30.15
    ``sgm``, sub-pixel and seg. 4.49     0.22   5.37   2.93   7.16   5.77   8.15
    ``graphcut``                2.08     0.75   7.54   2.21   6.13   3.76   6.09     5.2   30.64
    ``local``                   2.26     0.31   5.69   2.72   7.42   5.15   8.44     1.2   30.46
    ``bp``, census-gradient     1.88     0.41   4.89   2.35   6.46   3.26   5.06     2.0   30.08
    ``graphcut``, cens.-grad.   2.59     0.44   5.69   2.30   6.37   3.29   5.17     5.0   30.11
    OpenCV StereoSGBM           5.66     3.06   15.3   7.22   16.5   10.8   10.8     0.04  28.49
    ==========================  =======  =====  =====  =====  =====  =====  =======  ====  =====

    (s: seconds per Cones pair on two idle cores; the census-gradient rows were timed
    in a later session, when the default ``bp`` took 1.2 s.) The rows of ``bp``,
    ``patchmatch``, ``sgm``, ``graphcut`` and ``local`` are measured with AD-census
    counting only the neighbours like the centre in colour
    (:func:`mvtools.depth.cost.ad_census_cost`; before it ``bp`` had 1.56, 0.48, 5.19,
    2.48, 6.85, 3.70, 7.18 and 30.32 dB, ``sgm`` 2.14, 0.35, 5.19, 2.76, 6.45, 4.38,
    7.60 and 30.13 dB), their seconds before it (the like-colour masks add about 10 ms
    a Cones view); the other rows before it and before the census tolerance of half a
    grey level (:data:`mvtools.depth.cost.CENSUS_TOLERANCE`). ``bp`` with integer levels
    and segment planes is the default: under the bars of all four 2001/2003 pairs
    (Tsukuba 2.0, Venus 1.0, Teddy 6.0, Cones 3.0), and the lowest mean, 3.70 (``sgm``
    3.73; ``patchmatch`` 4.10, many times slower, gives the best synthesized view).
    With ``cost="census-gradient"`` ``bp`` is under the bars of all seven pairs (mean
    3.47; Moebius 5.06 against a bar of 5.39, half of StereoSGBM's error), but its
    synthesized view is 0.39 dB worse (1D mode: 29.75 against 30.60 dB), so AD-census
    stays the default (:func:`mvtools.depth.cost.census_gradient_cost`, Notes). The
    plane selection and fattening trim run on both views, the right one as the left
    view of the mirrored pair, and the left-right check then compares the refined maps:
    mean 3.95 against 4.04 with the left view alone (Teddy 5.08 against 5.59), for
    0.2 s more per Cones pair; only ``patchmatch`` loses by it (4.05 against 3.99,
    while its synthesized view gains 0.26 dB). Moebius keeps most of its errors, on
    untextured facets and background where the planes are fitted to wrong
    disparities. Their parameters were chosen on all seven sets together (left view
    only): a plane margin of 7.5, 10 and 12.5 % gives a mean of 4.21, 4.15 and 4.20
    without the trim; the trim reach of 1, 2 or 3 columns 4.06, 4.07, 4.08 without its
    cost test, 4.04 with it. Sub-pixel values lower the mean absolute error (Venus 0.28 to 0.19 px over
    the pixels within 1 px, without the planes) but push pixels whose integer level is
    one off beyond 1 px; the synthesized view hardly changes, as the 8-bit depth maps
    hold quarter pixels.

    Memory: at most one (H, W, D) float32 cost volume is alive at a time, plus strips.
    ``sgm`` and ``bp`` never build their volume: their winners in both views come a
    strip of rows at a time (:func:`mvtools.depth.sgm.sgm_winners`,
    :func:`mvtools.depth.bp.bp_winners`), bit for bit those of the volume;
    ``graphcut`` expands from one cost level at a time and builds the volume only for
    its label energies; ``local`` filters it in place; the mirrored pair's AD-census
    costs are the pair's reindexed in place (:func:`mvtools.depth.cost.mirror_costs`).
    Peak resident memory on the Aloe pair (1282x1110, 256 disparities; one volume is
    1390 MB; ``benchmarks/bench_depth_memory.py``) fell from 4541 MB to 1912 MB with
    ``sgm``, 11802 to 1994 MB with ``bp``, 4556 to 1789 MB with ``graphcut`` and
    4590 to 1977 MB with ``patchmatch``; ``local``, which failed beyond 128 levels
    (OpenCV's channel limit), takes 1917 MB.
    """
    # the right view is the left one of the mirrored, swapped pair, and is filled there
    left, right = _mirrored_pair(left, right, view)
    disparity, consistent, segments = _checked_left(
        left,
        right,
        max_disparity=max_disparity,
        min_disparity=min_disparity,
        method=method,
        cost=cost,
        segment_planes=segment_planes,
        subpixel=subpixel,
        keep_segments=segmentation,
    )
    filled = fill_invalid(disparity, consistent, left, segments=segments if segmentation else None)
    return np.ascontiguousarray(filled[:, ::-1]) if view == "right" else filled


def checked_disparity(
    left: np.ndarray,
    right: np.ndarray,
    *,
    max_disparity: int,
    min_disparity: int = 0,
    method: str = "bp",
    cost: str = "ad-census",
    segment_planes: bool = True,
    subpixel: bool = False,
    view: str = "left",
    segments: np.ndarray | None = None,
    signatures: tuple[np.ndarray, np.ndarray] | None = None,
    refine: str = "planes",
    refine_other: str = "planes",
) -> tuple[np.ndarray, np.ndarray]:
    """The disparity of one view of a rectified pair with its left-right check, before
    :func:`estimate_disparity` fills the pixels that fail it.

    Parameters
    ----------
    left, right, max_disparity, min_disparity, method, cost, segment_planes, subpixel, view
        As for :func:`estimate_disparity`.
    segments : ndarray of int, shape (H, W), optional
        The colour segments of the view (:func:`mvtools.depth.oversegment.plane_segments`)
        for the segment planes, when the caller has them: a view matched with several
        others is segmented once.
    signatures : (ndarray, ndarray) of uint64, optional
        The census signatures of ``left`` and ``right``
        (:func:`mvtools.depth.cost.ad_census_signatures`) for the ``ad-census`` cost,
        when the caller has them: a view matched with several others is transformed once.
    refine, refine_other : {"planes", "trim", "none"}
        How the view's map and the other view's are refined before the check: on their
        own segment planes, then by the fattening trim, as :func:`estimate_disparity`
        refines them (``"planes"``); by the trim alone (``"trim"``), which spares
        choosing the planes (Tsukuba, on one core: 22 of the 84 ms the other view's
        refinement takes); or not at all, the method's own map (``"none"``), which for
        the other view spares segmenting it too. With ``segment_planes=False`` neither
        view is refined.

    Returns
    -------
    disparity : ndarray of float32, shape (H, W)
        The view's disparity, ``x_right = x_left - d``.
    consistent : ndarray of bool, shape (H, W)
        Pixels whose disparity the other view's confirms
        (:func:`mvtools.depth.refine.left_right_consistent`): False where the other view
        does not see the point (occlusion, the border) or the match is unreliable.
    """
    if signatures is not None and cost != "ad-census":
        raise ValueError(f"census signatures are the ad-census cost's, not the {cost!r} cost's")
    if view == "right":
        # the mirrored pair's signatures are the views' mirrored alike (ad_census_cost)
        segments = None if segments is None else np.ascontiguousarray(segments[:, ::-1])
        signatures = None if signatures is None else [sig[:, ::-1] for sig in signatures[::-1]]
    disparity, consistent, _ = _checked_left(
        *_mirrored_pair(left, right, view),
        max_disparity=max_disparity,
        min_disparity=min_disparity,
        method=method,
        cost=cost,
        segment_planes=segment_planes,
        subpixel=subpixel,
        segments=segments,
        signatures=signatures,
        refine=refine,
        refine_other=refine_other,
    )
    if view == "right":
        return np.ascontiguousarray(disparity[:, ::-1]), np.ascontiguousarray(consistent[:, ::-1])
    return disparity, consistent


def _mirrored_pair(left, right, view):
    # the pair whose left view is ``view`` (the right one mirrored, or the pair itself)
    if view not in ("left", "right"):
        raise ValueError(f"view must be 'left' or 'right', got {view!r}")
    if view == "left":
        return left, right
    return [np.ascontiguousarray(np.asarray(picture)[:, ::-1]) for picture in (right, left)]


def _checked_left(
    left,
    right,
    *,
    max_disparity,
    min_disparity,
    method,
    cost,
    segment_planes,
    subpixel,
    keep_segments=False,
    segments=None,
    signatures=None,
    refine="planes",
    refine_other="planes",
):
    # The left view's disparity, its left-right consistent pixels, and its colour
    # segments when they were made (segment planes) or asked for; ``segments``, when
    # given, are the left view's, ``signatures`` the pair's (ad-census only).
    if method not in PAIR_METHODS:
        raise ValueError(f"{method!r} method is invalid, it must be one of {sorted(PAIR_METHODS)}")
    if cost not in COSTS:
        raise ValueError(f"{cost!r} cost is invalid, it must be one of {sorted(COSTS)}")
    for name, value in (("refine", refine), ("refine_other", refine_other)):
        if value not in _REFINEMENTS:
            raise ValueError(f"{name}={value!r} is invalid, it must be one of {list(_REFINEMENTS)}")
    left, right = check_pair(left, right, min_disparity=min_disparity, max_disparity=max_disparity)
    levels = max_disparity - min_disparity + 1
    cost_options = {"min_disparity": min_disparity, "levels": levels}
    if signatures is not None:
        cost_options["signatures"] = signatures
    # Memory: one cost volume, which the method overwrites with its own where it can,
    # then at most one while the segment planes are chosen, the costs computed again
    # if the method overwrote them.
    if method == "graphcut" and cost in _LEVELWISE:
        # the expansion asks for one level at a time; the volume only for the energies
        labels, weights_right, weights_down = graphcut_labels(
            _LEVELWISE[cost](left, right, **cost_options),
            levels,
            _rgb(left),
        )
        costs = COSTS[cost](left, right, **cost_options)
        volume = label_energies(
            costs, labels, weights_right, weights_down, _GRAPHCUT_TRUNCATION, out=costs
        )
        costs = None
    else:
        costs = COSTS[cost](left, right, **cost_options)
    if method == "graphcut" and cost in _LEVELWISE:
        disparity_left = winner_takes_all(volume) + min_disparity
        disparity_right = (
            winner_takes_all(volume, right_view=True, min_disparity=min_disparity) + min_disparity
        )
        del volume
    elif method in _STREAMED:
        # the method volume's winners a strip of rows at a time, the costs kept
        disparity_left, disparity_right = (
            view + min_disparity
            for view in _STREAMED[method](costs, _rgb(left), min_disparity=min_disparity)
        )
        costs = costs if segment_planes else None
    else:
        volume = METHODS[method](costs, _rgb(left), overwrite=True)
        # a method that kept the costs intact spares computing them again below
        costs = costs if segment_planes and not np.may_share_memory(costs, volume) else None
        disparity_left = winner_takes_all(volume) + min_disparity
        disparity_right = (
            winner_takes_all(volume, right_view=True, min_disparity=min_disparity) + min_disparity
        )
        del volume
    if method == "patchmatch":
        planes = patchmatch_planes(
            left,
            right,
            min_disparity=min_disparity,
            max_disparity=max_disparity,
            initial=(disparity_left, disparity_right),
        )
        disparity_left, disparity_right = (plane_disparity(view) for view in planes)
    elif subpixel:
        disparity_left = refine_subpixel(
            disparity_left, *(_rgb(view).mean(axis=2) for view in (left, right))
        )
    if segment_planes and not subpixel:
        # integer levels in both views, as the segment planes refine both
        disparity_left, disparity_right = np.rint(disparity_left), np.rint(disparity_right)
    elif not subpixel:
        disparity_left = np.rint(disparity_left)
    # the left view's own segments only where its map is refined on them or they are kept
    if segments is None and ((segment_planes and refine != "none") or keep_segments):
        segments = plane_segments(left)
    if segment_planes:
        # Both views refined as refine and refine_other say, then checked
        # against each other: the right view's map is the left one of the mirrored,
        # swapped pair, whose costs are those of the pair reindexed in place where the
        # cost allows it, else computed once the pair's are freed.
        if costs is None:
            costs = COSTS[cost](left, right, **cost_options)
        refined_left = _on_segment_planes(
            disparity_left,
            disparity_right,
            left,
            segments,
            costs,
            min_disparity=min_disparity,
            subpixel=subpixel,
            refinement=refine,
        )
        if refine_other == "none":
            return refined_left, left_right_consistent(refined_left, disparity_right), segments
        mirrored = [np.ascontiguousarray(view[:, ::-1]) for view in (right, left)]
        mirrored_segments = plane_segments(mirrored[0])
        if cost in _MIRRORABLE:
            costs = mirror_costs(costs, min_disparity=min_disparity)
        else:
            del costs
            costs = COSTS[cost](*mirrored, min_disparity=min_disparity, levels=levels)
        refined_right = _on_segment_planes(
            disparity_right[:, ::-1],
            disparity_left[:, ::-1],
            mirrored[0],
            mirrored_segments,
            costs,
            min_disparity=min_disparity,
            subpixel=subpixel,
            refinement=refine_other,
        )[:, ::-1]
        del costs
        disparity_left, disparity_right = refined_left, refined_right
    return disparity_left, left_right_consistent(disparity_left, disparity_right), segments


def _on_segment_planes(
    disparity, other, view, segments, cost, *, min_disparity, subpixel, refinement
):
    """A view's disparities refined on its segment planes
    (:func:`mvtools.depth.plane_selection.refine_on_segment_planes`: the whole segments'
    selection only with ``refinement="planes"``, the fattening trim unless ``"none"``),
    the reliable pixels being those that the other view's disparities ``other`` confirm."""
    disparity = np.ascontiguousarray(disparity, np.float32)
    if refinement != "none":
        valid = left_right_consistent(disparity, np.ascontiguousarray(other, np.float32))
        disparity, _ = refine_on_segment_planes(
            disparity,
            valid,
            segments,
            cost,
            view,
            min_disparity=min_disparity,
            select=refinement == "planes",
        )
    return disparity if subpixel else np.rint(disparity)


def _rgb(view: np.ndarray) -> np.ndarray:
    view = np.asarray(view, np.float32)
    return np.repeat(view[:, :, None], 3, axis=2) if view.ndim == 2 else view
