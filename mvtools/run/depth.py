"""Depth estimation runs: a depth video of a center view from its neighbours and their
cameras, frame by frame, and the disparity map of a rectified pair of pictures."""

from __future__ import annotations

import logging
import time
from collections.abc import Sequence

import numpy as np

from mvtools.depth import estimate_disparity
from mvtools.depth.ders import DersEstimator, Neighbour
from mvtools.depth.options import PAIR_METHOD, VIEWS_METHOD, DepthOptions
from mvtools.errors import DataError
from mvtools.geometry.camera import Camera
from mvtools.geometry.depth import DepthCoding
from mvtools.io.depth_sidecar import DepthSidecar
from mvtools.io.images import write_image
from mvtools.io.yuv import VideoReader, VideoWriter, frame_from_luma
from mvtools.run.stream import ProgressCallback, stream_frames
from mvtools.synthesis.working import to_working

__all__ = [
    "depth_estimator",
    "disparity_png_values",
    "estimate_depth_video",
    "estimate_pair_disparity",
]

LOG = logging.getLogger(__name__)

_PNG_MAX = np.iinfo(np.uint16).max


def depth_estimator(
    center: Camera, neighbours: Sequence[Neighbour], options: DepthOptions, *, bits: int
) -> tuple[DersEstimator, DepthCoding]:
    """The estimator of the center view's depth and the coding of its depth values in
    ``bits``-bit samples; a ValueError for options the cameras cannot use."""
    estimator = DersEstimator(options, center, neighbours, method=options.method or VIEWS_METHOD)
    return estimator, DepthCoding(estimator.depth_range, bits, depth_type=options.depth_type)


def estimate_depth_video(
    views: Sequence[VideoReader],
    *,
    center: Camera,
    neighbours: Sequence[Neighbour],
    options: DepthOptions,
    writer: VideoWriter,
    frames: range,
    progress: ProgressCallback | None = None,
    earlier_progress: ProgressCallback | None = None,
) -> DepthSidecar:
    """Write the depth of frames ``frames`` of the center view, estimated from its
    neighbours (:class:`mvtools.depth.ders.DersEstimator`).

    Parameters
    ----------
    views : sequence of VideoReader
        The center view's video, then each neighbour's, in colour (4:2:0, 4:2:2 or 4:4:4).
    center : Camera
    neighbours : sequence of Neighbour
        The neighbours' cameras, in the order of ``views[1:]``.
    options : DepthOptions
    writer : VideoWriter
        The depth video, 4:2:0 (chroma 128) or 4:0:0, whose bit depth codes the values.
    frames : range
        Frames read and written (step 1).
    progress, earlier_progress : callable (done, total), optional
        Called after each frame written, and after each earlier frame estimated
        unwritten: with TemporalEnhancement a run from a frame other than a refresh
        frame first estimates the frames from the last refresh frame on, so that its
        frames equal those of a run from that frame.

    Returns
    -------
    DepthSidecar
        What the depth values mean, for the sidecar.
    """
    depth_format = writer.format
    estimator, coding = depth_estimator(center, neighbours, options, bits=depth_format.bits)
    for reader in views:
        if reader.format.chroma == "400":
            raise DataError(
                "a view needs colour planes, this video is grey (4:0:0)", path=reader.path
            )
    bits = [reader.format.bits for reader in views]

    def depth(index: int, *planes) -> np.ndarray:
        if estimator.fresh_frame(index) == index:
            estimator.refresh()
        rgb = [_rgb_8bit_scale(frame, sample) for frame, sample in zip(planes, bits)]
        return estimator.frame(rgb[0], rgb[1:])

    first = estimator.fresh_frame(frames.start)
    if first < frames.start:
        LOG.warning(
            "estimating frames %d to %d first, unwritten: TemporalEnhancement "
            "carries depth from frame %d on (TemporalRefreshPeriod %d)",
            first,
            frames.start - 1,
            first,
            options.temporal_refresh_period,
        )
        stream_frames(range(first, frames.start), depth, readers=views, progress=earlier_progress)
    stream_frames(
        frames,
        lambda index, *planes: [
            frame_from_luma(depth_format, coding.values(depth(index, *planes)))
        ],
        readers=views,
        writers=[writer],
        progress=progress,
    )
    znear, zfar = estimator.depth_range
    return DepthSidecar(
        nearest=znear,
        farthest=zfar,
        depth_type=options.depth_type,
        camera=center.name,
        pix_fmt=depth_format.pix_fmt,
        width=depth_format.width,
        height=depth_format.height,
    )


def _rgb_8bit_scale(planes, bits: int) -> np.ndarray:
    """A YUV frame as (H, W, 3) float32 RGB on an 8-bit scale (the matching costs' scale)."""
    rgb = to_working(planes, color_space=1, bits=bits)
    return rgb / np.float32(1 << (bits - 8)) if bits > 8 else rgb


def estimate_pair_disparity(
    left: np.ndarray,
    right: np.ndarray,
    *,
    options: DepthOptions,
    pfm: str,
    png: str | None = None,
    png_scale: float = 4.0,
) -> np.ndarray:
    """Estimate the disparity of a rectified pair (:func:`mvtools.depth.estimate_disparity`)
    and write it as PFM (float pixels, inf where unknown) and, if ``png`` is given, as a
    16-bit PNG of :func:`disparity_png_values`.

    Parameters
    ----------
    left, right : ndarray, shape (H, W, 3) uint8
        The rectified pictures.
    options : DepthOptions
        The search range is ``options.minimum_value_of_disparity_search_range`` to
        ``options.maximum_value_of_disparity_search_range``.
    pfm, png : path
    png_scale : float
        PNG value / scale = disparity in pixels.

    Returns
    -------
    ndarray of float32, shape (H, W)
        The disparity, NaN where unknown.
    """
    start = time.perf_counter()
    disparity = estimate_disparity(
        left,
        right,
        max_disparity=options.maximum_value_of_disparity_search_range,
        min_disparity=options.minimum_value_of_disparity_search_range,
        method=options.method or PAIR_METHOD,
        cost=options.cost,
        subpixel=options.subpixel,
        segment_planes=options.segment_planes,
        segmentation=options.segmentation,
        view=options.view,
    )
    known = np.isfinite(disparity)
    LOG.info(
        "disparity estimated in %.2f s, %.1f %% of the pixels unknown",
        time.perf_counter() - start,
        100.0 * (1.0 - known.mean()),
    )
    write_image(pfm, np.where(known, disparity, np.inf).astype(np.float32))
    LOG.info("wrote %s", pfm)
    if png is not None:
        write_image(png, disparity_png_values(disparity, scale=png_scale))
        LOG.info("wrote %s (disparity * %g)", png, png_scale)
    return disparity


def disparity_png_values(disparity: np.ndarray, *, scale: float) -> np.ndarray:
    """16-bit PNG samples of a disparity map: ``round(disparity * scale)``, 0 where unknown.

    Parameters
    ----------
    disparity : ndarray of float, shape (H, W)
        Disparities in pixels, NaN or infinite where unknown, within
        ``[0, 65535 / scale]``.
    scale : float
        File value / scale = disparity in pixels.

    Returns
    -------
    ndarray of uint16, shape (H, W)

    Examples
    --------
    >>> disparity_png_values(np.array([[0.0, 1.25, np.nan]]), scale=4).tolist()
    [[0, 5, 0]]
    """
    known = np.isfinite(disparity)
    values = np.round(np.where(known, disparity, 0.0) * scale)
    return np.clip(values, 0, _PNG_MAX).astype(np.uint16)
