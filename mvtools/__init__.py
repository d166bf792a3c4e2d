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
