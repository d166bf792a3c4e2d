"""``mvtools colorcorrect``: make the colours of the views of an array agree."""

from __future__ import annotations

import contextlib
import logging
from pathlib import Path

import click
import numpy as np

from mvtools.cli.options import (
    DEPTH,
    ProgramCommand,
    frame_range_options,
    program,
    transposed_rotation_option,
    video_format_options,
)
from mvtools.cli.progress import Progress
from mvtools.color import rgb_to_yuv, yuv_to_rgb
from mvtools.color.chart import detect_chart, sample_patches
from mvtools.color.chart_correction import fit_chart_correction
from mvtools.color.colorimetry import delta_e_2000, linear_rgb_to_lab, srgb_to_linear
from mvtools.color.correct import (
    SPACES,
    TARGETS,
    channel_names,
    correct_planes,
    view_tables,
    working_codes,
)
from mvtools.color.correspondence import (
    common_view_samples,
    corresponding_samples,
    warped_psnr,
)
from mvtools.color.lut import apply_lut
from mvtools.errors import DataError, UsageError, at_fault
from mvtools.geometry.depth import DepthCoding, facing_camera
from mvtools.io.cameras import get_camera
from mvtools.io.color_charts import DEFAULT_CHART, read_colorchecker
from mvtools.io.guard import check_output
from mvtools.io.images import IMAGE_EXTENSIONS, read_image, write_image
from mvtools.io.inputs import frame_range, open_input_video
from mvtools.io.json_cameras import read_camera_file
from mvtools.io.luts import write_cube, write_lut, write_matrix
from mvtools.io.yuv import open_writer

LOG = logging.getLogger("mvtools")


