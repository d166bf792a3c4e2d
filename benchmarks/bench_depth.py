"""estimate-depth against OpenCV StereoSGBM on the published Middlebury pairs: bad 1.0
over each set's scored region and seconds per pair, side by side.

Environment: MVTOOLS_BENCH_METHODS=sgm,graphcut (default: every method),
MVTOOLS_BENCH_SETS=tsukuba,cones (default: the seven 2001/2003/2005 sets).
"""

from __future__ import annotations

import os
import time

from common import DATA, report

from mvtools.datasets import (load_middlebury_ground_truth, middlebury_pair,
                              opencv_sgbm_reference, score_middlebury)
from mvtools.depth import METHODS, estimate_disparity
from mvtools.io.middlebury import MIDDLEBURY_SETS

SETS = ("tsukuba", "venus", "teddy", "cones", "Art", "Dolls", "Moebius")


def _timed(function):
    start = time.perf_counter()
    result = function()
    return result, time.perf_counter() - start


def main() -> None:
    methods = os.environ.get("MVTOOLS_BENCH_METHODS", ",".join(METHODS)).split(",")
    names = os.environ.get("MVTOOLS_BENCH_SETS", ",".join(SETS)).split(",")
    root = DATA / "middlebury"
    # compile every kernel once so that no timing includes numba's compilation
    left, right = middlebury_pair(root, "tsukuba")
    for method in methods:
        estimate_disparity(left[:64, :96], right[:64, :96], max_disparity=15, method=method)
    rows = []
    for name in names:
        entry = MIDDLEBURY_SETS[name]
        left, right = middlebury_pair(root, name)
        truth = load_middlebury_ground_truth(root, name)
        sgbm, sgbm_seconds = _timed(lambda: opencv_sgbm_reference(
            left, right, disparities=entry.disparities))
        sgbm_bad = score_middlebury(sgbm, truth, name)
        for method in methods:
            ours, seconds = _timed(lambda: estimate_disparity(
                left, right, max_disparity=entry.disparities - 1, method=method))
            rows.append((f"{name} {method} bad 1.0 %", score_middlebury(ours, truth, name),
                         "OpenCV StereoSGBM", sgbm_bad))
            rows.append((f"{name} {method} seconds", seconds, "OpenCV StereoSGBM",
                         sgbm_seconds))
    report(rows)


if __name__ == "__main__":
    main()
