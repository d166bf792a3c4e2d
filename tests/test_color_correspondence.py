"""Colour comparisons across cameras (mvtools.color.correspondence): a view warped into
another camera against a hand-computed PSNR."""

from __future__ import annotations

import numpy as np
import pytest

from mvtools.color.correspondence import warped_psnr
from mvtools.geometry.camera import Camera


def test_warped_psnr_of_a_view_two_levels_brighter():
    # fx = 100, baseline 0.1, a wall at z = 10: the target sees every point one
    # column to the left of where the view sees it.
    K = [[100.0, 0.0, 32.0], [0.0, 100.0, 24.0], [0.0, 0.0, 1.0]]
    view_camera, target_camera = Camera("view", K), Camera("target", K, t=[0.1, 0.0, 0.0])
    texture = np.random.default_rng(3).integers(10, 240, (48, 65)).astype(np.float64)
    view, target = texture[:, :64], texture[:, 1:65] - 2
    z = np.full((48, 64), 10.0)
    # PSNR = 20 log10(255 / 2) over the pixels both see
    assert warped_psnr(
        view, view_camera, z, target, target_camera, z, max_value=255
    ) == pytest.approx(20 * np.log10(255 / 2), abs=1e-6)
    # a wall at another depth carries the view to the wrong columns
    assert warped_psnr(view, view_camera, z / 2, target, target_camera, z / 2, max_value=255) < 30


def test_warped_psnr_needs_a_shared_view():
    K = [[100.0, 0.0, 8.0], [0.0, 100.0, 8.0], [0.0, 0.0, 1.0]]
    plane = np.zeros((16, 16))
    far_apart = Camera("other", K, t=[1000.0, 0.0, 0.0])
    with pytest.raises(ValueError, match="sees none of the points"):
        warped_psnr(
            plane,
            Camera("view", K),
            np.full((16, 16), 10.0),
            plane,
            far_apart,
            np.full((16, 16), 10.0),
            max_value=255,
        )
