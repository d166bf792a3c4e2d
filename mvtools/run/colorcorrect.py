"""Colour correction of the views of an array: the run function of ``mvtools colorcorrect``.

:func:`correct_colours` makes the colours of the views agree: per-channel look-up tables
(eq. 1.18 of the chapter "Multiview video: acquisition, processing, compression, and
virtual view rendering"), estimated from the pixels that show the same scene point in a
view and the reference (given cameras and depth maps) or else by matching cumulative
histograms; or, with the target ``"chart"``, each view on its own to the reference
colours of the ColorChecker it shows. The tables are estimated from a few frames and
applied to every frame, one frame at a time.

Chart detection, the chart fit and the warping of views (OpenCV, SciPy) are imported
when a run needs them, so this module is cheap to import.
"""

from __future__ import annotations

import contextlib
import logging
import os
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from mvtools.color.correct import (
    SPACES,
    TARGETS,
    channel_names,
    correct_planes,
    view_tables,
    working_codes,
)
from mvtools.color.lut import apply_lut
from mvtools.color.space import rgb_to_yuv, yuv_to_rgb
from mvtools.errors import DataError, UsageError, at_fault
from mvtools.geometry.camera import Camera
from mvtools.geometry.depth import DepthCoding, facing_camera
from mvtools.io.color_charts import ColorChart
from mvtools.io.guard import check_output
from mvtools.io.images import IMAGE_EXTENSIONS, read_image, write_image
from mvtools.io.inputs import frame_range, open_input_video
from mvtools.io.luts import write_cube, write_lut, write_matrix
from mvtools.io.yuv import VideoReader, YuvFormat, open_writer
from mvtools.run.stream import ProgressCallback, stream_frames

if TYPE_CHECKING:
    from mvtools.color.chart_correction import ChartCorrection

LOG = logging.getLogger(__name__)

#: The corrections a run can aim at: the tables' targets, and a colour chart.
CORRECTION_TARGETS = (*TARGETS, "chart")

#: The tables written for each view: by every target, and by the target ``"chart"``.
TABLE_SUFFIXES = (".lut.txt", ".cube")
CHART_TABLE_SUFFIXES = (".lut.txt", ".ccm.txt", ".cube")


@dataclass(frozen=True)
class ColourCorrectionOptions:
    """How :func:`correct_colours` corrects the views.

    Attributes
    ----------
    reference : str, optional
        The view whose colours the others take; default the middle view.
    target : {"reference", "average", "chart"}
        ``"reference"``: every view takes the reference's colours; ``"average"``: every
        view, the reference too, takes the average colour profile of all views;
        ``"chart"``: every view takes the reference colours of the ColorChecker it shows.
    space : {"rgb", "yuv"}
        The channels the tables work on: RGB, or the Y, U, V planes as they are.
    chart : ColorChart, optional
        The chart's reference values; needed by the target ``"chart"``.
    chart_corners : mapping of str to ndarray, shape (4, 2)
        Corners of the chart's patch area in a view (top-left, top-right, bottom-right,
        bottom-left of the upright chart); the chart is detected in the other views.
    chart_model : {"3x3", "4x3"}
        The chart's colour matrix: linear or affine.
    estimate_frames : int
        The frames whose samples estimate the tables.
    estimate_from : int, optional
        The first of those frames; default the first frame corrected.
    """

    reference: str | None = None
    target: str = "reference"
    space: str = "rgb"
    chart: ColorChart | None = None
    chart_corners: Mapping[str, np.ndarray] = field(default_factory=dict)
    chart_model: str = "3x3"
    estimate_frames: int = 1
    estimate_from: int | None = None

    def __post_init__(self):
        if self.target not in CORRECTION_TARGETS:
            raise ValueError(f"target must be one of {', '.join(CORRECTION_TARGETS)}")
        if self.space not in SPACES:
            raise ValueError(f"space must be one of {', '.join(SPACES)}")
        if self.target == "chart" and (self.chart is None or self.space != "rgb"):
            raise ValueError("the target 'chart' needs a chart and corrects RGB")


@dataclass(frozen=True)
class ViewCorrection:
    """One view's correction, and how far the view is from its target before and after.

    Attributes
    ----------
    name : str
    table : ndarray, shape (C, L)
        The code each channel's code ``0 .. L - 1`` becomes; with a chart, the tone
        curve to linear RGB in codes (its ``NAME.lut.txt``).
    before, after : float
        The distance to the target in ``measure``, on the first estimation frame.
    measure : str
        What ``before`` and ``after`` measure.
    chart : ChartCorrection, optional
        With the target ``"chart"``: the fit, with each patch's CIEDE2000 after
        correction and the patches it used.
    """

    name: str
    table: np.ndarray
    before: float
    after: float
    measure: str
    chart: ChartCorrection | None = None


