"""Depth estimation runs, the run functions of ``mvtools estimate-depth``.

:func:`estimate_depth_video` writes the depth video of a center view estimated from its
neighbours' videos and cameras, frame by frame, from opened readers and a writer;
:func:`estimate_depth_config` does so for the DERS configuration a file describes, and
:func:`estimate_depth_loaded` for a configuration already loaded, with the program's
further views. :func:`estimate_pair_disparity` gives the disparity map of a rectified
pair of pictures and writes it on request, :func:`estimate_views_disparity` that of one
view of a linear array of pictures. The estimators
(:class:`mvtools.depth.ders.DersEstimator`, :func:`mvtools.depth.estimate_disparity`)
are imported when a run starts, so this module is cheap to import.
"""

from __future__ import annotations

import contextlib
import logging
import os
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from mvtools.depth.options import DEFAULT_METHOD, DepthOptions
from mvtools.errors import ConfigError, DataError, UsageError, at_fault
from mvtools.geometry.camera import Camera
from mvtools.geometry.depth import DepthCoding
from mvtools.io.atomic import output_folder_exists
from mvtools.io.depth_sidecar import (
    SIDECAR_WHAT,
    DepthSidecar,
    depth_sidecar_path,
    write_depth_sidecar,
)
from mvtools.io.guard import check_output
from mvtools.io.images import read_image, write_image
from mvtools.io.loaded_config import LoadedConfig, load_config, video_format_for
from mvtools.io.yuv import (
    VideoReader,
    VideoWriter,
    YuvFormat,
    format_from_name,
    frame_from_luma,
    open_video,
    open_writer,
)
from mvtools.params import DersParams
from mvtools.run.stream import ProgressCallback, stream_frames
from mvtools.synthesis.working import to_working

LOG = logging.getLogger(__name__)

#: Disparity-map PNG value / scale = disparity in pixels: quarter pixels, as the
#: Middlebury 2003 ground truth (Teddy, Cones) stores them.
DEFAULT_PNG_SCALE = 4.0
_PNG_MAX = np.iinfo(np.uint16).max

#: Neighbour sides that MatchDirection matches.
_DIRECTIONS = {1: ("left",), 2: ("right",), 3: ("left", "right")}


def depth_options(params: DersParams) -> DepthOptions:
    """The algorithm options that DERS parameters ask for."""
    return DepthOptions(
        method=params.method,
        minimum_value_of_disparity_search_range=params.minimum_value_of_disparity_search_range,
        maximum_value_of_disparity_search_range=params.maximum_value_of_disparity_search_range,
        depth_type=params.depth_type,
        minimum_value_of_disparity_range=params.minimum_value_of_disparity_range,
        maximum_value_of_disparity_range=params.maximum_value_of_disparity_range,
        depth_range=params.depth_range,
        search_depth_range=params.search_depth_range,
        number_of_depth_steps=params.number_of_depth_steps,
        baseline_basis=params.baseline_basis,
        search_level=params.search_level,
        smoothing_coefficient=params.smoothing_coefficient,
        precision=params.precision,
        vertical_precision=params.vertical_precision,
        filter=params.filter,
        matching_method=params.matching_method,
        matching_block=params.matching_block,
        soft_distance_coeff=params.soft_distance_coeff,
        soft_color_coeff=params.soft_color_coeff,
        soft_block_width=params.soft_block_width,
        soft_block_height=params.soft_block_height,
        image_segmentation=bool(params.image_segmentation),
        temporal_enhancement=bool(params.temporal_enhancement),
        threshold=params.threshold,
        temporal_refresh_period=params.temporal_refresh_period,
        view_combination=params.view_combination,
    )


# --------------------------------------------------------------------------- views and cameras


