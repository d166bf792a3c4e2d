"""The table of careless and hostile uses of the programs (issue 17), one module per
group of programs, run by ``tests/test_hostile_use.py``.

Each row is a :class:`Case`: the program's arguments, the files it finds in its
(empty, temporary) working folder, the exit code and a pattern of its one-line
message. The runner holds every row to the same rules: that exit code; for a failure
exactly one ``error:`` line matching the pattern and no traceback; every file that was
there before unchanged (nothing lost) unless the row names it as an output; no new
file but the row's outputs, and no temporary file, anywhere in the folder.

A new program gets the same treatment by adding rows.
"""

from __future__ import annotations

import shutil
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent.parent
SAMPLE = REPO / "sample_data"


@dataclass(frozen=True)
class Case:
    """One use of one program.

    Attributes
    ----------
    name : str
        Test id: what the user does wrong.
    args : tuple of str
        ``mvtools`` arguments, the program's name first; relative paths are in the
        working folder.
    exit_code : int
        0 success, 1 data error, 2 usage or config error, 130 SIGINT, 143 SIGTERM.
    message : str
        Regular expression searched for in the one ``error:`` line (failures only).
    files : callable, optional
        ``files(folder)`` writes the inputs into the working folder.
    outputs : tuple of str
        Files the run may create or replace (successes only).
    """

    name: str
    args: tuple[str, ...]
    exit_code: int
    message: str = ""
    files: Callable[[Path], None] | None = None
    outputs: tuple[str, ...] = field(default=())


def copy_sample(*names: str, folder: str = "line") -> Callable[[Path], None]:
    """A ``files`` function copying files of ``sample_data/FOLDER`` into the working folder."""

    def files(target: Path) -> None:
        for name in names:
            shutil.copy(SAMPLE / folder / name, target / name)

    return files


def write(name: str, content: str | bytes) -> Callable[[Path], None]:
    """A ``files`` function writing one file."""

    def files(target: Path) -> None:
        path = target / name
        path.parent.mkdir(parents=True, exist_ok=True)
        if isinstance(content, bytes):
            path.write_bytes(content)
        else:
            path.write_text(content)

    return files


def together(*functions: Callable[[Path], None]) -> Callable[[Path], None]:
    """A ``files`` function doing each of ``functions``."""

    def files(target: Path) -> None:
        for function in functions:
            function(target)

    return files


#: The sample line rig's synthesis inputs: configuration, cameras, views 1 and 3.
LINE_SYNTHESIS = copy_sample(
    "synthesize_cam2.cfg",
    "cameras.txt",
    "v1_texture_256x192_yuv420p.yuv",
    "v3_texture_256x192_yuv420p.yuv",
    "v1_depth_256x192_yuv420p.yuv",
    "v3_depth_256x192_yuv420p.yuv",
)
