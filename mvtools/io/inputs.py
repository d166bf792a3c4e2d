"""Opening the inputs named on a command line, the same way in every program."""

from __future__ import annotations

import logging
import os

from mvtools.errors import UsageError
from mvtools.io.config import ConfigEntry
from mvtools.io.yuv import VideoReader, YuvFormat, format_from_name, guess_format, open_video

LOG = logging.getLogger("mvtools")


def open_input_video(
    path: str | os.PathLike, size: tuple[int, int] | None, pix_fmt: str | None
) -> VideoReader:
    """Open a video given ``--size``/``--pix-fmt`` (either may be None).

    Missing values come from the file: a Y4M header or an ffmpeg-style name.
    """
    if size is None:
        named = format_from_name(path)
        if named is None or pix_fmt is None:
            reader = open_video(path)
            if pix_fmt is not None and reader.format.pix_fmt != pix_fmt:
                reader.close()
                raise UsageError(f"the file is {reader.format.pix_fmt}, not {pix_fmt}", path=path)
            return reader
        size = named.size
    width, height = size
    fmt = (
        YuvFormat.from_pix_fmt(width, height, pix_fmt)
        if pix_fmt
        else guess_format(path, width, height)
    )
    return open_video(path, fmt)


def frame_range(
    readers: list[VideoReader],
    start: int,
    count: int | None,
    *,
    start_given: ConfigEntry | None = None,
) -> range:
    """Frames ``start .. start+count-1`` that every reader has; warns when lengths differ.

    Parameters
    ----------
    readers : list of VideoReader
    start : int
        The first frame.
    count : int or None
        The number of frames; None for all that every reader has.
    start_given : ConfigEntry, optional
        The configuration key (in a file, or a ``Key=Value`` item) that gave ``start``,
        for the message of a start past the end; None when ``--start-frame`` gave it.

    Raises
    ------
    UsageError, ConfigError
        ``start`` is past the end of the shortest input.
    """
    available = min(len(reader) for reader in readers)
    if len({len(reader) for reader in readers}) > 1:
        lengths = ", ".join(f"{reader.path} has {len(reader)}" for reader in readers)
        LOG.warning("inputs differ in length (%s): using the first %d frames", lengths, available)
    if start >= available:
        message = f"{start} is past the end: the inputs have {available} frames"
        if start_given is not None:
            raise start_given.error(message)
        raise UsageError(f"--start-frame {message}")
    stop = available if count is None else start + count
    if stop > available:
        LOG.warning(
            "asked for %d frames from frame %d, the inputs have %d: using %d",
            count,
            start,
            available,
            available - start,
        )
        stop = available
    return range(start, stop)
