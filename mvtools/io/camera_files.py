"""Camera files by format: a reader and a writer per format, chosen by name or suffix.

The formats are those of the field's programs: the MPEG camera parameter file of VSRS
and DERS (``"mpeg"``, :mod:`mvtools.io.cameras`), the MPEG-I JSON sequence file of RVS
and TMIV (``"json"``, :mod:`mvtools.io.json_cameras`) and the 1D camera file of 3D-HTM
(``"htm"``, read only). Every program reads and writes camera files through
:func:`read_camera_file` and :func:`write_camera_file`, so a format is added in one
place; the formats themselves are described in ``docs/``.

Examples
--------
>>> from mvtools.io.camera_files import CAMERA_FILE_READERS, camera_file_format
>>> sorted(CAMERA_FILE_READERS)
['htm', 'json', 'mpeg']
>>> camera_file_format("cameras.json"), camera_file_format("cam_param_kendo.cfg")
('json', 'mpeg')
>>> camera_file_format("cameras.txt", method="vrml")
Traceback (most recent call last):
...
ValueError: 'vrml' is not a camera file format: mpeg, json or htm
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterable, Mapping
from pathlib import Path

from mvtools.geometry.camera import Camera
from mvtools.io.cameras import read_cameras, read_htm_cameras, write_cameras
from mvtools.io.json_cameras import read_json_cameras, write_json_cameras

#: Each camera file format and its reader: ``reader(path, **options)`` gives the
#: cameras by name, in the file's order.
CAMERA_FILE_READERS: dict[str, Callable[..., dict[str, Camera]]] = {
    "mpeg": read_cameras,
    "json": read_json_cameras,
    "htm": read_htm_cameras,
}

#: Each writable format and its writer: ``writer(path, cameras, **options)``.
CAMERA_FILE_WRITERS: dict[str, Callable[..., None]] = {
    "mpeg": write_cameras,
    "json": write_json_cameras,
}


def camera_file_format(
    path: str | os.PathLike,
    *,
    method: str | None = None,
    formats: Iterable[str] = CAMERA_FILE_READERS,
) -> str:
    """The format of a camera file: ``method`` when given, else ``"json"`` for a
    ``.json`` name and ``"mpeg"`` for any other.

    Raises
    ------
    ValueError
        ``method`` names no format of ``formats``.
    """
    formats = list(formats)
    if method is None:
        return "json" if Path(path).suffix.lower() == ".json" else "mpeg"
    if method not in formats:
        listed = ", ".join(formats[:-1]) + f" or {formats[-1]}"
        raise ValueError(f"{method!r} is not a camera file format: {listed}")
    return method


def read_camera_file(
    path: str | os.PathLike, *, method: str | None = None, transposed_rotation: bool = False
) -> dict[str, Camera]:
    """The cameras of a camera file, by name in the file's order.

    Parameters
    ----------
    path : path-like
    method : {"mpeg", "json", "htm"}, optional
        The format (:data:`CAMERA_FILE_READERS`); default by the name
        (:func:`camera_file_format`).
    transposed_rotation : bool
        The MPEG file stores ``R`` transposed, as VSRS 3.5 did (the other formats
        have one convention each).
    """
    method = camera_file_format(path, method=method)
    if method == "mpeg":
        return read_cameras(path, transposed_rotation=transposed_rotation)
    return CAMERA_FILE_READERS[method](path)


def write_camera_file(
    path: str | os.PathLike,
    cameras: Iterable[Camera] | Mapping[str, Camera],
    *,
    method: str | None = None,
    **options,
) -> None:
    """Write cameras in a format of :data:`CAMERA_FILE_WRITERS`, atomically.

    Parameters
    ----------
    path : path-like
    cameras : iterable of Camera, or mapping of name to Camera
    method : {"mpeg", "json"}, optional
        Default by the name (:func:`camera_file_format`).
    **options
        Passed to the format's writer (:func:`mvtools.io.cameras.write_cameras`,
        :func:`mvtools.io.json_cameras.write_json_cameras`).
    """
    method = camera_file_format(path, method=method, formats=CAMERA_FILE_WRITERS)
    CAMERA_FILE_WRITERS[method](path, cameras, **options)
