"""Temporal improvement of reference depth maps (VSRS ``TemporalImprovementOption``).

Depth estimated frame by frame flickers where the scene stands still, and the flicker
carries into the synthesized view. VSRS's 1D mode therefore smooths, before warping, the
depth of the blocks whose colour has not changed since the previous frame: a recursive
mean of the inverse depths, the moving blocks keeping their own (:class:`TemporalDepthFilter`,
used by :class:`mvtools.synthesis.pipeline.Synthesizer` in 1D mode). Every loop over
pixels is a numba kernel over rows or blocks.
"""

from __future__ import annotations

import cv2
import numba
import numpy as np

__all__ = ["TemporalDepthFilter"]


class TemporalDepthFilter:
    """Temporal smoothing of the depth of static blocks (``TemporalImprovementOption``).

    One filter per reference view, fed its frames in order. A ``block`` x ``block``
    block is static when the mean absolute change of its colour (mean of the three
    channels) since the previous frame is below ``sad_threshold / block**2`` in 8-bit
    code values (VSRS: 4x4 blocks, luma SAD < 100); it counts as moving when any block
    within ``spread`` blocks of it (rows and columns) changed, because depth edges need
    not follow colour edges. In static blocks the inverse depth becomes ``weight``
    times the previous frame's filtered value plus ``1 - weight`` times the current
    one (VSRS: 0.75, on depth values, which are linear in inverse depth); moving blocks
    keep their depth. The first frame, and a frame of another size, pass unchanged.

    Parameters
    ----------
    block : int
    sad_threshold : float
    weight : float
        In [0, 1].
    spread : int
    max_value : float
        Largest code value of the colours (255 for 8 bits): the threshold scales with it.
    """

    def __init__(
        self,
        *,
        block: int = 4,
        sad_threshold: float = 100.0,
        weight: float = 0.75,
        spread: int = 2,
        max_value: float = 255.0,
    ):
        if block < 1 or spread < 0 or not 0 <= weight <= 1 or not max_value > 0:
            raise ValueError(
                f"need block >= 1, spread >= 0, 0 <= weight <= 1, max_value > 0; "
                f"got {block}, {spread}, {weight}, {max_value}"
            )
        self.block = int(block)
        self.mean_threshold = sad_threshold / block**2 * max_value / 255.0
        self.weight = float(weight)
        self.spread = int(spread)
        self._intensity = None  # previous frame's channel mean, (H, W) float32
        self._inverse = None  # previous frame's filtered inverse depth, (H, W)

    def reset(self) -> None:
        """Forget the previous frame."""
        self._intensity = self._inverse = None

    def apply(self, z: np.ndarray, color: np.ndarray) -> np.ndarray:
        """Filtered depth of this frame.

        Parameters
        ----------
        z : ndarray, shape (H, W)
            Positive depths of the reference view.
        color : ndarray, shape (H, W, 3)
            Its texture.

        Returns
        -------
        ndarray of float64, shape (H, W)
        """
        z = np.ascontiguousarray(z, dtype=np.float64)
        color = np.ascontiguousarray(color, dtype=np.float32)
        if z.ndim != 2 or color.shape != z.shape + (3,):
            raise ValueError(f"need z (H, W) and color (H, W, 3), got {z.shape} and {color.shape}")
        first = self._intensity is None or self._intensity.shape != z.shape
        if first:
            self._intensity = np.zeros(z.shape, dtype=np.float32)
            self._inverse = np.empty(z.shape)
        change = _block_change(color, self._intensity, self.block)
        filtered = np.empty_like(z)
        if first:
            _smooth_static(
                z, np.zeros(change.shape, dtype=np.bool_), self.block, 0.0, self._inverse, filtered
            )
        else:
            moving = (change >= self.mean_threshold).astype(np.uint8)
            if self.spread:
                moving = cv2.dilate(
                    moving,
                    np.ones((2 * self.spread + 1,) * 2, np.uint8),
                    borderType=cv2.BORDER_CONSTANT,
                    borderValue=0,
                )
            _smooth_static(z, moving == 0, self.block, self.weight, self._inverse, filtered)
        return filtered


# serial: a few milliseconds a frame, where a second thread costs more CPU than it
# saves time (ten Kendo frames, 1D: 1.39 s of CPU in parallel, 1.30 s serial, same wall)
@numba.njit(cache=True, nogil=True)
def _block_change(color, intensity, block):
    """Mean absolute change of each block's channel mean; ``intensity`` becomes this frame's."""
    height, width = intensity.shape
    rows = (height + block - 1) // block
    columns = (width + block - 1) // block
    change = np.empty((rows, columns))
    for row in range(rows):
        for column in range(columns):
            total = 0.0
            count = 0
            for y in range(row * block, min((row + 1) * block, height)):
                for x in range(column * block, min((column + 1) * block, width)):
                    mean = (color[y, x, 0] + color[y, x, 1] + color[y, x, 2]) / np.float32(3.0)
                    total += abs(mean - intensity[y, x])
                    intensity[y, x] = mean
                    count += 1
            change[row, column] = total / count
    return change


# serial, as _block_change
@numba.njit(cache=True, nogil=True, error_model="numpy")
def _smooth_static(z, static, block, weight, inverse, out):
    """``inverse`` (previous filtered 1/z) becomes this frame's; ``out`` its depth."""
    height, width = z.shape
    for y in range(height):
        for x in range(width):
            current = 1.0 / z[y, x]
            if static[y // block, x // block]:
                current = weight * inverse[y, x] + (1.0 - weight) * current
                out[y, x] = 1.0 / current
            else:
                out[y, x] = z[y, x]
            inverse[y, x] = current
