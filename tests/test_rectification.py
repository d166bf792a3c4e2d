"""Lens distortion removal and rectification of camera arrays.

Truth: the exact cameras of the synthetic "distorted" rig (``sample_data/truth.json``)
and its scene, rendered again where needed; the published MPEG camera files of linear
arrays; hand-computed values.
"""

import json
import re
from pathlib import Path

import cv2
import numpy as np
import pytest
from scipy.ndimage import map_coordinates
from shared_data import shared_data

from mvtools.errors import DataError
from mvtools.geometry.camera import Camera
from mvtools.geometry.depth import depth_to_z
from mvtools.geometry.lens import pixel_rays, project_points
from mvtools.geometry.projection import project
from mvtools.io.cameras import read_cameras
from mvtools.io.yuv import read_frame
from mvtools.rectification import (
    EDGE_TOLERANCE,
    chroma_maps,
    rectified_depth,
    rectify_cameras,
    remap_plane,
    undistortion,
)
from mvtools.scene import default_scene, render, rotation_about_y

SAMPLE = Path(__file__).resolve().parent.parent / "sample_data"
TRUTH = json.loads((SAMPLE / "truth.json").read_text())
ZNEAR, ZFAR = TRUTH["znear"], TRUTH["zfar"]


def _distorted_rig() -> list[Camera]:
    return [
        Camera(
            name=c["name"],
            K=c["K"],
            R=c["R"],
            t=c["t"],
            distortion=c["distortion"],
            size=tuple(c["size"]),
            depth_range=(ZNEAR, ZFAR),
        )
        for c in TRUTH["rigs"]["distorted"]
    ]


@pytest.fixture(scope="module")
def rig():
    return _distorted_rig()


@pytest.fixture(scope="module")
def rectified(rig):
    return rectify_cameras(rig, alpha=0.0)


def _visible_points(cameras, count, *, seed, depth_range=(ZNEAR, ZFAR)):
    """Random world points seen by every camera: pixels of the middle camera at random
    depths, kept where all cameras (through their distortion) see them."""
    rng = np.random.default_rng(seed)
    middle = cameras[len(cameras) // 2]
    width, height = middle.size
    u, v = rng.uniform(0, width - 1, count), rng.uniform(0, height - 1, count)
    z = rng.uniform(*depth_range, count)
    points = middle.t + z[:, None] * pixel_rays(middle, u, v)
    seen = np.ones(count, dtype=bool)
    for camera in cameras:
        uv, depth = project_points(camera, points)
        seen &= (depth > 0) & np.all((uv >= 0) & (uv <= np.array(camera.size) - 1), axis=1)
    return points[seen]


def _rectified_positions(rectification, points):
    """(C, N, 2): each camera's true distorted projection, mapped into its output picture."""
    return np.stack(
        [
            rectification.rectify_points(project_points(camera, points)[0], i)
            for i, camera in enumerate(rectification.sources)
        ]
    )


def _rms_row_difference(positions):
    rows = positions[:, :, 1]
    rms = np.sqrt(np.mean((rows - rows.mean(axis=0)) ** 2))
    return float(rms), float(np.ptp(rows, axis=0).max())


# --------------------------------------------------------------------------- bar 1: synthetic rig


def test_corresponding_points_share_a_row_after_rectification(rectified, rig):
    points = _visible_points(rig, 3000, seed=1)
    assert len(points) > 1500
    before = np.stack([project_points(camera, points)[0] for camera in rig])
    rms_before, _ = _rms_row_difference(before)
    rms, largest = _rms_row_difference(_rectified_positions(rectified, points))
    # Centres exactly on the x axis: the rows agree to rounding (bar: 0.25 px RMS).
    assert rms < 1e-9 and largest < 1e-8
    assert rms_before > 0.5  # the rig as built is far from rectified


def test_rectified_cameras_are_one_model_with_the_original_centres(rectified, rig):
    K, R = rectified.cameras[0].K, rectified.cameras[0].R
    assert K[0, 0] == K[1, 1] and K[0, 1] == 0.0
    np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-15)
    assert np.linalg.det(R) > 0
    # x along the centres (the world x axis), pointing from cam0 to cam4.
    np.testing.assert_allclose(R[0], [1.0, 0.0, 0.0], atol=1e-15)
    for source, camera in zip(rig, rectified.cameras):
        np.testing.assert_array_equal(camera.K, K)
        np.testing.assert_array_equal(camera.R, R)
        np.testing.assert_array_equal(camera.t, source.t)
        assert not np.any(camera.distortion)
        assert camera.size == source.size and camera.name == source.name
        assert camera.depth_range == (ZNEAR, ZFAR)
    np.testing.assert_allclose(rectified.centre_offsets, 0.0, atol=1e-15)
    # The rig's cameras were turned by up to 0.5 degree about random axes.
    assert 0.0 < max(rectified.rotation_degrees) < 1.0


