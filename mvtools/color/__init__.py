"""Colour: YUV <-> RGB conversion and chroma resampling (numpy arrays in and out).

Colour correction lives in the submodules: :mod:`~mvtools.color.lut` (per-channel
tables), :mod:`~mvtools.color.correspondence` (samples that show the same scene point),
:mod:`~mvtools.color.correct` (tables of an array's views, applied to frames) and
:mod:`~mvtools.color.colorimetry` (transfer functions, white points, CIELAB, CIEDE2000),
:mod:`~mvtools.color.chart` (ColorChecker detection and sampling) and
:mod:`~mvtools.color.chart_correction` (tone curve plus matrix fitted to a chart).
"""

from mvtools.color.space import (
    MATRICES,
    downsample_chroma,
    rgb_to_yuv,
    rgb_to_yuv_matrix,
    upsample_chroma,
    yuv_to_rgb,
)

__all__ = [
    "MATRICES",
    "downsample_chroma",
    "rgb_to_yuv",
    "rgb_to_yuv_matrix",
    "upsample_chroma",
    "yuv_to_rgb",
]
