"""The DERS mode's winners taken a few levels at a time (issue 20): the center's level and
each rectified neighbour's own level from a method's volume given in chunks of levels are
those of the whole volume bit for bit (sgm's ``winner_takes_all``, and the neighbours' rule
written out here in numpy), and the ``local`` and ``graphcut``
methods give their volumes in such chunks without holding them."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import ndimage

from mvtools.depth.ders import _levelwise_winners, _scaled_levels, _winners
from mvtools.depth.graphcut import graphcut_levels, graphcut_volume
from mvtools.depth.local import local_levels, local_volume
from mvtools.depth.sgm import winner_takes_all


def _own_levels(volume, shift):
    # a rectified neighbour's pixel x takes the first level k whose center pixel
    # x - shift[k] (rounded half up, inside the picture) costs least; -1 if none is inside
    rows, cols, levels = volume.shape
    best = np.full((rows, cols), np.inf, np.float32)
    own = np.full((rows, cols), -1, np.int64)
    for k in range(levels):
        source = np.floor(np.arange(cols) - shift[k] + 0.5).astype(np.int64)
        inside = (source >= 0) & (source < cols)
        values = np.where(inside, volume[:, np.clip(source, 0, cols - 1), k], np.inf)
        better = values < best
        best[better], own[better] = values[better], k
    return own


def _chunks(volume, sizes):
    start = 0
    for size in sizes:
        yield start, volume[:, :, start : start + size]
        start += size
    assert start == volume.shape[2]


def _partitions(levels, seed=0):
    generator = np.random.default_rng(seed)
    cuts = np.sort(generator.choice(np.arange(1, levels), size=min(4, levels - 1), replace=False))
    return [[1] * levels, [levels], list(np.diff(np.concatenate([[0], cuts, [levels]])))]


# One row of four pixels, three levels. Neighbour a sees center pixel x - k at level k,
# neighbour b center pixel x + k, neighbour c none.
_HAND_VOLUME = np.array([[[3, 1, 2], [0, 5, 5], [4, 2, 2], [1, 1, 0]]], np.float32)
_HAND_SHIFTS = [np.array([0.0, 1.0, 2.0]), np.array([0.0, -1.0, -2.0]), np.array([10.0, 11, 12])]
# The parabola through the winner: pixel 0 (1 + (3 - 2) / (2 * 3)); pixel 2 ties with the
# level above, 1.5, which np.rint takes to 2: not the first minimum
_HAND_LEVEL = np.array([[1 + 1 / 6, 0.0, 1.5, 2.0]], np.float32)
_HAND_OWN = [np.array([[0, 0, 2, 0]]), np.array([[2, 0, 1, 0]]), np.array([[-1, -1, -1, -1]])]


@pytest.mark.parametrize("sizes", [[1, 1, 1], [2, 1], [1, 2], [3]])
def test_levelwise_winners_of_a_hand_volume(sizes):
    level, own = _levelwise_winners(_chunks(_HAND_VOLUME, sizes), (1, 4), 3, _HAND_SHIFTS)
    assert np.array_equal(level, _HAND_LEVEL)
    assert np.array_equal(np.rint(level), [[1, 0, 2, 2]])
    for theirs, expected in zip(own, _HAND_OWN):
        assert np.array_equal(theirs, expected)
    whole_level, whole_own = _winners(_HAND_VOLUME, _HAND_SHIFTS)
    assert np.array_equal(whole_level, _HAND_LEVEL)
    for theirs, expected in zip(whole_own, _HAND_OWN):
        assert np.array_equal(theirs, expected)
    assert np.array_equal(winner_takes_all(_HAND_VOLUME), _HAND_LEVEL)
    for shift, expected in zip(_HAND_SHIFTS, _HAND_OWN):
        assert np.array_equal(_own_levels(_HAND_VOLUME, shift), expected)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_levelwise_winners_are_those_of_the_whole_volume(seed):
    # few distinct values: many ties, with the level above among them; some inf and NaN
    generator = np.random.default_rng(seed)
    rows, cols, levels = 6, 31, 13
    volume = generator.integers(0, 5, (rows, cols, levels)).astype(np.float32)
    volume += generator.choice([0.0, 0.25, 1e-6], volume.shape).astype(np.float32)
    volume[generator.random(volume.shape) < 0.02] = np.inf
    volume[generator.random(volume.shape) < 0.01] = np.nan
    # half-pixel shifts too: rounded half up
    shifts = [
        np.linspace(0.0, 9.5, levels),
        -np.linspace(-2.0, 7.0, levels),
        generator.uniform(-40, 40, levels),
    ]
    expected_level = winner_takes_all(volume)
    expected_own = [_own_levels(volume, shift) for shift in shifts]
    for sizes in _partitions(levels, seed):
        level, own = _levelwise_winners(_chunks(volume, sizes), (rows, cols), levels, shifts)
        assert np.array_equal(level, expected_level)
        assert len(own) == len(shifts)
        for theirs, expected in zip(own, expected_own):
            assert np.array_equal(theirs, expected)
    level, own = _levelwise_winners(_chunks(volume, [levels]), (rows, cols), levels, [])
    assert np.array_equal(level, expected_level) and own == []


def test_levelwise_winners_refuse_missing_or_disordered_levels():
    with pytest.raises(ValueError, match="2 levels of 3"):
        _levelwise_winners(_chunks(_HAND_VOLUME[:, :, :2], [2]), (1, 4), 3, [])
    disordered = iter([(1, _HAND_VOLUME[:, :, 1:]), (0, _HAND_VOLUME[:, :, :1])])
    with pytest.raises(ValueError, match="level 1"):
        _levelwise_winners(disordered, (1, 4), 3, [])


def _costs_and_guide(rows=24, cols=40, levels=11, seed=5):
    generator = np.random.default_rng(seed)
    guide = ndimage.gaussian_filter(generator.uniform(0, 255, (rows, cols, 3)), (1, 1, 0))
    costs = ndimage.gaussian_filter(generator.uniform(0, 2, (rows, cols, levels)), 1)
    return costs.astype(np.float32), guide.astype(np.float32)


@pytest.mark.parametrize("scale", [1.0, 0.5, 4 / 3])
def test_scaled_levels_are_slices_of_the_scaled_volume(scale):
    costs, _ = _costs_and_guide()
    before = costs.copy()
    levels = _scaled_levels(costs, scale)
    whole = costs * np.float32(scale)
    for start, stop in [(0, 1), (3, 7), (0, 11)]:
        chunk = levels(start, stop)
        assert chunk.flags.c_contiguous and chunk.dtype == np.float32
        assert np.array_equal(chunk, whole[:, :, start:stop])
    assert np.array_equal(costs, before)


@pytest.mark.parametrize("chunk_bytes", [24 * 40 * 4, 3 * 24 * 40 * 4, 1 << 24])
@pytest.mark.parametrize("method", ["local", "graphcut"])
def test_method_levels_are_the_method_volume(monkeypatch, method, chunk_bytes):
    from mvtools.depth import graphcut, local

    monkeypatch.setattr(local if method == "local" else graphcut, "_CHUNK_BYTES", chunk_bytes)
    costs, guide = _costs_and_guide()
    before = costs.copy()
    function, levels_function = {
        "local": (local_volume, local_levels),
        "graphcut": (graphcut_volume, graphcut_levels),
    }[method]
    expected = function(costs.copy(), guide)
    chunks = list(levels_function(_scaled_levels(costs, 1.0), costs.shape[2], guide))
    assert [start for start, _ in chunks] == list(
        np.cumsum([0] + [chunk.shape[2] for _, chunk in chunks[:-1]])
    )
    assert np.array_equal(np.concatenate([chunk for _, chunk in chunks], axis=2), expected)
    assert np.array_equal(costs, before)


@pytest.mark.parametrize("step", [0.25, 0.5, 1.0, 1.37, 4.0, 8.0])
def test_bp_charges_its_smoothness_per_pixel_of_disparity(step):
    from mvtools.depth.bp import SMOOTHING, TRUNCATION
    from mvtools.depth.ders import _smoothness_in_pixels

    options = _smoothness_in_pixels("bp", step)
    assert options["truncation"] >= 1  # belief_propagation's lower limit
    # bp's pairwise term per level difference k, against w min(|disparity change|, T)
    for k in range(0, 40):
        per_level = options["smoothing"] * min(k, options["truncation"])
        assert per_level == pytest.approx(SMOOTHING * min(k * step, TRUNCATION))
    # hand-computed: quarter-pixel levels, w / 4 up to 16 levels; 8-pixel levels, Potts at w T
    if step == 0.25:
        assert options == {"smoothing": 4.0, "truncation": 16.0}
    if step == 8.0:
        assert options == {"smoothing": 64.0, "truncation": 1.0}


def test_methods_of_another_smoothness_keep_their_own():
    from mvtools.depth.ders import _smoothness_in_pixels

    assert _smoothness_in_pixels("sgm", 0.25) == {} == _smoothness_in_pixels("graphcut", 0.25)
