"""Published test material made ready for scoring: files read (mvtools.io) and the
scoring rules applied (mvtools.metrics). Used by ``mvtools evaluate``, the tests and
the benchmarks, so that every one of them scores a set the same way."""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from mvtools.errors import UsageError
from mvtools.io.middlebury import (MIDDLEBURY_SETS, check_same_size, read_ground_truth,
                                   read_nonoccluded_mask)
from mvtools.metrics.disparity import nonoccluded_from_other_view

__all__ = ["MiddleburyGroundTruth", "load_middlebury_ground_truth", "nonoccluded_pixels"]


@dataclass(frozen=True)
class MiddleburyGroundTruth:
    """Ground truth of a set's left view, ready for scoring.

    Attributes
    ----------
    disparity : ndarray of float32, shape (H, W)
        Disparity in pixels, 0 where unknown.
    known : ndarray of bool, shape (H, W)
    nonoccluded : ndarray of bool, shape (H, W), or None
        Non-occluded known pixels; None when the set defines none.
    """

    disparity: np.ndarray
    known: np.ndarray
    nonoccluded: np.ndarray | None


def nonoccluded_pixels(ground_truth: np.ndarray, known: np.ndarray, *, scale: float,
                       mask_path: str | os.PathLike | None = None,
                       other_view_path: str | os.PathLike | None = None) -> np.ndarray | None:
    """Non-occluded known pixels, from a mask file (2003 sets) or from the other view's
    ground truth (2005 rule); None when neither is given."""
    if mask_path is not None:
        mask = read_nonoccluded_mask(mask_path)
        check_same_size(mask, ground_truth, mask_path)
        return mask & known
    if other_view_path is not None:
        other, _ = read_ground_truth(other_view_path, scale=scale)
        check_same_size(other, ground_truth, other_view_path)
        return nonoccluded_from_other_view(ground_truth, other)
    return None


def load_middlebury_ground_truth(root: str | os.PathLike, name: str) -> MiddleburyGroundTruth:
    """Ground truth, known and non-occluded pixels of one set of :data:`MIDDLEBURY_SETS`.

    Parameters
    ----------
    root : path-like
        The ``middlebury`` data folder (holding ``2001/``, ``2003/``, ...).
    name : str
        Key of :data:`MIDDLEBURY_SETS`.
    """
    if name not in MIDDLEBURY_SETS:
        raise UsageError(f"unknown Middlebury set; known sets: {', '.join(MIDDLEBURY_SETS)}",
                         key=name)
    entry = MIDDLEBURY_SETS[name]
    root = Path(root)
    disparity, known = read_ground_truth(root / entry.ground_truth, scale=entry.scale)
    nonoccluded = nonoccluded_pixels(
        disparity, known, scale=entry.scale,
        mask_path=root / entry.nonoccluded_mask if entry.nonoccluded_mask else None,
        other_view_path=root / entry.right_ground_truth if entry.right_ground_truth else None)
    return MiddleburyGroundTruth(disparity, known, nonoccluded)