def test_rectified_cameras_project_points_where_the_maps_put_them(rectified, rig):
    points = _visible_points(rig, 2000, seed=2)
    mapped = _rectified_positions(rectified, points)
    for i, camera in enumerate(rectified.cameras):
        uv, z = project(camera, points)
        assert np.all(z > 0)
        np.testing.assert_allclose(mapped[i], uv, atol=1e-9)


def test_maps_return_the_source_pixel_of_the_rectified_position(rectified, rig):
    points = _visible_points(rig, 2000, seed=3)
    for i, camera in enumerate(rig):
        source_uv = project_points(camera, points)[0]
        out = rectified.rectify_points(source_uv, i)
        map_x, map_y = rectified.maps[i]
        inside = np.all((out >= 0) & (out <= np.array(rectified.cameras[i].size) - 1), axis=1)
        sampled = np.stack(
            [
                map_coordinates(m.astype(np.float64), [out[inside, 1], out[inside, 0]], order=1)
                for m in (map_x, map_y)
            ],
            axis=-1,
        )
        assert np.abs(sampled - source_uv[inside]).max() < 0.01
        # And at the output pixel centres themselves, exactly (float32 maps).
        v, u = np.mgrid[0:192, 0:256]
        back = rectified.rectify_points(np.stack([map_x.ravel(), map_y.ravel()], axis=-1), i)
        valid = np.isfinite(back[:, 0])
        assert np.abs(back[valid] - np.stack([u.ravel(), v.ravel()], -1)[valid]).max() < 1e-3


def _depth_z(view: int) -> np.ndarray:
    values = read_frame(SAMPLE / "distorted" / f"v{view}_depth_256x192_gray16le.yuv", index=0)[0]
    return depth_to_z(values, ZNEAR, ZFAR, bits=16)


def test_rectified_depth_is_the_depth_of_the_sampled_point_along_the_new_axis(rectified, rig):
    view = 1
    source, camera = rig[view], rectified.cameras[view]
    map_x, map_y = rectified.maps[view]
    z = _depth_z(view)
    out = rectified_depth(z, source, camera, map_x, map_y)
    assert out.shape == (192, 256) and out.dtype == np.float64
    # Hand truth from the definition: the nearest source pixel's point, seen by the
    # rectified camera.
    column, row = np.floor(map_x + 0.5).astype(int), np.floor(map_y + 0.5).astype(int)
    assert np.all((column >= 0) & (column < 256) & (row >= 0) & (row < 192))  # alpha = 0
    points = source.t + z[row, column].ravel()[:, None] * pixel_rays(
        source, column.ravel().astype(float), row.ravel().astype(float)
    )
    uv, expected = project(camera, points)
    np.testing.assert_allclose(out.ravel(), expected, rtol=1e-12)
    # That point is seen where the sampled pixel centre maps, near the output pixel: half
    # a source pixel's diagonal (0.71) times the zoom (1.035) and the lens' local scale.
    sampled = np.stack([column.ravel(), row.ravel()], axis=-1).astype(float)
    np.testing.assert_allclose(uv, rectified.rectify_points(sampled, view), atol=1e-9)
    v, u = np.mgrid[0:192, 0:256]
    assert np.hypot(uv[:, 0] - u.ravel(), uv[:, 1] - v.ravel()).max() < 0.8
    # Independent truth: the scene ray-cast into the rectified camera. Nearest sampling
    # and the 16-bit quantisation agree with it except at depth edges and on the
    # grazing ground.
    exact = render(default_scene(), camera, frame=0, samples=1).depth
    relative = np.abs(out - exact) / exact
    assert np.median(relative) < 1e-4
    assert np.mean(relative < 0.01) > 0.97


