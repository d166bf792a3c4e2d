"""Loading a VSRS or DERS configuration the same way in every program and in the library.

The configuration file, then ``Key=Value`` items, then command-line options (which
are derived from the same parameter table) make the parameters; the input files
they name are then found and the cameras they name are read.
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from mvtools.errors import ConfigError, DataError
from mvtools.geometry.camera import Camera
from mvtools.io.camera_files import read_camera_file
from mvtools.io.cameras import get_camera
from mvtools.io.config import (
    COMMAND_LINE,
    DEFAULT,
    ConfigEntry,
    load_params,
    override_entries,
    parse_overrides,
    read_config,
    resolve_input_path,
    resolve_output_path,
)
from mvtools.io.inputs import frame_range
from mvtools.io.yuv import VideoReader, YuvFormat, format_from_name, open_video
from mvtools.params import Kind, format_value, param_specs


@dataclass
class LoadedConfig:
    """Parameters with their files found and their cameras read.

    Attributes
    ----------
    params : VsrsParams or DersParams
    sources : dict of str to ConfigEntry
        Field name -> the entry that gave its value (file, ``Key=Value`` item or
        option), as :func:`mvtools.io.config.load_params` returns it; fields absent
        have their default values. See :meth:`entry`.
    inputs : dict of str to Path
        Field name -> input file found, for every non-empty input-file parameter.
    outputs : dict of str to Path
        Field name -> output file, for every non-empty output-file parameter.
    cameras : dict of str to Camera
        Field name (``left_camera_name`` ...) -> camera, for every non-empty name.
    all_cameras : dict of str to Camera
        Every camera of the camera parameter file, by camera name (empty when no
        camera file was read).
    options : frozenset of str
        Field names whose value a command-line option gave (``--start-frame`` ...),
        rather than the file or a ``Key=Value`` item.
    """

    params: Any
    sources: dict[str, ConfigEntry] = field(default_factory=dict)
    inputs: dict[str, Path] = field(default_factory=dict)
    outputs: dict[str, Path] = field(default_factory=dict)
    cameras: dict[str, Camera] = field(default_factory=dict)
    all_cameras: dict[str, Camera] = field(default_factory=dict)
    options: frozenset[str] = frozenset()

    def entry(self, name: str) -> ConfigEntry:
        """The entry a parameter's value came from, for path lookup and messages.

        Parameters
        ----------
        name : str
            Field name, e.g. ``"camera_parameter_file"``.

        Returns
        -------
        ConfigEntry
            ``sources[name]``, or for a default value an entry of its key and value
            with path :data:`mvtools.io.config.DEFAULT` and no line.
        """
        entry = self.sources.get(name)
        if entry is not None:
            return entry
        spec = next(spec for spec in param_specs(type(self.params)) if spec.name == name)
        return ConfigEntry(spec.key, format_value(getattr(self.params, name)), DEFAULT, None)

    @property
    def video_fields(self) -> list[str]:
        """Input-file fields that are videos (all but the camera parameter file)."""
        return [name for name in self.inputs if name != self.params.camera_file_field]

    def video_format(self, name: str) -> YuvFormat:
        """Format of an input video (:func:`video_format_for` with the configured size)."""
        size = (self.params.source_width, self.params.source_height)
        return video_format_for(self.inputs[name], size, key=self.entry(name).key)

    def open_video(self, name: str) -> VideoReader:
        return open_video(self.inputs[name], self.video_format(name))

    def frame_range(self, readers: list[VideoReader]) -> range:
        """The frames of StartFrame and TotalNumberOfFrames that every reader has
        (:func:`mvtools.io.inputs.frame_range`); a start past the end names what gave
        it: ``--start-frame``, or the key with its file and line."""
        params = self.params
        given = None if "start_frame" in self.options else self.entry("start_frame")
        return frame_range(
            readers, params.start_frame, params.total_number_of_frames, start_given=given
        )

    def command_line_camera(self, name: str, label: str) -> Camera:
        """A camera of the camera file named on the command line by the option ``label``."""
        return get_camera(
            self.all_cameras, name, path=self.inputs.get(self.params.camera_file_field), key=label
        )


def command_line_input(label: str, value: str, data_dirs: Iterable[str | os.PathLike]) -> Path:
    """An input file named on the command line by the option ``label``, found as the
    configuration's inputs are (:func:`mvtools.io.config.resolve_input_path`)."""
    return resolve_input_path(ConfigEntry(label, value, COMMAND_LINE, None), data_dirs=data_dirs)


def video_format_for(path: Path, size: tuple[int, int], *, key: str | None = None) -> YuvFormat:
    """Format of an input video of a configuration whose frames are ``size``.

    8-bit 4:2:0 (what the reference programs read) unless the file's name says
    otherwise the ffmpeg way (10/16-bit textures, 4:0:0 depth maps).

    Raises
    ------
    DataError
        The name gives another picture size than the configuration (``key``,
        the configuration key that named the file, goes into the message).
    """
    named = format_from_name(path)
    if named is None:
        return YuvFormat(*size)
    if named.size != size:
        raise DataError(
            f"the file name says {named.width}x{named.height}, the configuration "
            f"{size[0]}x{size[1]} (SourceWidth, SourceHeight)",
            path=path,
            key=key,
        )
    return named


def load_config(
    cls: type,
    config: str | os.PathLike | None,
    *,
    overrides: Iterable[str] = (),
    options: Mapping[str, Any] | None = None,
    data_dirs: Iterable[str | os.PathLike] = (),
    transposed_rotation: bool = False,
) -> LoadedConfig:
    """Read parameters of ``cls`` and find their files and cameras.

    The camera parameter file is an MPEG text file, or MPEG-I JSON when its name
    ends in ``.json``.

    Raises
    ------
    UsageError, ConfigError
        Unreadable configuration, bad values (file:line: key: message), input files
        not found (every place tried is listed), unknown camera names.
    """
    entries = read_config(config) if config is not None else {}
    entries.update(parse_overrides(overrides))
    entries.update(override_entries(cls, options or {}))
    params, sources = load_params(cls, entries)
    loaded = LoadedConfig(
        params,
        sources,
        options=frozenset(name for name, value in (options or {}).items() if value is not None),
    )
    data_dirs = tuple(data_dirs)
    for spec in param_specs(cls):
        if not getattr(params, spec.name):
            continue
        if spec.kind is Kind.INPUT_FILE:
            loaded.inputs[spec.name] = resolve_input_path(
                loaded.entry(spec.name), data_dirs=data_dirs
            )
        elif spec.kind is Kind.OUTPUT_FILE:
            loaded.outputs[spec.name] = resolve_output_path(loaded.entry(spec.name))
    camera_file = loaded.inputs.get(cls.camera_file_field)
    if camera_file is not None:
        cameras = read_camera_file(camera_file, transposed_rotation=transposed_rotation)
        loaded.all_cameras = cameras
        for spec in param_specs(cls):
            name = getattr(params, spec.name)
            if spec.name.endswith("_camera_name") and name:
                try:
                    loaded.cameras[spec.name] = get_camera(cameras, name)
                except ConfigError as error:
                    # Point at the configuration line that asked for the camera.
                    raise loaded.entry(spec.name).error(
                        f"{error.message} (in {camera_file})"
                    ) from None
    return loaded
