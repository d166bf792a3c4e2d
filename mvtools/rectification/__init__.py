"""Lens distortion removal and rectification of camera arrays.

- :mod:`~mvtools.rectification.array`: the rectified (or undistorted) cameras and the
  maps from their pixels to the original ones, :func:`rectify_cameras`,
  :func:`undistortion`;
- :mod:`~mvtools.rectification.maps`: resampling planes, chroma planes and depth maps
  through those maps.
"""

from mvtools.rectification.array import (
    EDGE_TOLERANCE,
    Rectification,
    cameras_between,
    rectify_cameras,
    undistortion,
)
from mvtools.rectification.maps import (
    CHROMA_SITING,
    DepthResampler,
    chroma_maps,
    rectified_depth,
    remap_plane,
)

__all__ = [
    "CHROMA_SITING",
    "EDGE_TOLERANCE",
    "DepthResampler",
    "Rectification",
    "cameras_between",
    "chroma_maps",
    "rectified_depth",
    "rectify_cameras",
    "remap_plane",
    "undistortion",
]
