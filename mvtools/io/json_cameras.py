"""MPEG-I sequence files: the camera descriptions (JSON) of RVS and TMIV.

The file is an object with ``Version``, ``Content_name``, ``Fps``, ``Frames_number`` and a
``cameras`` array; per camera ``Name``, ``Position`` [x, y, z], ``Rotation`` [yaw, pitch,
roll] in degrees, ``Depthmap`` (1: the camera has a depth map), ``Background``,
``Depth_range`` [near, far], ``Resolution`` [w, h], ``Projection``, ``Focal`` [fx, fy],
``Principle_point`` [cx, cy] (spelled so), and the fields that describe the camera's videos
(:class:`VideoDescription`). Only the ``Perspective`` projection is supported.
``docs/mpeg-i-json.md`` gives the conventions and the reasons for them.

Axes (OMAF): x forward, y left, z up. ``R_json = Rz(yaw) Ry(pitch) Rx(roll)`` maps
camera to world and a pixel ``(u, v)`` at depth ``d`` is the camera point
``(d, -d (u - cx) / fx, -d (v - cy) / fy)``. Our cameras look along +z with x right
and y down, so ``x_ours = M x_omaf`` with ``M = [[0, -1, 0], [0, 0, -1], [1, 0, 0]]``;
the world frame is kept as it is. Hence ``R = M R_json^T``, ``t = Position``, and
writing uses ``R_json = R^T M``.

Pixel centres: RVS and TMIV put the centre of pixel (column j, row i) at
``(j + 0.5, i + 0.5)``; the MPEG text files of VSRS and DERS, and our cameras, at
``(j, i)``. The same ray has JSON image coordinates larger by 0.5, and so has the
principal point: ``Principle_point = (cx + 0.5, cy + 0.5)``. It is written as the exact
decimal of that sum and read back with exact arithmetic, so that a camera file converted
to JSON and back keeps ``cx`` and ``cy`` to the last bit.

Depth ranges are positive distances. VSRS also reads negative Znear/Zfar: its scene then
lies at negative z in every camera's frame (``P`` and ``-P`` project alike). Such cameras
are written in the world reflected through its origin (``Position = -t``, the range
negated), where every camera sees the same picture with its scene in front of it.
"""

from __future__ import annotations

import json
import logging
import math
import os
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, replace
from fractions import Fraction
from pathlib import Path

import numpy as np

from mvtools.errors import ConfigError, UsageError
from mvtools.geometry.camera import Camera
from mvtools.io.atomic import atomic_output
from mvtools.io.cameras import store_camera
from mvtools.io.files import json_numbers, read_text

__all__ = [
    "JSON_VERSION",
    "OMAF_TO_CAMERA",
    "PIXEL_CENTRE_OFFSET",
    "RVS_FAR_LIMIT",
    "JsonSequence",
    "VideoDescription",
    "euler_from_rotation",
    "read_json_cameras",
    "read_json_sequence",
    "rotation_from_euler",
    "write_json_cameras",
    "write_json_sequence",
]

logger = logging.getLogger(__name__)

OMAF_TO_CAMERA = np.array([[0.0, -1.0, 0.0], [0.0, 0.0, -1.0], [1.0, 0.0, 0.0]])

# RVS 4.0 refuses a file without Version, or older than 3.0; TMIV's sequence files are 4.0.
JSON_VERSION = "4.0"

# RVS 4.0 refuses a far depth above 1000, which it takes for infinity.
RVS_FAR_LIMIT = 1000.0

# JSON image coordinates of a ray minus ours (pixel centres at integer + 0.5 there).
PIXEL_CENTRE_OFFSET = Fraction(1, 2)

DEFAULT_FPS = 30

# Rotations of the shipped MPEG files are orthonormal to 5e-7; a larger error would
# be silently changed by the yaw/pitch/roll form.
_ROTATION_TOLERANCE = 1e-6

