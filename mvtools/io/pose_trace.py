"""Pose traces: the viewer's camera per output frame, as RVS and TMIV read it (CSV).

An optional header line ``X,Y,Z,Yaw,Pitch,Roll``, then one row per output frame of six
numbers separated by commas (spaces around them allowed): the camera centre in the
camera file's world and its orientation in degrees. ``docs/pose-trace.md`` describes
the format and both conventions.

- ``"omaf"``: the numbers are an MPEG-I JSON camera's ``Position`` and ``Rotation``
  (:mod:`mvtools.io.json_cameras`): OMAF axes (x forward, y left, z up),
  camera to world ``Rz(yaw) Ry(pitch) Rx(roll)``, hence
  ``R = OMAF_TO_CAMERA @ rotation_from_euler(yaw, pitch, roll).T``.
- ``"mpeg"``: the same numbers in our camera axes (x right, y down, z forward):
  camera to world ``Ry(yaw) Rx(pitch) Rz(roll)`` (right-handed), so yaw > 0 turns the
  view towards +x, pitch > 0 tilts it up (towards -y), roll > 0 turns the image x axis
  towards +y.

Examples
--------
>>> import tempfile
>>> from pathlib import Path
>>> from mvtools.geometry import Camera
>>> template = Camera("v", np.diag([100.0, 100.0, 1.0]), size=(64, 48))
>>> with tempfile.TemporaryDirectory() as folder:
...     path = Path(folder) / "trace.csv"
...     _ = path.write_text("X,Y,Z,Yaw,Pitch,Roll\\n0,0,0,90,0,0\\n")
...     (camera,) = read_pose_trace(path, convention="mpeg", template=template)
>>> camera.name, np.round(camera.optical_axis, 12).tolist()
('v_pose000', [1.0, 0.0, 0.0])
"""

from __future__ import annotations

import math
import os
from collections.abc import Iterable, Sequence
from dataclasses import replace
from pathlib import Path

import numpy as np

from mvtools.errors import ConfigError, UsageError
from mvtools.geometry.camera import Camera
from mvtools.io.atomic import atomic_output
from mvtools.io.files import read_text
from mvtools.io.json_cameras import OMAF_TO_CAMERA, euler_from_rotation, rotation_from_euler

__all__ = [
    "POSE_TRACE_COLUMNS",
    "POSE_TRACE_CONVENTIONS",
    "check_frames",
    "read_pose_trace",
    "write_pose_trace",
]

#: The column names, as the header line gives them.
POSE_TRACE_COLUMNS = ("X", "Y", "Z", "Yaw", "Pitch", "Roll")

#: The meanings of the six numbers a reader and writer know (module docstring).
POSE_TRACE_CONVENTIONS = ("omaf", "mpeg")

_HEADER = ",".join(POSE_TRACE_COLUMNS)

# A rotation further than this from orthonormal has no yaw/pitch/roll worth writing.
_ROTATION_TOLERANCE = 1e-6


def _check_convention(convention: str) -> None:
    if convention not in POSE_TRACE_CONVENTIONS:
        raise UsageError(
            f"unknown pose trace convention {convention!r}; choose one of "
            + ", ".join(POSE_TRACE_CONVENTIONS),
            key="convention",
        )


def _rotation(convention: str, yaw: float, pitch: float, roll: float) -> np.ndarray:
    """World-to-camera ``R`` of one row."""
    if convention == "omaf":
        return OMAF_TO_CAMERA @ rotation_from_euler(yaw, pitch, roll).T
    # Our axes are OMAF's relabelled, x_ours = M x_omaf: our y (down) is OMAF's -z, our
    # x (right) OMAF's -y, our z (forward) OMAF's x. So Ry(yaw) Rx(pitch) Rz(roll) in our
    # axes is M Rz(-yaw) Ry(-pitch) Rx(roll) M^T in OMAF's, and R is its transpose.
    to_world = OMAF_TO_CAMERA @ rotation_from_euler(-yaw, -pitch, roll) @ OMAF_TO_CAMERA.T
    return to_world.T


def _angles(convention: str, R: np.ndarray) -> tuple[float, float, float]:
    """(yaw, pitch, roll) of a world-to-camera ``R`` (inverse of :func:`_rotation`)."""
    if convention == "omaf":
        return euler_from_rotation(R.T @ OMAF_TO_CAMERA)
    yaw, pitch, roll = euler_from_rotation(OMAF_TO_CAMERA.T @ R.T @ OMAF_TO_CAMERA)
    return -yaw + 0.0, -pitch + 0.0, roll


def _is_header(fields: list[str]) -> bool:
    return [f.lower() for f in fields] == [c.lower() for c in POSE_TRACE_COLUMNS]


