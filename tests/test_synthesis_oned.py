"""VSRS 1D mode: row warping, its options, the merging options and the temporal filter.

Expected values are computed by hand from the disparity formula
``d = fx_left (tx_virtual - tx_ref) / z - (cx_virtual - cx_ref)``, ``u_virtual = u_ref - d``.
"""

from pathlib import Path

import numpy as np
import pytest
from shared_data import shared_data

from mvtools.color.space import upsample_chroma
from mvtools.geometry.camera import Camera
from mvtools.geometry.depth import depth_to_z, inverse_depth_step
from mvtools.io.cameras import read_cameras
from mvtools.io.yuv import read_frame
from mvtools.synthesis.general import GeneralWarper
from mvtools.synthesis.oned import OneDWarper, merge_1d, warp_1d
from mvtools.synthesis.temporal import TemporalDepthFilter
from mvtools.synthesis.views import ReferenceView, WarpedView

SAMPLE_LINE = Path(__file__).resolve().parent.parent / "sample_data" / "line"
FX = 1000.0


def camera(name, x, *, fx=FX, cx=20.0):
    return Camera(name, [[fx, 0.0, cx], [0.0, fx, 3.0], [0.0, 0.0, 1.0]], t=[x, 0.0, 0.0])


LEFT = camera("left", 0.0)
VIRTUAL = camera("virtual", 1.0)
RIGHT = camera("right", 2.0)


def texture(height, width, seed=0):
    return np.random.default_rng(seed).uniform(0, 255, (height, width, 3)).astype(np.float32)


def depth_of(disparity):
    """z giving ``disparity`` between LEFT and VIRTUAL (baseline 1, fx 1000)."""
    return FX / np.asarray(disparity, dtype=np.float64)


def warp(reference_camera, color, z, **options):
    options.setdefault("clean_noise", False)
    options.setdefault("warp_enhancement", False)
    height, width = z.shape
    warper = OneDWarper(reference_camera, VIRTUAL, size=(width, height), left_camera=LEFT)
    return warper.warp(ReferenceView(reference_camera, color, z), **options)


# --------------------------------------------------------------------------- warping


@pytest.mark.parametrize("splatting", [0, 1, 2])
def test_plane_shifts_by_the_disparity_with_left_fx_and_principal_points(splatting):
    # The reference's own fx (500) must not be used: d = 1000 * 1 / 250 - (21 - 20) = 3.
    reference = camera("reference", 0.0, fx=500.0, cx=20.0)
    virtual = camera("virtual", 1.0, cx=21.0)
    color = texture(4, 30)
    z = np.full((4, 30), 250.0)
    warper = OneDWarper(reference, virtual, size=(30, 4), left_camera=LEFT)
    warped = warper.warp(ReferenceView(reference, color, z), precision=1, splatting=splatting)
    np.testing.assert_array_equal(warped.color[:, :27], color[:, 3:])
    np.testing.assert_array_equal(warped.z[:, :27], 250.0)
    assert warped.holes[:, 27:].all()
    np.testing.assert_array_equal(warped.color[:, 27:], 0.0)


def test_right_reference_shifts_the_other_way():
    # d = 1000 * (1 - 2) / 500 = -2: virtual v shows reference v - 2.
    color = texture(3, 25)
    warped = warp(RIGHT, color, np.full((3, 25), 500.0), precision=1)
    np.testing.assert_array_equal(warped.color[:, 2:], color[:, :23])
    assert warped.holes[:, :2].all() and not warped.holes[:, 2:].any()


