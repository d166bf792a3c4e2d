"""Colour look-up tables as files: mvtools' text tables and the ``.cube`` format.

Text tables (``read_lut``/``write_lut``) hold one line per input code: the code, then
the corrected value of every channel, with ``#`` comments naming the channels::

    # mvtools colour table: channels R G B, 256 codes
    0 1.250 0.000 3.117
    1 2.250 0.981 4.102
    ...

Colour matrices (``read_matrix``/``write_matrix``) hold three (linear) or four (affine)
rows of three numbers, row-vector convention: ``corrected = [r, g, b(, 1)] @ matrix``.

``.cube`` files (Adobe/Resolve, read by colour tools and ffmpeg's ``lut1d``/``lut3d``
filters) hold values normalised to 0..1: ``LUT_1D_SIZE`` tables (one line per entry,
one value per channel) or a ``LUT_3D_SIZE`` cube (red varying fastest).
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from mvtools.errors import ConfigError
from mvtools.io.atomic import atomic_output
from mvtools.io.files import read_text

__all__ = ["read_cube", "read_lut", "read_matrix", "write_cube", "write_lut", "write_matrix"]


def write_lut(path: str | os.PathLike, table: np.ndarray, *, channels: tuple[str, ...]) -> None:
    """Write tables of shape (C, L) as a text table, atomically.

    Parameters
    ----------
    path : path-like
    table : ndarray, shape (C, L)
        Corrected value of each code, per channel.
    channels : tuple of str
        A name per channel, e.g. ``("R", "G", "B")`` or ``("Y", "U", "V")``.
    """
    table = np.atleast_2d(np.asarray(table, dtype=np.float64))
    if len(channels) != table.shape[0]:
        raise ValueError(f"{table.shape[0]} tables but {len(channels)} channel names")
    lines = [f"# mvtools colour table: channels {' '.join(channels)}, {table.shape[1]} codes"]
    lines += [
        f"{code} " + " ".join(f"{value:.3f}" for value in table[:, code])
        for code in range(table.shape[1])
    ]
    with atomic_output(path, "w") as handle:
        handle.write("\n".join(lines) + "\n")


def read_lut(path: str | os.PathLike) -> tuple[np.ndarray, tuple[str, ...]]:
    """Read a text table: (tables of shape (C, L), channel names).

    Raises
    ------
    ConfigError
        A line that is not a code and C numbers, codes out of order or missing.
    """
    path = Path(path)
    channels: tuple[str, ...] | None = None
    rows = []
    for number, line in enumerate(read_text(path, "colour table").splitlines(), start=1):
        text, _, comment = line.partition("#")
        if "channels" in comment and channels is None:
            channels = tuple(comment.split("channels", 1)[1].split(",")[0].split())
        if not text.strip():
            continue
        fields = text.split()
        try:
            code, *values = int(fields[0]), *(float(field) for field in fields[1:])
        except ValueError:
            raise ConfigError(
                f"expected a code and a value per channel, got {text.strip()!r}",
                path=path,
                line=number,
            ) from None
        if code != len(rows):
            raise ConfigError(f"code {code} where code {len(rows)} was due", path=path, line=number)
        if rows and len(values) != len(rows[0]):
            raise ConfigError(
                f"{len(values)} values where earlier lines have {len(rows[0])}",
                path=path,
                line=number,
            )
        rows.append(values)
    if len(rows) < 2:
        raise ConfigError("a colour table needs at least two codes", path=path)
    table = np.array(rows).T
    if channels is None or len(channels) != table.shape[0]:
        channels = tuple(f"C{index}" for index in range(table.shape[0]))
    return table, channels


def write_cube(
    path: str | os.PathLike, table: np.ndarray, *, max_value: float, title: str | None = None
) -> None:
    """Write a ``.cube`` file, atomically.

    Parameters
    ----------
    path : path-like
    table : ndarray, shape (3, L) or (N, N, N, 3)
        Three per-channel tables (``LUT_1D_SIZE L``), or a cube indexed
        ``[blue, green, red]`` of RGB outputs (``LUT_3D_SIZE N``, red fastest).
    max_value : float
        The value that ``.cube``'s 1.0 stands for (255 for 8-bit codes).
    title : str, optional
    """
    table = np.asarray(table, dtype=np.float64)
    if table.ndim == 2 and table.shape[0] == 3:
        header, rows = f"LUT_1D_SIZE {table.shape[1]}", table.T
    elif table.ndim == 4 and table.shape[3] == 3 and len(set(table.shape[:3])) == 1:
        header, rows = f"LUT_3D_SIZE {table.shape[0]}", table.reshape(-1, 3)
    else:
        raise ValueError(f"a .cube holds (3, L) tables or an (N, N, N, 3) cube, got {table.shape}")
    lines = [f'TITLE "{title}"'] if title else []
    lines += [header, "DOMAIN_MIN 0.0 0.0 0.0", "DOMAIN_MAX 1.0 1.0 1.0"]
    lines += [
        " ".join(f"{value:.6f}" for value in np.clip(row / max_value, 0.0, 1.0)) for row in rows
    ]
    with atomic_output(path, "w") as handle:
        handle.write("\n".join(lines) + "\n")


def read_cube(path: str | os.PathLike) -> np.ndarray:
    """Read a ``.cube`` file with values in 0..1: (3, L) tables or an (N, N, N, 3) cube
    indexed ``[blue, green, red]``.

    Raises
    ------
    ConfigError
        No size line, a malformed line, or a count of entries that does not match.
    """
    path = Path(path)
    size, three_d, rows = None, False, []
    for number, line in enumerate(read_text(path, ".cube file").splitlines(), start=1):
        text = line.split("#", 1)[0].strip()
        if not text:
            continue
        keyword = text.split()[0]
        if keyword in ("LUT_1D_SIZE", "LUT_3D_SIZE"):
            try:
                size = int(text.split()[1])
            except (IndexError, ValueError):
                raise ConfigError(
                    f"{keyword} needs a whole number", path=path, line=number
                ) from None
            three_d = keyword == "LUT_3D_SIZE"
            continue
        if keyword in (
            "TITLE",
            "DOMAIN_MIN",
            "DOMAIN_MAX",
            "LUT_1D_INPUT_RANGE",
            "LUT_3D_INPUT_RANGE",
        ):
            continue
        try:
            values = [float(field) for field in text.split()]
        except ValueError:
            raise ConfigError(f"unknown line {text!r}", path=path, line=number) from None
        if len(values) != 3:
            raise ConfigError(f"expected three values, got {len(values)}", path=path, line=number)
        rows.append(values)
    if size is None:
        raise ConfigError("no LUT_1D_SIZE or LUT_3D_SIZE line", path=path)
    expected = size**3 if three_d else size
    if len(rows) != expected:
        raise ConfigError(f"{len(rows)} entries where the size asks for {expected}", path=path)
    rows = np.array(rows)
    return rows.reshape(size, size, size, 3) if three_d else rows.T


def write_matrix(path: str | os.PathLike, matrix: np.ndarray) -> None:
    """Write a (3, 3) or (4, 3) colour matrix as text, atomically."""
    matrix = np.asarray(matrix, dtype=np.float64)
    if matrix.shape not in ((3, 3), (4, 3)):
        raise ValueError(f"a colour matrix is (3, 3) or (4, 3), got {matrix.shape}")
    lines = [
        "# mvtools colour matrix, row vectors: corrected linear RGB = "
        + ("[r g b] @ M" if matrix.shape[0] == 3 else "[r g b 1] @ M")
    ]
    lines += [" ".join(f"{value:.9f}" for value in row) for row in matrix]
    with atomic_output(path, "w") as handle:
        handle.write("\n".join(lines) + "\n")


def read_matrix(path: str | os.PathLike) -> np.ndarray:
    """Read a colour matrix written by :func:`write_matrix`: shape (3, 3) or (4, 3).

    Raises
    ------
    ConfigError
        A row that is not three numbers, or not three or four rows.
    """
    path = Path(path)
    rows = []
    for number, line in enumerate(read_text(path, "colour matrix").splitlines(), start=1):
        text = line.split("#", 1)[0].strip()
        if not text:
            continue
        try:
            values = [float(field) for field in text.split()]
        except ValueError:
            values = []
        if len(values) != 3:
            raise ConfigError(f"expected three numbers, got {text!r}", path=path, line=number)
        rows.append(values)
    if len(rows) not in (3, 4):
        raise ConfigError(f"a colour matrix has 3 or 4 rows, got {len(rows)}", path=path)
    return np.array(rows)
