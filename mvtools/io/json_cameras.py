"""MPEG-I camera descriptions (the JSON files of RVS and TMIV).

The file is an object with a ``cameras`` array; per camera ``Name``, ``Position``
[x, y, z], ``Rotation`` [yaw, pitch, roll] in degrees, ``Depth_range`` [near, far],
``Resolution`` [w, h], ``Projection``, ``Focal`` [fx, fy], ``Principle_point``
[cx, cy] (spelled so), and ``BitDepthColor``, ``BitDepthDepth``, ``ColorSpace``,
``DepthColorSpace``, which describe the videos rather than the camera and are not
kept when reading. Only the ``Perspective`` projection is supported.

Axes (OMAF): x forward, y left, z up. ``R_json = Rz(yaw) Ry(pitch) Rx(roll)`` maps
camera to world and a pixel ``(u, v)`` at depth ``d`` is the camera point
``(d, -d (u - cx) / fx, -d (v - cy) / fy)``. Our cameras look along +z with x right
and y down, so ``x_ours = M x_omaf`` with ``M = [[0, -1, 0], [0, 0, -1], [1, 0, 0]]``;
the world frame is kept as it is. Hence ``R = M R_json^T``, ``t = Position``, and
writing uses ``R_json = R^T M``.
"""

from __future__ import annotations

import json
import math
import os
from collections.abc import Iterable, Mapping
from pathlib import Path

import numpy as np

from mvtools.errors import ConfigError, UsageError
from mvtools.geometry.camera import Camera
from mvtools.io.atomic import atomic_output
from mvtools.io.cameras import read_cameras, store_camera
from mvtools.io.files import json_numbers, read_json

__all__ = ["read_json_cameras", "write_json_cameras", "read_camera_file", "OMAF_TO_CAMERA",
           "rotation_from_euler", "euler_from_rotation"]

OMAF_TO_CAMERA = np.array([[0.0, -1.0, 0.0], [0.0, 0.0, -1.0], [1.0, 0.0, 0.0]])

# Rotations of the shipped MPEG files are orthonormal to 5e-7; a larger error would
# be silently changed by the yaw/pitch/roll form.
_ROTATION_TOLERANCE = 1e-6

# Below this cos(pitch) the camera looks straight up or down and yaw and roll turn
# about the same axis; roll is then set to zero.
_GIMBAL_LOCK = 1e-12


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


def _camera_from_json(entry: object, index: int, path: Path) -> Camera:
    if not isinstance(entry, dict):
        raise ConfigError("a camera must be a JSON object", path=path, key=f"cameras[{index}]")
    name = entry.get("Name")
    if not isinstance(name, str) or not name:
        raise ConfigError("Name must be a non-empty string", path=path, key=f"cameras[{index}]")
    projection = entry.get("Projection")
    if projection != "Perspective":
        raise ConfigError(f"projection {projection!r} is not supported (only 'Perspective')",
                          path=path, key=name)
    position = json_numbers(entry, "Position", 3, path=path, key=name)
    yaw, pitch, roll = json_numbers(entry, "Rotation", 3, path=path, key=name)
    fx, fy = json_numbers(entry, "Focal", 2, path=path, key=name)
    cx, cy = json_numbers(entry, "Principle_point", 2, path=path, key=name)
    resolution = json_numbers(entry, "Resolution", 2, path=path, key=name, required=False)
    depth_range = json_numbers(entry, "Depth_range", 2, path=path, key=name, required=False)
    if resolution is not None and not all(x.is_integer() and x > 0 for x in resolution):
        raise ConfigError(f"Resolution must be two positive integers, got {resolution}",
                          path=path, key=name)
    return Camera(name=name, K=[[fx, 0.0, cx], [0.0, fy, cy], [0.0, 0.0, 1.0]],
                  R=OMAF_TO_CAMERA @ rotation_from_euler(yaw, pitch, roll).T, t=position,
                  size=None if resolution is None else (int(resolution[0]), int(resolution[1])),
                  depth_range=None if depth_range is None else tuple(depth_range))


def read_json_cameras(path: str | os.PathLike) -> dict[str, Camera]:
    """Read the perspective cameras of an MPEG-I JSON camera description.

    Returns
    -------
    dict of str to Camera
        In file order, converted to our axes (module docstring). ``size`` and
        ``depth_range`` come from ``Resolution`` and ``Depth_range`` when present.

    Raises
    ------
    UsageError
        The file cannot be read.
    ConfigError
        Invalid JSON, no ``cameras`` array, a missing or malformed field, or a
        projection other than ``Perspective``.
    """
    path = Path(path)
    document = read_json(path, "camera file")
    entries = document.get("cameras") if isinstance(document, dict) else None
    if not isinstance(entries, list) or not entries:
        raise ConfigError("expected an object with a non-empty 'cameras' array", path=path)
    cameras: dict[str, Camera] = {}
    lines: dict[str, int | None] = {}
    for index, entry in enumerate(entries):
        store_camera(cameras, _camera_from_json(entry, index, path), lines, path=path)
    return cameras


