"""Outputs are written to a temporary name and renamed when complete."""

from __future__ import annotations

import contextlib
import logging
import os
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import IO

from mvtools.errors import UsageError
from mvtools.io.abort import unfinished_file
from mvtools.io.guard import claim_output

logger = logging.getLogger(__name__)


@contextlib.contextmanager
def atomic_output(
    path: str | os.PathLike, mode: str = "wb", *, what: str = "output"
) -> Iterator[IO]:
    """Open a temporary file next to ``path``; rename it to ``path`` on success.

    If the block raises, or the programs' signal handler calls
    :func:`mvtools.io.abort.abort`, the temporary file is removed and ``path`` is left as it was, so a failed run
    never leaves a half-written output behind. In a :func:`mvtools.io.guard.file_guard`
    scope, ``path`` may not name an input or another output of the run (checked when
    the file is opened and again before it replaces ``path``). ``what`` names the
    output in messages.
    """
    target = Path(path)
    directory = target.parent if str(target.parent) else Path(".")
    output_folder_exists(directory)
    claim_output(target, what)
    fd, tmp_name = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".part", dir=directory)
    try:
        with unfinished_file(tmp_name), os.fdopen(fd, mode) as handle:
            yield handle
            claim_output(target, what, again=True)
            # mkstemp creates the file private (0600); give it the usual permissions.
            os.chmod(tmp_name, 0o666 & ~_current_umask())
            handle.close()
            os.replace(tmp_name, target)
        logger.debug("%s: written (%d bytes)", target, os.path.getsize(target))
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp_name)
        raise


def output_folder_exists(directory: str | os.PathLike) -> None:
    """A UsageError naming ``directory`` unless it is an existing folder: outputs go
    where the user asked, and a missing folder is not created behind their back."""
    if not os.path.isdir(directory):
        state = "is not a folder" if os.path.exists(directory) else "does not exist"
        raise UsageError(f"the output folder {state}", path=directory)


def _current_umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask
