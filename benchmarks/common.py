"""Timing and reporting shared by the benchmarks: figures side by side with a baseline."""

from __future__ import annotations

import os
import statistics
import time
from collections.abc import Callable
from pathlib import Path

DATA = Path(os.environ.get("MVTOOLS_DATA", Path(__file__).resolve().parents[2] / "shared" / "data"))


def median_seconds(function: Callable[[], object], *, repeats: int = 10) -> float:
    """Median wall time of ``repeats`` calls, after one warm-up call."""
    function()
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def report(rows: list[tuple[str, float, str, float | None]]) -> None:
    """Print ``what, ours, baseline name, baseline`` rows with the ratio ours/baseline
    (a row without a baseline figure prints the figure alone)."""
    print(f"{'measure':<46}{'mvtools':>11}{'baseline':>11}{'ratio':>8}  baseline")
    for what, ours, baseline_name, baseline in rows:
        if baseline is None:
            print(f"{what:<46}{ours:>11.4g}{'':>11}{'':>8}  {baseline_name}")
        else:
            print(
                f"{what:<46}{ours:>11.4g}{baseline:>11.4g}{ours / baseline:>8.2f}  {baseline_name}"
            )
