"""Lens distortion removal and rectification of camera arrays.

- :mod:`~mvtools.rectification.array`: the rectified (or undistorted) cameras and the
  maps from their pixels to the original ones, :func:`rectify_cameras`,
  :func:`undistortion`;
- :mod:`~mvtools.rectification.maps`: resampling planes, chroma planes and depth maps
  through those maps.
"""

from mvtools.rectification.array import (EDGE_TOLERANCE, Rectification, cameras_between,
                                         rectify_cameras, undistortion)
from mvtools.rectification.maps import (CHROMA_SITING, DepthResampler, chroma_maps,
                                        rectified_depth, remap_plane)

__all__ = ["Rectification", "rectify_cameras", "undistortion", "cameras_between", "remap_plane",
           "chroma_maps", "rectified_depth", "DepthResampler", "EDGE_TOLERANCE", "CHROMA_SITING"]
