"""Disparity estimation.

A *method* turns a matching-cost volume into a volume whose per-pixel minimum is the
chosen level: semi-global matching's path sums, a local matcher's window sums, belief
propagation's beliefs, or for graph cuts each label's energy given the neighbours' final
labels. The same volume read along its diagonals gives the right view's levels, so every
method gets a left-right check from one optimisation, and the DERS mode can run any
method on its plane-sweep volume.

Arrays in, arrays out: the ``estimate-depth`` program reads the views and writes the maps.
Names are imported from their modules on first use, so ``import mvtools.depth`` does not
compile or load the numba kernels.
"""

from __future__ import annotations

from mvtools.lazy import attach

#: Each exported name and the module of this package that defines it.
_EXPORTS: dict[str, str] = {
    "COSTS": "cost",
    "METHODS": "stereo",
    "PAIR_METHODS": "stereo",
    "estimate_disparity": "stereo",
    "checked_disparity": "stereo",
    "estimate_array_disparity": "array",
    "DersEstimator": "ders",
    "Neighbour": "ders",
    "DepthOptions": "options",
}

__getattr__, __dir__, __all__ = attach(__name__, _EXPORTS)