# Below this cos(pitch) the camera looks straight up or down and yaw and roll turn
# about the same axis; roll is then set to zero.
_GIMBAL_LOCK = 1e-12


@dataclass(frozen=True)
class VideoDescription:
    """The fields of an MPEG-I camera that describe its videos rather than its geometry.

    Attributes
    ----------
    bit_depth_color, bit_depth_depth : int
        ``BitDepthColor`` and ``BitDepthDepth``.
    color_space, depth_color_space : str
        ``ColorSpace`` and ``DepthColorSpace``; RVS reads ``YUV420`` textures and
        ``YUV420`` or ``YUV400`` depth maps.
    has_depth_map : bool
        ``Depthmap``: the camera comes with a depth map (RVS reads no other camera).
    background : bool
        ``Background``: the camera shows the background only.
    has_invalid_depth : bool
        ``HasInvalidDepth``: depth value 0 marks pixels without a depth. False for
        VSRS and DERS depth maps, where 0 is the farthest depth.
    """

    bit_depth_color: int = 8
    bit_depth_depth: int = 8
    color_space: str = "YUV420"
    depth_color_space: str = "YUV420"
    has_depth_map: bool = True
    background: bool = False
    has_invalid_depth: bool = False


@dataclass
class JsonSequence:
    """An MPEG-I sequence file.

    Attributes
    ----------
    cameras : dict of str to Camera
        In file order, in our axes and pixel convention (module docstring).
    videos : dict of str to VideoDescription
        The video fields of each camera, by camera name.
    content_name : str
        ``Content_name``.
    fps : float
        ``Fps``.
    frame_count : int
        ``Frames_number``.
    """

    cameras: dict[str, Camera]
    videos: dict[str, VideoDescription]
    content_name: str
    fps: float = DEFAULT_FPS
    frame_count: int = 1


def rotation_from_euler(yaw: float, pitch: float, roll: float) -> np.ndarray:
    """``Rz(yaw) Ry(pitch) Rx(roll)`` for angles in degrees, shape (3, 3)."""
    a, b, c = np.radians([yaw, pitch, roll])
    rz = np.array([[np.cos(a), -np.sin(a), 0.0], [np.sin(a), np.cos(a), 0.0], [0.0, 0.0, 1.0]])
    ry = np.array([[np.cos(b), 0.0, np.sin(b)], [0.0, 1.0, 0.0], [-np.sin(b), 0.0, np.cos(b)]])
    rx = np.array([[1.0, 0.0, 0.0], [0.0, np.cos(c), -np.sin(c)], [0.0, np.sin(c), np.cos(c)]])
    return rz @ ry @ rx


def euler_from_rotation(rotation: np.ndarray) -> tuple[float, float, float]:
    """(yaw, pitch, roll) in degrees with ``rotation = Rz(yaw) Ry(pitch) Rx(roll)``.

    Pitch is in [-90, 90]; at +-90 (gimbal lock) roll is taken as 0.
    """
    r = np.asarray(rotation, dtype=np.float64)
    cos_pitch = math.hypot(r[0, 0], r[1, 0])
    pitch = math.atan2(-r[2, 0], cos_pitch)
    if cos_pitch > _GIMBAL_LOCK:
        yaw = math.atan2(r[1, 0], r[0, 0])
        roll = math.atan2(r[2, 1], r[2, 2])
    else:
        yaw = math.atan2(-r[0, 1], r[1, 1])
        roll = 0.0
    return math.degrees(yaw), math.degrees(pitch), math.degrees(roll)


class _JsonFloat(float):
    """A JSON number that keeps its text, so that it can be used exactly."""

    def __new__(cls, text: str):
        number = super().__new__(cls, text)
        number.text = text
        return number


class _JsonText(str):
    """A number written as this text rather than as the shortest float repr."""


def _exact(number: float) -> Fraction:
    """The value of a number read from JSON: its decimal text, not the nearest float."""
    return Fraction(number.text) if isinstance(number, _JsonFloat) else Fraction(number)