@pytest.mark.parametrize(
    "disparity, precision, filter, taps",
    [
        (2.25, 4, "bilinear", {2: 0.75, 3: 0.25}),  # v + 2.25 exactly
        (2.3, 4, "bilinear", {2: 0.75, 3: 0.25}),  # rounded to v + 2.25
        (2.3, 2, "bilinear", {2: 0.5, 3: 0.5}),  # rounded to v + 2.5
        (2.3, 1, "bilinear", {2: 1.0}),  # rounded to v + 2
        (2.6, 2, "bicubic", {1: -1 / 16, 2: 9 / 16, 3: 9 / 16, 4: -1 / 16}),  # Catmull-Rom, half
        # The finer precisions of mvtools (rows upsampled to 8 and 16 phases).
        (2.125, 8, "bilinear", {2: 7 / 8, 3: 1 / 8}),  # v + 2 + 1/8 exactly
        (2.2, 8, "bilinear", {2: 0.75, 3: 0.25}),  # rounded to v + 2 + 2/8
        (2.2, 16, "bilinear", {2: 13 / 16, 3: 3 / 16}),  # rounded to v + 2 + 3/16
        (2.875, 16, "bilinear", {2: 1 / 8, 3: 7 / 8}),  # v + 2 + 14/16 exactly
        (2.125, 8, "bicubic", {1: -49 / 1024, 2: 987 / 1024, 3: 93 / 1024, 4: -7 / 1024}),
        # AVC 6-tap at 3/8: 1/4 of the integer sample plus 3/4 of the half-pel one.
        (
            2.375,
            8,
            "avc6",
            {0: 3 / 128, 1: -15 / 128, 2: 92 / 128, 3: 60 / 128, 4: -15 / 128, 5: 3 / 128},
        ),
    ],
)
def test_sub_pixel_disparity_fetches_the_rounded_position(disparity, precision, filter, taps):
    color = texture(3, 32)
    for splatting in (0, 1):
        warped = warp(
            LEFT,
            color,
            np.full((3, 32), depth_of(disparity)),
            precision=precision,
            filter=filter,
            splatting=splatting,
        )
        expected = sum(weight * color[:, offset : offset + 27] for offset, weight in taps.items())
        np.testing.assert_allclose(warped.color[:, :27], expected, rtol=0, atol=1e-3)
        np.testing.assert_allclose(warped.z[:, :27], depth_of(disparity))


def test_odd_width_and_one_row():
    color = texture(1, 37)
    warped = warp(LEFT, color, np.full((1, 37), depth_of(4.0)), precision=2)
    assert warped.color.shape == (1, 37, 3) and warped.z.shape == (1, 37)
    np.testing.assert_array_equal(warped.color[:, :33], color[:, 4:])
    assert warped.holes[:, 33:].all()


def occlusion_scene():
    """Far plane d = 2 with a near square d = 6 over reference columns 20..29."""
    disparity = np.full((4, 60), 2.0)
    disparity[:, 20:30] = 6.0
    return texture(4, 60), depth_of(disparity)


@pytest.mark.parametrize("splatting", [0, 1, 2])
def test_nearer_surface_wins_and_disocclusion_is_the_disparity_difference(splatting):
    color, z = occlusion_scene()
    warped = warp(LEFT, color, z, precision=1, splatting=splatting)
    # The square moves to 14..23 over the background pixels 16..19 (which land on
    # 14..17); the background right of it moves by 2 only: 6 - 2 = 4 pixels uncovered.
    np.testing.assert_array_equal(warped.color[:, 14:24], color[:, 20:30])
    np.testing.assert_allclose(warped.z[:, 14:24], depth_of(6.0))
    np.testing.assert_array_equal(warped.color[:, :14], color[:, 2:16])
    np.testing.assert_array_equal(warped.color[:, 28:58], color[:, 30:60])
    np.testing.assert_allclose(warped.z[:, 28:58], depth_of(2.0))
    assert warped.holes[:, 24:28].all() and warped.holes[:, 58:].all()
    assert warped.holes.sum() == 4 * (4 + 2)


def test_clean_noise_skips_two_background_pixels_at_each_strong_edge():
    color, z = occlusion_scene()
    warped = warp(LEFT, color, z, precision=1, clean_noise=True)
    # Background pixels 30 and 31 (landing on 28, 29) are skipped; 18 and 19 were
    # hidden behind the square anyway.
    assert warped.holes[:, 24:30].all()
    np.testing.assert_array_equal(warped.color[:, 30:58], color[:, 32:60])
    np.testing.assert_array_equal(warped.color[:, 14:24], color[:, 20:30])
    np.testing.assert_array_equal(warped.color[:, :14], color[:, 2:16])


def cracks(virtual_columns, stretch, shift):
    """Virtual columns no pixel of one pixel's width covers when u = stretch x - shift.

    Pixel x covers u - 1/2 <= v < u + 1/2, so v is covered when some integer x has
    v - 1/2 < stretch x - shift <= v + 1/2.
    """
    return [
        v
        for v in virtual_columns
        if np.floor((v + 0.5 + shift) / stretch) <= (v - 0.5 + shift) / stretch
    ]


