"""Pictures of a calibration: where the corners were found and how far the model misses."""

from __future__ import annotations

import cv2
import numpy as np

__all__ = ["draw_corners"]

_DETECTED = (40, 220, 40)
_ERROR = (255, 40, 40)


def draw_corners(
    image: np.ndarray, detected, reprojected, *, error_scale: float = 20.0
) -> np.ndarray:
    """A camera's capture with the corners of all its captures and their errors drawn.

    The corners of every used capture show how well the captures cover the picture
    (distortion is only measured where corners are); each reprojection error is drawn
    as a line from the detected corner, ``error_scale`` times as long, since sub-pixel
    errors would not show at their own length.

    Parameters
    ----------
    image : ndarray, shape (H, W) or (H, W, 3), uint8
        Background, e.g. the camera's first capture; drawn at half brightness.
    detected, reprojected : sequence of ndarray, each shape (N, 2)
        Per capture, the detected corners and the model's projections of them.
    error_scale : float
        Magnification of the error lines, positive.

    Returns
    -------
    ndarray, shape (H, W, 3), uint8 RGB
    """
    if error_scale <= 0:
        raise ValueError(f"error_scale must be positive, got {error_scale}")
    if len(detected) != len(reprojected):
        raise ValueError(
            f"{len(detected)} detected corner sets but {len(reprojected)} reprojected ones"
        )
    image = np.asarray(image, dtype=np.uint8)
    if image.ndim == 2:
        image = np.repeat(image[..., None], 3, axis=2)
    canvas = np.ascontiguousarray(image // 2)
    # cv2 draws at integer pixels; 4 fractional bits keep sub-pixel positions
    shift, scale = 4, 16.0
    for found, model in zip(detected, reprojected):
        found = np.asarray(found, dtype=np.float64).reshape(-1, 2)
        model = np.asarray(model, dtype=np.float64).reshape(-1, 2)
        ends = found + error_scale * (model - found)
        for start, end in zip(
            np.round(found * scale).astype(int), np.round(ends * scale).astype(int)
        ):
            cv2.circle(canvas, tuple(start), int(3 * scale), _DETECTED, 1, cv2.LINE_AA, shift)
            cv2.line(canvas, tuple(start), tuple(end), _ERROR, 1, cv2.LINE_AA, shift)
    return canvas