def _read_document(path: Path):
    try:
        return json.loads(read_text(path, "camera file"), parse_float=_JsonFloat)
    except json.JSONDecodeError as err:
        raise ConfigError(
            f"invalid JSON: {err.msg} (column {err.colno})", path=path, line=err.lineno
        ) from None


def _integer(
    entry: dict, field: str, default: int, *, path: Path, key: str, minimum: int = 0
) -> int:
    value = entry.get(field)
    if value is None:
        return default
    if (
        isinstance(value, bool)
        or not isinstance(value, (int, float))
        or not float(value).is_integer()
        or value < minimum
    ):
        raise ConfigError(
            f"{field} must be an integer >= {minimum}, got {json.dumps(value)}", path=path, key=key
        )
    return int(value)


def _flag(entry: dict, field: str, default: bool, *, path: Path, key: str) -> bool:
    value = entry.get(field)
    if value is None:
        return default
    if value not in (0, 1):
        raise ConfigError(
            f"{field} must be 0, 1, true or false, got {json.dumps(value)}", path=path, key=key
        )
    return bool(value)


def _string(entry: dict, field: str, default: str, *, path: Path, key: str) -> str:
    value = entry.get(field, default)
    if not isinstance(value, str) or not value:
        raise ConfigError(
            f"{field} must be a non-empty string, got {json.dumps(value)}", path=path, key=key
        )
    return value


def _camera_from_json(entry: object, index: int, path: Path) -> tuple[Camera, VideoDescription]:
    if not isinstance(entry, dict):
        raise ConfigError("a camera must be a JSON object", path=path, key=f"cameras[{index}]")
    name = entry.get("Name")
    if not isinstance(name, str) or not name:
        raise ConfigError("Name must be a non-empty string", path=path, key=f"cameras[{index}]")
    projection = entry.get("Projection")
    if projection != "Perspective":
        raise ConfigError(
            f"projection {projection!r} is not supported (only 'Perspective')", path=path, key=name
        )
    position = json_numbers(entry, "Position", 3, path=path, key=name)
    yaw, pitch, roll = json_numbers(entry, "Rotation", 3, path=path, key=name)
    fx, fy = json_numbers(entry, "Focal", 2, path=path, key=name)
    json_numbers(entry, "Principle_point", 2, path=path, key=name)
    cx, cy = (float(_exact(x) - PIXEL_CENTRE_OFFSET) for x in entry["Principle_point"])
    resolution = json_numbers(entry, "Resolution", 2, path=path, key=name, required=False)
    depth_range = json_numbers(entry, "Depth_range", 2, path=path, key=name, required=False)
    if resolution is not None and not all(x.is_integer() and x > 0 for x in resolution):
        raise ConfigError(
            f"Resolution must be two positive integers, got {resolution}", path=path, key=name
        )
    if depth_range is not None and not 0 < depth_range[0] < depth_range[1]:
        raise ConfigError(
            f"Depth_range must be [near, far] with 0 < near < far, got {depth_range}",
            path=path,
            key=name,
        )
    camera = Camera(
        name=name,
        K=[[fx, 0.0, cx], [0.0, fy, cy], [0.0, 0.0, 1.0]],
        R=OMAF_TO_CAMERA @ rotation_from_euler(yaw, pitch, roll).T,
        t=position,
        size=None if resolution is None else (int(resolution[0]), int(resolution[1])),
        depth_range=None if depth_range is None else tuple(depth_range),
    )
    # An absent HasInvalidDepth means true to RVS, which keeps the files of RVS 2 valid.
    video = VideoDescription(
        bit_depth_color=_integer(entry, "BitDepthColor", 8, path=path, key=name, minimum=1),
        bit_depth_depth=_integer(entry, "BitDepthDepth", 8, path=path, key=name, minimum=1),
        color_space=_string(entry, "ColorSpace", "YUV420", path=path, key=name),
        depth_color_space=_string(entry, "DepthColorSpace", "YUV420", path=path, key=name),
        has_depth_map=_flag(entry, "Depthmap", True, path=path, key=name),
        background=_flag(entry, "Background", False, path=path, key=name),
        has_invalid_depth=_flag(entry, "HasInvalidDepth", True, path=path, key=name),
    )
    return camera, video


