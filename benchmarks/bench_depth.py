"""estimate-depth against OpenCV StereoSGBM on the published Middlebury pairs: bad 1.0
over each set's scored region and seconds per pair, side by side; then end to end:
Cones im4 synthesized (mvtools synthesize, 448x368, general and 1D mode, Precision 2)
from the depth of im2 and im6 estimated from that pair, Y-PSNR against the real im4.

Every method runs on the default AD-census cost; the methods of COST_METHODS run on the
census-gradient cost too, labelled "method+census-gradient".

Environment: MVTOOLS_BENCH_METHODS=sgm,graphcut (default: every method),
MVTOOLS_BENCH_SETS=tsukuba,cones (default: the seven 2001/2003/2005 sets).
"""

from __future__ import annotations

import os
import tempfile
import time
from pathlib import Path

from common import DATA, report
from synthesize_runner import run_synthesize

from mvtools.datasets import (
    cones_multiview,
    estimate_cones_disparities,
    load_middlebury_ground_truth,
    middlebury_pair,
    opencv_sgbm_reference,
    score_middlebury,
    write_cones_case,
)
from mvtools.depth import COSTS, PAIR_METHODS, estimate_disparity
from mvtools.io.middlebury import MIDDLEBURY_SETS
from mvtools.io.yuv import YuvFormat, read_frame
from mvtools.metrics import psnr

SETS = ("tsukuba", "venus", "teddy", "cones", "Art", "Dolls", "Moebius")

#: methods also measured with the census-gradient cost
COST_METHODS = ("bp", "graphcut")


def _configurations(methods: list[str]) -> list[tuple[str, str, str]]:
    """(label, method, cost) of every measured combination."""
    return [(method, method, "ad-census") for method in methods] + [
        (f"{method}+{cost}", method, cost)
        for cost in COSTS
        if cost != "ad-census"
        for method in COST_METHODS
        if method in methods
    ]


def _timed(function):
    start = time.perf_counter()
    result = function()
    return result, time.perf_counter() - start


def main() -> None:
    methods = os.environ.get("MVTOOLS_BENCH_METHODS", ",".join(PAIR_METHODS)).split(",")
    names = os.environ.get("MVTOOLS_BENCH_SETS", ",".join(SETS)).split(",")
    root = DATA / "middlebury"
    # compile every kernel once so that no timing includes numba's compilation
    left, right = middlebury_pair(root, "tsukuba")
    for _, method, cost in _configurations(methods):
        estimate_disparity(
            left[:64, :96], right[:64, :96], max_disparity=15, method=method, cost=cost
        )
    rows = []
    for name in names:
        entry = MIDDLEBURY_SETS[name]
        left, right = middlebury_pair(root, name)
        truth = load_middlebury_ground_truth(root, name)
        sgbm, sgbm_seconds = _timed(
            lambda: opencv_sgbm_reference(left, right, disparities=entry.disparities)
        )
        sgbm_bad = score_middlebury(sgbm, truth, name)
        for label, method, cost in _configurations(methods):
            ours, seconds = _timed(
                lambda: estimate_disparity(
                    left, right, max_disparity=entry.disparities - 1, method=method, cost=cost
                )
            )
            rows.append(
                (
                    f"{name} {label} bad 1.0 %",
                    score_middlebury(ours, truth, name),
                    "OpenCV StereoSGBM",
                    sgbm_bad,
                )
            )
            rows.append((f"{name} {label} seconds", seconds, "OpenCV StereoSGBM", sgbm_seconds))
    end_to_end(methods, rows)
    report(rows)


def cones_im4_psnr(disparities: dict, mode: int) -> float:
    """Y-PSNR of Cones im4 synthesized with mvtools from im2 and im6 with the given
    disparities (:func:`mvtools.datasets.cones_multiview`)."""
    case = cones_multiview(DATA / "middlebury", disparities=disparities)
    with tempfile.TemporaryDirectory() as folder:
        config = write_cones_case(case, folder, synthesis_mode=mode)
        code, _, err = run_synthesize(config, cwd=Path(folder))
        if code:
            raise RuntimeError(err)
        width, height = case.size
        result = read_frame(
            Path(folder) / f"synthesized_im4_{width}x{height}_yuv420p.yuv", YuvFormat(width, height)
        )[0]
    return psnr(case.yuv["im4"][0], result, max_value=255)


def end_to_end(methods: list[str], rows: list) -> None:
    root = DATA / "middlebury"
    baseline = estimate_cones_disparities(
        root, lambda left, right, count: opencv_sgbm_reference(left, right, disparities=count)
    )
    for configuration, method, cost in _configurations(methods):
        ours = estimate_cones_disparities(
            root,
            lambda left, right, count: estimate_disparity(
                left, right, max_disparity=count - 1, method=method, cost=cost
            ),
        )
        for mode, label in ((0, "general"), (1, "1D")):
            rows.append(
                (
                    f"Cones im4, {configuration} depth, {label} (dB; bar 30.5)",
                    cones_im4_psnr(ours, mode),
                    "SGBM depth, same synthesis",
                    cones_im4_psnr(baseline, mode),
                )
            )


if __name__ == "__main__":
    main()
