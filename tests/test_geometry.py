"""Projection, depth conversions, plane homographies and forward warping."""

import numpy as np
import pytest
from shared_data import shared_data

from mvtools.geometry import (
    Camera,
    DepthCoding,
    backproject,
    depth_along_axis,
    depth_to_z,
    depth_value_to_disparity,
    ders_depth_range,
    disparity_1d,
    disparity_to_depth_value,
    disparity_to_z,
    facing_camera,
    forward_warp,
    normalized_disparity,
    pixel_grid,
    plane_homography,
    project,
    reproject,
    turn_world,
    z_to_depth,
    z_to_disparity,
)
from mvtools.io.cameras import read_cameras
from mvtools.scene.rigs import axis_angle_rotation

CAMERAS = ("mpeg", "vsrs_camera_parameters")


def _cameras(name):
    return read_cameras(shared_data(*CAMERAS, name))


@pytest.fixture(scope="module")
def kendo():
    return read_cameras(shared_data("mpeg", "kendo", "config", "VSRS", "cam_param_kendo.cfg"))


def _random_pixels(rng, count, width=1024, height=768):
    return rng.uniform(0, width, count), rng.uniform(0, height, count)


# ---------------------------------------------------------------- projection


def test_pixel_grid():
    u, v = pixel_grid(4, 3)
    assert u.shape == v.shape == (3, 4)
    np.testing.assert_array_equal(u[2], [0, 1, 2, 3])
    np.testing.assert_array_equal(v[:, 1], [0, 1, 2])
    with pytest.raises(ValueError):
        pixel_grid(0, 3)


def test_project_hand_computed(kendo):
    uv, z = project(kendo["param_kendo01"], [[105.0, 50.0, 1000.0], [5.0, 0.0, 2000.0]])
    np.testing.assert_allclose(
        uv, [[2241.25607 * 0.1 + 701.5, 2241.25607 * 0.05 + 514.5], [701.5, 514.5]], rtol=1e-15
    )
    np.testing.assert_array_equal(z, [1000.0, 2000.0])


def test_project_with_axis_flip_rotation():
    news = _cameras("cam_param_news.txt")["param_news00"]
    # R = diag(1, -1, -1): the camera looks along world -z, image y is world -y.
    uv, z = project(news, [news.t[0] + 100.0, 30.0, -2000.0])
    assert z == 2000.0
    np.testing.assert_allclose(
        uv,
        [
            2929.4940521927465 * 100 / 2000 + 307.63334410569644,
            2922.7064498725026 * -30 / 2000 + 555.0109690422262,
        ],
        rtol=1e-15,
    )


@pytest.mark.parametrize(
    "name", ["cam_param_lovebird1_original.txt", "cam_param_bbb_butterfly2_arc+Znear-far.txt"]
)
def test_backproject_inverts_project_for_rotated_cameras(name):
    rng = np.random.default_rng(3)
    for camera in list(_cameras(name).values())[::4]:
        u, v = _random_pixels(rng, 100)
        z = rng.uniform(1.0, 5000.0, 100)
        points = backproject(camera, u, v, z)
        uv, depth = project(camera, points)
        np.testing.assert_allclose(uv, np.stack([u, v], axis=-1), rtol=0, atol=1e-8)
        np.testing.assert_allclose(depth, z, rtol=1e-12)
        # Depth is along the axis: the point lies z in front of the centre along R[2].
        np.testing.assert_allclose((points - camera.t) @ camera.optical_axis, z, rtol=1e-12)


def test_backproject_accepts_images_and_validates():
    camera = Camera("c", [[500, 0, 320], [0, 500, 240], [0, 0, 1]])
    u, v = pixel_grid(6, 5)
    assert backproject(camera, u, v, np.full((5, 6), 10.0)).shape == (5, 6, 3)
    assert backproject(camera, u, v, 10.0).shape == (5, 6, 3)
    for bad in (0.0, -1.0, np.nan):
        with pytest.raises(ValueError, match="positive"):
            backproject(camera, u, v, bad)
    with pytest.raises(ValueError, match="depth_type"):
        backproject(camera, u, v, 1.0, depth_type=2)
    with pytest.raises(ValueError, match="shape"):
        project(camera, [1.0, 2.0])


# ---------------------------------------------------------------- depth types


