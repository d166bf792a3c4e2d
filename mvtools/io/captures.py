"""Calibration captures of one camera: a folder of images, a glob pattern or a video.

A source reports its camera name and capture labels before any pixel is read, and
reads one grey capture at a time, so long capture videos never sit in memory whole.
"""

from __future__ import annotations

import glob
import os
import re
from pathlib import Path

import numpy as np

from mvtools.errors import DataError, UsageError
from mvtools.io.guard import note_input
from mvtools.io.images import IMAGE_EXTENSIONS, read_image
from mvtools.io.yuv import VideoReader

__all__ = ["VIDEO_EXTENSIONS", "CaptureSource", "open_captures"]

VIDEO_EXTENSIONS = (".yuv", ".y4m")
_GLOB_CHARACTERS = re.compile(r"[*?\[]")


class CaptureSource:
    """The captures of one camera, in capture order.

    Attributes
    ----------
    name : str
        Camera name: the folder's name, the pattern's fixed part (``left`` for
        ``left*.jpg``) or the video's stem.
    labels : list of str
        One per capture: the file name, or ``frame N`` of a video.
    """

    def __init__(
        self,
        name: str,
        labels: list[str],
        *,
        files: list[Path] | None = None,
        video: VideoReader | None = None,
    ):
        self.name = name
        self.labels = labels
        self._files = files
        self._video = video
        # noted now, not when each is read: a program checks its outputs against every
        # capture before the long search through them
        for file in files or ():
            note_input(file)

    def __len__(self) -> int:
        return len(self.labels)

    def __enter__(self) -> CaptureSource:
        return self

    def __exit__(self, *exc_info) -> None:
        if self._video is not None:
            self._video.close()

    def where(self, index: int) -> str:
        """The file of capture ``index`` (for a video: ``file, frame N``)."""
        if self._video is not None:
            return f"{self._video.path}, frame {index}"
        return str(self._files[index])

    def read(self, index: int) -> np.ndarray:
        """Capture ``index`` as a grey ``(H, W)`` uint8 image (a video's luma plane)."""
        if self._video is not None:
            luma = self._video.read(index)[0]
            if luma.dtype != np.uint8:
                shift = self._video.format.bits - 8
                return (np.asarray(luma) >> shift).astype(np.uint8)
            return np.array(luma)
        image = read_image(self._files[index], grayscale=True)
        if image.dtype != np.uint8:
            raise DataError(
                f"captures must be 8-bit images, got {image.dtype}", path=self._files[index]
            )
        return image


def _pattern_name(pattern: str) -> str:
    fixed = _GLOB_CHARACTERS.split(Path(pattern).name)[0]
    return fixed.rstrip("_-. ") or Path(pattern).parent.name


def open_captures(spec: str | os.PathLike, open_video) -> CaptureSource:
    """The captures named by ``spec``.

    Parameters
    ----------
    spec : str or path-like
        A folder (its images, sorted by name), a glob pattern such as ``left*.jpg``
        (its matches, sorted), or a ``.yuv``/``.y4m`` video (its frames).
    open_video : callable
        ``open_video(path) -> VideoReader`` for videos, which knows the size and
        pixel format the command line gave.

    Raises
    ------
    UsageError
        Nothing exists at ``spec``, or it holds no images.
    """
    text = os.fspath(spec)
    path = Path(text)
    if _GLOB_CHARACTERS.search(path.name):
        files = sorted(
            Path(match)
            for match in glob.glob(text)
            if Path(match).suffix.lower() in IMAGE_EXTENSIONS
        )
        if not files:
            raise UsageError("no image matches the pattern", path=text)
        return CaptureSource(_pattern_name(text), [file.name for file in files], files=files)
    if path.is_dir():
        files = sorted(
            file
            for file in path.iterdir()
            if file.is_file() and file.suffix.lower() in IMAGE_EXTENSIONS
        )
        if not files:
            raise UsageError(
                f"the folder holds no images ({', '.join(IMAGE_EXTENSIONS)})", path=path
            )
        return CaptureSource(path.resolve().name, [file.name for file in files], files=files)
    if not path.exists():
        raise UsageError("no such folder, image pattern or video", path=path)
    if path.suffix.lower() in VIDEO_EXTENSIONS:
        video = open_video(path)
        # cam0_640x480_yuv420p.yuv is camera cam0
        name = re.sub(r"_\d+x\d+(_\w+)?$", "", path.stem) or path.stem
        return CaptureSource(name, [f"frame {index}" for index in range(len(video))], video=video)
    raise UsageError(
        "captures are a folder of images, an image pattern (quoted, e.g. "
        "'left*.jpg') or a .yuv/.y4m video",
        path=path,
    )
