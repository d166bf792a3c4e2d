"""``mvtools report``: one self-contained HTML page of what a pipeline wrote."""

from __future__ import annotations

import contextlib
import logging
import math
import re
from collections.abc import Iterator
from pathlib import Path

import click
import numpy as np

from mvtools.cli.options import ProgramCommand, program
from mvtools.color import yuv_to_rgb
from mvtools.color.levels import depth_preview
from mvtools.errors import ConfigError, DataError, UsageError
from mvtools.io.atomic import atomic_output, output_folder_exists
from mvtools.io.files import read_bytes, read_json, read_text
from mvtools.io.images import encode_image, read_image
from mvtools.io.yuv import format_from_name, open_video
from mvtools.report import Picture, Plot, Section, Table, bar_plot, html_page, line_plot

LOG = logging.getLogger("mvtools")

# Enough pictures to see every stage, few enough to keep the page light.
MAX_PICTURES = 100


@click.command(name="report", cls=ProgramCommand)
@click.argument("build_dir", type=click.Path(file_okay=False))
@click.option(
    "-o",
    "--output",
    type=click.Path(dir_okay=False),
    default=None,
    help="The page (default BUILD_DIR/report.html).",
)
@click.option("--title", default=None, help="The page's title (default: the folder's name).")
@program
def command(build_dir, output, title):
    """Write an HTML page of the results under BUILD_DIR: calibration errors per capture
    (plot and table) with the corner pictures, the first frame of every video (depth maps
    colour-mapped), the scores mvtools evaluate wrote (*.scores: the table, a plot of the
    luma PSNR along the frames, infinite values of identical frames left out, and a
    contact sheet of up to 6 frames spread over the videos, first and last included, each
    a row of reference | test | luma error x4), the disparity error histograms of its
    --depth and --disparity scores (*.errors.json, from --json), and rate-distortion
    curves with Bjontegaard deltas from mvtools encode. Pictures are embedded: the page
    is one file.
    """
    folder = Path(build_dir)
    if not folder.is_dir():
        raise UsageError("no such folder", path=folder)
    output = Path(output) if output else folder / "report.html"
    # before the videos are read, not after: the page is written last
    output_folder_exists(output.parent)
    sections = [
        _calibrations(folder),
        _pictures(folder),
        _scores(folder),
        _depth_errors(folder),
        _compressions(folder),
    ]
    page = html_page(title or f"mvtools report of {folder.resolve().name}", sections)
    with atomic_output(output, "w") as handle:
        handle.write(page)
    LOG.info("wrote %s (%d sections)", output, sum(bool(section.items) for section in sections))


def _reports(folder: Path, key: str):
    """``(path, document)`` of the ``report.json`` files under ``folder`` that have ``key``."""
    for path in sorted(folder.rglob("report.json")):
        document = read_json(path)
        if isinstance(document, dict) and key in document:
            yield path, document


@contextlib.contextmanager
def _document(path: Path, what: str) -> Iterator[None]:
    """The scope in which the fields of ``path``, a file another program wrote, are read:
    a field that is missing or of the wrong kind is a ConfigError naming the file (and a
    missing key), not a traceback. ``what`` names what the file should be."""
    try:
        yield
    except KeyError as error:
        raise ConfigError(f"not {what}: it has no {error.args[0]!r}", path=path) from error
    except (TypeError, ValueError, IndexError, AttributeError) as error:
        raise ConfigError(f"not {what}: {error}", path=path) from error