@click.command(name="colorcorrect", cls=ProgramCommand)
@click.option(
    "--view",
    "views",
    multiple=True,
    nargs=2,
    required=True,
    metavar="NAME VIDEO",
    help="A view to correct: its camera name and texture video (repeatable, in the array's order).",
)
@click.option(
    "--reference",
    default=None,
    metavar="NAME",
    help="The view whose colours the others take (default: the middle view).",
)
@click.option(
    "--target",
    type=click.Choice((*TARGETS, "chart")),
    default="reference",
    show_default=True,
    help="reference: every view takes the reference's colours; average: every view, "
    "the reference too, takes the average colour profile of all views; chart: "
    "every view takes the reference colours of the ColorChecker it shows.",
)
@click.option(
    "--chart-reference",
    type=click.Path(dir_okay=False),
    default=None,
    help="With --target chart: the chart's reference values, colour-science's "
    "CCS_COLOURCHECKERS JSON file.",
)
@click.option(
    "--chart-name",
    default=DEFAULT_CHART,
    show_default=True,
    help="The chart's entry in --chart-reference.",
)
@click.option(
    "--chart-corners",
    "chart_corners",
    multiple=True,
    nargs=2,
    metavar="NAME X,Y,X,Y,X,Y,X,Y",
    help="Corners of the chart's patch area in a view (top-left, top-right, "
    "bottom-right, bottom-left of the upright chart); without, the chart is "
    "detected.",
)
@click.option(
    "--chart-model",
    type=click.Choice(("3x3", "4x3")),
    default="3x3",
    show_default=True,
    help="The colour matrix: linear (3x3) or affine (4x3), after a per-channel "
    "tone curve fitted to the chart's grey patches.",
)
@click.option(
    "--cameras",
    "camera_file",
    type=click.Path(dir_okay=False),
    default=None,
    help="Camera parameter file (MPEG text or JSON). With --depth, tables come from "
    "the pixels that show the same scene point in both views; without, the "
    "histograms are taken over the field of view both cameras share.",
)
@click.option(
    "--depth",
    "depths",
    multiple=True,
    nargs=2,
    metavar="NAME VIDEO",
    help="Depth map video of a view (MPEG convention, repeatable). Without depth "
    "for a view and the reference, their cumulative histograms are matched.",
)
@click.option(
    "--depth-range",
    nargs=2,
    type=DEPTH,
    default=None,
    metavar="ZNEAR ZFAR",
    help="Znear and Zfar of the depth maps (default: the cameras' Depth_range in "
    "an MPEG-I JSON camera file).",
)
@click.option(
    "--space",
    type=click.Choice(SPACES),
    default="rgb",
    show_default=True,
    help="Channels the tables work on: RGB (a camera's response is per sensor "
    "channel) or the Y, U, V planes as they are (no resampling of chroma).",
)
@click.option(
    "--estimate-frames",
    type=click.IntRange(min=1),
    default=1,
    show_default=True,
    help="Frames whose samples estimate the tables.",
)
@click.option(
    "--estimate-from",
    type=click.IntRange(min=0),
    default=None,
    help="First of those frames (default: the first frame processed). Chunks of a "
    "sequence corrected in parallel give one run's bytes when they all estimate "
    "from the same frames.",
)
@click.option(
    "-o",
    "--out-dir",
    required=True,
    type=click.Path(file_okay=False),
    help="Folder for the corrected videos (named as their inputs) and each view's "
    "tables, NAME.lut.txt and NAME.cube.",
)
@video_format_options
@frame_range_options
@transposed_rotation_option
@program
def command(
    views,
    reference,
    target,
    chart_reference,
    chart_name,
    chart_corners,
    chart_model,
    camera_file,
    depths,
    depth_range,
    space,
    estimate_frames,
    estimate_from,
    out_dir,
    size,
    pix_fmt,
    start_frame,
    frame_count,
    transposed_rotation,
):
    """Per-channel look-up tables that make the views' colours agree (the chapter's eq. 1.18),
    estimated from pixels that project onto each other (given cameras and depth maps)
    or else by cumulative-histogram matching, then applied to every frame.

    The tables are monotonic and smooth, estimated from the first --estimate-frames
    frames and applied to all, one frame at a time.
    """
    names = [name for name, _ in views]
    if len(set(names)) != len(names):
        raise UsageError(f"a view is given twice ({', '.join(names)})")
    out = Path(out_dir)
    targets = {}
    for name, path in views:
        for other, corrected in targets.items():
            if corrected.name == Path(path).name:
                raise UsageError(
                    f"--view {name}: the same file name as --view {other}: their "
                    "corrected videos would share one name in -o; rename one",
                    path=path,
                )
        targets[name] = out / Path(path).name
    if target == "chart":
        _correct_to_chart(
            views,
            targets,
            chart_reference,
            chart_name,
            dict(chart_corners),
            chart_model,
            space,
            estimate_frames,
            estimate_from,
            size,
            pix_fmt,
            start_frame,
            frame_count,
        )
        return
    if len(views) < 2:
        raise UsageError("colour correction needs at least two views (or --target chart)")
    reference_index = names.index(reference) if reference in names else len(names) // 2
    if reference is not None and reference not in names:
        raise UsageError(f"--reference {reference}: no such view (views: {', '.join(names)})")
    depth_of = dict(depths)
    unknown = sorted(set(depth_of) - set(names))
    if unknown:
        raise UsageError(f"--depth {unknown[0]}: no such view (views: {', '.join(names)})")
    images = [Path(path).suffix.lower() in IMAGE_EXTENSIONS for _, path in views]
    if any(images):
        if not all(images) or depth_of or camera_file:
            raise UsageError(
                "views given as images are matched by their histograms: give "
                "only images, without --depth and --cameras"
            )
        _correct_images(views, targets, reference_index, target)
        return
    cameras = _cameras(camera_file, depth_of, names, transposed_rotation)
    with contextlib.ExitStack() as stack:
        videos = [stack.enter_context(open_input_video(path, size, pix_fmt)) for _, path in views]
        fmt = _common_format(videos, names)
        depth_videos = {
            name: stack.enter_context(open_input_video(path, size, pix_fmt))
            for name, path in depth_of.items()
        }
        _check_outputs(targets, "video", _TABLES)
        frames = frame_range(videos + list(depth_videos.values()), start_frame, frame_count)
        estimation = _estimation_frames(videos, frames, estimate_from, estimate_frames)
        matcher = _Matcher(names, reference_index, cameras, depth_videos, depth_range, fmt, space)
        samples, method = matcher.samples(videos, estimation)
        tables = view_tables(
            samples, reference_index, target=target, method=method, levels=2**fmt.bits
        )
        _write_corrected(
            names,
            videos,
            targets,
            frames,
            fmt,
            [
                lambda planes, table=table: correct_planes(
                    planes, table, bits=fmt.bits, space=space, chroma=fmt.chroma
                )
                for table in tables
            ],
        )
        channels = channel_names(space, len(fmt.plane_shapes))
        for name, table in zip(names, tables):
            write_lut(_table_file(targets, name, ".lut.txt"), table, channels=channels)
            if len(channels) == 3:
                write_cube(
                    _table_file(targets, name, ".cube"),
                    table,
                    max_value=2**fmt.bits - 1,
                    title=f"mvtools colorcorrect {name} ({space})",
                )
        click.echo(matcher.summary(videos, tables, estimation[0]))


