"""The scores of one video frame against its reference, by metric name."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from mvtools.metrics.ivpsnr import iv_psnr
from mvtools.metrics.psnr import plane_psnr, yuv_psnr
from mvtools.metrics.ssim import ssim

__all__ = ["VIDEO_METRICS", "frame_scores"]

#: Metric names: ``psnr`` gives Y-, U-, V-PSNR and the 6:1:1 YUV-PSNR, ``ssim`` luma SSIM,
#: ``ivpsnr`` MPEG's IV-PSNR.
VIDEO_METRICS = ("psnr", "ssim", "ivpsnr")


def frame_scores(
    reference: Sequence[np.ndarray],
    test: Sequence[np.ndarray],
    *,
    bits: int,
    metrics: Sequence[str] = VIDEO_METRICS,
) -> dict[str, float]:
    """Scores of a frame against its reference.

    Parameters
    ----------
    reference, test : sequence of ndarray
        The frames' planes (Y, or Y, U, V), of equal shapes.
    bits : int
        Bit depth of the samples.
    metrics : sequence of str
        Names from :data:`VIDEO_METRICS`.

    Returns
    -------
    dict of str to float
        ``Y-PSNR``, ``U-PSNR``, ``V-PSNR``, ``YUV-PSNR`` (three planes only), ``Y-SSIM``,
        ``IV-PSNR``, as the metrics ask, in that order.
    """
    unknown = sorted(set(metrics) - set(VIDEO_METRICS))
    if unknown:
        raise ValueError(f"unknown metric {unknown[0]!r}, they are {', '.join(VIDEO_METRICS)}")
    scores = {}
    if "psnr" in metrics:
        for name, value in zip(
            ("Y-PSNR", "U-PSNR", "V-PSNR"), plane_psnr(reference, test, bits=bits)
        ):
            scores[name] = value
        if len(reference) == 3:
            scores["YUV-PSNR"] = yuv_psnr(reference, test, bits=bits)
    if "ssim" in metrics:
        scores["Y-SSIM"] = ssim(reference[0], test[0], max_value=2**bits - 1)
    if "ivpsnr" in metrics:
        scores["IV-PSNR"] = iv_psnr(reference, test, bits=bits)
    return scores
