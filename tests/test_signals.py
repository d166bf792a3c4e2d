"""Interrupted runs: SIGINT and SIGTERM stop a program with one line and exit codes 130
and 143 (128 + the signal's number, as shells report them), and remove the temporary
file of the output being written; an earlier output of the same name is left as it was.

The run is a whole-process ``mvtools synthesize`` over a long input (the sample line
rig's three frames repeated), signalled once its temporary output exists: with its
kernels compiled and cached, and while numba compiles them (a fresh cache), when the
signal's handler may run inside a callback from the compiler, where a raised exception
is ignored. A program whose run sits in such a callback (C's qsort calling Python) is
signalled too: it must end all the same.
"""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

LINE = Path(__file__).resolve().parent.parent / "sample_data" / "line"
INPUTS = (
    "v1_texture_256x192_yuv420p.yuv",
    "v3_texture_256x192_yuv420p.yuv",
    "v1_depth_256x192_yuv420p.yuv",
    "v3_depth_256x192_yuv420p.yuv",
)
REPEATS = 200  # 600 frames: tens of seconds, far longer than the wait for the signal
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


SIGNALS = pytest.mark.parametrize(
    "signum, exit_code, word",
    [(signal.SIGINT, 130, "interrupted"), (signal.SIGTERM, 143, "terminated")],
    ids=["SIGINT", "SIGTERM"],
)


def _signal_once_writing(command, folder, output, signum, *, after=0.0, env=None):
    """Run ``command`` in ``folder``; send ``signum`` ``after`` seconds from the moment
    the temporary file of ``output`` exists. Returns the exit code and stderr."""
    process = subprocess.Popen(
        command, cwd=folder, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env
    )
    try:
        deadline = time.monotonic() + 60
        while not list(folder.glob(f".{output}.*")):
            assert process.poll() is None, process.communicate()[1]
            assert time.monotonic() < deadline, "no temporary output after 60 s"
            time.sleep(0.02)
        time.sleep(after)
        process.send_signal(signum)
        _, err = process.communicate(timeout=30)
    finally:
        process.kill()
    return process.returncode, err


def _assert_ended_cleanly(returncode, err, exit_code, word):
    assert returncode == exit_code, err
    errors = [line for line in err.splitlines() if "error:" in line]
    assert len(errors) == 1 and word in errors[0], err
    assert "Traceback" not in err and "Exception ignored" not in err, err


@pytest.mark.parametrize("kernels", ["compiled", "compiling"])
@SIGNALS
def test_a_signalled_run_removes_its_temporary_output(
    long_rig, tmp_path, kernels, signum, exit_code, word
):
    (long_rig / OUTPUT).write_bytes(EARLIER)
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path)) if kernels == "compiling" else None
    returncode, err = _signal_once_writing(
        [
            sys.executable,
            "-m",
            "mvtools",
            "synthesize",
            "synthesize_cam2.cfg",
            f"TotalNumberOfFrames={3 * REPEATS}",
            "-o",
            OUTPUT,
        ],
        long_rig,
        OUTPUT,
        signum,
        after=0.5 if kernels == "compiling" else 0.0,
        env=env,
    )
    _assert_ended_cleanly(returncode, err, exit_code, word)
    assert (long_rig / OUTPUT).read_bytes() == EARLIER
    assert sorted(path.name for path in long_rig.iterdir()) == sorted(
        [*INPUTS, "synthesize_cam2.cfg", "cameras.txt", OUTPUT]
    )


#: A program whose run spends its time in Python code called back from C (qsort's
#: comparisons), as numba's compilation does through llvmlite.
IN_A_C_CALLBACK = """
import ctypes, time
import click
from mvtools.cli.options import program
from mvtools.io.atomic import atomic_output

COMPARE = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_void_p, ctypes.c_void_p)

@click.command()
@program
def main():
    with atomic_output("out.bin") as handle:
        handle.write(b"partial")
        numbers = (ctypes.c_int * 100000)()
        ctypes.CDLL(None).qsort(numbers, len(numbers), ctypes.sizeof(ctypes.c_int),
                                COMPARE(lambda a, b: time.sleep(0.001) or 0))

main()
"""


@SIGNALS
def test_a_signal_ends_a_run_inside_a_callback_from_c(tmp_path, signum, exit_code, word):
    returncode, err = _signal_once_writing(
        [sys.executable, "-c", IN_A_C_CALLBACK], tmp_path, "out.bin", signum, after=0.2
    )
    _assert_ended_cleanly(returncode, err, exit_code, word)
    assert list(tmp_path.iterdir()) == []
