"""Colour over-segmentation of a view: Felzenszwalb and Huttenlocher's graph-based
merging ("Efficient graph-based image segmentation", IJCV 2004). The segments carry the
disparity planes of :mod:`mvtools.depth.segment`: homogeneous colour regions rarely
straddle a depth edge."""

from __future__ import annotations

import cv2
import numpy as np
from numba import njit

__all__ = ["plane_segments", "segment_image"]


@njit(cache=True, nogil=True)
def _find(parent, node):
    root = node
    while parent[root] != root:
        root = parent[root]
    while parent[node] != root:
        parent[node], node = root, parent[node]
    return root


@njit(cache=True, nogil=True)
def _felzenszwalb(first, second, weight, pixels, scale, min_size):
    # edges in merge order: by increasing weight, ties in their listed order
    parent = np.arange(pixels).astype(np.int32)
    size = np.ones(pixels, np.int32)
    # a component's internal difference plus scale / size: the merge threshold
    threshold = np.full(pixels, scale, np.float64)
    for e in range(first.size):
        a, b = _find(parent, first[e]), _find(parent, second[e])
        if a != b and weight[e] <= threshold[a] and weight[e] <= threshold[b]:
            if size[a] < size[b]:
                a, b = b, a
            parent[b] = a
            size[a] += size[b]
            threshold[a] = weight[e] + scale / size[a]
    # components below min_size join their most similar neighbour
    for e in range(first.size):
        a, b = _find(parent, first[e]), _find(parent, second[e])
        if a != b and (size[a] < min_size or size[b] < min_size):
            if size[a] < size[b]:
                a, b = b, a
            parent[b] = a
            size[a] += size[b]
    labels = np.empty(pixels, np.int64)
    number = np.full(pixels, -1, np.int64)
    count = 0
    for i in range(pixels):
        root = _find(parent, i)
        if number[root] < 0:
            number[root] = count
            count += 1
        labels[i] = number[root]
    return labels


@njit(cache=True, nogil=True)
def _stable_order(keys):
    # Indices that sort non-negative float32 keys, ties in index order: a least-significant
    # digit radix sort of their bit patterns (which order as the values do), two passes
    # of 16 bits, linear where np.argsort(kind="stable") merges.
    bits = keys.view(np.uint32)
    order = np.arange(bits.size).astype(np.int32)
    spare = np.empty_like(order)
    for shift in (0, 16):
        counts = np.zeros(65537, np.int64)
        for i in range(bits.size):
            counts[((bits[i] >> shift) & 0xFFFF) + 1] += 1
        for digit in range(65536):
            counts[digit + 1] += counts[digit]
        for i in range(order.size):
            digit = (bits[order[i]] >> shift) & 0xFFFF
            spare[counts[digit]] = order[i]
            counts[digit] += 1
        order, spare = spare, order
    return order


@njit(cache=True, nogil=True)
def _graph_edges(colour):
    # Each 8-connected edge once: every right neighbour in raster order, then every down,
    # down-right and down-left one; its two pixels' flat indices and Euclidean colour
    # distance, summed over the channels in order in float32.
    rows, cols, channels = colour.shape
    count = rows * (cols - 1) + (rows - 1) * cols + 2 * (rows - 1) * (cols - 1)
    first = np.empty(count, np.int32)
    second = np.empty(count, np.int32)
    weight = np.empty(count, np.float32)
    edge = 0
    for down, across in ((0, 1), (1, 0), (1, 1), (1, -1)):
        for y in range(rows - down):
            for x in range(max(0, -across), cols - max(0, across)):
                total = np.float32(0)
                for channel in range(channels):
                    difference = colour[y, x, channel] - colour[y + down, x + across, channel]
                    total += difference * difference
                first[edge] = y * cols + x
                second[edge] = (y + down) * cols + x + across
                weight[edge] = np.sqrt(total)
                edge += 1
    return first, second, weight


@njit(cache=True, nogil=True)
def _in_merge_order(first, second, weight):
    # the edges by increasing weight, ties in their listed order, to be read one after
    # the other
    order = _stable_order(weight)
    return first[order], second[order], weight[order]


def segment_image(
    image: np.ndarray, *, scale: float = 300.0, min_size: int = 40, sigma: float = 0.8
) -> np.ndarray:
    """Over-segmentation by Felzenszwalb and Huttenlocher's graph-based merging.

    Pixels are nodes of an 8-connected graph weighted by Euclidean colour distance;
    edges are visited by increasing weight and join two components when the weight does
    not exceed either's largest internal edge plus ``scale / size``.

    Parameters
    ----------
    image : ndarray, shape (H, W, 3) or (H, W)
        Colour or grey view.
    scale : keyword-only float
        Larger values give larger segments (colour units, 0..255 per channel).
    min_size : keyword-only int
        Segments smaller than this join their most similar neighbour.
    sigma : keyword-only float
        Gaussian smoothing before the colour differences; 0 for none.

    Returns
    -------
    ndarray of int64, shape (H, W)
        Labels ``0 .. n - 1``, numbered in raster order of their first pixel;
        deterministic for a given image.
    """
    image = np.asarray(image, np.float32)
    if image.ndim not in (2, 3) or (image.ndim == 3 and image.shape[2] != 3):
        raise ValueError(f"image must be (H, W) or (H, W, 3), got {image.shape}")
    if scale <= 0 or min_size < 1 or sigma < 0:
        raise ValueError(
            f"need scale > 0, min_size >= 1, sigma >= 0, got {scale}, {min_size}, {sigma}"
        )
    colour = image[:, :, None] if image.ndim == 2 else image
    if sigma > 0:
        colour = cv2.GaussianBlur(colour, (0, 0), sigma).reshape(colour.shape)
    rows, cols = colour.shape[:2]
    first, second, weight = _in_merge_order(*_graph_edges(np.ascontiguousarray(colour)))
    return _felzenszwalb(first, second, weight, rows * cols, float(scale), int(min_size)).reshape(
        rows, cols
    )


def plane_segments(view: np.ndarray) -> np.ndarray:
    """The over-segmentation the plane steps fit planes to: :func:`segment_image` with
    scale 120 and segments of at least 20 pixels, fine enough that a segment rarely
    straddles a depth edge."""
    return segment_image(view, scale=120.0, min_size=20)
