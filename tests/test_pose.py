"""Quaternions, camera paths and stereo eyes (mvtools.geometry.pose).

The truth: quaternions of quarter and half turns worked out by hand (``(cos a/2, sin a/2 n)``),
the rigs of mvtools.scene.rigs (a path along a linear rig stays on its line, one along an
arc on its circle, looking at its target), straight-line interpolation written out, and
eye centres computed from the camera's right axis by hand.
"""

import math

import numpy as np
import pytest

from mvtools.geometry import Camera
from mvtools.geometry.pose import (
    camera_path,
    eye_cameras,
    quaternion_from_rotation,
    rotation_from_quaternion,
    slerp,
)
from mvtools.scene.rigs import arc_rig, linear_rig, rotation_about_y, sample_intrinsics

H = math.sqrt(0.5)

# (matrix, quaternion (w, x, y, z)) for the identity and quarter turns about x, y, z.
KNOWN = [
    (np.eye(3), [1.0, 0.0, 0.0, 0.0]),
    ([[1, 0, 0], [0, 0, -1], [0, 1, 0]], [H, H, 0.0, 0.0]),
    ([[0, 0, 1], [0, 1, 0], [-1, 0, 0]], [H, 0.0, H, 0.0]),
    ([[0, -1, 0], [1, 0, 0], [0, 0, 1]], [H, 0.0, 0.0, H]),
    (np.diag([1.0, -1.0, -1.0]), [0.0, 1.0, 0.0, 0.0]),  # half turn about x
    (np.diag([-1.0, -1.0, 1.0]), [0.0, 0.0, 0.0, 1.0]),  # half turn about z
]


@pytest.mark.parametrize(("matrix", "quaternion"), KNOWN)
def test_quaternions_of_known_rotations(matrix, quaternion):
    matrix = np.asarray(matrix, dtype=float)
    q = quaternion_from_rotation(matrix)
    np.testing.assert_allclose(q, quaternion, atol=1e-15)
    assert q[0] >= 0
    np.testing.assert_allclose(rotation_from_quaternion(quaternion), matrix, atol=1e-15)


def test_quaternion_sign_is_canonical_and_scale_free():
    # a quarter turn about -z is (h, 0, 0, -h), never (-h, 0, 0, h)
    q = quaternion_from_rotation([[0, 1, 0], [-1, 0, 0], [0, 0, 1]])
    np.testing.assert_allclose(q, [H, 0, 0, -H], atol=1e-15)
    np.testing.assert_allclose(
        rotation_from_quaternion([-2 * H, 0, 0, 2 * H]),  # -2 (h, 0, 0, -h)
        [[0, 1, 0], [-1, 0, 0], [0, 0, 1]],
        atol=1e-15,
    )


def test_quaternion_errors():
    with pytest.raises(ValueError):
        quaternion_from_rotation(np.eye(2))
    with pytest.raises(ValueError):
        quaternion_from_rotation(np.full((3, 3), np.nan))
    with pytest.raises(ValueError):
        rotation_from_quaternion([0, 0, 0, 0])
    with pytest.raises(ValueError):
        rotation_from_quaternion([1, 0, 0])


def test_slerp_midpoints_and_extrapolation():
    identity = np.array([1.0, 0, 0, 0])
    quarter_z = np.array([H, 0, 0, H])
    c, s = math.cos(math.radians(22.5)), math.sin(math.radians(22.5))
    np.testing.assert_allclose(slerp(identity, quarter_z, 0.5), [c, 0, 0, s], atol=1e-15)
    # quarter turns about x and about y are 60 degrees apart on the quaternion sphere:
    # the midpoint is their normalised sum (2h, h, h, 0) / (h sqrt 6)
    middle = slerp([H, H, 0, 0], [H, 0, H, 0], 0.5)
    np.testing.assert_allclose(middle, np.array([2, 1, 1, 0]) / math.sqrt(6), atol=1e-15)
    # -q1 is the same rotation: the shorter arc gives the same midpoint rotation
    np.testing.assert_allclose(
        rotation_from_quaternion(slerp([H, H, 0, 0], [-H, 0, -H, 0], 0.5)),
        rotation_from_quaternion(middle),
        atol=1e-15,
    )
    # continuing the quarter turn: s = 2 a half turn, s = -1 a quarter turn back
    assert abs(slerp(identity, quarter_z, 2.0) @ [0, 0, 0, 1]) == pytest.approx(1.0, abs=1e-15)
    np.testing.assert_allclose(slerp(identity, quarter_z, -1.0), [H, 0, 0, -H], atol=1e-15)
    np.testing.assert_allclose(slerp(identity, quarter_z, 0.0), identity, atol=0)
    np.testing.assert_allclose(slerp(quarter_z, quarter_z, 0.3), quarter_z, atol=1e-15)
    with pytest.raises(ValueError):
        slerp(identity, quarter_z, math.nan)


K = sample_intrinsics(256, 192)


