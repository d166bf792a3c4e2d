"""The frame loop every run function shares: frame by frame, one frame in memory."""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from typing import Any

#: Called after each frame with the frames done and the frames in all.
ProgressCallback = Callable[[int, int], None]


def stream_frames(
    frames: range,
    step: Callable[..., Iterable[Any] | None],
    *,
    readers: Sequence[Any] = (),
    writers: Sequence[Any] = (),
    progress: ProgressCallback | None = None,
) -> None:
    """Run ``step`` on each frame of ``frames`` in order.

    ``step(index, *frames_read)`` gets the frame index and frame ``index`` of each of
    ``readers`` (objects with ``read(index)``, as :class:`mvtools.io.yuv.VideoReader`);
    it returns one frame for each of ``writers`` (objects with ``write(frame)``), in
    their order, or None when there are no writers. Each frame's arrays are freed
    before the next frame is read, so memory does not grow with the number of frames.
    """
    total = len(frames)
    for done, index in enumerate(frames, start=1):
        outputs = step(index, *(reader.read(index) for reader in readers))
        if writers:
            outputs = list(outputs)
            if len(outputs) != len(writers):
                raise ValueError(f"the step gave {len(outputs)} frames for {len(writers)} writers")
            for writer, frame in zip(writers, outputs):
                writer.write(frame)
        del outputs
        if progress is not None:
            progress(done, total)
