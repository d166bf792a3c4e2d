"""Quality metrics: PSNR, YUV-PSNR, SSIM, IV-PSNR, Middlebury disparity scores and
Bjontegaard deltas.

Arrays in, numbers out: no files here (``mvtools.io.middlebury`` reads the
Middlebury ground truth). Names are imported from their modules on first use, so
``import mvtools.metrics`` loads neither OpenCV nor SciPy.
"""

from __future__ import annotations

from mvtools.lazy import attach

# ``psnr`` and ``ssim`` name both a module of this package and its function: the
# functions are bound here, as importing the module would otherwise leave the module
# under the name (both modules load OpenCV only when they compute).
from mvtools.metrics.psnr import psnr as psnr
from mvtools.metrics.ssim import ssim as ssim

#: Each exported name and the module of this package that defines it.
_EXPORTS: dict[str, str] = {
    "bd_psnr": "bjontegaard",
    "bd_rate": "bjontegaard",
    "ERROR_BIN_EDGES": "disparity",
    "DisparityScore": "disparity",
    "check_thresholds": "disparity",
    "error_histogram": "disparity",
    "known_ground_truth": "disparity",
    "nonoccluded_from_other_view": "disparity",
    "score_disparity": "disparity",
    "global_color_shift": "ivpsnr",
    "iv_psnr": "ivpsnr",
    "YUV_PSNR_WEIGHTS": "psnr",
    "plane_psnr": "psnr",
    "yuv_psnr": "psnr",
    "VIDEO_METRICS": "video",
    "frame_scores": "video",
}

__getattr__, __dir__, __all__ = attach(__name__, _EXPORTS, eager=("psnr", "ssim"))
