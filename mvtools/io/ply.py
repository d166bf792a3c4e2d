"""PLY point-cloud files: coloured vertices written in binary, read in any encoding.

:func:`write_ply` writes one ``vertex`` element of ``x, y, z`` (float32, or float64
with ``precision="double"``) and ``red, green, blue`` (uchar), binary little-endian,
atomically. :func:`read_ply` reads the vertices of ``binary_little_endian``,
``binary_big_endian`` and ``ascii`` files with the properties in any order, skipping
the properties it does not need and the elements other than ``vertex`` (faces with
their list properties included). docs/ply.md describes the subset.

Binary data is read with numpy structured dtypes, one read for all vertices.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from mvtools.errors import ConfigError, DataError
from mvtools.io.atomic import atomic_output

__all__ = ["PLY_TYPES", "read_ply", "write_ply"]

#: PLY scalar type names (both spellings) and their numpy types.
PLY_TYPES = {
    "char": "i1",
    "int8": "i1",
    "uchar": "u1",
    "uint8": "u1",
    "short": "i2",
    "int16": "i2",
    "ushort": "u2",
    "uint16": "u2",
    "int": "i4",
    "int32": "i4",
    "uint": "u4",
    "uint32": "u4",
    "float": "f4",
    "float32": "f4",
    "double": "f8",
    "float64": "f8",
}

_ENCODINGS = {"binary_little_endian": "<", "binary_big_endian": ">", "ascii": None}
_PRECISIONS = {"single": ("float", "<f4"), "double": ("double", "<f8")}
_COLOURS = ("red", "green", "blue")
_POSITIONS = ("x", "y", "z")
#: Longest header we read before deciding that a file is not PLY.
_MAX_HEADER_BYTES = 1 << 20


def write_ply(
    path: str | os.PathLike,
    points,
    colors,
    *,
    precision: str = "single",
    comment: str | None = "written by mvtools",
) -> None:
    """Write coloured points as a binary little-endian PLY file, atomically.

    Parameters
    ----------
    path : path-like
    points : array_like, shape (N, 3)
        Positions; stored as float32 (``precision="single"``) or float64 (``"double"``).
    colors : array_like of int, shape (N, 3)
        RGB in 0..255, stored as uchar.
    precision : {"single", "double"}
    comment : str or None
        One header comment line (no line breaks), or none.

    Raises
    ------
    ValueError
        Shapes that are not (N, 3), colours outside 0..255, an unknown precision.
    UsageError
        An output folder that does not exist (:func:`mvtools.io.atomic.atomic_output`).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "two.ply"
    >>> write_ply(path, [[0, 0, 1], [1, 2, 3]], [[255, 0, 0], [0, 0, 255]])
    >>> read_ply(path)[0].tolist()
    [[0.0, 0.0, 1.0], [1.0, 2.0, 3.0]]
    """
    if precision not in _PRECISIONS:
        raise ValueError(f"precision must be 'single' or 'double', got {precision!r}")
    points = np.asarray(points)
    colors = np.asarray(colors)
    if points.ndim != 2 or points.shape[1] != 3:
        raise ValueError(f"points must have shape (N, 3), got {points.shape}")
    if colors.shape != points.shape:
        raise ValueError(f"colors must have the shape of points {points.shape}, got {colors.shape}")
    if colors.dtype != np.uint8 and (
        colors.dtype.kind not in "iu" or (colors.size and (colors.min() < 0 or colors.max() > 255))
    ):
        raise ValueError("colors must be integers in 0..255")
    if comment is not None and ("\n" in comment or "\r" in comment):
        raise ValueError("a PLY comment is one line")
    type_name, dtype = _PRECISIONS[precision]
    record = np.dtype([(name, dtype) for name in _POSITIONS] + [(c, "u1") for c in _COLOURS])
    data = np.empty(len(points), record)
    for axis, name in enumerate(_POSITIONS):
        data[name] = points[:, axis]
    for channel, name in enumerate(_COLOURS):
        data[name] = colors[:, channel]
    header = ["ply", "format binary_little_endian 1.0"]
    if comment is not None:
        header.append(f"comment {comment}")
    header.append(f"element vertex {len(points)}")
    header += [f"property {type_name} {name}" for name in _POSITIONS]
    header += [f"property uchar {name}" for name in _COLOURS]
    header.append("end_header")
    with atomic_output(path, "wb", what="PLY file") as handle:
        handle.write(("\n".join(header) + "\n").encode("ascii"))
        handle.write(data.tobytes())


class _Element:
    """An element of a PLY header: name, count, properties, header line."""

    def __init__(self, name: str, count: int, line: int):
        self.name = name
        self.count = count
        self.line = line
        # (name, numpy type) for scalars, (name, (count type, item type)) for lists
        self.properties: list[tuple[str, object]] = []

    @property
    def has_lists(self) -> bool:
        return any(isinstance(kind, tuple) for _, kind in self.properties)

    def dtype(self, order: str) -> np.dtype:
        return np.dtype([(name, order + kind) for name, kind in self.properties])


def _parse_header(handle, path: Path) -> tuple[str | None, list[_Element], int]:
    """(byte order or None for ascii, elements, number of header lines)."""
    first = handle.readline(16)
    if first.rstrip(b"\r\n") != b"ply":
        raise ConfigError("not a PLY file (the first line is not 'ply')", path=path, line=1)
    order = ...
    elements: list[_Element] = []
    names: set[str] = set()
    line_number = 1
    read = len(first)
    while True:
        raw = handle.readline(_MAX_HEADER_BYTES)
        line_number += 1
        read += len(raw)
        if not raw:
            raise ConfigError("the header has no end_header line", path=path, line=line_number)
        if read > _MAX_HEADER_BYTES:
            raise ConfigError("the header is longer than 1 MB", path=path, line=line_number)
        try:
            text = raw.decode("ascii").strip()
        except UnicodeDecodeError:
            raise ConfigError(
                "the header line is not ASCII text", path=path, line=line_number
            ) from None
        words = text.split()
        if not words or words[0] in ("comment", "obj_info"):
            continue
        keyword = words[0]
        if keyword == "end_header":
            break
        if keyword == "format":
            if len(words) != 3 or words[1] not in _ENCODINGS:
                raise ConfigError(
                    f"format must be one of {', '.join(_ENCODINGS)} with a version, got {text!r}",
                    path=path,
                    line=line_number,
                )
            if words[2] not in ("1.0", "1"):
                raise ConfigError(f"PLY version {words[2]} is not 1.0", path=path, line=line_number)
            order = _ENCODINGS[words[1]]
        elif keyword == "element":
            if len(words) != 3 or not words[2].isdigit():
                raise ConfigError(
                    f"an element line is 'element NAME COUNT', got {text!r}",
                    path=path,
                    line=line_number,
                )
            if words[1] in names:
                raise ConfigError(
                    f"element {words[1]} is declared twice", path=path, line=line_number
                )
            names.add(words[1])
            elements.append(_Element(words[1], int(words[2]), line_number))
        elif keyword == "property":
            if not elements:
                raise ConfigError("a property before any element", path=path, line=line_number)
            element = elements[-1]
            if len(words) == 5 and words[1] == "list":
                kinds = [PLY_TYPES.get(word) for word in words[2:4]]
                if None in kinds or kinds[0][0] == "f":
                    raise ConfigError(
                        f"a list property is 'property list COUNT_TYPE ITEM_TYPE NAME' "
                        f"with an integer count type, got {text!r}",
                        path=path,
                        line=line_number,
                    )
                kind: object = tuple(kinds)
            elif len(words) == 3 and words[1] in PLY_TYPES:
                kind = PLY_TYPES[words[1]]
            else:
                raise ConfigError(
                    f"a property line is 'property TYPE NAME' with TYPE one of "
                    f"char uchar short ushort int uint float double, got {text!r}",
                    path=path,
                    line=line_number,
                )
            if any(name == words[-1] for name, _ in element.properties):
                raise ConfigError(
                    f"property {words[-1]} of element {element.name} is declared twice",
                    path=path,
                    line=line_number,
                )
            element.properties.append((words[-1], kind))
        else:
            raise ConfigError(f"unknown header line {text!r}", path=path, line=line_number)
    if order is ...:
        raise ConfigError("the header has no format line", path=path, line=2)
    return order, elements, line_number


def _vertex_element(elements: list[_Element], path: Path) -> tuple[int, _Element]:
    found = [index for index, element in enumerate(elements) if element.name == "vertex"]
    if not found:
        raise ConfigError("the file has no vertex element", path=path, key="vertex")
    index = found[0]
    element = elements[index]
    properties = dict(element.properties)
    for name in _POSITIONS + _COLOURS:
        if name not in properties:
            raise ConfigError(
                f"the vertex element has no {name} property",
                path=path,
                line=element.line,
                key=name,
            )
        if isinstance(properties[name], tuple):
            raise ConfigError(
                f"vertex property {name} is a list, not a number",
                path=path,
                line=element.line,
                key=name,
            )
    for name in _COLOURS:
        if properties[name][0] == "f":
            raise ConfigError(
                f"vertex property {name} is a float; colours are integers 0..255",
                path=path,
                line=element.line,
                key=name,
            )
    return index, element


def read_ply(path: str | os.PathLike) -> tuple[np.ndarray, np.ndarray]:
    """The coloured vertices of a PLY file.

    Parameters
    ----------
    path : path-like
        A PLY file, binary (either byte order) or ASCII, whose ``vertex`` element has
        ``x, y, z`` (any numeric type) and ``red, green, blue`` (integers 0..255), in
        any order among other properties.

    Returns
    -------
    points : ndarray of float64, shape (N, 3)
    colors : ndarray of uint8, shape (N, 3)

    Raises
    ------
    UsageError
        A missing file.
    ConfigError
        Not a PLY file, a bad header line (``line=``), no vertex element or no
        ``x, y, z, red, green, blue`` property (``key=`` the property).
    DataError
        The data ends before the last vertex ("vertex 1234 of 5000: file ends",
        vertices counted from 0), an ASCII line with missing or bad fields (``line=``),
        colours outside 0..255.
    """
    path = Path(path)
    from mvtools.errors import UsageError

    if not path.is_file():
        raise UsageError("no such file" if not path.exists() else "not a file", path=path)
    with open(path, "rb") as handle:
        order, elements, header_lines = _parse_header(handle, path)
        index, _ = _vertex_element(elements, path)
        if order is None:
            data = _read_ascii(handle, path, elements, index, header_lines)
        else:
            data = _read_binary(handle, path, elements, index, order)
    points = np.stack([data[name].astype(np.float64) for name in _POSITIONS], axis=-1)
    colors = np.empty((len(data), 3), np.uint8)
    for channel, name in enumerate(_COLOURS):
        values = data[name]
        if values.dtype != np.uint8 and values.size and (values.min() < 0 or values.max() > 255):
            bad = int(np.flatnonzero((values < 0) | (values > 255))[0])
            raise DataError(
                f"vertex {bad} of {len(data)}: {name} {values[bad]} is outside 0..255",
                path=path,
                key=name,
            )
        colors[:, channel] = values
    return points, colors


def _read_binary(handle, path: Path, elements, index: int, order: str) -> np.ndarray:
    for element in elements[:index]:
        _skip_binary(handle, path, element, order)
    vertex = elements[index]
    if vertex.has_lists:
        raise ConfigError(
            "a vertex element with list properties is not read", path=path, line=vertex.line
        )
    dtype = vertex.dtype(order)
    wanted = dtype.itemsize * vertex.count
    raw = handle.read(wanted)
    if len(raw) < wanted:
        raise DataError(
            f"vertex {len(raw) // dtype.itemsize} of {vertex.count}: file ends", path=path
        )
    return np.frombuffer(raw, dtype)


def _skip_binary(handle, path: Path, element: _Element, order: str) -> None:
    """Move past the data of an element before ``vertex``."""
    if not element.has_lists:
        itemsize = element.dtype(order).itemsize
        remaining = os.fstat(handle.fileno()).st_size - handle.tell()
        if remaining < itemsize * element.count:
            raise DataError(
                f"{element.name} {remaining // itemsize} of {element.count}: file ends", path=path
            )
        handle.seek(itemsize * element.count, os.SEEK_CUR)
        return
    # Lists make rows of varying size: walk them (elements before vertex are rare).
    for row in range(element.count):
        for _, kind in element.properties:
            if isinstance(kind, tuple):
                count_type = np.dtype(order + kind[0])
                raw = handle.read(count_type.itemsize)
                if len(raw) < count_type.itemsize:
                    raise DataError(
                        f"{element.name} {row} of {element.count}: file ends", path=path
                    )
                length = int(np.frombuffer(raw, count_type)[0])
                size = length * np.dtype(kind[1]).itemsize
            else:
                size = np.dtype(kind).itemsize
            raw = handle.read(size)
            if len(raw) < size:
                raise DataError(f"{element.name} {row} of {element.count}: file ends", path=path)


def _read_ascii(handle, path: Path, elements, index: int, header_lines: int) -> np.ndarray:
    try:
        text = handle.read().decode("ascii")
    except UnicodeDecodeError:
        raise DataError("the ASCII data is not ASCII text", path=path) from None
    lines = text.splitlines()
    # Elements before vertex: one line per row (lists included) to skip.
    skip = sum(element.count for element in elements[:index])
    vertex = elements[index]
    if vertex.has_lists:
        raise ConfigError(
            "a vertex element with list properties is not read", path=path, line=vertex.line
        )
    first_line = header_lines + 1 + skip
    rows = lines[skip : skip + vertex.count]
    names = [name for name, _ in vertex.properties]
    if len(rows) < vertex.count:
        raise DataError(
            f"vertex {len(rows)} of {vertex.count}: file ends",
            path=path,
            line=header_lines + len(lines) + 1,
        )
    fields = [row.split() for row in rows]
    for row, words in enumerate(fields):
        if len(words) != len(names):
            missing = names[len(words)] if len(words) < len(names) else None
            detail = (
                f"has {len(words)} of {len(names)} fields, no {missing}"
                if missing
                else f"has {len(words)} fields, {len(names)} expected"
            )
            raise DataError(
                f"vertex {row} of {vertex.count} {detail}",
                path=path,
                line=first_line + row,
                key=missing,
            )
    data = np.empty(vertex.count, vertex.dtype("<"))
    if vertex.count:
        try:
            table = np.array(fields, dtype=np.float64)
        except ValueError:
            for row, words in enumerate(fields):
                for name, word in zip(names, words):
                    try:
                        float(word)
                    except ValueError:
                        raise DataError(
                            f"vertex {row} of {vertex.count}: {word!r} is not a number",
                            path=path,
                            line=first_line + row,
                            key=name,
                        ) from None
            raise
        for column, name in enumerate(names):
            data[name] = table[:, column]
    return data