def estimate_depth_video(
    views: Sequence[VideoReader],
    *,
    center: Camera,
    neighbours: Sequence,
    options: DepthOptions,
    writer: VideoWriter,
    frames: range | None = None,
    sidecar: str | os.PathLike | None = None,
    progress: ProgressCallback | None = None,
    earlier_progress: ProgressCallback | None = None,
) -> DepthSidecar:
    """Estimate the depth of the center view in every frame of ``frames`` and write it.

    One frame of each view is in memory at a time. With TemporalEnhancement, whose
    depth can come from any earlier frame, a run from a frame other than one estimated
    afresh (:meth:`DersEstimator.fresh_frame <mvtools.depth.ders.DersEstimator.fresh_frame>`)
    first estimates, unwritten, the frames from that one on, so a chunk of a run gives
    the bytes of the whole run.

    Parameters
    ----------
    views : sequence of VideoReader
        The center view's video, then each neighbour's, in colour (4:2:0, 4:2:2 or
        4:4:4); or objects with ``format``, ``path``, ``len()`` and ``read(index)``.
    center : Camera
    neighbours : sequence of Neighbour
        The neighbours' cameras (:class:`mvtools.depth.ders.Neighbour`), in the order
        of ``views[1:]``.
    options : DepthOptions
    writer : VideoWriter
        Gets the depth video: an object with ``format`` (4:2:0, whose chroma is 128, or
        4:0:0; its bit depth codes the values) and ``write(planes)``.
    frames : range, optional
        Frames read and written; default every frame all the views have.
    sidecar : path, optional
        Where to write the depth values' description
        (:func:`mvtools.io.depth_sidecar.write_depth_sidecar`), after the last frame.
    progress, earlier_progress : callable, optional
        ``progress(done, total)`` after each frame written, and after each earlier
        frame estimated unwritten.

    Returns
    -------
    DepthSidecar
        What the depth values mean.

    Raises
    ------
    DataError
        A grey (4:0:0) view.
    ValueError
        Options or cameras the estimator cannot use (:class:`DersEstimator
        <mvtools.depth.ders.DersEstimator>`).
    """
    from mvtools.depth.ders import DersEstimator

    depth_format = writer.format
    estimator = DersEstimator(options, center, neighbours, method=options.method or DEFAULT_METHOD)
    coding = DepthCoding(estimator.depth_range, depth_format.bits, depth_type=options.depth_type)
    znear, zfar = estimator.depth_range
    for reader in views:
        if reader.format.chroma == "400":
            raise DataError(
                "a view needs colour planes, this video is grey (4:0:0)", path=reader.path
            )
    if frames is None:
        frames = range(min(len(reader) for reader in views))
    LOG.info(
        "estimating the depth of %s from %s (%s, %d planes), %d frame%s from frame %d",
        center.name,
        " and ".join(n.camera.name for n in neighbours),
        estimator.method,
        estimator.inverse_depths.size,
        len(frames),
        "s" if len(frames) != 1 else "",
        frames.start,
    )
    LOG.info(
        "depth values mean NearestDepthValue %.6f FarthestDepthValue %.6f (%d-bit%s)",
        znear,
        zfar,
        depth_format.bits,
        "" if sidecar is None else f", {sidecar}",
    )
    bits = [reader.format.bits for reader in views]

    def depth(index: int, *planes) -> np.ndarray:
        if estimator.fresh_frame(index) == index:
            estimator.refresh()
        rgb = [_rgb_8bit_scale(frame, sample_bits) for frame, sample_bits in zip(planes, bits)]
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
    description = DepthSidecar(
        nearest=znear,
        farthest=zfar,
        depth_type=options.depth_type,
        camera=center.name,
        pix_fmt=depth_format.pix_fmt,
        width=depth_format.width,
        height=depth_format.height,
    )
    if sidecar is not None:
        write_depth_sidecar(sidecar, description)
    return description


def _rgb_8bit_scale(planes, bits: int) -> np.ndarray:
    """A YUV frame as (H, W, 3) float32 RGB on an 8-bit scale (the matching costs' scale)."""
    rgb = to_working(planes, color_space=1, bits=bits)
    return rgb / np.float32(1 << (bits - 8)) if bits > 8 else rgb


# --------------------------------------------------------------------------- configurations


@dataclass(frozen=True)
class FurtherView:
    """A neighbour view beyond the configuration's left and right: its camera, its
    video, and the option that named them, for error messages."""

    camera: Camera
    video: Path
    key: str


