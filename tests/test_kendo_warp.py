"""End-to-end proof of the camera and depth conventions on real MPEG material.

View 1 of Kendo, warped into camera 3 with its own depth map, must look like the
real view 3 wherever it lands. Each convention on the way (camera file layout,
``t`` as the camera centre, 255 = Znear, inverse-depth quantisation, projection
signs) is exercised; breaking one of them makes the views disagree, which the
test shows by breaking two of them on purpose.
"""

import numpy as np
import pytest
from shared_data import shared_data

from mvtools.geometry import Camera, depth_to_z, forward_warp
from mvtools.io.cameras import get_camera, read_cameras
from mvtools.io.config import read_config
from mvtools.io.yuv import YuvFormat, read_frame

FORMAT = YuvFormat(1024, 768)


@pytest.fixture(scope="module")
def kendo():
    folder = shared_data("mpeg", "kendo")
    config = read_config(folder / "config" / "VSRS" / "vsrs_kendo_ori.cfg")
    cameras = read_cameras(folder / "config" / "VSRS" / "cam_param_kendo.cfg")

    def luma(name):
        return read_frame(folder / f"kendo_ori_{name}.yuv", FORMAT)[0]

    return {
        "left": get_camera(cameras, config["LeftCameraName"].value),
        "right": get_camera(cameras, config["RightCameraName"].value),
        "znear": float(config["LeftNearestDepthValue"].value),
        "zfar": float(config["LeftFarthestDepthValue"].value),
        "texture": luma("I_1"),
        "depth": luma("D_1"),
        "target": luma("I_3"),
    }


def _luma_error(kendo, z, dst):
    """Absolute luma differences to the real view 3 over the pixels that land."""
    warped, _, filled = forward_warp(kendo["texture"], z, kendo["left"], dst)
    assert filled.mean() > 0.9
    return np.abs(warped[filled].astype(np.int16) - kendo["target"][filled].astype(np.int16))


def test_config_names_the_expected_cameras_and_range(kendo):
    assert (kendo["left"].name, kendo["right"].name) == ("param_kendo01", "param_kendo03")
    assert (kendo["znear"], kendo["zfar"]) == (448.251214, 11206.280350)


def test_view_1_warped_into_camera_3_matches_view_3(kendo):
    z = depth_to_z(kendo["depth"], kendo["znear"], kendo["zfar"])
    error = _luma_error(kendo, z, kendo["right"])
    # Measured: median 2, mean 3.45. Unwarped, the views differ by a median of 6.
    assert np.median(error) <= 4
    assert error.mean() < 5
    unwarped = np.abs(kendo["texture"].astype(np.int16) - kendo["target"].astype(np.int16))
    assert np.median(error) < np.median(unwarped)


def test_wrong_conventions_are_detected(kendo):
    z = depth_to_z(kendo["depth"], kendo["znear"], kendo["zfar"])
    right = kendo["right"]
    # Baseline sign flipped: camera 3 put on the other side of camera 1 (median 12).
    mirrored = Camera("mirrored", right.K, right.R, 2 * kendo["left"].t - right.t)
    assert np.median(_luma_error(kendo, z, mirrored)) > 8
    # Depth read with Znear and Zfar swapped (0 = near): mean 10.7 against 3.45.
    swapped = 1.0 / (
        kendo["depth"] / 255.0 * (1 / kendo["zfar"] - 1 / kendo["znear"]) + 1 / kendo["znear"]
    )
    assert _luma_error(kendo, swapped, right).mean() > 8