def read_json_sequence(path: str | os.PathLike) -> JsonSequence:
    """Read an MPEG-I sequence file: its perspective cameras and the fields around them.

    Fields that are absent take the defaults of :class:`VideoDescription` and
    :class:`JsonSequence` (``HasInvalidDepth`` true, as RVS reads it), and
    ``Content_name`` the file's stem.

    Returns
    -------
    JsonSequence
        Cameras in file order, converted to our axes and pixel centres (module
        docstring); ``size`` and ``depth_range`` come from ``Resolution`` and
        ``Depth_range`` when present.

    Raises
    ------
    UsageError
        The file cannot be read.
    ConfigError
        Invalid JSON, no ``cameras`` array, a missing or malformed field, a depth range
        that is not ``0 < near < far``, a projection other than ``Perspective``, or a
        camera that cannot project (:func:`mvtools.io.cameras.store_camera`).
    """
    path = Path(path)
    document = _read_document(path)
    entries = document.get("cameras") if isinstance(document, dict) else None
    if not isinstance(entries, list) or not entries:
        raise ConfigError("expected an object with a non-empty 'cameras' array", path=path)
    cameras: dict[str, Camera] = {}
    videos: dict[str, VideoDescription] = {}
    lines: dict[str, int | None] = {}
    for index, entry in enumerate(entries):
        camera, video = _camera_from_json(entry, index, path)
        store_camera(cameras, camera, lines, path=path)
        videos[camera.name] = video
    fps = document.get("Fps", DEFAULT_FPS)
    if isinstance(fps, bool) or not isinstance(fps, (int, float)) or not 0 < fps < math.inf:
        raise ConfigError(
            f"Fps must be a positive number, got {json.dumps(fps)}", path=path, key="Fps"
        )
    return JsonSequence(
        cameras=cameras,
        videos=videos,
        content_name=_string(document, "Content_name", path.stem, path=path, key="Content_name"),
        fps=float(fps),
        frame_count=_integer(
            document, "Frames_number", 1, path=path, key="Frames_number", minimum=1
        ),
    )


def read_json_cameras(path: str | os.PathLike) -> dict[str, Camera]:
    """The cameras of an MPEG-I sequence file (:func:`read_json_sequence`), by name."""
    return read_json_sequence(path).cameras


def _scene_side(depth_range: tuple[float, float], name: str, path: Path) -> int:
    """+1 when the range lies in front of the camera, -1 when at negative z (VSRS)."""
    near, far = depth_range
    if 0 < near < far < math.inf:
        return 1
    if -math.inf < far < near < 0:
        return -1
    raise UsageError(
        f"camera {name!r}: depth range (near {near:g}, far {far:g}) needs "
        "0 < near < far, or far < near < 0 for a scene at negative z, both "
        "finite",
        path=path,
    )


def _facing_scene(cameras: list[Camera], depth_range, path: Path) -> list[Camera]:
    """The cameras with their depth ranges filled in, in a world where they face their scene."""
    cameras = [
        camera
        if camera.depth_range is not None or depth_range is None
        else replace(camera, depth_range=tuple(depth_range))
        for camera in cameras
    ]
    sides = {
        camera.name: _scene_side(camera.depth_range, camera.name, path)
        for camera in cameras
        if camera.depth_range is not None
    }
    if -1 not in sides.values():
        return cameras
    if 1 in sides.values():
        front = next(name for name, side in sides.items() if side == 1)
        behind = next(name for name, side in sides.items() if side == -1)
        raise UsageError(
            f"camera {front!r} has a positive depth range and camera {behind!r} "
            "a negative one; one world cannot hold both",
            path=path,
        )
    logger.warning(
        "%s: the depth ranges are negative (scene at negative z, as VSRS allows); "
        "the cameras are written in the world reflected through its origin "
        "(Position = -t) where they face the scene with positive depths",
        path,
    )
    # x_cam = R (X - t) becomes -x_cam for X -> -X and t -> -t: the same pixels, with
    # the scene at positive depth.
    return [
        replace(
            camera,
            t=-camera.t,
            depth_range=None
            if camera.depth_range is None
            else (-camera.depth_range[0], -camera.depth_range[1]),
        )
        for camera in cameras
    ]


