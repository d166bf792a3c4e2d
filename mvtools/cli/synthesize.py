"""``mvtools synthesize``: virtual views from texture and depth, reading VSRS configurations.

The configuration file is read unmodified (:func:`mvtools.cli.configs.load_config`);
``Key=Value`` items and the options derived from the same parameter table override it.
Frames are streamed: one frame of every input is in memory at a time, and every
output is written atomically (nothing appears at an output path unless the whole run
succeeds).
"""

from __future__ import annotations

import contextlib
import dataclasses
import logging
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import click
import numpy as np

from mvtools.cli.configs import (
    LoadedConfig,
    command_line_input,
    load_config,
    video_format_for,
)
from mvtools.cli.options import (
    DEPTH,
    ProgramCommand,
    data_dir_option,
    overrides_argument,
    param_options,
    program,
    transposed_rotation_option,
)
from mvtools.cli.progress import Progress
from mvtools.errors import ConfigError, DataError, UsageError, at_fault
from mvtools.geometry.camera import Camera
from mvtools.geometry.depth import DepthCoding, depth_sign, facing_camera
from mvtools.io.config import (
    COMMAND_LINE,
    ConfigEntry,
    param_entry,
    resolve_output_path,
)
from mvtools.io.guard import check_output
from mvtools.io.yuv import (
    VideoReader,
    YuvFormat,
    frame_from_luma,
    open_video,
    open_writer,
)
from mvtools.params import VsrsParams
from mvtools.synthesis import ReferenceView, SynthesisOptions
from mvtools.synthesis.pipeline import Synthesizer
from mvtools.synthesis.views import FILTERS, HOLE_FILLING
from mvtools.synthesis.working import from_working, to_working, world_z

LOG = logging.getLogger(__name__)

#: Hole filling of ``IvsrsInpaint 1`` (VSRS's default, depth-aware filling from the
#: background side) and when nothing is said: the best background-side method measured
#: on Cones (see the README). ``IvsrsInpaint 0`` is plain inpainting; ``--hole-filling``
#: chooses any method, VSRS's own row rule ("background") included.
DEFAULT_HOLE_FILLING = "background-diffusion"


#: Command-line names of VSRS keys beyond ``--`` + the key in snake case.
_SECONDARY_NAMES = {
    "total_number_of_frames": ("--frames",),
    "output_virtual_view_image_name": ("-o", "--output"),
}


