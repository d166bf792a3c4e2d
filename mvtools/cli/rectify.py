"""``mvtools rectify``: lens distortion removal and rectification of a camera array."""

from __future__ import annotations

import logging
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING

import click
import numpy as np

from mvtools.cli.options import (
    DEPTH,
    FiniteFloat,
    ProgramCommand,
    frame_range_options,
    parse_size,
    program,
    transposed_rotation_option,
    video_format_options,
)
from mvtools.cli.progress import Progress
from mvtools.errors import DataError, UsageError, at_fault
from mvtools.geometry.camera import turn_world
from mvtools.geometry.depth import DepthCoding, check_depth_range
from mvtools.io.atomic import output_folder_exists
from mvtools.io.cameras import get_camera, write_cameras
from mvtools.io.chroma import CHROMA_SUBSAMPLING
from mvtools.io.guard import check_output
from mvtools.io.inputs import frame_range, open_input_video
from mvtools.io.json_cameras import read_camera_file, write_json_cameras
from mvtools.io.yuv import open_writer

if TYPE_CHECKING:
    from mvtools.rectification import Rectification

LOG = logging.getLogger("mvtools")

# Centres further than this fraction of the mean neighbour distance off the common line
# make the 1D modes of synthesize and estimate-depth visibly approximate.
_OFF_LINE_WARNING = 0.01


@click.command(name="rectify", cls=ProgramCommand)
@click.argument("camera_file", type=click.Path(dir_okay=False))
@click.option(
    "--camera",
    "camera_names",
    multiple=True,
    metavar="NAME",
    help="A camera of the array, in order along it (repeatable; default: the "
    "cameras of --texture and --depth, in the order given).",
)
@click.option(
    "--texture",
    "textures",
    multiple=True,
    nargs=2,
    metavar="CAMERA VIDEO",
    help="A texture video of a camera to rectify (repeatable).",
)
@click.option(
    "--depth",
    "depths",
    multiple=True,
    nargs=2,
    metavar="CAMERA VIDEO",
    help="A depth map video of a camera (MPEG: 255 or 65535 = Znear), sampled at the "
    "nearest pixel and re-measured along the rectified camera's axis "
    "(repeatable).",
)
@click.option(
    "--depth-range",
    nargs=2,
    type=DEPTH,
    default=None,
    metavar="ZNEAR ZFAR",
    help="Znear and Zfar of the depth maps (default: the cameras' Depth_range of an "
    "MPEG-I JSON camera file); the output keeps them.",
)
@click.option(
    "--undistort",
    "undistort_only",
    is_flag=True,
    help="Only remove the lens distortion: every camera keeps its orientation.",
)
@click.option(
    "--keep-world",
    is_flag=True,
    help="Describe the rectified cameras in the input's world frame. By default the "
    "world frame turns with them, so that their rotations are the identity and "
    "the centres lie along x, as VSRS's and DERS's 1D modes read camera files.",
)
@click.option(
    "--alpha",
    type=FiniteFloat(0.0, 1.0),
    default=0.0,
    show_default=True,
    help="Kept field of view: 0 crops so that every output pixel is valid, 1 keeps "
    "every source pixel (with empty borders), values between interpolate.",
)
@click.option(
    "--virtual",
    "virtual_count",
    type=click.IntRange(min=0),
    default=0,
    show_default=True,
    help="Virtual cameras to add to the camera file between each pair of neighbours, "
    "evenly spaced (named LEFT_RIGHT_k), for the views synthesized in between.",
)
@click.option(
    "-o",
    "--out-dir",
    required=True,
    type=click.Path(file_okay=False),
    help="Folder for the rectified videos (named as their inputs) and the cameras.",
)
@click.option(
    "--cameras-out",
    default=None,
    type=click.Path(dir_okay=False),
    help="Camera file of the rectified cameras (default OUT_DIR/cameras.txt; a .json "
    "name writes MPEG-I JSON).",
)
@click.option(
    "--camera-size",
    callback=parse_size,
    default=None,
    metavar="WxH",
    help="Picture size of cameras that have no video here and no size in the camera "
    "file (MPEG camera parameter files carry none).",
)
@video_format_options
@frame_range_options
@transposed_rotation_option
@program
def command(
    camera_file,
    camera_names,
    textures,
    depths,
    depth_range,
    undistort_only,
    keep_world,
    virtual_count,
    alpha,
    out_dir,
    cameras_out,
    camera_size,
    size,
    pix_fmt,
    start_frame,
    frame_count,
    transposed_rotation,
):
    """Rectify the cameras of CAMERA_FILE (a pair or a linear array) and their videos.

    Rectified cameras share one orientation (x along the line of the centres) and one
    intrinsic matrix, and have no lens distortion, so that epipolar lines are rows and
    the 1D modes of synthesize and estimate-depth apply. The camera centres stay where
    they are. Each camera's look-up table is computed once and applied to every frame:
    textures are sampled bilinearly (chroma at its own resolution), depth maps at the
    nearest pixel.
    """
    if depth_range is not None:
        with at_fault(UsageError, key="--depth-range"):
            check_depth_range(*depth_range)
    cameras = read_camera_file(camera_file, transposed_rotation=transposed_rotation)
    names = list(camera_names) or list(dict.fromkeys(name for name, _ in (*textures, *depths)))
    if not names:
        raise UsageError("name the cameras to rectify with --camera, --texture or --depth")
    if virtual_count and undistort_only:
        raise UsageError("--virtual cameras go between rectified cameras, not with --undistort")
    if len(names) < 2 and not undistort_only:
        raise UsageError(
            f"rectifying needs at least two cameras (a pair or a linear array), "
            f"got {', '.join(names)}; --undistort works on one"
        )
    videos = {
        "texture": _videos_by_camera(textures, names, "--texture"),
        "depth": _videos_by_camera(depths, names, "--depth"),
    }
    selected = [
        _sized_camera(
            get_camera(cameras, name, path=camera_file), videos, camera_size, size, pix_fmt
        )
        for name in names
    ]
    if len({camera.size for camera in selected}) > 1:
        listed = ", ".join(
            f"{camera.name} {camera.size[0]}x{camera.size[1]}" for camera in selected
        )
        raise DataError(
            f"the cameras differ in picture size ({listed}); rectified cameras share one"
        )
    index_of = {name: index for index, name in enumerate(names)}
    depth_ranges = {
        name: _depth_range_of(selected[index_of[name]], depth_range, path)
        for name, path in videos["depth"].items()
    }
    out = Path(out_dir)
    camera_target = Path(cameras_out) if cameras_out else out / "cameras.txt"
    targets = _outputs(videos, out, camera_target)
    # the rectification's maps and warps load OpenCV: for a run, not for --help
    from mvtools.rectification import cameras_between, rectify_cameras, undistortion

    with at_fault(DataError, path=camera_file):
        if undistort_only:
            result = undistortion(selected, alpha=alpha)
        else:
            result = rectify_cameras(selected, alpha=alpha)
    _log_warps(result, undistort_only)
    for kind, by_camera in videos.items():
        for name, path in by_camera.items():
            index = index_of[name]
            _rectify_video(
                Path(path),
                targets[kind, name],
                kind,
                result,
                index,
                selected[index],
                size,
                pix_fmt,
                start_frame,
                frame_count,
                depth_ranges.get(name),
            )
    described = result.cameras
    if virtual_count:
        described = described + cameras_between(described, virtual_count)
    if not (undistort_only or keep_world):
        described = turn_world(described, described[0].R)
    out.mkdir(parents=True, exist_ok=True)
    _write_cameras(camera_target, described)
    click.echo(_summary(result, undistort_only))