def test_rectified_views_match_at_the_disparity_of_their_depth(rectified, rig):
    """Views 1 and 3 after rectification: u3 = u1 - f B / z, v3 = v1 (a row-only shift)."""
    z1 = rectified_depth(_depth_z(1), rig[1], rectified.cameras[1], *rectified.maps[1])
    z3 = rectified_depth(_depth_z(3), rig[3], rectified.cameras[3], *rectified.maps[3])
    camera = rectified.cameras[1]
    baseline = camera.R @ (rig[3].t - rig[1].t)
    np.testing.assert_allclose(baseline, [0.2, 0.0, 0.0], atol=1e-15)
    v, u = np.mgrid[0:192, 0:256].astype(np.float64)
    u3 = u - camera.fx * baseline[0] / z1
    # The same point has the same depth along the common axis in both views.
    z3_there = map_coordinates(z3, [v, u3], order=0, mode="constant", cval=np.nan)
    agree = np.abs(z3_there - z1) < 0.005 * z1
    assert np.mean(agree) > 0.8  # the rest is seen by view 1 only (occlusions, borders)

    def luma(view):
        y = read_frame(SAMPLE / "distorted" / f"v{view}_texture_256x192_yuv420p.yuv", index=0)[0]
        return remap_plane(y, *rectified.maps[view]).astype(np.float64)

    y1, y3 = luma(1), luma(3)
    keep = agree & (u3 > 1) & (u3 < 254) & (u > 1) & (u < 254) & (v > 1) & (v < 190)

    def residual(row_shift, column_shift):
        # The views differ in colour (truth.json colour_mismatch): compare after the best
        # gain and offset.
        sampled = map_coordinates(y3, [v + row_shift, u3 + column_shift], order=1)[keep]
        design = np.column_stack([sampled, np.ones_like(sampled)])
        fit = np.linalg.lstsq(design, y1[keep], rcond=None)[0]
        return float(np.sqrt(np.mean((y1[keep] - design @ fit) ** 2)))

    shifts = np.array([-0.2, 0.0, 0.2])
    for errors in ([residual(s, 0.0) for s in shifts], [residual(0.0, s) for s in shifts]):
        # Vertex of the parabola through the three residuals: the best shift.
        best = 0.2 * (errors[0] - errors[2]) / (2.0 * (errors[0] - 2.0 * errors[1] + errors[2]))
        assert abs(best) < 0.05
    assert residual(0.0, 0.0) < 0.5 * min(residual(-1.0, 0.0), residual(1.0, 0.0))


def test_a_pair_is_rectified_along_its_baseline(rig):
    pair = rectify_cameras([rig[1], rig[3]])
    np.testing.assert_allclose(pair.cameras[0].R[0], [1.0, 0.0, 0.0], atol=1e-15)
    points = _visible_points([rig[1], rig[3]], 1000, seed=4)
    _, largest = _rms_row_difference(_rectified_positions(pair, points))
    assert largest < 1e-8


# --------------------------------------------------------------------------- bar 3: alpha


def _border_margins(rectification):
    """Per camera, how far inside its source picture the output border samples (min over
    the four sides), and how far inside the output the source border lands."""
    sampled, landed = [], []
    for i, (source, (map_x, map_y)) in enumerate(zip(rectification.sources, rectification.maps)):
        width, height = source.size
        sampled.append(
            min(map_x.min(), width - 1 - map_x.max(), map_y.min(), height - 1 - map_y.max())
        )
        u = np.r_[np.arange(width), np.full(height, width - 1), np.arange(width), np.zeros(height)]
        v = np.r_[np.zeros(width), np.arange(height), np.full(width, height - 1), np.arange(height)]
        out = rectification.rectify_points(np.stack([u, v], axis=-1).astype(float), i)
        out_width, out_height = rectification.cameras[i].size
        landed.append(
            min(
                out[:, 0].min(),
                out_width - 1 - out[:, 0].max(),
                out[:, 1].min(),
                out_height - 1 - out[:, 1].max(),
            )
        )
    return np.array(sampled), np.array(landed)