def test_splatting_closes_the_cracks_of_a_stretched_surface():
    # A slanted surface: d = 8.03 - 0.1 x, so u = 1.1 x - 8.03, stretched by 1.1 (the
    # 0.03 keeps footprint ends off pixel centres).
    disparity = np.tile(8.03 - 0.1 * np.arange(60), (2, 1))
    color = texture(2, 60)
    points = warp(LEFT, color, depth_of(disparity), precision=4, filter="bilinear", splatting=0)
    splats = warp(LEFT, color, depth_of(disparity), precision=4, filter="bilinear", splatting=1)
    inside = np.arange(3, 56)  # reference 10 (u = 2.97) .. 58 (u = 55.77)
    expected_cracks = cracks(inside, 1.1, 8.03)
    assert len(expected_cracks) >= 4
    assert list(inside[points.holes[0, inside]]) == expected_cracks
    assert not splats.holes[:, inside].any()
    # Splats fetch where the surface maps exactly, x = (v + 8.03) / 1.1, rounded to 1/4.
    position = np.floor((inside + 8.03) / 1.1 * 4 + 0.5) / 4
    base = np.floor(position).astype(int)
    fraction = (position - base)[None, :, None]
    expected = (1 - fraction) * color[:, base] + fraction * color[:, base + 1]
    np.testing.assert_allclose(splats.color[:, inside], expected, atol=1e-3)


def test_boundary_splatting_acts_only_near_strong_edges():
    # The slanted surface u = 1.1 x - 12.03 up to reference 39, then a step back by
    # 3 px of disparity (a strong edge): u = 1.1 x - 9.03 from reference 40 on.
    x = np.arange(60)
    disparity = np.tile(12.03 - 0.1 * x - 3.0 * (x >= 40), (2, 1))
    z = depth_of(disparity)
    color = texture(2, 60)
    none = warp(LEFT, color, z, precision=4, splatting=0)
    near = warp(LEFT, color, z, precision=4, splatting=2, boundary_growth=5)
    everywhere = warp(LEFT, color, z, precision=4, splatting=2, boundary_growth=60)
    full = warp(LEFT, color, z, precision=4, splatting=1)
    np.testing.assert_array_equal(everywhere.color, full.color)
    np.testing.assert_array_equal(everywhere.z, full.z)
    # Far from the edge (reference 12..28, virtual 2..18) nothing is splatted.
    far = np.arange(2, 19)
    assert list(far[none.holes[0, far]]) == cracks(far, 1.1, 12.03) != []
    np.testing.assert_array_equal(near.z[:, far], none.z[:, far])
    # The band, reference 34..45, covers 26..30 and 35..40 without a crack.
    assert list(np.flatnonzero(none.holes[0, 26:31]) + 26) == cracks(range(26, 31), 1.1, 12.03)
    band = np.r_[26:31, 35:41]
    assert none.holes[:, band].any()
    assert not near.holes[:, band].any()


def test_warp_enhancement_fills_a_one_pixel_crack():
    # Point sampling (no splatting): reference 19 (d = 3) lands on 16, reference 20
    # (d = 2, the same surface) on 18; 17 stays empty.
    disparity = np.where(np.arange(40) < 20, 3.0, 2.0)[None, :].repeat(2, axis=0)
    color = texture(2, 40)
    plain = warp(LEFT, color, depth_of(disparity), precision=1, splatting=0)
    assert plain.holes[:, 17].all() and not plain.holes[:, :17].any()
    enhanced = warp(
        LEFT, color, depth_of(disparity), precision=1, splatting=0, warp_enhancement=True
    )
    assert not enhanced.holes[:, :37].any()
    np.testing.assert_allclose(enhanced.color[:, 17], (color[:, 19] + color[:, 20]) / 2)
    np.testing.assert_allclose(enhanced.z[:, 17], FX / 2.5)
    np.testing.assert_array_equal(enhanced.color[:, :17], plain.color[:, :17])