def _videos_by_camera(pairs, names, option) -> dict[str, str]:
    by_camera: dict[str, str] = {}
    for name, path in pairs:
        if name not in names:
            raise UsageError(
                f"{option} {name} {path}: {name} is not among the cameras "
                f"rectified ({', '.join(names)})"
            )
        if name in by_camera:
            raise UsageError(f"{option} given twice for camera {name}")
        by_camera[name] = path
    return by_camera


def _outputs(videos, out: Path, camera_target: Path) -> dict[tuple[str, str], Path]:
    """The rectified video of each (kind, camera): OUT_DIR/its input's name.

    The outputs are refused now, before the work, rather than when each is written,
    which would leave the videos written before it: no two alike (two inputs of one
    name in two folders would collide), none an input (the guard's rule; the inputs
    have been read), and the camera file's folder either OUT_DIR, which is created, or
    one that exists.
    """
    targets: dict[tuple[str, str], Path] = {}
    written: dict[Path, str] = {}
    for kind, by_camera in videos.items():
        for name, path in by_camera.items():
            target = targets[kind, name] = out / Path(path).name
            if target.resolve() in written:
                raise UsageError(
                    f"{written[target.resolve()]} and {path} would both be "
                    f"written to {target}: rename one"
                )
            written[target.resolve()] = path
    if camera_target.resolve() in written:
        raise UsageError(
            f"the camera file would replace the rectified "
            f"{written[camera_target.resolve()]}: give another --cameras-out",
            path=camera_target,
        )
    for target in (*targets.values(), camera_target):
        check_output(target)
    if camera_target.parent.resolve() != out.resolve():
        output_folder_exists(camera_target.parent)
    return targets


