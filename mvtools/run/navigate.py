"""Free-viewpoint video from multiview video plus depth: the run functions of ``mvtools
navigate``.

An output *stream* is the camera of each output frame: a camera path (a pose trace, or
keyframes interpolated, :func:`mvtools.geometry.pose.camera_path`), the two eyes of
each of its poses (:func:`mvtools.geometry.pose.eye_cameras`), or the still cameras of
dense views between those of an array. :func:`navigate_video` renders any number of
streams from opened readers into writers, or packed into one video (side by side, top
and bottom, a grid: :mod:`mvtools.pack`); :func:`navigate_files` opens the files first.
Output frame ``k`` reads input frame ``input_frames[k]``: all 0 for static content,
``k`` for video. Each input frame is decoded once, however many outputs it serves.
"""

from __future__ import annotations

import contextlib
import logging
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

from mvtools.errors import DataError, UsageError, at_fault
from mvtools.geometry.camera import Camera
from mvtools.io.guard import check_outputs
from mvtools.io.inputs import open_input_video
from mvtools.pack.layout import Layout, plan_layout
from mvtools.run.stream import ProgressCallback, stream_frames
from mvtools.run.synthesize import ReferenceFiles, ReferenceVideo, depth_coding, texture_format
from mvtools.synthesis.views import ReferenceView, SynthesisOptions

LOG = logging.getLogger(__name__)

__all__ = [
    "STREAM_LAYOUTS",
    "NavigationOptions",
    "frames_after",
    "navigate_files",
    "navigate_video",
    "output_streams",
    "stream_layout",
]

#: How several output streams share one video (:func:`mvtools.pack.plan_layout`).
STREAM_LAYOUTS = ("side-by-side", "top-bottom", "grid")


@dataclass(frozen=True)
class NavigationOptions:
    """What renders each virtual view.

    Attributes
    ----------
    synthesis : SynthesisOptions
        The view synthesis; the general mode serves any pose, the 1D mode poses on the
        line of a rectified array.
    views_per_frame : int or None
        Reference views serving each virtual view, the nearest that look its way
        (:func:`mvtools.synthesis.navigation.serving_views`); None: all of them.
    max_angle : float
        Degrees between optical axes beyond which a reference does not serve.
    """

    synthesis: SynthesisOptions = field(default_factory=SynthesisOptions)
    views_per_frame: int | None = None
    max_angle: float = 60.0


def stream_layout(count: int, size: tuple[int, int], kind: str) -> Layout:
    """Where each of ``count`` streams of ``size`` goes in one packed video of ``kind``
    (one of :data:`STREAM_LAYOUTS`)."""
    return plan_layout([(f"stream{j}", size) for j in range(count)], layout=kind, block=2)


class _DecodedViews(Sequence):
    """The reference views of one input frame in the working space, each decoded when a
    stream first takes it and kept for the other streams of the frame."""

    def __init__(self, references: Sequence[ReferenceVideo], bits: int, color_space: int):
        self.references = references
        self.bits = bits
        self.color_space = color_space
        self.frame = None
        self._views: dict[int, ReferenceView] = {}

    def at(self, frame: int) -> _DecodedViews:
        if frame != self.frame:
            self.frame = frame
            self._views = {}
        return self

    def __len__(self) -> int:
        return len(self.references)

    def __getitem__(self, index: int) -> ReferenceView:
        from mvtools.synthesis.working import to_working

        if index not in self._views:
            ref = self.references[index]
            color = to_working(
                ref.texture.read(self.frame), color_space=self.color_space, bits=self.bits
            )
            self._views[index] = ReferenceView(
                ref.camera, color, ref.coding.z(ref.depth.read(self.frame)[0])
            )
        return self._views[index]