def test_depth_types_agree_for_a_camera_at_the_origin_looking_along_world_z(kendo):
    rng = np.random.default_rng(5)
    u, v = _random_pixels(rng, 50)
    z = rng.uniform(400, 12000, 50)
    origin = Camera("o", kendo["param_kendo01"].K)
    np.testing.assert_array_equal(
        backproject(origin, u, v, z, depth_type=1), backproject(origin, u, v, z, depth_type=0)
    )
    # Kendo cameras only move along x: world z is still the depth.
    camera = kendo["param_kendo03"]
    np.testing.assert_allclose(
        backproject(camera, u, v, z, depth_type=1), backproject(camera, u, v, z), rtol=1e-15
    )


def test_depth_type_1_on_a_rotated_camera():
    camera = _cameras("cam_param_bbb_butterfly2_arc+Znear-far.txt")["param_ptm05"]
    c, s = 0.939692620786, 0.342020143326  # R = [[c, 0, -s], [0, 1, 0], [s, 0, c]]
    u, v = camera.cx + 0.5 * camera.fx, camera.cy  # normalised image x = 0.5
    world_z = 0.25
    # The ray R^T (0.5, 0, 1) climbs c - 0.5 s in world z per unit of depth.
    depth = (world_z - -1.45652356222) / (c - 0.5 * s)
    point = backproject(camera, u, v, world_z, depth_type=1)
    assert abs(point[2] - world_z) < 1e-14
    np.testing.assert_allclose(point, backproject(camera, u, v, depth), rtol=1e-14)
    np.testing.assert_allclose(
        depth_along_axis(camera, u, v, world_z, depth_type=1), depth, rtol=1e-14
    )
    # As depth along the axis the same number is a different point.
    assert np.abs(backproject(camera, u, v, world_z) - point).max() > 0.1


def test_depth_type_1_behind_the_camera_as_vsrs_computes_it():
    news = _cameras("cam_param_news.txt")["param_news03"]
    # The camera looks along world -z from z = 0: the plane Z = 3000 is behind it.
    depth = depth_along_axis(
        news, np.array([0.0, 500.0]), np.array([0.0, 700.0]), 3000.0, depth_type=1
    )
    np.testing.assert_allclose(depth, [-3000.0, -3000.0], rtol=1e-15)


# ---------------------------------------------------------------- depth values


def test_depth_values_to_z_hand_computed():
    np.testing.assert_allclose(
        depth_to_z(np.array([255, 51, 0], np.uint8), 100.0, 200.0),
        [100.0, 1 / 0.006, 200.0],
        rtol=1e-14,
    )
    np.testing.assert_allclose(
        depth_to_z([1023, 341, 0], 100.0, 200.0, bits=10), [100.0, 150.0, 200.0], rtol=1e-14
    )
    # Kendo's range: the value 255 is Znear, 0 is Zfar.
    np.testing.assert_allclose(
        depth_to_z([255, 0], 448.251214, 11206.280350), [448.251214, 11206.280350], rtol=1e-14
    )
    assert depth_to_z(0, 100.0, np.inf) == np.inf
    assert depth_to_z(127.5, 100.0, np.inf) == 200.0


def test_z_to_depth_rounds_and_clips():
    values = z_to_depth([100.0, 1 / 0.006, 200.0, 50.0, 1e6, np.inf], 100.0, 200.0)
    assert values.dtype == np.uint8
    np.testing.assert_array_equal(values, [255, 51, 0, 255, 0, 0])
    # 255 (1/z - 1/Zfar) / (1/Znear - 1/Zfar) = 128.01 and 126.99 round to the nearest.
    np.testing.assert_array_equal(z_to_depth([1 / 0.00751, 1 / 0.00749], 100.0, 200.0), [128, 127])
    tenbit = z_to_depth(150.0, 100.0, 200.0, bits=10)
    assert tenbit.dtype == np.uint16 and tenbit == 341


@pytest.mark.parametrize("bits", [8, 10, 16])
def test_depth_round_trip_over_every_value(bits):
    values = np.arange(2**bits, dtype=np.uint16 if bits > 8 else np.uint8)
    np.testing.assert_array_equal(
        z_to_depth(
            depth_to_z(values, 448.251214, 11206.28035, bits=bits),
            448.251214,
            11206.28035,
            bits=bits,
        ),
        values,
    )


