"""MPEG camera parameter files (VSRS, DERS) and the 1D camera files of 3D-HTM.

An MPEG camera parameter file holds one block per camera::

    param_kendo01
    2241.25607 0.0 701.5        intrinsic matrix K, three rows
    0.0 2241.25607 514.5
    0.0 0.0 1.0
    0.0                         radial distortion K1
    0.0                         radial distortion K2
    1.0 0.0 0.0 5.0             [R | t], three rows
    0.0 1.0 0.0 0.0
    0.0 0.0 1.0 0.0

``R`` rotates world into camera coordinates and ``t`` is the camera centre in world
coordinates (VSRS 4.x, DERS 6.1): ``x_cam = R (X - t)``. VSRS 3.5 stored ``R``
transposed; ``transposed_rotation=True`` reads and writes that convention.

Reading follows the token-stream rule of the reference programs, made explicit so
that every file seen in the field loads and a damaged one is reported:

- ``#`` starts a comment that runs to the end of the line.
- A line made only of words (two or more tokens, none a number), such as a table
  header ``ViewNum ZNear ZFar``, is skipped.
- Every other non-numeric token is a camera name; the numbers that follow it, across
  line breaks, up to the next name are its block. The first 23 are the camera
  (9 for K, K1, K2, 12 for [R | t]). A block with fewer than 23 numbers is a
  :class:`~mvtools.errors.ConfigError`; numbers beyond the 23rd are ignored with a
  warning. Numbers before the first name (a table of depth ranges, as in
  ``cam_param_bbb_butterfly2_arc+Znear-far.txt``) are skipped.
- A purely numeric token is never a camera name.
- When a name occurs twice the last block is used, as VSRS does (DERS uses the
  first), and a warning names both lines.
- A rotation that is not orthonormal (``max |R R^T - I| > 1e-3``) or that is a
  reflection is loaded with a warning naming the camera.
- A singular ``K`` (all zeros, a focal length of 0) or a number that is not finite
  is a :class:`~mvtools.errors.ConfigError` naming the camera, in this format and in
  the others (:func:`store_camera`).
"""

from __future__ import annotations

import difflib
import logging
import os
import re
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from mvtools.errors import ConfigError, UsageError
from mvtools.geometry.camera import Camera
from mvtools.io.atomic import atomic_output
from mvtools.io.files import read_text

__all__ = [
    "NUMBERS_PER_CAMERA",
    "ORTHONORMAL_TOLERANCE",
    "get_camera",
    "read_cameras",
    "read_htm_cameras",
    "store_camera",
    "write_cameras",
]

logger = logging.getLogger(__name__)

NUMBERS_PER_CAMERA = 23
ORTHONORMAL_TOLERANCE = 1e-3

