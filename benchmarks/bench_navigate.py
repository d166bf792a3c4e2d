"""Free navigation (issue 19), whole processes of ``mvtools navigate``:

- a 60-frame keyframe path through the five cameras of the sample line and arc, half a
  camera interval beyond the outer ones, static content, each frame against the scene
  ray-cast at its pose (the exact truth): mean and lowest Y-PSNR, for both eyes of a
  stereo path too, and all five views against the nearest two on the frames beyond the
  outer cameras; frames per CPU second; peak memory for 30 and 60 frames;
- Kendo: 16 dense views between cameras 1 and 3 in one run against one view
  (``mvtools synthesize``), and each dense view against that view synthesized alone.
"""

from __future__ import annotations

import sys
import tempfile
from multiprocessing import Pool
from pathlib import Path

import numpy as np
from common import DATA, report, run_measured

from mvtools.color.space import rgb_to_yuv
from mvtools.geometry.pose import camera_path, eye_cameras
from mvtools.io.camera_files import read_camera_file, write_camera_file
from mvtools.io.yuv import YuvFormat, open_video
from mvtools.metrics.psnr import psnr
from mvtools.scene import default_scene
from mvtools.scene.render import render

ROOT = Path(__file__).resolve().parents[1]
SAMPLE = ROOT / "sample_data"
FRAMES = 60
EXTEND = 0.5
KENDO = DATA / "mpeg" / "kendo"
KENDO_CONFIG = KENDO / "config" / "VSRS" / "vsrs_kendo_ori.cfg"
KENDO_RANGE = ("448.251214", "11206.280350")
#: VSRS 4.2 synthesizes one Kendo view per run: 1.06 s of CPU in general mode, Precision 4
#: (reference_outputs/README.md); 16 views are 16 runs.
VSRS_KENDO_VIEW = 1.06


def run(arguments: list[str], cwd: Path) -> tuple[float, float]:
    """CPU seconds and peak resident MB of one whole ``mvtools`` process."""
    _, usage = run_measured(
        [sys.executable, "-m", "mvtools", *arguments, "-q"], cwd=cwd, check=True
    )
    return usage.cpu_seconds, usage.peak_mib


def _views(folder: Path, names: list[str], depth: str = "yuv420p") -> list[str]:
    arguments = []
    for index, name in enumerate(names):
        arguments += ["--view", name, str(folder / f"v{index}_texture_256x192_yuv420p.yuv")]
        arguments += ["--depth", name, str(folder / f"v{index}_depth_256x192_{depth}.yuv")]
    return arguments


def _truth(camera) -> np.ndarray:
    return rgb_to_yuv(render(default_scene(seed=0), camera, samples=4, size=(256, 192)).color)[0]


def _psnrs(video: Path, truths: list[np.ndarray], fmt: YuvFormat) -> np.ndarray:
    with open_video(video, fmt) as frames:
        return np.array(
            [psnr(truth, frames.read(k)[0], max_value=255) for k, truth in enumerate(truths)]
        )


