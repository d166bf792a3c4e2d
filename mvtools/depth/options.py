"""Options of depth estimation: what the ``estimate-depth`` program and the DERS keys drive.

:class:`DepthOptions` holds plain values; the program builds it from a DERS
configuration (:class:`mvtools.params.DersParams`) or from its stereo-pair options, and
:class:`mvtools.depth.ders.DersEstimator` and :func:`mvtools.depth.estimate_disparity`
read it through the run functions of :mod:`mvtools.run.depth`.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["PAIR_METHOD", "VIEWS_METHOD", "DepthOptions"]

#: Method of a rectified pair when none is given, the best measured on the Middlebury
#: pairs (bad 1.0 and the synthesized Cones view, :func:`mvtools.depth.estimate_disparity`).
PAIR_METHOD = "bp"

#: Method of views with cameras when none is given (DERS's Method key), the best on
#: Kendo: the fetch error of view 3 into camera 1 is a median of 1.53, bp 1.45, local
#: 1.39, graphcut 1.44, in 5.3 s per frame against 9.9, 15.1 and 105 s.
VIEWS_METHOD = "sgm"


@dataclass(frozen=True, kw_only=True)
class DepthOptions:
    """Algorithm options of depth estimation; the defaults are the program's.

    Attributes named after a DERS key hold that key's value (``image_segmentation`` and
    ``temporal_enhancement`` as booleans, the two z ranges as pairs).

    Both inputs:

    - ``method``: a key of :data:`mvtools.depth.METHODS`, or ``"patchmatch"`` for a
      pair; None: :data:`PAIR_METHOD` for a rectified pair, :data:`VIEWS_METHOD` for
      views with cameras.
    - ``minimum_value_of_disparity_search_range``, ``maximum_value_of_disparity_search_range``:
      the disparities searched, in pixels, inclusive (a pair: integer levels, left x -
      right x; views: towards the BaselineBasis view, ``1 / search_level`` apart).

    A rectified pair (:func:`mvtools.depth.estimate_disparity`): ``cost`` (a key of
    :data:`mvtools.depth.cost.COSTS`), ``subpixel``, ``segment_planes``,
    ``segmentation``, ``view`` (``"left"`` or ``"right"``: whose disparity).

    Views with cameras (:class:`mvtools.depth.ders.DersEstimator`): ``depth_type``,
    ``minimum_value_of_disparity_range``, ``maximum_value_of_disparity_range`` (the
    disparities written as depth values 0 and 255), ``depth_range`` ((Znear, Zfar)
    written instead, or None), ``search_depth_range`` ((nearest, farthest) z searched
    with ``number_of_depth_steps`` planes instead of the disparity search range, or
    None), ``baseline_basis``, ``search_level``, ``smoothing_coefficient``,
    ``precision``, ``vertical_precision``, ``filter``, ``matching_method``,
    ``matching_block``, the soft-segment matching's ``soft_*``,
    ``image_segmentation``, and ``temporal_enhancement`` with ``threshold`` and
    ``temporal_refresh_period``. The DERS keys that change nothing (SmoothingCoefficient2,
    VerticalFilter, SegmentationMethod, MaxCluster) have no attribute.
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

    def __post_init__(self):
        if self.view not in ("left", "right"):
            raise ValueError(f"view must be 'left' or 'right', got {self.view!r}")
        if self.depth_type not in (0, 1):
            raise ValueError(f"depth_type must be 0 or 1, got {self.depth_type}")
