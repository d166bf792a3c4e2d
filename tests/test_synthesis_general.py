"""General-mode warping (VSRS SynthesisMode 0) and sub-pixel sampling.

Known truths: exact samples at integer positions, filters that reproduce ramps,
the published H.264 and Catmull-Rom taps, the parallax ``f B / z`` of a
fronto-parallel plane, disocclusion widths computed by hand, the numpy reference
z-buffer :func:`mvtools.geometry.forward_warp` for rotated cameras, and real Kendo
views.
"""

import numpy as np
import pytest
from shared_data import shared_data

from mvtools.geometry import Camera, depth_to_z, forward_warp, reproject
from mvtools.synthesis.general import GeneralWarper, warp_general
from mvtools.synthesis.sampling import sample_image, tap_table
from mvtools.synthesis.views import FILTERS, ReferenceView, SynthesisOptions

PRECISIONS = (1, 2, 4, 8, 16)  # 8 and 16: the mvtools extension of VSRS Precision


def _camera(name, *, f=500.0, size=(80, 60), R=np.eye(3), t=(0.0, 0.0, 0.0)):
    width, height = size
    K = [[f, 0.0, (width - 1) / 2], [0.0, f, (height - 1) / 2], [0.0, 0.0, 1.0]]
    return Camera(name, K, R, t, size=size)


def _rotation(yaw_deg, pitch_deg, roll_deg):
    a, b, c = np.radians([yaw_deg, pitch_deg, roll_deg])
    about_y = np.array([[np.cos(a), 0, np.sin(a)], [0, 1, 0], [-np.sin(a), 0, np.cos(a)]])
    about_x = np.array([[1, 0, 0], [0, np.cos(b), -np.sin(b)], [0, np.sin(b), np.cos(b)]])
    about_z = np.array([[np.cos(c), -np.sin(c), 0], [np.sin(c), np.cos(c), 0], [0, 0, 1]])
    return about_z @ about_x @ about_y


def _ramp(size, *, slope_x=3.0, slope_y=2.0):
    """A 3-channel linear ramp, float32 (every filter reproduces it exactly)."""
    width, height = size
    v, u = np.mgrid[0:height, 0:width].astype(np.float64)
    base = slope_x * u + slope_y * v + 1.0
    return np.stack([base, 0.5 * base, 200.0 - base], axis=-1).astype(np.float32)


def _view(camera, color, z):
    return ReferenceView(camera, np.asarray(color, np.float32), np.asarray(z, np.float64))


# ---------------------------------------------------------------- sampling


@pytest.mark.parametrize("filter", FILTERS)
@pytest.mark.parametrize("precision", PRECISIONS)
def test_sample_image_is_exact_at_integer_positions(filter, precision):
    rng = np.random.default_rng(1)
    image = rng.uniform(0, 255, (13, 17, 3)).astype(np.float32)
    v, u = np.mgrid[0:13, 0:17].astype(np.float64)
    np.testing.assert_array_equal(
        sample_image(image, u, v, precision=precision, filter=filter), image
    )
    np.testing.assert_array_equal(
        sample_image(image[..., 1], u, v, precision=precision, filter=filter), image[..., 1]
    )


@pytest.mark.parametrize("filter", FILTERS)
@pytest.mark.parametrize("precision", [2, 4, 8, 16])
def test_sample_image_reproduces_a_linear_ramp_at_every_phase(filter, precision):
    image = _ramp((30, 20))
    phases = np.arange(precision) / precision
    # Every combination of horizontal and vertical phase, away from the border.
    x, y = np.meshgrid(10 + phases, 8 + phases)
    base = 3.0 * x + 2.0 * y + 1.0
    expected = np.stack([base, 0.5 * base, 200.0 - base], axis=-1)
    np.testing.assert_allclose(
        sample_image(image, x, y, precision=precision, filter=filter), expected, atol=2e-4
    )