@dataclass(frozen=True)
class ColourCorrection:
    """What :func:`correct_colours` did.

    Attributes
    ----------
    views : tuple of ViewCorrection
        In the order of the views.
    method : {"correspondences", "histograms", "chart"}
        Where the tables come from.
    reference : str, optional
        The reference view (None with the target ``"chart"``).
    """

    views: tuple[ViewCorrection, ...]
    method: str
    reference: str | None


def correct_colours(
    views: Mapping[str, str | os.PathLike],
    outputs: Mapping[str, str | os.PathLike],
    options: ColourCorrectionOptions,
    *,
    cameras: Mapping[str, Camera] | None = None,
    depths: Mapping[str, str | os.PathLike] | None = None,
    depth_range: tuple[float, float] | None = None,
    size: tuple[int, int] | None = None,
    pix_fmt: str | None = None,
    start_frame: int = 0,
    frame_count: int | None = None,
    progress: ProgressCallback | None = None,
) -> ColourCorrection:
    """Correct the colours of ``views`` and write the corrected views and their tables.

    Every input is opened before any output is written, and no output may name an
    input. Views given as pictures (PNG, ...) are matched by their RGB histograms.

    Parameters
    ----------
    views : mapping of str to path
        Each view's name (its camera's) and texture video or picture, in the array's order.
    outputs : mapping of str to path
        Each view's corrected video or picture. Its tables go beside it: ``NAME.lut.txt``
        and ``NAME.cube``, and with a chart ``NAME.ccm.txt``.
    options : ColourCorrectionOptions
    cameras : mapping of str to Camera, optional
        The views' cameras. With ``depths``, the tables come from the pixels that show the
        same scene point in a view and the reference; without, the histograms are taken
        over the field of view both cameras share.
    depths : mapping of str to path, optional
        The depth map video of every view (MPEG convention), or of none.
    depth_range : (float, float), optional
        Znear and Zfar of the depth maps; default the cameras' common ``depth_range``.
    size, pix_fmt : optional
        The videos' size and pixel format when their names or headers do not say.
    start_frame, frame_count : int
        The frames corrected; ``frame_count`` None for all that every video has.
    progress : callable, optional
        ``progress(done, total)`` after each frame of each view corrected.

    Returns
    -------
    ColourCorrection

    Raises
    ------
    UsageError, DataError
        Options the views cannot take (an estimation frame past their end, no common
        Znear and Zfar); views of different formats, constant views, no chart found.
    """
    views = {name: Path(path) for name, path in views.items()}
    outputs = {name: Path(path) for name, path in outputs.items()}
    names = list(views)
    if options.target == "chart":
        return _correct_to_chart(
            views, outputs, options, size, pix_fmt, start_frame, frame_count, progress
        )
    reference_index = (
        names.index(options.reference) if options.reference is not None else len(names) // 2
    )
    if all(_is_picture(path) for path in views.values()):
        return _correct_images(views, outputs, reference_index, options.target)
    depths = {name: Path(path) for name, path in (depths or {}).items()}
    with contextlib.ExitStack() as stack:
        videos = [
            stack.enter_context(open_input_video(path, size, pix_fmt)) for path in views.values()
        ]
        fmt = _common_format(videos, names)
        depth_videos = {
            name: stack.enter_context(open_input_video(path, size, pix_fmt))
            for name, path in depths.items()
        }
        _check_outputs(outputs, "video", TABLE_SUFFIXES)
        frames = frame_range(videos + list(depth_videos.values()), start_frame, frame_count)
        estimation = _estimation_frames(
            videos, frames, options.estimate_from, options.estimate_frames
        )
        matcher = _Matcher(
            names, reference_index, cameras, depth_videos, depth_range, fmt, options.space
        )
        samples = matcher.samples(videos, estimation)
        tables = view_tables(
            samples,
            reference_index,
            target=options.target,
            method=matcher.method,
            levels=2**fmt.bits,
        )
        _write_corrected(
            videos,
            [outputs[name] for name in names],
            frames,
            fmt,
            [
                lambda planes, table=table: correct_planes(
                    planes, table, bits=fmt.bits, space=options.space, chroma=fmt.chroma
                )
                for table in tables
            ],
            progress,
        )
        channels = channel_names(options.space, len(fmt.plane_shapes))
        for name, table in zip(names, tables):
            write_lut(_table_file(outputs, name, ".lut.txt"), table, channels=channels)
            if len(channels) == 3:
                write_cube(
                    _table_file(outputs, name, ".cube"),
                    table,
                    max_value=2**fmt.bits - 1,
                    title=f"mvtools colorcorrect {name} ({options.space})",
                )
        return ColourCorrection(
            tuple(matcher.scores(videos, tables, estimation[0])),
            matcher.method,
            names[reference_index],
        )


