"""A synthetic multiview scene with exact ground truth (the project's sample data).

- :mod:`~mvtools.scene.content`: textures, primitives, motion, :func:`default_scene`;
- :mod:`~mvtools.scene.render`: exact ray casting through lens distortion, :func:`render`;
- :mod:`~mvtools.scene.rigs`: linear and arc rigs, imperfections, colour mismatch;
- :mod:`~mvtools.scene.checkerboard`: calibration captures with their ground truth.
"""

from mvtools.scene.checkerboard import (
    Checkerboard,
    CheckerboardCaptures,
    board_poses,
    calibration_rig,
    capture_checkerboard,
    corner_visibility,
)
from mvtools.scene.content import (
    GROUND_Y,
    Box,
    Cylinder,
    NoiseTexture,
    Plane,
    Rectangle,
    Scene,
    Sphere,
    UniformTexture,
    default_scene,
    fractal_noise,
)
from mvtools.scene.render import Rendering, quantize, render
from mvtools.scene.rigs import (
    ColorMismatch,
    arc_rig,
    axis_angle_rotation,
    intrinsics,
    linear_rig,
    perturb_rig,
    random_color_mismatches,
    rotation_about_y,
    sample_intrinsics,
    sample_rigs,
)

__all__ = [
    "GROUND_Y",
    "Box",
    "Checkerboard",
    "CheckerboardCaptures",
    "ColorMismatch",
    "Cylinder",
    "NoiseTexture",
    "Plane",
    "Rectangle",
    "Rendering",
    "Scene",
    "Sphere",
    "UniformTexture",
    "arc_rig",
    "axis_angle_rotation",
    "board_poses",
    "calibration_rig",
    "capture_checkerboard",
    "corner_visibility",
    "default_scene",
    "fractal_noise",
    "intrinsics",
    "linear_rig",
    "perturb_rig",
    "quantize",
    "random_color_mismatches",
    "render",
    "rotation_about_y",
    "sample_intrinsics",
    "sample_rigs",
]