def test_alpha_0_samples_only_inside_the_sources(rectified):
    assert rectified.valid_fraction == [1.0] * 5
    sampled, _ = _border_margins(rectified)
    assert sampled.min() >= -EDGE_TOLERANCE
    assert sampled.min() < 0.05  # and no smaller than needed: some camera touches its border
    assert all(0.85 < kept < 1.0 for kept in rectified.kept_fraction)


def test_alpha_1_keeps_every_source_pixel(rig):
    whole = rectify_cameras(rig, alpha=1.0)
    assert whole.kept_fraction == [1.0] * 5
    _, landed = _border_margins(whole)
    assert landed.min() >= -EDGE_TOLERANCE and landed.min() < 0.05
    assert all(0.85 < valid < 1.0 for valid in whole.valid_fraction)


def test_alpha_between_interpolates_the_output_rectangle(rig, rectified):
    """The output rectangle's centre and size, (half - c) / f and 1 / f, are linear in alpha."""
    whole = rectify_cameras(rig, alpha=1.0)
    half = rectify_cameras(rig, alpha=0.5)
    ends = [r.cameras[0].K for r in (rectified, whole)]
    K = half.cameras[0].K
    middle = np.array([127.5, 95.5])
    assert 1.0 / K[0, 0] == pytest.approx(np.mean([1.0 / k[0, 0] for k in ends]), rel=1e-12)
    for axis in (0, 1):
        assert (middle[axis] - K[axis, 2]) / K[0, 0] == pytest.approx(
            np.mean([(middle[axis] - k[axis, 2]) / k[0, 0] for k in ends]), rel=1e-9
        )
    assert all(0.9 < f < 1.0 for f in half.valid_fraction[:4] + half.kept_fraction[:4])


def test_one_principal_point_for_cameras_with_different_ones():
    """Hand-computed: parallel cameras, f = 200, cy = 95.5, cx = 100 and 140, 256x192. In
    pixels of f, camera 0 sees x in [-100, 155], camera 1 [-140, 115]: alpha = 0 fits the
    output's 255 px width to the common [-100, 115], alpha = 1 to the union [-140, 155]."""
    cameras = [
        Camera(
            f"c{i}",
            [[200.0, 0.0, cx], [0.0, 200.0, 95.5], [0.0, 0.0, 1.0]],
            t=[0.1 * i, 0.0, 0.0],
            size=(256, 192),
        )
        for i, cx in enumerate((100, 140))
    ]
    for alpha, (low, high) in ((0.0, (-100.0, 115.0)), (1.0, (-140.0, 155.0))):
        result = rectify_cameras(cameras, alpha=alpha)
        zoom = 255.0 / (high - low)
        np.testing.assert_allclose(
            result.cameras[0].K,
            [[200.0 * zoom, 0.0, -low * zoom], [0.0, 200.0 * zoom, 95.5], [0.0, 0.0, 1.0]],
            atol=1e-9,
        )
        np.testing.assert_array_equal(result.cameras[1].K, result.cameras[0].K)
    assert rectify_cameras(cameras, alpha=0.0).valid_fraction == [1.0, 1.0]
    assert rectify_cameras(cameras, alpha=1.0).kept_fraction == [1.0, 1.0]


# --------------------------------------------------------------------------- undistortion


def test_undistortion_keeps_each_orientation_and_removes_the_lens(rig):
    for alpha in (0.0, 1.0):
        result = undistortion(rig, alpha=alpha)
        points = _visible_points(rig, 1000, seed=5)
        for i, (source, camera) in enumerate(zip(rig, result.cameras)):
            np.testing.assert_array_equal(camera.R, source.R)
            assert camera.fx / camera.fy == pytest.approx(source.fx / source.fy, rel=1e-12)
            assert not np.any(camera.distortion)
            uv = result.rectify_points(project_points(source, points)[0], i)
            np.testing.assert_allclose(uv, project(camera, points)[0], atol=1e-9)
        fractions = result.valid_fraction if alpha == 0.0 else result.kept_fraction
        assert fractions == [1.0] * 5
        assert result.rotation_degrees == [0.0] * 5
        assert np.all(np.isnan(result.centre_offsets))


