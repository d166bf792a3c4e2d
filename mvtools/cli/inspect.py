"""``mvtools inspect``: describe and validate videos, camera files and VSRS/DERS configurations."""

from __future__ import annotations

import re
from pathlib import Path

import click
import numpy as np

from mvtools.cli.options import (
    ProgramCommand,
    data_dir_option,
    program,
    transposed_rotation_option,
    video_format_options,
)
from mvtools.errors import UsageError
from mvtools.geometry.camera import Camera
from mvtools.io.cameras import read_cameras, read_htm_cameras
from mvtools.io.config import read_htm_config
from mvtools.io.inputs import open_input_video
from mvtools.io.json_cameras import read_json_cameras
from mvtools.io.loaded_config import LoadedConfig, load_config
from mvtools.params import DersParams, VsrsParams, param_specs

KINDS = ("video", "cameras", "json-cameras", "htm-cameras", "vsrs", "ders", "htm-config")
_KEY_LINE = re.compile(r"^\s*([A-Za-z]\w*)[ \t]")
_HTM_KEY_LINE = re.compile(r"^\s*\w+\s*:")
_NUMBERS_LINE = re.compile(r"^[\s0-9.eE+-]*$")


@click.command(name="inspect", cls=ProgramCommand)
@click.argument("files", nargs=-1, required=True, metavar="FILE... [Key=Value]...")
@click.option(
    "--as",
    "kind",
    type=click.Choice(KINDS),
    default=None,
    help="What the files are (default: from the extension and the content).",
)
@video_format_options
@data_dir_option
@transposed_rotation_option
@program
def command(files, kind, size, pix_fmt, data_dirs, transposed_rotation):
    """Describe FILEs and check that they can be used.

    \b
    Videos (.yuv, .y4m): format and number of frames.
    Camera files (MPEG text, MPEG-I JSON): every camera's intrinsics, centre, viewing
    direction and distance to the previous camera.
    VSRS and DERS configurations: every parameter and where it came from, the input
    files found, the cameras, and the videos' formats; Key=Value items override
    the file as on the reference programs' command lines.

    Exits with 0 when everything is usable, 2 for a bad configuration or camera
    file, 1 for damaged data, with a one-line message naming the place at fault.
    """
    overrides = [item for item in files if "=" in item and not Path(item).exists()]
    paths = [Path(item) for item in files if item not in overrides]
    if overrides and len(paths) != 1:
        raise UsageError("Key=Value items go with exactly one configuration file")
    for path in paths:
        file_kind = kind or _detect(path)
        if file_kind == "video":
            click.echo(_describe_video(path, size, pix_fmt))
        elif file_kind in CAMERA_READERS:
            cameras = (
                read_cameras(path, transposed_rotation=transposed_rotation)
                if file_kind == "cameras"
                else CAMERA_READERS[file_kind](path)
            )
            click.echo(f"{path}: {len(cameras)} cameras\n{_camera_table(cameras.values())}")
        elif file_kind == "htm-config":
            entries = read_htm_config(path)
            click.echo(f"{path}: 3D-HTM encoder configuration, {len(entries)} keys")
            click.echo("\n".join(f"  {entry.key:<30} {entry.value}" for entry in entries.values()))
        else:
            cls = VsrsParams if file_kind == "vsrs" else DersParams
            loaded = load_config(
                cls,
                path,
                overrides=overrides,
                data_dirs=data_dirs,
                transposed_rotation=transposed_rotation,
            )
            click.echo(_describe_config(path, loaded))


CAMERA_READERS = {
    "cameras": read_cameras,
    "json-cameras": read_json_cameras,
    "htm-cameras": read_htm_cameras,
}


def _detect(path: Path) -> str:
    suffix = path.suffix.lower()
    if suffix in (".yuv", ".y4m"):
        return "video"
    if suffix == ".json":
        return "json-cameras"
    try:
        text = path.read_text(errors="replace")
    except FileNotFoundError:
        raise UsageError("no such file", path=path) from None
    lines = [
        line for line in text.splitlines() if line.strip() and not line.lstrip().startswith("#")
    ]
    if lines and all(_HTM_KEY_LINE.match(line) for line in lines):
        return "htm-config"
    if lines and all(_NUMBERS_LINE.match(line) for line in lines):
        return "htm-cameras"
    keys = {match.group(1) for match in map(_KEY_LINE.match, lines) if match}
    vsrs_keys = {spec.key for spec in param_specs(VsrsParams)}
    ders_keys = {spec.key for spec in param_specs(DersParams)}
    if keys & (ders_keys - vsrs_keys):
        return "ders"
    if keys & (vsrs_keys - ders_keys):
        return "vsrs"
    return "cameras"


def _describe_video(path: Path, size, pix_fmt) -> str:
    with open_input_video(path, size, pix_fmt) as video:
        return f"{path}: {video.format}, {len(video)} frames of {video.format.frame_bytes} bytes"


def _camera_table(cameras) -> str:
    lines = [
        f"{'name':<20}{'fx':>11}{'fy':>11}{'cx':>10}{'cy':>10}   {'centre (x, y, z)':<32}"
        f"{'viewing direction':<24}{'to previous':>12}"
    ]
    previous: Camera | None = None
    for camera in cameras:
        centre = ", ".join(f"{value:.4g}" for value in camera.t)
        axis = ", ".join(f"{value:+.3f}" for value in camera.optical_axis)
        step = "" if previous is None else f"{np.linalg.norm(camera.t - previous.t):12.5g}"
        lines.append(
            f"{camera.name:<20}{camera.fx:11.3f}{camera.fy:11.3f}{camera.cx:10.2f}"
            f"{camera.cy:10.2f}   {'(' + centre + ')':<32}{'(' + axis + ')':<24}{step}"
        )
        previous = camera
    return "\n".join(lines)


def _describe_config(path: Path, loaded: LoadedConfig) -> str:
    params = loaded.params
    lines = [f"{path}: {params.program} configuration"]
    for spec in param_specs(type(params)):
        source = loaded.sources.get(spec.name)
        if source is None:
            where = "default"
        else:
            where = f"line {source.line}" if source.line is not None else source.path
        lines.append(f"  {spec.key:<30} {getattr(params, spec.name)!s:<30}  ({where})")
    lines.append("files found:")
    lines += [f"  {name:<36}{found}" for name, found in loaded.inputs.items()]
    lines += [f"  {name:<36}{found} (output)" for name, found in loaded.outputs.items()]
    if loaded.cameras:
        lines.append("cameras:")
        lines.append(_camera_table(loaded.cameras.values()))
    lines.append("videos:")
    lengths = []
    for name in loaded.video_fields:
        with loaded.open_video(name) as video:
            lines.append(f"  {name:<36}{video.format}, {len(video)} frames")
            lengths.append(len(video))
    wanted = params.start_frame + params.total_number_of_frames
    if lengths and min(lengths) < wanted:
        usable = max(min(lengths) - params.start_frame, 0)
        lines.append(
            f"note: StartFrame + TotalNumberOfFrames = {wanted} but the shortest input has "
            f"{min(lengths)} frames: {usable} frames would be processed"
        )
    return "\n".join(lines)
