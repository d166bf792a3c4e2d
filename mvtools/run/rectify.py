"""Lens distortion removal and rectification of a camera array's videos: the run
functions of ``mvtools rectify``.

:func:`rectify_video` resamples one opened video through one camera's maps;
:func:`rectify_videos` rectifies the cameras of an array, their texture and depth
videos by file and writes the rectified videos and camera file, as the program does.
The maps themselves are :func:`mvtools.rectification.rectify_cameras` and
:func:`mvtools.rectification.undistortion` (the chapter's fig. 1.16), imported when a
run starts (they load OpenCV), so this module is cheap to import.
"""

from __future__ import annotations

import contextlib
import logging
import os
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from mvtools.errors import DataError, UsageError, at_fault
from mvtools.geometry.camera import Camera, turn_world
from mvtools.geometry.depth import DepthCoding
from mvtools.io.atomic import output_folder_exists
from mvtools.io.camera_files import write_camera_file
from mvtools.io.chroma import CHROMA_SUBSAMPLING
from mvtools.io.guard import check_output
from mvtools.io.inputs import frame_range, open_input_video
from mvtools.io.yuv import VideoReader, open_writer
from mvtools.run.stream import ProgressCallback, stream_frames

if TYPE_CHECKING:
    from mvtools.rectification import Rectification

LOG = logging.getLogger(__name__)

#: The kinds of video a camera may have, in the order they are rectified.
VIDEO_KINDS = ("texture", "depth")

# Centres further than this fraction of the mean neighbour distance off the common line
# make the 1D modes of synthesize and estimate-depth visibly approximate.
_OFF_LINE_WARNING = 0.01


@dataclass(frozen=True)
class RectifyOptions:
    """How an array is rectified (the options of ``mvtools rectify``).

    Attributes
    ----------
    undistort_only : bool
        Only remove the lens distortion: every camera keeps its orientation
        (:func:`mvtools.rectification.undistortion`).
    alpha : float
        Kept field of view in [0, 1]: 0 crops so that every output pixel is valid, 1
        keeps every source pixel (with empty borders).
    virtual_count : int
        Virtual cameras added to the camera file between each pair of neighbours,
        evenly spaced (:func:`mvtools.rectification.cameras_between`).
    keep_world : bool
        Describe the rectified cameras in the input's world frame; otherwise the world
        turns with them (identity rotations, centres along x), as VSRS's and DERS's 1D
        modes read camera files.
    depth_range : (float, float), optional
        Znear and Zfar of the depth videos (default: each camera's ``depth_range``);
        the output keeps them.
    camera_size : (int, int), optional
        Picture size of cameras that have no video and no size of their own.

    Raises
    ------
    UsageError
        Virtual cameras asked for with ``undistort_only``.
    """

    undistort_only: bool = False
    alpha: float = 0.0
    virtual_count: int = 0
    keep_world: bool = False
    depth_range: tuple[float, float] | None = None
    camera_size: tuple[int, int] | None = None

    def __post_init__(self):
        if self.virtual_count and self.undistort_only:
            raise UsageError("--virtual cameras go between rectified cameras, not with --undistort")


@dataclass(frozen=True)
class RectifiedArray:
    """What :func:`rectify_videos` computed and wrote.

    Attributes
    ----------
    rectification : Rectification
        The rectified (or undistorted) cameras, their maps and measures.
    cameras : list of Camera
        The cameras of the camera file written: the rectified ones, the virtual ones
        after them, in the turned world unless ``keep_world`` or ``undistort_only``.
    videos : dict of (str, str) to Path
        The rectified video of each ``(kind, camera name)``.
    camera_file : Path
        The camera file written.
    """

    rectification: Rectification
    cameras: list[Camera]
    videos: dict[tuple[str, str], Path]
    camera_file: Path