def test_sample_image_quantises_positions_to_the_precision():
    image = _ramp((20, 10))[..., :1]
    x = np.array([[4.3, 4.13, 4.124, 4.6, 4.75, 4.03125, 4.1875]])
    y = np.full_like(x, 2.0)
    # Rounded half up to 1/precision: 4.3 -> 4 | 4.5 | 4.25 | 4.25 | 4.3125; the last two
    # are ties at 1/16 (4 + 1/32 -> 4.0625) and at 1/8 (4 + 3/16 -> 4.25).
    expected = {
        1: [4, 4, 4, 5, 5, 4, 4],
        2: [4.5, 4, 4, 4.5, 5, 4, 4],
        4: [4.25, 4.25, 4, 4.5, 4.75, 4, 4.25],
        8: [4.25, 4.125, 4.125, 4.625, 4.75, 4, 4.25],
        16: [4.3125, 4.125, 4.125, 4.625, 4.75, 4.0625, 4.1875],
    }
    for precision, columns in expected.items():
        got = sample_image(image, x, y, precision=precision, filter="bilinear")[0, :, 0]
        np.testing.assert_allclose(got, 3.0 * np.array(columns) + 2.0 * 2 + 1, rtol=1e-6)


def test_sample_image_avc6_taps_are_those_of_h264():
    impulse = np.zeros((1, 9), np.float32)
    impulse[0, 4] = 64.0
    # Sampling an impulse at x + phase gives the tap that x + phase puts on pixel 4.
    x = np.arange(9, dtype=np.float64)[None, :] - 0.5
    half = sample_image(impulse, x + 0.0, np.zeros_like(x), precision=2, filter="avc6")[0]
    np.testing.assert_allclose(half[2:8], np.array([1, -5, 20, 20, -5, 1]) * 2, atol=1e-5)
    quarter = sample_image(
        impulse, x[:, 1:] - 0.25, np.zeros_like(x[:, 1:]), precision=4, filter="avc6"
    )[0]
    # position i + 1/4 = average of pixel i and the half-pel sample i + 1/2
    np.testing.assert_allclose(quarter[1:7], [1, -5, 20, 20 + 32, -5, 1], atol=1e-5)


@pytest.mark.parametrize(
    "precision, phase, taps",
    [
        # Finer than H.264: linear between the integer (tap 2), half-pel and next integer
        # (tap 3) samples, in 32nds.
        (8, 1 / 8, np.array([1, -5, 20, 20, -5, 1]) / 4 + [0, 0, 24, 0, 0, 0]),
        (8, 3 / 8, np.array([3, -15, 60, 60, -15, 3]) / 4 + [0, 0, 8, 0, 0, 0]),
        (8, 5 / 8, np.array([3, -15, 60, 60, -15, 3]) / 4 + [0, 0, 0, 8, 0, 0]),
        (16, 1 / 16, np.array([1, -5, 20, 20, -5, 1]) / 8 + [0, 0, 28, 0, 0, 0]),
        (16, 11 / 16, np.array([5, -25, 100, 100, -25, 5]) / 8 + [0, 0, 0, 12, 0, 0]),
    ],
)
def test_sample_image_avc6_finer_phases_interpolate_between_h264_samples(precision, phase, taps):
    impulse = np.zeros((1, 12), np.float32)
    impulse[0, 5] = 32.0
    # At i + phase the taps fall on pixels i - 2 .. i + 3: pixel 5 gets tap 7 - i.
    x = np.arange(2, 8, dtype=np.float64)[None, ::-1] + phase
    got = sample_image(impulse, x, np.zeros_like(x), precision=precision, filter="avc6")[0]
    np.testing.assert_allclose(got, taps, atol=1e-5)


@pytest.mark.parametrize("filter", FILTERS)
def test_finer_precisions_keep_the_coarser_phases(filter):
    for coarse, fine in ((1, 2), (2, 4), (4, 8), (8, 16)):
        np.testing.assert_array_equal(tap_table(filter, fine)[0][::2], tap_table(filter, coarse)[0])