# --------------------------------------------------------------------------- bar 2: MPEG files

# (file, picture size, cameras used: the real cameras of the linear array, whether the
# published centres are exactly collinear, depth range of the points).
MPEG_ARRAYS = [
    ("cam_param_poznan_street.txt", (1920, 1088), r"param_cam\d+", True, (5.0, 500.0)),
    ("cam_param_poznan_hall2.txt", (1920, 1088), r"param_cam\d+", True, (5.0, 500.0)),
    # Lovebird1 (its VSRS configuration: 1024x768, depth 1418.29 to 156012.2): cameras
    # 7 to 12 sit 0.437650541 below and 0.000100426 behind cameras 1 to 6.
    ("cam_param_lovebird1.txt", (1024, 768), r"param_loveb1_\d+", False, (1418.29, 156012.2)),
    ("cam_param_lovebird2.txt", (720, 576), r"param_loveb2_\d+", True, (3733.7, 112012.3)),
]


def _mpeg_array(name, size, pattern):
    cameras = [
        camera
        for camera in read_cameras(shared_data("mpeg", "vsrs_camera_parameters", name)).values()
        if re.fullmatch(pattern, camera.name)
    ]
    for camera in cameras:
        camera.size = size
    return cameras


@pytest.mark.parametrize(
    "name, size, pattern, collinear, depths", MPEG_ARRAYS, ids=[entry[0] for entry in MPEG_ARRAYS]
)
def test_mpeg_linear_arrays_rectify_to_one_model(name, size, pattern, collinear, depths):
    cameras = _mpeg_array(name, size, pattern)
    assert len(cameras) in (9, 12)
    result = rectify_cameras(cameras)
    K, R = result.cameras[0].K, result.cameras[0].R
    assert K[0, 0] == K[1, 1] and K[0, 1] == 0.0
    for camera, source in zip(result.cameras, cameras):
        np.testing.assert_array_equal(camera.K, K)
        np.testing.assert_array_equal(camera.R, R)
        np.testing.assert_array_equal(camera.t, source.t)
    # The published rotations (identity, or Lovebird's y and z flip) face across the
    # line; the rectified x axis keeps pointing along each camera's own x axis.
    np.testing.assert_allclose(R[0] @ cameras[0].R[0], 1.0, atol=1e-5)
    centres = np.stack([camera.t for camera in cameras])
    extent = np.ptp(centres, axis=0).max()
    if collinear:
        assert result.centre_offsets.max() < 1e-12 * extent
    else:
        assert 1e-3 < result.centre_offsets.max() <= 0.437650541
    # Reported warps: the rotation each camera turned by, and its homography.
    rng = np.random.default_rng(6)
    pixels = rng.uniform(0, 1, (500, 2)) * (np.array(size) - 1)
    for i, (camera, source) in enumerate(zip(result.cameras, cameras)):
        rotation_vector = cv2.Rodrigues(camera.R @ source.R.T)[0]
        assert result.rotation_degrees[i] == pytest.approx(
            np.degrees(np.linalg.norm(rotation_vector)), abs=1e-9
        )
        warped = np.c_[pixels, np.ones(len(pixels))] @ result.homographies[i].T
        np.testing.assert_allclose(
            warped[:, :2] / warped[:, 2:], result.rectify_points(pixels, i), atol=1e-6
        )
    assert result.valid_fraction == [1.0] * len(cameras)
    # Epipolar rows: points in front of the array.
    points = _visible_points(cameras, 2000, seed=7, depth_range=depths)
    assert len(points) > 200
    positions = _rectified_positions(result, points)
    _, largest = _rms_row_difference(positions)
    if collinear:
        assert largest < 1e-6
    else:
        # v_i = cy + f (q - e_i) / (s - g_i) for a point at (p, q, s) seen from centres
        # off the line by (e_i, g_i): the rows differ by up to f (max e - min e) / s.
        across = np.stack([R @ (c - centres.mean(axis=0)) for c in centres])[:, 1]
        bound = K[0, 0] * np.ptp(across) / depths[0]
        assert 0.1 * bound < largest < 1.01 * bound


