"""Middlebury stereo ground truth and the table of the published sets.

Ground-truth disparity maps are 8-bit PGM/PNG files holding ``disparity * scale``
with 0 meaning "unknown" (Tsukuba: scale 16, Venus: 8, Teddy/Cones: 4, the
third-size 2005 sets: 3, Aloe: 1); PFM maps (2014 sets) hold pixels with ``inf``
for unknown and are read with ``scale=1``.

Scoring protocol (``../shared/data/README.md``): a map is scored over all pixels
with known ground truth ("all") and over the non-occluded ones ("nonocc"); no
extra border is excluded (the 2001 Tsukuba ground truth already marks its
18-pixel border unknown). Non-occluded pixels come from ``occl.png`` for the 2003
sets (non-zero = non-occluded) and, for the 2005 sets, from the other view's
ground truth (:func:`mvtools.metrics.disparity.nonoccluded_from_other_view`).

Cite the papers of ``middlebury/MIDDLEBURY_TERMS.txt`` when using the data:
Scharstein & Szeliski IJCV 2002 (2001 sets), CVPR 2003 (2003 sets); Scharstein &
Pal CVPR 2007 or Hirschmueller & Scharstein CVPR 2007 (2005 and 2006 sets).
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from mvtools.errors import DataError, UsageError
from mvtools.io.images import read_image

__all__ = [
    "MIDDLEBURY_SETS",
    "MiddleburySet",
    "check_same_size",
    "middlebury_set_for",
    "read_ground_truth",
    "read_nonoccluded_mask",
]


@dataclass(frozen=True)
class MiddleburySet:
    """One stereo pair and how to score it.

    Paths are relative to the ``middlebury`` data folder (``../shared/data/middlebury``).

    Attributes
    ----------
    name : str
    left, right : str
        Left and right images (the ground truth belongs to the left one).
    ground_truth : str
        Left-view ground-truth disparity file.
    scale : float
        File value / scale = disparity in pixels.
    disparities : int or None
        Number of disparity levels of the evaluation protocol (None: not stated).
    nonoccluded_mask : str or None
        Mask file, non-zero = non-occluded (2003 sets).
    right_ground_truth : str or None
        Right-view ground truth, from which the non-occluded pixels are derived
        (2005 sets).
    """

    name: str
    left: str
    right: str
    ground_truth: str
    scale: float
    disparities: int | None = None
    nonoccluded_mask: str | None = None
    right_ground_truth: str | None = None


def _set_2005(scene: str) -> MiddleburySet:
    return MiddleburySet(
        scene,
        f"2005/{scene}/view1.png",
        f"2005/{scene}/view5.png",
        f"2005/{scene}/disp1.png",
        3,
        80,
        right_ground_truth=f"2005/{scene}/disp5.png",
    )


MIDDLEBURY_SETS: dict[str, MiddleburySet] = {
    s.name: s
    for s in (
        MiddleburySet(
            "tsukuba",
            "2001/tsukuba/tsukuba3.png",
            "2001/tsukuba/tsukuba4.png",
            "2001/tsukuba/disp3.pgm",
            16,
            16,
        ),
        MiddleburySet(
            "venus", "2001/venus/im2.png", "2001/venus/im6.png", "2001/venus/disp2.pgm", 8, 32
        ),
        MiddleburySet(
            "teddy",
            "2003/teddy/im2.png",
            "2003/teddy/im6.png",
            "2003/teddy/disp2.png",
            4,
            64,
            nonoccluded_mask="2003/teddy/occl.png",
        ),
        MiddleburySet(
            "cones",
            "2003/cones/im2.png",
            "2003/cones/im6.png",
            "2003/cones/disp2.png",
            4,
            64,
            nonoccluded_mask="2003/cones/occl.png",
        ),
        _set_2005("Art"),
        _set_2005("Dolls"),
        _set_2005("Moebius"),
        MiddleburySet(
            "aloe", "2006/aloe/aloeL.jpg", "2006/aloe/aloeR.jpg", "2006/aloe/aloeGT.png", 1
        ),
    )
}


def read_ground_truth(path: str | os.PathLike, *, scale: float) -> tuple[np.ndarray, np.ndarray]:
    """Read a ground-truth disparity map.

    Parameters
    ----------
    path : path-like
        Single-channel PGM/PNG (8 or 16 bit) or PFM file.
    scale : float
        File value / scale = disparity in pixels.

    Returns
    -------
    disparity : ndarray of float32, shape (H, W)
        Disparity in pixels; 0 where unknown.
    known : ndarray of bool, shape (H, W)
        Pixels with known ground truth (file value finite and non-zero).

    Raises
    ------
    UsageError
        Missing file, or a scale that is not positive.
    DataError
        A file that is not a single-channel image.
    """
    if not scale > 0:
        raise UsageError(
            f"the ground-truth scale must be positive, got {scale}", path=path, key="scale"
        )
    values = read_image(path)
    if values.ndim != 2:
        raise DataError(
            f"a ground-truth disparity map has one channel, this image has {values.shape[2]}",
            path=path,
        )
    known = np.isfinite(values) & (values != 0)
    disparity = np.where(known, values.astype(np.float64) / scale, 0.0).astype(np.float32)
    return disparity, known


def read_nonoccluded_mask(path: str | os.PathLike) -> np.ndarray:
    """Read a non-occlusion mask (e.g. ``occl.png``): non-zero = non-occluded.

    Returns
    -------
    ndarray of bool, shape (H, W)
    """
    return read_image(path, grayscale=True) != 0


def middlebury_set_for(ground_truth_path: str | os.PathLike) -> MiddleburySet | None:
    """The set of :data:`MIDDLEBURY_SETS` whose ground-truth file this is, if any."""
    posix = Path(ground_truth_path).resolve().as_posix()
    for entry in MIDDLEBURY_SETS.values():
        if posix.endswith("/" + entry.ground_truth):
            return entry
    return None


def check_same_size(image: np.ndarray, ground_truth: np.ndarray, path: str | os.PathLike) -> None:
    """DataError unless a mask or map read from ``path`` has the ground truth's size."""
    if image.shape != ground_truth.shape:
        raise DataError(
            f"size {image.shape[1]}x{image.shape[0]} differs from the ground "
            f"truth's {ground_truth.shape[1]}x{ground_truth.shape[0]}",
            path=path,
        )
