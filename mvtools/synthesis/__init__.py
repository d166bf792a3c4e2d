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
"""

from mvtools.synthesis.views import ReferenceView, SynthesisOptions, SynthesisResult, WarpedView

__all__ = ["ReferenceView", "SynthesisOptions", "SynthesisResult", "WarpedView"]