@pytest.mark.parametrize("extend", [0.0, 0.5])
def test_path_along_a_linear_rig_stays_on_its_line(extend):
    rig = linear_rig(5, baseline=0.1, K=K, size=(256, 192), depth_range=(2.0, 13.0))
    path = camera_path(rig, 41, extend=extend)
    assert len(path) == 41
    expected_x = np.linspace(-0.2 - 0.1 * extend, 0.2 + 0.1 * extend, 41)
    for camera, x in zip(path, expected_x):
        assert camera.t[1] == 0.0 and camera.t[2] == 0.0
        assert camera.t[0] == pytest.approx(x, abs=1e-12)
        assert np.array_equal(camera.R, rig[0].R)
        assert np.array_equal(camera.K, K)
        assert camera.size == (256, 192) and camera.depth_range == (2.0, 13.0)
    if extend == 0.0:
        assert np.array_equal(path[0].t, rig[0].t) and np.array_equal(path[-1].t, rig[-1].t)
        assert np.array_equal(path[10].t, rig[1].t)  # frame 10 is keyframe 1
    assert [c.name for c in path[:2]] == ["path000", "path001"]


@pytest.mark.parametrize("extend", [0.0, 0.5])
def test_path_along_an_arc_stays_on_it_looking_at_the_target(extend):
    target = np.array([0.0, 0.0, 4.5])
    rig = arc_rig(5, radius=4.5, angle_step=5.0, target=target, K=K, size=(256, 192))
    path = camera_path(rig, 37, extend=extend)
    for camera in path:
        assert camera.t[1] == 0.0
        assert abs(np.linalg.norm(camera.t - target) - 4.5) < 1e-3 * 4.5
        towards = (target - camera.t) / np.linalg.norm(target - camera.t)
        angle = math.degrees(math.acos(min(1.0, camera.optical_axis @ towards)))
        assert angle < 0.2
        assert camera.R[1] @ [0, 1, 0] == pytest.approx(1.0, abs=1e-12)  # upright
    # the path spans the rig's angles, plus half a step beyond each end when extended
    angles = [math.degrees(math.atan2(c.t[0], -(c.t[2] - 4.5))) for c in (path[0], path[-1])]
    span = 10.0 + 5.0 * extend
    assert angles == pytest.approx([-span, span], abs=0.01)


def _camera(name, t, R, fx, depth_range=None):
    return Camera(
        name,
        [[fx, 0, 50], [0, fx, 40], [0, 0, 1]],
        R=R,
        t=t,
        size=(100, 80),
        depth_range=depth_range,
    )


def test_two_keyframes_give_a_straight_line_at_uniform_speed():
    a = _camera("a", [1.0, 2.0, 3.0], rotation_about_y(0.0), 100.0, (2.0, 10.0))
    b = _camera("b", [3.0, 2.0, -1.0], rotation_about_y(40.0), 200.0, (1.0, 8.0))
    b.size = (999, 999)  # size comes from keyframe 0
    for extend, params in [(0.0, [0, 0.25, 0.5, 0.75, 1]), (0.5, [-0.5, 0, 0.5, 1, 1.5])]:
        path = camera_path([a, b], 5, extend=extend, name="v")
        assert [c.name for c in path] == ["v000", "v001", "v002", "v003", "v004"]
        for camera, s in zip(path, params):
            expected = np.array([1 + 2 * s, 2.0, 3 - 4 * s])
            np.testing.assert_allclose(camera.t, expected, atol=1e-14)
            np.testing.assert_allclose(camera.R, rotation_about_y(40.0 * s), atol=1e-14)
            assert camera.fx == pytest.approx(100 + 100 * s, abs=1e-12)
            assert camera.cx == 50 and camera.cy == 40
            assert camera.size == (100, 80)
            assert camera.depth_range == (1.0, 10.0)
    path = camera_path([a, b], 5)
    assert np.array_equal(path[0].R, a.R) and np.array_equal(path[-1].R, b.R)
    assert np.array_equal(path[-1].t, b.t) and np.array_equal(path[-1].K, b.K)


def test_a_single_keyframe_stands_still_and_bad_arguments_are_refused():
    a = _camera("a", [1.0, 2.0, 3.0], np.eye(3), 100.0)
    path = camera_path([a], 3)
    assert [c.name for c in path] == ["path000", "path001", "path002"]
    assert all(np.array_equal(c.t, a.t) and c.depth_range is None for c in path)
    b = _camera("b", [2.0, 2.0, 3.0], np.eye(3), 100.0)
    for keyframes, frames, extend in [([], 3, 0.0), ([a, b], 1, 0.0), ([a, b], 3, -1.0)]:
        with pytest.raises(ValueError):
            camera_path(keyframes, frames, extend=extend)
    with pytest.raises(ValueError):
        camera_path([a, b], 3, extend=math.inf)


def test_eye_cameras_of_a_turned_camera():
    # turned 90 degrees towards +x: its right (R[0]) is world -z
    camera = _camera("c", [1.0, 2.0, 3.0], rotation_about_y(90.0), 100.0)
    left, right = eye_cameras(camera, 0.1)
    assert (left.name, right.name) == ("c_left", "c_right")
    np.testing.assert_allclose(left.t, [1.0, 2.0, 3.05], atol=1e-15)
    np.testing.assert_allclose(right.t, [1.0, 2.0, 2.95], atol=1e-15)
    for eye in (left, right):
        assert np.array_equal(eye.R, camera.R) and np.array_equal(eye.K, camera.K)
        assert eye.size == camera.size
    np.testing.assert_array_equal(camera.t, [1.0, 2.0, 3.0])  # the camera is left alone
    for ipd in (0.0, -0.1, math.nan, math.inf):
        with pytest.raises(ValueError):
            eye_cameras(camera, ipd)
