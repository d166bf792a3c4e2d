"""Timing, memory and reporting shared by the benchmarks: figures side by side with a
baseline."""

from __future__ import annotations

import os
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

DATA = Path(os.environ.get("MVTOOLS_DATA", Path(__file__).resolve().parents[2] / "shared" / "data"))

# the tests' helpers, which some benchmarks share
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from process_peak import Usage, measured, read_usage


def run_measured(
    command: list[str], *, limit_mib: float | None = None, **options
) -> tuple[subprocess.CompletedProcess, Usage]:
    """``subprocess.run(command, **options)`` and the command's own peak resident memory
    and CPU time (``tests/process_peak.py``): a child started straight from the benchmark
    runner, grown to gigabytes by earlier benchmarks, would report the runner's peak.
    ``limit_mib`` stops the command past that resident size (``Usage.stopped``)."""
    with tempfile.TemporaryDirectory() as folder:
        usage = Path(folder) / "usage.json"
        completed = subprocess.run(measured(command, usage, limit_mib=limit_mib), **options)
        return completed, read_usage(usage)


def median_seconds(function: Callable[[], object], *, repeats: int = 10) -> float:
    """Median wall time of ``repeats`` calls, after one warm-up call."""
    return interleaved_median_seconds([function], repeats=repeats)[0]


def interleaved_median_seconds(
    functions: list[Callable[[], object]], *, repeats: int = 10
) -> list[float]:
    """Median wall time of each function over ``repeats`` rounds that call them all in
    turn, after a warm-up call of each: the load of a shared machine, which changes from
    second to second, weighs on a figure and on its baseline alike."""
    for function in functions:
        function()
    times = [[] for _ in functions]
    for _ in range(repeats):
        for function, taken in zip(functions, times):
            start = time.perf_counter()
            function()
            taken.append(time.perf_counter() - start)
    return [statistics.median(taken) for taken in times]


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