def rectify_video(
    reader: VideoReader,
    writer,
    rectification: Rectification,
    index: int,
    *,
    depth_coding: DepthCoding | None = None,
    frames: range | None = None,
    progress: ProgressCallback | None = None,
) -> None:
    """Resample the frames of camera ``index``'s video through its map and write them.

    A texture is sampled bilinearly, its chroma at the chroma's own resolution, with
    black luma and mid-grey chroma outside the source picture. A depth map
    (``depth_coding`` given) is sampled at the nearest pixel and its depths are
    re-measured along the rectified camera's axis
    (:class:`mvtools.rectification.DepthResampler`); outside the source it takes the
    farthest value.

    Parameters
    ----------
    reader : VideoReader
        The video of ``rectification.sources[index]``, of its picture size.
    writer : writer
        Gets the rectified frames, in the reader's format (an object with
        ``write(planes)``, as :class:`mvtools.io.yuv.VideoWriter`).
    rectification : Rectification
    index : int
        The camera of ``rectification`` the video belongs to.
    depth_coding : DepthCoding, optional
        How the samples of a depth video give depths; None for a texture.
    frames : range, optional
        Frames to rectify; default every frame of the reader.
    progress : callable, optional
        ``progress(done, total)`` after each frame.
    """
    from mvtools.rectification import DepthResampler, chroma_maps, remap_plane

    map_x, map_y = rectification.maps[index]
    fmt = reader.format
    mid = 1 << (fmt.bits - 1)
    if frames is None:
        frames = range(len(reader))
    if depth_coding is not None:
        resample = DepthResampler(
            rectification.sources[index], rectification.cameras[index], map_x, map_y
        )

        def step(_, planes) -> list:
            # Depths along the axes, as positive as the facing cameras' (the rectified
            # axis measures them alike: the factor is positive).
            luma = depth_coding.values(resample(depth_coding.z(planes[0])))
            # Outside the source there is no depth: the farthest value.
            return [[luma, *(np.full_like(plane, mid) for plane in planes[1:])]]

    else:
        factors = CHROMA_SUBSAMPLING[fmt.chroma]
        chroma = chroma_maps(map_x, map_y, subsampling=factors) if factors else None
        black = 16 << (fmt.bits - 8)

        def step(_, planes) -> list:
            luma = remap_plane(planes[0], map_x, map_y, fill=black)
            return [[luma, *(remap_plane(plane, *chroma, fill=mid) for plane in planes[1:])]]

    stream_frames(frames, step, readers=[reader], writers=[writer], progress=progress)


