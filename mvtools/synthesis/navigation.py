"""Free navigation: the views of any number of virtual cameras from N reference views.

What multiview video is for (the chapter "Multiview video: acquisition, processing,
compression, and virtual view rendering", sections 1.1 to 1.1.5): a viewpoint that moves
through the scene, the two eyes of a headset, the dozens of adjacent views of a light-field
display. Each virtual camera is served by the reference cameras that look the same way
(:func:`serving_views`), nearest first; they are warped into it, merged as
:func:`mvtools.synthesis.blend.merge_views` does (the chapter's eq. 1.20 over the two
nearest views, where their depths agree; the farther views fill what those two do not
see) and the rest is filled (:class:`mvtools.synthesis.pipeline.Synthesizer`).

:class:`ViewRenderer` renders several output streams (two eyes, N dense views) one after
the other, each frame from one set of decoded reference views: a reference is decoded once
per input frame however many outputs it serves.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from mvtools.geometry.camera import Camera, same_camera
from mvtools.synthesis.general import ZBuffers
from mvtools.synthesis.pipeline import Synthesizer
from mvtools.synthesis.views import ReferenceView, SynthesisOptions, SynthesisResult

__all__ = ["DEFAULT_MAX_ANGLE", "ViewRenderer", "serving_views"]

#: Reference cameras whose optical axis turns from the virtual camera's by more than
#: this (degrees) do not serve it: they see the scene from another side.
DEFAULT_MAX_ANGLE = 60.0


def serving_views(
    virtual: Camera,
    cameras: Sequence[Camera],
    *,
    count: int | None = None,
    max_angle: float = DEFAULT_MAX_ANGLE,
) -> list[int]:
    """The reference cameras that serve ``virtual``, nearest first.

    A camera serves when its optical axis is within ``max_angle`` degrees of the virtual
    camera's; of those the ``count`` nearest (by centre distance; on equal distances the
    first given) are taken.

    Parameters
    ----------
    virtual : Camera
    cameras : sequence of Camera
    count : int, optional
        At most this many (default: every camera that serves).
    max_angle : float
        Degrees, in (0, 180].

    Returns
    -------
    list of int
        Indices into ``cameras``, nearest first; empty when no camera looks the same way.

    Examples
    --------
    >>> import numpy as np
    >>> from mvtools.geometry.camera import Camera
    >>> K = np.diag([100.0, 100.0, 1.0])
    >>> rig = [Camera(f"cam{i}", K, t=[0.1 * i, 0.0, 0.0]) for i in range(5)]
    >>> serving_views(Camera("v", K, t=[0.32, 0.0, 0.0]), rig, count=2)
    [3, 4]
    """
    if count is not None and count < 1:
        raise ValueError(f"count must be at least 1, got {count}")
    if not 0 < max_angle <= 180:
        raise ValueError(f"max_angle must be in (0, 180] degrees, got {max_angle}")
    cos_limit = np.cos(np.radians(max_angle))
    axis = virtual.optical_axis
    distances = [float(np.linalg.norm(camera.t - virtual.t)) for camera in cameras]
    facing = [
        index
        for index, camera in enumerate(cameras)
        if float(camera.optical_axis @ axis) >= cos_limit - 1e-12
    ]
    facing.sort(key=lambda index: distances[index])  # stable: ties keep the given order
    return facing if count is None else facing[:count]


class ViewRenderer:
    """Renders output streams of virtual views from N reference views, frame after frame.

    Each output stream has its own :class:`~mvtools.synthesis.pipeline.Synthesizer`,
    kept while the stream's camera stays where it is (a dense view, or a still camera of
    a path: the 1D mode's temporal depth filter goes on from frame to frame) and built
    anew when the camera moves.

    Parameters
    ----------
    reference_cameras : sequence of Camera
        All the reference cameras, facing the scene.
    options : SynthesisOptions
        The general mode serves any camera; the 1D mode takes one or two views on the
        reference cameras' line (``count`` at most 2).
    size : (width, height)
        Size of the virtual views.
    depth_range : (znear, zfar)
        The common range of the depth comparisons (see :class:`Synthesizer`).
    count : int, optional
        Views that serve each virtual camera, at most (default: all that look its way).
    max_angle : float
        See :func:`serving_views`.
    """

    def __init__(
        self,
        reference_cameras: Sequence[Camera],
        options: SynthesisOptions,
        *,
        size: tuple[int, int],
        depth_range: tuple[float, float],
        count: int | None = None,
        max_angle: float = DEFAULT_MAX_ANGLE,
    ):
        self.reference_cameras = list(reference_cameras)
        if not self.reference_cameras:
            raise ValueError("need at least one reference camera")
        if options.mode == "1d" and (count is None or count > 2):
            count = 2
        self.options = options
        self.size = size
        self.depth_range = depth_range
        self.count = count
        self.max_angle = max_angle
        self._streams: dict[int, tuple[Camera, list[int], Synthesizer]] = {}
        # the streams are rendered one after the other: one set of z-buffers serves all
        self._z_buffers = ZBuffers()

    def serving(self, virtual: Camera) -> list[int]:
        """Indices of the reference cameras that serve ``virtual`` (raises ValueError
        when none does)."""
        used = serving_views(
            virtual, self.reference_cameras, count=self.count, max_angle=self.max_angle
        )
        if not used:
            raise ValueError(
                f"no reference camera looks within {self.max_angle:g} degrees of the "
                f"direction of camera {virtual.name!r}"
            )
        # the 1D mode takes its two views left first, in the order given
        return sorted(used) if self.options.mode == "1d" else used

    def render(
        self, references: Sequence[ReferenceView], stream: int, virtual: Camera
    ) -> SynthesisResult:
        """The virtual view of output stream ``stream`` at this frame.

        Parameters
        ----------
        references : sequence of ReferenceView
            One per reference camera, in the constructor's order; each is taken only
            when a stream uses it (a lazy sequence decodes only those).
        stream : int
            Which output stream (a camera that stays put keeps its synthesizer).
        virtual : Camera
            The stream's camera at this frame.

        Returns
        -------
        SynthesisResult
        """
        kept = self._streams.get(stream)
        if kept is None or not same_camera(kept[0], virtual):
            used = self.serving(virtual)
            synthesizer = Synthesizer(
                virtual,
                [self.reference_cameras[i] for i in used],
                self.options,
                size=self.size,
                depth_range=self.depth_range,
                z_buffers=self._z_buffers,
            )
            kept = self._streams[stream] = (virtual, used, synthesizer)
        _, used, synthesizer = kept
        return synthesizer.frame([references[i] for i in used])
