"""Colour: YUV <-> RGB conversion and chroma resampling (numpy arrays in and out)."""

from mvtools.color.space import (MATRICES, downsample_chroma, rgb_to_yuv, rgb_to_yuv_matrix,
                                 upsample_chroma, yuv_to_rgb)

__all__ = ["MATRICES", "downsample_chroma", "rgb_to_yuv", "rgb_to_yuv_matrix", "upsample_chroma",
           "yuv_to_rgb"]
