"""Options of depth estimation, the plain values that ``mvtools estimate-depth`` and
the DERS keys set.

:class:`DepthOptions` serves both inputs of the program: a rectified pair of pictures
(:func:`mvtools.depth.estimate_disparity`) and a center view with neighbours and
cameras (:class:`mvtools.depth.ders.DersEstimator`). This module imports no kernel, so
the program's options and help can name the choices without loading them.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["COST_NAMES", "DEFAULT_METHOD", "VIEW_COMBINATIONS", "DepthOptions"]

#: Method of both modes when none is given (``--method``, DERS's Method key): ``bp``, the
#: best measured on all shared data together. Bad 1.0 % mean of the seven Middlebury
#: pairs 3.70 (``sgm`` 3.73) in the stereo-pair mode, and of the eight DERS cases 4.30
#: (``sgm`` 4.45); the synthesized Cones im4 30.47 dB (``sgm`` 30.44); on Kendo the fetch
#: error of view 3 into camera 1 a median of 1.49 grey levels (``sgm`` 1.55, the shipped
#: depth 2.00); Poznan Hall 2's camera 7 from camera 5 with the estimated depth 34.85 dB
#: (``sgm`` 34.91, the shipped depth 32.29).
DEFAULT_METHOD = "bp"

#: How the neighbours' matches combine in the views mode (ViewCombination).
VIEW_COMBINATIONS = ("least-cost", "vote")

#: The matching costs of a rectified pair, the keys of :data:`mvtools.depth.COSTS`
#: (which loads the kernels).
COST_NAMES = ("ad-census", "census-gradient")


@dataclass(frozen=True, kw_only=True)
class DepthOptions:
    """Algorithm options of depth estimation; each default is the program's.

    Attributes named after a DERS key hold that key's value, but for
    ``image_segmentation`` and ``temporal_enhancement`` (booleans) and the two z ranges
    (pairs, None when not given).

    Attributes
    ----------
    method : str, optional
        A key of :data:`mvtools.depth.METHODS`, or ``"patchmatch"`` for a pair; None:
        :data:`DEFAULT_METHOD`.
    minimum_value_of_disparity_search_range, maximum_value_of_disparity_search_range : int
        The disparities searched, in pixels, inclusive: for a pair the integer levels
        of left x - right x; for views, towards the BaselineBasis view in steps of
        ``1 / search_level``.
    cost : str
        A rectified pair's matching cost, one of :data:`COST_NAMES`: ad-census gives
        the better synthesized views, census-gradient the better bad 1.0
        (:func:`mvtools.depth.cost.census_gradient_cost`, Notes).
    subpixel, segment_planes, segmentation : bool
        A rectified pair: sub-pixel disparities rather than the integer levels; colour
        segments take their disparity plane where it matches about as well, and
        fattened foreground returns to the background plane; the pixels failing the
        left-right check are filled from segment planes.
    view : {"left", "right"}
        A rectified pair: whose disparity is estimated.
    depth_type : {0, 1}
        Views: depth along the center camera's axis (0) or from the world origin (1).
    minimum_value_of_disparity_range, maximum_value_of_disparity_range : int
        Views: the disparities (pixels, to the BaselineBasis view) written as the
        smallest and the largest depth value, unless ``depth_range`` is given.
    depth_range : (float, float), optional
        Views: (Znear, Zfar) written as the largest and the smallest depth value
        (NearestDepthValue, FarthestDepthValue).
    search_depth_range : (float, float), optional
        Views: the nearest and farthest z searched, with ``number_of_depth_steps``
        planes, instead of the disparity search range.
    number_of_depth_steps, baseline_basis, search_level, smoothing_coefficient, precision, \
vertical_precision, filter, matching_method, matching_block, soft_distance_coeff, \
soft_color_coeff, soft_block_width, soft_block_height, threshold, \
temporal_refresh_period
        Views: the DERS keys of those names (:mod:`mvtools.depth.ders` says how each
        is read).
    image_segmentation, temporal_enhancement : bool
        Views: ImageSegmentation and TemporalEnhancement.
    view_combination : {"least-cost", "vote"}
        Views: ViewCombination, how the neighbours' matches combine: the least cost of
        the views that see a point in one sweep (DERS), or each neighbour's own depth
        and a vote (the linear-array mode's rule).

    The DERS keys that change nothing (SmoothingCoefficient2, VerticalFilter,
    SegmentationMethod, MaxCluster) have no attribute.
    """

    method: str | None = None
    minimum_value_of_disparity_search_range: int = 0
    maximum_value_of_disparity_search_range: int = 20
    # a rectified pair
    cost: str = "ad-census"
    subpixel: bool = False
    segment_planes: bool = True
    segmentation: bool = False
    view: str = "left"
    # views with cameras
    depth_type: int = 0
    minimum_value_of_disparity_range: int = 0
    maximum_value_of_disparity_range: int = 20
    depth_range: tuple[float, float] | None = None
    search_depth_range: tuple[float, float] | None = None
    number_of_depth_steps: int = 10
    baseline_basis: int = 1
    search_level: float = 2.0
    smoothing_coefficient: float = 4.0
    precision: int = 4
    vertical_precision: int = 1
    filter: int = 1
    matching_method: int = 2
    matching_block: int = 1
    soft_distance_coeff: float = 20.0
    soft_color_coeff: float = 20.0
    soft_block_width: int = 3
    soft_block_height: int = 3
    image_segmentation: bool = False
    temporal_enhancement: bool = False
    threshold: float = 0.0
    temporal_refresh_period: int = 0
    view_combination: str = "least-cost"

    def __post_init__(self):
        if self.cost not in COST_NAMES:
            raise ValueError(f"unknown cost {self.cost!r}; known costs: {', '.join(COST_NAMES)}")
        if self.view not in ("left", "right"):
            raise ValueError(f"view must be 'left' or 'right', got {self.view!r}")
        if self.depth_type not in (0, 1):
            raise ValueError(f"depth_type must be 0 or 1, got {self.depth_type}")
        if self.view_combination not in VIEW_COMBINATIONS:
            raise ValueError(
                f"unknown view combination {self.view_combination!r}; known: "
                f"{', '.join(VIEW_COMBINATIONS)}"
            )