def test_depth_validation():
    cases = {
        (200.0, 100.0): "farther than",
        (-100.0, -50.0): "farther than",
        (100.0, 100.0): "farther than",
        (0.0, 100.0): "Znear must be finite and not 0",
        (100.0, 0.0): "Zfar must not be 0",
        (-5.0, 100.0): "opposite signs",
        (5.0, -100.0): "opposite signs",
    }
    for (znear, zfar), message in cases.items():
        with pytest.raises(ValueError, match=message):
            depth_to_z([0], znear, zfar)
        with pytest.raises(ValueError, match=message):
            z_to_depth([150.0], znear, zfar)
    with pytest.raises(ValueError, match=r"0\.\.255"):
        depth_to_z([256], 100.0, 200.0)
    with pytest.raises(ValueError, match="not be 0"):
        z_to_depth([150.0, 0.0], 100.0, 200.0)
    with pytest.raises(ValueError, match="8 to 16 bits"):
        depth_to_z([0], 100.0, 200.0, bits=7)


def test_negative_range_is_the_positive_one_signed():
    """Poznan's ranges: 1/z = v/255 (1/Znear - 1/Zfar) + 1/Zfar with signed z."""
    z = depth_to_z(np.array([255, 51, 0], np.uint8), -100.0, -200.0)
    np.testing.assert_allclose(z, [-100.0, -1 / 0.006, -200.0], rtol=1e-14)
    np.testing.assert_array_equal(
        z_to_depth([-100.0, -1 / 0.006, -200.0, -50.0, -1e6], -100.0, -200.0), [255, 51, 0, 255, 0]
    )
    coding = DepthCoding((-100.0, -200.0), 8, depth_type=0)
    np.testing.assert_allclose(
        coding.z(np.array([255, 51, 0])), [100.0, 1 / 0.006, 200.0], rtol=1e-14
    )
    np.testing.assert_array_equal(
        coding.values(np.array([100.0, 1 / 0.006, 200.0, np.inf])), [255, 51, 0, 0]
    )
    assert coding.inverse_step == pytest.approx((1 / 100 - 1 / 200) / 255, rel=1e-14)


@pytest.mark.parametrize("bits", [8, 16])
def test_depth_coding_is_depth_to_z_and_back(bits):
    coding = DepthCoding((448.251214, 11206.28035), bits, depth_type=0)
    values = np.arange(2**bits)
    np.testing.assert_array_equal(
        coding.z(values), depth_to_z(values, 448.251214, 11206.28035, bits=bits)
    )
    np.testing.assert_array_equal(coding.values(coding.z(values)), values)
    # Nothing seen (inf) is the farthest value.
    assert coding.values(np.array([np.inf]))[0] == 0


def test_depth_coding_of_a_range_through_the_world_origin():
    # DepthType 1, Znear > 0 > Zfar (the shipped Big Buck Bunny arc configuration):
    # 1/z runs linearly from 1/Zfar < 0 (value 0) to 1/Znear (value 255).
    znear, zfar = 0.464901, -2.424092
    coding = DepthCoding((znear, zfar), 8, depth_type=1)
    z = coding.z(np.array([0, 255]))
    np.testing.assert_allclose(z, [zfar, znear])
    inverse = 1 / zfar + 100 / 255 * (1 / znear - 1 / zfar)
    np.testing.assert_allclose(coding.z(np.array([100])), 1 / inverse)
    np.testing.assert_array_equal(coding.values(coding.z(np.arange(256))), np.arange(256))
    assert coding.values(np.array([np.inf]))[0] == 0
    # A very far point: 1/z = 0 is the value that solves 0 = 1/Zfar + v/255 (1/Znear - 1/Zfar).
    assert coding.values(np.array([1e12]))[0] == round(-255 * (1 / zfar) / (1 / znear - 1 / zfar))
    with pytest.raises(ValueError, match="opposite signs"):
        DepthCoding((znear, zfar), 8, depth_type=0)


