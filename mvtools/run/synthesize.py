"""Virtual-view videos from texture and depth videos: the run functions of ``mvtools
synthesize``.

:func:`synthesize_video` takes opened readers and writers; :func:`synthesize_config`
synthesizes the video a VSRS configuration describes in one call, and
:func:`synthesize_loaded` does so for a configuration already loaded, with the
program's further views and outputs. The depth-image-based rendering itself is
:class:`mvtools.synthesis.pipeline.Synthesizer`, imported when a run starts, so this
module is cheap to import.
"""

from __future__ import annotations

import contextlib
import dataclasses
import logging
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from mvtools.errors import ConfigError, DataError, UsageError, at_fault
from mvtools.geometry.camera import Camera
from mvtools.geometry.depth import DepthCoding, depth_sign, facing_camera
from mvtools.io.guard import check_output
from mvtools.io.loaded_config import LoadedConfig, load_config, video_format_for
from mvtools.io.yuv import VideoReader, YuvFormat, frame_from_luma, open_video, open_writer
from mvtools.params import VsrsParams
from mvtools.run.stream import ProgressCallback, stream_frames
from mvtools.synthesis.views import (
    DEFAULT_HOLE_FILLING,
    FILTERS,
    ReferenceView,
    SynthesisOptions,
)
from mvtools.synthesis.working import from_working, to_working, world_z

LOG = logging.getLogger(__name__)


@dataclass(frozen=True)
class ReferenceVideo:
    """One reference view to synthesize from: its camera, videos and depth coding.

    Attributes
    ----------
    camera : Camera
        Facing the scene (:func:`mvtools.geometry.depth.facing_camera`).
    texture, depth : VideoReader
        Or any object with ``format`` (:class:`mvtools.io.yuv.YuvFormat`), ``path``
        (named in error messages), ``len()`` and ``read(index)`` giving a frame's planes.
    coding : DepthCoding
        How the depth video's samples give depths.
    """

    camera: Camera
    texture: VideoReader
    depth: VideoReader
    coding: DepthCoding


def synthesize_video(
    references: Sequence[ReferenceVideo],
    virtual: Camera,
    options: SynthesisOptions,
    *,
    view,
    depth=None,
    depth_coding: DepthCoding | None = None,
    holes=None,
    frames: range | None = None,
    color_space: int = 0,
    progress: ProgressCallback | None = None,
    warm_up_progress: ProgressCallback | None = None,
) -> None:
    """Synthesize the virtual view of every frame of ``frames`` and write it.

    One frame is in memory at a time, and within a frame one reference view: each is
    read when the synthesizer takes it and let go once warped. With the temporal depth
    filter of the 1D mode (``options.temporal_improvement``), whose frames depend on
    the frames before them, frames 0 to ``frames.start - 1`` are taken in first, so a
    chunk of a run gives the bytes of the whole run.

    Parameters
    ----------
    references : sequence of ReferenceVideo
        The textures share their bit depth and size, the size of the virtual view.
    virtual : Camera
        The virtual camera, facing the scene.
    options : SynthesisOptions
    view : writer
        Gets the virtual view, YUV 4:2:0 of the textures' bit depth (an object with
        ``write(planes)``, as :class:`mvtools.io.yuv.VideoWriter`).
    depth : writer, optional
        Gets the virtual view's depth map in the format of the first reference's
        depth video, coded by ``depth_coding`` (default: the first reference's coding);
        world z when ``options.depth_type`` is 1.
    holes : writer, optional
        Gets the hole mask, one 8-bit plane: 255 where no view saw the scene (before
        hole filling), 0 elsewhere.
    frames : range, optional
        Frames to synthesize; default every frame all the inputs have.
    color_space : {0, 1}
        VSRS ColorSpace: synthesis in YUV 4:4:4 (0) or RGB (1).
    progress, warm_up_progress : callable, optional
        ``progress(done, total)`` after each frame synthesized, and after each frame
        taken in before ``frames.start``.

    Raises
    ------
    DataError
        A grey texture, or textures of different bit depths.
    ValueError
        Options or cameras the synthesizer cannot use (:class:`Synthesizer
        <mvtools.synthesis.pipeline.Synthesizer>`).
    """
    from mvtools.synthesis.pipeline import Synthesizer

    textures = [ref.texture for ref in references]
    depths = [ref.depth for ref in references]
    bits = texture_format(textures).bits
    if frames is None:
        frames = range(min(len(reader) for reader in textures + depths))
    cameras = [ref.camera for ref in references]
    synthesizer = Synthesizer(
        virtual,
        cameras,
        options,
        size=textures[0].format.size,
        depth_range=references[0].coding.depth_range,
    )
    depth_format = depths[0].format
    depth_coding = depth_coding or references[0].coding
    world_z_camera = virtual if options.depth_type == 1 else None

    def views(index: int) -> _FrameViews:
        return _FrameViews(references, index, color_space=color_space, bits=bits)

    def synthesize(index: int) -> list:
        result = synthesizer.frame(views(index))
        written = [from_working(result.color, color_space=color_space, bits=bits)]
        if depth is not None:
            z = result.z if world_z_camera is None else world_z(world_z_camera, result.z)
            written.append(frame_from_luma(depth_format, depth_coding.values(z)))
        if holes is not None:
            written.append(np.where(result.holes, np.uint8(255), np.uint8(0)))
        return written

    if synthesizer.carries_state and frames.start:
        LOG.info(
            "taking in frames 0 to %d first (TemporalImprovementOption 1 carries "
            "depth from frame to frame)",
            frames.start - 1,
        )
        stream_frames(
            range(frames.start),
            lambda index: synthesizer.warm_up(views(index)),
            progress=warm_up_progress,
        )
    writers = [writer for writer in (view, depth, holes) if writer is not None]
    stream_frames(frames, synthesize, writers=writers, progress=progress)


