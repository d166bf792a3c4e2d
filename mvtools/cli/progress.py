"""Progress of long work on stderr: frames done, rate and time left."""

from __future__ import annotations

import logging
import time

LOG = logging.getLogger("mvtools")


class Progress:
    """Report ``label: done/total done, rate, time left`` at most every ``interval``
    seconds (and when the last frame is done).

    Messages go through the ``mvtools`` logger at INFO level, so ``-q`` silences them.
    An instance is also a :data:`mvtools.run.stream.ProgressCallback`: calling it with
    (done, total) sets both and reports.
    """

    def __init__(self, total: int | None, label: str = "frames", *, interval: float = 1.0):
        self.total = total
        self.label = label
        self.interval = interval
        self.done = 0
        self._start = time.perf_counter()
        self._last = self._start

    def advance(self, count: int = 1) -> None:
        self.done += count
        now = time.perf_counter()
        if now - self._last >= self.interval or self.done == self.total:
            self._last = now
            LOG.info("%s", self._line(now))

    def __call__(self, done: int, total: int) -> None:
        self.total = total
        self.advance(done - self.done)

    def _line(self, now: float) -> str:
        elapsed = max(now - self._start, 1e-9)
        rate = self.done / elapsed
        line = f"{self.label}: {self.done}"
        if self.total is not None:
            line += f"/{self.total}"
        line += f" done, {rate:.2f}/s"
        if self.total is not None and self.done < self.total and rate > 0:
            line += f", {_duration((self.total - self.done) / rate)} left"
        return line


def _duration(seconds: float) -> str:
    """``42 s``, ``3 min 20 s``, ``2 h 05 min``."""
    seconds = round(seconds)
    if seconds < 60:
        return f"{seconds} s"
    if seconds < 3600:
        return f"{seconds // 60} min {seconds % 60:02d} s"
    return f"{seconds // 3600} h {seconds % 3600 // 60:02d} min"