def estimate_depth_config(
    config: str | os.PathLike,
    *,
    overrides: Mapping[str, Any] | None = None,
    data_dirs: Sequence[str | os.PathLike] = (),
    output: str | os.PathLike | None = None,
    depth_bits: int | None = None,
    progress: ProgressCallback | None = None,
) -> dict[str, Path]:
    """Estimate the depth video a DERS configuration describes, as ``mvtools
    estimate-depth CONFIG`` does.

    Parameters
    ----------
    config : path
        A DERS configuration file, read unmodified.
    overrides : mapping, optional
        Parameters that replace the file's, by :class:`mvtools.params.DersParams`
        field name (``{"start_frame": 2, "method": "bp"}``), as the program's options
        give them.
    data_dirs : sequence of path
        Further folders where the input files are looked for.
    output : path, optional
        The depth video (default: the configuration's ``FileOutputDepthMapImage``).
    depth_bits : {8, 16}, optional
        As :func:`estimate_depth_loaded`.
    progress : callable, optional
        ``progress(done, total)`` after each frame written.

    Returns
    -------
    dict of str to Path
        The files written: ``"depth"`` and ``"sidecar"``.

    Raises
    ------
    UsageError, ConfigError, DataError
        As the program: a bad configuration or parameter, damaged or inconsistent data.
        Nothing is written then.
    """
    options = dict(overrides or {})
    if output is not None:
        options["file_output_depth_map_image"] = os.fspath(output)
    loaded = load_config(DersParams, config, options=options, data_dirs=data_dirs)
    return estimate_depth_loaded(
        loaded, config_path=Path(config), depth_bits=depth_bits, progress=progress
    )


def estimate_depth_loaded(
    loaded: LoadedConfig,
    *,
    config_path: Path,
    further_views: Sequence[FurtherView] = (),
    depth_bits: int | None = None,
    progress: ProgressCallback | None = None,
    earlier_progress: ProgressCallback | None = None,
) -> dict[str, Path]:
    """Estimate the depth video of the center view of a loaded DERS configuration
    (:func:`mvtools.io.loaded_config.load_config`), from the neighbours MatchDirection
    selects and ``further_views``.

    Every input is opened before any output, and no output may name an input; the
    outputs are written atomically (nothing appears unless the whole run succeeds).

    Parameters
    ----------
    loaded : LoadedConfig
        Of :class:`mvtools.params.DersParams`.
    config_path : Path
        The configuration file, named in the errors of its cameras and ranges.
    further_views : sequence of FurtherView
        Views matched besides the configuration's left and right.
    depth_bits : {8, 16}, optional
        The depth video's format when its name does not give it: 8-bit 4:2:0
        (default) or 16-bit 4:0:0; when the name gives it, the two must agree.
    progress, earlier_progress : callable, optional
        As :func:`estimate_depth_video`.

    Returns
    -------
    dict of str to Path
        The files written: ``"depth"`` and ``"sidecar"`` (the depth video's name with
        ``.json`` added).
    """
    from mvtools.depth.ders import Neighbour
    from mvtools.depth.stereo import METHODS

    params = loaded.params
    if params.method not in METHODS:
        raise loaded.entry("method").error(
            f"method {params.method!r} is for stereo pairs; DERS mode methods: {', '.join(METHODS)}"
        )
    if params.file_camera_parameter == "":
        raise loaded.entry("file_camera_parameter").error("no camera parameter file given")
    if "center_camera_name" not in loaded.cameras:
        raise loaded.entry("center_camera_name").error("no camera name given")
    sides = _matched_sides(loaded, further=bool(further_views))
    fields = ["file_center_view_image"] + [f"file_{side}_view_image" for side in sides]
    for field in fields:
        if field not in loaded.inputs:
            raise loaded.entry(field).error("no file given")
    size = (params.source_width, params.source_height)
    # (path, format) of every view read, the center first, then the neighbours in order
    videos = [(loaded.inputs[field], loaded.video_format(field)) for field in fields]
    neighbours = [Neighbour(loaded.cameras[f"{side}_camera_name"], side) for side in sides]
    for view in further_views:
        videos.append((view.video, video_format_for(view.video, size, key=view.key)))
        neighbours.append(Neighbour(view.camera))
    if "file_output_depth_map_image" not in loaded.outputs:
        raise loaded.entry("file_output_depth_map_image").error(
            "no output file given (or -o)", UsageError
        )
    target = loaded.outputs["file_output_depth_map_image"]
    sidecar = depth_sidecar_path(target)
    depth_format = _depth_format(target, size, depth_bits)
    with contextlib.ExitStack() as stack:
        readers = [stack.enter_context(open_video(path, fmt)) for path, fmt in videos]
        # Every input is now open, so the run's guard knows it: an output that names
        # one is refused before any work.
        check_output(target)
        check_output(sidecar, SIDECAR_WHAT)
        frames = loaded.frame_range(readers)
        writer = stack.enter_context(open_writer(target, depth_format))
        with at_fault(ConfigError, path=config_path):
            estimate_depth_video(
                readers,
                center=loaded.cameras["center_camera_name"],
                neighbours=neighbours,
                options=depth_options(params),
                writer=writer,
                frames=frames,
                sidecar=sidecar,
                progress=progress,
                earlier_progress=earlier_progress,
            )
    return {"depth": target, "sidecar": sidecar}


