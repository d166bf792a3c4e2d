"""The first run of a program compiles its numba kernels, and says so.

numba compiles each kernel for the machine the first time it runs and caches the
result (in the package's ``__pycache__``, or ``NUMBA_CACHE_DIR``); later runs load it
in milliseconds. The first run of a program after installing therefore waits some
seconds to a minute before its first frame: :func:`announce_compilation` makes that wait
one line on stderr instead of silence. It costs nothing until numba is imported, so
programs that never reach a kernel (``--help``, ``inspect``) do not pay for numba.
"""

from __future__ import annotations

import functools
import importlib.abc
import importlib.util
import logging
import sys

LOG = logging.getLogger("mvtools")

MESSAGE = (
    "compiling numba kernels for this machine, once: this first run waits up to a minute; "
    "later runs load them from the cache"
)


def announce_compilation() -> None:
    """Log :data:`MESSAGE` (INFO) when a kernel first compiles rather than loads from the
    cache, once per process; kernels loaded from the cache say nothing."""
    if "numba" in sys.modules:
        _listen()
    else:
        _around_import("numba", _then_listen)


def defer_blas_check() -> None:
    """Keep numba from importing SciPy's linear algebra in every process that loads a
    kernel.

    numba's array functions ask at import whether BLAS is there by importing
    ``scipy.linalg.cython_blas``, which loads all of ``scipy.linalg``: 0.2 s of CPU
    in a run of a fraction of a second, though no kernel of mvtools calls BLAS. Here the
    question is answered by whether SciPy is installed, which is the same answer where
    SciPy is sound; numba still imports the BLAS module when a kernel that uses it
    compiles or loads.
    """
    if "numba.np.arraymath" not in sys.modules:
        _around_import("numba.np.arraymath", _without_importing_blas)


def _around_import(name: str, around) -> None:
    """Run ``around(load, module)`` instead of ``load(module)`` when module ``name`` is
    first imported, by whoever imports it."""
    if not any(isinstance(f, _AroundImport) and f.name == name for f in sys.meta_path):
        sys.meta_path.insert(0, _AroundImport(name, around))


class _AroundImport(importlib.abc.MetaPathFinder):
    def __init__(self, name: str, around):
        self.name = name
        self.around = around

    def find_spec(self, fullname, path, target=None):
        if fullname != self.name:
            return None
        sys.meta_path.remove(self)
        spec = importlib.util.find_spec(fullname)
        if spec is None or spec.loader is None:
            return spec
        load = spec.loader.exec_module
        spec.loader.exec_module = lambda module: self.around(load, module)
        return spec


def _then_listen(load, module) -> None:
    load(module)
    _listen()


def _without_importing_blas(load, module) -> None:
    import numba.np.linalg as linalg

    ensure_blas = linalg.ensure_blas

    def scipy_installed() -> None:
        if importlib.util.find_spec("scipy") is None:
            raise ImportError("scipy 0.16+ is required for linear algebra")

    # arraymath binds the name when it imports: only its import-time check sees this
    linalg.ensure_blas = scipy_installed
    try:
        load(module)
    finally:
        linalg.ensure_blas = ensure_blas


@functools.cache  # one listener per process
def _listen() -> None:
    from numba.core import event

    class FirstCompilation(event.Listener):
        said = False

        def on_start(self, event):
            # numba:compile starts only on a cache miss (dispatcher.compile)
            if not self.said:
                self.said = True
                LOG.info("%s", MESSAGE)

        def on_end(self, event):
            pass

    event.register("numba:compile", FirstCompilation())