def test_mpeg_file_with_a_camera_off_the_line_is_refused():
    # Poznan Street lists a virtual camera "param_cam3.5a" 50 units in front of the array.
    cameras = _mpeg_array("cam_param_poznan_street.txt", (1920, 1088), r"param_cam.*")
    with pytest.raises(DataError, match="would turn by"):
        rectify_cameras(cameras)


# --------------------------------------------------------------------------- bar 4: bad input


def _two_cameras(**changes):
    cameras = _distorted_rig()[1:3]
    for key, value in changes.items():
        setattr(cameras[1], key, value)
    return cameras


@pytest.mark.parametrize(
    "cameras, options, message",
    [
        (_distorted_rig()[:1], {}, r"need at least 2 cameras, got 1"),
        ([], {}, r"need at least 2 cameras, got 0"),
        (_two_cameras(size=None), {}, r"camera 'cam2' has no size"),
        (
            _two_cameras(t=np.array([-0.1, 0.0, 0.0])),
            {},
            r"cameras 'cam1' and 'cam2' have the same "
            r"centre \[-0.1, 0.0, 0.0\]",
        ),
        (_distorted_rig()[1:3], {"alpha": -0.1}, r"alpha must be in \[0, 1\].*got -0.1"),
        (_distorted_rig()[1:3], {"alpha": 1.5}, r"alpha must be in \[0, 1\].*got 1.5"),
        (_distorted_rig()[1:3], {"alpha": float("nan")}, r"alpha must be in \[0, 1\].*got nan"),
        (_two_cameras(size=(320, 240)), {}, r"picture sizes differ"),
        (_distorted_rig()[1:3], {"size": (1, 100)}, r"output size must be at least 2x2"),
    ],
)
def test_bad_input_is_refused(cameras, options, message):
    with pytest.raises(ValueError, match=message):
        rectify_cameras(cameras, **options)


def test_undistortion_needs_a_camera_with_a_size():
    with pytest.raises(ValueError, match="need at least 1 camera, got 0"):
        undistortion([])
    with pytest.raises(ValueError, match="camera 'cam2' has no size"):
        undistortion(_two_cameras(size=None))
    with pytest.raises(ValueError, match=r"alpha must be in \[0, 1\]"):
        undistortion(_distorted_rig(), alpha=2)


# --------------------------------------------------------------------------- planes


def test_remap_plane_bilinear_and_nearest():
    plane = np.array([[0, 100, 200], [40, 140, 240]], dtype=np.uint8)
    map_x = np.array([[0.5, 1.5, 2.75, -3.0]], dtype=np.float32)
    map_y = np.array([[0.0, 0.5, 1.0, 0.0]], dtype=np.float32)
    # (0 + 100) / 2; mean of 100, 200, 140, 240; 240 / 4 + 3 / 4 of the fill; fill.
    np.testing.assert_array_equal(remap_plane(plane, map_x, map_y), [[50, 170, 60, 0]])
    # Nearest: 0.5 rounds up to column 1; 2.75 rounds to column 3, outside.
    np.testing.assert_array_equal(
        remap_plane(plane, map_x, map_y, nearest=True, fill=7), [[100, 240, 7, 7]]
    )
    for dtype in (np.uint16, np.float32, np.float64):
        out = remap_plane(plane.astype(dtype), map_x[:, :2], map_y[:, :2])
        assert out.dtype == dtype
        np.testing.assert_allclose(out, [[50, 170]])


def test_nearest_sampling_never_mixes_depths(rectified, rig):
    z = _depth_z(1)
    out = remap_plane(z, *rectified.maps[1], nearest=True)
    assert np.isin(out, z).all()