def _matched_sides(loaded: LoadedConfig, *, further: bool) -> list[str]:
    """The neighbour sides to match: named in the configuration and asked for by
    MatchDirection; none is an error unless ``further`` views are given."""
    params = loaded.params
    wanted = _DIRECTIONS[params.match_direction]
    named = [side for side in ("left", "right") if f"{side}_camera_name" in loaded.cameras]
    if not named and not further:
        raise loaded.entry("left_camera_name").error(
            "no neighbour view: give LeftCameraName and/or RightCameraName"
        )
    if params.match_direction != 3 and wanted[0] not in named and named:
        raise loaded.entry("match_direction").error(
            f"MatchDirection {params.match_direction} matches the {wanted[0]} view, but "
            f"{wanted[0].title()}CameraName is not given"
        )
    return [side for side in named if side in wanted]


def _depth_format(path: Path, size: tuple[int, int], bits: int | None) -> YuvFormat:
    """Format of the depth output: as its name says, else 8-bit 4:2:0 or 16-bit 4:0:0."""
    named = format_from_name(path)
    if named is None:
        bits = 8 if bits is None else bits
        return YuvFormat(*size, chroma="420" if bits == 8 else "400", bits=bits)
    if named.size != size:
        raise UsageError(
            f"the output name says {named.width}x{named.height}, the configuration "
            f"{size[0]}x{size[1]} (SourceWidth, SourceHeight)",
            path=path,
        )
    if named.chroma not in ("420", "400"):
        raise UsageError(
            f"depth maps are written as 4:2:0 or 4:0:0, the name says {named.chroma}", path=path
        )
    if bits is not None and bits != named.bits:
        raise UsageError(
            f"--depth-bits {bits} disagrees with the output name ({named.bits} bits)", path=path
        )
    return named


# --------------------------------------------------------------------------- stereo pairs


