"""HEVC encoding and decoding of raw YUV files by Debian's ``x265`` and ``ffmpeg`` programs.

The programs are found on the PATH when a feature needs them; a missing one is a
UsageError that says how to install it. Bitstreams and decoded videos are written to a
temporary name and renamed when the program has finished.
"""

from __future__ import annotations

import os
import shutil
from pathlib import Path

from mvtools.errors import DataError, UsageError
from mvtools.io.abort import run_program, unfinished_file
from mvtools.io.atomic import output_folder_exists
from mvtools.io.guard import claim_output, note_input
from mvtools.io.yuv import YuvFormat

__all__ = ["ENCODERS", "decode_hevc", "encode_hevc", "program_path"]

ENCODERS = ("x265", "ffmpeg")
_INSTALL = {"x265": "apt-get install x265", "ffmpeg": "apt-get install ffmpeg"}
_X265_CSP = {"420": "i420", "422": "i422", "444": "i444", "400": "i400"}


def program_path(name: str) -> str:
    """The program's path, or a UsageError naming the package to install."""
    found = shutil.which(name)
    if found is None:
        raise UsageError(
            f"the {name} program is not installed: `{_INSTALL[name]}` (Debian) installs it"
        )
    return found


def _run(command: list[str], what: str, target: Path) -> None:
    output_folder_exists(target.parent)
    claim_output(target, f"{what} output")
    temporary = target.with_name(f".{target.name}.part{target.suffix}")
    command = [part if part != "{output}" else str(temporary) for part in command]
    with unfinished_file(temporary):
        try:
            completed = run_program(command)
            if completed.returncode != 0:
                message = (completed.stderr or completed.stdout).strip().splitlines()
                raise DataError(
                    f"{what} failed (exit code {completed.returncode}): "
                    f"{message[-1] if message else 'no message'}",
                    path=target,
                )
            os.replace(temporary, target)
        finally:
            if temporary.exists():
                temporary.unlink()


def encode_hevc(
    source: str | os.PathLike,
    fmt: YuvFormat,
    bitstream: str | os.PathLike,
    *,
    qp: int,
    encoder: str = "x265",
    preset: str = "medium",
    fps: float = 25.0,
) -> int:
    """Encode a raw YUV file at a constant QP; returns the bitstream's size in bytes.

    Both encoders run x265 with one frame thread, so that the same input gives the
    same bitstream.
    """
    if encoder not in ENCODERS:
        raise UsageError(f"encoder must be one of {', '.join(ENCODERS)}, got {encoder!r}")
    bitstream = Path(bitstream)
    note_input(source)
    if encoder == "x265":
        command = [
            program_path("x265"),
            "--input",
            str(source),
            "--input-res",
            f"{fmt.width}x{fmt.height}",
            "--input-csp",
            _X265_CSP[fmt.chroma],
            "--input-depth",
            str(fmt.bits),
            "--output-depth",
            str(fmt.bits),
            "--fps",
            f"{fps:g}",
            "--qp",
            str(qp),
            "--preset",
            preset,
            "--frame-threads",
            "1",
            "--no-info",
            "--log-level",
            "error",
            "--output",
            "{output}",
        ]
    else:
        command = [
            program_path("ffmpeg"),
            "-nostdin",
            "-y",
            "-loglevel",
            "error",
            "-f",
            "rawvideo",
            "-pix_fmt",
            fmt.pix_fmt,
            "-s",
            f"{fmt.width}x{fmt.height}",
            "-r",
            f"{fps:g}",
            "-i",
            str(source),
            "-c:v",
            "libx265",
            "-preset",
            preset,
            "-x265-params",
            f"qp={qp}:frame-threads=1:info=0:log-level=error",
            "-f",
            "hevc",
            "{output}",
        ]
    _run(command, f"{encoder} encoding", bitstream)
    return bitstream.stat().st_size


def decode_hevc(bitstream: str | os.PathLike, output: str | os.PathLike, fmt: YuvFormat) -> None:
    """Decode an HEVC bitstream to a raw YUV file of ``fmt`` with ffmpeg."""
    note_input(bitstream)
    command = [
        program_path("ffmpeg"),
        "-nostdin",
        "-y",
        "-loglevel",
        "error",
        "-i",
        str(bitstream),
        "-f",
        "rawvideo",
        "-pix_fmt",
        fmt.pix_fmt,
        "{output}",
    ]
    _run(command, "ffmpeg decoding", Path(output))