def _calibrations(folder: Path) -> Section:
    section = Section("Calibration")
    for path, document in _reports(folder, "baselines_m"):
        with _document(path, "the calibration report of mvtools calibrate"):
            cameras = [
                _expect(camera, dict, "camera")
                for camera in _expect(document["cameras"], list, "cameras")
            ]
            section.items.append(
                Table(
                    f"{path.parent.relative_to(folder)}: cameras",
                    ("camera", "fx", "fy", "cx", "cy", "K1", "K2", "RMS px", "captures"),
                    [
                        (
                            camera["name"],
                            camera["K"][0][0],
                            camera["K"][1][1],
                            camera["K"][0][2],
                            camera["K"][1][2],
                            camera["distortion"]["K1"],
                            camera["distortion"]["K2"],
                            camera["rms_px"],
                            len(camera["captures_used"]),
                        )
                        for camera in cameras
                    ],
                )
            )
            errors = {
                camera["name"]: [float(rms) for rms in camera["capture_rms_px"].values()]
                for camera in cameras
            }
            section.items.append(
                Plot(
                    "reprojection error of every capture used (px RMS), per camera",
                    bar_plot(errors, y_label="px RMS"),
                )
            )
        section.items += [
            Picture(picture.stem, read_bytes(picture, "picture"))
            for picture in sorted(path.parent.glob("*_corners.png"))
        ]
    return section


def _first_frame(path: Path) -> np.ndarray | None:
    fmt = format_from_name(path)
    if fmt is None:
        return None
    with open_video(path, fmt) as video:
        if len(video) == 0:
            return None
        return _rgb(video.read(0), fmt, path)


def _rgb(planes, fmt, path: Path) -> np.ndarray | None:
    """A frame's planes as an 8-bit RGB picture (a depth map colour-mapped), or None for
    a texture of more than 8 bits."""
    if "depth" in path.name:
        return depth_preview(np.asarray(planes[0]), bits=fmt.bits)
    return yuv_to_rgb(planes, bits=fmt.bits) if fmt.bits == 8 else None


def _pictures(folder: Path) -> Section:
    section = Section("Pictures (first frames; depth maps colour-mapped, red near)")
    # the many decoded videos of a rate-distortion run are shown by its curves instead
    encoded = {path.parent for path, _ in _reports(folder, "modes")}
    for path in sorted(folder.rglob("*.yuv")):
        if encoded.intersection(path.parents):
            continue
        if len(section.items) >= MAX_PICTURES:
            LOG.warning("%s: more than %d videos; the report shows the first", folder, MAX_PICTURES)
            break
        picture = _first_frame(path)
        if picture is not None:
            section.items.append(Picture(str(path.relative_to(folder)), encode_image(picture)))
    for path in sorted(folder.rglob("*.png")):
        if len(section.items) >= MAX_PICTURES:
            break
        if not path.name.endswith("_corners.png"):
            section.items.append(
                Picture(str(path.relative_to(folder)), encode_image(read_image(path)))
            )
    return section


def _scores(folder: Path) -> Section:
    """The tables of the *.scores files (mvtools evaluate's output), each with a plot of
    its luma PSNR along the frames (two frames or more) and a contact sheet of up to
    :data:`SHEET_FRAMES` of its frames: reference | test | luma error (the first frame
    alone when one frame was scored)."""
    section = Section("Scores (reference | test | luma error x4)")
    for path in sorted(folder.rglob("*.scores")):
        text = read_text(path, "scores file")
        # a table is text; a NUL byte says that this is some other file named so
        if "\0" in text:
            raise DataError("not the table of mvtools evaluate: the file is not text", path=path)
        lines = [line.split() for line in text.splitlines()]
        header = next((line for line in lines if line and line[0] == "frame"), None)
        if header is None:
            continue
        rows = [line for line in lines if len(line) == len(header) and line[0] != "frame"]
        name = str(path.relative_to(folder))
        section.items.append(Table(name, header, rows))
        frames = {int(row[0]): row for row in rows if row[0].isdigit()}
        plot = _score_plot(name, header, frames)
        if plot is not None:
            section.items.append(plot)
        videos = {
            line[0]: Path(line[1])
            for line in lines
            if len(line) >= 2 and line[0] in ("reference", "test")
        }
        if set(videos) == {"reference", "test"} and all(map(Path.exists, videos.values())):
            comparison = _comparison(videos["reference"], videos["test"], name, sorted(frames))
            if comparison is not None:
                section.items.append(comparison)
    return section


# The frames of a scores file's contact sheet, at most.
SHEET_FRAMES = 6


