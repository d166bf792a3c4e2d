"""Peak resident memory of estimate_disparity per method on the Middlebury 2006 Aloe pair
at full size (1282x1110) with 256 disparities, against the 2 GB bar of issue 20.

Each method runs in a fresh subprocess; its peak is the child's ``ru_maxrss`` (from
``os.wait4``, so every method is measured alone), the seconds are those of the
``estimate_disparity`` call inside the child. A child whose resident size passes
``MVTOOLS_BENCH_MEMORY_LIMIT_MB`` (default 20000) is stopped and reported as such.

Environment: MVTOOLS_BENCH_METHODS=sgm,bp (default: every method of PAIR_METHODS),
MVTOOLS_BENCH_COST=census-gradient (default ad-census), MVTOOLS_BENCH_SCALE=2 (divide the
views' size, for a quick check; default 1), MVTOOLS_BENCH_DISPARITIES=256.
"""

from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

from common import DATA, report

from mvtools.depth import PAIR_METHODS

BAR_MB = 2048.0

_CHILD = r"""
import sys, time
import numpy as np
from mvtools.datasets import middlebury_pair
from mvtools.depth import estimate_disparity

root, method, cost, scale, disparities = sys.argv[1:6]
scale, disparities = int(scale), int(disparities)
left, right = middlebury_pair(root, "aloe")
if scale > 1:
    import cv2
    size = (left.shape[1] // scale, left.shape[0] // scale)
    left, right = (cv2.resize(v, size, interpolation=cv2.INTER_AREA) for v in (left, right))
start = time.perf_counter()
result = estimate_disparity(left, right, max_disparity=disparities - 1, method=method, cost=cost)
print("seconds", time.perf_counter() - start, "finite", float(np.isfinite(result).mean()))
"""


def _resident_mb(pid: int) -> float:
    try:
        for line in Path(f"/proc/{pid}/status").read_text().splitlines():
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024
    except OSError:
        pass
    return 0.0


def measure(method: str, *, cost: str, scale: int, disparities: int, limit_mb: float):
    """(peak resident MB, seconds or None, "STOPPED" / "FAILED" / "") of one method in a
    fresh process."""
    process = subprocess.Popen(
        [
            sys.executable,
            "-c",
            _CHILD,
            str(DATA / "middlebury"),
            method,
            cost,
            str(scale),
            str(disparities),
        ],
        stdout=subprocess.PIPE,
        text=True,
    )
    stopped = False
    while True:
        # wait4 (not poll, which would reap the child) gives this child's own rusage
        pid, status, usage = os.wait4(process.pid, os.WNOHANG)
        if pid:
            break
        if not stopped and _resident_mb(process.pid) > limit_mb:
            process.kill()
            stopped = True
        time.sleep(0.2)
    output = process.stdout.read()
    process.returncode = os.waitstatus_to_exitcode(status)
    process.stdout.close()
    seconds = None
    for line in output.splitlines():
        if line.startswith("seconds"):
            seconds = float(line.split()[1])
    failed = not stopped and process.returncode != 0
    return usage.ru_maxrss / 1024, seconds, "STOPPED" if stopped else "FAILED" if failed else ""


def main() -> None:
    methods = os.environ.get("MVTOOLS_BENCH_METHODS", ",".join(PAIR_METHODS)).split(",")
    cost = os.environ.get("MVTOOLS_BENCH_COST", "ad-census")
    scale = int(os.environ.get("MVTOOLS_BENCH_SCALE", "1"))
    disparities = int(os.environ.get("MVTOOLS_BENCH_DISPARITIES", "256"))
    limit_mb = float(os.environ.get("MVTOOLS_BENCH_MEMORY_LIMIT_MB", "20000"))
    # one float32 volume of the pair, for scale
    volume_mb = (1110 // scale) * (1282 // scale) * disparities * 4 / 2**20
    rows = [(f"one float32 volume (MB), {disparities} disparities", volume_mb, "", None)]
    for method in methods:
        peak, seconds, stopped = measure(
            method, cost=cost, scale=scale, disparities=disparities, limit_mb=limit_mb
        )
        label = f"aloe/{scale} {method} {cost}" if scale > 1 else f"aloe {method} {cost}"
        rows.append(
            (
                f"{label} peak MB" + (f" ({stopped})" if stopped else ""),
                peak,
                "issue 20 bar",
                BAR_MB,
            )
        )
        if seconds is not None:
            rows.append((f"{label} seconds", seconds, "", None))
        print(method, peak, seconds, stopped, flush=True)
    report(rows)


if __name__ == "__main__":
    main()
