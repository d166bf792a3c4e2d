"""Semi-global matching (mvtools.depth): synthetic pairs with exact answers and the
Middlebury 2001/2003/2005 pairs against their published ground truth."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import ndimage
from shared_data import shared_data

from mvtools.datasets import load_middlebury_ground_truth, middlebury_pair, score_middlebury
from mvtools.depth import METHODS, estimate_disparity
from mvtools.depth.cost import census_transform
from mvtools.depth.refine import fill_from_background
from mvtools.io.middlebury import MIDDLEBURY_SETS


def _texture(rows, cols, *, seed, blur=0.0):
    generator = np.random.default_rng(seed)
    texture = generator.uniform(0, 255, (rows, cols, 3))
    if blur:
        texture = ndimage.gaussian_filter(texture, (blur, blur, 0))
        texture = (texture - texture.min()) * 255 / np.ptp(texture)
    return texture


@pytest.mark.parametrize("method", METHODS)
def test_constant_integer_shift_is_recovered_exactly(method):
    texture = _texture(60, 100, seed=1).astype(np.uint8)
    # x_right = x_left - 7: the right view shows the texture 7 columns further on
    left, right = texture[:, :90], texture[:, 7:97]
    disparity = estimate_disparity(left, right, max_disparity=15, method=method)
    assert disparity.dtype == np.float32 and disparity.shape == (60, 90)
    assert np.all(disparity == 7.0)
    # a search range not starting at 0, in both views
    assert np.all(
        estimate_disparity(left, right, min_disparity=4, max_disparity=12, method=method) == 7.0
    )
    assert np.all(
        estimate_disparity(
            texture[:, 10:90], texture[:, 7:87], min_disparity=-6, max_disparity=2, method=method
        )
        == -3.0
    )


@pytest.mark.parametrize("shift", [4.5, 6.25])
def test_non_integer_shift_is_recovered_to_a_tenth_of_a_pixel(shift):
    texture = _texture(60, 100, seed=2, blur=1.0)
    left = np.clip(np.rint(texture[:, :90]), 0, 255).astype(np.uint8)
    moved = ndimage.shift(texture, (0, -shift, 0), order=3, mode="nearest")
    right = np.clip(np.rint(moved[:, :90]), 0, 255).astype(np.uint8)
    disparity = estimate_disparity(left, right, max_disparity=15, subpixel=True)
    interior = disparity[5:-5, 20:-5]
    assert abs(np.median(interior) - shift) < 0.1
    assert np.mean(np.abs(interior - shift) < 0.25) > 0.9


@pytest.mark.parametrize("method", METHODS)
def test_two_planes_and_the_occluded_strip_filled_from_the_background(method):
    rows, cols, near, far = 80, 120, 12, 4
    background = _texture(rows, cols + near, seed=3)
    foreground = _texture(rows, cols + near, seed=4)
    top, bottom, x0, x1 = 20, 60, 50, 90
    columns = np.arange(cols)
    in_square_rows = (np.arange(rows) >= top) & (np.arange(rows) < bottom)
    left = background[:, :cols].copy()
    left[top:bottom, x0:x1] = foreground[top:bottom, x0:x1]
    # The right view at column xr sees the square's point of left column xr + near
    # where that lies in the square, else the background point of left column xr + far.
    right = background[:, columns + far].copy()
    shows_square = (columns + near >= x0) & (columns + near < x1)
    right[np.ix_(in_square_rows, shows_square)] = foreground[
        np.ix_(in_square_rows, columns[shows_square] + near)
    ]
    disparity = estimate_disparity(
        left.astype(np.uint8), right.astype(np.uint8), max_disparity=20, method=method
    )
    square = disparity[top + 3 : bottom - 3, x0 + 3 : x1 - 3]
    assert np.mean(np.abs(square - near) < 0.5) > 0.98
    assert np.mean(np.abs(disparity[5 : top - 3, 25:-5] - far) < 0.5) > 0.98
    # Background points left of the square, x in [x0 - 8, x0), hide behind it in
    # the right view: they must take the background's disparity, not the square's.
    strip = disparity[top + 3 : bottom - 3, x0 - (near - far) : x0 - 1]
    assert np.mean(np.abs(strip - far) < 1.0) > 0.9


# Measured bad 1.0 (%) at integer levels (the default) with sgm: Tsukuba 2.68, Venus 1.88
# (all known pixels), Teddy 6.55, Cones 2.85, Art 7.11, Dolls 4.75, Moebius 8.28
# (non-occluded); on Tsukuba graphcut 2.50 and bp 2.61. OpenCV StereoSGBM (HH, block 5)
# on the same data and protocol: 5.7, 3.1, 15.3, 7.2, 16.5, 10.8, 10.8
# (tests/test_middlebury.py). Each threshold is below SGBM's score.
@pytest.mark.parametrize(
    "name, method, threshold",
    [
        ("tsukuba", "sgm", 3.5),
        ("venus", "sgm", 2.6),
        ("teddy", "sgm", 7.6),
        ("cones", "sgm", 3.8),
        ("Art", "sgm", 9.0),
        ("Dolls", "sgm", 6.8),
        ("Moebius", "sgm", 9.8),
        ("tsukuba", "local", 6.2),
        ("tsukuba", "graphcut", 3.5),
        ("tsukuba", "bp", 3.5),
    ],
)
def test_middlebury_scores(name, method, threshold):
    root = shared_data("middlebury")
    left, right = middlebury_pair(root, name)
    truth = load_middlebury_ground_truth(root, name)
    disparities = MIDDLEBURY_SETS[name].disparities
    disparity = estimate_disparity(left, right, max_disparity=disparities - 1, method=method)
    assert not np.isnan(disparity).any()
    assert score_middlebury(disparity, truth, name) < threshold
    # A broken matcher must fail the threshold: winner-takes-all on raw absolute
    # differences of the colour values.
    levels = np.arange(disparities)
    columns = np.arange(left.shape[1])
    shifted = right[:, np.clip(columns[:, None] - levels[None, :], 0, None)]
    raw = np.abs(left[:, :, None].astype(np.int16) - shifted).sum(axis=-1)
    assert score_middlebury(np.argmin(raw, axis=2).astype(np.float32), truth, name) > threshold + 5


def test_unknown_method_names_the_known_ones():
    image = np.zeros((8, 8), np.uint8)
    with pytest.raises(ValueError, match="sgm"):
        estimate_disparity(image, image, max_disparity=2, method="sgbm")
    assert "sgm" in METHODS


def test_bad_ranges_and_shapes():
    image = np.zeros((8, 8), np.uint8)
    with pytest.raises(ValueError, match="exceeds"):
        estimate_disparity(image, image, max_disparity=2, min_disparity=3)
    with pytest.raises(ValueError, match="same shape"):
        estimate_disparity(image, image[:, :6], max_disparity=2)


def test_fill_from_background_by_hand():
    disparity = np.array([[5.0, 9.0, 9.0, 2.0, 7.0], [1.0, 1.0, 1.0, 1.0, 1.0]], np.float32)
    valid = np.array([[True, False, False, True, False], [False, False, False, False, False]])
    filled = fill_from_background(disparity, valid)
    # between 5 and 2 the smaller (farther) wins; the last pixel has only 2 to its left
    assert filled[0].tolist() == [5.0, 2.0, 2.0, 2.0, 2.0]
    assert np.isnan(filled[1]).all()


def test_census_bits_by_hand():
    grey = np.array([[1, 5, 1], [5, 3, 1], [1, 1, 9]], np.uint8)
    signature = census_transform(grey, window=(3, 3))
    # row-major neighbours of the centre 3, bit set when darker: 1 5 1 / 5 . 1 / 1 1 9
    darker = [1, 0, 1, 0, 1, 1, 1, 0]
    assert int(signature[1, 1]) == int("".join(map(str, darker)), 2)
