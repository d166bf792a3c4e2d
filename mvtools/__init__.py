"""mvtools: a multiview video toolchain compatible with the MPEG reference programs."""

import os as _os
import sys as _sys

__version__ = "0.1.0"

# numba's threading layer, chosen before any parallel kernel runs. numba prefers TBB
# whenever libtbb is installed (Debian's ffmpeg and OpenCV packages bring it in), and
# TBB's scheduler spins in its finalisation at interpreter exit on a loaded machine: a
# finished run then took minutes to exit. OpenMP is the first choice (safe when several
# threads launch kernels at once, as a threaded Dask worker does); the workqueue layer,
# always built in, is the fallback (one caller at a time), so TBB, last because numba
# wants all three named, is never reached. NUMBA_THREADING_LAYER set by the user still
# wins.
_LAYERS = "omp workqueue tbb"
if "numba" in _sys.modules:
    import numba as _numba

    _numba.config.THREADING_LAYER_PRIORITY = _LAYERS.split()
else:
    _os.environ.setdefault("NUMBA_THREADING_LAYER_PRIORITY", _LAYERS)
# GNU OpenMP's idle threads spin some milliseconds after each parallel region before they
# sleep: on a machine whose cores other processes want, they take the time the working
# threads need (400 frames of synthesize under load: 23.8 s wall and 21.7 s CPU, with
# PASSIVE 15.0 s and 9.0 s). PASSIVE: they sleep at once. libgomp reads it when it
# loads, at the first parallel kernel; the user's setting still wins.
_os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")
# NumPy's OpenBLAS starts a thread per core and they spin-wait after each matrix product
# (the camera projections of every frame are such products, small ones): one Kendo frame
# of 1D synthesis took 0.9 s of CPU with them and 0.6 s without, in the same wall time.
# The parallel work of mvtools is in its numba kernels and its Dask workers, so BLAS
# runs on the calling thread. Read when NumPy loads: a program sets it before; a Python
# user who imported NumPy first keeps NumPy's choice, and the user's setting wins.
_os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

# numba's import-time BLAS probe would load scipy.linalg in every run (mvtools.kernels).
from mvtools.kernels import defer_blas_check as _defer_blas_check  # noqa: E402

_defer_blas_check()