def rectify_videos(
    cameras: Sequence[Camera],
    *,
    out_dir: str | os.PathLike,
    textures: Mapping[str, str | os.PathLike] | None = None,
    depths: Mapping[str, str | os.PathLike] | None = None,
    options: RectifyOptions | None = None,
    cameras_out: str | os.PathLike | None = None,
    size: tuple[int, int] | None = None,
    pix_fmt: str | None = None,
    start_frame: int = 0,
    frame_count: int | None = None,
    camera_file: str | os.PathLike | None = None,
    video_progress: Callable[[Path], ProgressCallback | None] | None = None,
) -> RectifiedArray:
    """Rectify an array's cameras and videos and write them, as ``mvtools rectify`` does.

    Every input is opened and every output refused (two alike, one naming an input)
    before any work; a refused run leaves no ``out_dir``.

    Parameters
    ----------
    cameras : sequence of Camera
        The array in order along it (at least two, or one with ``undistort_only``);
        a camera without a size takes its videos' (or ``options.camera_size``).
    out_dir : path
        Folder of the rectified videos, each named as its input, and by default of
        the camera file.
    textures, depths : mapping of str to path, optional
        The texture and depth videos to rectify, by camera name.
    options : RectifyOptions, optional
    cameras_out : path, optional
        The camera file (default ``out_dir/cameras.txt``; a ``.json`` name writes
        MPEG-I JSON). Its folder is ``out_dir`` or one that exists.
    size, pix_fmt : optional
        The videos' picture size and pixel format when their names or headers do not
        say (:func:`mvtools.io.inputs.open_input_video`).
    start_frame, frame_count : int, optional
        The frames of each video to rectify (default: all from ``start_frame``).
    camera_file : path, optional
        The file the cameras were read from, named in the errors of their geometry.
    video_progress : callable, optional
        ``video_progress(path)`` gives the progress callback of the video read from
        ``path``, called ``(done, total)`` after each of its frames.

    Returns
    -------
    RectifiedArray

    Raises
    ------
    UsageError
        Too few cameras, a video for a camera not in ``cameras``, a camera without
        a size, a depth video without a depth range, outputs that collide.
    DataError
        Cameras or videos of different sizes, or cameras that cannot be rectified.
    """
    from mvtools.rectification import cameras_between, rectify_cameras, undistortion

    options = options or RectifyOptions()
    names = [camera.name for camera in cameras]
    if len(names) < 2 and not options.undistort_only:
        raise UsageError(
            f"rectifying needs at least two cameras (a pair or a linear array), "
            f"got {', '.join(names)}; --undistort works on one"
        )
    videos = {"texture": dict(textures or {}), "depth": dict(depths or {})}
    for kind, by_camera in videos.items():
        for name, path in by_camera.items():
            if name not in names:
                raise UsageError(
                    f"--{kind} {name} {path}: {name} is not among the cameras "
                    f"rectified ({', '.join(names)})"
                )
    out = Path(out_dir)
    camera_target = Path(cameras_out) if cameras_out else out / "cameras.txt"
    with contextlib.ExitStack() as stack:
        readers: dict[tuple[str, str], VideoReader] = {}
        for name in names:
            for kind in VIDEO_KINDS:
                if name in videos[kind]:
                    reader = open_input_video(videos[kind][name], size, pix_fmt)
                    readers[kind, name] = stack.enter_context(reader)
        selected = [_sized_camera(camera, readers, options.camera_size) for camera in cameras]
        if len({camera.size for camera in selected}) > 1:
            listed = ", ".join(
                f"{camera.name} {camera.size[0]}x{camera.size[1]}" for camera in selected
            )
            raise DataError(
                f"the cameras differ in picture size ({listed}); rectified cameras share one"
            )
        index_of = {name: index for index, name in enumerate(names)}
        depth_ranges = {
            name: _depth_range_of(selected[index_of[name]], options.depth_range, path)
            for name, path in videos["depth"].items()
        }
        targets = _outputs(videos, out, camera_target)
        with at_fault(DataError, path=camera_file):
            if options.undistort_only:
                result = undistortion(selected, alpha=options.alpha)
            else:
                result = rectify_cameras(selected, alpha=options.alpha)
        _log_warps(result, options.undistort_only)
        for kind, by_camera in videos.items():
            for name, path in by_camera.items():
                reader = readers[kind, name]
                frames = frame_range([reader], start_frame, frame_count)
                coding = (
                    DepthCoding(depth_ranges[name], reader.format.bits) if kind == "depth" else None
                )
                # OUT_DIR is made once the run is known to be good: a refused run leaves none
                out.mkdir(parents=True, exist_ok=True)
                with open_writer(targets[kind, name], reader.format) as writer:
                    rectify_video(
                        reader,
                        writer,
                        result,
                        index_of[name],
                        depth_coding=coding,
                        frames=frames,
                        progress=video_progress(Path(path)) if video_progress else None,
                    )
    described = result.cameras
    if options.virtual_count:
        described = described + cameras_between(described, options.virtual_count)
    if not (options.undistort_only or options.keep_world):
        described = turn_world(described, described[0].R)
    out.mkdir(parents=True, exist_ok=True)
    write_camera_file(camera_target, described)
    return RectifiedArray(result, described, targets, camera_target)


def _outputs(videos, out: Path, camera_target: Path) -> dict[tuple[str, str], Path]:
    """The rectified video of each (kind, camera): OUT_DIR/its input's name.

    The outputs are refused now, before the work, rather than when each is written,
    which would leave the videos written before it: no two alike (two inputs of one
    name in two folders would collide), none an input (the guard's rule; the inputs
    are open), and the camera file's folder either OUT_DIR, which is created, or one
    that exists.
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


def _sized_camera(camera: Camera, readers, camera_size) -> Camera:
    """The camera with its picture size: from its videos, else its own, else
    ``camera_size``."""
    sizes = {
        reader.path: reader.format.size
        for (_, name), reader in readers.items()
        if name == camera.name
    }
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


def _depth_range_of(camera: Camera, depth_range, path) -> tuple[float, float]:
    """The depth range given, else the camera's (the camera file's reader checks it)."""
    if depth_range is None and camera.depth_range is None:
        raise UsageError(
            "the depth map's Znear and Zfar are unknown: give --depth-range ZNEAR ZFAR", path=path
        )
    return tuple(depth_range if depth_range is not None else camera.depth_range)


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