def path_rows(rig: str, folder: Path, pool: Pool) -> list:
    cameras = read_camera_file(SAMPLE / rig / "cameras.txt")
    names = list(cameras)
    path = camera_path([cameras[name] for name in names], FRAMES, extend=EXTEND)
    eyes = [eye_cameras(camera, 0.065) for camera in path]
    truths = pool.map(_truth, path)
    left_truths = pool.map(_truth, [left for left, _ in eyes])
    right_truths = pool.map(_truth, [right for _, right in eyes])
    common = ["navigate", str(SAMPLE / rig / "cameras.txt"), *_views(SAMPLE / rig, names)]
    common += ["--depth-range", "2", "13", "--static", "--precision", "4"]
    fmt = YuvFormat(256, 192)
    rows = []
    cpu, memory = run(
        [*common, "--frames", str(FRAMES), "--extend", str(EXTEND), "-o", "all.yuv"], folder
    )
    every = _psnrs(folder / "all.yuv", truths, fmt)
    run(
        [
            *common,
            "--frames",
            str(FRAMES),
            "--extend",
            str(EXTEND),
            "--views-per-frame",
            "2",
            "-o",
            "two.yuv",
        ],
        folder,
    )
    two = _psnrs(folder / "two.yuv", truths, fmt)
    _, half_memory = run(
        [*common, "--frames", str(FRAMES // 2), "--extend", str(EXTEND), "-o", "half.yuv"], folder
    )
    run(
        [
            *common,
            "--frames",
            str(FRAMES),
            "--extend",
            str(EXTEND),
            "--stereo",
            "-o",
            "eye_%s.yuv",
        ],
        folder,
    )
    left = _psnrs(folder / "eye_left.yuv", left_truths, fmt)
    right = _psnrs(folder / "eye_right.yuv", right_truths, fmt)
    # path parameter of each frame in keyframe intervals: beyond the outer cameras below 0
    # and above the last keyframe's index
    parameter = np.linspace(-EXTEND, len(names) - 1 + EXTEND, FRAMES)
    beyond = (parameter < 0) | (parameter > len(names) - 1)
    finite = np.isfinite
    rows.append((f"{rig}: path mean Y-PSNR (dB)", every[finite(every)].mean(), "bar", 35.0))
    rows.append((f"{rig}: path lowest Y-PSNR (dB)", every.min(), "bar", 30.0))
    for eye, values in (("left", left), ("right", right)):
        rows.append(
            (f"{rig}: {eye} eye mean Y-PSNR (dB)", values[finite(values)].mean(), "bar", 35.0)
        )
        rows.append((f"{rig}: {eye} eye lowest Y-PSNR (dB)", values.min(), "bar", 30.0))
    rows.append(
        (
            f"{rig}: beyond the outer cameras, 5 views (dB)",
            every[beyond].mean(),
            "nearest 2 views",
            two[beyond].mean(),
        )
    )
    rows.append((f"{rig}: path frames per CPU second", FRAMES / cpu, "bar", 20.0))
    rows.append((f"{rig}: peak memory, 60 frames (MB)", memory, "30 frames", half_memory))
    return rows


def kendo_rows(folder: Path, mode: int) -> list:
    cameras = KENDO / "config" / "VSRS" / "cam_param_kendo.cfg"
    views = [
        "--view",
        "param_kendo01",
        str(KENDO / "kendo_ori_I_1.yuv"),
        "--depth",
        "param_kendo01",
        str(KENDO / "kendo_ori_D_1.yuv"),
        "--view",
        "param_kendo03",
        str(KENDO / "kendo_ori_I_3.yuv"),
        "--depth",
        "param_kendo03",
        str(KENDO / "kendo_ori_D_3.yuv"),
    ]
    dense, _ = run(
        [
            "navigate",
            str(cameras),
            *views,
            "--depth-range",
            *KENDO_RANGE,
            "--size",
            "1024x768",
            "--dense",
            "--frames",
            "16",
            "--static",
            "--precision",
            "4",
            "--synthesis-mode",
            str(mode),
            "-o",
            "dense_%s_1024x768.yuv",
        ],
        folder,
    )
    # the same 16 cameras in a camera file, each synthesized alone by the VSRS program
    all_cameras = read_camera_file(cameras)
    path = camera_path([all_cameras["param_kendo01"], all_cameras["param_kendo03"]], 16)
    write_camera_file(folder / "dense_cameras.txt", path)
    fmt = YuvFormat(1024, 768)
    differences = []
    alone = []
    for index, camera in enumerate(path):
        cpu, _ = run(
            [
                "synthesize",
                str(KENDO_CONFIG),
                "--data-dir",
                str(KENDO),
                f"CameraParameterFile={folder / 'dense_cameras.txt'}",
                f"LeftCameraName={path[0].name}",
                f"RightCameraName={path[-1].name}",
                f"VirtualCameraName={camera.name}",
                "TotalNumberOfFrames=1",
                # navigate blends the two views (ViewBlending 0), whatever the file says
                "ViewBlending=0",
                f"SynthesisMode={mode}",
                "-o",
                f"alone_{index:02d}_1024x768.yuv",
            ],
            folder,
        )
        alone.append(cpu)
        with (
            open_video(folder / f"dense_{index:02d}_1024x768.yuv", fmt) as a,
            open_video(folder / f"alone_{index:02d}_1024x768.yuv", fmt) as b,
        ):
            differences.append((a.read(0)[0], b.read(0)[0]))
    worst = min(psnr(a, b, max_value=255) for a, b in differences)
    one = float(np.median(alone))
    label = ("general", "1D")[mode]
    return [
        (f"Kendo {label}: 16 dense views, one run (CPU s)", dense, "4x one view", 4 * one),
        (
            f"Kendo {label}: 16 dense views, one run (CPU s)",
            dense,
            "VSRS 4.2, 16 runs",
            16 * VSRS_KENDO_VIEW,
        ),
        (f"Kendo {label}: dense vs alone, lowest PSNR (dB)", worst, "", None),
    ]


def main() -> None:
    rows = []
    with tempfile.TemporaryDirectory() as name, Pool(2) as pool:
        folder = Path(name)
        for rig in ("line", "arc"):
            rows += path_rows(rig, folder, pool)
        if KENDO_CONFIG.exists():
            rows += kendo_rows(folder, 0) + kendo_rows(folder, 1)
        else:
            print(f"Kendo not found under {DATA}: its rows are skipped")
    report(rows)


if __name__ == "__main__":
    main()
