"""Peak resident memory of estimate_disparity per method on the Middlebury 2006 Aloe pair
at full size (1282x1110) with 256 disparities, against the 2 GB bar of issue 20.

Each method runs in a fresh subprocess; its peak is the child's own
(``common.run_measured``: every method measured alone, whatever the benchmark runner
holds), the seconds are those of the ``estimate_disparity`` call inside the child. A
child whose resident size passes ``MVTOOLS_BENCH_MEMORY_LIMIT_MB`` (default 20000) is
stopped and reported as such.

Environment: MVTOOLS_BENCH_METHODS=sgm,bp (default: every method of PAIR_METHODS),
MVTOOLS_BENCH_COST=census-gradient (default ad-census), MVTOOLS_BENCH_SCALE=2 (divide the
views' size, for a quick check; default 1), MVTOOLS_BENCH_DISPARITIES=256.
"""

from __future__ import annotations

import os
import subprocess
import sys

from common import DATA, report, run_measured

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


def measure(method: str, *, cost: str, scale: int, disparities: int, limit_mb: float):
    """(peak resident MB, seconds or None, "STOPPED" / "FAILED" / "") of one method in a
    fresh process."""
    completed, usage = run_measured(
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
        limit_mib=limit_mb,
        stdout=subprocess.PIPE,
        text=True,
    )
    seconds = None
    for line in completed.stdout.splitlines():
        if line.startswith("seconds"):
            seconds = float(line.split()[1])
    failed = not usage.stopped and usage.exit_code != 0
    return usage.peak_mib, seconds, "STOPPED" if usage.stopped else "FAILED" if failed else ""


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
