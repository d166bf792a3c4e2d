"""The one rule on what a run may write: never a file it reads, never one file twice.

A run of a program (or of a run function called from Python) is a scope,
:func:`file_guard`. Inside it every input the io layer opens is noted
(:func:`note_input`), and every output is claimed before it is written and again
before its temporary file replaces it (:func:`claim_output`, called by
:func:`mvtools.io.atomic.atomic_output`): an output that names an input, after
resolving symbolic links and relative paths (and, for existing files, hard links:
the same device and inode), or an output already written by the run, is a
:class:`~mvtools.errors.UsageError` and nothing is written. The second check catches
inputs that are read only after their output was opened.

Outside a scope nothing is checked: a script that reads a file, then writes it on
purpose, may.
"""

from __future__ import annotations

import contextlib
import contextvars
import os
from collections.abc import Iterable, Iterator
from dataclasses import dataclass, field
from pathlib import Path

from mvtools.errors import UsageError

__all__ = ["check_output", "check_outputs", "claim_output", "file_guard", "note_input"]


@dataclass
class _RunFiles:
    inputs: dict[object, Path] = field(default_factory=dict)  # identity -> as given
    outputs: dict[str, str] = field(default_factory=dict)  # real path -> what it is


_RUN: contextvars.ContextVar[_RunFiles | None] = contextvars.ContextVar(
    "mvtools_run_files", default=None
)


@contextlib.contextmanager
def file_guard() -> Iterator[None]:
    """The scope of one run; nested scopes share the outermost one's files."""
    if _RUN.get() is not None:
        yield
        return
    token = _RUN.set(_RunFiles())
    try:
        yield
    finally:
        _RUN.reset(token)


def _identities(path: Path) -> list[object]:
    """What makes two names one file: the real path, and device and inode if it exists."""
    found: list[object] = [os.path.realpath(path)]
    with contextlib.suppress(OSError):
        status = os.stat(path)
        found.append((status.st_dev, status.st_ino))
    return found


def note_input(path: str | os.PathLike) -> None:
    """Note that the current run reads ``path``."""
    run = _RUN.get()
    if run is None:
        return
    path = Path(path)
    for identity in _identities(path):
        run.inputs.setdefault(identity, path)


def check_output(path: str | os.PathLike, what: str = "output") -> None:
    """Raise a UsageError if ``path`` names a file the current run reads or has already
    claimed as an output. Claims nothing: for a program's early check of outputs it
    writes later (see also :func:`check_outputs`)."""
    run = _RUN.get()
    if run is None:
        return
    path = Path(path)
    for identity in _identities(path):
        if identity in run.inputs:
            given = run.inputs[identity]
            same = "" if given == path else f" ({given})"
            raise UsageError(
                f"the {what} would overwrite an input{same}: give it another name or folder",
                path=path,
            )
    earlier = run.outputs.get(os.path.realpath(path))
    if earlier is not None:
        raise UsageError(
            f"the {what} is already the {earlier} of this run: give each output its own name",
            path=path,
        )


def check_outputs(outputs: Iterable[tuple[str | os.PathLike, str]]) -> None:
    """:func:`check_output` for each ``(path, what)`` of ``outputs``, and a UsageError
    if two of them name one file: a program's check, before long work, of the outputs it
    writes at the end."""
    seen: dict[str, str] = {}
    for path, what in outputs:
        check_output(path, what)
        real = os.path.realpath(path)
        if real in seen:
            raise UsageError(
                f"the {what} and the {seen[real]} are one file: give each output its own name",
                path=path,
            )
        seen[real] = what


def claim_output(path: str | os.PathLike, what: str = "output", *, again: bool = False) -> None:
    """Check ``path`` as :func:`check_output` does, and note it as an output of the run.

    ``again=True`` re-checks an output this run has already claimed (just before it
    replaces the file) against the inputs read since.
    """
    run = _RUN.get()
    if run is None:
        return
    path = Path(path)
    real = os.path.realpath(path)
    if again:
        run.outputs.pop(real, None)
    check_output(path, what)
    run.outputs[real] = what