def test_facing_camera_turns_cameras_that_look_away_from_the_range():
    camera = Camera("c", K=[[1000, 0, 320], [0, 1000, 240], [0, 0, 1]], t=[1.0, 2.0, 3.0])
    assert facing_camera(camera, (10.0, 20.0)) is camera
    turned = facing_camera(camera, (-10.0, -20.0))
    np.testing.assert_array_equal(turned.R, -camera.R)
    np.testing.assert_array_equal(turned.t, camera.t)
    # The same pixel for every point, and depth along the axis of the other sign.
    points = np.array([[0.5, -1.0, -7.0], [3.0, 4.0, 11.0]])
    for point in points:
        (uv, z), (uv_turned, z_turned) = project(camera, point), project(turned, point)
        np.testing.assert_allclose(uv_turned, uv, rtol=1e-14)
        assert z_turned == pytest.approx(-z, rel=1e-14)
    # DepthType 1, Newspaper's axes (R = diag(1, -1, -1): the camera looks along world
    # -z): a positive world-z range lies behind it at t_z = 0, a negative one in front.
    news = Camera("n", K=camera.K, R=np.diag([1.0, -1.0, -1.0]))
    assert facing_camera(news, (-2715.18, -9050.61), depth_type=1) is news
    np.testing.assert_array_equal(
        facing_camera(news, (3393.98, 7542.17), depth_type=1).R, np.diag([-1.0, 1.0, 1.0])
    )


# ---------------------------------------------------------------- disparity


def test_disparity_and_z():
    np.testing.assert_array_equal(
        disparity_to_z([10.0, 20.0, 0.0], 1000.0, 0.5), [50.0, 25.0, np.inf]
    )
    np.testing.assert_array_equal(
        z_to_disparity([50.0, 25.0, np.inf], 1000.0, 0.5), [10.0, 20.0, 0.0]
    )
    with pytest.raises(ValueError):
        disparity_to_z([-1.0], 1000.0, 0.5)
    with pytest.raises(ValueError):
        z_to_disparity([10.0], 1000.0, 0.0)


def test_normalized_disparity_and_ders_labels():
    np.testing.assert_array_equal(
        normalized_disparity([10.0, 35.0, 60.0], 10.0, 60.0), [0.0, 127.5, 255.0]
    )
    labels = disparity_to_depth_value([10.0, 35.0, 60.0, 70.0, 0.0], 10.0, 60.0)
    assert labels.dtype == np.uint8
    np.testing.assert_array_equal(labels, [0, 128, 255, 255, 0])
    np.testing.assert_allclose(
        depth_value_to_disparity([0, 51, 255], 10.0, 60.0), [10.0, 20.0, 60.0], rtol=1e-15
    )
    # A decreasing mapping, as the inverse depths of negative ranges make.
    np.testing.assert_array_equal(
        normalized_disparity([60.0, 35.0, 10.0], 60.0, 10.0), [0.0, 127.5, 255.0]
    )
    with pytest.raises(ValueError, match="dmin != dmax"):
        normalized_disparity([1.0], 5.0, 5.0)


def test_ders_depth_range_matches_the_depth_value_formula():
    znear, zfar = ders_depth_range(1000.0, 10.0, 5.0, 45.0, offset=5.0)
    assert (znear, zfar) == (200.0, 1000.0)
    assert ders_depth_range(1000.0, 10.0, 0.0, 40.0) == (250.0, np.inf)
    # Writing disparity d as a DERS label equals writing z = f B / (d + off) as depth.
    d = np.random.default_rng(2).uniform(5.0, 45.0, 1000)
    np.testing.assert_array_equal(
        disparity_to_depth_value(d, 5.0, 45.0), z_to_depth(1000.0 * 10.0 / (d + 5.0), znear, zfar)
    )
    with pytest.raises(ValueError):
        ders_depth_range(1000.0, 10.0, -6.0, 45.0, offset=5.0)


def test_disparity_1d_on_kendo_agrees_with_3d_reprojection(kendo):
    left, right = kendo["param_kendo01"], kendo["param_kendo03"]
    z = np.array([500.0, 1000.0, 8000.0])
    d = disparity_1d(
        z,
        focal=left.fx,
        tx_ref=left.t[0],
        tx_virtual=right.t[0],
        cx_ref=left.cx,
        cx_virtual=right.cx,
    )
    np.testing.assert_allclose(d, 2241.25607 * 10 / z, rtol=1e-15)
    u2, v2, z2 = reproject(left, right, 500.0, 300.0, z)
    np.testing.assert_allclose(u2, 500.0 - d, rtol=1e-14)
    np.testing.assert_allclose(v2, 300.0, rtol=1e-14)
    np.testing.assert_allclose(z2, z, rtol=1e-15)
    # Principal points enter with the opposite sign.
    shifted = disparity_1d(
        1000.0, focal=1000.0, tx_ref=0.0, tx_virtual=1.0, cx_ref=500.0, cx_virtual=510.0
    )
    assert shifted == 1.0 - 10.0