def navigate_video(
    references: Sequence[ReferenceVideo],
    streams: Sequence[Sequence[Camera]],
    options: NavigationOptions,
    *,
    outputs: Sequence,
    input_frames: Sequence[int],
    layout: Layout | None = None,
    color_space: int = 0,
    progress: ProgressCallback | None = None,
) -> None:
    """Render every output frame of every stream and write it.

    Parameters
    ----------
    references : sequence of ReferenceVideo
        All the reference views (textures of one size and bit depth), facing the scene.
    streams : sequence of sequence of Camera
        ``streams[j][k]``: the camera of stream ``j`` at output frame ``k``; every
        stream has ``len(input_frames)`` cameras.
    options : NavigationOptions
    outputs : sequence of writer
        One per stream (objects with ``write(planes)``), or one that gets the packed
        frames when ``layout`` is given.
    input_frames : sequence of int
        The input frame each output frame is rendered from.
    layout : Layout, optional
        Packs the streams' views into one frame (:func:`stream_layout`).
    color_space : {0, 1}
        VSRS ColorSpace of the synthesis: YUV (0) or RGB (1).
    progress : callable, optional
        ``progress(done, total)`` after each output frame.

    Raises
    ------
    DataError
        An input frame past the end of a reference video.
    ValueError
        Cameras or options the renderer cannot use.
    """
    from mvtools.pack.frames import pack_frame
    from mvtools.synthesis.navigation import ViewRenderer
    from mvtools.synthesis.working import from_working

    if not streams:
        raise ValueError("no output stream")
    frame_count = len(input_frames)
    for j, stream in enumerate(streams):
        if len(stream) != frame_count:
            raise ValueError(f"stream {j} has {len(stream)} cameras for {frame_count} frames")
    expected = 1 if layout is not None else len(streams)
    if len(outputs) != expected:
        raise ValueError(f"{expected} writers needed, got {len(outputs)}")
    videos = [ref.texture for ref in references] + [ref.depth for ref in references]
    available = min(len(video) for video in videos)
    past = [k for k, frame in enumerate(input_frames) if frame >= available]
    if past:
        shortest = min(videos, key=len)
        raise DataError(
            f"output frame {past[0]} reads input frame {input_frames[past[0]]}, but the video "
            f"has {available} frames (still content reads one frame for every output frame)",
            path=getattr(shortest, "path", None),
        )
    textures = [ref.texture for ref in references]
    bits = texture_format(textures).bits
    size = textures[0].format.size
    renderer = ViewRenderer(
        [ref.camera for ref in references],
        options.synthesis,
        size=size,
        depth_range=references[0].coding.depth_range,
        count=options.views_per_frame,
        max_angle=options.max_angle,
    )
    decoded = _DecodedViews(references, bits, color_space)
    chroma = outputs[0].format.chroma

    def render(index: int) -> list:
        references = decoded.at(input_frames[index])
        # each view leaves the working space at once: one stream's arrays at a time
        views = [
            from_working(
                renderer.render(references, j, stream[index]).color,
                color_space=color_space,
                bits=bits,
            )
            for j, stream in enumerate(streams)
        ]
        if layout is None:
            return views
        packed = {(f"stream{j}", "texture"): planes for j, planes in enumerate(views)}
        return [pack_frame(layout, packed, chroma=chroma, bits=bits)]

    LOG.info(
        "rendering %d stream%s of %d frame%s from %s (%s mode, Precision %d)",
        len(streams),
        "s" * (len(streams) != 1),
        frame_count,
        "s" * (frame_count != 1),
        ", ".join(ref.camera.name for ref in references),
        options.synthesis.mode,
        options.synthesis.precision,
    )
    stream_frames(range(frame_count), render, writers=list(outputs), progress=progress)


def frames_after(
    references: Sequence[ReferenceFiles], start: int, *, size: tuple[int, int] | None = None
) -> int:
    """Frames of the shortest of the reference videos from frame ``start`` on (the output
    frames of dense views of video).

    Raises
    ------
    UsageError
        ``start`` is past the end of the shortest video (``--start-frame``).
    """
    lengths = []
    for ref in references:
        for path in (ref.texture, ref.depth):
            with open_input_video(path, size, None) as video:
                lengths.append(len(video))
    if min(lengths) <= start:
        raise UsageError(
            f"is past the end of the shortest input ({min(lengths)} frames)", key="--start-frame"
        )
    return min(lengths) - start


