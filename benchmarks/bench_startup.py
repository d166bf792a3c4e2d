"""Whole-process start-up and short runs, as a Makefile calling a program hundreds of
times sees them (issue 18): CPU seconds (user + system, the interpreter's start
included), median of 5, beside the bars and VSRS 4.2's figures for the same runs on this
machine class (``reference_outputs/README.md``: one Kendo frame 1.06 s in general mode
Precision 4 and 0.34 s in 1D mode Precision 2; each further frame 1.11 s and 0.31 s).
"""

from __future__ import annotations

import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

from common import DATA, report

KENDO = DATA / "mpeg" / "kendo"
KENDO_CONFIG = KENDO / "config" / "VSRS" / "vsrs_kendo_ori.cfg"
KENDO_FILES = ("kendo_ori_I_1.yuv", "kendo_ori_I_3.yuv", "kendo_ori_D_1.yuv", "kendo_ori_D_3.yuv")
REPEATS = 5

#: mode, Precision, SynthesisMode, VSRS's first-frame and further-frame CPU seconds, and
#: the bars: one frame at most (s), ten frames at least this many times faster than VSRS
KENDO_RUNS = (("1d", 2, 1, 0.34, 0.31, 0.8, 2.5), ("general", 4, 0, 1.06, 1.11, 1.2, 6.0))


def cpu_seconds(command: list[str], cwd: Path | None = None) -> float:
    """Median CPU seconds (user + system) of ``REPEATS`` whole-process runs of ``command``."""
    times = []
    for _ in range(REPEATS):
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        subprocess.run(command, cwd=cwd, check=True, stdout=subprocess.DEVNULL)
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        times.append(after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime)
    return statistics.median(times)


def mvtools(*arguments: str) -> list[str]:
    return [sys.executable, "-m", "mvtools", *arguments]


def startup_rows() -> list:
    rows = []
    for arguments in (("--version",), ("synthesize", "--help"), ("estimate-depth", "--help")):
        rows.append(
            (f"mvtools {' '.join(arguments)} (CPU s)", cpu_seconds(mvtools(*arguments)), "bar", 0.3)
        )
    return rows


def kendo_rows(folder: Path) -> list:
    """One and ten Kendo frames (the one published frame, repeated), whole process."""
    for name in KENDO_FILES:
        (folder / name).write_bytes((KENDO / name).read_bytes() * 10)
    shutil.copy(KENDO / "config" / "VSRS" / "cam_param_kendo.cfg", folder)
    rows = []
    for mode, precision, synthesis_mode, vsrs_first, vsrs_next, bar, speed_up in KENDO_RUNS:
        for frames in (1, 10):
            command = mvtools(
                "synthesize",
                str(KENDO_CONFIG),
                "-q",
                "--data-dir",
                str(folder),
                f"SynthesisMode={synthesis_mode}",
                f"Precision={precision}",
                f"TotalNumberOfFrames={frames}",
                "-o",
                "out_1024x768_yuv420p.yuv",
            )
            ours = cpu_seconds(command, folder)
            vsrs = vsrs_first + (frames - 1) * vsrs_next
            what = f"Kendo {mode} P{precision}, {frames} frame{'s' * (frames > 1)} (CPU s)"
            rows.append((what, ours, "VSRS 4.2 (README)", vsrs))
            limit = bar if frames == 1 else vsrs / speed_up
            rows.append(("  bar", ours, f"at most {limit:.2f} s", limit))
    return rows


def main() -> None:
    rows = startup_rows()
    if KENDO_CONFIG.exists():
        with tempfile.TemporaryDirectory() as folder:
            rows += kendo_rows(Path(folder))
    else:
        print(f"Kendo not found under {DATA}: its rows are skipped")
    report(rows)


if __name__ == "__main__":
    main()