def _correct_images(views, targets, reference_index, target) -> None:
    """Pictures (a stereo pair's PNGs, say): RGB tables from the cumulative histograms."""
    names = [name for name, _ in views]
    pictures = [read_image(path) for _, path in views]
    for (name, path), picture in zip(views, pictures):
        if picture.ndim != 3 or picture.dtype != np.uint8:
            raise DataError(
                f"view {name} is not an 8-bit colour picture ({picture.dtype}, "
                f"shape {picture.shape})",
                path=path,
            )
        _check_not_constant(picture, name, path)
    _check_outputs(targets, "picture", _TABLES)
    reference = pictures[reference_index].reshape(-1, 3)
    samples = [
        None if index == reference_index else (picture.reshape(-1, 3), reference)
        for index, picture in enumerate(pictures)
    ]
    tables = view_tables(samples, reference_index, target=target, method="histograms")
    next(iter(targets.values())).parent.mkdir(parents=True, exist_ok=True)
    lines = [f"{'view':12s} mean RGB difference to {names[reference_index]}: before   after"]
    for (name, _), picture, table in zip(views, pictures, tables):
        corrected = np.stack([apply_lut(picture[..., c], table[c]) for c in range(3)], axis=-1)
        write_image(targets[name], corrected)
        write_lut(_table_file(targets, name, ".lut.txt"), table, channels=("R", "G", "B"))
        write_cube(
            _table_file(targets, name, ".cube"),
            table,
            max_value=255,
            title=f"mvtools colorcorrect {name} (rgb)",
        )
        before, after = (
            float(np.abs(image.reshape(-1, 3).mean(0) - reference.mean(0)).mean())
            for image in (picture, corrected)
        )
        lines.append(f"{name:12s} {'':>33s}{before:7.2f} {after:7.2f}")
    click.echo("\n".join(lines))


#: The tables written for each view: by every target, and by --target chart.
_TABLES = (".lut.txt", ".cube")
_CHART_TABLES = (".lut.txt", ".ccm.txt", ".cube")


def _table_file(targets: dict[str, Path], name: str, suffix: str) -> Path:
    """Where view ``name``'s table ``suffix`` goes: beside its corrected video."""
    return targets[name].parent / f"{name}{suffix}"


def _check_outputs(targets: dict[str, Path], what: str, tables: tuple[str, ...]) -> None:
    """Every output against the inputs, once they are all open: the corrected views and
    the tables are written only after the tables' estimation."""
    for name, target in targets.items():
        check_output(target, f"corrected {what} of {name} (in -o, under its input's name)")
        for suffix in tables:
            check_output(_table_file(targets, name, suffix), f"table of {name}")


def _estimation_frames(videos, frames: range, start: int | None, count: int) -> range:
    """The frames whose samples estimate the tables: ``count`` from ``start`` (default
    the first frame processed), within what every video holds."""
    start = frames.start if start is None else start
    stop = min(start + count, *(len(video) for video in videos))
    if start >= stop:
        raise UsageError(f"--estimate-from {start} is past the end: the views have {stop} frames")
    return range(start, stop)


def _write_corrected(names, videos, targets, frames, fmt, corrections) -> None:
    """Every frame of every view through its correction, one frame at a time."""
    next(iter(targets.values())).parent.mkdir(parents=True, exist_ok=True)
    progress = Progress(len(frames) * len(videos), "frames corrected")
    for name, video, correct in zip(names, videos, corrections):
        with open_writer(targets[name], fmt) as writer:
            for index in frames:
                writer.write(correct(video.read(index)))
                progress.advance()


def _parse_corners(name: str, text: str) -> np.ndarray:
    try:
        values = [float(value) for value in text.split(",")]
    except ValueError:
        values = []
    if len(values) != 8:
        raise UsageError(f"--chart-corners {name} {text}: give eight numbers X,Y,X,Y,X,Y,X,Y")
    return np.array(values).reshape(4, 2)