def navigate_files(
    references: Sequence[ReferenceFiles],
    streams: Sequence[Sequence[Camera]],
    options: NavigationOptions,
    *,
    outputs: Sequence[str | Path],
    input_frames: Sequence[int],
    layout: str | None = None,
    size: tuple[int, int] | None = None,
    frame_rate=None,
    progress: ProgressCallback | None = None,
) -> list[Path]:
    """Open the reference videos and the outputs, and :func:`navigate_video`.

    Parameters
    ----------
    references : sequence of ReferenceFiles
        Cameras facing the scene, texture and depth files, depth ranges, and the
        options that named them (for messages).
    streams, options, input_frames
        As :func:`navigate_video`.
    outputs : sequence of path
        One file per stream, or one when ``layout`` packs them: raw YUV (sizes and
        formats in the name or as the inputs), Y4M (``.y4m``, ``-`` for standard
        output) or MP4 (``.mp4``, through ffmpeg). Written atomically.
    layout : {"side-by-side", "top-bottom", "grid"}, optional
    size : (width, height), optional
        Of raw YUV inputs whose names do not say it.
    frame_rate : optional
        Of Y4M and MP4 outputs.

    Returns
    -------
    list of Path
        The files written.
    """
    from mvtools.io.encoders import open_video_output

    if not references:
        raise UsageError("no reference view: give --view NAME VIDEO and --depth NAME VIDEO")
    outputs = [Path(path) for path in outputs]
    with contextlib.ExitStack() as stack:
        textures = [
            stack.enter_context(open_input_video(ref.texture, size, None)) for ref in references
        ]
        depths = [
            stack.enter_context(open_input_video(ref.depth, textures[0].format.size, None))
            for ref in references
        ]
        for video in textures + depths:
            if video.format.size != textures[0].format.size:
                raise DataError(
                    f"{video.format.width}x{video.format.height}, but the first view is "
                    f"{textures[0].format.width}x{textures[0].format.height}",
                    path=video.path,
                )
        check_outputs((path, "output") for path in outputs)
        videos = [
            ReferenceVideo(
                ref.camera,
                texture,
                depth,
                depth_coding(ref.depth_range, depth.format.bits, ref.depth_key, depth_type=0),
            )
            for ref, texture, depth in zip(references, textures, depths)
        ]
        view_format = texture_format(textures).with_(chroma="420")
        packing = None
        if layout is not None:
            packing = stream_layout(len(streams), view_format.size, layout)
            view_format = view_format.with_(width=packing.width, height=packing.height)
        writers = [
            stack.enter_context(open_video_output(path, view_format, frame_rate=frame_rate))
            for path in outputs
        ]
        with at_fault(UsageError):
            navigate_video(
                videos,
                streams,
                options,
                outputs=writers,
                input_frames=input_frames,
                layout=packing,
                progress=progress,
            )
    return outputs


def output_streams(
    poses: Sequence[Camera], *, stereo: float | None = None, dense_frames: int | None = None
) -> tuple[list[str], list[list[Camera]]]:
    """The output streams of a camera path: their names and the camera of each frame.

    Parameters
    ----------
    poses : sequence of Camera
        The path's cameras, one per output frame; with ``dense_frames``, the still
        cameras of dense views.
    stereo : float, optional
        Interpupillary distance (in the camera file's units): a ``left`` and a
        ``right`` stream of eyes at each pose (:func:`mvtools.geometry.pose.eye_cameras`).
    dense_frames : int, optional
        Each pose is the still camera of a stream of its own (named by its index,
        ``00``, ``01`` ...) over this many output frames.

    Returns
    -------
    (names, streams)
        ``streams[j][k]``: the camera of stream ``j`` at output frame ``k``.
    """
    from mvtools.geometry.pose import eye_cameras

    if dense_frames is not None:
        names = [f"{index:02d}" for index in range(len(poses))]
        streams = [[camera] * dense_frames for camera in poses]
    else:
        names, streams = ["view"], [list(poses)]
    if stereo is None:
        return names, streams
    eyed_names, eyed = [], []
    for name, stream in zip(names, streams):
        pairs = [eye_cameras(camera, stereo) for camera in stream]
        for side, label in enumerate(("left", "right")):
            eyed_names.append(label if name == "view" else f"{name}_{label}")
            eyed.append([pair[side] for pair in pairs])
    return eyed_names, eyed
