"""Colour correction of the views of an array by per-channel tables: the working colour
spaces, the tables of every view towards a reference or the average of the views, and
their application to the planes of a frame."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from mvtools.color.lut import LUT_METHODS, apply_lut, average_target, identity_lut
from mvtools.color.space import rgb_to_yuv, upsample_chroma, yuv_to_rgb

__all__ = ["SPACES", "TARGETS", "channel_names", "correct_planes", "view_tables", "working_codes"]

SPACES = ("rgb", "yuv")
TARGETS = ("reference", "average")


def channel_names(space: str, planes: int) -> tuple[str, ...]:
    """``("R", "G", "B")``, ``("Y", "U", "V")`` or ``("Y",)`` for grey pictures."""
    _check_space(space, planes)
    return ("Y",) if planes == 1 else tuple(space.upper())


def _check_space(space: str, planes: int) -> None:
    if space not in SPACES:
        raise ValueError(f"space must be one of {', '.join(SPACES)}, got {space!r}")
    if planes not in (1, 3):
        raise ValueError(f"a frame has 1 or 3 planes, got {planes}")


def working_codes(planes: Sequence[np.ndarray], *, bits: int, space: str) -> np.ndarray:
    """A frame's codes at luma resolution in the space the tables work in.

    ``"rgb"``: BT.601 limited-range RGB (bilinear chroma upsampling). ``"yuv"``: the
    planes themselves, chroma repeated to luma resolution (nearest, so that every
    sample keeps its own code). Grey frames give their luma in either space.

    Returns
    -------
    ndarray, shape (H, W, C), the planes' dtype
    """
    _check_space(space, len(planes))
    if len(planes) == 1:
        return np.asarray(planes[0])[..., None]
    if space == "rgb":
        return yuv_to_rgb(planes, bits=bits)
    return np.stack(upsample_chroma(planes, method="nearest"), axis=-1)


def correct_planes(
    planes: Sequence[np.ndarray], tables: np.ndarray, *, bits: int, space: str, chroma: str
) -> list[np.ndarray]:
    """A frame with its tables applied, as planes of the same layout.

    In ``"yuv"`` every plane takes its own table at its own resolution; in ``"rgb"`` the
    frame goes to RGB, through the tables, and back to YUV with ``chroma`` subsampling.
    """
    _check_space(space, len(planes))
    tables = np.atleast_2d(tables)
    if tables.shape[0] != (1 if len(planes) == 1 else 3):
        raise ValueError(f"{tables.shape[0]} tables for {len(planes)} planes")
    if len(planes) == 1 or space == "yuv":
        return [apply_lut(plane, table) for plane, table in zip(planes, tables)]
    rgb = yuv_to_rgb(planes, bits=bits)
    corrected = np.stack([apply_lut(rgb[..., c], tables[c]) for c in range(3)], axis=-1)
    return list(rgb_to_yuv(corrected, chroma=chroma, bits=bits))


def view_tables(
    samples: Sequence[tuple[np.ndarray, np.ndarray] | None],
    reference: int,
    *,
    target: str = "reference",
    method: str = "correspondences",
    levels: int = 256,
) -> list[np.ndarray]:
    """The tables of every view.

    Parameters
    ----------
    samples : sequence, one entry per view
        ``(view_codes, reference_values)`` of shapes (N, C) and (N, C) for
        ``"correspondences"``, ``(view_codes, reference_codes)`` of shapes (N, C) and
        (M, C) for ``"histograms"``; None for the reference view itself.
    reference : int
        Index of the reference view, whose table is the identity towards itself.
    target : {"reference", "average"}
        Bring every view to the reference, or every view (the reference too) to the
        average colour profile of all views.
    method : {"correspondences", "histograms"}
        :data:`mvtools.color.lut.LUT_METHODS`.
    levels : int
        Codes per channel.

    Returns
    -------
    list of ndarray, each shape (C, levels)
    """
    if target not in TARGETS:
        raise ValueError(f"target must be one of {', '.join(TARGETS)}, got {target!r}")
    if method not in LUT_METHODS:
        raise ValueError(f"method must be one of {', '.join(LUT_METHODS)}, got {method!r}")
    if not 0 <= reference < len(samples) or samples[reference] is not None:
        raise ValueError("samples must hold None at the reference view and pairs elsewhere")
    fit = LUT_METHODS[method]
    channels = next(pair[0].shape[1] for pair in samples if pair is not None)
    tables = [
        identity_lut(channels, levels) if pair is None else fit(*pair, levels=levels)
        for pair in samples
    ]
    return average_target(tables) if target == "average" else tables
