"""Progress of long work on stderr: frames done and rate."""

from __future__ import annotations

import logging
import time

LOG = logging.getLogger("mvtools")


class Progress:
    """Report ``label: done/total frames, rate`` at most every ``interval`` seconds.

    Messages go through the ``mvtools`` logger at INFO level, so ``-q`` silences them.
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

    def _line(self, now: float) -> str:
        elapsed = max(now - self._start, 1e-9)
        of_total = f"/{self.total}" if self.total is not None else ""
        return f"{self.label}: {self.done}{of_total} done, {self.done / elapsed:.2f}/s"
