"""Interrupted runs: SIGINT and SIGTERM stop a program with one line and exit codes 130
and 143 (128 + the signal's number, as shells report them), and remove the temporary
file of the output being written; an earlier output of the same name is left as it was.

The run is a whole-process ``mvtools synthesize`` over a long input (the sample line
rig's three frames repeated), signalled once its temporary output exists.
"""

from __future__ import annotations

import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

LINE = Path(__file__).resolve().parent.parent / "sample_data" / "line"
INPUTS = ("v1_texture_256x192_yuv420p.yuv", "v3_texture_256x192_yuv420p.yuv",
          "v1_depth_256x192_yuv420p.yuv", "v3_depth_256x192_yuv420p.yuv")
REPEATS = 200       # 600 frames: tens of seconds, far longer than the wait for the signal
OUTPUT = "out_256x192_yuv420p.yuv"
EARLIER = b"the output of an earlier run"


@pytest.fixture(scope="module")
def long_rig(tmp_path_factory):
    folder = tmp_path_factory.mktemp("long_rig")
    for name in INPUTS:
        (folder / name).write_bytes((LINE / name).read_bytes() * REPEATS)
    for name in ("synthesize_cam2.cfg", "cameras.txt"):
        shutil.copy(LINE / name, folder / name)
    return folder


@pytest.mark.parametrize("signum, exit_code, word", [(signal.SIGINT, 130, "interrupted"),
                                                     (signal.SIGTERM, 143, "terminated")],
                         ids=["SIGINT", "SIGTERM"])
def test_a_signalled_run_removes_its_temporary_output(long_rig, signum, exit_code, word):
    (long_rig / OUTPUT).write_bytes(EARLIER)
    process = subprocess.Popen(
        [sys.executable, "-m", "mvtools", "synthesize", "synthesize_cam2.cfg",
         f"TotalNumberOfFrames={3 * REPEATS}", "-o", OUTPUT],
        cwd=long_rig, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        deadline = time.monotonic() + 60
        while not list(long_rig.glob(f".{OUTPUT}.*")):
            assert process.poll() is None, process.communicate()[1]
            assert time.monotonic() < deadline, "no temporary output after 60 s"
            time.sleep(0.05)
        process.send_signal(signum)
        _, err = process.communicate(timeout=60)
    finally:
        process.kill()
    assert process.returncode == exit_code, err
    errors = [line for line in err.splitlines() if "error:" in line]
    assert len(errors) == 1 and word in errors[0], err
    assert "Traceback" not in err
    assert (long_rig / OUTPUT).read_bytes() == EARLIER
    assert sorted(path.name for path in long_rig.iterdir()) == sorted(
        [*INPUTS, "synthesize_cam2.cfg", "cameras.txt", OUTPUT])