def _is_picture(path: Path) -> bool:
    return path.suffix.lower() in IMAGE_EXTENSIONS


def _correct_images(views, outputs, reference_index, target) -> ColourCorrection:
    """Pictures (a stereo pair's PNGs, say): RGB tables from the cumulative histograms."""
    names = list(views)
    pictures = [read_image(path) for path in views.values()]
    for (name, path), picture in zip(views.items(), pictures):
        if picture.ndim != 3 or picture.dtype != np.uint8:
            raise DataError(
                f"view {name} is not an 8-bit colour picture ({picture.dtype}, "
                f"shape {picture.shape})",
                path=path,
            )
        _check_not_constant(picture, name, path)
    _check_outputs(outputs, "picture", TABLE_SUFFIXES)
    reference = pictures[reference_index].reshape(-1, 3)
    samples = [
        None if index == reference_index else (picture.reshape(-1, 3), reference)
        for index, picture in enumerate(pictures)
    ]
    tables = view_tables(samples, reference_index, target=target, method="histograms")
    next(iter(outputs.values())).parent.mkdir(parents=True, exist_ok=True)
    corrections = []
    for name, picture, table in zip(names, pictures, tables):
        corrected = np.stack([apply_lut(picture[..., c], table[c]) for c in range(3)], axis=-1)
        write_image(outputs[name], corrected)
        write_lut(_table_file(outputs, name, ".lut.txt"), table, channels=("R", "G", "B"))
        write_cube(
            _table_file(outputs, name, ".cube"),
            table,
            max_value=255,
            title=f"mvtools colorcorrect {name} (rgb)",
        )
        before, after = (
            float(np.abs(image.reshape(-1, 3).mean(0) - reference.mean(0)).mean())
            for image in (picture, corrected)
        )
        corrections.append(
            ViewCorrection(name, table, before, after, "mean RGB difference to the reference")
        )
    return ColourCorrection(tuple(corrections), "histograms", names[reference_index])


def _table_file(outputs: Mapping[str, Path], name: str, suffix: str) -> Path:
    """Where view ``name``'s table ``suffix`` goes: beside its corrected video."""
    return outputs[name].parent / f"{name}{suffix}"


def _check_outputs(outputs: Mapping[str, Path], what: str, tables: tuple[str, ...]) -> None:
    """Every output against the inputs, once they are all open: the corrected views and
    the tables are written only after the tables' estimation."""
    for name, output in outputs.items():
        check_output(output, f"corrected {what} of {name} (in -o, under its input's name)")
        for suffix in tables:
            check_output(_table_file(outputs, name, suffix), f"table of {name}")


def _estimation_frames(videos, frames: range, start: int | None, count: int) -> range:
    """The frames whose samples estimate the tables: ``count`` from ``start`` (default
    the first frame processed), within what every video holds."""
    start = frames.start if start is None else start
    stop = min(start + count, *(len(video) for video in videos))
    if start >= stop:
        raise UsageError(f"--estimate-from {start} is past the end: the views have {stop} frames")
    return range(start, stop)


def _write_corrected(
    videos: Sequence[VideoReader],
    outputs: Sequence[Path],
    frames: range,
    fmt: YuvFormat,
    corrections: Sequence[Callable],
    progress: ProgressCallback | None,
) -> None:
    """Every frame of every view through its correction, one frame at a time; progress
    counts the frames of all views."""
    outputs[0].parent.mkdir(parents=True, exist_ok=True)
    total = len(frames) * len(videos)
    for view, (video, output, correct) in enumerate(zip(videos, outputs, corrections)):
        view_progress = None
        if progress is not None:
            done_before = view * len(frames)

            def view_progress(done, _frames, done_before=done_before):
                progress(done_before + done, total)

        with open_writer(output, fmt) as writer:
            stream_frames(
                frames,
                lambda _index, planes, correct=correct: [correct(planes)],
                readers=[video],
                writers=[writer],
                progress=view_progress,
            )


