"""What a process stopped by a signal must undo: the temporary files of its unfinished
outputs, and the programs it is running.

A signal's Python handler runs wherever the main thread happens to be, which may be
inside a callback from C code (numba compiling a kernel through llvmlite, for one) where
an exception is printed and ignored rather than raised. So a stopped program does not
unwind: its handler calls :func:`abort`, which undoes what this module was told of, and
the process ends there.
"""

from __future__ import annotations

import contextlib
import os
import subprocess
from collections.abc import Callable, Iterator

#: Temporary files being written, child programs running, and other undoing to do.
_UNFINISHED_FILES: set[str] = set()
_CHILDREN: set[subprocess.Popen] = set()
_UNDOING: list[Callable[[], None]] = []


@contextlib.contextmanager
def unfinished_file(path: str | os.PathLike) -> Iterator[None]:
    """Within the block, ``path`` is a temporary file that :func:`abort` removes."""
    name = os.fspath(path)
    _UNFINISHED_FILES.add(name)
    try:
        yield
    finally:
        _UNFINISHED_FILES.discard(name)


@contextlib.contextmanager
def running_child(child: subprocess.Popen) -> Iterator[subprocess.Popen]:
    """Within the block, ``child`` is a program that :func:`abort` kills; it is killed
    too when the block raises."""
    _CHILDREN.add(child)
    try:
        yield child
    except BaseException:
        child.kill()
        child.wait()
        raise
    finally:
        _CHILDREN.discard(child)


def run_program(command: list[str]) -> subprocess.CompletedProcess:
    """``subprocess.run(command, capture_output=True, text=True)``, the child being
    killed by :func:`abort` and on any exception here."""
    with subprocess.Popen(
        command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
    ) as child:
        _CHILDREN.add(child)
        try:
            stdout, stderr = child.communicate()
        except BaseException:
            child.kill()
            raise
        finally:
            _CHILDREN.discard(child)
    return subprocess.CompletedProcess(command, child.returncode, stdout, stderr)


@contextlib.contextmanager
def undone_on_abort(undo: Callable[[], None]) -> Iterator[None]:
    """Within the block, :func:`abort` calls ``undo`` (after killing the child programs,
    before removing the unfinished files): for work this module cannot see, such as the
    worker processes of a Dask cluster and the temporary files they write."""
    _UNDOING.append(undo)
    try:
        yield
    finally:
        _UNDOING.remove(undo)


def abort() -> None:
    """Kill the running child programs, undo what :func:`undone_on_abort` was given, and
    remove the unfinished temporary files."""
    for child in list(_CHILDREN):
        with contextlib.suppress(OSError):
            child.kill()
    for undo in reversed(_UNDOING):
        with contextlib.suppress(Exception):
            undo()
    for name in list(_UNFINISHED_FILES):
        with contextlib.suppress(OSError):
            os.unlink(name)
