"""Disparity of a linear array from all its views against one pair (issue 22).

Tsukuba's view 3 (384x288, 16 disparities) from views 2 to 4 and from all five
(``estimate_array_disparity``) beside the stereo-pair chain on views 3 and 4
(``estimate_disparity``, ``bp``): bad 1.0 % over all known pixels and the median time of
seven runs, the three run in turn, and the whole ``mvtools estimate-depth`` runs of both
(start-up, reading and writing included: how a Makefile calls them), three each. Cones'
view 2 from its views 2, 4 and 6 (the reference at the end of the line) beside the pair
2-6. Then the synthetic scene rendered as a line of 17 cameras 5 cm apart: bad 1.0 % of
the middle view against its exact disparity with its middle 5, 9 and 17 views, beside the
pair, and with ``subpixel`` its mean error in pixels beside the whole pixels'. Last,
Tsukuba as a DERS case (``write_middlebury_ders_case``): ``mvtools estimate-depth`` with
ViewCombination vote from all five views beside DERS's least-cost sweep from views 2 to
4, bad 1.0 % and the median time of three whole runs.
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
from common import interleaved_median_seconds, median_seconds, report

from mvtools.datasets import (
    load_middlebury_ground_truth,
    score_ders_case,
    score_middlebury,
    write_middlebury_ders_case,
)
from mvtools.depth import estimate_array_disparity, estimate_disparity
from mvtools.io.images import read_image
from mvtools.scene import default_scene, linear_rig, quantize, render, sample_intrinsics

ROOT = Path(__file__).resolve().parent.parent
DATA = Path(os.environ.get("MVTOOLS_DATA", ROOT.parent / "shared" / "data"))


def tsukuba(rows: list) -> None:
    folder = DATA / "middlebury" / "2001" / "tsukuba"
    if not folder.exists():
        print(f"skipped Tsukuba: {folder} not found (set MVTOOLS_DATA)", file=sys.stderr)
        return
    views = [read_image(folder / f"tsukuba{index}.png") for index in range(1, 6)]
    truth = load_middlebury_ground_truth(DATA / "middlebury", "tsukuba")

    def pair():
        return estimate_disparity(views[2], views[3], max_disparity=15)

    def three():
        return estimate_array_disparity(views[1:4], reference=1, max_disparity=15)

    def five():
        return estimate_array_disparity(views, reference=2, max_disparity=15)

    pair_seconds, *seconds = interleaved_median_seconds([pair, three, five], repeats=7)
    pair_bad = score_middlebury(pair(), truth, "tsukuba")
    for label, run, run_seconds in (("3 views", three, seconds[0]), ("5 views", five, seconds[1])):
        rows.append(
            (f"Tsukuba {label}, bad 1.0 %", score_middlebury(run(), truth, "tsukuba"),
             "pair 3-4 bp", pair_bad)
        )  # fmt: skip
        rows.append(
            (f"Tsukuba {label}, s (bar 2x for 5)", run_seconds, "pair 3-4 bp", pair_seconds)
        )  # fmt: skip
    # the programs as a Makefile runs them: start-up, reading and writing included
    with tempfile.TemporaryDirectory() as temporary:
        program = [sys.executable, "-m", "mvtools", "estimate-depth", "-q", "--disparities", "15"]
        output = ["-o", str(Path(temporary) / "disparity.pfm")]
        pictures = [str(folder / f"tsukuba{index}.png") for index in range(1, 6)]
        pair_command = program + ["--left", pictures[2], "--right", pictures[3]] + output
        five_command = program + ["--views", ",".join(pictures), "--reference", "3"] + output
        rows.append(
            ("Tsukuba 5 views, whole program, s", _program_seconds(five_command),
             "pair 3-4 bp, whole program", _program_seconds(pair_command))
        )  # fmt: skip


def _program_seconds(command: list[str]) -> float:
    return median_seconds(lambda: subprocess.run(command, check=True), repeats=3)


def cones(rows: list) -> None:
    folder = DATA / "middlebury" / "2003" / "cones"
    if not folder.exists():
        print(f"skipped Cones: {folder} not found (set MVTOOLS_DATA)", file=sys.stderr)
        return
    views = [read_image(folder / f"im{index}.png") for index in (2, 4, 6)]
    truth = load_middlebury_ground_truth(DATA / "middlebury", "cones")
    pair = estimate_disparity(views[0], views[2], max_disparity=59)
    three = estimate_array_disparity(views, reference=0, positions=[0, 0.5, 1], max_disparity=59)
    rows.append(
        ("Cones views 2, 4, 6 for view 2, bad 1.0 %", score_middlebury(three, truth, "cones"),
         "pair 2-6 bp", score_middlebury(pair, truth, "cones"))
    )  # fmt: skip


def dense_line(rows: list) -> None:
    count, baseline, size = 17, 0.05, (256, 192)
    K = sample_intrinsics(*size)
    renderings = [
        render(default_scene(), camera)
        for camera in linear_rig(count, baseline=baseline, K=K, size=size)
    ]
    views = [quantize(rendering.color) for rendering in renderings]
    truth = K[0, 0] * baseline / renderings[count // 2].depth

    def bad(disparity):
        return 100.0 * float(np.mean(np.abs(disparity - truth) > 1.0))

    def mean_error(disparity):
        return float(np.mean(np.abs(disparity - truth)))

    middle = count // 2
    pair = bad(estimate_disparity(views[middle], views[middle + 1], max_disparity=6))
    for used in (5, 9, 17):
        chosen = views[middle - used // 2 : middle + used // 2 + 1]
        disparity = estimate_array_disparity(chosen, reference=used // 2, max_disparity=6)
        rows.append((f"synthetic line, {used} views, bad 1.0 %", bad(disparity), "pair", pair))
        finer = estimate_array_disparity(
            chosen, reference=used // 2, max_disparity=6, subpixel=True
        )
        rows.append(
            (f"synthetic line, {used} views, --subpixel mean px", mean_error(finer),
             "whole pixels", mean_error(disparity))
        )  # fmt: skip


def ders_case(rows: list) -> None:
    root = DATA / "middlebury"
    if not root.exists():
        print(f"skipped the DERS case: {root} not found (set MVTOOLS_DATA)", file=sys.stderr)
        return
    further = [("2001/tsukuba/tsukuba1.png", -2), ("2001/tsukuba/tsukuba5.png", 2)]
    results = {}
    with tempfile.TemporaryDirectory() as temporary:
        for combination, views in (("least-cost", 3), ("vote", 5)):
            folder = Path(temporary) / combination
            folder.mkdir()
            used = further if views == 5 else []
            config = write_middlebury_ders_case(
                root,
                "tsukuba",
                folder,
                left_view="2001/tsukuba/tsukuba2.png",
                further_views=used,
                view_combination=combination,
            )
            output = folder / "depth_384x288_gray16le.yuv"
            command = [sys.executable, "-m", "mvtools", "estimate-depth", str(config), "-q"]
            command += ["-o", str(output)]
            for picture, _ in used:
                stem = Path(picture).stem
                command += ["--view", stem, str(folder / f"{stem}_384x288_yuv420p.yuv")]

            def estimate(command=command):
                subprocess.run(command, check=True)

            seconds = median_seconds(estimate, repeats=3)
            results[combination] = (score_ders_case(output, root, "tsukuba"), seconds)
    (vote_bad, vote_seconds), (sweep_bad, sweep_seconds) = results["vote"], results["least-cost"]
    baseline = "DERS case, least-cost, views 2-4"
    rows.append(("DERS case, vote from 5 views, bad 1.0 %", vote_bad, baseline, sweep_bad))
    rows.append(("DERS case, vote from 5 views, s", vote_seconds, baseline, sweep_seconds))


def main() -> None:
    rows: list = []
    tsukuba(rows)
    cones(rows)
    dense_line(rows)
    ders_case(rows)
    report(rows)


if __name__ == "__main__":
    main()