def _number(text: str, column: str, path: Path, line: int) -> float:
    try:
        if "_" in text:  # float() reads 1_000; a CSV reader does not
            raise ValueError
        value = float(text)
    except ValueError:
        shown = "empty" if not text else f"{text!r} is not a number"
        hint = " (the only header allowed is X,Y,Z,Yaw,Pitch,Roll)" if line == 1 else ""
        raise ConfigError(f"{shown}{hint}", path=path, line=line, key=column) from None
    if not math.isfinite(value):
        raise ConfigError(f"{text!r} is not a finite number", path=path, line=line, key=column)
    return value


def read_pose_trace(
    path: str | os.PathLike,
    *,
    convention: str = "omaf",
    template: Camera,
    frames: int | None = None,
) -> list[Camera]:
    """The cameras of a pose trace, one per row.

    Parameters
    ----------
    path : path-like
        The CSV file (module docstring); blank lines are skipped.
    convention : {"omaf", "mpeg"}
        What the six numbers mean (:data:`POSE_TRACE_CONVENTIONS`, module docstring).
    template : Camera
        Gives every camera its ``K``, ``size``, ``distortion`` and ``depth_range``.
    frames : int, optional
        Frames asked for: the trace must have at least that many rows
        (:func:`check_frames`) and the first ``frames`` cameras are returned.

    Returns
    -------
    list of Camera
        Named ``f"{template.name}_pose{row:03d}"``, rows counted from 0; ``t = (X, Y, Z)``.
        With ``"omaf"`` a row holding a JSON camera's ``Position`` and ``Rotation``
        gives exactly the camera :func:`mvtools.io.json_cameras.read_json_cameras` reads.

    Raises
    ------
    UsageError
        An unknown convention, a file that cannot be read.
    ConfigError
        A row without 6 fields, a field that is not a finite number, a file without
        rows, fewer rows than ``frames``: one line naming the file, line and column.
    """
    _check_convention(convention)
    path = Path(path)
    cameras = []
    first = True  # the header may only be the first non-blank line
    for number, text in enumerate(read_text(path, "pose trace").splitlines(), start=1):
        if not text.strip():
            continue
        fields = [field.strip() for field in text.split(",")]
        header, first = first and _is_header(fields), False
        if header:
            continue
        if len(fields) != len(POSE_TRACE_COLUMNS):
            raise ConfigError(
                f"{len(fields)} fields, {len(POSE_TRACE_COLUMNS)} needed ({_HEADER})",
                path=path,
                line=number,
            )
        x, y, z, yaw, pitch, roll = (
            _number(field, column, path, number)
            for field, column in zip(fields, POSE_TRACE_COLUMNS)
        )
        cameras.append(
            replace(
                template,
                name=f"{template.name}_pose{len(cameras):03d}",
                K=template.K.copy(),
                R=_rotation(convention, yaw, pitch, roll),
                t=np.array([x, y, z]),
                distortion=template.distortion.copy(),
            )
        )
    if not cameras:
        raise ConfigError(f"no poses: the file has no rows of {_HEADER}", path=path)
    if frames is not None:
        check_frames(cameras, frames, path)
        cameras = cameras[:frames]
    return cameras


def check_frames(cameras: Sequence[Camera], frames: int, path: str | os.PathLike) -> None:
    """A ConfigError naming ``path`` and both counts when the trace ``cameras`` read
    from it has fewer than ``frames`` poses."""
    if len(cameras) < frames:
        raise ConfigError(
            f"the pose trace has {len(cameras)} poses, fewer than the {frames} frames asked",
            path=path,
        )


def write_pose_trace(
    path: str | os.PathLike, cameras: Iterable[Camera], *, convention: str = "omaf"
) -> None:
    """Write the poses of ``cameras`` as a pose trace with its header line.

    Numbers are written as Python's shortest exact repr, so
    :func:`read_pose_trace` gives back ``t`` exactly and ``R`` to about 1e-15 (at
    pitch +-90 degrees, where yaw and roll turn about one axis, roll is written as 0).

    Parameters
    ----------
    path : path-like
        Written atomically.
    cameras : iterable of Camera
    convention : {"omaf", "mpeg"}

    Raises
    ------
    UsageError
        An unknown convention, no cameras, a camera whose ``R`` is not a rotation.
    """
    _check_convention(convention)
    cameras = list(cameras)
    if not cameras:
        raise UsageError("no cameras to write as a pose trace", path=path)
    rows = [_HEADER]
    for camera in cameras:
        R = camera.R
        error = float(np.abs(R @ R.T - np.eye(3)).max())
        if not np.all(np.isfinite(camera.t)) or error > _ROTATION_TOLERANCE or np.linalg.det(R) < 0:
            raise UsageError(
                f"camera {camera.name!r}: not a finite centre and a rotation "
                f"(max |R R^T - I| = {error:.3g}), so it has no pose to write",
                path=path,
            )
        values = [*(float(x) for x in camera.t), *_angles(convention, R)]
        rows.append(",".join(repr(float(v)) for v in values))
    with atomic_output(path, "w", what="pose trace") as handle:
        handle.write("\n".join(rows) + "\n")
