"""Camera geometry: projection, back-projection, depth conversions, homographies."""

from mvtools.geometry.camera import Camera, turn_world
from mvtools.geometry.depth import (
    DepthCoding,
    check_depth_range,
    depth_sign,
    depth_to_z,
    depth_value_to_disparity,
    ders_depth_range,
    disparity_1d,
    disparity_to_depth_value,
    disparity_to_z,
    facing_camera,
    inverse_depth_step,
    max_depth_value,
    normalized_disparity,
    z_to_depth,
    z_to_disparity,
)
from mvtools.geometry.homography import plane_homography
from mvtools.geometry.projection import (
    backproject,
    depth_along_axis,
    pixel_grid,
    project,
    reproject,
)
from mvtools.geometry.warp import forward_warp

__all__ = [
    "Camera",
    "DepthCoding",
    "backproject",
    "check_depth_range",
    "depth_along_axis",
    "depth_sign",
    "depth_to_z",
    "depth_value_to_disparity",
    "ders_depth_range",
    "disparity_1d",
    "disparity_to_depth_value",
    "disparity_to_z",
    "facing_camera",
    "forward_warp",
    "inverse_depth_step",
    "max_depth_value",
    "normalized_disparity",
    "pixel_grid",
    "plane_homography",
    "project",
    "reproject",
    "turn_world",
    "z_to_depth",
    "z_to_disparity",
]
