"""Raw planar YUV video and YUV4MPEG2 (``.y4m``) files.

A frame is a tuple of 2-D arrays: ``(Y,)`` for 4:0:0 (grey) or ``(Y, U, V)``;
``uint8`` for 8-bit formats, ``uint16`` for 10, 12 and 16 bits. Raw files hold the
planes of each frame back to back with no header; samples above 8 bits take two
bytes, little-endian, the value in the low bits (ffmpeg ``yuv420p10le``,
``gray16le``). Chroma planes of 4:2:0 are ``ceil(H/2) x ceil(W/2)``, of 4:2:2
``H x ceil(W/2)``.

Readers map one frame at a time (``np.memmap``, read-only) and drop the mapping
with the arrays, so memory does not grow with the number of frames read. Writers
go through :func:`mvtools.io.atomic.atomic_output`: nothing appears at the output
path unless the writer is closed without error.

Sizes and formats can come from ffmpeg-style file names
(``v0_texture_1920x1080_yuv420p10le.yuv``); :func:`guess_format` decides from the
file size when only the picture size is known, and refuses when the guess could
halve or double the frame count.
"""

from __future__ import annotations

import contextlib
import dataclasses
import logging
import os
import re
import shutil
import sys
import tempfile
from collections.abc import Iterable, Iterator, Sequence
from fractions import Fraction
from pathlib import Path

import numpy as np

from mvtools.errors import DataError, UsageError
from mvtools.io.abort import unfinished_file
from mvtools.io.atomic import atomic_output
from mvtools.io.chroma import CHROMA_FORMATS, chroma_plane_shape
from mvtools.io.guard import note_input

__all__ = [
    "BIT_DEPTHS",
    "DEFAULT_FRAME_RATE",
    "SUPPORTED_PIX_FMTS",
    "RawVideoReader",
    "VideoReader",
    "VideoWriter",
    "Y4mReader",
    "YuvFormat",
    "format_from_name",
    "frame_from_luma",
    "guess_format",
    "open_video",
    "open_writer",
    "read_frame",
    "write_video",
]

logger = logging.getLogger(__name__)

BIT_DEPTHS = (8, 10, 12, 16)

# ffmpeg's names: "yuv420p", "yuv420p10le", ..., "gray", "gray10le", ...
_PIX_FMT_BASE = {"420": "yuv420p", "422": "yuv422p", "444": "yuv444p", "400": "gray"}
SUPPORTED_PIX_FMTS = tuple(
    base if bits == 8 else f"{base}{bits}le"
    for base in _PIX_FMT_BASE.values()
    for bits in BIT_DEPTHS
)
_PIX_FMTS = {
    (base if bits == 8 else f"{base}{bits}le"): (chroma, bits)
    for chroma, base in _PIX_FMT_BASE.items()
    for bits in BIT_DEPTHS
}
# Other spellings met in file names: yuv400p is the MPEG name of grey.
_PIX_FMTS.update(
    {("yuv400p" if bits == 8 else f"yuv400p{bits}le"): ("400", bits) for bits in BIT_DEPTHS}
)
_PIX_FMTS["gray8"] = ("400", 8)
_PIX_FMTS["y8"] = ("400", 8)


