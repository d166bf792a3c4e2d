"""Camera geometry: projection, back-projection, depth conversions, homographies.

Cameras follow VSRS and DERS (:class:`Camera`: ``x_cam = R (X - t)``, looking along +z);
depth maps store values linear in inverse depth (:class:`DepthCoding`,
:func:`depth_to_z`, :func:`z_to_depth`), rectified pairs relate disparity and depth by
``z = f B / d`` (:func:`z_to_disparity`, :func:`disparity_to_z`).

Names are imported from their modules on first use, so ``import mvtools.geometry`` is
cheap.
"""

from __future__ import annotations

from mvtools.lazy import attach

#: Each exported name and the module of this package that defines it.
_EXPORTS: dict[str, str] = {
    "Camera": "camera",
    "same_camera": "camera",
    "turn_world": "camera",
    "camera_path": "pose",
    "eye_cameras": "pose",
    "quaternion_from_rotation": "pose",
    "rotation_from_quaternion": "pose",
    "slerp": "pose",
    "DepthCoding": "depth",
    "check_depth_range": "depth",
    "depth_sign": "depth",
    "depth_to_z": "depth",
    "depth_value_to_disparity": "depth",
    "ders_depth_range": "depth",
    "disparity_1d": "depth",
    "disparity_to_depth_value": "depth",
    "disparity_to_z": "depth",
    "facing_camera": "depth",
    "inverse_depth_step": "depth",
    "max_depth_value": "depth",
    "normalized_disparity": "depth",
    "z_to_depth": "depth",
    "z_to_disparity": "depth",
    "plane_homography": "homography",
    "backproject": "projection",
    "depth_along_axis": "projection",
    "pixel_grid": "projection",
    "project": "projection",
    "reproject": "projection",
    "forward_warp": "warp",
}

__getattr__, __dir__, __all__ = attach(__name__, _EXPORTS)
