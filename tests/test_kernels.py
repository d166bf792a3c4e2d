"""The first run of a program that compiles a numba kernel says so, once; a run that
loads the kernel from numba's cache says nothing. The program is a whole process with
a kernel of its own, compiled into a fresh cache folder."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest

from mvtools.kernels import MESSAGE

A_PROGRAM_WITH_KERNELS = """
import sys
import click
from mvtools.cli.options import program

@click.command()
@program
def main():
    sys.path.insert(0, ".")
    import kernels
    print(kernels.double(21.0) + kernels.triple(1.0))

main()
"""

KERNELS = """
import numba

@numba.njit(cache=True)
def double(x):
    return 2 * x

@numba.njit(cache=True)
def triple(x):
    return 3 * x
"""


def _run(folder, cache):
    return subprocess.run(
        [sys.executable, "-c", A_PROGRAM_WITH_KERNELS],
        cwd=folder,
        capture_output=True,
        text=True,
        env=dict(os.environ, NUMBA_CACHE_DIR=str(cache)),
        check=True,
    )


@pytest.mark.slow
def test_the_first_run_says_it_compiles_and_the_next_does_not(tmp_path):
    (tmp_path / "kernels.py").write_text(KERNELS)
    cache = tmp_path / "cache"
    first, second = _run(tmp_path, cache), _run(tmp_path, cache)
    assert first.stdout == second.stdout == "45.0\n"
    assert first.stderr.count(MESSAGE) == 1, first.stderr
    assert MESSAGE not in second.stderr, second.stderr
