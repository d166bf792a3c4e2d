"""The one exception hierarchy of mvtools.

Every error a user can cause derives from :class:`MvtoolsError`. It carries the
place at fault (file, line, key) so that the command-line edge can print one line
such as ``cam.txt:12: param_kendo01: camera block has 22 numbers, 23 needed`` and
exit with the class's exit code, without a traceback.
"""

from __future__ import annotations

import contextlib
import os
from collections.abc import Iterator


class MvtoolsError(Exception):
    """Base class. ``exit_code`` is what the command-line programs exit with."""

    exit_code = 1

    def __init__(
        self,
        message: str,
        *,
        path: str | os.PathLike | None = None,
        line: int | None = None,
        key: str | None = None,
    ):
        super().__init__(message)
        self.message = message
        self.path = os.fspath(path) if path is not None else None
        self.line = line
        self.key = key

    def __str__(self) -> str:
        place = ""
        if self.path is not None:
            place = self.path if self.line is None else f"{self.path}:{self.line}"
        if self.key is not None:
            place = f"{place}: {self.key}" if place else self.key
        return f"{place}: {self.message}" if place else self.message


class UsageError(MvtoolsError):
    """Wrong options or arguments, missing input files (exit code 2)."""

    exit_code = 2


class ConfigError(UsageError):
    """A configuration or camera parameter file that cannot be used (exit code 2)."""


class DataError(MvtoolsError):
    """Input data that is inconsistent or damaged: truncated video, wrong sizes (exit code 1)."""

    exit_code = 1


@contextlib.contextmanager
def at_fault(
    kind: type[MvtoolsError] = UsageError,
    *,
    path: str | os.PathLike | None = None,
    key: str | None = None,
    prefix: str = "",
) -> Iterator[None]:
    """A ValueError raised in the block (the algorithm layer's word for a value it cannot
    use) becomes ``kind`` naming the place that gave the value: an option (``key``), a
    file (``path``), a frame (``prefix="frame 3: "``).

    The programs' edge turns any other ValueError into exit code 2; this says whose
    fault it is, and a data error (``kind=DataError``) exits with 1.
    """
    try:
        yield
    except ValueError as error:
        raise kind(f"{prefix}{error}", path=path, key=key) from None
