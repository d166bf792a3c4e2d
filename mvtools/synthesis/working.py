"""Between files and synthesis: textures in the working colour space and depth-map coding.

The working space is YUV 4:4:4 (chroma upsampled) or RGB, float32, sample values as in
the files. Depth maps are decoded by :class:`mvtools.geometry.depth.DepthCoding`.
"""

from __future__ import annotations

import numpy as np

from mvtools.color.space import downsample_chroma, rgb_to_yuv, upsample_chroma, yuv_to_rgb
from mvtools.geometry.camera import Camera
from mvtools.geometry.projection import backproject, pixel_grid

__all__ = ["from_working", "to_working", "world_z"]


def world_z(camera: Camera, z: np.ndarray) -> np.ndarray:
    """Depth along ``camera``'s axis -> world z (DepthType 1); inf where nothing was seen."""
    u, v = pixel_grid(z.shape[1], z.shape[0])
    seen = np.isfinite(z) & (z > 0)
    return np.where(seen, backproject(camera, u, v, np.where(seen, z, 1.0))[..., 2], np.inf)


def to_working(planes, *, color_space: int, bits: int) -> np.ndarray:
    """A texture frame in the working space of the synthesis.

    Parameters
    ----------
    planes : (Y, U, V)
        Samples of ``bits`` bits; chroma subsampled or full size.
    color_space : {0, 1}
        VSRS ColorSpace: 0 YUV 4:4:4 (chroma upsampled, centred siting, unrounded),
        1 RGB (BT.601 limited range, rounded as VSRS does).
    bits : int

    Returns
    -------
    ndarray of float32, shape (H, W, 3)
    """
    if color_space == 1:
        return yuv_to_rgb(planes, bits=bits).astype(np.float32)
    luma = planes[0]
    image = np.empty(luma.shape + (3,), dtype=np.float32)
    image[..., 0] = luma
    # chroma straight into the image, with no full-size float64 temporaries
    upsample_chroma(planes, out=(image[..., 1], image[..., 2]))
    return image


def from_working(image: np.ndarray, *, color_space: int, bits: int) -> tuple[np.ndarray, ...]:
    """A working-space image (see :func:`to_working`) as YUV 4:2:0 planes of ``bits``
    bits (uint8 or uint16): chroma averaged over 2x2 blocks, rounded half up and clipped."""
    max_value = 2**bits - 1
    if color_space == 1:
        return rgb_to_yuv(np.clip(image / max_value, 0.0, 1.0), chroma="420", bits=bits)
    dtype = np.uint8 if bits == 8 else np.uint16
    luma = np.clip(np.floor(image[..., 0] + 0.5), 0, max_value).astype(dtype)
    return (luma, *(downsample_chroma(image[..., channel], bits=bits) for channel in (1, 2)))