def _luma_psnr_columns(header: list[str]) -> list[int]:
    """The indices of the columns of ``header`` that are a luma PSNR in dB (``Y-PSNR``,
    ``psnr_y``, ``PSNR-luma`` ...), or failing that of every PSNR column (``IV-PSNR``)."""
    words = [set(re.split(r"[-_.\s]+", name.lower())) for name in header]
    psnr = [index for index, name in enumerate(words) if index > 0 and "psnr" in name]
    luma = [index for index in psnr if words[index] & {"y", "luma"}]
    return luma or psnr


def _score_plot(name: str, header: list[str], frames: dict[int, list[str]]) -> Plot | None:
    """A plot of the luma PSNR columns of the table's rows ``frames`` (frame index to
    row) along the frames, when there are two frames or more; infinite PSNRs (identical
    frames) and cells that are not numbers are left out, and the caption says which."""
    columns = _luma_psnr_columns(header)
    if len(frames) < 2 or not columns:
        return None
    series, left_out = {}, set()
    for column in columns:
        points = []
        for frame, row in frames.items():
            try:
                value = float(row[column])
            except ValueError:
                value = math.nan
            if math.isfinite(value):
                points.append((float(frame), value))
            else:
                left_out.add(frame)
        if points:
            series[header[column]] = points
    if not series:
        return None
    caption = f"{name}: {', '.join(series)} per frame (dB)"
    if left_out:
        caption += (
            f"; frames {', '.join(map(str, sorted(left_out)))} left out "
            "(infinite PSNR: identical frames, or no number)"
        )
    return Plot(caption, line_plot(series, x_label="frame", y_label="dB"))


def _spread(frames: list[int], count: int = SHEET_FRAMES) -> list[int]:
    """At most ``count`` of ``frames`` evenly spread over them, the first and the last
    included.

    Examples
    --------
    >>> _spread(list(range(10)))
    [0, 2, 4, 5, 7, 9]
    >>> _spread([3, 4])
    [3, 4]
    """
    if len(frames) <= count:
        return list(frames)
    picks = np.round(np.linspace(0, len(frames) - 1, count)).astype(int)
    return [frames[index] for index in dict.fromkeys(picks.tolist())]


def _comparison(
    reference: Path, test: Path, caption: str, frames: list[int] | None = None
) -> Picture | None:
    """Rows of reference | test | luma error x4 of up to :data:`SHEET_FRAMES` of
    ``frames`` (default: all of the videos'), stacked in one picture; None when the
    videos cannot be shown side by side (no size in the names, more than 8 bits,
    different sizes)."""
    formats = [format_from_name(reference), format_from_name(test)]
    if None in formats:
        return None
    with open_video(reference, formats[0]) as ref_video, open_video(test, formats[1]) as test_video:
        length = min(len(ref_video), len(test_video))
        frames = [frame for frame in frames or range(length) if 0 <= frame < length]
        frames = _spread(frames or list(range(length)))
        rows = []
        # one frame at a time: a long video is never held whole
        for frame in frames:
            pictures = [
                _rgb(video.read(frame), fmt, path)
                for video, fmt, path in zip(
                    (ref_video, test_video), formats, (reference, test), strict=True
                )
            ]
            if any(picture is None for picture in pictures) or (
                pictures[0].shape != pictures[1].shape
            ):
                return None
            luma = [picture.astype(np.float64) @ (0.299, 0.587, 0.114) for picture in pictures]
            error = np.clip(np.abs(luma[0] - luma[1]) * 4, 0, 255).astype(np.uint8)
            rows.append(np.hstack([*pictures, np.repeat(error[..., None], 3, axis=2)]))
    if not rows:
        return None
    label = f"{caption}: {reference.name} | {test.name} | error"
    if len(frames) > 1:
        label += f" x4, frames {', '.join(map(str, frames))}"
    return Picture(label, encode_image(np.vstack(rows)))


