"""The synthesis of one virtual view, frame after frame.

:class:`Synthesizer` is built once per virtual camera (it precomputes the camera
pair constants and keeps the temporal state of the 1D mode) and turns each frame's
reference views into a :class:`~mvtools.synthesis.views.SynthesisResult`:

1. warp every reference into the virtual camera (general mode:
   :class:`~mvtools.synthesis.general.GeneralWarper`; 1D mode:
   :class:`~mvtools.synthesis.oned.OneDWarper` after the reference depth has been
   through :class:`~mvtools.synthesis.temporal.TemporalDepthFilter` when
   ``temporal_improvement`` is on);
2. with ``boundary_noise_removal``, turn each warped view's background-side fringe
   into holes (:func:`~mvtools.synthesis.boundary.remove_boundary_noise`);
3. merge (general: :func:`~mvtools.synthesis.blend.merge_views` over any number of
   views; 1D: :func:`~mvtools.synthesis.oned.merge_1d`);
4. fill what is left (:func:`~mvtools.synthesis.holes.fill_holes`);
5. with ``edge_softening``, anti-alias the outlines of objects
   (:func:`~mvtools.synthesis.boundary.soften_edges`), unless a reference sits at
   the virtual camera.

One reference (or the same camera given several times, as VSRS users do to
extrapolate) is warped once and filled.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from mvtools.geometry.camera import Camera, same_camera
from mvtools.geometry.projection import depth_along_axis, pixel_grid
from mvtools.synthesis.blend import at_virtual_camera, merge_views, view_weights
from mvtools.synthesis.boundary import remove_boundary_noise, soften_edges
from mvtools.synthesis.general import GeneralWarper, ZBuffers
from mvtools.synthesis.holes import fill_holes
from mvtools.synthesis.oned import OneDWarper, merge_1d
from mvtools.synthesis.temporal import TemporalDepthFilter
from mvtools.synthesis.views import ReferenceView, SynthesisOptions, SynthesisResult, WarpedView

__all__ = ["Synthesizer"]


class Synthesizer:
    """Synthesizes one virtual view from reference views, frame after frame.

    Parameters
    ----------
    virtual_camera : Camera
    reference_cameras : sequence of Camera
        In 1D mode one or two, left first (its ``fx`` serves both, as in VSRS); in
        general mode any number. Cameras with the same ``K``, ``R`` and ``t`` are one
        reference: only the first of them is warped.
    options : SynthesisOptions
        ``view_blending`` and ``depth_blend_difference`` steer the general mode's
        merging; the 1D mode merges by ``merging`` (``MergingOption``), as VSRS does.
    size : (width, height)
        Size of the virtual view.
    depth_range : (znear, zfar)
        The common range in whose 8-bit depth-value units ``depth_blend_difference``
        and the 1D ``depth_threshold`` compare the warped depths (whatever the
        ranges of the reference depth maps).
    z_buffers : ZBuffers, optional
        The general mode's z-buffers, shared with synthesizers that never run at the
        same time as this one (default: its own).
    """

    def __init__(
        self,
        virtual_camera: Camera,
        reference_cameras: Sequence[Camera],
        options: SynthesisOptions,
        *,
        size: tuple[int, int],
        depth_range: tuple[float, float],
        z_buffers: ZBuffers | None = None,
    ):
        cameras = list(reference_cameras)
        if not cameras:
            raise ValueError("need at least one reference camera")
        self.options = options
        self.size = tuple(int(value) for value in size)
        self.depth_range = (float(depth_range[0]), float(depth_range[1]))
        self.reference_count = len(cameras)
        self._used = _distinct(cameras)
        used_cameras = [cameras[i] for i in self._used]
        self.weights = view_weights(virtual_camera, used_cameras)
        self._reference_at_virtual = bool(at_virtual_camera(virtual_camera, used_cameras).any())
        if options.mode == "general":
            # The views are warped one after the other: one set of z-buffers serves all.
            z_buffers = ZBuffers() if z_buffers is None else z_buffers
            self._warpers = [
                GeneralWarper(
                    camera,
                    virtual_camera,
                    size=self.size,
                    depth_type=options.depth_type,
                    z_buffers=z_buffers,
                )
                for camera in used_cameras
            ]
            self._temporal = None
        else:
            if len(used_cameras) > 2:
                raise ValueError(
                    f"1D mode takes one or two reference views, got {len(used_cameras)}"
                )
            self._warpers = [
                OneDWarper(camera, virtual_camera, size=self.size, left_camera=cameras[0])
                for camera in used_cameras
            ]
            self._temporal = (
                [TemporalDepthFilter() for _ in used_cameras]
                if options.temporal_improvement
                else None
            )

    @property
    def carries_state(self) -> bool:
        """True when a frame's result depends on the frames before it (the temporal
        depth filter of the 1D mode)."""
        return self._temporal is not None

    def warm_up(self, references: Sequence[ReferenceView]) -> None:
        """Take in one frame that comes before the first one synthesized.

        Only the temporal state is updated, which costs a small part of a frame's
        synthesis: a run that starts at frame S after ``warm_up`` on frames 0 .. S-1
        synthesizes the bytes of a run from frame 0. Does nothing when
        :attr:`carries_state` is false.

        Parameters
        ----------
        references : sequence of ReferenceView
            As in :meth:`frame`.
        """
        if len(references) != self.reference_count:
            raise ValueError(
                f"expected {self.reference_count} reference views, got {len(references)}"
            )
        if self._temporal is None:
            return
        for index, i in enumerate(self._used):
            view = references[i]
            self._temporal[index].apply(view.z, view.color)

    def frame(self, references: Sequence[ReferenceView]) -> SynthesisResult:
        """Synthesize the virtual view of one frame.

        Parameters
        ----------
        references : sequence of ReferenceView
            One per reference camera, in the constructor's order. Each view used is
            taken once (``references[i]``) and let go once warped: a sequence that
            reads the views on access holds one reference view in memory at a time.

        Returns
        -------
        SynthesisResult
        """
        if len(references) != self.reference_count:
            raise ValueError(
                f"expected {self.reference_count} reference views, got {len(references)}"
            )
        warped = [self._warp(index, references[i]) for index, i in enumerate(self._used)]
        holes = np.logical_and.reduce([view.holes for view in warped])
        options = self.options
        if options.boundary_noise_removal:
            warped = remove_boundary_noise(warped, depth_range=self.depth_range)
        # The warped views are this frame's own: merged into their arrays, and the
        # merged arrays filled in place.
        merged = self._merge(warped)
        del warped
        color, z = fill_holes(
            np.ascontiguousarray(merged.color, dtype=np.float32),
            np.ascontiguousarray(merged.z, dtype=np.float64),
            merged.holes,
            method=options.hole_filling,
            overwrite=True,
        )
        # A reference at the virtual camera already shows its outlines as a camera does.
        if options.edge_softening and not self._reference_at_virtual:
            color = soften_edges(color, z, depth_range=self.depth_range)
        return SynthesisResult(color, z, holes)

    def _warp(self, index: int, view: ReferenceView) -> WarpedView:
        options = self.options
        if options.mode == "general":
            return self._warpers[index].warp(
                view, precision=options.precision, filter=options.filter
            )
        if options.depth_type == 1:
            view = ReferenceView(
                view.camera, view.color, _axis_depth(self._warpers[index].reference_camera, view.z)
            )
        if self._temporal is not None:
            view = ReferenceView(
                view.camera, view.color, self._temporal[index].apply(view.z, view.color)
            )
        return self._warpers[index].warp(
            view,
            precision=options.precision,
            filter=options.filter,
            splatting=options.splatting,
            boundary_growth=options.boundary_growth,
            warp_enhancement=options.warp_enhancement,
            clean_noise=options.clean_noise,
        )

    def _merge(self, warped: list[WarpedView]) -> WarpedView:
        options = self.options
        if len(warped) == 1:
            return warped[0]
        if options.mode == "1d":
            return merge_1d(
                warped[0],
                warped[1],
                weights=tuple(self.weights),
                merging=options.merging,
                depth_threshold=options.depth_threshold,
                hole_count_threshold=options.hole_count_threshold,
                depth_range=self.depth_range,
                out=warped[0],
            )
        return merge_views(
            warped,
            self.weights,
            view_blending=options.view_blending,
            depth_blend_difference=options.depth_blend_difference,
            depth_range=self.depth_range,
            overwrite=True,
        )


def _axis_depth(camera: Camera, world_z: np.ndarray) -> np.ndarray:
    """World z (DepthType 1) -> depth along ``camera``'s axis, for the 1D mode, which
    warps by ``f B / depth``; points behind the camera (or at infinity) become ``inf``,
    which the 1D mode takes as the farthest background."""
    u, v = pixel_grid(world_z.shape[1], world_z.shape[0])
    with np.errstate(divide="ignore", invalid="ignore"):
        depth = depth_along_axis(camera, u, v, world_z, depth_type=1)
    return np.where(np.isfinite(depth) & (depth > 0), depth, np.inf)


def _distinct(cameras: list[Camera]) -> list[int]:
    """Indices of the first of each group of cameras at the same pose with the same K."""
    used: list[int] = []
    for i, camera in enumerate(cameras):
        if not any(same_camera(camera, cameras[j]) for j in used):
            used.append(i)
    return used
