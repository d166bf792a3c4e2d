"""Structural similarity (SSIM) of two planes.

Z. Wang, A. C. Bovik, H. R. Sheikh and E. P. Simoncelli, "Image quality
assessment: from error visibility to structural similarity", IEEE Transactions on
Image Processing 13(4):600-612, 2004.
"""

from __future__ import annotations

import numpy as np

from mvtools.metrics.psnr import plane_pair

WINDOW_SIZE = 11
WINDOW_SIGMA = 1.5
K1 = 0.01
K2 = 0.03


def ssim(ref: np.ndarray, test: np.ndarray, *, max_value: float) -> float:
    """Mean SSIM of two planes, as in Wang et al. 2004.

    Local statistics use the paper's 11x11 Gaussian window (sigma 1.5,
    normalised to sum 1)::

        SSIM(x, y) = (2 mu_x mu_y + C1) (2 sigma_xy + C2)
                     / ((mu_x^2 + mu_y^2 + C1) (sigma_x^2 + sigma_y^2 + C2))

    with ``C1 = (K1 L)^2``, ``C2 = (K2 L)^2``, ``K1 = 0.01``, ``K2 = 0.03`` and
    ``L = max_value``. As in the authors' reference code (``ssim_index.m``,
    ``filter2(..., 'valid')``) only windows lying entirely inside the image are
    used, so the map is ``(H - 10, W - 10)``; the image is not downsampled first.
    Computation in float64.

    Parameters
    ----------
    ref, test : ndarray, shape (H, W)
        Planes of any numeric dtype, at least 11x11.
    max_value : float
        Dynamic range ``L`` (``2**bits - 1`` for integer samples).

    Returns
    -------
    float
        Mean of the SSIM map; 1.0 for identical planes.
    """
    ref, test = plane_pair(ref, test, max_value)
    if min(ref.shape) < WINDOW_SIZE:
        raise ValueError(
            f"SSIM needs planes of at least {WINDOW_SIZE}x{WINDOW_SIZE}, "
            f"got {ref.shape[1]}x{ref.shape[0]}"
        )
    # imported here, so that importing the metrics does not load OpenCV
    import cv2

    x = ref.astype(np.float64)
    y = test.astype(np.float64)
    kernel = cv2.getGaussianKernel(WINDOW_SIZE, WINDOW_SIGMA, cv2.CV_64F)
    half = WINDOW_SIZE // 2

    def local_mean(image: np.ndarray) -> np.ndarray:
        # Any border mode works: the cropped "valid" part never reads it.
        filtered = cv2.sepFilter2D(image, cv2.CV_64F, kernel, kernel, borderType=cv2.BORDER_REFLECT)
        return filtered[half:-half, half:-half]

    mu_x = local_mean(x)
    mu_y = local_mean(y)
    var_x = local_mean(x * x) - mu_x * mu_x
    var_y = local_mean(y * y) - mu_y * mu_y
    cov_xy = local_mean(x * y) - mu_x * mu_y
    c1 = (K1 * max_value) ** 2
    c2 = (K2 * max_value) ** 2
    ssim_map = (
        (2 * mu_x * mu_y + c1)
        * (2 * cov_xy + c2)
        / ((mu_x * mu_x + mu_y * mu_y + c1) * (var_x + var_y + c2))
    )
    return float(ssim_map.mean())
