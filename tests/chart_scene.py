"""A synthetic photograph of a ColorChecker, shared by the chart and colorcorrect tests."""

import cv2
import numpy as np

from mvtools.scene.rigs import ColorMismatch

# The flat chart in units of a patch side: gaps of 0.2 between the patches and a black
# body reaching 0.5 beyond the patch area (6 + 5 * 0.2 by 4 + 3 * 0.2).
GAP, BORDER = 0.2, 0.5
AREA = (6 + 5 * GAP, 4 + 3 * GAP)
BODY, BACKGROUND = 0.08, 0.5
CORNERS = np.array([[52.0, 48.0], [268.0, 34.0], [290.0, 200.0], [38.0, 186.0]])
MISMATCH = ColorMismatch(
    gain=(0.97, 0.92, 1.04), offset=(0.02, -0.015, 0.01), gamma=(0.9, 1.08, 1.12)
)


def render_chart(colours, corners, size=(320, 240), samples=4):
    """Display RGB in [0, 1] of a ColorChecker whose patch area has these image corners
    (top-left, top-right, bottom-right, bottom-left of the chart upright) on a grey
    background: every pixel the mean of samples x samples points mapped exactly to the
    flat chart."""
    flat = np.array([[0, 0], [AREA[0], 0], AREA, [0, AREA[1]]], dtype=np.float64)
    to_flat = np.linalg.inv(cv2.findHomography(flat, np.asarray(corners, np.float64), 0)[0])
    width, height = size
    ys, xs = np.mgrid[0:height, 0:width].astype(np.float64)
    image = np.zeros((height, width, 3))
    for dy in (np.arange(samples) + 0.5) / samples - 0.5:
        for dx in (np.arange(samples) + 0.5) / samples - 0.5:
            point = np.stack([xs + dx, ys + dy, np.ones_like(xs)], axis=-1) @ to_flat.T
            u, v = point[..., 0] / point[..., 2], point[..., 1] / point[..., 2]
            colour = np.full((height, width, 3), BACKGROUND)
            colour[
                (u > -BORDER) & (u < AREA[0] + BORDER) & (v > -BORDER) & (v < AREA[1] + BORDER)
            ] = BODY
            column, row = np.floor(u / (1 + GAP)), np.floor(v / (1 + GAP))
            patch = (
                (u - column * (1 + GAP) < 1)
                & (v - row * (1 + GAP) < 1)
                & (column >= 0)
                & (column < 6)
                & (row >= 0)
                & (row < 4)
            )
            colour[patch] = colours[(row * 6 + column)[patch].astype(int)]
            image += colour
    return image / samples**2


def photograph(colours, corners, *, seed=0):
    """The chart as a camera with :data:`MISMATCH` and noise of 1 code sees it, 8 bits."""
    rng = np.random.default_rng(seed)
    image = MISMATCH.apply(render_chart(colours, corners)) + rng.normal(0, 1 / 255, (240, 320, 3))
    return np.rint(np.clip(image, 0, 1) * 255).astype(np.uint8)
