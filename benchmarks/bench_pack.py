"""pack and encode on the synthetic scene rendered with 8 frames: 5 views (and, for the
MPEG evaluation, the depth maps of cameras 1 and 3) coded at QPs 22, 27, 32, 37 with x265
(preset medium), simulcast against a packed grid and against an atlas; bitrates and
qualities of packing side by side with simulcast, the Bjontegaard deltas, camera 2
synthesized from the decoded views and depths, and the wall time of each run (the issue's
bar: under 5 minutes)."""

from __future__ import annotations

import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from common import report

QPS = (22, 27, 32, 37)


def _mvtools(*args) -> float:
    start = time.perf_counter()
    subprocess.run(
        [sys.executable, "-m", "mvtools", *map(str, args), "-q"],
        check=True,
        stdout=subprocess.DEVNULL,
    )
    return time.perf_counter() - start


def main() -> None:
    with tempfile.TemporaryDirectory() as folder:
        folder = Path(folder)
        render = _mvtools("scene", folder / "scene", "--frames", 8, "--samples", 2, "--captures", 1)
        line = folder / "scene" / "line"
        views = [
            arg
            for index in range(5)
            for arg in ("--view", f"cam{index}", line / f"v{index}_texture_256x192_yuv420p.yuv")
        ]
        depths = [
            arg
            for index in (1, 3)
            for arg in ("--depth", f"cam{index}", line / f"v{index}_depth_256x192_yuv420p.yuv")
        ]
        qps = [arg for qp in QPS for arg in ("--qp", qp)]
        grid_seconds = _mvtools("encode", *views, *qps, "-o", folder / "grid")
        atlas_seconds = _mvtools(
            "encode",
            *views,
            *depths,
            *qps,
            "--synthesize",
            line / "synthesize_cam2.cfg",
            "-o",
            folder / "atlas",
        )
        rows = [("render 8 frames of the scene, s", render, "", None)]
        for label, name, seconds in (
            ("grid", "grid", grid_seconds),
            ("atlas", "atlas", atlas_seconds),
        ):
            result = json.loads((folder / name / "report.json").read_text())
            rows.append((f"{label}: s for the whole RD run (bar 300)", seconds, "", None))
            for simulcast, packed in zip(result["modes"]["simulcast"], result["modes"]["packed"]):
                qp = packed["qp"]
                rows.append(
                    (
                        f"{label} QP {qp}: kbit/s, packed",
                        packed["kbps"],
                        "simulcast",
                        simulcast["kbps"],
                    )
                )
                rows.append(
                    (
                        f"{label} QP {qp}: texture YUV-PSNR dB, packed",
                        packed["mean_texture_yuv_psnr"],
                        "simulcast",
                        simulcast["mean_texture_yuv_psnr"],
                    )
                )
                if "synthesis" in packed:
                    rows.append(
                        (
                            f"{label} QP {qp}: cam2 synthesized IV-PSNR dB, packed",
                            packed["synthesis"]["iv_psnr"],
                            "simulcast",
                            simulcast["synthesis"]["iv_psnr"],
                        )
                    )
            for method, deltas in result["bjontegaard"].items():
                rows.append(
                    (
                        f"{label}: BD-rate % of packing ({method})",
                        deltas["bd_rate_percent"],
                        "",
                        None,
                    )
                )
                rows.append(
                    (f"{label}: BD-PSNR dB of packing ({method})", deltas["bd_psnr_db"], "", None)
                )
    report(rows)


if __name__ == "__main__":
    main()