def test_sample_image_bicubic_is_catmull_rom():
    impulse = np.zeros((1, 9), np.float32)
    impulse[0, 4] = 16.0
    x = np.arange(2.5, 6.5)[None, :]  # pixel 4 is at distance 1.5, 0.5, 0.5, 1.5
    got = sample_image(impulse, x, np.zeros_like(x), precision=2, filter="bicubic")[0]
    np.testing.assert_allclose(got, [-1, 9, 9, -1], atol=1e-5)
    # At 1/8: the Catmull-Rom weights (-t^3 + 2t^2 - t, 3t^3 - 5t^2 + 2, -3t^3 + 4t^2 + t,
    # t^3 - t^2) / 2 at t = 1/8 are (-49, 987, 93, -7) / 1024, on pixels i - 1 .. i + 2.
    impulse[0, 4] = 1024.0
    x = np.arange(2.0, 6.0)[None, ::-1] + 1 / 8  # pixel 4 at offset -1, 0, 1, 2
    for precision in (8, 16):
        got = sample_image(impulse, x, np.zeros_like(x), precision=precision, filter="bicubic")[0]
        np.testing.assert_allclose(got, [-49, 987, 93, -7], atol=1e-3)


def test_sample_image_clamps_outside_and_propagates_nan():
    image = _ramp((6, 4))
    x = np.array([[-3.0, 9.0, 2.0, np.nan]])
    y = np.array([[1.0, 1.0, -7.0, 1.0]])
    got = sample_image(image, x, y, precision=4, filter="bicubic")
    np.testing.assert_array_equal(got[0, :3], image[[1, 1, 0], [0, 5, 2]])
    assert np.isnan(got[0, 3]).all()


def test_sample_image_rejects_bad_arguments():
    image = np.zeros((4, 4, 3), np.float32)
    grid = np.zeros((2, 2))
    for precision in (3, 32, 0):
        with pytest.raises(ValueError, match="precision must be one of 1, 2, 4, 8, 16"):
            sample_image(image, grid, grid, precision=precision, filter="bicubic")
    with pytest.raises(ValueError, match="precision must be one of 1, 2, 4, 8, 16, got 32"):
        SynthesisOptions(precision=32)
    assert SynthesisOptions(precision=16).precision == 16
    with pytest.raises(ValueError, match="filter"):
        sample_image(image, grid, grid, precision=2, filter="lanczos")
    with pytest.raises(ValueError, match=r"same shape|one shape"):
        sample_image(image, grid, grid[:1], precision=2, filter="bilinear")
    assert tap_table("avc6", 4)[0].shape == (4, 6)
    assert tap_table("bicubic", 16)[0].shape == (16, 4)


# ---------------------------------------------------------------- general warp


@pytest.mark.parametrize("filter", FILTERS)
@pytest.mark.parametrize("precision", PRECISIONS)
def test_identity_warp_returns_the_reference(filter, precision):
    rng = np.random.default_rng(7)
    size = (37, 23)
    camera = _camera("ref", size=size, R=_rotation(20, -10, 5), t=(1.0, -2.0, 3.0))
    color = rng.uniform(0, 255, (23, 37, 3))
    z = rng.uniform(20, 200, (23, 37))
    warped = warp_general(
        _view(camera, color, z), camera, size=size, precision=precision, filter=filter
    )
    np.testing.assert_array_equal(warped.color, color.astype(np.float32))
    np.testing.assert_allclose(warped.z, z, rtol=1e-12)