def test_warp_enhancement_replaces_a_background_pixel_seen_through_a_crack():
    # Near surface over reference 20..29 (d = 8, then 7 from 23: a crack at 15 without
    # splatting); the background pixel 17 (d = 2) lands in it.
    disparity = np.full((2, 40), 2.0)
    disparity[:, 20:23] = 8.0
    disparity[:, 23:30] = 7.0
    color = texture(2, 40)
    plain = warp(LEFT, color, depth_of(disparity), precision=1, splatting=0)
    np.testing.assert_array_equal(plain.color[:, 15], color[:, 17])
    enhanced = warp(
        LEFT, color, depth_of(disparity), precision=1, splatting=0, warp_enhancement=True
    )
    np.testing.assert_allclose(enhanced.color[:, 15], (color[:, 22] + color[:, 23]) / 2)
    np.testing.assert_allclose(enhanced.z[:, 15], FX / 7.5)


@pytest.mark.parametrize("far", [1.0, 1.5])
def test_warp_enhancement_leaves_wider_gaps_and_depth_edges(far):
    # d = 3 then 1: a two-pixel gap; d = 3 then 1.5: a one-pixel gap between two
    # surfaces 1.5 px of disparity apart (a disocclusion, not a crack).
    disparity = np.where(np.arange(40) < 20, 3.0, far)[None, :].repeat(2, axis=0)
    color = texture(2, 40)
    for splatting in (0, 1):
        plain = warp(LEFT, color, depth_of(disparity), precision=1, splatting=splatting)
        enhanced = warp(
            LEFT,
            color,
            depth_of(disparity),
            precision=1,
            splatting=splatting,
            warp_enhancement=True,
        )
        assert plain.holes[:, 17].all()
        np.testing.assert_array_equal(enhanced.z, plain.z)
        np.testing.assert_array_equal(enhanced.color, plain.color)


@pytest.mark.parametrize("precision", [2, 8, 16])
def test_one_dimensional_mode_matches_the_general_mode_on_rectified_cameras(precision):
    cameras = read_cameras(SAMPLE_LINE / "cameras.txt")
    texture_planes = read_frame(SAMPLE_LINE / "v1_texture_256x192_yuv420p.yuv")
    values = read_frame(SAMPLE_LINE / "v1_depth_256x192_gray16le.yuv")[0]
    view = ReferenceView(
        cameras["cam1"],
        np.stack(upsample_chroma(texture_planes), axis=-1).astype(np.float32),
        depth_to_z(values, 2.0, 13.0, bits=16),
    )
    general = GeneralWarper(cameras["cam1"], cameras["cam2"], size=(256, 192)).warp(
        view, precision=precision, filter="bicubic"
    )
    oned = warp_1d(
        view,
        cameras["cam2"],
        left_camera=cameras["cam1"],
        size=(256, 192),
        precision=precision,
        filter="bicubic",
        splatting=1,
        clean_noise=False,
        warp_enhancement=False,
    )
    both = ~general.holes & ~oned.holes
    difference = np.abs(general.color - oned.color)[both]
    assert np.median(difference) <= 1.0 and difference.mean() < 0.5
    assert np.count_nonzero(general.holes != oned.holes) < 0.005 * both.size
    # And both are the real view 2 where they see it (a synthetic scene, exact depth).
    real = read_frame(SAMPLE_LINE / "v2_texture_256x192_yuv420p.yuv")[0].astype(np.float64)
    error = oned.color[..., 0][~oned.holes] - real[~oned.holes]
    assert 10 * np.log10(255.0**2 / np.mean(error**2)) > 38.0


def test_cones_warped_and_merged_in_1d_mode():
    from mvtools.datasets import cones_multiview

    case = cones_multiview(shared_data("middlebury"))
    width, height = case.size
    warped = []
    for name in ("im2", "im6"):
        color = np.stack(upsample_chroma(case.yuv[name]), axis=-1).astype(np.float32)
        warper = OneDWarper(
            case.cameras[name], case.cameras["im4"], size=case.size, left_camera=case.cameras["im2"]
        )
        warped.append(
            warper.warp(
                ReferenceView(case.cameras[name], color, case.z[name]),
                precision=2,
                filter="bicubic",
            )
        )
    merged = merge_1d(*warped, weights=(0.5, 0.5), depth_range=case.depth_range)
    truth = case.yuv["im4"][0].astype(np.float64)
    seen = ~merged.holes
    error = merged.color[..., 0][seen] - truth[seen]
    assert 10 * np.log10(255.0**2 / np.mean(error**2)) > 30.0
    assert merged.holes.mean() < 0.015
    assert merged.z.shape == (height, width)