def test_rectified_depth_of_a_turned_camera_by_hand():
    """Source: f = 100, centre pixel (5, 5), a plane z = 2. The output camera is turned
    about y by atan(0.03); source column 8 (x = 0.03) holds the point 2 (0.03, 0, 1),
    whose depth along the turned axis (0.03, 0, 1) / sqrt(1.0009) is 2 sqrt(1.0009)."""
    source = Camera("s", [[100.0, 0.0, 5.0], [0.0, 100.0, 5.0], [0.0, 0.0, 1.0]], size=(11, 11))
    turned = Camera("s", source.K, R=rotation_about_y(np.degrees(np.arctan(0.03))), size=(3, 1))
    map_x = np.array([[8.0, 7.5, -0.6]], dtype=np.float32)  # 7.5 rounds up to 8
    map_y = np.array([[5.0, 5.4, 5.0]], dtype=np.float32)
    out = rectified_depth(np.full((11, 11), 2.0), source, turned, map_x, map_y)
    np.testing.assert_allclose(out[0, :2], 2.0 * np.sqrt(1.0009), rtol=1e-14)
    assert out[0, 2] == np.inf
    assert np.isnan(
        rectified_depth(np.full((11, 11), 2.0), source, turned, map_x, map_y, fill=np.nan)[0, 2]
    )
    with pytest.raises(ValueError, match="float depths"):
        rectified_depth(np.full((11, 11), 2, dtype=np.uint16), source, turned, map_x, map_y)


def test_chroma_maps_follow_mpeg_siting():
    """4:2:0 chroma (i, j) sits at luma (2 j, 2 i + 0.5). Hand-computed cases:

    - a 2x zoom out (map = 2 u, 2 v): luma (2j, 2i + 0.5) samples (4j, 4i + 1), chroma
      (2j, 2i + 0.25);
    - a mirror (map = 7 - u, 7 - v) of an 8x8 picture: (7 - 2j, 6.5 - 2i), chroma
      (3.5 - j, 3 - i): rows mirror onto rows (centred siting), columns by half a sample
      (co-sited)."""
    v, u = np.mgrid[0:8, 0:8].astype(np.float32)
    j, i = np.mgrid[0:4, 0:4].astype(np.float32)[::-1]
    cx, cy = chroma_maps(2 * u, 2 * v, subsampling=(2, 2))
    np.testing.assert_allclose(cx, 2 * j, atol=1e-6)
    np.testing.assert_allclose(cy, 2 * i + 0.25, atol=1e-6)
    cx, cy = chroma_maps(7 - u, 7 - v, subsampling=(2, 2))
    np.testing.assert_allclose(cx, 3.5 - j, atol=1e-6)
    np.testing.assert_allclose(cy, 3 - i, atol=1e-6)
    # 4:2:2: rows are not subsampled; 4:4:4: the luma maps themselves.
    cx, cy = chroma_maps(2 * u, 2 * v, subsampling=(2, 1))
    assert cx.shape == (8, 4)
    np.testing.assert_allclose(cx, 2 * np.mgrid[0:8, 0:4][1], atol=1e-6)
    np.testing.assert_allclose(cy, 2 * v[:, :4], atol=1e-6)
    cx, cy = chroma_maps(2 * u, 3 * v, subsampling=(1, 1))
    np.testing.assert_array_equal(cx, 2 * u)
    np.testing.assert_array_equal(cy, 3 * v)
    # Odd sizes: ceil(7 / 2) rows, the last one extrapolated (exact for affine maps).
    v7, u7 = np.mgrid[0:7, 0:5].astype(np.float32)
    cx, cy = chroma_maps(u7 + 1, v7 + 2, subsampling=(2, 2))
    assert cx.shape == (4, 3)
    np.testing.assert_allclose(cy, np.mgrid[0:4, 0:3][0] + 1.0, atol=1e-6)
    np.testing.assert_allclose(cx, np.mgrid[0:4, 0:3][1] + 0.5, atol=1e-6)
    with pytest.raises(ValueError, match="subsampling"):
        chroma_maps(u, v, subsampling=(1, 2))
