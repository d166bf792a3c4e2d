"""Pipeline files: the chain ``mvtools run`` carries out over a sequence, in TOML.

A pipeline names the cameras of an array (in their order along it, so that neighbours
are adjacent), their texture videos, and the configurations of the stages, as the
Makefile chain does::

    # the sample line: every camera's depth from its neighbours, each inner camera
    # synthesized from its neighbours and scored against its own view
    cameras = "../sample_data/line/cameras.txt"
    views = ["cam0", "cam1", "cam2", "cam3", "cam4"]
    textures = "../sample_data/line/v{index}_texture_256x192_yuv420p.yuv"
    chunk = 8                      # frames per task (0: whole videos)

    [estimate-depth]
    config = "../sample_data/line/depth_cam2.cfg"
    output = "v{index}_depth_256x192_yuv420p.yuv"

    [synthesize]
    config = "../sample_data/line/synthesize_cam2.cfg"
    output = "v{index}_synthesized_256x192_yuv420p.yuv"

    [evaluate]
    output = "v{index}_synthesized.scores.json"

Before the depth, ``[rectify]`` (``output``: a folder; ``alpha``) and ``[colorcorrect]``
(``output``: a folder; ``reference``, ``space``, ``depth-range``) may rectify the array
and correct its colours (``configs/sample_distorted_pipeline.toml``); docs/pipeline.md
describes every key.

Paths of inputs are relative to the pipeline file's folder; outputs are names in the
folder the run writes to. ``{index}`` is a camera's position in ``views`` and ``{name}``
its name. Optional keys: ``frames`` (number of frames, default all of the textures').
"""

from __future__ import annotations

import os
import re
import string
from dataclasses import dataclass, field
from pathlib import Path

from mvtools.errors import ConfigError
from mvtools.io.files import read_text

try:  # Python 3.11+
    import tomllib
except ModuleNotFoundError:  # pragma: no cover - Python 3.10
    import tomli as tomllib

__all__ = ["PIPELINE_STAGES", "PipelineSpec", "StageSpec", "read_pipeline"]

#: The stages a pipeline may name, in the order they run.
PIPELINE_STAGES = ("rectify", "colorcorrect", "estimate-depth", "synthesize", "evaluate")

#: Each stage's keys and their types; the others beside ``output`` are optional.
_STAGE_KEYS: dict[str, dict[str, type]] = {
    "rectify": {"output": str, "alpha": float},
    "colorcorrect": {"output": str, "reference": str, "space": str, "depth-range": list},
    "estimate-depth": {"config": str, "output": str},
    "synthesize": {"config": str, "output": str},
    "evaluate": {"output": str},
}

#: Stages whose output is a folder of the output folder, holding each camera's video under
#: its input's name (and the camera file or tables), as the program writes them.
FOLDER_STAGES = ("rectify", "colorcorrect")

#: Fields of the names a template may hold.
_TEMPLATE_FIELDS = {"index", "name"}


@dataclass(frozen=True)
class StageSpec:
    """A stage of a pipeline: its configuration file (for ``estimate-depth`` and
    ``synthesize``), the template of its outputs' names (a folder's name for
    :data:`FOLDER_STAGES`), and its other keys (``alpha``, ``reference`` ...)."""

    config: Path | None
    output: str
    settings: dict = field(default_factory=dict)


@dataclass(frozen=True)
class PipelineSpec:
    """A pipeline file, read (:func:`read_pipeline`)."""

    path: Path
    cameras: Path
    views: tuple[str, ...]
    textures: str
    chunk: int
    frames: int | None
    stages: dict[str, StageSpec]

    def texture(self, index: int) -> Path:
        """The texture video of camera ``views[index]``."""
        return self.path.parent / fill(self.textures, index, self.views[index])


def fill(template: str, index: int, name: str) -> str:
    """A template with ``{index}`` and ``{name}`` filled in."""
    return template.format(index=index, name=name)