def _camera_to_json(camera: Camera, *, size, depth_range, path: Path) -> dict:
    k = camera.K
    if k[0, 1] != 0 or k[1, 0] != 0 or np.any(k[2] != [0, 0, 1]):
        raise UsageError(f"camera {camera.name!r}: K has skew or is not [[fx 0 cx] [0 fy cy] "
                         "[0 0 1]]; MPEG-I JSON cannot store it", path=path)
    if np.any(camera.distortion != 0):
        raise UsageError(f"camera {camera.name!r} has lens distortion, which MPEG-I JSON "
                         "cannot store", path=path)
    rotation_json = camera.R.T @ OMAF_TO_CAMERA
    error = float(np.abs(rotation_json @ rotation_json.T - np.eye(3)).max())
    if error > _ROTATION_TOLERANCE or np.linalg.det(rotation_json) < 0:
        raise UsageError(f"camera {camera.name!r}: R is not a rotation (max |R R^T - I| = "
                         f"{error:.3g}, det {np.linalg.det(rotation_json):.3g}), so it has no "
                         "yaw/pitch/roll", path=path)
    entry: dict = {"Name": camera.name,
                   "Position": [float(x) for x in camera.t],
                   "Rotation": list(euler_from_rotation(rotation_json))}
    size = camera.size if camera.size is not None else size
    depth_range = camera.depth_range if camera.depth_range is not None else depth_range
    if depth_range is not None:
        entry["Depth_range"] = [float(x) for x in depth_range]
    if size is not None:
        entry["Resolution"] = [int(x) for x in size]
    entry.update({"Projection": "Perspective",
                  "Focal": [camera.fx, camera.fy],
                  "Principle_point": [camera.cx, camera.cy]})
    return entry


def write_json_cameras(path: str | os.PathLike, cameras: Iterable[Camera] | Mapping[str, Camera],
                       *, size: tuple[int, int] | None = None,
                       depth_range: tuple[float, float] | None = None,
                       bit_depth_color: int = 8, bit_depth_depth: int = 8,
                       color_space: str = "YUV420", depth_color_space: str = "YUV420") -> None:
    """Write cameras as an MPEG-I JSON camera description (``{"cameras": [...]}``).

    Parameters
    ----------
    path : path-like
        Output file, written atomically.
    cameras : iterable of Camera, or mapping of name to Camera
        Perspective cameras without skew or distortion.
    size, depth_range : tuple or None
        ``Resolution`` and ``Depth_range`` for the cameras that do not carry their own;
        the fields are left out when neither gives them.
    bit_depth_color, bit_depth_depth, color_space, depth_color_space
        The video description fields written for every camera.

    Raises
    ------
    UsageError
        A camera the format cannot represent (skew, distortion, a reflection).
    """
    path = Path(path)
    if isinstance(cameras, Mapping):
        cameras = cameras.values()
    entries = []
    for camera in cameras:
        entry = _camera_to_json(camera, size=size, depth_range=depth_range, path=path)
        entry.update({"BitDepthColor": bit_depth_color, "BitDepthDepth": bit_depth_depth,
                      "ColorSpace": color_space, "DepthColorSpace": depth_color_space})
        entries.append(entry)
    with atomic_output(path, "w") as handle:
        handle.write(_format_document(entries))


def _format_document(entries: list[dict]) -> str:
    """``{"cameras": [...]}`` with one field a line and each list on its field's line."""
    cameras = []
    for entry in entries:
        fields = ",\n".join(f"            {json.dumps(key)}: {json.dumps(value)}"
                             for key, value in entry.items())
        cameras.append(f"        {{\n{fields}\n        }}")
    return '{\n    "cameras": [\n' + ",\n".join(cameras) + "\n    ]\n}\n"


def read_camera_file(path: str | os.PathLike, *, transposed_rotation: bool = False
                     ) -> dict[str, Camera]:
    """Cameras of an MPEG-I JSON file (``.json``) or else an MPEG camera parameter file.

    ``transposed_rotation`` applies to the MPEG text format, see
    :func:`mvtools.io.cameras.read_cameras`.
    """
    if Path(path).suffix.lower() == ".json":
        return read_json_cameras(path)
    return read_cameras(path, transposed_rotation=transposed_rotation)
