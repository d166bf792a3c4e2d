"""DERS's soft-segment cost weighting (MatchingMethod 3) against hand-computed sums."""

from __future__ import annotations

import numpy as np
import pytest

from mvtools.depth.local import soft_segment_aggregate


def test_uniform_colour_weights_by_distance_alone():
    cost = np.zeros((5, 5, 2), np.float32)
    cost[2, 2, 0] = 1.0  # one costly pixel, level 0 only
    guide = np.full((5, 5, 3), 100.0, np.float32)
    result = soft_segment_aggregate(
        cost, guide, block=(3, 3), distance_coeff=2.0, colour_coeff=20.0
    )
    # at the centre: weight 1 of 1 + 4 e^(-1/2) + 4 e^(-sqrt(2)/2); beside it, in a row
    # of the block, e^(-1/2) of the same total; level 1 stays 0
    total = 1 + 4 * np.exp(-0.5) + 4 * np.exp(-np.sqrt(2) / 2)
    assert result[2, 2, 0] == pytest.approx(1 / total, rel=1e-6)
    assert result[2, 3, 0] == pytest.approx(np.exp(-0.5) / total, rel=1e-6)
    assert result[2, 4, 0] == 0.0 and not result[..., 1].any()


def test_another_colour_hardly_counts():
    # left half dark with cost 0, right half bright with cost 1: a dark pixel at the edge
    # gives the bright column exp(-255 / 5) of a weight
    cost = np.zeros((3, 4, 1), np.float32)
    cost[:, 2:] = 1.0
    guide = np.zeros((3, 4, 3), np.float32)
    guide[:, 2:] = 255.0
    result = soft_segment_aggregate(
        cost, guide, block=(3, 3), distance_coeff=20.0, colour_coeff=5.0
    )
    assert result[1, 1, 0] < 1e-20 and result[1, 2, 0] == pytest.approx(1.0)


def test_even_blocks_reach_further_right_and_down():
    cost = np.zeros((3, 3, 1), np.float32)
    cost[2, 2] = 1.0
    guide = np.zeros((3, 3, 3), np.float32)
    two = soft_segment_aggregate(cost, guide, block=(2, 2), distance_coeff=1e9, colour_coeff=1.0)
    assert two[1, 1, 0] == pytest.approx(0.25) and two[0, 0, 0] == 0.0


@pytest.mark.parametrize(
    "block, distance, colour", [((0, 3), 20.0, 20.0), ((3, 3), 0.0, 20.0), ((3, 3), 20.0, -1.0)]
)
def test_bad_arguments(block, distance, colour):
    with pytest.raises(ValueError, match="positive coefficients"):
        soft_segment_aggregate(
            np.zeros((2, 2, 1)),
            np.zeros((2, 2, 3)),
            block=block,
            distance_coeff=distance,
            colour_coeff=colour,
        )
