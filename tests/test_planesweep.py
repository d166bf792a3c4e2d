"""Plane sweeping (:mod:`mvtools.depth.planesweep`) against hand-made geometry: rectified
cameras give pure shifts, a textured plane is found at its depth by one or two
neighbours (also when one of them sees garbage), and in a general layout."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np
import pytest

from mvtools.depth.planesweep import plane_sweep_cost, sweep_homographies
from mvtools.geometry.camera import Camera
from mvtools.geometry.homography import plane_homography

FOCAL, BASELINE = 100.0, 0.1
K = [[FOCAL, 0, 40], [0, FOCAL, 30], [0, 0, 1]]


def camera(name, x, rotation=np.eye(3)):
    return Camera(name, K, rotation, [x, 0.0, 0.0])


def texture(shape=(60, 80), seed=0):
    # Smooth random texture: census and colour both vary at every pixel.
    noise = np.random.default_rng(seed).uniform(0, 255, (shape[0] // 2, shape[1] // 2))
    grey = cv2.resize(noise, shape[::-1], interpolation=cv2.INTER_CUBIC)
    return np.repeat(np.clip(grey, 0, 255)[:, :, None], 3, axis=2).astype(np.float32)


def shifted(image, disparity):
    """The view of a camera BASELINE to the right: x_right = x - disparity."""
    matrix = np.array([[1.0, 0.0, disparity], [0.0, 1.0, 0.0]])
    return cv2.warpAffine(
        image,
        matrix,
        image.shape[1::-1],
        flags=cv2.INTER_LINEAR | cv2.WARP_INVERSE_MAP,
        borderMode=cv2.BORDER_REFLECT,
    )


#: Planes at disparities 0..8 px to a camera BASELINE away: 1/z = d / (f B).
INVERSE = np.arange(9) / (FOCAL * BASELINE)


def test_rectified_homographies_are_horizontal_shifts():
    center, right = camera("c", 0.0), camera("r", BASELINE)
    homographies = sweep_homographies(center, right, INVERSE)
    for disparity, homography in enumerate(homographies):
        expected = np.eye(3)
        expected[0, 2] = -disparity
        np.testing.assert_allclose(homography / homography[2, 2], expected, atol=1e-9)


def test_world_planes_agree_with_camera_planes_for_a_camera_at_the_origin():
    center, right = camera("c", 0.0), camera("r", BASELINE)
    np.testing.assert_allclose(
        sweep_homographies(center, right, INVERSE[1:], depth_type=1),
        sweep_homographies(center, right, INVERSE[1:]),
        atol=1e-9,
    )


def test_a_textured_plane_is_found_at_its_disparity_by_either_neighbour():
    center_view = texture()
    for side, x, disparity in (("right", BASELINE, 5), ("left", -BASELINE, -5)):
        sweep = plane_sweep_cost(
            center_view,
            [shifted(center_view, disparity)],
            camera("c", 0.0),
            [camera(side, x)],
            INVERSE,
        )
        interior = np.s_[5:-5, 15:-15]
        assert (sweep.cost.argmin(axis=2)[interior] == 5).mean() > 0.99
        assert sweep.seen[interior].all()


def test_points_outside_the_neighbour_are_not_seen():
    center_view = texture()
    sweep = plane_sweep_cost(
        center_view,
        [shifted(center_view, 3)],
        camera("c", 0.0),
        [camera("r", BASELINE)],
        INVERSE,
        outside_cost=0.5,
    )
    # plane k sends x to x - k: columns x < k - 0.5 leave the picture
    for k in range(9):
        columns = np.arange(80)
        assert np.array_equal(sweep.seen[0, :, k], columns - k >= -0.5)
        assert np.all(sweep.cost[0, columns - k < -0.5, k] == np.float32(0.5))


def test_the_least_cost_of_the_neighbours_ignores_one_that_sees_garbage():
    center_view = texture()
    garbage = texture(seed=1)
    right = shifted(center_view, 4)
    cameras = [camera("l", -BASELINE), camera("r", BASELINE)]
    sweep = plane_sweep_cost(center_view, [garbage, right], camera("c", 0.0), cameras, INVERSE)
    alone = plane_sweep_cost(center_view, [garbage], camera("c", 0.0), cameras[:1], INVERSE)
    interior = np.s_[5:-5, 15:-15]
    assert (sweep.cost.argmin(axis=2)[interior] == 4).mean() > 0.99
    assert (alone.cost.argmin(axis=2)[interior] == 4).mean() < 0.5


def test_general_layout_a_rotated_neighbour_finds_the_plane():
    angle = np.radians(4.0)
    rotation = np.array(
        [[np.cos(angle), 0, -np.sin(angle)], [0, 1, 0], [np.sin(angle), 0, np.cos(angle)]]
    )
    center, neighbour = camera("c", 0.0), camera("n", 0.3, rotation)
    z = 4.0
    # A plane textured beyond what the center sees, so that the neighbour sees texture
    # everywhere: the center view is the middle of the big picture.
    big = texture((180, 240))
    center_view = big[60:120, 80:160]
    to_center = np.array([[1.0, 0, -80], [0, 1, -60], [0, 0, 1]])
    # The neighbour's view of the plane z = 4: neighbour(H x) = center(x).
    homography = plane_homography(center, neighbour, z) @ to_center
    view = cv2.warpPerspective(big, homography, (80, 60), flags=cv2.INTER_LINEAR)
    inverse = np.linspace(0.05, 0.45, 21)  # 0.6 px apart; 1/4 is plane 10
    sweep = plane_sweep_cost(center_view, [view], center, [neighbour], inverse)
    chosen = sweep.cost.argmin(axis=2)
    seen_interior = sweep.seen[8:-8, 8:-8].all(axis=2)
    # measured 0.88 (random planes: 0.14)
    assert (np.abs(chosen[8:-8, 8:-8] - 10) <= 1)[seen_interior].mean() > 0.8


def test_block_costs_are_3x3_means():
    center_view = texture()
    args = (
        center_view,
        [shifted(center_view, 2)],
        camera("c", 0.0),
        [camera("r", BASELINE)],
        INVERSE,
    )
    single = plane_sweep_cost(*args).cost
    block = plane_sweep_cost(*args, block=3).cost
    np.testing.assert_allclose(block[10, 30], single[9:12, 29:32].mean(axis=(0, 1)), rtol=1e-5)


@pytest.mark.parametrize(
    "change, message",
    [
        ({"neighbours": []}, "at least one neighbour"),
        ({"inverse_depths": [-0.1, 0.2]}, "finite and >= 0"),
        ({"inverse_depths": []}, "no depth planes"),
        ({"block": 2}, "block must be 1 or 3"),
        ({"precision": (0, 1)}, "precision must be two positive integers"),
        ({"filter": "nearest"}, "filter must be one of"),
    ],
)
def test_bad_arguments(change, message):
    arguments = {
        "center": texture(),
        "neighbours": [texture()],
        "center_camera": camera("c", 0),
        "neighbour_cameras": [camera("r", BASELINE)],
        "inverse_depths": INVERSE,
    }
    arguments.update(change)
    with pytest.raises(ValueError, match=message):
        plane_sweep_cost(**arguments)


def test_rectified_neighbours_take_the_row_kernel_with_the_same_costs(monkeypatch):
    # the sample line's cameras: every plane's homography is a shift along the rows
    import mvtools.depth.planesweep as planesweep
    from mvtools.color.space import yuv_to_rgb
    from mvtools.io.cameras import read_cameras
    from mvtools.io.yuv import YuvFormat, read_frame

    line = Path(__file__).resolve().parent.parent / "sample_data" / "line"
    cameras = read_cameras(line / "cameras.txt")
    views = [
        yuv_to_rgb(
            read_frame(line / f"v{i}_texture_256x192_yuv420p.yuv", YuvFormat(256, 192)), bits=8
        )
        for i in (1, 2, 3)
    ]
    inverse = np.linspace(1 / 13, 1 / 2, 24)
    homographies = sweep_homographies(cameras["cam2"], cameras["cam3"], inverse)
    assert planesweep._sweep(homographies) is planesweep._sweep_along_rows
    arguments = (
        views[1],
        [views[0], views[2]],
        cameras["cam2"],
        [cameras["cam1"], cameras["cam3"]],
    )
    rows = plane_sweep_cost(*arguments, inverse, precision=(4, 2))
    monkeypatch.setattr(planesweep, "_sweep", lambda homographies: planesweep._sweep_neighbour)
    general = plane_sweep_cost(*arguments, inverse, precision=(4, 2))
    np.testing.assert_array_equal(rows.cost, general.cost)
    np.testing.assert_array_equal(rows.seen, general.seen)