def read_pipeline(path: str | os.PathLike) -> PipelineSpec:
    """Read a pipeline file (TOML, see the module's description).

    Raises
    ------
    ConfigError
        Bad TOML, a missing or unknown key, a value of the wrong type, a template with
        an unknown field, a stage whose outputs would not have one name per camera:
        naming the file, the line where the TOML parser stopped, and the key.
    """
    path = Path(path)
    text = read_text(path, "pipeline file")
    try:
        document = tomllib.loads(text)
    except tomllib.TOMLDecodeError as error:
        found = re.search(r"line (\d+)", str(error))
        raise ConfigError(
            re.sub(r"\s*\(at line \d+, column \d+\)", "", str(error)),
            path=path,
            line=int(found.group(1)) if found else None,
        ) from None
    known = {"cameras", "views", "textures", "chunk", "frames", *PIPELINE_STAGES}
    for key in document:
        if key not in known:
            raise ConfigError(
                f"unknown key; known keys: {', '.join(sorted(known))}", path=path, key=key
            )
    folder = path.parent

    def value(table: dict, key: str, kind: type, where: str = "", *, required: bool = True):
        name = f"{where}.{key}" if where else key
        if key not in table:
            if required:
                raise ConfigError("missing", path=path, key=name)
            return None
        item = table[key]
        kinds = (int, float) if kind is float else kind
        if not isinstance(item, kinds) or isinstance(item, bool):
            raise ConfigError(
                f"must be a {kind.__name__}, got {type(item).__name__}", path=path, key=name
            )
        return item

    def template(item: str, key: str, *, output: bool) -> str:
        fields = {name for _, name, _, _ in string.Formatter().parse(item) if name is not None}
        if not fields <= _TEMPLATE_FIELDS:
            raise ConfigError(
                f"{item!r}: unknown field {sorted(fields - _TEMPLATE_FIELDS)[0]!r}; a name "
                "may hold {index} and {name}",
                path=path,
                key=key,
            )
        if output and Path(item).name != item:
            raise ConfigError(
                f"{item!r}: an output is a file name in the run's output folder",
                path=path,
                key=key,
            )
        return item

    views = value(document, "views", list)
    if not views or not all(isinstance(view, str) and view for view in views):
        raise ConfigError("must be a list of camera names", path=path, key="views")
    if len(set(views)) != len(views):
        raise ConfigError("a camera is named twice", path=path, key="views")
    chunk = value(document, "chunk", int, required=False)
    chunk = 0 if chunk is None else chunk
    if chunk < 0:
        raise ConfigError(f"must be 0 (whole videos) or more, got {chunk}", path=path, key="chunk")
    frames = value(document, "frames", int, required=False)
    if frames is not None and frames < 1:
        raise ConfigError(f"must be at least 1, got {frames}", path=path, key="frames")
    stages = {}
    for stage in PIPELINE_STAGES:
        table = value(document, stage, dict, required=False)
        if table is None:
            continue
        allowed = _STAGE_KEYS[stage]
        for key in table:
            if key not in allowed:
                raise ConfigError(
                    f"unknown key; known keys: {', '.join(sorted(allowed))}",
                    path=path,
                    key=f"{stage}.{key}",
                )
        config = folder / value(table, "config", str, stage) if "config" in allowed else None
        output = template(value(table, "output", str, stage), f"{stage}.output", output=True)
        settings = {
            key: value(table, key, kind, stage, required=False)
            for key, kind in allowed.items()
            if key not in ("config", "output") and key in table
        }
        if isinstance(settings.get("alpha"), int):
            settings["alpha"] = float(settings["alpha"])
        if "depth-range" in settings and not (
            len(settings["depth-range"]) == 2
            and all(
                isinstance(x, (int, float)) and not isinstance(x, bool)
                for x in settings["depth-range"]
            )
        ):
            raise ConfigError("must be [Znear, Zfar]", path=path, key=f"{stage}.depth-range")
        if settings.get("space", "rgb") not in ("rgb", "yuv"):
            raise ConfigError("must be rgb or yuv", path=path, key=f"{stage}.space")
        if settings.get("reference", views[0]) not in views:
            raise ConfigError(
                f"{settings['reference']!r} is not one of the views",
                path=path,
                key=f"{stage}.reference",
            )
        if stage in FOLDER_STAGES:
            if set(string.Formatter().parse(output)) != {(output, None, None, None)}:
                raise ConfigError(
                    f"{output!r}: a folder's name, the same for every camera",
                    path=path,
                    key=f"{stage}.output",
                )
        elif len({fill(output, i, view) for i, view in enumerate(views)}) != len(views):
            raise ConfigError(
                f"{output!r} gives two cameras one name: use {{index}} or {{name}}",
                path=path,
                key=f"{stage}.output",
            )
        stages[stage] = StageSpec(config, output, settings)
    if "synthesize" in stages and "estimate-depth" not in stages:
        raise ConfigError(
            "synthesize reads the estimated depth: the pipeline needs [estimate-depth]",
            path=path,
            key="synthesize",
        )
    if "evaluate" in stages and "synthesize" not in stages:
        raise ConfigError(
            "evaluate scores the synthesized views: the pipeline needs [synthesize]",
            path=path,
            key="evaluate",
        )
    if not stages:
        raise ConfigError(f"no stage: name at least one of {', '.join(PIPELINE_STAGES)}", path=path)
    return PipelineSpec(
        path=path,
        cameras=folder / value(document, "cameras", str),
        views=tuple(views),
        textures=template(value(document, "textures", str), "textures", output=False),
        chunk=chunk,
        frames=frames,
        stages=stages,
    )
