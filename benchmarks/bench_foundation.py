"""Foundation: YUV streaming, metrics and the geometric warp, against plain baselines.

- Reading frames: mvtools' memory-mapped reader against numpy.fromfile of each frame.
- Memory: resident size growth while streaming 300 1080p frames (must stay flat).
- PSNR against OpenCV's cv2.PSNR; IV-PSNR per 1080p frame (time alone).
- Forward warp of one Kendo view (1024x768) against VSRS 4.2's 2.5 s for a whole general-mode frame.
"""

from __future__ import annotations

import resource
import tempfile
from pathlib import Path

import cv2
import numpy as np
from common import DATA, median_seconds, report

from mvtools.geometry.depth import depth_to_z
from mvtools.geometry.warp import forward_warp
from mvtools.io.cameras import read_cameras
from mvtools.io.yuv import YuvFormat, open_video, open_writer, read_frame
from mvtools.metrics import iv_psnr, psnr


def _rss_mb() -> float:
    with open("/proc/self/statm") as handle:
        return int(handle.read().split()[1]) * resource.getpagesize() / 2**20


def main() -> None:
    rows = []
    fmt = YuvFormat(1920, 1080)
    rng = np.random.default_rng(0)
    frame = tuple(rng.integers(0, 256, size=shape, dtype=np.uint8) for shape in fmt.plane_shapes)
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "big_1920x1080_yuv420p.yuv"
        with open_writer(path, fmt) as writer:
            for _ in range(300):
                writer.write(frame)
        with open_video(path) as video:

            def ours():
                return sum(int(planes[0].sum()) for planes in video.frames(0, 60))

            before = _rss_mb()
            for planes in video:
                planes[0].sum()
            growth = _rss_mb() - before

            def baseline():
                with open(path, "rb") as handle:
                    return sum(
                        int(
                            np.fromfile(handle, np.uint8, fmt.frame_bytes)[
                                : fmt.width * fmt.height
                            ].sum()
                        )
                        for _ in range(60)
                    )

            rows.append(
                (
                    "read 60 1080p frames (s)",
                    median_seconds(ours, repeats=5),
                    "numpy.fromfile",
                    median_seconds(baseline, repeats=5),
                )
            )
        print(
            f"resident memory growth while streaming 300 1080p frames: {growth:.1f} MB "
            f"(the file is {300 * fmt.frame_bytes / 2**20:.0f} MB)"
        )

    noisy = np.clip(frame[0].astype(np.int16) + rng.integers(-3, 4, frame[0].shape), 0, 255).astype(
        np.uint8
    )
    rows.append(
        (
            "PSNR of a 1080p luma plane (s)",
            median_seconds(lambda: psnr(frame[0], noisy, max_value=255)),
            "cv2.PSNR",
            median_seconds(lambda: cv2.PSNR(frame[0], noisy)),
        )
    )
    test_frame = (noisy, frame[1], frame[2])
    rows.append(
        (
            "IV-PSNR of a 1080p 4:2:0 frame (s)",
            median_seconds(lambda: iv_psnr(frame, test_frame, bits=8), repeats=3),
            "no baseline at hand (reference IVPSNR not installed)",
            None,
        )
    )

    kendo = DATA / "mpeg" / "kendo"
    if kendo.exists():
        cameras = read_cameras(kendo / "config" / "VSRS" / "cam_param_kendo.cfg")
        texture = read_frame(kendo / "kendo_ori_I_1.yuv", YuvFormat(1024, 768))[0]
        depth = read_frame(kendo / "kendo_ori_D_1.yuv", YuvFormat(1024, 768))[0]
        z = depth_to_z(depth, 448.251214, 11206.280350)
        seconds = median_seconds(
            lambda: forward_warp(texture, z, cameras["param_kendo01"], cameras["param_kendo03"]),
            repeats=5,
        )
        rows.append(
            (
                "forward warp, Kendo view 1 -> camera 3 (s)",
                seconds,
                "VSRS 4.2 whole frame, quoted",
                2.5,
            )
        )
    else:
        print(f"Kendo material not found under {DATA}: warp benchmark skipped")
    report(rows)


if __name__ == "__main__":
    main()