def _json_pixel_coordinate(coordinate: float) -> float | _JsonText:
    """``coordinate + 0.5`` as a JSON number that reads back to ``coordinate`` exactly."""
    exact = Fraction(coordinate) + PIXEL_CENTRE_OFFSET
    nearest = float(exact)
    if Fraction(nearest) == exact:
        return nearest
    # The sum needs one bit more than a float holds (it crossed a power of two): its
    # denominator is 2**k, so it has an exact decimal of k digits after the point.
    k = exact.denominator.bit_length() - 1
    digits = str(abs(exact.numerator) * 5**k).rjust(k + 1, "0")
    sign = "-" if exact < 0 else ""
    return _JsonText(f"{sign}{digits[:-k]}.{digits[-k:]}")


def _camera_to_json(camera: Camera, size, video: VideoDescription, path: Path) -> dict:
    k = camera.K
    if k[0, 1] != 0 or k[1, 0] != 0 or np.any(k[2] != [0, 0, 1]):
        raise UsageError(
            f"camera {camera.name!r}: K has skew or is not [[fx 0 cx] [0 fy cy] "
            "[0 0 1]]; MPEG-I JSON cannot store it",
            path=path,
        )
    if np.any(camera.distortion != 0):
        raise UsageError(
            f"camera {camera.name!r} has lens distortion, which MPEG-I JSON cannot store", path=path
        )
    rotation_json = camera.R.T @ OMAF_TO_CAMERA
    error = float(np.abs(rotation_json @ rotation_json.T - np.eye(3)).max())
    if error > _ROTATION_TOLERANCE or np.linalg.det(rotation_json) < 0:
        raise UsageError(
            f"camera {camera.name!r}: R is not a rotation (max |R R^T - I| = "
            f"{error:.3g}, det {np.linalg.det(rotation_json):.3g}), so it has no "
            "yaw/pitch/roll",
            path=path,
        )
    entry: dict = {
        "Name": camera.name,
        "Position": [float(x) for x in camera.t],
        "Rotation": list(euler_from_rotation(rotation_json)),
        "Depthmap": int(video.has_depth_map),
        "Background": int(video.background),
    }
    size = camera.size if camera.size is not None else size
    if camera.depth_range is not None:
        entry["Depth_range"] = [float(x) for x in camera.depth_range]
    if size is not None:
        entry["Resolution"] = [int(x) for x in size]
    entry.update(
        {
            "Projection": "Perspective",
            "Focal": [camera.fx, camera.fy],
            "Principle_point": [
                _json_pixel_coordinate(camera.cx),
                _json_pixel_coordinate(camera.cy),
            ],
            "BitDepthColor": video.bit_depth_color,
            "BitDepthDepth": video.bit_depth_depth,
            "ColorSpace": video.color_space,
            "DepthColorSpace": video.depth_color_space,
            "HasInvalidDepth": video.has_invalid_depth,
        }
    )
    return entry


