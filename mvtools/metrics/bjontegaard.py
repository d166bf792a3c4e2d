"""Bjontegaard deltas between two rate-distortion curves (VCEG-M33, 2001).

BD-rate is the mean difference in bitrate at equal quality, in percent; BD-PSNR the
mean difference in quality at equal bitrate, in dB; both over the range of the other
axis that the two curves share. The curves are interpolated either by the cubic
polynomial through the points of each (Bjontegaard's original) or piecewise-cubic
Hermite (PCHIP, as the JCT-VC common-test-condition sheets do), always in log10 of
the rate.
"""

from __future__ import annotations

import numpy as np
from scipy.interpolate import PchipInterpolator

__all__ = ["BD_METHODS", "bd_psnr", "bd_rate"]


def _polynomial_integral(x: np.ndarray, y: np.ndarray, low: float, high: float) -> float:
    coefficients = np.polyfit(x, y, 3)
    antiderivative = np.polyint(coefficients)
    return float(np.polyval(antiderivative, high) - np.polyval(antiderivative, low))


def _pchip_integral(x: np.ndarray, y: np.ndarray, low: float, high: float) -> float:
    order = np.argsort(x)
    return float(PchipInterpolator(x[order], y[order]).integrate(low, high))


BD_METHODS = {"cubic": _polynomial_integral, "pchip": _pchip_integral}


def _curves(rate_a, psnr_a, rate_b, psnr_b, method):
    if method not in BD_METHODS:
        raise ValueError(f"method must be one of {', '.join(BD_METHODS)}, got {method!r}")
    curves = []
    for rate, quality, label in ((rate_a, psnr_a, "anchor"), (rate_b, psnr_b, "test")):
        rate = np.asarray(rate, dtype=np.float64)
        quality = np.asarray(quality, dtype=np.float64)
        if rate.ndim != 1 or rate.shape != quality.shape or rate.size < 4:
            raise ValueError(
                f"the {label} curve needs at least 4 (rate, PSNR) points of equal "
                f"count, got {rate.shape} and {quality.shape}"
            )
        if np.any(rate <= 0) or not np.all(np.isfinite(quality)):
            raise ValueError(f"the {label} curve needs positive rates and finite PSNRs")
        if len(np.unique(quality)) != quality.size or len(np.unique(rate)) != rate.size:
            raise ValueError(f"the {label} curve repeats a rate or a PSNR")
        curves.append((np.log10(rate), quality))
    return curves


def _mean_difference(x_a, y_a, x_b, y_b, method) -> float:
    low, high = max(x_a.min(), x_b.min()), min(x_a.max(), x_b.max())
    if not high > low:
        raise ValueError("the curves do not overlap: no common range to compare them over")
    integrate = BD_METHODS[method]
    return (integrate(x_b, y_b, low, high) - integrate(x_a, y_a, low, high)) / (high - low)


def bd_rate(rate_anchor, psnr_anchor, rate_test, psnr_test, *, method: str = "cubic") -> float:
    """Mean bitrate difference of the test against the anchor at equal PSNR, in percent
    (negative: the test needs less rate).

    Parameters
    ----------
    rate_anchor, psnr_anchor, rate_test, psnr_test : array_like, shape (N,)
        At least four points per curve (kbit/s or any rate unit, dB).
    method : keyword-only {"cubic", "pchip"}

    Returns
    -------
    float
    """
    (log_a, quality_a), (log_b, quality_b) = _curves(
        rate_anchor, psnr_anchor, rate_test, psnr_test, method
    )
    mean_log_difference = _mean_difference(quality_a, log_a, quality_b, log_b, method)
    return float((10.0**mean_log_difference - 1.0) * 100.0)


def bd_psnr(rate_anchor, psnr_anchor, rate_test, psnr_test, *, method: str = "cubic") -> float:
    """Mean PSNR difference of the test against the anchor at equal rate, in dB
    (positive: the test is better). Parameters as :func:`bd_rate`."""
    (log_a, quality_a), (log_b, quality_b) = _curves(
        rate_anchor, psnr_anchor, rate_test, psnr_test, method
    )
    return float(_mean_difference(log_a, quality_a, log_b, quality_b, method))