# What C's strtod accepts as a decimal number, without "nan", "inf" or hex forms,
# which would otherwise turn camera names such as "inf" into numbers.
_NUMBER = re.compile(r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?")


def _is_number(token: str) -> bool:
    return _NUMBER.fullmatch(token) is not None


@dataclass(frozen=True)
class _Token:
    text: str
    line: int


def _tokens(text: str) -> list[_Token]:
    """The tokens that matter, with their line numbers (comments and header lines dropped)."""
    tokens = []
    for number, line in enumerate(text.splitlines(), start=1):
        words = line.split("#", 1)[0].split()
        if len(words) >= 2 and not any(_is_number(word) for word in words):
            continue
        tokens.extend(_Token(word, number) for word in words)
    return tokens


def _blocks(tokens: list[_Token], path: Path) -> Iterable[tuple[_Token, list[float]]]:
    """Each camera name token with its 23 numbers."""
    index = 0
    while index < len(tokens) and _is_number(tokens[index].text):
        index += 1
    while index < len(tokens):
        name = tokens[index]
        end = index + 1
        while end < len(tokens) and _is_number(tokens[end].text):
            end += 1
        numbers = tokens[index + 1 : end]
        if len(numbers) < NUMBERS_PER_CAMERA:
            raise ConfigError(
                f"camera block has {len(numbers)} numbers, {NUMBERS_PER_CAMERA} needed",
                path=path,
                line=name.line,
                key=name.text,
            )
        if len(numbers) > NUMBERS_PER_CAMERA:
            extra = numbers[NUMBERS_PER_CAMERA:]
            logger.warning(
                "%s:%d: %s: camera block has %d numbers, the %d after the %dth "
                "(lines %d-%d) are ignored",
                path,
                name.line,
                name.text,
                len(numbers),
                len(extra),
                NUMBERS_PER_CAMERA,
                extra[0].line,
                extra[-1].line,
            )
        yield name, [float(token.text) for token in numbers[:NUMBERS_PER_CAMERA]]
        index = end


def store_camera(
    cameras: dict[str, Camera],
    camera: Camera,
    lines: dict[str, int],
    *,
    path: str | os.PathLike,
    line: int | None = None,
) -> None:
    """Check ``camera``, read from a camera file, and add it to ``cameras``; a name seen
    before is replaced with a warning.

    Every reader of camera files (MPEG text, MPEG-I JSON, 3D-HTM) stores its cameras
    here, so that one rule judges a camera whatever its format and whatever the mode
    that uses it. ``lines`` remembers where each name was defined (line number, or
    ``None`` when the format has none) so that the warning can point at both
    definitions.

    Raises
    ------
    ConfigError
        A camera that cannot project: non-finite numbers, or a singular ``K``.
    """
    where = f"{path}:{line}" if line is not None else f"{path}"
    _check_camera(camera, path, line, where)
    if camera.name in cameras:
        first = lines[camera.name]
        first_place = f" (first at line {first})" if first is not None else ""
        logger.warning(
            "%s: camera %r is defined again%s; the last definition is used, as VSRS does",
            where,
            camera.name,
            first_place,
        )
    cameras[camera.name] = camera
    lines[camera.name] = line


def _check_camera(camera: Camera, path: str | os.PathLike, line: int | None, where: str) -> None:
    """Refuse a camera that no program can use; warn about a rotation that is not one.

    A singular ``K`` (all zeros, as a file exported without intrinsics holds, or a
    focal length of 0) gives no pixel a ray: the general mode cannot invert it and the
    1D modes would divide by its focal length, so it is refused here for every mode.
    """
    numbers = np.concatenate([camera.K.ravel(), camera.R.ravel(), camera.t, camera.distortion])
    if not np.all(np.isfinite(numbers)):
        raise ConfigError(
            "the camera has non-finite parameters (inf or nan)",
            path=path,
            line=line,
            key=camera.name,
        )
    if np.linalg.matrix_rank(camera.K) < 3:
        rows = ", ".join(" ".join(f"{value:g}" for value in row) for row in camera.K)
        raise ConfigError(
            f"the intrinsic matrix K ({rows}) is singular: a camera needs "
            "focal lengths fx, fy other than 0 and the last row 0 0 1",
            path=path,
            line=line,
            key=camera.name,
        )
    error = float(np.abs(camera.R @ camera.R.T - np.eye(3)).max())
    if error > ORTHONORMAL_TOLERANCE:
        logger.warning(
            "%s: %s: rotation is not orthonormal (max |R R^T - I| = %.3g)",
            where,
            camera.name,
            error,
        )
    elif np.linalg.det(camera.R) < 0:
        logger.warning("%s: %s: rotation is a reflection (det R = -1)", where, camera.name)


def read_cameras(
    path: str | os.PathLike, *, transposed_rotation: bool = False
) -> dict[str, Camera]:
    """Read an MPEG camera parameter file (VSRS, DERS).

    Parameters
    ----------
    path : path-like
        The camera parameter file (any line endings, spaces or tabs).
    transposed_rotation : bool
        The file stores ``R`` transposed (camera to world), as VSRS 3.5 did.

    Returns
    -------
    dict of str to Camera
        The cameras in the order of the file. ``distortion`` holds ``(K1, K2)``;
        ``size`` and ``depth_range`` are None (the format has neither).

    Raises
    ------
    UsageError
        The file cannot be read.
    ConfigError
        A camera block with fewer than 23 numbers, a camera that cannot project
        (:func:`store_camera`), or no camera at all.

    Notes
    -----
    See the module docstring for the exact reading rule. A name defined twice keeps
    its last block (as VSRS; DERS keeps the first) and is warned about.
    """
    path = Path(path)
    cameras: dict[str, Camera] = {}
    lines: dict[str, int] = {}
    # Every block is parsed before any camera is judged: a damaged file (a block cut
    # short) is reported as such, wherever the damage is.
    blocks = list(_blocks(_tokens(read_text(path, "camera parameter file")), path))
    for name, numbers in blocks:
        rotation_translation = np.array(numbers[11:]).reshape(3, 4)
        rotation = rotation_translation[:, :3]
        camera = Camera(
            name=name.text,
            K=numbers[:9],
            R=rotation.T if transposed_rotation else rotation,
            t=rotation_translation[:, 3],
            distortion=numbers[9:11],
        )
        store_camera(cameras, camera, lines, path=path, line=name.line)
    if not cameras:
        raise ConfigError(
            f"no camera found (a camera is a name followed by {NUMBERS_PER_CAMERA} numbers)",
            path=path,
        )
    return cameras


def get_camera(
    cameras: Mapping[str, Camera],
    name: str,
    *,
    path: str | os.PathLike | None = None,
    key: str | None = None,
) -> Camera:
    """The camera called ``name``, or a ConfigError suggesting the closest names.

    ``path`` (the camera file) and ``key`` (the configuration key that asked for the
    camera, e.g. ``LeftCameraName``) only serve the error message.
    """
    try:
        return cameras[name]
    except KeyError:
        pass
    close = difflib.get_close_matches(name, list(cameras), n=3, cutoff=0.6)
    if close:
        hint = "did you mean " + " or ".join(repr(known) for known in close) + "?"
    else:
        shown = ", ".join(repr(known) for known in list(cameras)[:10])
        more = f" and {len(cameras) - 10} more" if len(cameras) > 10 else ""
        hint = f"the file has {shown}{more}"
    raise ConfigError(f"no camera {name!r}; {hint}", path=path, key=key)


def _format_row(values: Iterable[float]) -> str:
    # repr gives the shortest text that reads back as the same float.
    return " ".join(repr(float(value)) for value in values)


def _check_writable(camera: Camera, path: Path) -> None:
    name = camera.name
    if not name or any(ch.isspace() for ch in name) or "#" in name or _is_number(name):
        raise UsageError(
            f"camera name {name!r} cannot be written: it must be one token, "
            "not a number, without '#'",
            path=path,
        )
    if np.any(camera.distortion[2:] != 0):
        raise UsageError(
            f"camera {name!r} has distortion terms beyond K1, K2 "
            f"({camera.distortion.tolist()}), which the format cannot store",
            path=path,
        )
    numbers = np.concatenate([camera.K.ravel(), camera.R.ravel(), camera.t, camera.distortion])
    if not np.all(np.isfinite(numbers)):
        raise UsageError(f"camera {name!r} has non-finite parameters", path=path)


def write_cameras(
    path: str | os.PathLike,
    cameras: Iterable[Camera] | Mapping[str, Camera],
    *,
    transposed_rotation: bool = False,
) -> None:
    """Write cameras as an MPEG camera parameter file that reads back to the same numbers.

    Parameters
    ----------
    path : path-like
        Output file, written atomically.
    cameras : iterable of Camera, or mapping of name to Camera
        The cameras, written in this order.
    transposed_rotation : bool
        Store ``R`` transposed (VSRS 3.5 convention).

    Raises
    ------
    UsageError
        A name that would not read back (spaces, ``#``, numeric, duplicated),
        distortion terms beyond K1, K2, or non-finite numbers.
    """
    path = Path(path)
    if isinstance(cameras, Mapping):
        cameras = cameras.values()
    cameras = list(cameras)
    seen: set[str] = set()
    for camera in cameras:
        _check_writable(camera, path)
        if camera.name in seen:
            raise UsageError(f"camera {camera.name!r} given twice", path=path)
        seen.add(camera.name)
    blocks = []
    for camera in cameras:
        rotation = camera.R.T if transposed_rotation else camera.R
        distortion = np.zeros(2)
        distortion[: min(2, camera.distortion.size)] = camera.distortion[:2]
        rows = [
            camera.name,
            *(_format_row(row) for row in camera.K),
            *(_format_row([value]) for value in distortion),
            *(_format_row([*rotation[i], camera.t[i]]) for i in range(3)),
        ]
        blocks.append("\n".join(rows) + "\n\n")
    with atomic_output(path, "w") as handle:
        handle.write("".join(blocks))


def read_htm_cameras(path: str | os.PathLike, *, frame: int = 0) -> dict[str, Camera]:
    """Read a 3D-HTM camera file of the 1D (parallel) form.

    Each row is ``ViewNum StartFrame EndFrame FocalLength Position CShift ZNear ZFar``
    (``ZNear ZFar`` may be absent, for views without depth); ``#`` starts a comment.

    Parameters
    ----------
    path : path-like
        The HTM camera file.
    frame : int
        The rows whose ``[StartFrame, EndFrame]`` contain this frame are used
        (HTM lets parameters change over time).

    Returns
    -------
    dict of str to Camera
        Keyed by the view number as written. ``K = [[f, 0, CShift], [0, f, 0],
        [0, 0, 1]]``: the file has no vertical principal point, so ``cy = 0``
        (only horizontal disparities are defined by it). ``R = I``,
        ``t = (Position, 0, 0)``, ``depth_range = (ZNear, ZFar)`` or None.
    """
    path = Path(path)
    cameras: dict[str, Camera] = {}
    lines: dict[str, int] = {}
    for number, line in enumerate(read_text(path, "camera parameter file").splitlines(), start=1):
        words = line.split("#", 1)[0].split()
        if not words:
            continue
        if len(words) not in (6, 8) or not all(_is_number(word) for word in words):
            raise ConfigError(
                f"expected 6 or 8 numbers (ViewNum StartFrame EndFrame "
                f"FocalLength Position CShift [ZNear ZFar]), got {line.strip()!r}",
                path=path,
                line=number,
            )
        values = [float(word) for word in words]
        start, end, focal, position, shift = values[1:6]
        if not start <= frame <= end:
            continue
        camera = Camera(
            name=words[0],
            K=[[focal, 0.0, shift], [0.0, focal, 0.0], [0, 0, 1]],
            t=[position, 0.0, 0.0],
            depth_range=(values[6], values[7]) if len(values) == 8 else None,
        )
        store_camera(cameras, camera, lines, path=path, line=number)
    if not cameras:
        raise ConfigError(f"no camera row covers frame {frame}", path=path)
    return cameras
