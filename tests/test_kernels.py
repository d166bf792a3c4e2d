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


BLAS_PROBE = """
import sys
import numpy as np
import mvtools
import numba

@numba.njit
def add(a, b):
    return a + b

add(1.0, 2.0)  # numba's array functions load with the first kernel
print("scipy.linalg" in sys.modules)

@numba.njit
def matrix_product(a, b):
    return a @ b

print(matrix_product(np.array([[1.0, 2.0], [3.0, 4.0]]), np.array([[5.0], [6.0]])).ravel())
print("scipy.linalg" in sys.modules)
"""


@pytest.mark.slow
def test_kernels_load_without_scipy_linalg_and_blas_still_serves_those_that_use_it(tmp_path):
    """numba's import-time BLAS probe is deferred (mvtools.kernels.defer_blas_check): a
    kernel loads without scipy.linalg, and a kernel that multiplies matrices still gets
    BLAS, [[1, 2], [3, 4]] @ [[5], [6]] = [[17], [39]] by hand."""
    done = subprocess.run(
        [sys.executable, "-c", BLAS_PROBE],
        capture_output=True,
        text=True,
        cwd=tmp_path,
        env={**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "cache")},
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.split("\n")[:3] == ["False", "[17. 39.]", "True"]
