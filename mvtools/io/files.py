"""Reading whole input files with one-line errors that name them."""

from __future__ import annotations

import json
import math
import os
from pathlib import Path

from mvtools.errors import ConfigError, UsageError
from mvtools.io.guard import note_input


def read_bytes(path: str | os.PathLike, what: str = "file") -> bytes:
    """The bytes of ``path``; a missing or unreadable file is a UsageError naming it."""
    note_input(path)
    try:
        return Path(path).read_bytes()
    except FileNotFoundError:
        raise UsageError(f"no such {what}", path=path) from None
    except IsADirectoryError:
        raise UsageError(f"is a folder, not a {what}", path=path) from None
    except OSError as err:
        raise UsageError(f"cannot read the {what}: {err.strerror}", path=path) from None


def read_text(path: str | os.PathLike, what: str = "file") -> str:
    """The text of ``path``: UTF-8 (with or without a byte-order mark), else Latin-1,
    since files written on Windows in a local code page may hold any byte in comments."""
    data = read_bytes(path, what)
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError:
        return data.decode("latin-1")


def read_json(path: str | os.PathLike, what: str = "JSON file"):
    """The document of a JSON file; invalid JSON is a ConfigError naming line and column."""
    try:
        return json.loads(read_text(path, what))
    except json.JSONDecodeError as err:
        raise ConfigError(
            f"invalid JSON: {err.msg} (column {err.colno})", path=path, line=err.lineno
        ) from None


def json_numbers(
    entry: dict, field: str, count: int, *, path: str | os.PathLike, key: str, required: bool = True
) -> list[float] | None:
    """``entry[field]`` as a list of ``count`` finite numbers (None when absent and not
    ``required``); anything else is a ConfigError naming the file and ``key``."""
    value = entry.get(field)
    if value is None and not required:
        return None
    if (
        not isinstance(value, list)
        or len(value) != count
        or not all(
            isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)
            for x in value
        )
    ):
        shown = "missing" if value is None else f"got {json.dumps(value)}"
        raise ConfigError(
            f"{field} must be a list of {count} finite numbers, {shown}", path=path, key=key
        )
    return [float(x) for x in value]