def _correct_to_chart(
    views,
    targets,
    chart_reference,
    chart_name,
    corners_of,
    model,
    space,
    estimate_frames,
    estimate_from,
    size,
    pix_fmt,
    start_frame,
    frame_count,
) -> None:
    """Each view on its own to the reference colours of the ColorChecker it shows."""
    if chart_reference is None:
        raise UsageError(
            "--target chart needs --chart-reference: colour-science's "
            "CCS_COLOURCHECKERS JSON file of reference values"
        )
    if space != "rgb":
        raise UsageError("--target chart corrects RGB: leave --space at rgb")
    names = [name for name, _ in views]
    unknown = sorted(set(corners_of) - set(names))
    if unknown:
        raise UsageError(f"--chart-corners {unknown[0]}: no such view (views: {', '.join(names)})")
    corners_of = {name: _parse_corners(name, text) for name, text in corners_of.items()}
    chart = read_colorchecker(chart_reference, chart=chart_name)
    with contextlib.ExitStack() as stack:
        videos = [stack.enter_context(open_input_video(path, size, pix_fmt)) for _, path in views]
        fmt = _common_format(videos, names)
        if fmt.chroma == "400":
            raise DataError(f"{videos[0].path}: a chart needs colour views, not grey ones")
        _check_outputs(targets, "video", _CHART_TABLES)
        frames = frame_range(videos, start_frame, frame_count)
        estimation = _estimation_frames(videos, frames, estimate_from, estimate_frames)
        top = 2**fmt.bits - 1
        corrections, lines = (
            [],
            [
                f"{'view':12s} {'patches':>8s} {'mean dE00 before':>17s} "
                f"{'after':>7s} {'max after':>10s}"
            ],
        )
        for name, video in zip(names, videos):
            pictures = [yuv_to_rgb(video.read(index), bits=fmt.bits) for index in estimation]
            corners = corners_of.get(name)
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
            correction = fit_chart_correction(
                measured, chart.lab, linearization="grey-curve", model=model, white=chart.white_xyz
            )
            before = delta_e_2000(
                linear_rgb_to_lab(srgb_to_linear(measured), white=chart.white_xyz), chart.lab
            )
            lines.append(
                f"{name:12s} {int(correction.used.sum()):8d} {before.mean():17.2f} "
                f"{correction.delta_e.mean():7.2f} {correction.delta_e.max():10.2f}"
            )
            corrections.append(correction)
        _write_corrected(
            names,
            videos,
            targets,
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
        )
    grid = np.linspace(0.0, 1.0, 33)
    blue, green, red = np.meshgrid(grid, grid, grid, indexing="ij")
    for name, correction in zip(names, corrections):
        write_lut(
            _table_file(targets, name, ".lut.txt"), correction.curve * top, channels=("R", "G", "B")
        )
        write_matrix(_table_file(targets, name, ".ccm.txt"), correction.matrix)
        write_cube(
            _table_file(targets, name, ".cube"),
            correction.apply(np.stack([red, green, blue], -1)),
            max_value=1.0,
            title=f"mvtools colorcorrect {name} (chart)",
        )
    click.echo("\n".join(lines))


def _cameras(camera_file, depth_of, names, transposed_rotation):
    if camera_file is None:
        if depth_of:
            raise UsageError("--depth needs --cameras: the camera parameter file of the views")
        return None
    cameras = read_camera_file(camera_file, transposed_rotation=transposed_rotation)
    return {name: get_camera(cameras, name, path=camera_file) for name in names}


def _common_format(videos, names):
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
        return samples, self.method

    def _pair(self, name, picture, reference_picture, index):
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

    def summary(self, videos, tables, index) -> str:
        """How far each view is from the reference before and after, on the first
        estimation frame: Y-PSNR of the view warped into the reference where both see
        the scene, or without depth the difference of the mean codes."""
        reference_name = self.names[self.reference]
        by_name = dict(zip(self.names, videos))
        reference = np.asarray(by_name[reference_name].read(index)[0])
        lines = [f"{'view':12s} {'method':16s} before   after"]
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
                unit = "dB Y-PSNR, warped into the reference"
            else:
                scores = [
                    abs(float(np.mean(luma)) - float(np.mean(reference)))
                    for luma in (planes[0], corrected[0])
                ]
                unit = "mean Y difference to the reference"
            lines.append(f"{name:12s} {self.method:16s} {scores[0]:7.2f} {scores[1]:7.2f}  {unit}")
        return "\n".join(lines)

    def _warped_psnr(self, name, luma, reference, index):
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