# --------------------------------------------------------------------------- merging


def view(color, z):
    z = np.asarray(z, dtype=np.float64)
    return WarpedView(np.broadcast_to(np.asarray(color, np.float32), z.shape + (3,)).copy(), z)


def test_z_buffer_merging_takes_the_nearer_view():
    z_left = np.array([[100.0, 50.0, 70.0, np.inf, 80.0, np.inf]])
    z_right = np.array([[50.0, 100.0, 70.0, 60.0, np.inf, np.inf]])
    merged = merge_1d(
        view(10.0, z_left),
        view(200.0, z_right),
        weights=(0.5, 0.5),
        merging=0,
        depth_range=(40.0, 1000.0),
    )
    np.testing.assert_array_equal(merged.color[0, :, 0], [200, 10, 10, 200, 10, 0])
    np.testing.assert_array_equal(merged.z[0], [50, 50, 70, 60, 80, np.inf])


def test_averaging_merging_weights_colours_and_inverse_depths():
    merged = merge_1d(
        view(10.0, [[100.0, np.inf]]),
        view(200.0, [[50.0, 60.0]]),
        weights=(1.0, 3.0),
        merging=1,
        depth_range=(40.0, 1000.0),
    )
    np.testing.assert_allclose(merged.color[0, 0], 0.25 * 10 + 0.75 * 200)
    np.testing.assert_allclose(merged.z[0, 0], 1 / (0.25 / 100 + 0.75 / 50))
    np.testing.assert_allclose(merged.color[0, 1], 200.0)
    assert merged.z[0, 1] == 60.0


@pytest.mark.parametrize(
    "values, averaged",
    [((100, 174), True), ((100, 176), False), ((100, 110), True), ((200, 100), False)],
)
def test_adaptive_merging_switches_on_the_depth_threshold(values, averaged):
    depth_range = (50.0, 1000.0)
    step = inverse_depth_step(depth_range)
    z_left, z_right = (1.0 / (1.0 / 1000.0 + v * step) for v in values)
    merged = merge_1d(
        view(10.0, [[z_left]]),
        view(200.0, [[z_right]]),
        weights=(0.5, 0.5),
        merging=2,
        depth_threshold=75,
        depth_range=depth_range,
    )
    if averaged:
        np.testing.assert_allclose(merged.color[0, 0], 105.0)
        np.testing.assert_allclose(1 / merged.z[0, 0], 0.5 / z_left + 0.5 / z_right)
    else:
        nearer = (10.0, z_left) if z_left < z_right else (200.0, z_right)
        np.testing.assert_allclose(merged.color[0, 0], nearer[0])
        assert merged.z[0, 0] == nearer[1]


@pytest.mark.parametrize("holes, one_view", [(30, True), (29, False)])
def test_adaptive_merging_takes_the_view_with_fewer_holes_around(holes, one_view):
    # One surface in both views; the left view has `holes` holes in the 7x7 window
    # around the centre pixel, the right none.
    z_left = np.full((9, 9), 100.0)
    window = [(y, x) for y in range(1, 8) for x in range(1, 8) if (y, x) != (4, 4)]
    for y, x in window[:holes]:
        z_left[y, x] = np.inf
    merged = merge_1d(
        view(10.0, z_left),
        view(200.0, np.full((9, 9), 101.0)),
        weights=(0.5, 0.5),
        merging=2,
        hole_count_threshold=30,
        depth_range=(50.0, 1000.0),
    )
    np.testing.assert_allclose(merged.color[4, 4], 200.0 if one_view else 105.0)


def test_merge_may_write_into_an_input():
    left = view(10.0, [[100.0, np.inf, 50.0]])
    right = view(200.0, [[100.0, 80.0, np.inf]])
    merged = merge_1d(
        left, right, weights=(0.5, 0.5), merging=1, depth_range=(40.0, 1000.0), out=left
    )
    assert merged is left
    np.testing.assert_allclose(merged.color[0, :, 1], [105.0, 200.0, 10.0])
    np.testing.assert_allclose(merged.z[0], [100.0, 80.0, 50.0])


# --------------------------------------------------------------------------- temporal