@dataclass(frozen=True)
class _FrameViews(Sequence):
    """The reference views of frame ``frame`` in the working space, read from the
    videos on each access (the synthesizer takes each once)."""

    references: Sequence[ReferenceVideo]
    frame: int
    color_space: int
    bits: int

    def __len__(self) -> int:
        return len(self.references)

    def __getitem__(self, view: int) -> ReferenceView:
        ref = self.references[view]
        color = to_working(
            ref.texture.read(self.frame), color_space=self.color_space, bits=self.bits
        )
        return ReferenceView(ref.camera, color, ref.coding.z(ref.depth.read(self.frame)[0]))


def texture_format(readers: Sequence[VideoReader]) -> YuvFormat:
    """The format the texture videos share (the virtual view's but for its chroma).

    Raises
    ------
    DataError
        A grey (4:0:0) texture, or textures of different bit depths.
    """
    for reader in readers:
        if reader.format.chroma == "400":
            raise DataError(
                "a texture needs colour planes, this video is grey (4:0:0)", path=reader.path
            )
    bits = {reader.format.bits for reader in readers}
    if len(bits) > 1:
        formats = ", ".join(f"{reader.path} is {reader.format.pix_fmt}" for reader in readers)
        raise DataError(f"the textures differ in bit depth ({formats})")
    return readers[0].format


def synthesis_options(params: VsrsParams, *, hole_filling: str | None = None) -> SynthesisOptions:
    """The algorithm options that VSRS parameters ask for.

    Parameters
    ----------
    params : VsrsParams
    hole_filling : str, optional
        A method of :data:`mvtools.synthesis.views.HOLE_FILLING`; default
        :data:`DEFAULT_HOLE_FILLING`, or ``"inpaint"`` with ``IvsrsInpaint 0``.
    """
    if hole_filling is None:
        hole_filling = "inpaint" if params.ivsrs_inpaint == 0 else DEFAULT_HOLE_FILLING
    return SynthesisOptions(
        mode="1d" if params.synthesis_mode == 1 else "general",
        precision=params.precision,
        filter=FILTERS[params.filter],
        depth_type=params.depth_type,
        view_blending=bool(params.view_blending),
        depth_blend_difference=float(params.depth_blend_difference),
        hole_filling=hole_filling,
        boundary_noise_removal=bool(params.boundary_noise_removal),
        splatting=params.splatting_option,
        boundary_growth=params.boundary_growth,
        merging=params.merging_option,
        depth_threshold=params.depth_threshold,
        hole_count_threshold=params.hole_count_threshold,
        temporal_improvement=bool(params.temporal_improvement_option),
        warp_enhancement=bool(params.warp_enhancement_option),
        clean_noise=bool(params.clean_noise_option),
    )


# --------------------------------------------------------------------------- configurations


@dataclass(frozen=True)
class ReferenceFiles:
    """A reference view to open: camera, files, depth range, and the keys (or options)
    that named them, for error messages."""

    camera: Camera
    texture: Path
    depth: Path
    depth_range: tuple[float, float]
    texture_key: str
    depth_key: str


