"""HEVC encoding and decoding of raw YUV files by Debian's ``x265`` and ``ffmpeg`` programs,
and MP4 output (H.264) through ``ffmpeg``.

The programs are found on the PATH when a feature needs them; a missing one is a
UsageError that says how to install it. Bitstreams and decoded videos are written to a
temporary name and renamed when the program has finished.
"""

from __future__ import annotations

import contextlib
import os
import shutil
import subprocess
from fractions import Fraction
from pathlib import Path

from mvtools.errors import DataError, UsageError
from mvtools.io.abort import run_program, running_child, unfinished_file
from mvtools.io.atomic import output_folder_exists
from mvtools.io.guard import claim_output, note_input
from mvtools.io.yuv import YuvFormat, frame_bytes, open_writer, y4m_header

__all__ = [
    "ENCODERS",
    "Mp4Writer",
    "decode_hevc",
    "encode_hevc",
    "open_video_output",
    "program_path",
]

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


class Mp4Writer:
    """Writes frames to an MP4 file (H.264, CRF 18, one encoder thread: the same frames
    give the same bytes) through ``ffmpeg``; the interface of
    :class:`mvtools.io.yuv.VideoWriter`. The file appears when :meth:`close` is reached;
    after an error, or :meth:`abort`, nothing is left behind.

    Takes 8-bit 4:2:0 video, what MP4 players show.
    """

    def __init__(
        self,
        path: str | os.PathLike,
        fmt: YuvFormat,
        *,
        frame_rate: Fraction | int | str | None = None,
        what: str = "output",
    ):
        if fmt.bits != 8 or fmt.chroma != "420":
            raise UsageError(
                f"MP4 output takes 8-bit 4:2:0 video, not {fmt.pix_fmt}: write .y4m or .yuv",
                path=path,
            )
        self.path = Path(path)
        self.format = fmt
        self.num_frames = 0
        output_folder_exists(self.path.parent if str(self.path.parent) else Path("."))
        claim_output(self.path, what)
        self._what = what
        self._temporary = self.path.with_name(f".{self.path.name}.part.mp4")
        command = [
            program_path("ffmpeg"),
            "-hide_banner",
            "-y",
            "-loglevel",
            "error",
            "-f",
            "yuv4mpegpipe",
            "-i",
            "-",
            "-c:v",
            "libx264",
            "-crf",
            "18",
            "-threads",
            "1",
            "-pix_fmt",
            "yuv420p",
            "-movflags",
            "+faststart",
            str(self._temporary),
        ]
        self._stack = contextlib.ExitStack()
        self._stack.enter_context(unfinished_file(self._temporary))
        self._child = self._stack.enter_context(
            running_child(
                subprocess.Popen(
                    command,
                    stdin=subprocess.PIPE,
                    stdout=subprocess.DEVNULL,
                    stderr=subprocess.PIPE,
                )
            )
        )
        self._child.stdin.write(y4m_header(fmt, frame_rate))

    def write(self, planes) -> None:
        """Append one frame (as :meth:`mvtools.io.yuv.VideoWriter.write`)."""
        data = frame_bytes(self.format, planes)
        try:
            self._child.stdin.write(b"FRAME\n" + data)
        except BrokenPipeError:
            raise DataError("ffmpeg stopped reading the video", path=self.path) from None
        self.num_frames += 1

    def close(self) -> None:
        """Finish encoding: the file appears at ``path``."""
        if self._child is None:
            return
        child, self._child = self._child, None
        try:
            child.stdin.close()
            error = child.stderr.read().decode(errors="replace").strip().splitlines()
            if child.wait() != 0:
                raise DataError(
                    f"ffmpeg encoding failed (exit code {child.returncode}): "
                    f"{error[-1] if error else 'no message'}",
                    path=self.path,
                )
            claim_output(self.path, self._what, again=True)
            os.replace(self._temporary, self.path)
        finally:
            with contextlib.suppress(FileNotFoundError):
                self._temporary.unlink()
            self._stack.close()

    def abort(self) -> None:
        """Give up: stop ffmpeg, remove its unfinished file."""
        if self._child is None:
            return
        child, self._child = self._child, None
        child.kill()
        child.wait()
        with contextlib.suppress(FileNotFoundError):
            self._temporary.unlink()
        self._stack.close()

    def __enter__(self) -> Mp4Writer:
        return self

    def __exit__(self, exc_type, exc, tb) -> None:
        if exc_type is None:
            self.close()
        else:
            self.abort()


def open_video_output(
    path: str | os.PathLike,
    fmt: YuvFormat,
    *,
    frame_rate: Fraction | int | str | None = None,
    what: str = "output",
):
    """A writer for ``path``: MP4 through ffmpeg for a ``.mp4`` name (:class:`Mp4Writer`),
    else raw YUV or Y4M (:func:`mvtools.io.yuv.open_writer`)."""
    if Path(path).suffix.lower() == ".mp4":
        return Mp4Writer(path, fmt, frame_rate=frame_rate, what=what)
    return open_writer(path, fmt, frame_rate=frame_rate, what=what)