@pytest.mark.parametrize("size", [(80, 60), (333, 201), (101, 7)])
@pytest.mark.parametrize("filter", FILTERS)
@pytest.mark.parametrize(
    "baseline, fetched",
    [
        # f B / z = 500 * 0.74 / 100 = 3.7 px to the left in the camera to the right; each
        # virtual pixel fetches the reference at u + 3.7, rounded to 1/precision: 1/20 px
        # off at Precision 4, 3/10 px at Precision 1, 1/80 px at 16.
        (0.74, {1: 4.0, 2: 3.5, 4: 3.75, 8: 3.75, 16: 3.6875}),
        # 3.625 = 3 + 5/8 px: exact from Precision 8 on.
        (0.725, {1: 4.0, 8: 3.625, 16: 3.625}),
    ],
)
def test_plane_moves_by_f_b_over_z(size, filter, baseline, fetched):
    width, height = size
    reference = _camera("ref", size=size)
    virtual = _camera("virtual", size=size, t=(baseline, 0.0, 0.0))
    color = _ramp(size)
    view = _view(reference, color, np.full((height, width), 100.0))
    u = np.arange(width)
    for precision, shift in fetched.items():
        warped = warp_general(view, virtual, size=size, precision=precision, filter=filter)
        # Splats land at u - 3.7 rounded = u - 4: the last 4 columns see nothing.
        assert np.isinf(warped.z[:, width - 4 :]).all()
        np.testing.assert_allclose(warped.z[:, : width - 4], 100.0, rtol=1e-12)
        # (Away from the right border, where the taps of the longer filters are clamped.)
        inside = u[: width - 7]
        expected = 3.0 * (inside + shift)[None, :] + 2.0 * np.arange(height)[:, None] + 1.0
        np.testing.assert_allclose(warped.color[:, : width - 7, 0], expected, atol=1e-3)
        assert (warped.color[:, width - 4 :] == 0).all()


@pytest.mark.parametrize("depth_type", [0, 1])
def test_rotated_cameras_agree_with_reproject_and_the_reference_z_buffer(depth_type):
    size = (90, 70)
    reference = _camera("ref", size=size, R=_rotation(-1, 0.5, 1), t=(0.2, 0.1, -0.5))
    virtual = _camera("virtual", size=size, R=_rotation(-1, -1, 4), t=(1.5, -0.4, 0.6))
    # A tilted plane in front of the reference.
    v, u = np.mgrid[0:70, 0:90].astype(np.float64)
    z = 60.0 + 0.1 * u + 0.05 * v
    color = _ramp(size, slope_x=1.0, slope_y=0.5)
    view = _view(reference, color, z)
    warper = GeneralWarper(reference, virtual, size=size, depth_type=depth_type)
    warped = warper.warp(view, precision=4, filter="bilinear")

    _, expected_z, landed = forward_warp(
        np.zeros(z.shape), z, reference, virtual, depth_type=depth_type
    )
    assert landed.mean() > 0.6
    # Pixels whose centre's ray meets the plane outside the reference are holes.
    vv, uu = np.nonzero(landed)
    x, y, _ = reproject(virtual, reference, uu, vv, expected_z[landed])
    seen = (x >= -0.5) & (x < 89.5) & (y >= -0.5) & (y < 69.5)
    assert np.count_nonzero(~seen) < 0.05 * seen.size
    filled = ~warped.holes
    assert filled[vv[seen], uu[seen]].all() and not filled[vv[~seen], uu[~seen]].any()
    np.testing.assert_allclose(warped.z[vv[seen], uu[seen]], expected_z[landed][seen], rtol=1e-9)
    # Only cracks were added (and they are few) ...
    assert (filled & ~landed).sum() < 0.05 * landed.sum()
    # ... and the colour is the reference's at the back-projection of each pixel
    # (the border clamped), to the 1/8 px of Precision 4 along each axis.
    vv, uu = np.nonzero(filled)
    x, y, _ = reproject(virtual, reference, uu, vv, warped.z[filled])
    expected = 1.0 * np.clip(x, 0, 89) + 0.5 * np.clip(y, 0, 69) + 1.0
    np.testing.assert_allclose(warped.color[filled, 0], expected, atol=(1.0 + 0.5) / 8 + 1e-6)


