"""The dataclasses that flow through view synthesis."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mvtools.geometry.camera import Camera

FILTERS = ("bilinear", "bicubic", "avc6")  # VSRS Filter 0, 1, 2
# VSRS Precision: integer, half, quarter pixel; 8 and 16 are mvtools extensions.
PRECISIONS = (1, 2, 4, 8, 16)
HOLE_FILLING = ("background", "inpaint", "background-diffusion")  # IvsrsInpaint 1, 0, new

#: Hole filling of the library and of the program with ``IvsrsInpaint 1`` (VSRS's
#: default, depth-aware filling from the background side) or nothing said: the best
#: background-side method measured on Cones (see the README). ``IvsrsInpaint 0`` is plain
#: inpainting; ``--hole-filling`` chooses any method, VSRS's own row rule ("background")
#: included.
DEFAULT_HOLE_FILLING = "background-diffusion"


@dataclass(eq=False)
class ReferenceView:
    """A real view: its camera, its texture and its depth.

    Attributes
    ----------
    camera : Camera
    color : ndarray of float32, shape (H, W, 3)
        Texture in the working colour space (chroma upsampled to full size).
    z : ndarray of float64, shape (H, W)
        Depth of every pixel with the meaning of ``depth_type`` (0: along this camera's
        axis; 1: world z coordinate), already converted from depth-map values with this
        view's own Znear/Zfar.
    """

    camera: Camera
    color: np.ndarray
    z: np.ndarray


@dataclass(eq=False)
class WarpedView:
    """One reference seen from the virtual camera.

    Attributes
    ----------
    color : ndarray of float32, shape (H, W, 3)
        Colour fetched for each virtual pixel (undefined where ``z`` is inf).
    z : ndarray of float64, shape (H, W)
        Depth along the VIRTUAL camera's axis; ``inf`` where the reference gives
        nothing (disocclusion or outside its field of view).
    """

    color: np.ndarray
    z: np.ndarray

    @property
    def holes(self) -> np.ndarray:
        return ~np.isfinite(self.z)


@dataclass(frozen=True)
class SynthesisOptions:
    """Algorithm options, built by the program from :class:`mvtools.params.VsrsParams`.

    Attributes mirror the VSRS keys: ``mode`` (SynthesisMode 0 "general", 1 "1d"),
    ``precision`` (one of :data:`PRECISIONS`: VSRS's 1, 2, 4 and the finer 8 and 16 of
    mvtools), ``filter`` (one of :data:`FILTERS`), ``depth_type`` (0, 1),
    ``view_blending`` (ViewBlending 1 = True), ``depth_blend_difference`` (in 8-bit
    depth-value units of the common inverse-depth range, see
    :func:`mvtools.synthesis.blend.merge_views`), ``hole_filling`` (IvsrsInpaint),
    ``boundary_noise_removal``, and the 1D-mode keys. ``edge_softening`` (no VSRS
    key) anti-aliases object outlines (:func:`mvtools.synthesis.boundary.soften_edges`).
    """

    mode: str = "general"
    precision: int = 2
    filter: str = "bicubic"
    depth_type: int = 0
    view_blending: bool = False
    depth_blend_difference: float = 5.0
    hole_filling: str = DEFAULT_HOLE_FILLING
    boundary_noise_removal: bool = False
    edge_softening: bool = True
    # 1D mode
    splatting: int = 2
    boundary_growth: int = 40
    merging: int = 2
    depth_threshold: int = 75
    hole_count_threshold: int = 30
    temporal_improvement: bool = True
    warp_enhancement: bool = True
    clean_noise: bool = True

    def __post_init__(self):
        if self.mode not in ("general", "1d"):
            raise ValueError(f"mode must be 'general' or '1d', got {self.mode!r}")
        if self.precision not in PRECISIONS:
            raise ValueError(
                f"precision must be one of {', '.join(map(str, PRECISIONS))}, "
                f"got {self.precision!r}"
            )
        if self.filter not in FILTERS:
            raise ValueError(f"filter must be one of {', '.join(FILTERS)}, got {self.filter!r}")
        if self.depth_type not in (0, 1):
            raise ValueError(f"depth_type must be 0 or 1, got {self.depth_type}")
        if self.hole_filling not in HOLE_FILLING:
            raise ValueError(
                f"hole_filling must be one of {', '.join(HOLE_FILLING)}, got {self.hole_filling!r}"
            )


@dataclass(eq=False)
class SynthesisResult:
    """The virtual view.

    Attributes
    ----------
    color : ndarray of float32, shape (H, W, 3)
        Working colour space, holes filled.
    z : ndarray of float64, shape (H, W)
        Virtual depth along the virtual camera's axis (holes filled from the background
        side; inf only where nothing could be filled).
    holes : ndarray of bool, shape (H, W)
        Pixels that no reference view saw (before filling).
    """

    color: np.ndarray
    z: np.ndarray
    holes: np.ndarray
