"""The shared frame loop and the progress line, against hand-worked runs."""

from __future__ import annotations

import logging

import pytest

from mvtools.cli import progress as progress_module
from mvtools.cli.progress import Progress
from mvtools.run import stream_frames


class _Reader:
    def __init__(self, offset):
        self.offset = offset
        self.asked = []

    def read(self, index):
        self.asked.append(index)
        return index + self.offset


class _Writer:
    def __init__(self):
        self.frames = []

    def write(self, frame):
        self.frames.append(frame)


def test_each_frame_is_read_stepped_and_written_in_order():
    readers = [_Reader(100), _Reader(200)]
    writers = [_Writer(), _Writer()]
    reports = []
    stream_frames(
        range(3, 6),
        lambda index, a, b: (a + b, index),
        readers=readers,
        writers=writers,
        progress=lambda done, total: reports.append((done, total)),
    )
    assert readers[0].asked == readers[1].asked == [3, 4, 5]
    assert writers[0].frames == [306, 308, 310]
    assert writers[1].frames == [3, 4, 5]
    assert reports == [(1, 3), (2, 3), (3, 3)]


def test_a_step_giving_too_few_frames_is_refused():
    with pytest.raises(ValueError, match="1 frames for 2 writers"):
        stream_frames(range(1), lambda index: (index,), writers=[_Writer(), _Writer()])


def test_the_progress_line_gives_rate_and_time_left(monkeypatch, caplog):
    clock = iter([0.0, 10.0, 20.0, 200.0])
    monkeypatch.setattr(progress_module.time, "perf_counter", lambda: next(clock))
    reporter = Progress(None, "frames synthesized")
    with caplog.at_level(logging.INFO, logger="mvtools"):
        reporter(5, 100)  # 5 frames in 10 s: 0.5/s, 95 left: 190 s
        reporter(10, 100)  # 10 in 20 s: 0.5/s, 90 left: 180 s
        reporter(100, 100)
    assert caplog.messages == [
        "frames synthesized: 5/100 done, 0.50/s, 3 min 10 s left",
        "frames synthesized: 10/100 done, 0.50/s, 3 min 00 s left",
        "frames synthesized: 100/100 done, 0.50/s",
    ]
