"""Reading whole input files with one-line errors that name them."""

from __future__ import annotations

import os
from pathlib import Path

from mvtools.errors import UsageError


def read_bytes(path: str | os.PathLike, what: str = "file") -> bytes:
    """The bytes of ``path``; a missing or unreadable file is a UsageError naming it."""
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
