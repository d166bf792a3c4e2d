"""View synthesis by depth-image-based rendering (VSRS-compatible, general and 1D modes).

Data flow of one frame (:class:`mvtools.synthesis.pipeline.Synthesizer`):

1. each :class:`ReferenceView` is warped into the virtual camera
   (:func:`mvtools.synthesis.general.warp_general` or :func:`mvtools.synthesis.oned.warp_1d`),
   giving a :class:`WarpedView`;
2. the warped views are merged (:mod:`mvtools.synthesis.blend`, or the 1D merging of
   :mod:`mvtools.synthesis.oned`);
3. boundary noise is removed and the holes no view saw are filled
   (:mod:`mvtools.synthesis.boundary`, :mod:`mvtools.synthesis.holes`).

Images inside this package are ``(H, W, 3)`` float32 in the working colour space (YUV
4:4:4 or RGB, sample values as in the files: 0..255 for 8 bits); depths are float64 along
the camera axis, ``inf`` where a pixel holds nothing.

Names are imported from their modules on first use, so ``import mvtools.synthesis`` does
not compile or load the numba kernels.
"""

from __future__ import annotations

from mvtools.lazy import attach

#: Each exported name and the module of this package that defines it.
_EXPORTS: dict[str, str] = {
    "ReferenceView": "views",
    "SynthesisOptions": "views",
    "SynthesisResult": "views",
    "WarpedView": "views",
    "FILTERS": "views",
    "PRECISIONS": "views",
    "HOLE_FILLING": "views",
    "Synthesizer": "pipeline",
    "to_working": "working",
    "from_working": "working",
    "ViewRenderer": "navigation",
    "serving_views": "navigation",
    "PointCloud": "pointcloud",
    "points_from_views": "pointcloud",
    "render_point_cloud": "pointcloud",
}

__getattr__, __dir__, __all__ = attach(__name__, _EXPORTS)