@click.command(name="synthesize", cls=ProgramCommand)
@click.argument("config", type=click.Path(dir_okay=False))
@overrides_argument
@data_dir_option
@click.option(
    "--view",
    "extra_views",
    multiple=True,
    nargs=5,
    type=(str, click.Path(dir_okay=False), click.Path(dir_okay=False), float, float),
    metavar="NAME TEXTURE DEPTH ZNEAR ZFAR",
    help="A further reference view (repeatable): camera NAME of the camera file, "
    "its texture and depth videos and their Znear, Zfar. With the left and "
    "right views of the configuration, or instead of them.",
)
@click.option(
    "--hole-filling",
    type=click.Choice(HOLE_FILLING),
    default=None,
    help=f"How the holes no view saw are filled: background is VSRS's row rule, "
    f"inpaint plain image inpainting (default: {DEFAULT_HOLE_FILLING}, or "
    "inpaint with IvsrsInpaint 0).",
)
@click.option(
    "--output-depth",
    type=click.Path(dir_okay=False),
    default=None,
    help="Also write the virtual view's depth map, in the format of the left depth map "
    "(8-bit 4:2:0 with chroma 128, or as its name says).",
)
@click.option(
    "--output-depth-range",
    nargs=2,
    type=DEPTH,
    default=None,
    metavar="ZNEAR ZFAR",
    help="Znear, Zfar of --output-depth (default: the left view's).",
)
@click.option(
    "--output-holes",
    type=click.Path(dir_okay=False),
    default=None,
    help="Also write the hole mask: 8-bit grey (4:0:0) video, 255 where no view saw the "
    "scene (before hole filling), 0 elsewhere.",
)
@transposed_rotation_option
@param_options(VsrsParams, _SECONDARY_NAMES)
@program
def command(
    config,
    overrides,
    data_dirs,
    extra_views,
    hole_filling,
    output_depth,
    output_depth_range,
    output_holes,
    transposed_rotation,
    **options,
):
    """Synthesize the virtual view that CONFIG describes.

    CONFIG is a VSRS configuration file, read unmodified: the camera parameter file
    (MPEG text, or MPEG-I JSON when its name ends in .json), the left and right texture
    and depth videos, the virtual camera. Key=Value items override the file as on the
    VSRS command line, and the options below override both.

    \b
    Both VSRS modes: general (3D warping, any camera layout) and 1D (rectified
    parallel cameras). One reference (left = right) extrapolates; --view adds
    reference views beyond the two of VSRS (general mode).
    Texture videos: YUV 4:2:0, 8-bit as VSRS, or 10/16-bit when the name says so
    (name_1920x1080_yuv420p10le.yuv); the output has the textures' format.
    Depth videos: 8-bit 4:2:0 (chroma ignored), or 16-bit luma only by name
    (name_1920x1080_gray16le.yuv), each with its own Znear/Zfar.
    Frames: StartFrame, TotalNumberOfFrames (the shortest input limits them,
    with a warning); progress on stderr.

    Exits with 2 for a bad configuration or option, 1 for damaged or inconsistent
    data, leaving no output file.
    """
    loaded = load_config(
        VsrsParams,
        config,
        overrides=overrides,
        options=options,
        data_dirs=data_dirs,
        transposed_rotation=transposed_rotation,
    )
    params = loaded.params
    output = _output_path(loaded)
    extras = [_extra_reference(loaded, view, data_dirs) for view in extra_views]
    references = _config_references(loaded) + extras
    if not references:
        raise ConfigError(
            "no reference view: give LeftCameraName (and RightCameraName) or --view",
            key="LeftCameraName",
        )
    references = _facing(references, params.depth_type)
    virtual = facing_camera(
        _camera(loaded, "virtual_camera_name"),
        references[0].depth_range,
        depth_type=params.depth_type,
    )
    algorithm = synthesis_options(params, hole_filling=hole_filling)
    extra_outputs = {"depth": output_depth, "holes": output_holes}
    outputs = {
        "view": output,
        **{
            name: _command_line_output(f"--output-{name}", path)
            for name, path in extra_outputs.items()
            if path is not None
        },
    }
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
        texture_format = _texture_format(textures)
        frames = loaded.frame_range(textures + depths)
        codings = [
            _depth_coding(
                ref.depth_range, reader.format.bits, ref.depth_key, depth_type=params.depth_type
            )
            for ref, reader in zip(references, depths)
        ]
        depth_range = references[0].depth_range
        with at_fault(ConfigError, path=config):
            synthesizer = Synthesizer(
                virtual,
                [ref.camera for ref in references],
                algorithm,
                size=size,
                depth_range=depth_range,
            )
        depth_output = None
        if "depth" in outputs:
            out_range = tuple(output_depth_range) if output_depth_range else depth_range
            depth_output = _DepthOutput(
                _depth_coding(
                    out_range,
                    depths[0].format.bits,
                    "--output-depth-range",
                    depth_type=params.depth_type,
                ),
                depths[0].format,
                virtual if params.depth_type == 1 else None,
            )
        formats = {
            "view": texture_format.with_(chroma="420"),
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
        loop = _FrameLoop(
            synthesizer,
            [ref.camera for ref in references],
            textures,
            depths,
            codings,
            params.color_space,
            texture_format,
            writers,
            depth_output,
        )
        if synthesizer.carries_state and frames.start:
            # the temporal depth filter carries state from frame 0: a chunk of a longer
            # run takes in the frames before it to give the bytes of the whole run
            LOG.info(
                "taking in frames 0 to %d first (TemporalImprovementOption 1 carries "
                "depth from frame to frame)",
                frames.start - 1,
            )
            warm_up = Progress(frames.start, "frames taken in")
            for index in range(frames.start):
                synthesizer.warm_up(_FrameViews(loop, index))
                warm_up.advance()
        progress = Progress(len(frames), "frames synthesized")
        for index in frames:
            loop.process(index)
            progress.advance()
    LOG.info("wrote %s", ", ".join(str(path) for path in outputs.values()))


@dataclass(frozen=True)
class _DepthOutput:
    """How the virtual depth is written: coding, file format, and the virtual camera
    when the depth maps hold world z (DepthType 1)."""

    coding: DepthCoding
    format: YuvFormat
    world_z_camera: Camera | None


@dataclass
class _FrameLoop:
    """Everything that lives across frames; :meth:`process` does one frame.

    A frame's arrays are locals of :meth:`process`, so they are freed before the next
    frame is read: memory holds one frame, whatever the number of frames. Within a
    frame each reference view is read when the synthesizer takes it and freed once
    warped (:class:`_FrameViews`).
    """

    synthesizer: Synthesizer
    cameras: list[Camera]
    textures: list[VideoReader]
    depths: list[VideoReader]
    codings: list[DepthCoding]
    color_space: int
    texture_format: YuvFormat
    writers: dict
    depth_output: _DepthOutput | None

    def reference(self, view: int, index: int) -> ReferenceView:
        """Frame ``index`` of reference ``view``, in the working space."""
        color = to_working(
            self.textures[view].read(index),
            color_space=self.color_space,
            bits=self.texture_format.bits,
        )
        return ReferenceView(
            self.cameras[view], color, self.codings[view].z(self.depths[view].read(index)[0])
        )

    def process(self, index: int) -> None:
        result = self.synthesizer.frame(_FrameViews(self, index))
        self.writers["view"].write(
            from_working(result.color, color_space=self.color_space, bits=self.texture_format.bits)
        )
        if self.depth_output is not None:
            z = result.z
            camera = self.depth_output.world_z_camera
            if camera is not None:
                z = world_z(camera, z)
            values = self.depth_output.coding.values(z)
            self.writers["depth"].write(frame_from_luma(self.depth_output.format, values))
        if "holes" in self.writers:
            self.writers["holes"].write(np.where(result.holes, np.uint8(255), np.uint8(0)))


@dataclass(frozen=True)
class _FrameViews(Sequence):
    """The reference views of frame ``index``, read from the files on each access."""

    loop: _FrameLoop
    index: int

    def __len__(self) -> int:
        return len(self.loop.cameras)

    def __getitem__(self, view: int) -> ReferenceView:
        return self.loop.reference(view, self.index)


# --------------------------------------------------------------------------- references


@dataclass(frozen=True)
class _Reference:
    """A reference view to open: camera, files, depth range, and the keys that named them."""

    camera: Camera
    texture: Path
    depth: Path
    depth_range: tuple[float, float]
    texture_key: str
    depth_key: str


def _camera(loaded: LoadedConfig, field: str) -> Camera:
    if field not in loaded.cameras:
        raise param_entry(loaded.params, field).error("no camera name given")
    return loaded.cameras[field]


def _config_references(loaded: LoadedConfig) -> list[_Reference]:
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
                raise param_entry(params, field).error(f"no file given for camera {camera.name!r}")
            files.append(loaded.inputs[field])
        depth_range = getattr(params, f"{side}_depth_range") or camera.depth_range
        if depth_range is None:
            raise param_entry(params, f"{side}_nearest_depth_value").error(
                f"the depth range of camera {camera.name!r} is not given ({side.title()}Nearest"
                f"DepthValue and {side.title()}FarthestDepthValue)"
            )
        keys = [
            param_entry(params, field).key
            for field in (f"{side}_view_image_name", f"{side}_depth_map_name")
        ]
        references.append(_Reference(camera, *files, tuple(depth_range), *keys))
    if len(references) == 1 and not params.left_camera_name:
        raise param_entry(params, "left_camera_name").error(
            "RightCameraName is given without LeftCameraName; give one reference view as the left"
        )
    return references


def _extra_reference(loaded: LoadedConfig, view: tuple, data_dirs) -> _Reference:
    name, texture, depth, znear, zfar = view
    label = f"--view {name}"
    camera = loaded.command_line_camera(name, label)
    _depth_coding((znear, zfar), 8, label, depth_type=loaded.params.depth_type)
    paths = [command_line_input(label, value, data_dirs) for value in (texture, depth)]
    return _Reference(camera, *paths, (znear, zfar), label, label)


def _facing(references: list[_Reference], depth_type: int) -> list[_Reference]:
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
        raise param_entry(loaded.params, "output_virtual_view_image_name").error(
            "no output file given", UsageError
        )
    return loaded.outputs["output_virtual_view_image_name"]


def _command_line_output(option: str, value: str) -> Path:
    return resolve_output_path(ConfigEntry(option, value, COMMAND_LINE, None))


def _open(path: Path, size: tuple[int, int], key: str) -> VideoReader:
    """An input video of the configured size (8-bit 4:2:0 unless its name says otherwise)."""
    fmt = video_format_for(path, size, key=key)
    return open_video(path, fmt)


def _texture_format(readers: list[VideoReader]) -> YuvFormat:
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


# --------------------------------------------------------------------------- conversions


def _depth_coding(depth_range, bits: int, key: str, *, depth_type: int) -> DepthCoding:
    with at_fault(UsageError, key=key):
        return DepthCoding(depth_range, bits, depth_type=depth_type)


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