# ---------------------------------------------------------------- reprojection, homography


def test_reproject_equals_backproject_then_project():
    cameras = list(_cameras("cam_param_lovebird1_original.txt").values())
    rng = np.random.default_rng(11)
    u, v = _random_pixels(rng, 200)
    z = rng.uniform(1500, 20000, 200)
    for depth_type in (0, 1):
        src, dst = cameras[0], cameras[5]
        u2, v2, z2 = reproject(src, dst, u, v, z, depth_type=depth_type)
        uv, depth = project(dst, backproject(src, u, v, z, depth_type=depth_type))
        np.testing.assert_allclose(np.stack([u2, v2], -1), uv, rtol=1e-11)
        np.testing.assert_allclose(z2, depth, rtol=1e-11)


def _apply(homography, u, v):
    mapped = homography @ np.stack([u, v, np.ones_like(u)])
    return mapped[0] / mapped[2], mapped[1] / mapped[2]


@pytest.mark.parametrize(
    "name, src, dst, z, depth_type",
    [
        ("cam_param_lovebird1_original.txt", "param_loveb1_001", "param_loveb1_006", 3000.0, 0),
        ("cam_param_bbb_butterfly2_arc+Znear-far.txt", "param_ptm05", "param_ptm20", 2.0, 0),
        ("cam_param_bbb_butterfly2_arc+Znear-far.txt", "param_ptm05", "param_ptm20", 0.3, 1),
        ("cam_param_news.txt", "param_news03", "param_news06", 4000.0, 1),
    ],
)
def test_plane_homography_agrees_with_reproject(name, src, dst, z, depth_type):
    cameras = _cameras(name)
    u, v = _random_pixels(np.random.default_rng(4), 100)
    expected_u, expected_v, _ = reproject(
        cameras[src], cameras[dst], u, v, z, depth_type=depth_type
    )
    mapped_u, mapped_v = _apply(
        plane_homography(cameras[src], cameras[dst], z, depth_type=depth_type), u, v
    )
    np.testing.assert_allclose(mapped_u, expected_u, rtol=0, atol=1e-8)
    np.testing.assert_allclose(mapped_v, expected_v, rtol=0, atol=1e-8)


def test_plane_homography_vectorised_and_validated(kendo):
    left, right = kendo["param_kendo01"], kendo["param_kendo03"]
    planes = np.array([500.0, 1000.0, 4000.0])
    stacked = plane_homography(left, right, planes)
    assert stacked.shape == (3, 3, 3)
    for homography, z in zip(stacked, planes):
        np.testing.assert_array_equal(homography, plane_homography(left, right, z))
        # Rectified pair: a pure horizontal shift by the disparity.
        np.testing.assert_allclose(
            homography, [[1, 0, -2241.25607 * 10 / z], [0, 1, 0], [0, 0, 1]], atol=1e-12
        )
    with pytest.raises(ValueError):
        plane_homography(left, right, 0.0)
    with pytest.raises(ValueError, match="centre"):
        plane_homography(left, right, 0.0, depth_type=1)


# ---------------------------------------------------------------- forward warping


def _rig(shift):
    """A source camera at the origin and a target moved by ``shift`` along x, f = 100."""
    K = [[100.0, 0, 0], [0, 100.0, 0], [0, 0, 1]]
    return Camera("src", K), Camera("dst", K, t=[shift, 0.0, 0.0])


def test_forward_warp_shifts_a_plane_by_its_disparity():
    src, dst = _rig(1.0)
    values = np.arange(4 * 6, dtype=np.uint8).reshape(4, 6)
    warped, warped_z, filled = forward_warp(values, np.full((4, 6), 100.0), src, dst)
    # Disparity f B / z = 1 pixel to the left.
    np.testing.assert_array_equal(warped[:, :5], values[:, 1:])
    np.testing.assert_array_equal(filled[:, :5], True)
    np.testing.assert_array_equal(filled[:, 5], False)
    np.testing.assert_array_equal(warped[:, 5], 0)
    np.testing.assert_array_equal(warped_z[:, :5], 100.0)
    assert np.all(np.isinf(warped_z[:, 5]))
    assert warped.dtype == np.uint8


