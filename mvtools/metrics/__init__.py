"""Quality metrics: PSNR, YUV-PSNR, SSIM, IV-PSNR, Middlebury disparity scores and
Bjontegaard deltas.

Arrays in, numbers out: no files here (``mvtools.io.middlebury`` reads the
Middlebury ground truth).
"""

from mvtools.metrics.bjontegaard import bd_psnr, bd_rate
from mvtools.metrics.disparity import (
    ERROR_BIN_EDGES, DisparityScore, check_thresholds, error_histogram, known_ground_truth,
    nonoccluded_from_other_view, score_disparity)
from mvtools.metrics.ivpsnr import global_color_shift, iv_psnr
from mvtools.metrics.psnr import YUV_PSNR_WEIGHTS, plane_psnr, psnr, yuv_psnr
from mvtools.metrics.ssim import ssim
from mvtools.metrics.video import VIDEO_METRICS, frame_scores

__all__ = [
    "psnr", "plane_psnr", "yuv_psnr", "YUV_PSNR_WEIGHTS", "ssim", "iv_psnr",
    "global_color_shift", "check_thresholds", "score_disparity", "DisparityScore", "known_ground_truth",
    "error_histogram", "ERROR_BIN_EDGES",
    "nonoccluded_from_other_view", "bd_rate", "bd_psnr", "VIDEO_METRICS", "frame_scores",
]
