"""The reference programs' cases and scores, for the tests and ``make bench`` alike.

Every number is one of the reference outputs' README (``reference_outputs/README.md``
of the shared data): what VSRS 4.2 and RVS 4.0 score on the inputs there.
"""

#: VSRS 4.2's Y-PSNR of Cones im4 by mode, Precision and BoundaryNoiseRemoval;
#: Precision 1 in general mode is the ipelfix build (VSRS 4.2 as released fails there).
VSRS_CONES = {
    ("general", 1, 0): 29.80,
    ("general", 1, 1): 30.13,
    ("general", 2, 0): 29.995,
    ("general", 2, 1): 30.194,
    ("general", 4, 0): 30.068,
    ("general", 4, 1): 30.288,
    ("1d", 1, 0): 29.139,
    ("1d", 2, 0): 30.853,
    ("1d", 4, 0): 30.028,
}
#: RVS 4.0's Y-PSNR of Cones im4 with its default settings.
RVS_CONES = 30.281

#: VSRS 4.2's Y-PSNR of Poznan Hall 2 camera 7 from camera 5 alone.
VSRS_HALL_FROM_CAMERA_5 = {"general": 31.58, "1d": 32.67}

#: SynthesisMode of each mode's name.
MODES = {"general": 0, "1d": 1}

#: Camera 5 as the right view too, with its own depth range (the shipped
#: configuration's right view is camera 7).
CAMERA_5_AS_RIGHT = (
    "RightCameraName=param_cam5",
    r"RightViewImageName=..\data\hall\hall_I_cam05.yuv",
    r"RightDepthMapName=..\data\hall\hall_D_cam05.yuv",
    "RightNearestDepthValue=-23.394160",
    "RightFarthestDepthValue=-172.531931",
)
