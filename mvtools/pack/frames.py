"""Packing the planes of several views into one frame and restoring them."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from mvtools.io.chroma import CHROMA_FORMATS, CHROMA_SUBSAMPLING, chroma_plane_shape
from mvtools.pack.layout import Layout, Placement

__all__ = ["pack_frame", "unpack_frame"]


def _plane_box(placement: Placement, plane: int, chroma: str) -> tuple[int, int, int, int]:
    """(x, y, width, height) of the placement in plane ``plane`` of the packed frame."""
    if plane == 0:
        return placement.x, placement.y, placement.width, placement.height
    fx, fy = CHROMA_SUBSAMPLING[chroma]
    return (
        placement.x // fx,
        placement.y // fy,
        -(-placement.width // fx),
        -(-placement.height // fy),
    )


def _decimate(plane: np.ndarray, factors: tuple[int, int]) -> np.ndarray:
    """Mean of each ``factors`` block (the last, partial block over what it has)."""
    values = np.asarray(plane, dtype=np.float64)
    for axis, factor in ((1, factors[0]), (0, factors[1])):
        if factor == 1:
            continue
        size = values.shape[axis]
        padded = (
            np.concatenate([values, np.take(values, [-1], axis=axis)], axis=axis)
            if size % 2
            else values
        )
        first = np.take(padded, np.arange(0, padded.shape[axis], 2), axis=axis)
        second = np.take(padded, np.arange(1, padded.shape[axis], 2), axis=axis)
        values = (first + second) / 2.0
    return np.round(values).astype(plane.dtype)


def _interpolate(plane: np.ndarray, factors: tuple[int, int], shape: tuple[int, int]) -> np.ndarray:
    """Back to ``shape``: linear interpolation between decimated samples, each of which
    sits at the centre of the block it averaged."""
    values = np.asarray(plane, dtype=np.float64)
    for axis, factor, size in ((1, factors[0], shape[1]), (0, factors[1], shape[0])):
        if factor == 1:
            continue
        positions = (np.arange(size) - (factor - 1) / 2.0) / factor
        low = np.clip(np.floor(positions).astype(np.intp), 0, values.shape[axis] - 1)
        high = np.clip(low + 1, 0, values.shape[axis] - 1)
        weight = np.clip(positions - low, 0.0, 1.0)
        weight_shape = [1, 1]
        weight_shape[axis] = size
        weight = weight.reshape(weight_shape)
        values = (
            np.take(values, low, axis=axis) * (1 - weight)
            + np.take(values, high, axis=axis) * weight
        )
    return np.round(values).astype(plane.dtype)


def pack_frame(
    layout: Layout, views: Mapping[tuple[str, str], Sequence[np.ndarray]], *, chroma: str, bits: int
) -> list[np.ndarray]:
    """One packed frame.

    Parameters
    ----------
    layout : Layout
    views : mapping of (name, kind) to planes
        Every placement's frame: ``(Y, U, V)`` in the packed frame's ``chroma`` format,
        or ``(Y,)`` (a depth map), whose chroma in the packed frame is mid-grey.
    chroma : keyword-only {"420", "422", "444", "400"}
    bits : keyword-only int

    Returns
    -------
    list of ndarray
        The packed planes; samples outside every view are black (luma 16, chroma
        mid-grey, at 8 bits).
    """
    if chroma not in CHROMA_FORMATS:
        raise ValueError(f"chroma must be one of {', '.join(CHROMA_FORMATS)}, got {chroma!r}")
    dtype = np.uint8 if bits <= 8 else np.uint16
    mid, black = 1 << (bits - 1), 16 << (bits - 8)
    planes = [np.full((layout.height, layout.width), black, dtype)]
    if chroma != "400":
        shape = chroma_plane_shape((layout.height, layout.width), chroma)
        planes += [np.full(shape, mid, dtype), np.full(shape, mid, dtype)]
    for placement in layout.placements:
        source = views[(placement.name, placement.kind)]
        for index, packed in enumerate(planes):
            x, y, width, height = _plane_box(placement, index, chroma)
            if index >= len(source):
                packed[y : y + height, x : x + width] = mid
                continue
            plane = _decimate(np.asarray(source[index]), placement.decimation)
            if plane.shape != (height, width):
                raise ValueError(
                    f"plane {index} of {placement.kind} {placement.name!r} has "
                    f"shape {np.shape(source[index])}, which the layout does not "
                    f"expect for {placement.source_width}x"
                    f"{placement.source_height} {chroma} samples"
                )
            packed[y : y + height, x : x + width] = plane
    return planes


def unpack_frame(
    layout: Layout, planes: Sequence[np.ndarray], *, chroma: str, depth_planes: int = 1
) -> dict[tuple[str, str], list[np.ndarray]]:
    """Every view of a packed frame, at its own size.

    Parameters
    ----------
    layout : Layout
    planes : sequence of ndarray
        The packed frame's planes.
    chroma : keyword-only str
        The packed frame's chroma format (that of the textures).
    depth_planes : keyword-only {1, 3}
        Planes to return for depth maps: their luma only, or with mid-grey chroma.

    Returns
    -------
    dict of (name, kind) to list of planes
    """
    if len(planes) != (1 if chroma == "400" else 3):
        raise ValueError(f"{len(planes)} planes for {chroma} frames")
    if planes[0].shape != (layout.height, layout.width):
        raise ValueError(
            f"the packed frame is {planes[0].shape[1]}x{planes[0].shape[0]}, the "
            f"layout {layout.width}x{layout.height}"
        )
    views = {}
    for placement in layout.placements:
        count = depth_planes if placement.kind == "depth" else len(planes)
        restored = []
        for index in range(count):
            x, y, width, height = _plane_box(placement, index, chroma)
            plane = planes[index][y : y + height, x : x + width]
            if index == 0:
                shape = (placement.source_height, placement.source_width)
            else:
                shape = chroma_plane_shape(
                    (placement.source_height, placement.source_width), chroma
                )
            restored.append(
                _interpolate(plane, placement.decimation, shape)
                if placement.decimation != (1, 1)
                else np.array(plane)
            )
        views[(placement.name, placement.kind)] = restored
    return views
