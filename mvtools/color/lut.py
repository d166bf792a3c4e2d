"""Per-channel look-up tables that make one view's colours agree with another's (the chapter's
eq. 1.18): estimated from corresponding samples or from cumulative histograms, made
monotonic and smooth, combined into a common target, and applied to planes.

A table is a float64 array of shape (C, L): entry ``[c, v]`` is the corrected value of
code ``v`` of channel ``c``, for ``L = 2**bits`` codes.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "LUT_METHODS",
    "apply_lut",
    "average_target",
    "compose_luts",
    "fit_lut",
    "histogram_lut",
    "identity_lut",
    "invert_lut",
]

# Fewest samples of a code for its own estimate; sparser codes are interpolated from
# their neighbours (one stray match must not bend the table).
_MIN_SAMPLES = 5


def identity_lut(channels: int, levels: int = 256) -> np.ndarray:
    """The table that changes nothing, shape (channels, levels)."""
    return np.tile(np.arange(levels, dtype=np.float64), (channels, 1))


def _check_samples(source, target, levels):
    source = np.asarray(source)
    target = np.asarray(target, dtype=np.float64)
    if source.ndim == 1:
        source, target = source[:, None], target[:, None]
    if source.ndim != 2 or source.shape != target.shape:
        raise ValueError(
            f"source and target must be (N, C) arrays of one shape, got "
            f"{source.shape} and {target.shape}"
        )
    if levels < 2:
        raise ValueError(f"levels must be at least 2, got {levels}")
    if source.size and (
        source.min() < 0 or source.max() >= levels or not np.issubdtype(source.dtype, np.integer)
    ):
        raise ValueError(f"source must hold integer codes 0..{levels - 1}")
    return source, target


def _pool_adjacent_violators(values: np.ndarray, weights: np.ndarray) -> np.ndarray:
    """The non-decreasing sequence closest to ``values`` in weighted least squares."""
    means, sizes, counts = [], [], []
    for value, weight in zip(values, weights):
        means.append(value)
        sizes.append(weight)
        counts.append(1)
        while len(means) > 1 and means[-2] > means[-1]:
            total = sizes[-2] + sizes[-1]
            merged = (means[-2] * sizes[-2] + means[-1] * sizes[-1]) / total
            count = counts[-2] + counts[-1]
            del means[-1], sizes[-1], counts[-1]
            means[-1], sizes[-1], counts[-1] = merged, total, count
    return np.repeat(means, counts)


def _table_from_points(
    codes: np.ndarray, values: np.ndarray, weights: np.ndarray, levels: int, smoothing: float
) -> np.ndarray:
    """A monotonic, smooth table through weighted (code, value) points.

    Codes between the points are interpolated; beyond the outermost points the table
    continues with the slope of the outer tenth of the samples, then is smoothed by
    a Gaussian of ``smoothing`` codes (which keeps it monotonic) and clipped."""
    if codes.size == 0:
        raise ValueError("no samples to estimate the table from")
    monotonic = _pool_adjacent_violators(values, weights)
    if codes.size == 1:
        return np.clip(np.full(levels, monotonic[0]) + np.arange(levels) - codes[0], 0, levels - 1)
    grid = np.arange(levels, dtype=np.float64)
    table = np.interp(grid, codes, monotonic)
    # Beyond the data the table goes on with the slope of the outer tenth of the samples,
    # fitted with their counts as weights: the last few codes are sparse and noisy.
    share = np.cumsum(weights) / weights.sum()
    for end, beyond, outer in (
        (codes[0], grid < codes[0], share <= 0.1),
        (codes[-1], grid > codes[-1], share >= 0.9),
    ):
        outer[codes == end] = True
        if outer.sum() > 1 and np.ptp(codes[outer]) > 0:
            slope = np.polyfit(codes[outer], monotonic[outer], 1, w=np.sqrt(weights[outer]))[0]
        else:
            slope = 1.0
        table[beyond] = np.interp(end, codes, monotonic) + max(slope, 0.0) * (grid[beyond] - end)
    if smoothing > 0:
        from scipy.ndimage import gaussian_filter1d  # loads SciPy when a table is fitted

        table = gaussian_filter1d(table, smoothing, mode="nearest")
    return np.clip(table, 0.0, levels - 1.0)


def fit_lut(source, target, *, levels: int = 256, smoothing: float = 1.5) -> np.ndarray:
    """Tables from corresponding samples: the corrected value of each code is the
    median target value of the samples with that code.

    Medians ignore the few wrong correspondences that survive a visibility check
    (occlusion borders, specular spots); the table is then made non-decreasing by
    weighted isotonic regression and smoothed, so that codes without samples and the
    ends of the range follow their neighbours.

    Parameters
    ----------
    source : ndarray of int, shape (N,) or (N, C)
        Codes of the view to correct, ``0 .. levels - 1``.
    target : ndarray, shape of ``source``
        The values the same scene points have in the target view.
    levels : keyword-only int
        Codes per channel (256 for 8 bits).
    smoothing : keyword-only float
        Standard deviation, in codes, of the Gaussian that smooths the table; 0 for none.

    Returns
    -------
    ndarray of float64, shape (C, levels)
    """
    source, target = _check_samples(source, target, levels)
    tables = []
    for channel in range(source.shape[1]):
        order = np.argsort(source[:, channel], kind="stable")
        codes = source[order, channel]
        values = target[order, channel]
        starts = np.flatnonzero(np.r_[True, codes[1:] != codes[:-1]])
        counts = np.diff(np.r_[starts, codes.size])
        keep = counts >= _MIN_SAMPLES
        medians = np.array(
            [
                np.median(values[start : start + count])
                for start, count in zip(starts[keep], counts[keep])
            ]
        )
        tables.append(
            _table_from_points(
                codes[starts[keep]].astype(np.float64),
                medians,
                counts[keep].astype(np.float64),
                levels,
                smoothing,
            )
        )
    return np.array(tables)


def histogram_lut(source, target, *, levels: int = 256, smoothing: float = 1.5) -> np.ndarray:
    """Tables that give the source the target's cumulative histogram, per channel.

    For views without correspondences: each code goes where the same fraction of the
    target's samples lies (mid-rank quantiles, so equal histograms give the identity).
    Both sample sets should cover the same part of the scene, e.g. the views' common
    field of view.

    Parameters
    ----------
    source : ndarray of int, shape (N,) or (N, C)
        Samples of the view to correct, ``0 .. levels - 1``.
    target : ndarray of int, shape (M,) or (M, C)
        Samples of the target view (any count).
    levels, smoothing : keyword-only
        As in :func:`fit_lut`.

    Returns
    -------
    ndarray of float64, shape (C, levels)
    """
    source = np.asarray(source)
    target = np.asarray(target)
    if source.ndim == 1:
        source, target = source[:, None], target[:, None]
    if source.ndim != 2 or target.ndim != 2 or source.shape[1] != target.shape[1]:
        raise ValueError(
            f"source and target must be (N, C) and (M, C) arrays, got "
            f"{source.shape} and {target.shape}"
        )
    _check_samples(source, source, levels)
    _check_samples(target, target, levels)
    tables = []
    for channel in range(source.shape[1]):
        source_counts = np.bincount(source[:, channel], minlength=levels).astype(np.float64)
        target_counts = np.bincount(target[:, channel], minlength=levels).astype(np.float64)
        present = source_counts > 0
        # mid-rank fraction of each present source code, read off the target's quantiles
        fractions = (np.cumsum(source_counts) - source_counts / 2.0) / source_counts.sum()
        target_fractions = (np.cumsum(target_counts) - target_counts / 2.0) / target_counts.sum()
        target_codes = np.flatnonzero(target_counts > 0)
        values = np.interp(
            fractions[present], target_fractions[target_codes], target_codes.astype(np.float64)
        )
        tables.append(
            _table_from_points(
                np.flatnonzero(present).astype(np.float64),
                values,
                source_counts[present],
                levels,
                smoothing,
            )
        )
    return np.array(tables)


LUT_METHODS = {"correspondences": fit_lut, "histograms": histogram_lut}


def invert_lut(table: np.ndarray) -> np.ndarray:
    """The inverse of non-decreasing tables, on the same codes, shape (C, L).

    Flat stretches (codes merged by clipping) invert to their middle."""
    table = np.asarray(table, dtype=np.float64)
    codes = np.arange(table.shape[-1], dtype=np.float64)
    inverse = []
    for row in np.atleast_2d(table):
        if np.any(np.diff(row) < 0):
            raise ValueError("a table to invert must be non-decreasing")
        # np.interp needs increasing x: average the codes that share a value
        values, first = np.unique(row, return_index=True)
        last = np.r_[first[1:], row.size] - 1
        inverse.append(np.interp(codes, values, (first + last) / 2.0))
    return np.array(inverse)


def compose_luts(outer: np.ndarray, inner: np.ndarray) -> np.ndarray:
    """``outer(inner(v))`` per channel, linear between codes, shape (C, L)."""
    outer = np.atleast_2d(np.asarray(outer, dtype=np.float64))
    inner = np.atleast_2d(np.asarray(inner, dtype=np.float64))
    if outer.shape != inner.shape:
        raise ValueError(f"tables of shapes {outer.shape} and {inner.shape} do not compose")
    codes = np.arange(outer.shape[1], dtype=np.float64)
    return np.array(
        [np.interp(row_inner, codes, row_outer) for row_outer, row_inner in zip(outer, inner)]
    )


def average_target(tables: list[np.ndarray]) -> list[np.ndarray]:
    """Tables that bring every view to the average colour profile of all the views.

    ``tables[i]`` maps view ``i`` to a common reference (the reference view's own table
    is the identity). A reference value ``r`` is seen as ``tables[i]^-1(r)`` by view
    ``i``; the average profile is their mean ``m(r)``, and view ``i`` is corrected by
    ``m(tables[i](v))`` (the chapter's ref. [30]). The result does not depend on which view was
    the reference, up to interpolation.

    Parameters
    ----------
    tables : list of ndarray, each shape (C, L)

    Returns
    -------
    list of ndarray, each shape (C, L)
    """
    if not tables:
        raise ValueError("no tables to average")
    mean_profile = np.mean([invert_lut(table) for table in tables], axis=0)
    return [compose_luts(mean_profile, table) for table in tables]


def apply_lut(plane: np.ndarray, table: np.ndarray) -> np.ndarray:
    """One channel's table applied to a plane of integer codes, rounded, same dtype.

    Parameters
    ----------
    plane : ndarray of uint8 or uint16, any shape
    table : ndarray, shape (L,)
        ``L`` at least the plane's largest code + 1.
    """
    plane = np.asarray(plane)
    table = np.asarray(table, dtype=np.float64)
    if table.ndim != 1:
        raise ValueError(f"apply one channel's table, shape (L,), got {table.shape}")
    if plane.dtype.kind != "u":
        raise ValueError(f"planes hold unsigned integer codes, got {plane.dtype}")
    if plane.size and plane.max() >= table.size:
        raise ValueError(f"code {plane.max()} is beyond the table's {table.size} entries")
    codes = np.clip(np.round(table), 0, np.iinfo(plane.dtype).max).astype(plane.dtype)
    return codes[plane]
