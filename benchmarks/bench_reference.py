"""mvtools side by side with VSRS 4.2 and RVS 4.0 on identical input (issue 16).

The inputs, configurations, reference outputs and their scores are those of
``reference_outputs/`` in the shared data (its README): Cones im4 at every setting
VSRS was run with, Poznan Hall 2 camera 7 from camera 5 alone, and Kendo camera 02
(no real view: the agreement of the outputs, Y-PSNR between them, is printed). Then
the whole process of ``mvtools synthesize`` on one Kendo frame, CPU and wall time
(interpreter start included), against the CPU times of VSRS in the README.
"""

from __future__ import annotations

import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from common import DATA, report
from reference_cases import (
    CAMERA_5_AS_RIGHT,
    MODES,
    RVS_CONES,
    VSRS_CONES,
    VSRS_HALL_FROM_CAMERA_5,
)

from mvtools.io.yuv import YuvFormat, read_frame
from mvtools.metrics import psnr

REFERENCE = DATA / "reference_outputs"
CONES = REFERENCE / "cones_mvd"
HALL = DATA / "mpeg" / "poznan_hall2"
KENDO = DATA / "mpeg" / "kendo"
KENDO_CONFIG = KENDO / "config" / "VSRS" / "vsrs_kendo_ori.cfg"

# Kendo: the settings VSRS was run with, its output and its whole-process CPU seconds
# for one frame (README).
KENDO_RUNS = (
    ("general", 4, "vsrs42_cam02_general_P4", 1.06),
    ("1d", 2, "vsrs42_cam02_1d_P2", 0.34),
)


def synthesize(config: Path, *settings: str, data_dir: Path, fmt: YuvFormat, folder: Path):
    """Run ``mvtools synthesize`` as a user does, in a process of its own: the luma of its
    one frame, and the process's CPU and wall seconds."""
    output = folder / "synthesized.yuv"
    cpu_before = _children_cpu_seconds()
    start = time.perf_counter()
    subprocess.run(
        [
            sys.executable,
            "-m",
            "mvtools",
            "synthesize",
            str(config),
            "-q",
            "--data-dir",
            str(data_dir),
            *settings,
            "-o",
            str(output),
        ],
        cwd=folder,
        check=True,
    )
    wall = time.perf_counter() - start
    return read_frame(output, fmt)[0], _children_cpu_seconds() - cpu_before, wall


def _children_cpu_seconds() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def y_psnr(reference, luma) -> float:
    return psnr(reference, luma, max_value=255)


def cones_rows(folder: Path) -> list:
    fmt = YuvFormat(448, 368)
    truth = read_frame(CONES / "cones_4_448x368_yuv420p.yuv", fmt)[0]
    rows = []
    for (mode, precision, noise_removal), vsrs in VSRS_CONES.items():
        luma, _, _ = synthesize(
            CONES / f"vsrs_cones_{mode}.cfg",
            f"Precision={precision}",
            f"BoundaryNoiseRemoval={noise_removal}",
            data_dir=CONES,
            fmt=fmt,
            folder=folder,
        )
        rows.append(
            (
                "Cones im4",
                f"{mode} P{precision} B{noise_removal}",
                y_psnr(truth, luma),
                vsrs,
                RVS_CONES,
            )
        )
    return rows


def hall_rows(folder: Path) -> list:
    fmt = YuvFormat(1920, 1088)
    truth = read_frame(HALL / "hall_I_cam07.yuv", fmt)[0]
    config = HALL / "config" / "VSRS" / "vsrs_poznanhall2_ori.cfg"
    rows = []
    for mode, synthesis_mode in MODES.items():
        luma, _, _ = synthesize(
            config,
            "VirtualCameraName=param_cam7",
            *CAMERA_5_AS_RIGHT,
            f"SynthesisMode={synthesis_mode}",
            data_dir=HALL,
            fmt=fmt,
            folder=folder,
        )
        vsrs_output = read_frame(
            REFERENCE / "poznan_hall2" / f"vsrs42_cam07_from_cam05_{mode}_1920x1088_yuv420p.yuv",
            fmt,
        )[0]
        rows.append(
            (
                "Hall2 cam7 from cam5",
                f"{mode} P4 (shipped)",
                y_psnr(truth, luma),
                VSRS_HALL_FROM_CAMERA_5[mode],
                None,
            )
        )
        rows.append(("  agreement", f"{mode} P4", None, y_psnr(vsrs_output, luma), None))
        luma, _, _ = synthesize(
            config,
            "VirtualCameraName=param_cam7",
            f"SynthesisMode={synthesis_mode}",
            data_dir=HALL,
            fmt=fmt,
            folder=folder,
        )
        rows.append(
            ("Hall2 cam7 from cam5+7", f"{mode} P4 (shipped)", y_psnr(truth, luma), None, None)
        )
    return rows