def estimate_pair_disparity(
    left: np.ndarray | str | os.PathLike,
    right: np.ndarray | str | os.PathLike,
    *,
    options: DepthOptions,
    output: str | os.PathLike | None = None,
    png: str | os.PathLike | None = None,
    png_scale: float = DEFAULT_PNG_SCALE,
) -> np.ndarray:
    """Estimate the disparity map of a rectified pair
    (:func:`mvtools.depth.estimate_disparity`) and write it on request.

    Corresponding points lie on the same row, the right view's to the left: disparity
    = left x - right x.

    Parameters
    ----------
    left, right : ndarray of shape (H, W, 3) uint8, or path
        The pictures, or their files (PNG, PPM, JPEG...; grey is repeated, 16-bit
        samples reduced to 8 bits).
    options : DepthOptions
        The disparities searched are ``minimum_value_of_disparity_search_range`` to
        ``maximum_value_of_disparity_search_range``; the method (default
        :data:`mvtools.depth.options.DEFAULT_METHOD`), ``cost``, ``subpixel``,
        ``segment_planes``, ``segmentation`` and ``view`` are read too.
    output : path, optional
        Write the map as PFM (float pixels, ``inf`` where unknown, as Middlebury stores
        unknown values); the name ends in ``.pfm``.
    png : path, optional
        With ``output``, also write the map as a 16-bit PNG of
        :func:`disparity_png_values` (Middlebury's ground-truth convention).
    png_scale : float
        PNG value / scale = disparity in pixels.

    Returns
    -------
    ndarray of float, shape (H, W)
        The disparity of ``options.view``, NaN or ``inf`` where unknown.

    Raises
    ------
    UsageError
        An output that cannot be written or cannot hold the range (checked after the
        pictures are read, before the estimation: nothing is written then).
    DataError
        Pictures of different sizes, or a float map given as a picture.
    ValueError
        A range or picture size that the method cannot use.
    """
    from mvtools.depth.stereo import estimate_disparity

    low = options.minimum_value_of_disparity_search_range
    high = options.maximum_value_of_disparity_search_range
    names = {"left": left, "right": right}
    left_rgb, right_rgb = (_picture(picture) for picture in (left, right))
    outputs = []
    if output is not None:
        outputs = _check_pair_outputs(
            Path(output), None if png is None else Path(png), png_scale, low, high
        )
    if left_rgb.shape != right_rgb.shape:
        raise DataError(
            f"the right picture is {right_rgb.shape[1]}x{right_rgb.shape[0]}, the "
            f"left one {left_rgb.shape[1]}x{left_rgb.shape[0]}",
            path=None if isinstance(right, np.ndarray) else right,
        )
    height, width = left_rgb.shape[:2]
    name = names[options.view]
    method = options.method or DEFAULT_METHOD
    LOG.info(
        "%s: %dx%d, disparities %d..%d, method %s, cost %s",
        f"the {options.view} picture" if isinstance(name, np.ndarray) else name,
        width,
        height,
        low,
        high,
        method,
        options.cost,
    )
    start = time.perf_counter()
    disparity = estimate_disparity(
        left_rgb,
        right_rgb,
        max_disparity=high,
        min_disparity=low,
        method=method,
        cost=options.cost,
        subpixel=options.subpixel,
        segment_planes=options.segment_planes,
        segmentation=options.segmentation,
        view=options.view,
    )
    _write_disparity(disparity, outputs, png_scale, time.perf_counter() - start)
    return disparity


def estimate_views_disparity(
    pictures: Sequence[np.ndarray | str | os.PathLike],
    *,
    reference: int,
    options: DepthOptions,
    positions: Sequence[float] | None = None,
    output: str | os.PathLike | None = None,
    png: str | os.PathLike | None = None,
    png_scale: float = DEFAULT_PNG_SCALE,
    progress: ProgressCallback | None = None,
) -> np.ndarray:
    """Estimate the disparity map of one view of a linear array from all its views
    (:func:`mvtools.depth.array.estimate_array_disparity`) and write it on request.

    Parameters
    ----------
    pictures : sequence of ndarray of shape (H, W, 3) uint8, or path
        Rectified views on a line, left to right (a point's x falls from one view to
        the next), or their files.
    reference : int
        Index in ``pictures`` of the view whose disparity is estimated.
    options : DepthOptions
        The disparities searched per unit of ``positions`` are
        ``minimum_value_of_disparity_search_range`` to
        ``maximum_value_of_disparity_search_range``; the method, ``cost``,
        ``segment_planes`` and ``subpixel`` are read too.
    positions : sequence of float, optional
        The views' places on the line; by default equal steps of one.
    output, png, png_scale
        As for :func:`estimate_pair_disparity`.
    progress : callable, optional
        ``progress(done, total)`` as each pair of the reference and another view is
        matched.

    Returns
    -------
    ndarray of float, shape (H, W)
        Disparity per unit of ``positions``, NaN where unknown.

    Raises
    ------
    UsageError, DataError, ValueError
        As for :func:`estimate_pair_disparity`.
    """
    from mvtools.depth.array import estimate_array_disparity

    low = options.minimum_value_of_disparity_search_range
    high = options.maximum_value_of_disparity_search_range
    views = [_picture(picture) for picture in pictures]
    outputs = []
    if output is not None:
        outputs = _check_pair_outputs(
            Path(output), None if png is None else Path(png), png_scale, low, high
        )
    for picture, view in zip(pictures, views):
        if view.shape != views[0].shape:
            raise DataError(
                f"this picture is {view.shape[1]}x{view.shape[0]}, the first one "
                f"{views[0].shape[1]}x{views[0].shape[0]}",
                path=None if isinstance(picture, np.ndarray) else picture,
            )
    method = options.method or DEFAULT_METHOD
    LOG.info(
        "view %d of %d: %dx%d, disparities %d..%d per unit of baseline, method %s, cost %s",
        reference + 1,
        len(views),
        views[0].shape[1],
        views[0].shape[0],
        low,
        high,
        method,
        options.cost,
    )
    start = time.perf_counter()
    disparity = estimate_array_disparity(
        views,
        reference=reference,
        positions=positions,
        max_disparity=high,
        min_disparity=low,
        method=method,
        cost=options.cost,
        segment_planes=options.segment_planes,
        subpixel=options.subpixel,
        progress=progress,
    )
    _write_disparity(disparity, outputs, png_scale, time.perf_counter() - start)
    return disparity


