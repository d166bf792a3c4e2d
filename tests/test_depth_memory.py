"""Memory-lean paths of the depth methods (issue 20) give what the whole-volume paths
give: the streamed SGM winners, the methods writing over their costs, the mirrored pair's
costs by reindexing; and they do not hold extra volumes."""

from __future__ import annotations

import tracemalloc

import numpy as np
import pytest
from scipy import ndimage

from mvtools.depth import METHODS, estimate_disparity, local
from mvtools.depth.bp import bp_volume, bp_winners
from mvtools.depth.cost import ad_census_cost, ad_census_levels, census_gradient_cost, mirror_costs
from mvtools.depth.graphcut import graphcut_labels, graphcut_volume, label_energies
from mvtools.depth.sgm import sgm_volume, sgm_winners, winner_takes_all


def _pair(rows=40, cols=70, shift=5, seed=3):
    generator = np.random.default_rng(seed)
    texture = ndimage.gaussian_filter(generator.uniform(0, 255, (rows, cols + shift, 3)), (1, 1, 0))
    texture = np.clip(texture, 0, 255).astype(np.uint8)
    # x_right = x_left - shift
    return np.ascontiguousarray(texture[:, :cols]), np.ascontiguousarray(texture[:, shift:])


@pytest.mark.parametrize(("min_disparity", "levels"), [(0, 9), (2, 7), (-3, 10)])
def test_mirrored_ad_census_costs_are_the_pairs_reindexed(min_disparity, levels):
    left, right = _pair()
    mirrored = ad_census_cost(
        np.ascontiguousarray(right[:, ::-1]),
        np.ascontiguousarray(left[:, ::-1]),
        min_disparity=min_disparity,
        levels=levels,
    )
    costs = ad_census_cost(left, right, min_disparity=min_disparity, levels=levels)
    assert mirror_costs(costs, min_disparity=min_disparity) is costs
    assert np.array_equal(costs, mirrored)


def test_mirror_costs_refuses_a_copy_it_could_not_write_back():
    with pytest.raises(ValueError, match="contiguous"):
        mirror_costs(np.zeros((2, 3, 4)), min_disparity=0)


@pytest.mark.parametrize("strip_rows", [None, 1, 6, 40, 100])
@pytest.mark.parametrize("min_disparity", [0, 2])
def test_streamed_sgm_winners_are_those_of_the_volume(strip_rows, min_disparity):
    left, right = _pair()
    costs = census_gradient_cost(left, right, min_disparity=min_disparity, levels=9)
    before = costs.copy()
    guide = left.astype(np.float32)
    volume = sgm_volume(costs, guide)
    streamed = sgm_winners(costs, guide, min_disparity=min_disparity, strip_rows=strip_rows)
    assert np.array_equal(costs, before)
    assert np.array_equal(streamed[0], winner_takes_all(volume))
    assert np.array_equal(
        streamed[1], winner_takes_all(volume, right_view=True, min_disparity=min_disparity)
    )


@pytest.mark.parametrize("strip_rows", [1, 4, 32, 100])
@pytest.mark.parametrize("scales", [1, 3, 5])
def test_streamed_bp_winners_are_those_of_the_volume(strip_rows, scales):
    # odd sizes: coarse blocks cut by the frame's edges
    left, right = _pair(rows=41, cols=67)
    costs = ad_census_cost(left, right, min_disparity=2, levels=8)
    before = costs.copy()
    guide = left.astype(np.float32)
    volume = bp_volume(costs, guide, scales=scales)
    streamed = bp_winners(costs, guide, min_disparity=2, scales=scales, strip_rows=strip_rows)
    assert np.array_equal(costs, before)
    assert np.array_equal(streamed[0], winner_takes_all(volume))
    assert np.array_equal(streamed[1], winner_takes_all(volume, right_view=True, min_disparity=2))


@pytest.mark.parametrize("min_disparity", [0, 3])
def test_ad_census_levels_are_the_volumes(min_disparity):
    left, right = _pair()
    volume = ad_census_cost(left, right, min_disparity=min_disparity, levels=9)
    level = ad_census_levels(left, right, min_disparity=min_disparity, levels=9)
    for k in range(9):
        assert np.array_equal(level(k), volume[:, :, k])
    with pytest.raises(ValueError, match="level 9"):
        level(9)


def test_graphcut_labels_level_by_level_are_those_of_the_volume():
    left, right = _pair()
    volume = ad_census_cost(left, right, min_disparity=0, levels=9)
    guide = left.astype(np.float32)
    labels, weights_right, weights_down = graphcut_labels(
        ad_census_levels(left, right, min_disparity=0, levels=9), 9, guide
    )
    expected = graphcut_volume(volume.copy(), guide)
    energies = label_energies(volume, labels, weights_right, weights_down, 4)
    assert np.array_equal(energies, expected)


@pytest.mark.parametrize("method", METHODS)
def test_overwriting_methods_give_the_same_volume(method):
    left, right = _pair()
    costs = ad_census_cost(left, right, min_disparity=0, levels=9)
    guide = left.astype(np.float32)
    kept = METHODS[method](costs.copy(), guide)
    scratch = costs.copy()
    overwritten = METHODS[method](scratch, guide, overwrite=True)
    assert np.array_equal(kept, overwritten)
    if method != "sgm":
        assert np.shares_memory(overwritten, scratch)


def test_local_method_takes_more_levels_than_opencv_has_channels():
    # OpenCV 5 filters at most 128 channels at once; the shift is found among 140 levels
    left, right = _pair(rows=30, cols=160, shift=9)
    disparity = estimate_disparity(left, right, max_disparity=139, method="local")
    assert np.mean(disparity[:, 20:] == 9.0) > 0.95


@pytest.mark.parametrize("method", ["local", "graphcut"])
def test_overwriting_methods_allocate_nothing_per_level(monkeypatch, method):
    # NumPy's and OpenCV's arrays are traced (numba's are not). Writing over the costs,
    # a method's peak grows with the pixels only: twice the levels, the same peak
    # (with the guided filter's chunks of four levels), where a second volume would add
    # the bytes of the extra levels.
    monkeypatch.setattr(local, "_CHUNK_BYTES", 60 * 90 * 4 * 4)
    left, right = _pair(rows=60, cols=90)
    guide = left.astype(np.float32)
    function = local.local_volume if method == "local" else graphcut_volume
    peaks = []
    for levels in (32, 64):
        costs = ad_census_cost(left, right, min_disparity=0, levels=levels)
        function(costs.copy(), guide, overwrite=True)  # compiled outside the trace
        tracemalloc.start()
        try:
            function(costs, guide, overwrite=True)
            peaks.append(tracemalloc.get_traced_memory()[1])
        finally:
            tracemalloc.stop()
    extra_levels_bytes = 60 * 90 * 32 * 4
    assert peaks[1] - peaks[0] < 0.1 * extra_levels_bytes