@dataclasses.dataclass(frozen=True)
class YuvFormat:
    """Picture size and sample layout of a planar YUV video.

    Parameters
    ----------
    width, height : int
        Luma size in pixels (odd sizes allowed).
    chroma : {"420", "422", "444", "400"}
        Chroma subsampling; "400" is luma only (grey, depth maps).
    bits : {8, 10, 12, 16}
        Bits per sample; above 8 bits samples are stored as little-endian uint16.
    """

    width: int
    height: int
    chroma: str = "420"
    bits: int = 8

    def __post_init__(self):
        for name in ("width", "height"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
                raise UsageError(f"{name} must be a positive integer, got {value!r}")
        if self.chroma not in CHROMA_FORMATS:
            raise UsageError(
                f"chroma format {self.chroma!r} is not one of {', '.join(CHROMA_FORMATS)}"
            )
        if self.bits not in BIT_DEPTHS:
            raise UsageError(
                f"bit depth {self.bits!r} is not one of {', '.join(map(str, BIT_DEPTHS))}"
            )
        object.__setattr__(self, "width", int(self.width))
        object.__setattr__(self, "height", int(self.height))

    @classmethod
    def from_pix_fmt(cls, width: int, height: int, pix_fmt: str) -> YuvFormat:
        """Build a format from an ffmpeg pixel format name such as ``"yuv420p10le"``.

        Raises
        ------
        UsageError
            For an unknown or unsupported name (the message lists the supported ones).
        """
        chroma, bits = _parse_pix_fmt(pix_fmt)
        return cls(width, height, chroma, bits)

    def with_(self, **changes) -> YuvFormat:
        """Copy with some fields changed (``fmt.with_(bits=16)``)."""
        return dataclasses.replace(self, **changes)

    @property
    def dtype(self) -> np.dtype:
        """``uint8`` for 8 bits, little-endian ``uint16`` (``'<u2'``) above."""
        return np.dtype(np.uint8) if self.bits == 8 else np.dtype("<u2")

    @property
    def bytes_per_sample(self) -> int:
        return 1 if self.bits == 8 else 2

    @property
    def num_planes(self) -> int:
        return 1 if self.chroma == "400" else 3

    @property
    def chroma_shape(self) -> tuple[int, int] | None:
        """(rows, columns) of each chroma plane, ``None`` for 4:0:0."""
        return chroma_plane_shape((self.height, self.width), self.chroma)

    @property
    def plane_shapes(self) -> tuple[tuple[int, int], ...]:
        """(rows, columns) of each plane: Y, then U and V if present."""
        luma = (self.height, self.width)
        if self.chroma == "400":
            return (luma,)
        return (luma, self.chroma_shape, self.chroma_shape)

    @property
    def frame_bytes(self) -> int:
        """Bytes of one frame in a raw file."""
        return sum(h * w for h, w in self.plane_shapes) * self.bytes_per_sample

    @property
    def pix_fmt(self) -> str:
        """ffmpeg name: ``yuv420p``, ``yuv444p10le``, ``gray``, ``gray16le`` ..."""
        base = _PIX_FMT_BASE[self.chroma]
        return base if self.bits == 8 else f"{base}{self.bits}le"

    @property
    def max_value(self) -> int:
        return 2**self.bits - 1

    @property
    def size(self) -> tuple[int, int]:
        """(width, height)."""
        return (self.width, self.height)

    def __str__(self) -> str:
        return f"{self.width}x{self.height} {self.pix_fmt}"


def _parse_pix_fmt(pix_fmt: str) -> tuple[str, int]:
    key = str(pix_fmt).strip().lower()
    if key in _PIX_FMTS:
        return _PIX_FMTS[key]
    hint = ""
    if key.endswith("be"):
        hint = " (big-endian samples are not supported; convert to the 'le' form)"
    raise UsageError(
        f"unknown pixel format {pix_fmt!r}{hint}; supported: "
        f"{', '.join(SUPPORTED_PIX_FMTS)} (yuv400p* is accepted for gray*)"
    )


def frame_from_luma(fmt: YuvFormat, luma: np.ndarray) -> tuple[np.ndarray, ...]:
    """Frame of ``fmt`` with the given luma and neutral chroma (``2**(bits-1)``).

    The MPEG tools store 8-bit depth maps as 4:2:0 files whose chroma is 128; this
    builds such a frame (or ``(luma,)`` for 4:0:0).
    """
    luma = np.asarray(luma)
    planes = [luma]
    if fmt.num_planes == 3:
        planes += [np.full(fmt.chroma_shape, 2 ** (fmt.bits - 1), dtype=fmt.dtype)] * 2
    return tuple(planes)


# --------------------------------------------------------------------------- names

_SIZE_TOKEN = re.compile(r"^(\d+)x(\d+)$", re.IGNORECASE)
_OTHER_PIX_FMT = re.compile(
    r"^(yuv\d{3}p\w*|yuvj\d{3}p|gray\w+|nv12|nv21|p010le|rgb24|bgr24)$", re.IGNORECASE
)


def _parse_name(path: str | os.PathLike) -> tuple[tuple[int, int] | None, str | None]:
    """(width, height) and pix_fmt found in an ffmpeg-style file name (either may be None)."""
    size = pix_fmt = None
    for token in re.split(r"[_\-.\s]+", Path(path).name):
        match = _SIZE_TOKEN.match(token)
        if match:
            size = (int(match.group(1)), int(match.group(2)))
        elif token.lower() in _PIX_FMTS:
            pix_fmt = token.lower()
        elif _OTHER_PIX_FMT.match(token):
            _parse_pix_fmt(token)  # a pixel format we do not support: say so
    return size, pix_fmt


def format_from_name(path: str | os.PathLike) -> YuvFormat | None:
    """Format carried by an ffmpeg-style name, or ``None`` when the name has no size.

    ``kendo_1024x768_yuv420p.yuv``, ``v0_depth_1920x1080_yuv420p16le.yuv``,
    ``d_640x480_gray16le.yuv``; a size alone (``name_1024x768.yuv``) means yuv420p.

    Raises
    ------
    UsageError
        If the name carries a pixel format that is not supported.
    """
    size, pix_fmt = _parse_name(path)
    if size is None:
        return None
    try:
        return YuvFormat.from_pix_fmt(size[0], size[1], pix_fmt or "yuv420p")
    except UsageError as err:
        raise UsageError(err.message, path=path) from None


# Formats tried when only the picture size is known, in order of preference. The
# 2-byte formats of one chroma layout cannot be told apart by size (10, 12, 16 bits).
_GUESS_ORDER = ("420", "400", "444", "422")


def _label(chroma: str, two_bytes: bool) -> str:
    base = "yuv400p (gray)" if chroma == "400" else _PIX_FMT_BASE[chroma]
    if not two_bytes:
        return base
    base = "gray" if chroma == "400" else base
    return f"{base}10le/12le/16le"


def _fitting_formats(file_bytes: int, width: int, height: int) -> list[tuple[str, YuvFormat, int]]:
    """(label, format, frames) for every layout whose frame size divides ``file_bytes``."""
    fits = []
    for bits in (8, 16):
        for chroma in _GUESS_ORDER:
            fmt = YuvFormat(width, height, chroma, bits)
            if file_bytes % fmt.frame_bytes == 0:
                fits.append((_label(chroma, bits != 8), fmt, file_bytes // fmt.frame_bytes))
    return fits


_COMMON_SIZES = (
    (1024, 768),
    (1920, 1080),
    (1920, 1088),
    (2048, 1088),
    (1280, 720),
    (1280, 960),
    (640, 480),
    (720, 576),
    (352, 288),
    (3840, 2160),
    (4096, 2048),
    (2048, 2048),
    (4096, 2160),
    (1280, 768),
)


def _describe(fits: Iterable[tuple[str, YuvFormat, int]], *, with_size: bool = False) -> str:
    return "; ".join(
        f"as {f'{fmt.width}x{fmt.height} ' if with_size else ''}{label} it is "
        f"{n} frame{'s' if n != 1 else ''}"
        for label, fmt, n in fits
    )


def _size_mismatch_message(file_bytes: int, fmt: YuvFormat) -> str:
    """One line: what does not fit, and which formats or sizes would."""
    message = f"{file_bytes} bytes is not a whole number of {fmt} frames of {fmt.frame_bytes} bytes"
    fits = _fitting_formats(file_bytes, fmt.width, fmt.height)
    if fits:
        return f"{message}; {_describe(fits)}: give the right --pix-fmt"
    other = [
        fit
        for size in _COMMON_SIZES
        if size != fmt.size
        for fit in _fitting_formats(file_bytes, *size)
        if fit[1].bits == fmt.bits and fit[1].chroma == fmt.chroma
    ]
    if other:
        return f"{message}; no format of that size fits, but {_describe(other, with_size=True)}"
    return f"{message}; no format of that size fits (truncated file or wrong size?)"


def guess_format(path: str | os.PathLike, width: int, height: int) -> YuvFormat:
    """Format of a raw file when only the picture size is known.

    A pixel format in the file name is used, and a Y4M file gives its own
    format. Otherwise the file size decides:
    yuv420p when it holds a whole number of yuv420p frames, else the one 8-bit
    layout (gray, yuv444p, yuv422p) that fits.

    Raises
    ------
    UsageError
        When yuv420p fits but another layout gives the same, half or double the
        number of frames (two yuv420p frames are one yuv420p10le or yuv444p
        frame), or when yuv420p does not fit and several layouts do; the message
        lists the candidates and asks for ``--pix-fmt``.
    DataError
        When the file is empty or no layout fits.
    """
    path = Path(path)
    _, pix_fmt = _parse_name(path)
    if pix_fmt is not None:
        return YuvFormat.from_pix_fmt(width, height, pix_fmt)
    file_bytes = _file_size(path)
    if _is_y4m(path):
        with Y4mReader(path) as reader:
            return reader.format
    fits = _fitting_formats(file_bytes, width, height)
    if not fits:
        raise DataError(_size_mismatch_message(file_bytes, YuvFormat(width, height)), path=path)
    # 8-bit formats come first in `fits`; a 2-byte format always has its 8-bit twin
    # at twice the count, so it is never chosen silently.
    _, chosen, frames = fits[0]
    if chosen.chroma == "420" and chosen.bits == 8:
        rivals = [fit for fit in fits[1:] if fit[2] in (frames, 2 * frames) or 2 * fit[2] == frames]
    else:
        rivals = fits[1:]
    if rivals:
        raise UsageError(
            f"cannot tell the pixel format of this {file_bytes}-byte file from the size "
            f"{width}x{height} alone: {_describe([fits[0], *rivals])}; give --pix-fmt "
            f"(or name the file like name_{width}x{height}_{chosen.pix_fmt}.yuv)",
            path=path,
        )
    return chosen


def _file_size(path: Path) -> int:
    try:
        size = path.stat().st_size
    except FileNotFoundError:
        raise UsageError("no such file", path=path) from None
    except OSError as err:
        raise UsageError(f"cannot read the file: {err.strerror}", path=path) from None
    if path.is_dir():
        raise UsageError("is a directory, not a video file", path=path)
    if size == 0:
        raise DataError("the file is empty", path=path)
    return size


# --------------------------------------------------------------------------- readers


class VideoReader:
    """Frames of a planar video file, memory-mapped one at a time.

    Use :func:`open_video`. ``path``, ``format`` and ``num_frames`` are known
    before any pixel is read, and ``frame_rate``: a Y4M header's, None for raw video,
    which carries none.
    """

    frame_rate: Fraction | None = None

    def __init__(self, path: Path, fmt: YuvFormat, handle, num_frames: int):
        self.path = path
        self.format = fmt
        self.num_frames = num_frames
        self._file = handle
        logger.debug("%s: %s, %d frames", path, fmt, num_frames)

    # The subclass knows where a frame's samples start.
    def _frame_offset(self, index: int) -> int:
        raise NotImplementedError

    def __len__(self) -> int:
        return self.num_frames

    def __enter__(self) -> VideoReader:
        return self

    def __exit__(self, *exc_info) -> None:
        self.close()

    def close(self) -> None:
        if self._file is not None:
            self._file.close()
            self._file = None

    @property
    def closed(self) -> bool:
        return self._file is None

    def __repr__(self) -> str:
        return (
            f"<{type(self).__name__} {str(self.path)!r} {self.format} "
            f"{self.num_frames} frames{' closed' if self.closed else ''}>"
        )

    def _check_index(self, index: int) -> int:
        if isinstance(index, bool) or not isinstance(index, (int, np.integer)):
            raise TypeError(f"frame index must be an integer, got {index!r}")
        if not 0 <= index < self.num_frames:
            valid = f" (0..{self.num_frames - 1})" if self.num_frames else ""
            raise UsageError(
                f"frame {index} does not exist: the video has {self.num_frames} "
                f"frame{'s' if self.num_frames != 1 else ''}{valid}",
                path=self.path,
            )
        return int(index)

    def read(self, index: int) -> tuple[np.ndarray, ...]:
        """Planes of frame ``index`` (0-based), read-only arrays mapped on the file.

        Raises
        ------
        UsageError
            If ``index`` is outside ``0 .. num_frames - 1``.
        """
        index = self._check_index(index)
        if self._file is None:
            raise ValueError(f"{self.path}: the reader is closed")
        fmt = self.format
        mapped = np.memmap(
            self._file,
            dtype=np.uint8,
            mode="r",
            offset=self._frame_offset(index),
            shape=(fmt.frame_bytes,),
        )
        samples = mapped.view(np.ndarray)
        if fmt.bits != 8:
            samples = samples.view(fmt.dtype)
        planes, start = [], 0
        for rows, cols in fmt.plane_shapes:
            planes.append(samples[start : start + rows * cols].reshape(rows, cols))
            start += rows * cols
        return tuple(planes)

    def frames(self, start: int = 0, count: int | None = None) -> Iterator[tuple[np.ndarray, ...]]:
        """Yield frames ``start, start+1, ...`` (``count`` of them, or to the end)."""
        if not 0 <= start <= self.num_frames:
            self._check_index(start)
        stop = self.num_frames if count is None else start + count
        if count is not None and (count < 0 or stop > self.num_frames):
            raise UsageError(
                f"{count} frames from frame {start} asked, the video has {self.num_frames} frames",
                path=self.path,
            )
        for index in range(start, stop):
            yield self.read(index)

    def __iter__(self) -> Iterator[tuple[np.ndarray, ...]]:
        return self.frames()


class RawVideoReader(VideoReader):
    """Headerless planar YUV file."""

    def __init__(self, path: str | os.PathLike, fmt: YuvFormat):
        path = Path(path)
        file_bytes = _file_size(path)
        if file_bytes % fmt.frame_bytes:
            raise DataError(_size_mismatch_message(file_bytes, fmt), path=path)
        note_input(path)
        # the reader owns the handle: its close() (or the with block) closes it
        handle = open(path, "rb")  # noqa: SIM115
        super().__init__(path, fmt, handle, file_bytes // fmt.frame_bytes)

    def _frame_offset(self, index: int) -> int:
        return index * self.format.frame_bytes


# --------------------------------------------------------------------------- YUV4MPEG2

Y4M_MAGIC = b"YUV4MPEG2"
_MAX_HEADER = 1 << 16

# ffmpeg's C tags (libavformat/yuv4mpegenc.c) and the format each stands for.
_Y4M_8BIT = {
    "420jpeg": "420",
    "420paldv": "420",
    "420mpeg2": "420",
    "420": "420",
    "422": "422",
    "444": "444",
    "mono": "400",
}
_Y4M_DEEP = re.compile(r"^(?:(420|422|444)p|mono)(\d+)$")


def _y4m_colorspace(fmt: YuvFormat) -> str:
    """The C tag ffmpeg writes, with its XYSCSS extension tag."""
    if fmt.chroma == "400":
        return "Cmono" if fmt.bits == 8 else f"Cmono{fmt.bits}"
    name = (
        {"420": "420jpeg"}.get(fmt.chroma, fmt.chroma)
        if fmt.bits == 8
        else f"{fmt.chroma}p{fmt.bits}"
    )
    return f"C{name} XYSCSS={name.upper()}"


def _y4m_format(tag: str, width: int, height: int, path: Path) -> YuvFormat:
    if tag in _Y4M_8BIT:
        chroma, bits = _Y4M_8BIT[tag], 8
    else:
        match = _Y4M_DEEP.match(tag)
        if not (match and int(match.group(2)) in BIT_DEPTHS):
            raise DataError(
                f"YUV4MPEG2 colour space C{tag} is not supported (supported: "
                f"420jpeg, 420paldv, 420mpeg2, 420, 422, 444, mono and their "
                f"p10/p12/p16, mono10/12/16)",
                path=path,
            )
        chroma, bits = match.group(1) or "400", int(match.group(2))
    try:
        return YuvFormat(width, height, chroma, bits)
    except UsageError as error:  # W0 or H-4: the file's header is at fault, not the user
        raise DataError(f"YUV4MPEG2 header: {error.message}", path=path) from None


class Y4mReader(VideoReader):
    """YUV4MPEG2 file: a header line, then frames each behind a ``FRAME...`` line.

    Frame offsets assume every ``FRAME`` line has the length of the first (what
    every writer does); this is verified at the last frame and at every read, and
    the file is indexed line by line if it does not hold.
    """

    def __init__(self, path: str | os.PathLike):
        path = Path(path)
        file_bytes = _file_size(path)
        note_input(path)
        handle = open(path, "rb")  # noqa: SIM115 (the reader owns it, as above)
        try:
            fmt, params, self._data_start = self._parse_header(handle, path)
            self.frame_rate = _ratio(params.get("F"), path, "F")
            self.pixel_aspect = _ratio(params.get("A"), path, "A")
            self.interlacing = params.get("I")
            self.parameters = params
            self._offsets = None
            self._frame_line = 0
            self.path, self.format = path, fmt  # needed by the frame count's messages
            super().__init__(path, fmt, handle, self._count_frames(handle, file_bytes))
        except BaseException:
            handle.close()
            raise

    @staticmethod
    def _parse_header(handle, path: Path) -> tuple[YuvFormat, dict[str, str], int]:
        head = handle.read(_MAX_HEADER)
        end = head.find(b"\n")
        if not head.startswith(Y4M_MAGIC + b" ") or end < 0:
            raise DataError("not a YUV4MPEG2 file (no 'YUV4MPEG2 ...' header line)", path=path)
        params: dict[str, str] = {}
        for token in head[len(Y4M_MAGIC) : end].decode("ascii", "replace").split():
            if token[0] != "X":  # X tags are extensions; ffmpeg's XYSCSS repeats C
                params[token[0]] = token[1:]
        try:
            width, height = int(params["W"]), int(params["H"])
        except (KeyError, ValueError):
            raise DataError("YUV4MPEG2 header without a valid W and H", path=path) from None
        fmt = _y4m_format(params.get("C", "420jpeg"), width, height, path)
        return fmt, params, end + 1

    @staticmethod
    def _frame_line_at(handle, offset: int) -> int:
        """Length of the FRAME line starting at ``offset`` (0 if there is none)."""
        handle.seek(offset)
        line = handle.read(1024)
        end = line.find(b"\n")
        return end + 1 if line.startswith(b"FRAME") and end >= 0 else 0

    def _count_frames(self, handle, file_bytes: int) -> int:
        payload = file_bytes - self._data_start
        if payload == 0:
            # as an empty raw file is: no program has anything to do with it
            raise DataError(
                "the video holds no frame (a YUV4MPEG2 header and nothing more)", path=self.path
            )
        frame_line = self._frame_line_at(handle, self._data_start)
        if frame_line == 0:
            raise DataError(f"no FRAME line at byte {self._data_start}", path=self.path)
        stride = frame_line + self.format.frame_bytes
        count, remainder = divmod(payload, stride)
        if (
            remainder == 0
            and self._frame_line_at(handle, self._data_start + (count - 1) * stride) == frame_line
        ):
            self._frame_line = frame_line
            return count
        return len(self._index(handle, file_bytes))

    def _index(self, handle, file_bytes: int) -> np.ndarray:
        """Offsets of every frame's samples, found by walking the FRAME lines."""
        offsets, position, fmt = [], self._data_start, self.format
        while position < file_bytes:
            frame_line = self._frame_line_at(handle, position)
            if frame_line == 0:
                raise DataError(
                    f"frame {len(offsets)}: no FRAME line at byte {position}", path=self.path
                )
            if position + frame_line + fmt.frame_bytes > file_bytes:
                raise DataError(
                    f"frame {len(offsets)} is truncated: {file_bytes - position - frame_line} of "
                    f"{fmt.frame_bytes} bytes of a {fmt} frame present",
                    path=self.path,
                )
            offsets.append(position + frame_line)
            position += frame_line + fmt.frame_bytes
        self._offsets = np.asarray(offsets, dtype=np.int64)
        return self._offsets

    def _frame_offset(self, index: int) -> int:
        if self._offsets is not None:
            return int(self._offsets[index])
        stride = self._frame_line + self.format.frame_bytes
        line_start = self._data_start + index * stride
        if self._frame_line_at(self._file, line_start) != self._frame_line:
            self._index(self._file, os.fstat(self._file.fileno()).st_size)
            return int(self._offsets[index])
        return line_start + self._frame_line


def _ratio(value: str | None, path: Path, tag: str) -> Fraction | None:
    if value is None:
        return None
    try:
        num, den = (int(part) for part in value.split(":"))
        return Fraction(num, den) if den else None
    except ValueError:
        raise DataError(
            f"YUV4MPEG2 header tag {tag}{value} is not 'number:number'", path=path
        ) from None


#: The file name that means standard input (for a reader) or standard output (for a
#: writer), as in ffmpeg: the stream is Y4M, which carries its own format.
STANDARD_STREAM = "-"


def is_standard_stream(path: str | os.PathLike) -> bool:
    """Whether ``path`` is :data:`STANDARD_STREAM` (a file named ``-`` is written as ``./-``)."""
    return os.fspath(path) == STANDARD_STREAM


class StdinY4mReader(Y4mReader):
    """A Y4M stream on standard input (``ffmpeg ... -f yuv4mpegpipe -``).

    Programs address frames by index and know the number of frames before they start,
    which a pipe cannot tell; so the stream is first copied, in blocks, to a temporary
    file (in ``TMPDIR``), which :meth:`close` removes, as does a stopping signal. Memory
    does not grow with the number of frames; the disk holds one copy of the input.
    """

    def __init__(self, stream=None):
        stream = sys.stdin.buffer if stream is None else stream
        fd, name = tempfile.mkstemp(prefix=".mvtools-stdin.", suffix=".y4m")
        self._spool = contextlib.ExitStack()
        self._spool.enter_context(unfinished_file(name))
        self._spool.callback(os.unlink, name)
        try:
            with os.fdopen(fd, "wb") as spool:
                shutil.copyfileobj(stream, spool, 1 << 20)
            with open(name, "rb") as spooled:
                start = spooled.read(len(Y4M_MAGIC))
            if not start:
                raise DataError("standard input is empty: pipe a Y4M stream into it", path="-")
            if start != Y4M_MAGIC:
                raise DataError(
                    "standard input is not a Y4M stream (no 'YUV4MPEG2 ...' header): "
                    "pipe Y4M into it, e.g. ffmpeg ... -f yuv4mpegpipe -",
                    path="-",
                )
            super().__init__(name)
        except BaseException:
            self._spool.close()
            raise
        self.path = Path(STANDARD_STREAM)

    def close(self) -> None:
        super().close()
        self._spool.close()


def _is_y4m(path: Path) -> bool:
    if path.suffix.lower() == ".y4m":
        return True
    with contextlib.suppress(OSError), open(path, "rb") as handle:
        return handle.read(len(Y4M_MAGIC)) == Y4M_MAGIC
    return False


def open_video(path: str | os.PathLike, fmt: YuvFormat | None = None) -> VideoReader:
    """Open a raw YUV or ``.y4m`` file for reading.

    Parameters
    ----------
    path : path-like
        ``.y4m`` (or any file starting with ``YUV4MPEG2``) carries its format; a raw
        file needs ``fmt`` or an ffmpeg-style name (``name_1024x768_yuv420p.yuv``).
        ``-`` reads a Y4M stream from standard input (:class:`StdinY4mReader`).
    fmt : YuvFormat, optional
        Format of a raw file (wins over the name). Ignored for Y4M, except that a
        different size or layout is an error.

    Returns
    -------
    VideoReader
        Context manager with ``path``, ``format``, ``num_frames``, ``read(index)``,
        ``frames(start, count)`` and iteration over frames.

    Raises
    ------
    UsageError
        Missing file, or no format given and none in the name.
    DataError
        Empty file, a Y4M file holding no frame, or a size that is not a whole number
        of frames (the message names the formats that would fit).
    """
    if is_standard_stream(path):
        reader = StdinY4mReader()
    else:
        path = Path(path)
        _file_size(path)
        reader = Y4mReader(path) if _is_y4m(path) else None
    if reader is not None:
        if fmt is not None and fmt != reader.format:
            reader.close()
            raise UsageError(f"the file is {reader.format}, not {fmt} as asked", path=path)
        return reader
    named = format_from_name(path)
    if fmt is None:
        if named is None:
            raise UsageError(
                "picture size and pixel format unknown: give them (e.g. --size "
                "1024x768 --pix-fmt yuv420p) or name the file like "
                "name_1024x768_yuv420p.yuv",
                path=path,
            )
        fmt = named
    elif named is not None and _parse_name(path)[1] is not None and named != fmt:
        logger.warning("%s: the name says %s, reading it as %s as asked", path, named, fmt)
    return RawVideoReader(path, fmt)


def read_frame(
    path: str | os.PathLike, fmt: YuvFormat | None = None, index: int = 0
) -> tuple[np.ndarray, ...]:
    """One frame of a video file as writable in-memory arrays (see :func:`open_video`)."""
    with open_video(path, fmt) as reader:
        return tuple(
            np.array(plane, dtype=reader.format.dtype.newbyteorder("="))
            for plane in reader.read(index)
        )


# --------------------------------------------------------------------------- writers

#: Frames a second written into a Y4M header when the source tells none.
DEFAULT_FRAME_RATE = 25


def y4m_header(fmt: YuvFormat, frame_rate: Fraction | int | str | None = None) -> bytes:
    """The Y4M stream header of ``fmt`` (ffmpeg's colour-space tags); ``frame_rate``
    None is :data:`DEFAULT_FRAME_RATE`."""
    rate = Fraction(DEFAULT_FRAME_RATE if frame_rate is None else frame_rate)
    return (
        f"YUV4MPEG2 W{fmt.width} H{fmt.height} F{rate.numerator}:{rate.denominator} "
        f"Ip A1:1 {_y4m_colorspace(fmt)}\n".encode("ascii")
    )


def frame_bytes(fmt: YuvFormat, planes: Sequence[np.ndarray] | np.ndarray) -> bytes:
    """One frame's samples as a raw YUV file stores them.

    Parameters
    ----------
    fmt : YuvFormat
    planes : sequence of ndarray
        ``(Y, U, V)`` (``(Y,)`` or a bare 2-D array for 4:0:0), shapes
        ``fmt.plane_shapes``, dtype uint8 for 8 bits, uint16 above.

    Raises
    ------
    ValueError
        Wrong number of planes, shape or dtype, or samples above ``max_value``.
    """
    if isinstance(planes, np.ndarray) and planes.ndim == 2:
        planes = (planes,)
    if len(planes) != fmt.num_planes:
        raise ValueError(f"{fmt.pix_fmt} frame needs {fmt.num_planes} planes, got {len(planes)}")
    chunks = []
    for name, plane, shape in zip("YUV", planes, fmt.plane_shapes):
        plane = np.asarray(plane)
        if plane.shape != shape:
            raise ValueError(
                f"plane {name} of a {fmt} frame must have shape {shape}, got {plane.shape}"
            )
        expected = np.uint8 if fmt.bits == 8 else np.uint16
        if plane.dtype.kind != "u" or plane.dtype.itemsize != np.dtype(expected).itemsize:
            raise ValueError(
                f"plane {name} of a {fmt.bits}-bit frame must be {np.dtype(expected)}, "
                f"got {plane.dtype}"
            )
        if fmt.bits not in (8, 16) and plane.size and int(plane.max()) > fmt.max_value:
            raise ValueError(
                f"plane {name} has value {int(plane.max())} above the {fmt.bits}-bit "
                f"maximum {fmt.max_value}"
            )
        chunks.append(np.ascontiguousarray(plane, dtype=fmt.dtype).tobytes())
    return b"".join(chunks)


class VideoWriter:
    """Writes frames to a raw YUV or Y4M file, atomically. Use :func:`open_writer`.

    The output appears at ``path`` when :meth:`close` (or the end of the
    ``with`` block) is reached without error; after an exception in the block
    nothing is left behind.
    """

    def __init__(
        self,
        path: str | os.PathLike,
        fmt: YuvFormat,
        *,
        y4m: bool,
        frame_rate: Fraction | int | str | None = None,
        what: str = "output",
    ):
        self.path = Path(path)
        self.format = fmt
        self.num_frames = 0
        self.y4m = y4m
        self._stack = contextlib.ExitStack()
        if is_standard_stream(path):
            # A stream cannot be renamed into place: what was written has gone down the pipe.
            self._file = sys.stdout.buffer
            self._stack.callback(self._file.flush)
        else:
            self._file = self._stack.enter_context(atomic_output(self.path, "wb", what=what))
        if y4m:
            self._file.write(y4m_header(fmt, frame_rate))

    def write(self, planes: Sequence[np.ndarray] | np.ndarray) -> None:
        """Append one frame.

        Parameters
        ----------
        planes : sequence of ndarray
            ``(Y, U, V)`` (``(Y,)`` or a bare 2-D array for 4:0:0), shapes
            ``format.plane_shapes``, dtype uint8 for 8 bits, uint16 above.

        Raises
        ------
        ValueError
            Wrong number of planes, shape or dtype, or samples above ``max_value``.
        """
        if self._file is None:
            raise ValueError(f"{self.path}: the writer is closed")
        data = frame_bytes(self.format, planes)
        if self.y4m:
            self._file.write(b"FRAME\n")
        self._file.write(data)
        self.num_frames += 1

    def close(self) -> None:
        """Finish the file: it appears at ``path``."""
        if self._file is not None:
            self._file = None
            self._stack.close()

    def abort(self) -> None:
        """Give up: remove the temporary file, leave ``path`` as it was."""
        if self._file is not None:
            self._file = None
            with contextlib.suppress(_Aborted):
                self._stack.__exit__(_Aborted, _Aborted(), None)

    def __enter__(self) -> VideoWriter:
        return self

    def __exit__(self, exc_type, exc, tb) -> None:
        if exc_type is None:
            self.close()
        else:
            self.abort()

    def __repr__(self) -> str:
        return f"<VideoWriter {str(self.path)!r} {self.format} {self.num_frames} frames>"


class _Aborted(Exception):
    """Sent into the atomic output to make it discard the temporary file."""


def open_writer(
    path: str | os.PathLike,
    fmt: YuvFormat,
    *,
    frame_rate: Fraction | int | str | None = None,
    what: str = "output",
) -> VideoWriter:
    """Open a raw YUV (any extension but ``.y4m``) or Y4M file for writing.

    ``frame_rate`` (Y4M only) is a number or ``"30000/1001"``; None (a source that
    carries none, such as raw video) is :data:`DEFAULT_FRAME_RATE`. The Y4M header is
    ffmpeg's: ``C420jpeg`` for 8-bit 4:2:0, ``C444``, ``Cmono``, ``C420p10``,
    ``Cmono16`` ... ``what`` names the output in messages (``"packed video (-o)"``).
    ``-`` writes a Y4M stream to standard output (``... -o - | ffplay -``).
    """
    y4m = is_standard_stream(path) or Path(path).suffix.lower() == ".y4m"
    return VideoWriter(path, fmt, y4m=y4m, frame_rate=frame_rate, what=what)


def write_video(
    path: str | os.PathLike,
    fmt: YuvFormat,
    frames: Iterable[Sequence[np.ndarray]],
    *,
    frame_rate: Fraction | int | str | None = None,
) -> int:
    """Write all ``frames`` (each a tuple of planes) to ``path``; returns the count."""
    with open_writer(path, fmt, frame_rate=frame_rate) as writer:
        for planes in frames:
            writer.write(planes)
    return writer.num_frames