def _correct_to_chart(
    views, outputs, options, size, pix_fmt, start_frame, frame_count, progress
) -> ColourCorrection:
    """Each view on its own to the reference colours of the ColorChecker it shows."""
    from mvtools.color.chart import detect_chart, sample_patches
    from mvtools.color.chart_correction import fit_chart_correction
    from mvtools.color.colorimetry import delta_e_2000, linear_rgb_to_lab, srgb_to_linear

    names = list(views)
    chart = options.chart
    with contextlib.ExitStack() as stack:
        videos = [
            stack.enter_context(open_input_video(path, size, pix_fmt)) for path in views.values()
        ]
        fmt = _common_format(videos, names)
        if fmt.chroma == "400":
            raise DataError(f"{videos[0].path}: a chart needs colour views, not grey ones")
        _check_outputs(outputs, "video", CHART_TABLE_SUFFIXES)
        frames = frame_range(videos, start_frame, frame_count)
        estimation = _estimation_frames(
            videos, frames, options.estimate_from, options.estimate_frames
        )
        top = 2**fmt.bits - 1
        corrections, befores = [], []
        for name, video in zip(names, videos):
            pictures = [yuv_to_rgb(video.read(index), bits=fmt.bits) for index in estimation]
            corners = options.chart_corners.get(name)
            if corners is None:
                corners = detect_chart(pictures[0])
                if corners is None:
                    raise DataError(
                        f"view {name}: no ColorChecker found in frame "
                        f"{estimation[0]}; give its corners with --chart-corners",
                        path=video.path,
                    )
                LOG.info("%s: chart found at %s", name, np.round(corners, 1).tolist())
            measured = (
                np.mean([sample_patches(picture, corners) for picture in pictures], axis=0) / top
            )
            corrections.append(
                fit_chart_correction(
                    measured,
                    chart.lab,
                    linearization="grey-curve",
                    model=options.chart_model,
                    white=chart.white_xyz,
                )
            )
            befores.append(
                delta_e_2000(
                    linear_rgb_to_lab(srgb_to_linear(measured), white=chart.white_xyz), chart.lab
                ).mean()
            )
        _write_corrected(
            videos,
            [outputs[name] for name in names],
            frames,
            fmt,
            [
                lambda planes, correction=correction: rgb_to_yuv(
                    np.round(
                        correction.apply(yuv_to_rgb(planes, bits=fmt.bits) / top) * top
                    ).astype(fmt.dtype),
                    chroma=fmt.chroma,
                    bits=fmt.bits,
                )
                for correction in corrections
            ],
            progress,
        )
    grid = np.linspace(0.0, 1.0, 33)
    blue, green, red = np.meshgrid(grid, grid, grid, indexing="ij")
    results = []
    for name, correction, before in zip(names, corrections, befores):
        table = correction.curve * top
        write_lut(_table_file(outputs, name, ".lut.txt"), table, channels=("R", "G", "B"))
        write_matrix(_table_file(outputs, name, ".ccm.txt"), correction.matrix)
        write_cube(
            _table_file(outputs, name, ".cube"),
            correction.apply(np.stack([red, green, blue], -1)),
            max_value=1.0,
            title=f"mvtools colorcorrect {name} (chart)",
        )
        results.append(
            ViewCorrection(
                name,
                table,
                float(before),
                float(correction.delta_e.mean()),
                "mean CIEDE2000 to the chart's reference colours",
                chart=correction,
            )
        )
    return ColourCorrection(tuple(results), "chart", None)


def _common_format(videos, names) -> YuvFormat:
    formats = {video.format for video in videos}
    if len(formats) > 1:
        listed = ", ".join(f"{name} {video.format}" for name, video in zip(names, videos))
        raise DataError(
            f"the views differ in size or format ({listed}); colour tables map codes of one format"
        )
    return formats.pop()