def test_temporal_filter_smooths_static_blocks_and_leaves_moving_ones():
    rng = np.random.default_rng(3)
    color = texture(40, 44, seed=3)
    z1, z2, z3 = (rng.uniform(100.0, 200.0, (40, 44)) for _ in range(3))
    temporal = TemporalDepthFilter()
    np.testing.assert_array_equal(temporal.apply(z1, color), z1)
    moved = color.copy()
    moved[20:24, 20:24] += 50.0  # block (5, 5) changes
    second = temporal.apply(z2, moved)
    # Moving: blocks 3..7 in both directions (2 around the changed one), pixels 12..31.
    moving = np.zeros((40, 44), dtype=bool)
    moving[12:32, 12:32] = True
    np.testing.assert_allclose(second[moving], z2[moving])
    smoothed = 1.0 / (0.75 / z1 + 0.25 / z2)
    np.testing.assert_allclose(second[~moving], smoothed[~moving])
    # Recursive: the third static frame builds on the second's filtered depth.
    third = temporal.apply(z3, moved)
    np.testing.assert_allclose(third, 1.0 / (0.75 / second + 0.25 / z3))


@pytest.mark.parametrize("change, static", [(6.0, True), (7.0, False)])
def test_temporal_filter_threshold_is_a_mean_change_of_100_over_16(change, static):
    color = texture(8, 8)
    z1 = np.full((8, 8), 100.0)
    z2 = np.full((8, 8), 200.0)
    temporal = TemporalDepthFilter(spread=0)
    temporal.apply(z1, color)
    changed = color.copy()
    changed[:4, :4] += change
    result = temporal.apply(z2, changed)
    np.testing.assert_allclose(result[:4, :4], 1 / (0.75 / 100 + 0.25 / 200) if static else 200.0)
    np.testing.assert_allclose(result[4:, 4:], 1 / (0.75 / 100 + 0.25 / 200))


def test_temporal_filter_on_odd_sizes_and_after_a_size_change():
    color = texture(21, 43)
    temporal = TemporalDepthFilter()
    temporal.apply(np.full((21, 43), 100.0), color)
    changed = color.copy()
    changed[20, 40:] += 100.0  # the partial corner block (5, 10) moves
    result = temporal.apply(np.full((21, 43), 200.0), changed)
    moving = np.zeros((21, 43), dtype=bool)
    moving[12:, 32:] = True
    np.testing.assert_allclose(result[moving], 200.0)
    np.testing.assert_allclose(result[~moving], 1 / (0.75 / 100 + 0.25 / 200))
    # Another size: a first frame again.
    np.testing.assert_array_equal(temporal.apply(np.full((5, 7), 300.0), texture(5, 7)), 300.0)


# --------------------------------------------------------------------------- bad input


def test_bad_options_and_inputs_are_refused():
    color, z = texture(2, 10), np.full((2, 10), 100.0)
    warper = OneDWarper(LEFT, VIRTUAL, size=(10, 2), left_camera=LEFT)
    reference = ReferenceView(LEFT, color, z)
    with pytest.raises(ValueError, match="splatting"):
        warper.warp(reference, splatting=3)
    for precision in (3, 32):
        with pytest.raises(ValueError, match="precision must be one of 1, 2, 4, 8, 16"):
            warper.warp(reference, precision=precision)
    with pytest.raises(ValueError, match="filter"):
        warper.warp(reference, filter="lanczos")
    with pytest.raises(ValueError, match="positive"):
        warper.warp(ReferenceView(LEFT, color, -z))
    with pytest.raises(ValueError, match="H = 3"):
        OneDWarper(LEFT, VIRTUAL, size=(10, 3), left_camera=LEFT).warp(reference)
    with pytest.raises(ValueError, match="out"):
        warper.warp(reference, out=WarpedView(np.empty((2, 10, 3)), np.empty((2, 10))))
    with pytest.raises(ValueError, match="merging"):
        merge_1d(view(1.0, z), view(1.0, z), weights=(1, 1), merging=3, depth_range=(1, 2))
    with pytest.raises(ValueError, match="weights"):
        merge_1d(view(1.0, z), view(1.0, z), weights=(0, 0), depth_range=(1, 2))
    with pytest.raises(ValueError, match="differ in size"):
        merge_1d(view(1.0, z), view(1.0, z[:, :5]), weights=(1, 1), depth_range=(1, 2))