def test_result_does_not_depend_on_the_number_of_threads():
    import numba

    rng = np.random.default_rng(5)
    size = (70, 50)
    reference = _camera("ref", size=size)
    virtual = _camera("virtual", size=size, f=350.0, R=_rotation(1, 0, 2), t=(0.8, 0.2, 0.5))
    # Blocks of equal depths: many points compete for the same pixels, with ties.
    z = np.kron(rng.choice([40.0, 60.0, 90.0], (10, 14)), np.ones((5, 5)))
    view = _view(reference, rng.uniform(0, 255, (50, 70, 3)), z)
    results = []
    default = numba.get_num_threads()
    for threads in sorted({1, default}):
        numba.set_num_threads(threads)
        try:
            results.append(
                GeneralWarper(reference, virtual, size=size).warp(view, precision=4, filter="avc6")
            )
        finally:
            numba.set_num_threads(default)
    for other in results[1:]:
        np.testing.assert_array_equal(other.z, results[0].z)
        np.testing.assert_array_equal(other.color, results[0].color)


def test_depth_type_1_equals_depth_type_0_for_cameras_on_the_world_z_0_plane():
    rng = np.random.default_rng(3)
    size = (64, 48)
    reference = _camera("ref", size=size)
    virtual = _camera("virtual", size=size, t=(0.6, -0.3, 0.0))
    view = _view(reference, rng.uniform(0, 255, (48, 64, 3)), rng.uniform(40, 90, (48, 64)))
    along_axis, world = (
        GeneralWarper(reference, virtual, size=size, depth_type=depth_type).warp(
            view, precision=2, filter="bicubic"
        )
        for depth_type in (0, 1)
    )
    np.testing.assert_array_equal(world.z, along_axis.z)
    np.testing.assert_array_equal(world.color, along_axis.color)
    assert 0.5 < np.mean(~along_axis.holes) < 1


def test_near_square_occludes_and_leaves_a_hole_of_the_parallax_difference():
    # Far plane z = 250 moves 2 px, the near square z = 50 moves 10 px (f B = 500).
    size = (100, 80)
    reference = _camera("ref", size=size)
    virtual = _camera("virtual", size=size, t=(1.0, 0.0, 0.0))
    z = np.full((80, 100), 250.0)
    z[30:50, 40:60] = 50.0
    color = np.zeros((80, 100, 3))
    color[..., 0] = 10.0
    color[30:50, 40:60, 0] = 200.0
    warped = warp_general(
        _view(reference, color, z), virtual, size=size, precision=4, filter="bicubic"
    )
    square = warped.z[30:50]
    # The square moved to columns 30..49 and hides the background landing there too.
    np.testing.assert_allclose(square[:, 30:50], 50.0)
    assert (warped.color[30:50, 30:50, 0] == 200.0).all()
    # Background the square hid in the reference (columns 38..57 here) minus the
    # square itself: 50..57, 10 - 2 = 8 columns, all holes, not closed as cracks.
    assert np.isinf(square[:, 50:58]).all()
    np.testing.assert_allclose(square[:, :30], 250.0)
    np.testing.assert_allclose(square[:, 58:98], 250.0)
    # Rows without the square: only the 2 columns at the right border are holes.
    np.testing.assert_allclose(warped.z[:30, :98], 250.0)
    assert np.isinf(warped.z[:, 98:]).all()
    assert (warped.color[:30, :98, 0] == 10.0).all()


def test_two_pixel_disocclusion_between_surfaces_is_not_closed():
    # Far plane moves 2 px, near square 4 px: a 2 px strip, ends 2 px of parallax apart.
    size = (60, 40)
    reference = _camera("ref", size=size)
    virtual = _camera("virtual", size=size, t=(1.0, 0.0, 0.0))
    z = np.full((40, 60), 250.0)
    z[10:30, 20:40] = 125.0
    warped = warp_general(
        _view(reference, np.zeros((40, 60, 3)), z),
        virtual,
        size=size,
        precision=1,
        filter="bilinear",
    )
    assert np.isinf(warped.z[10:30, 36:38]).all()
    np.testing.assert_allclose(warped.z[10:30, 16:36], 125.0)
    np.testing.assert_allclose(warped.z[10:30, 38:58], 250.0)


