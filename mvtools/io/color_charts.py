"""Reference colours of colour charts, as colour-science publishes them.

- ``CCS_COLOURCHECKERS_*.json`` (colour-science's ``CCS_COLOURCHECKERS``): an object
  of charts by name, each an object with ``illuminant_xy`` [x, y] (the white the
  values are relative to), ``rows``, ``columns`` and ``patches``, an object of patch
  name to ``XYZ`` (Y of the perfect diffuser = 1) and ``Lab_under_chart_illuminant``
  (CIELAB relative to that white), patches in chart order: row by row from the
  top-left. The ColorChecker 24 charts are "ColorChecker 2005", "ColorChecker24 -
  Before November 2014" and "ColorChecker24 - After November 2014" (D50), and
  "ColorChecker 1976" (illuminant C).
- ``ColorChecker24_*_sRGB8bit_*.csv``: the header ``patch,R,G,B`` then one patch a line
  in chart order, 8-bit sRGB (D65) code values with decimals.
"""

from __future__ import annotations

import csv
import json
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from mvtools.color.colorimetry import xy_to_xyz
from mvtools.errors import ConfigError
from mvtools.io.files import json_numbers, read_json, read_text

__all__ = ["DEFAULT_CHART", "ColorChart", "read_colorchecker", "read_colorchecker_srgb"]

DEFAULT_CHART = "ColorChecker24 - After November 2014"


@dataclass(frozen=True)
class ColorChart:
    """The reference colours of a chart.

    Attributes
    ----------
    name : str
    patch_names : tuple of str
        In chart order, row by row from the top-left.
    layout : (int, int)
        (columns, rows); (6, 4) for a ColorChecker 24.
    xyz : ndarray, shape (N, 3)
        CIE XYZ, Y of the perfect diffuser = 1.
    lab : ndarray, shape (N, 3)
        CIELAB relative to the white of ``white_xy``.
    white_xy : (float, float)
        Chromaticity of the illuminant the values are relative to.
    """

    name: str
    patch_names: tuple[str, ...]
    layout: tuple[int, int]
    xyz: np.ndarray
    lab: np.ndarray
    white_xy: tuple[float, float]

    @property
    def white_xyz(self) -> np.ndarray:
        """The white's tristimulus values with Y = 1, shape (3,)."""
        return xy_to_xyz(self.white_xy)


# The shapes of a CCS_COLOURCHECKERS file's charts and patches, for messages.
_CHART_SHAPE = "an object of illuminant_xy [x, y], rows, columns and patches"
_PATCH_SHAPE = "an object of XYZ [X, Y, Z] and Lab_under_chart_illuminant [L, a, b]"


def _kind(value) -> str:
    """What a JSON value is, for a message: an object by its first keys."""
    if isinstance(value, dict):
        if not value:
            return "an empty object"
        more = ", ..." if len(value) > 4 else ""
        return f"an object of {', '.join(repr(key) for key in list(value)[:4])}{more}"
    if isinstance(value, list):
        return "a list"
    return "text" if isinstance(value, str) else json.dumps(value)


def _count(entry: dict, field: str, *, path: Path, key: str) -> int:
    value = entry.get(field)
    if not isinstance(value, int) or isinstance(value, bool) or value < 1:
        shown = "missing" if field not in entry else f"got {json.dumps(value)}"
        raise ConfigError(f"{field} must be a positive integer, {shown}", path=path, key=key)
    return value