class _Matcher:
    """Where the samples of each view and the reference come from: corresponding pixels
    when both have depth maps, else their whole pictures' histograms."""

    def __init__(self, names, reference, cameras, depth_videos, depth_range, fmt, space):
        self.names, self.reference, self.cameras = names, reference, cameras
        self.depth_videos, self.fmt, self.space = depth_videos, fmt, space
        self.depth_range = None
        self._codings = {}
        if cameras is not None:
            self.depth_range = depth_range or _camera_depth_range(cameras, names)
            with at_fault(UsageError, key="--depth-range"):
                self.cameras = {
                    name: facing_camera(camera, self.depth_range)
                    for name, camera in cameras.items()
                }
        missing = [name for name in names if name not in depth_videos]
        if depth_videos and missing:
            raise UsageError(
                f"depth maps are given for some views but not for "
                f"{', '.join(missing)}: give --depth for every view or for none"
            )
        self.method = "correspondences" if depth_videos else "histograms"

    def _z(self, name, index):
        video = self.depth_videos[name]
        bits = video.format.bits
        if bits not in self._codings:
            self._codings[bits] = DepthCoding(self.depth_range, bits)
        return self._codings[bits].z(video.read(index)[0])

    def samples(self, videos, frames):
        """Each view's samples and the reference's (None for the reference itself)."""
        codes = {}
        for index in frames:
            for name, video in zip(self.names, videos):
                picture = working_codes(video.read(index), bits=self.fmt.bits, space=self.space)
                _check_not_constant(picture, name, video.path)
                codes.setdefault(name, []).append(picture)
        reference_name = self.names[self.reference]
        samples = []
        for name in self.names:
            if name == reference_name:
                samples.append(None)
                continue
            pairs = [
                self._pair(name, codes[name][k], codes[reference_name][k], index)
                for k, index in enumerate(frames)
            ]
            samples.append(
                (
                    np.concatenate([pair[0] for pair in pairs]),
                    np.concatenate([pair[1] for pair in pairs]),
                )
            )
            LOG.info(
                "%s: %d samples (%s) towards %s",
                name,
                len(samples[-1][0]),
                self.method,
                reference_name,
            )
        return samples

    def _pair(self, name, picture, reference_picture, index):
        from mvtools.color.correspondence import common_view_samples, corresponding_samples

        channels = picture.shape[2]
        if self.method == "histograms":
            if self.cameras is None:
                return picture.reshape(-1, channels), reference_picture.reshape(-1, channels)
            return common_view_samples(
                picture,
                self.cameras[name],
                reference_picture,
                self.cameras[self.names[self.reference]],
                depth_range=self.depth_range,
            )
        reference_name = self.names[self.reference]
        pair = corresponding_samples(
            picture,
            self.cameras[name],
            self._z(name, index),
            reference_picture,
            self.cameras[reference_name],
            self._z(reference_name, index),
        )
        if len(pair[0]) == 0:
            raise DataError(
                f"view {name} and the reference {reference_name} share no "
                "visible pixel at the depths given: are the cameras and depth "
                "maps those of these views?"
            )
        return pair

    def scores(self, videos, tables, index) -> list[ViewCorrection]:
        """How far each view is from the reference before and after, on the first
        estimation frame: Y-PSNR of the view warped into the reference where both see
        the scene, or without depth the difference of the mean codes."""
        reference_name = self.names[self.reference]
        by_name = dict(zip(self.names, videos))
        reference = np.asarray(by_name[reference_name].read(index)[0])
        corrections = []
        for name, table in zip(self.names, tables):
            planes = by_name[name].read(index)
            corrected = correct_planes(
                planes, table, bits=self.fmt.bits, space=self.space, chroma=self.fmt.chroma
            )
            if self.method == "correspondences" and name != reference_name:
                scores = [
                    self._warped_psnr(name, luma, reference, index)
                    for luma in (planes[0], corrected[0])
                ]
                measure = "dB Y-PSNR, warped into the reference"
            else:
                scores = [
                    abs(float(np.mean(luma)) - float(np.mean(reference)))
                    for luma in (planes[0], corrected[0])
                ]
                measure = "mean Y difference to the reference"
            corrections.append(ViewCorrection(name, table, *scores, measure))
        return corrections

    def _warped_psnr(self, name, luma, reference, index):
        from mvtools.color.correspondence import warped_psnr

        reference_name = self.names[self.reference]
        return warped_psnr(
            luma,
            self.cameras[name],
            self._z(name, index),
            reference,
            self.cameras[reference_name],
            self._z(reference_name, index),
            max_value=2**self.fmt.bits - 1,
        )


def _camera_depth_range(cameras, names):
    ranges = {cameras[name].depth_range for name in names}
    if None in ranges or len(ranges) != 1:
        raise UsageError(
            "the scene's Znear and Zfar are unknown (for depth maps, and for "
            "the views' common field of view): give --depth-range ZNEAR ZFAR"
        )
    return ranges.pop()


def _check_not_constant(picture, name, path):
    for channel in range(picture.shape[2]):
        values = picture[..., channel]
        if values.min() == values.max():
            raise DataError(
                f"view {name} is constant (every sample of channel {channel} is "
                f"{values.min()}): it has no colours to match",
                path=path,
            )