@pytest.mark.parametrize("shift", [1.0, -1.0])
def test_forward_warp_nearer_surface_wins_in_either_order(shift):
    src, dst = _rig(shift)
    z = np.full((1, 10), 100.0)  # 1 pixel of disparity
    z[0, 5] = 50.0  # foreground: 2 pixels
    values = np.arange(10, dtype=np.float32)[None]
    warped, warped_z, filled = forward_warp(values, z, src, dst)
    direction = -int(shift)
    # The foreground pixel lands where background pixel 5 - direction also lands.
    assert warped[0, 5 + 2 * direction] == 5.0
    assert warped_z[0, 5 + 2 * direction] == 50.0
    # Where background pixel 5 would have gone nothing lands (disocclusion).
    assert not filled[0, 5 + direction]
    assert filled.sum() == 8


def test_forward_warp_ties_go_to_the_first_source_pixel():
    src = Camera("src", [[100.0, 0, 0], [0, 100.0, 0], [0, 0, 1]])
    dst = Camera("dst", [[50.0, 0, 0], [0, 100.0, 0], [0, 0, 1]])
    values = np.arange(1, 7, dtype=np.uint8)[None].repeat(2, axis=0)
    values = np.stack([values, 10 * values], axis=-1)  # (H, W, C)
    warped, _warped_z, filled = forward_warp(values, np.full((2, 6), 7.0), src, dst)
    # u2 = u / 2 rounded half up: 0->0, 1->1, 2->1, 3->2, 4->2, 5->3.
    np.testing.assert_array_equal(warped[0, :4, 0], [1, 2, 4, 6])
    np.testing.assert_array_equal(warped[1, :4, 1], [10, 20, 40, 60])
    np.testing.assert_array_equal(filled[0], [True, True, True, True, False, False])


def test_forward_warp_drops_points_behind_the_target_and_validates():
    src = Camera("src", [[100.0, 0, 2], [0, 100.0, 2], [0, 0, 1]])
    values = np.arange(25.0).reshape(5, 5)
    plane = np.full((5, 5), 5.0)
    # Both targets look along world -z; the plane z = 5 is behind the one at z = -10.
    behind = Camera("dst", src.K, R=np.diag([-1.0, 1.0, -1.0]), t=[0.0, 0.0, -10.0])
    _, warped_z, filled = forward_warp(values, plane, src, behind)
    assert not filled.any() and np.all(np.isinf(warped_z))
    # From z = 10 it sees the plane mirrored left-right; out_size sets the frame.
    facing = Camera("dst", src.K, R=np.diag([-1.0, 1.0, -1.0]), t=[0.0, 0.0, 10.0])
    warped, warped_z, filled = forward_warp(values, plane, src, facing, out_size=(7, 6))
    assert filled.shape == (6, 7) and filled.sum() == 25
    np.testing.assert_array_equal(warped[:5, :5], values[:, ::-1])
    np.testing.assert_array_equal(warped_z[filled], 5.0)
    with pytest.raises(ValueError, match="same"):
        forward_warp(values, np.ones((5, 4)), src, behind)
    with pytest.raises(ValueError, match="positive"):
        forward_warp(values, -plane, src, behind)


def test_turning_the_world_changes_no_picture():
    rotation = axis_angle_rotation((0.3, -1.0, 0.2), 17.0)
    camera = Camera(
        "c",
        K=[[500.0, 0, 320], [0, 505.0, 240], [0, 0, 1]],
        R=axis_angle_rotation((1.0, 0.5, 0.0), 8.0),
        t=[0.4, -0.1, 2.0],
    )
    points = np.random.default_rng(1).uniform(-2, 2, (20, 3)) + [0.0, 0.0, 8.0]
    (turned,) = turn_world([camera], rotation)
    uv, z = project(camera, points)
    uv_turned, z_turned = project(turned, points @ rotation.T)
    np.testing.assert_allclose(uv_turned, uv, atol=1e-9)
    np.testing.assert_allclose(z_turned, z, atol=1e-12)
    # the world taking the camera's own orientation gives it exactly the identity
    np.testing.assert_array_equal(turn_world([camera], camera.R)[0].R, np.eye(3))
    with pytest.raises(ValueError, match="rotation"):
        turn_world([camera], np.diag([1.0, 1.0, -1.0]))
