"""estimate-depth through DERS configurations (issue 20): the Middlebury pairs written as
DERS cases (:func:`mvtools.datasets.write_middlebury_ders_case`: center = left picture,
parallel cameras, the set's disparity range as the search range at the finest SearchLevel
within DERS's 256 labels), bad 1.0 over each set's scored region beside OpenCV StereoSGBM
on the same pair and the issue's bar; Tsukuba also with views 2 and 4 as the left and
right neighbours of view 3.

Environment: MVTOOLS_BENCH_METHODS=sgm,bp (default: the DERS default alone),
MVTOOLS_BENCH_SETS=tsukuba,cones (default: all).
"""

from __future__ import annotations

import os
import re
import tempfile
import time
from pathlib import Path

from common import DATA, report

from mvtools.datasets import (
    ders_case_disparity,
    load_middlebury_ground_truth,
    middlebury_pair,
    opencv_sgbm_reference,
    score_middlebury,
    write_middlebury_ders_case,
)
from mvtools.io.middlebury import MIDDLEBURY_SETS
from mvtools.run.depth import estimate_depth_config

ROOT = DATA / "middlebury"
#: case -> (set, left neighbour's picture or None)
CASES = {
    "tsukuba": ("tsukuba", None),
    "tsukuba 2-3-4": ("tsukuba", "2001/tsukuba/tsukuba2.png"),
    "venus": ("venus", None),
    "teddy": ("teddy", None),
    "cones": ("cones", None),
    "Art": ("Art", None),
    "Dolls": ("Dolls", None),
    "Moebius": ("Moebius", None),
}
#: bad 1.0 bars of issue 20 (None: half of StereoSGBM's)
BARS = {"tsukuba": 2.0, "tsukuba 2-3-4": 1.8, "venus": 1.0, "teddy": 6.0, "cones": 3.0}


def ders_bad(case: str, method: str | None) -> tuple[float, float]:
    name, left_view = CASES[case]
    with tempfile.TemporaryDirectory() as folder:
        settings = {} if method is None else {"method": method}
        config = write_middlebury_ders_case(ROOT, name, folder, left_view=left_view, **settings)
        output = re.search(r"FileOutputDepthMapImage\s+(\S+)", config.read_text()).group(1)
        start = time.perf_counter()
        written = estimate_depth_config(config, data_dirs=[folder], output=Path(folder) / output)
        seconds = time.perf_counter() - start
        disparity = ders_case_disparity(written["depth"])
    return score_middlebury(disparity, load_middlebury_ground_truth(ROOT, name), name), seconds


def main() -> None:
    methods = os.environ.get("MVTOOLS_BENCH_METHODS")
    methods = methods.split(",") if methods else [None]
    cases = os.environ.get("MVTOOLS_BENCH_SETS", ",".join(CASES)).split(",")
    rows = []
    for case in cases:
        name = CASES[case][0]
        left, right = middlebury_pair(ROOT, name)
        truth = load_middlebury_ground_truth(ROOT, name)
        sgbm = opencv_sgbm_reference(left, right, disparities=MIDDLEBURY_SETS[name].disparities)
        sgbm_bad = score_middlebury(sgbm, truth, name)
        bar = BARS.get(case, sgbm_bad / 2)
        for method in methods:
            label = f"{case} DERS {method or 'default'}"
            bad, seconds = ders_bad(case, method)
            rows.append((f"{label} bad 1.0 %", bad, "OpenCV StereoSGBM", sgbm_bad))
            rows.append((f"{label} bad 1.0 %", bad, "bar", bar))
            rows.append((f"{label} seconds", seconds, "", None))
    report(rows)


if __name__ == "__main__":
    main()