def _write_disparity(
    disparity: np.ndarray, outputs: list[Path], png_scale: float, seconds: float
) -> None:
    """Report an estimated map and write it to the checked outputs: PFM, then PNG."""
    known = np.isfinite(disparity)
    LOG.info(
        "disparity estimated in %.2f s, %.1f %% of the pixels unknown",
        seconds,
        100.0 * (1.0 - known.mean()),
    )
    if outputs:
        write_image(outputs[0], np.where(known, disparity, np.inf).astype(np.float32))
        LOG.info("wrote %s", outputs[0])
    if len(outputs) > 1:
        write_image(outputs[1], disparity_png_values(disparity, scale=png_scale))
        LOG.info("wrote %s (disparity * %g)", outputs[1], png_scale)


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


def _check_pair_outputs(
    output: Path, png: Path | None, png_scale: float, min_disparity: int, max_disparity: int
) -> list[Path]:
    """The output paths, checked once the inputs are read and before the estimation, so
    that a bad one fails at once and leaves nothing behind."""
    if output.suffix.lower() != ".pfm":
        raise UsageError(
            "the disparity map is written as PFM: give a name ending in .pfm", path=output, key="-o"
        )
    outputs = [output]
    if png is not None:
        if png.suffix.lower() != ".png":
            raise UsageError("--png needs a name ending in .png", path=png, key="--png")
        if not png_scale > 0:
            raise UsageError(f"--png-scale must be positive, got {png_scale:g}")
        if min_disparity < 0:
            raise UsageError(
                f"a PNG disparity map cannot hold negative disparities "
                f"(--min-disparity {min_disparity}); use the PFM output alone"
            )
        if max_disparity * png_scale > _PNG_MAX:
            raise UsageError(
                f"--disparities {max_disparity} * --png-scale {png_scale:g} exceeds "
                f"{_PNG_MAX}, the largest 16-bit value; lower --png-scale"
            )
        outputs.append(png)
    for path in outputs:
        output_folder_exists(path.parent)
        check_output(path)
    return outputs


def _picture(picture: np.ndarray | str | os.PathLike) -> np.ndarray:
    """A picture as ``(H, W, 3)`` uint8 RGB, read from its file if a path is given."""
    if isinstance(picture, np.ndarray):
        return picture
    path = Path(picture)
    image = read_image(path)
    if image.dtype.kind == "f":
        raise DataError("a picture is expected, this is a float (PFM) map", path=path)
    if image.dtype == np.uint16:
        image = (image // 257).astype(np.uint8)
    if image.ndim == 2:
        image = np.repeat(image[..., None], 3, axis=2)
    return image