def write_json_cameras(
    path: str | os.PathLike,
    cameras: Iterable[Camera] | Mapping[str, Camera],
    *,
    size: tuple[int, int] | None = None,
    depth_range: tuple[float, float] | None = None,
    video: VideoDescription | Mapping[str, VideoDescription] = VideoDescription(),
    content_name: str | None = None,
    fps: float = DEFAULT_FPS,
    frame_count: int = 1,
) -> None:
    """Write cameras as a complete MPEG-I sequence file, as RVS 4.0 and TMIV read it.

    Parameters
    ----------
    path : path-like
        Output file, written atomically.
    cameras : iterable of Camera, or mapping of name to Camera
        Perspective cameras without skew or distortion, in our pixel convention.
    size, depth_range : tuple or None
        ``Resolution`` and ``Depth_range`` for the cameras that do not carry their own;
        a field neither gives is left out, with a warning (RVS and TMIV need both).
        Negative ranges (VSRS) are written positive, in the world reflected through
        its origin (module docstring); a warning says so.
    video : VideoDescription or mapping of camera name to VideoDescription
        The video fields of every camera, or of each (missing names take the defaults).
    content_name : str, optional
        ``Content_name``; the file's stem by default.
    fps, frame_count
        ``Fps`` and ``Frames_number``.

    Raises
    ------
    UsageError
        A camera the format cannot represent (skew, distortion, a reflection), a depth
        range that is neither ``0 < near < far`` nor ``far < near < 0``, positive and
        negative ranges in one file, or a non-positive ``fps`` or ``frame_count``.
    """
    path = Path(path)
    if isinstance(cameras, Mapping):
        cameras = cameras.values()
    if not 0 < fps < math.inf or frame_count < 1:
        raise UsageError(
            f"need Fps > 0 and Frames_number >= 1, got {fps:g} and {frame_count}", path=path
        )
    entries = []
    for camera in _facing_scene(list(cameras), depth_range, path):
        description = (
            video.get(camera.name, VideoDescription()) if isinstance(video, Mapping) else video
        )
        entries.append(_camera_to_json(camera, size, description, path))
    too_far = [
        entry["Name"]
        for entry in entries
        if "Depth_range" in entry and entry["Depth_range"][1] > RVS_FAR_LIMIT
    ]
    if too_far:
        logger.warning(
            "%s: far depth above %g for camera %s, which RVS refuses (%g stands for "
            "infinity there); a larger world unit brings it below",
            path,
            RVS_FAR_LIMIT,
            ", ".join(too_far),
            RVS_FAR_LIMIT,
        )
    for field in ("Depth_range", "Resolution"):
        lacking = [entry["Name"] for entry in entries if field not in entry]
        if lacking:
            logger.warning(
                "%s: no %s for camera %s, which RVS and TMIV require",
                path,
                field,
                ", ".join(lacking),
            )
    document = {
        "Version": JSON_VERSION,
        "Content_name": content_name if content_name is not None else path.stem,
        "Fps": int(fps) if float(fps).is_integer() else float(fps),
        "Frames_number": int(frame_count),
        "cameras": entries,
    }
    with atomic_output(path, "w") as handle:
        handle.write(_format_document(document))


def write_json_sequence(path: str | os.PathLike, sequence: JsonSequence) -> None:
    """Write a sequence read by :func:`read_json_sequence`, its fields kept."""
    write_json_cameras(
        path,
        sequence.cameras,
        video=sequence.videos,
        content_name=sequence.content_name,
        fps=sequence.fps,
        frame_count=sequence.frame_count,
    )


def _value_text(value) -> str:
    if isinstance(value, _JsonText):
        return str(value)
    if isinstance(value, list):
        return "[" + ", ".join(_value_text(item) for item in value) + "]"
    return json.dumps(value)


def _format_document(document: dict) -> str:
    """One field a line, each list on its field's line, the cameras one object each."""
    fields = [
        f"    {json.dumps(key)}: {_value_text(value)}"
        for key, value in document.items()
        if key != "cameras"
    ]
    cameras = []
    for entry in document["cameras"]:
        lines = ",\n".join(
            f"            {json.dumps(key)}: {_value_text(value)}" for key, value in entry.items()
        )
        cameras.append(f"        {{\n{lines}\n        }}")
    fields.append('    "cameras": [\n' + ",\n".join(cameras) + "\n    ]")
    return "{\n" + ",\n".join(fields) + "\n}\n"