def synthesize_config(
    config: str | os.PathLike,
    *,
    overrides: Mapping[str, Any] | None = None,
    data_dirs: Sequence[str | os.PathLike] = (),
    output: str | os.PathLike | None = None,
    progress: ProgressCallback | None = None,
) -> Path:
    """Synthesize the virtual video a VSRS configuration describes, as ``mvtools
    synthesize CONFIG`` does.

    Parameters
    ----------
    config : path
        A VSRS configuration file, read unmodified.
    overrides : mapping, optional
        Parameters that replace the file's, by :class:`mvtools.params.VsrsParams`
        field name (``{"left_view_image_name": path, "start_frame": 0}``), as the
        program's options give them.
    data_dirs : sequence of path
        Further folders where the input files are looked for.
    output : path, optional
        The virtual view's file (default: the configuration's
        ``OutputVirtualViewImageName``).
    progress : callable, optional
        ``progress(done, total)`` after each frame.

    Returns
    -------
    Path
        The virtual view's file.

    Raises
    ------
    UsageError, ConfigError, DataError
        As the program: a bad configuration or parameter, damaged or inconsistent data.
        Nothing is written then.
    """
    options = dict(overrides or {})
    if output is not None:
        options["output_virtual_view_image_name"] = os.fspath(output)
    loaded = load_config(VsrsParams, config, options=options, data_dirs=data_dirs)
    return synthesize_loaded(loaded, config_path=Path(config), progress=progress)["view"]


def synthesize_loaded(
    loaded: LoadedConfig,
    *,
    config_path: Path,
    extra_references: Sequence[ReferenceFiles] = (),
    hole_filling: str | None = None,
    output_depth: Path | None = None,
    output_depth_range: tuple[float, float] | None = None,
    output_holes: Path | None = None,
    progress: ProgressCallback | None = None,
    warm_up_progress: ProgressCallback | None = None,
) -> dict[str, Path]:
    """Synthesize the virtual video of a loaded VSRS configuration
    (:func:`mvtools.io.loaded_config.load_config`), from its left and right views and
    ``extra_references``.

    Every input is opened before any output, and no output may name an input; the
    outputs are written atomically (nothing appears unless the whole run succeeds).

    Parameters
    ----------
    loaded : LoadedConfig
        Of :class:`mvtools.params.VsrsParams`.
    config_path : Path
        The configuration file, named in the errors of its cameras.
    extra_references : sequence of ReferenceFiles
        Reference views beyond the configuration's.
    hole_filling : str, optional
        As :func:`synthesis_options`.
    output_depth, output_holes : Path, optional
        Also write the virtual depth map (coded with ``output_depth_range``, default
        the first reference's) and the hole mask (see :func:`synthesize_video`).
    progress, warm_up_progress : callable, optional
        As :func:`synthesize_video`.

    Returns
    -------
    dict of str to Path
        The files written: ``"view"``, and ``"depth"``, ``"holes"`` when asked for.
    """
    params = loaded.params
    outputs = {"view": _output_path(loaded), "depth": output_depth, "holes": output_holes}
    outputs = {name: path for name, path in outputs.items() if path is not None}
    references = _config_references(loaded) + list(extra_references)
    if not references:
        raise ConfigError(
            "no reference view: give LeftCameraName (and RightCameraName) or --view",
            key="LeftCameraName",
        )
    references = facing_references(references, params.depth_type)
    if "virtual_camera_name" not in loaded.cameras:
        raise loaded.entry("virtual_camera_name").error("no camera name given")
    virtual = facing_camera(
        loaded.cameras["virtual_camera_name"],
        references[0].depth_range,
        depth_type=params.depth_type,
    )
    algorithm = synthesis_options(params, hole_filling=hole_filling)
    size = (params.source_width, params.source_height)
    with contextlib.ExitStack() as stack:
        textures = [
            stack.enter_context(_open(ref.texture, size, ref.texture_key)) for ref in references
        ]
        depths = [stack.enter_context(_open(ref.depth, size, ref.depth_key)) for ref in references]
        # Every input is now open, so the run's guard knows it: an output that names
        # one is refused before any work (two outputs of one name when they open).
        for path in outputs.values():
            check_output(path)
        view_format = texture_format(textures).with_(chroma="420")
        frames = loaded.frame_range(textures + depths)
        videos = [
            ReferenceVideo(
                ref.camera,
                texture,
                depth,
                depth_coding(
                    ref.depth_range, depth.format.bits, ref.depth_key, depth_type=params.depth_type
                ),
            )
            for ref, texture, depth in zip(references, textures, depths)
        ]
        coding = None
        if output_depth is not None and output_depth_range is not None:
            coding = depth_coding(
                output_depth_range,
                depths[0].format.bits,
                "--output-depth-range",
                depth_type=params.depth_type,
            )
        formats = {
            "view": view_format,
            "depth": depths[0].format,
            "holes": YuvFormat(*size, chroma="400"),
        }
        writers = {
            name: stack.enter_context(open_writer(path, formats[name]))
            for name, path in outputs.items()
        }
        LOG.info(
            "synthesizing %s from %s (%s mode, Precision %d), %d frame%s from frame %d",
            virtual.name,
            ", ".join(ref.camera.name for ref in references),
            algorithm.mode,
            algorithm.precision,
            len(frames),
            "s" if len(frames) != 1 else "",
            frames.start,
        )
        with at_fault(ConfigError, path=config_path):
            synthesize_video(
                videos,
                virtual,
                algorithm,
                view=writers["view"],
                depth=writers.get("depth"),
                depth_coding=coding,
                holes=writers.get("holes"),
                frames=frames,
                color_space=params.color_space,
                progress=progress,
                warm_up_progress=warm_up_progress,
            )
    return outputs