def kendo_rows(folder: Path) -> tuple[list, list]:
    """Agreement with VSRS's and RVS's camera 02, and the timing rows."""
    fmt = YuvFormat(1024, 768)
    rvs_output = read_frame(REFERENCE / "kendo" / "rvs40_cam02_1024x768_yuv420p.yuv", fmt)[0]
    quality, timing = [], []
    for mode, precision, vsrs_name, vsrs_cpu in KENDO_RUNS:
        luma, cpu, wall = synthesize(
            KENDO_CONFIG,
            "TotalNumberOfFrames=1",
            f"SynthesisMode={MODES[mode]}",
            f"Precision={precision}",
            data_dir=KENDO,
            fmt=fmt,
            folder=folder,
        )
        vsrs_output = read_frame(REFERENCE / "kendo" / f"{vsrs_name}_1024x768_yuv420p.yuv", fmt)[0]
        quality.append(
            (
                "Kendo cam02 agreement",
                f"{mode} P{precision}",
                None,
                y_psnr(vsrs_output, luma),
                y_psnr(rvs_output, luma),
            )
        )
        quality.append(
            ("  VSRS with RVS", f"{mode} P{precision}", None, None, y_psnr(rvs_output, vsrs_output))
        )
        timing.append(
            (
                f"Kendo {mode} P{precision}, whole process, CPU (s)",
                cpu,
                "VSRS 4.2, one frame, README",
                vsrs_cpu,
            )
        )
        timing.append(
            (
                f"Kendo {mode} P{precision}, whole process, wall (s)",
                wall,
                "VSRS 4.2 CPU, one frame, README",
                vsrs_cpu,
            )
        )
    return quality, timing


def _figure(value: float | None) -> str:
    return f"{value:>9.2f}" if value is not None else f"{'':>9}"


def print_quality(rows: list) -> None:
    """Case, setting, mvtools dB, VSRS dB, RVS dB and mvtools's lead over each.

    Scores are Y-PSNR against the real view; an agreement row (no mvtools figure) gives
    the Y-PSNR of the program's output against mvtools's (``VSRS with RVS``: VSRS's
    against RVS's)."""
    print(
        f"{'case':<24}{'setting':<20}{'mvtools':>9}{'VSRS':>9}{'RVS':>9}"
        f"{'-VSRS':>9}{'-RVS':>9}  (Y-PSNR, dB)"
    )
    for case, setting, ours, vsrs, rvs in rows:
        lead_vsrs = ours - vsrs if None not in (ours, vsrs) else None
        lead_rvs = ours - rvs if None not in (ours, rvs) else None
        print(
            f"{case:<24}{setting:<20}{_figure(ours)}{_figure(vsrs)}{_figure(rvs)}"
            f"{_figure(lead_vsrs)}{_figure(lead_rvs)}"
        )


def main() -> None:
    if not all(path.exists() for path in (REFERENCE, HALL, KENDO)):
        print(f"reference outputs or MPEG material not found under {DATA}: benchmark skipped")
        return
    with tempfile.TemporaryDirectory() as folder:
        folder = Path(folder)
        kendo_quality, timing = kendo_rows(folder)
        print_quality(cones_rows(folder) + hall_rows(folder) + kendo_quality)
    print()
    report(timing)


if __name__ == "__main__":
    main()