def test_zoom_cracks_are_closed_also_where_the_background_shows_through():
    # The virtual camera moves 50 towards a square at z = 100 in front of a plane at
    # z = 400: the square doubles in size (a one-pixel crack after every splat) and
    # background points land in its cracks.
    size = (120, 90)
    reference = _camera("ref", size=size, f=300.0)
    virtual = _camera("virtual", size=size, f=300.0, t=(0.0, 0.0, 50.0))
    z = np.full((90, 120), 400.0)
    z[35:55, 45:75] = 100.0
    color = np.zeros((90, 120, 3))
    color[35:55, 45:75] = 255.0
    view = _view(reference, color, z)
    open_cracks = GeneralWarper(reference, virtual, size=size, max_crack=0).warp(
        view, precision=2, filter="bilinear"
    )
    warped = warp_general(view, virtual, size=size, precision=2, filter="bilinear")
    # The square (reference columns 44.5..74.5, rows 34.5..54.5) covers virtual
    # columns 29.5..89.5 and rows 24.5..64.5 (2 (c - 59.5) + 59.5); its splats land
    # on every other pixel from 31 and 26. Inside, away from its edges:
    inner = (slice(27, 64), slice(32, 89))
    assert np.isinf(open_cracks.z[inner]).mean() > 0.2  # cracks to close
    np.testing.assert_allclose(
        open_cracks.z[inner][np.isfinite(open_cracks.z[inner])].max(), 350.0
    )  # background through
    np.testing.assert_allclose(warped.z[inner], 50.0)
    assert (warped.color[inner] == 255.0).all()
    # The background's cracks (it grows by 400 / 350) are closed too.
    assert warped.holes.mean() < 0.005


def test_slanted_plane_stretched_by_the_warp_has_no_cracks():
    size = (160, 40)
    reference = _camera("ref", size=size, f=400.0)
    virtual = _camera("virtual", size=size, f=400.0, t=(2.0, 0.0, 0.0))
    # 1/z linear in u: the parallax f B / z falls from 30 px to 10 px across the
    # image, so the plane lands at 1.126 u - 30, stretched.
    u = np.arange(160, dtype=np.float64)
    inverse = (30.0 - 20.0 * u / 159) / 800.0
    z = np.broadcast_to(1.0 / inverse, (40, 160))
    warped = warp_general(
        _view(reference, _ramp(size), z), virtual, size=size, precision=4, filter="bicubic"
    )
    _, _, landed = forward_warp(np.zeros(z.shape), z, reference, virtual)
    assert not landed[:, :140].all()  # forward warping leaves cracks
    assert not warped.holes[:, :149].any()
    assert warped.holes[:, 150:].all()
    # The depth of each pixel is the plane's at most half a pixel away.
    columns = u - 800.0 * inverse
    expected = np.interp(np.arange(149), columns, 1.0 / inverse)
    np.testing.assert_allclose(warped.z[5, :149], expected, rtol=0.01)


def test_virtual_view_of_another_size():
    # Same centre and focal length, a larger picture: the reference appears in the
    # middle, shifted by the difference of the principal points (5, 3).
    rng = np.random.default_rng(11)
    reference = _camera("ref", size=(40, 30))
    virtual = _camera("virtual", size=(50, 36))
    color = rng.uniform(0, 255, (30, 40, 3))
    warped = warp_general(
        _view(reference, color, np.full((30, 40), 70.0)),
        virtual,
        size=(50, 36),
        precision=2,
        filter="bicubic",
    )
    np.testing.assert_array_equal(warped.color[3:33, 5:45], color.astype(np.float32))
    inside = np.zeros((36, 50), bool)
    inside[3:33, 5:45] = True
    np.testing.assert_array_equal(warped.holes, ~inside)


