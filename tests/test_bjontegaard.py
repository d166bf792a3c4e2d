"""Bjontegaard deltas: the issue's check vector (VCEG-M33 cubic and the JCT-VC PCHIP sheet)
and curves whose deltas are known by construction."""

from __future__ import annotations

import numpy as np
import pytest

from mvtools.metrics.bjontegaard import bd_psnr, bd_rate

ANCHOR_RATE = [9487.76, 4593.60, 2486.44, 1358.24]
ANCHOR_PSNR = [40.037, 38.615, 36.845, 34.851]
TEST_RATE = [9787.80, 4469.00, 2451.52, 1356.24]
TEST_PSNR = [40.121, 38.651, 36.970, 34.987]


@pytest.mark.parametrize(
    "method, rate, quality", [("cubic", -4.4205, 0.1204), ("pchip", -4.4175, 0.1197)]
)
def test_check_vector(method, rate, quality):
    assert bd_rate(ANCHOR_RATE, ANCHOR_PSNR, TEST_RATE, TEST_PSNR, method=method) == pytest.approx(
        rate, abs=5e-4
    )
    assert bd_psnr(ANCHOR_RATE, ANCHOR_PSNR, TEST_RATE, TEST_PSNR, method=method) == pytest.approx(
        quality, abs=5e-4
    )


@pytest.mark.parametrize("method", ["cubic", "pchip"])
def test_deltas_known_by_construction(method):
    # the same quality at 90 % of the rate is a BD-rate of -10 % exactly
    cheaper = np.array(ANCHOR_RATE) * 0.9
    assert bd_rate(ANCHOR_RATE, ANCHOR_PSNR, cheaper, ANCHOR_PSNR, method=method) == pytest.approx(
        -10.0, abs=1e-9
    )
    # 0.5 dB more at the same rates is a BD-PSNR of +0.5 dB
    better = np.array(ANCHOR_PSNR) + 0.5
    assert bd_psnr(ANCHOR_RATE, ANCHOR_PSNR, ANCHOR_RATE, better, method=method) == pytest.approx(
        0.5, abs=1e-9
    )
    assert bd_rate(
        ANCHOR_RATE, ANCHOR_PSNR, ANCHOR_RATE, ANCHOR_PSNR, method=method
    ) == pytest.approx(0.0, abs=1e-12)


@pytest.mark.parametrize(
    "arguments, message",
    [
        (([1, 2, 3], [30, 31, 32], [1, 2, 3], [30, 31, 32]), "at least 4"),
        (([1, 2, 3, 4], [30, 31, 32, 33], [10, 20, 30, 40], [40, 41, 42, 43]), "overlap"),
        (([1, 2, 3, -4], [30, 31, 32, 33], [1, 2, 3, 4], [30, 31, 32, 33]), "positive"),
    ],
)
def test_bad_curves(arguments, message):
    with pytest.raises(ValueError, match=message):
        bd_rate(*arguments)
    with pytest.raises(ValueError, match="method"):
        bd_psnr(ANCHOR_RATE, ANCHOR_PSNR, TEST_RATE, TEST_PSNR, method="akima")
