"""Camera geometry: projection, back-projection, depth conversions, homographies."""

from mvtools.geometry.camera import Camera, turn_world
from mvtools.geometry.depth import (
    DepthCoding, check_depth_range, depth_sign, depth_to_z, depth_value_to_disparity,
    ders_depth_range, disparity_1d, disparity_to_depth_value, disparity_to_z, facing_camera,
    inverse_depth_step, max_depth_value, normalized_disparity, z_to_depth, z_to_disparity)
from mvtools.geometry.homography import plane_homography
from mvtools.geometry.projection import (
    backproject, depth_along_axis, pixel_grid, project, reproject)
from mvtools.geometry.warp import forward_warp

__all__ = [
    "Camera", "turn_world", "project", "backproject", "reproject", "depth_along_axis", "pixel_grid",
    "DepthCoding", "check_depth_range", "depth_sign", "facing_camera", "inverse_depth_step",
    "depth_to_z", "z_to_depth", "disparity_to_z", "z_to_disparity", "normalized_disparity",
    "disparity_to_depth_value", "depth_value_to_disparity", "ders_depth_range",
    "disparity_1d", "max_depth_value", "plane_homography", "forward_warp",
]
