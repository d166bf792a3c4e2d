"""Multi-camera calibration from checkerboard captures.

- :mod:`~mvtools.calibration.detect`: the board, corner detection in one image;
- :mod:`~mvtools.calibration.rig`: intrinsics, lens distortion and poses of a rig.
"""

from mvtools.calibration.detect import Board, Detection, detect_board, grid_defect
from mvtools.calibration.rig import RigCalibration, calibrate_rig

__all__ = ["Board", "Detection", "RigCalibration", "calibrate_rig", "detect_board", "grid_defect"]