def _sized_camera(camera, videos, camera_size, size, pix_fmt):
    """The camera with its picture size: from its videos, else the camera file, else
    --camera-size."""
    sizes = {}
    for by_camera in videos.values():
        if camera.name in by_camera:
            with open_input_video(by_camera[camera.name], size, pix_fmt) as video:
                sizes[by_camera[camera.name]] = video.format.size
    if len(set(sizes.values())) > 1:
        listed = ", ".join(f"{path} is {w}x{h}" for path, (w, h) in sizes.items())
        raise DataError(f"camera {camera.name}: its videos differ in size ({listed})")
    found = next(iter(sizes.values()), None) or camera.size or camera_size
    if found is None:
        raise UsageError(
            f"camera {camera.name} has no picture size: give its video or --camera-size WxH"
        )
    if camera.size is not None and tuple(camera.size) != tuple(found):
        raise DataError(
            f"camera {camera.name} is {camera.size[0]}x{camera.size[1]} in the "
            f"camera file but its video is {found[0]}x{found[1]}"
        )
    return replace(camera, size=tuple(found))


def _log_warps(result: Rectification, undistort_only: bool) -> None:
    for camera, valid, kept in zip(result.cameras, result.valid_fraction, result.kept_fraction):
        LOG.info(
            "%s: %.1f %% of the output samples the source, %.1f %% of the source is kept",
            camera.name,
            100 * valid,
            100 * kept,
        )
    if undistort_only or len(result.cameras) < 2:
        return
    centres = np.array([camera.t for camera in result.cameras])
    spacing = np.mean(np.linalg.norm(np.diff(centres, axis=0), axis=1))
    for camera, offset in zip(result.cameras, result.centre_offsets):
        if offset > _OFF_LINE_WARNING * spacing:
            LOG.warning(
                "%s: the camera centre is %.3g off the array's line (%.1f %% of the "
                "camera spacing): rows agree only approximately, depending on depth",
                camera.name,
                offset,
                100 * offset / spacing,
            )


def _write_cameras(path: Path, cameras) -> None:
    if path.suffix.lower() == ".json":
        write_json_cameras(path, cameras)
    else:
        write_cameras(path, cameras)


def _depth_range_of(camera, depth_range, path) -> tuple[float, float]:
    """--depth-range (checked), else the camera's (the camera file's reader checks it)."""
    if depth_range is None and camera.depth_range is None:
        raise UsageError(
            "the depth map's Znear and Zfar are unknown: give --depth-range ZNEAR ZFAR", path=path
        )
    return tuple(depth_range if depth_range is not None else camera.depth_range)


def _rectify_video(
    path: Path,
    target: Path,
    kind: str,
    result: Rectification,
    index: int,
    source_camera,
    size,
    pix_fmt,
    start_frame,
    frame_count,
    depth_range,
) -> None:
    from mvtools.rectification import DepthResampler, chroma_maps, remap_plane

    map_x, map_y = result.maps[index]
    with open_input_video(path, size, pix_fmt) as video:
        fmt = video.format
        frames = frame_range([video], start_frame, frame_count)
        mid = 1 << (fmt.bits - 1)
        factors = CHROMA_SUBSAMPLING[fmt.chroma]
        chroma = chroma_maps(map_x, map_y, subsampling=factors) if factors else None
        if kind == "depth":
            coding = DepthCoding(depth_range, fmt.bits)
            resample = DepthResampler(source_camera, result.cameras[index], map_x, map_y)
        progress = Progress(len(frames), f"{path.name} frames rectified")
        # OUT_DIR is made once the run is known to be good: a refused run leaves none
        target.parent.mkdir(parents=True, exist_ok=True)
        with open_writer(target, fmt) as writer:
            for frame in frames:
                planes = video.read(frame)
                if kind == "depth":
                    # Depths along the axes, as positive as the facing cameras' (the
                    # rectified axis measures them alike: the factor is positive).
                    luma = coding.values(resample(coding.z(planes[0])))
                    # Outside the source there is no depth: the farthest value.
                    rest = [np.full_like(plane, mid) for plane in planes[1:]]
                else:
                    black = 16 << (fmt.bits - 8)
                    luma = remap_plane(planes[0], map_x, map_y, fill=black)
                    rest = [remap_plane(plane, *chroma, fill=mid) for plane in planes[1:]]
                writer.write([luma, *rest])
                progress.advance()


def _summary(result: Rectification, undistort_only: bool) -> str:
    lines = [
        f"{'camera':10s} {'fx':>9s} {'cx':>8s} {'cy':>8s} {'valid %':>8s} {'kept %':>7s} "
        f"{'off line':>9s}  homography (undistorted source -> output)"
    ]
    for camera, valid, kept, offset, warp in zip(
        result.cameras,
        result.valid_fraction,
        result.kept_fraction,
        result.centre_offsets,
        result.homographies,
    ):
        rows = " / ".join(" ".join(f"{value:.6g}" for value in row) for row in warp)
        lines.append(
            f"{camera.name:10s} {camera.fx:9.2f} {camera.cx:8.2f} {camera.cy:8.2f} "
            f"{100 * valid:8.2f} {100 * kept:7.2f} {offset:9.3g}  {rows}"
        )
    return "\n".join(lines)