def test_points_behind_the_virtual_camera_are_dropped():
    size = (40, 30)
    reference = _camera("ref", size=size)
    # The virtual camera at z = 200 looks back at the reference: a plane at
    # z = 250 lies behind it, a plane at z = 150 50 in front of it.
    virtual = _camera("virtual", size=size, R=np.diag([-1.0, 1.0, -1.0]), t=(0.0, 0.0, 200.0))
    z = np.full((30, 40), 250.0)
    warped = warp_general(
        _view(reference, np.ones((30, 40, 3)), z),
        virtual,
        size=size,
        precision=2,
        filter="bilinear",
    )
    assert warped.holes.all()
    z[:] = 150.0
    warped = warp_general(
        _view(reference, np.ones((30, 40, 3)), z),
        virtual,
        size=size,
        precision=2,
        filter="bilinear",
    )
    assert warped.holes.mean() < 0.05
    np.testing.assert_allclose(warped.z[~warped.holes], 50.0)


def test_warp_rejects_bad_input():
    size = (8, 6)
    camera = _camera("ref", size=size)
    warper = GeneralWarper(camera, camera, size=size)
    good = _view(camera, np.zeros((6, 8, 3)), np.ones((6, 8)))
    with pytest.raises(ValueError, match="same size"):
        warper.warp(
            _view(camera, np.zeros((6, 8, 3)), np.ones((6, 7))), precision=2, filter="bicubic"
        )
    with pytest.raises(ValueError, match="NaN"):
        warper.warp(
            _view(camera, np.zeros((6, 8, 3)), np.full((6, 8), np.nan)),
            precision=2,
            filter="bicubic",
        )
    with pytest.raises(ValueError, match="positive"):
        warper.warp(
            _view(camera, np.zeros((6, 8, 3)), -np.ones((6, 8))), precision=2, filter="bicubic"
        )
    with pytest.raises(ValueError, match="precision"):
        warper.warp(good, precision=12, filter="bicubic")
    with pytest.raises(ValueError, match="depth_type"):
        GeneralWarper(camera, camera, size=size, depth_type=2)
    with pytest.raises(ValueError, match="size"):
        GeneralWarper(camera, camera, size=(0, 6))


# ---------------------------------------------------------------- real data


def test_kendo_view_1_warped_into_camera_3_matches_view_3():
    from mvtools.color.space import upsample_chroma
    from mvtools.io.cameras import read_cameras
    from mvtools.io.yuv import YuvFormat, read_frame

    folder = shared_data("mpeg", "kendo")
    cameras = read_cameras(folder / "config" / "VSRS" / "cam_param_kendo.cfg")
    fmt = YuvFormat(1024, 768)
    texture = np.stack(upsample_chroma(read_frame(folder / "kendo_ori_I_1.yuv", fmt)), axis=-1)
    z = depth_to_z(read_frame(folder / "kendo_ori_D_1.yuv", fmt)[0], 448.251214, 11206.280350)
    target = read_frame(folder / "kendo_ori_I_3.yuv", fmt)[0].astype(np.float64)
    view = _view(cameras["param_kendo01"], texture, z)
    warped = warp_general(
        view, cameras["param_kendo03"], size=(1024, 768), precision=4, filter="bicubic"
    )
    seen = ~warped.holes
    # Measured: 3.7 % holes (disocclusions, the left border), median 2, mean 3.5.
    assert 0.9 < seen.mean() < 0.99
    error = np.abs(warped.color[..., 0] - target)[seen]
    assert np.median(error) <= 3
    assert error.mean() < 4.5
    # Without the geometry (the reference as it is) the views differ a lot more.
    assert np.median(np.abs(texture[..., 0] - target)) > 2 * np.median(error)