def read_colorchecker(path: str | os.PathLike, *, chart: str = DEFAULT_CHART) -> ColorChart:
    """Read one chart of colour-science's ``CCS_COLOURCHECKERS`` JSON file.

    Parameters
    ----------
    path : path-like
    chart : str
        The chart's key in the file.

    Returns
    -------
    ColorChart

    Raises
    ------
    UsageError
        The file cannot be read.
    ConfigError
        Invalid JSON, no chart of that name (the message lists those there), or a
        malformed field: the key names the chart and the patch.
    """
    path = Path(path)
    document = read_json(path, "colour chart file")
    if not isinstance(document, dict):
        raise ConfigError(
            "expected an object of charts by name (colour-science's "
            f"CCS_COLOURCHECKERS), got {_kind(document)}",
            path=path,
        )
    if chart not in document:
        names = ", ".join(repr(name) for name in document) or "none"
        raise ConfigError(f"no chart {chart!r} in the file (charts: {names})", path=path)
    entry = document[chart]
    if not isinstance(entry, dict) or not {"illuminant_xy", "rows", "columns", "patches"} & set(
        entry
    ):
        # a list, or colour-science's other file: spectral distributions by patch name
        raise ConfigError(
            f"the chart must be {_CHART_SHAPE}, got {_kind(entry)}", path=path, key=chart
        )
    columns = _count(entry, "columns", path=path, key=chart)
    rows = _count(entry, "rows", path=path, key=chart)
    white_x, white_y = json_numbers(entry, "illuminant_xy", 2, path=path, key=chart)
    if white_y <= 0:
        raise ConfigError(
            f"illuminant_xy must have y > 0, got {[white_x, white_y]}", path=path, key=chart
        )
    patches = entry.get("patches")
    if not isinstance(patches, dict):
        raise ConfigError(
            f"must be an object of patch name to {_PATCH_SHAPE}, in chart "
            f"order, got {_kind(patches) if 'patches' in entry else 'nothing'}",
            path=path,
            key=f"{chart}: patches",
        )
    if len(patches) != columns * rows:
        raise ConfigError(
            f"columns x rows = {columns} x {rows} = {columns * rows} patches, got {len(patches)}",
            path=path,
            key=f"{chart}: patches",
        )
    xyz, lab = [], []
    for name, patch in patches.items():
        key = f"{chart}: {name}"
        if not isinstance(patch, dict):
            raise ConfigError(
                f"a patch must be {_PATCH_SHAPE}, got {_kind(patch)}", path=path, key=key
            )
        xyz.append(json_numbers(patch, "XYZ", 3, path=path, key=key))
        lab.append(json_numbers(patch, "Lab_under_chart_illuminant", 3, path=path, key=key))
    return ColorChart(
        name=chart,
        patch_names=tuple(patches),
        layout=(columns, rows),
        xyz=np.array(xyz),
        lab=np.array(lab),
        white_xy=(white_x, white_y),
    )


def read_colorchecker_srgb(path: str | os.PathLike) -> tuple[tuple[str, ...], np.ndarray]:
    """Read a chart's 8-bit sRGB values from a ``patch,R,G,B`` CSV file.

    Returns
    -------
    patch_names : tuple of str
        In file (chart) order.
    values : ndarray, shape (N, 3)
        sRGB code values in [0, 255], float64, as written (with their decimals).

    Raises
    ------
    UsageError
        The file cannot be read.
    ConfigError
        A wrong header, a line without four fields, a value that is not a number in
        [0, 255], a repeated patch name, or no patch; the line is named.
    """
    path = Path(path)
    lines = csv.reader(read_text(path, "colour chart file").splitlines())
    header = next(lines, None)
    if header is None or [field.strip().lower() for field in header] != ["patch", "r", "g", "b"]:
        raise ConfigError(
            f"the header must be 'patch,R,G,B', got {','.join(header or [])!r}", path=path, line=1
        )
    names: list[str] = []
    values: list[list[float]] = []
    for number, fields in enumerate(lines, start=2):
        if not fields or not "".join(fields).strip():
            continue
        if len(fields) != 4:
            raise ConfigError(
                f"expected 4 fields (patch, R, G, B), got {len(fields)}", path=path, line=number
            )
        name = fields[0].strip()
        if name in names:
            raise ConfigError(f"patch {name!r} appears twice", path=path, line=number)
        try:
            rgb = [float(field) for field in fields[1:]]
        except ValueError:
            raise ConfigError(
                f"R, G, B of {name!r} must be numbers, got {fields[1:]}", path=path, line=number
            ) from None
        if not all(0.0 <= value <= 255.0 for value in rgb):
            raise ConfigError(
                f"R, G, B of {name!r} must be in [0, 255], got {rgb}", path=path, line=number
            )
        names.append(name)
        values.append(rgb)
    if not names:
        raise ConfigError("no patch in the file", path=path)
    return tuple(names), np.array(values)
