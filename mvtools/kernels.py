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
    elif not any(isinstance(finder, _WhenNumbaLoads) for finder in sys.meta_path):
        sys.meta_path.insert(0, _WhenNumbaLoads())


class _WhenNumbaLoads(importlib.abc.MetaPathFinder):
    """Registers the listener right after numba is imported, by whoever imports it."""

    def find_spec(self, fullname, path, target=None):
        if fullname != "numba":
            return None
        sys.meta_path.remove(self)
        spec = importlib.util.find_spec(fullname)
        if spec is None or spec.loader is None:
            return spec
        load = spec.loader.exec_module

        def exec_module(module):
            load(module)
            _listen()

        spec.loader.exec_module = exec_module
        return spec


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