def depth_coding(depth_range, bits: int, key: str, *, depth_type: int) -> DepthCoding:
    """:class:`DepthCoding` whose bad range is the fault of ``key`` (a UsageError)."""
    with at_fault(UsageError, key=key):
        return DepthCoding(depth_range, bits, depth_type=depth_type)


def _config_references(loaded: LoadedConfig) -> list[ReferenceFiles]:
    """The left and right views of the configuration that name a camera (none, one or two)."""
    params = loaded.params
    references = []
    for side in ("left", "right"):
        if not getattr(params, f"{side}_camera_name"):
            continue
        camera = loaded.cameras[f"{side}_camera_name"]
        files = []
        for field in (f"{side}_view_image_name", f"{side}_depth_map_name"):
            if field not in loaded.inputs:
                raise loaded.entry(field).error(f"no file given for camera {camera.name!r}")
            files.append(loaded.inputs[field])
        depth_range = getattr(params, f"{side}_depth_range") or camera.depth_range
        if depth_range is None:
            raise loaded.entry(f"{side}_nearest_depth_value").error(
                f"the depth range of camera {camera.name!r} is not given ({side.title()}Nearest"
                f"DepthValue and {side.title()}FarthestDepthValue)"
            )
        keys = [
            loaded.entry(field).key
            for field in (f"{side}_view_image_name", f"{side}_depth_map_name")
        ]
        references.append(ReferenceFiles(camera, *files, tuple(depth_range), *keys))
    if len(references) == 1 and not params.left_camera_name:
        raise loaded.entry("left_camera_name").error(
            "RightCameraName is given without LeftCameraName; give one reference view as the left"
        )
    return references


def facing_references(references: list[ReferenceFiles], depth_type: int) -> list[ReferenceFiles]:
    """The references with cameras that face their depth ranges (one side of the scene)."""
    if depth_type == 0:
        sign = depth_sign(*references[0].depth_range)
        for ref in references[1:]:
            if depth_sign(*ref.depth_range) != sign:
                raise UsageError(
                    f"depth range {ref.depth_range[0]:g} {ref.depth_range[1]:g} "
                    f"has the other sign than {references[0].camera.name!r}'s: "
                    "the views would put the scene on opposite sides of their "
                    "cameras",
                    key=ref.depth_key,
                )
    return [
        dataclasses.replace(
            ref, camera=facing_camera(ref.camera, ref.depth_range, depth_type=depth_type)
        )
        for ref in references
    ]


def _output_path(loaded: LoadedConfig) -> Path:
    if "output_virtual_view_image_name" not in loaded.outputs:
        raise loaded.entry("output_virtual_view_image_name").error(
            "no output file given", UsageError
        )
    return loaded.outputs["output_virtual_view_image_name"]


def _open(path: Path, size: tuple[int, int], key: str) -> VideoReader:
    """An input video of the configured size (8-bit 4:2:0 unless its name says otherwise)."""
    return open_video(path, video_format_for(path, size, key=key))