def _depth_errors(folder: Path) -> Section:
    """The error histograms of ``mvtools evaluate --depth/--disparity --json`` outputs
    (``*.errors.json``) in one plot, and their scores in one table."""
    section = Section("Depth and disparity errors")
    what = "the JSON of mvtools evaluate --depth/--disparity"
    bins, percentages, rows = None, {}, []
    for path in sorted(folder.rglob("*.errors.json")):
        document = read_json(path)
        if not isinstance(document, dict) or "histogram" not in document:
            LOG.warning("%s: not %s; left out", path, what)
            continue
        name = path.name[: -len(".errors.json")]
        with _document(path, what):
            histogram = _expect(document["histogram"], dict, "histogram")
            percent = [float(value) for value in _expect(histogram["percent"], list, "percent")]
            if len(percent) != len(_expect(histogram["bins"], list, "bins")):
                raise ValueError("the histogram has not one percentage per bin")
            # one plot: every histogram has the bins of the first
            if bins is not None and list(histogram["bins"]) != bins:
                raise ValueError(f"the histogram's bins are not {bins}")
            bins = list(histogram["bins"])
            mean = document.get("mean") or {
                **{f"bad {t}": value for t, value in document["bad_all"].items()},
                "mean abs": document["mean_abs_error"],
                "RMS": document["rms_error"],
            }
            rows.append(
                (
                    name,
                    *(
                        float(mean.get(key, math.nan))
                        for key in ("bad 1", "bad 2", "mean abs", "RMS")
                    ),
                )
            )
        percentages[name] = percent
    if bins is None:
        return section
    groups = {
        label: [percent[i] for percent in percentages.values()] for i, label in enumerate(bins)
    }
    section.items.append(
        Plot(
            "% of pixels per absolute disparity error (px)",
            bar_plot(groups, y_label="% of pixels", series=list(percentages)),
        )
    )
    section.items.append(
        Table(
            "disparity errors against the ground truth",
            ("depth", "bad 1 %", "bad 2 %", "mean abs px", "RMS px"),
            rows,
        )
    )
    return section


def _compressions(folder: Path) -> Section:
    section = Section("Compression")
    for path, document in _reports(folder, "modes"):
        where = path.parent.relative_to(folder)
        with _document(path, "the rate-distortion report of mvtools encode"):
            modes = {
                mode: [
                    _expect(point, dict, f"a point of {mode}")
                    for point in _expect(points, list, mode)
                ]
                for mode, points in _expect(document["modes"], dict, "modes").items()
            }
            series = {
                mode: [
                    (_rate(point["kbps"]), float(point["mean_texture_yuv_psnr"]))
                    for point in points
                ]
                for mode, points in modes.items()
            }
            section.items.append(
                Plot(
                    f"{where}: rate-distortion (mean texture YUV-PSNR)",
                    line_plot(series, x_label="kbit/s", y_label="dB", log_x=True),
                )
            )
            section.items.append(
                Table(
                    f"{where}: rate points",
                    ("mode", "QP", "kbit/s", "YUV-PSNR"),
                    [
                        (mode, point["qp"], point["kbps"], point["mean_texture_yuv_psnr"])
                        for mode, points in modes.items()
                        for point in points
                    ],
                )
            )
            deltas = _expect(document.get("bjontegaard", {}), dict, "bjontegaard")
            if deltas:
                section.items.append(
                    Table(
                        f"{where}: packed against simulcast",
                        ("interpolation", "BD-rate %", "BD-PSNR dB"),
                        [
                            (method, values["bd_rate_percent"], values["bd_psnr_db"])
                            for method, values in deltas.items()
                        ],
                    )
                )
    return section


def _expect(value, kind: type, name: str):
    """``value`` if it is a ``kind`` (dict: a JSON object, list: an array), else a
    TypeError naming the field, for :func:`_document`."""
    if not isinstance(value, kind):
        raise TypeError(f"{name} is not a JSON {'object' if kind is dict else 'array'}")
    return value


def _rate(kbps) -> float:
    """A rate of the plot's logarithmic axis: a positive number."""
    rate = float(kbps)
    if not rate > 0:
        raise ValueError(f"a rate of {kbps} kbit/s")
    return rate
