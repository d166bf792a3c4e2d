"""The ``local``, ``graphcut`` and ``bp`` depth methods: synthetic pairs with exact answers,
small energies minimised by hand, and the Tsukuba pair against its ground truth."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from mvtools.depth import METHODS
from mvtools.depth.bp import belief_propagation
from mvtools.depth.graphcut import (
    alpha_expansion,
    graphcut_volume,
    label_energies,
    smoothness_weights,
)
from mvtools.depth.local import guided_filter


def _brute_force(cost, right, truncation):
    # every labelling of a 1xN chain
    levels = cost.shape[2]
    best = None
    for labels in itertools.product(range(levels), repeat=cost.shape[1]):
        labels = np.array(labels)
        energy = (
            cost[0, np.arange(len(labels)), labels].sum()
            + (right[0] * np.minimum(np.abs(np.diff(labels)), truncation)).sum()
        )
        if best is None or energy < best[0]:
            best = (energy, labels)
    return best[1]


def test_potts_chain_by_hand():
    # A 1x3 chain whose middle pixel prefers level 1 by 1.5, its ends level 0 by 2.
    # With weight 1 a lone 1 costs two jumps (2 > 1.5): all 0 (energy 1.5). With
    # weight 0.5 the jumps cost 1 < 1.5: 0 1 0 (energy 1).
    cost = np.array([[[0.0, 2.0], [1.5, 0.0], [0.0, 2.0]]], np.float32)
    down = np.zeros((0, 3), np.float32)
    for weight, expected in ((1.0, [0, 0, 0]), (0.5, [0, 1, 0])):
        right = np.full((1, 2), weight, np.float32)
        labels = alpha_expansion(cost, right, down, truncation=1)
        assert labels[0].tolist() == expected
        # the chain is a tree: belief propagation is exact on it
        beliefs = belief_propagation(cost, right, down, truncation=1, scales=1, iterations=6)
        assert np.argmin(beliefs, axis=2)[0].tolist() == expected


def test_truncated_linear_chain_by_hand():
    # Ends want levels 0 and 3 strongly, the middle is indifferent except level 3
    # costs 1 more. Truncation 2, weight 1: 0 0 3 costs 0 + 2 = 2, 0 1 3 and 0 2 3
    # cost 1 + 2 and 2 + 1 = 3, 0 3 3 costs 1 + 2 = 3; the minimum is 0 0 3.
    cost = np.array([[[0, 9, 9, 9], [0, 0, 0, 1], [9, 9, 9, 0]]], np.float32)
    right = np.ones((1, 2), np.float32)
    down = np.zeros((0, 3), np.float32)
    labels = alpha_expansion(cost, right, down, truncation=2)
    assert labels[0].tolist() == [0, 0, 3] == _brute_force(cost, right, 2).tolist()
    energies = label_energies(cost, labels, right, down, 2)
    # middle pixel: level d costs cost + min(d, 2) + min(3 - d, 2)
    assert np.allclose(energies[0, 1], [0 + 0 + 2, 0 + 1 + 2, 0 + 2 + 1, 1 + 2 + 0])
    beliefs = belief_propagation(cost, right, down, truncation=2, scales=1, iterations=6)
    assert np.argmin(beliefs, axis=2)[0].tolist() == [0, 0, 3]


def _messages_by_definition(cost, right, down, truncation, scales, iterations):
    # Hierarchical checkerboard min-sum belief propagation written from its definition
    # (Felzenszwalb & Huttenlocher 2006), in float64: the message to a neighbour is
    # min_e [h(e) + w min(|d - e|, T)] over every level e, shifted to a minimum of 0,
    # with h the data cost plus the messages from the three other neighbours; half-sweep
    # k updates the pixels with (x + y) % 2 == k % 2. The coarser level is the energy
    # restricted to labels constant on 2x2 blocks, and each pixel starts from the
    # messages its block received there. Messages by slot: from above, below, left, right.
    rows, cols, levels = cost.shape
    messages = np.zeros((4,) + cost.shape)
    if scales > 1 and min(rows, cols) > 1:
        coarse_rows, coarse_cols = -(-rows // 2), -(-cols // 2)
        coarse_cost = np.zeros((coarse_rows, coarse_cols, levels))
        coarse_right = np.zeros((coarse_rows, coarse_cols - 1))
        coarse_down = np.zeros((coarse_rows - 1, coarse_cols))
        for y, x in itertools.product(range(rows), range(cols)):
            coarse_cost[y // 2, x // 2] += cost[y, x]
            if x % 2 == 1 and x < cols - 1:
                coarse_right[y // 2, x // 2] += right[y, x]
            if y % 2 == 1 and y < rows - 1:
                coarse_down[y // 2, x // 2] += down[y, x]
        coarse = _messages_by_definition(
            coarse_cost, coarse_right, coarse_down, truncation, scales - 1, iterations
        )
        for y, x in itertools.product(range(rows), range(cols)):
            messages[:, y, x] = coarse[:, y // 2, x // 2]
    jumps = np.minimum(np.abs(np.subtract.outer(np.arange(levels), np.arange(levels))), truncation)
    for half_sweep in range(iterations):
        for y, x in itertools.product(range(rows), range(cols)):
            if (x + y) % 2 != half_sweep % 2:
                continue
            total = cost[y, x] + messages[:, y, x].sum(axis=0)
            # (neighbour, the slot it receives this pixel's message in, weight, the
            # slot of the message from that neighbour, left out of h)
            for (ny, nx), slot, weight, own in (
                ((y - 1, x), 1, down[y - 1, x] if y > 0 else 0, 0),
                ((y + 1, x), 0, down[y, x] if y < rows - 1 else 0, 1),
                ((y, x - 1), 3, right[y, x - 1] if x > 0 else 0, 2),
                ((y, x + 1), 2, right[y, x] if x < cols - 1 else 0, 3),
            ):
                if 0 <= ny < rows and 0 <= nx < cols:
                    h = total - messages[own, y, x]
                    sent = (h[None, :] + weight * jumps).min(axis=1)
                    messages[slot, ny, nx] = sent - h.min()
    return messages


@pytest.mark.parametrize(
    ("shape", "scales", "iterations"),
    [
        ((5, 7, 4), 1, 1),
        ((37, 11, 5), 1, 6),
        ((19, 13, 6), 3, 5),
        ((1, 9, 3), 2, 4),
        ((6, 1, 3), 2, 3),
    ],
)
def test_belief_propagation_follows_its_definition(shape, scales, iterations):
    # odd sizes, more rows than a strip of the sweeps, a row or a column alone
    generator = np.random.default_rng(9)
    cost = generator.uniform(0, 2, shape).astype(np.float32)
    right = generator.uniform(0, 1, (shape[0], shape[1] - 1)).astype(np.float32)
    down = generator.uniform(0, 1, (shape[0] - 1, shape[1])).astype(np.float32)
    beliefs = belief_propagation(
        cost, right, down, truncation=2.5, scales=scales, iterations=iterations
    )
    messages = _messages_by_definition(
        cost.astype(np.float64), right, down, 2.5, scales, iterations
    )
    assert np.allclose(beliefs, cost + messages.sum(axis=0), rtol=1e-5, atol=1e-4)


def test_random_small_chains_reach_the_exact_minimum():
    # alpha-expansion is within a factor 2 of the optimum for truncated linear terms
    # (Boykov et al. 2001); on chains of 5 pixels it finds the optimum in practice.
    generator = np.random.default_rng(5)
    for _ in range(10):
        cost = generator.uniform(0, 2, (1, 5, 4)).astype(np.float32)
        right = generator.uniform(0, 0.6, (1, 4)).astype(np.float32)
        labels = alpha_expansion(cost, right, np.zeros((0, 5), np.float32), truncation=2)
        assert labels[0].tolist() == _brute_force(cost, right, 2).tolist()


def test_graphcut_volume_minimum_is_the_expansion_labels():
    generator = np.random.default_rng(6)
    cost = generator.uniform(0, 2, (12, 15, 6)).astype(np.float32)
    guide = generator.uniform(0, 255, (12, 15, 3)).astype(np.float32)
    right, down = smoothness_weights(cost, guide, smoothing=16.0, smoothing2=1.0, colour_scale=10.0)
    labels = alpha_expansion(cost, right, down, truncation=4)
    volume = graphcut_volume(cost, guide)
    # alpha-expansion ends where no single pixel can lower the energy
    assert np.all(volume.min(axis=2) == volume[np.arange(12)[:, None], np.arange(15), labels])


def test_smoothness_weights_follow_ders():
    cost = np.array([[[0.0, 2.0]] * 3], np.float32)
    guide = np.array([[[10, 10, 10], [10, 10, 10], [250, 250, 250]]], np.float32)
    right, down = smoothness_weights(cost, guide, smoothing=4.0, smoothing2=0.5, colour_scale=10.0)
    # one grey level of an 8-bit data cost is range / 255 = 2 / 255; equal colours get
    # SmoothingCoefficient of them, a strong edge SmoothingCoefficient * SmoothingCoefficient2
    assert down.shape == (0, 3)
    assert np.allclose(right[0], [4 * 2 / 255, 4 * 0.5 * 2 / 255], rtol=1e-4)


def test_guided_filter_keeps_constants_and_guide_edges():
    guide = np.zeros((20, 30, 3), np.float32)
    guide[:, 15:] = 1.0
    volume = np.stack(
        [
            np.full((20, 30), 0.3, np.float32),
            np.where(guide[:, :, 0] > 0, 1.0, 0.0).astype(np.float32),
        ],
        axis=2,
    )
    filtered = guided_filter(volume, guide, radius=4, epsilon=1e-4)
    assert np.allclose(filtered[:, :, 0], 0.3, atol=1e-5)
    # a cost step along the guide's edge is not blurred across it
    assert np.allclose(filtered[:, :, 1], volume[:, :, 1], atol=1e-2)


def test_option_errors():
    cost = np.zeros((4, 5, 3), np.float32)
    guide = np.zeros((4, 5, 3), np.float32)
    with pytest.raises(ValueError, match="non-negative"):
        graphcut_volume(cost, guide, smoothing=-1.0)
    with pytest.raises(ValueError, match="colour_scale"):
        METHODS["bp"](cost, guide, colour_scale=0.0)
    with pytest.raises(ValueError, match="at least 1"):
        METHODS["bp"](cost, guide, iterations=0)
    with pytest.raises(ValueError, match="radius"):
        METHODS["local"](cost, guide, radius=0)
    with pytest.raises(ValueError, match="grid"):
        alpha_expansion(cost, np.zeros((4, 3)), np.zeros((3, 5)), truncation=2)
