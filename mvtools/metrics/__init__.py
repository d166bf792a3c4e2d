"""Quality metrics: PSNR, YUV-PSNR, SSIM, IV-PSNR, Middlebury disparity scores and
Bjontegaard deltas.

Arrays in, numbers out: no files here (``mvtools.io.middlebury`` reads the
Middlebury ground truth).
"""

from mvtools.metrics.bjontegaard import bd_psnr, bd_rate
from mvtools.metrics.disparity import (
    ERROR_BIN_EDGES,
    DisparityScore,
    check_thresholds,
    error_histogram,
    known_ground_truth,
    nonoccluded_from_other_view,
    score_disparity,
)
from mvtools.metrics.ivpsnr import global_color_shift, iv_psnr
from mvtools.metrics.psnr import YUV_PSNR_WEIGHTS, plane_psnr, psnr, yuv_psnr
from mvtools.metrics.ssim import ssim
from mvtools.metrics.video import VIDEO_METRICS, frame_scores

__all__ = [
    "ERROR_BIN_EDGES",
    "VIDEO_METRICS",
    "YUV_PSNR_WEIGHTS",
    "DisparityScore",
    "bd_psnr",
    "bd_rate",
    "check_thresholds",
    "error_histogram",
    "frame_scores",
    "global_color_shift",
    "iv_psnr",
    "known_ground_truth",
    "nonoccluded_from_other_view",
    "plane_psnr",
    "psnr",
    "score_disparity",
    "ssim",
    "yuv_psnr",
]
