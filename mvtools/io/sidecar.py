"""The JSON sidecar of a packed video: its layout, the views' names, files, sizes,
offsets and decimation, so that ``mvtools pack --unpack`` restores every view::

    {"format": "mvtools-pack", "version": 1, "layout": "grid",
     "width": 768, "height": 384, "pix_fmt": "yuv420p", "frames": 3,
     "views": [{"name": "cam0", "kind": "texture", "file": "v0_texture_256x192_yuv420p.yuv",
                "pix_fmt": "yuv420p", "x": 0, "y": 0, "width": 256, "height": 192,
                "source_width": 256, "source_height": 192, "decimation": [1, 1]}, ...]}
"""

from __future__ import annotations

import json
import os
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path, PurePosixPath, PureWindowsPath

from mvtools.errors import ConfigError, UsageError
from mvtools.io.atomic import atomic_output
from mvtools.io.files import read_json
from mvtools.io.yuv import YuvFormat
from mvtools.pack.layout import KINDS, LAYOUTS, Layout, Placement

__all__ = ["PackedVideo", "read_sidecar", "repeated_file", "sidecar_path", "write_sidecar"]

FORMAT_NAME = "mvtools-pack"
VERSION = 1


@dataclass(frozen=True)
class PackedVideo:
    """What a sidecar says: the layout, the packed frames' pixel format and count, and
    per view its original file name and pixel format."""

    layout: Layout
    pix_fmt: str
    frames: int
    files: dict[tuple[str, str], str]
    pix_fmts: dict[tuple[str, str], str]


def sidecar_path(video: str | os.PathLike) -> Path:
    """``packed_1920x1080_yuv420p.yuv`` -> ``packed_1920x1080_yuv420p.json``."""
    return Path(video).with_suffix(".json")


def write_sidecar(path: str | os.PathLike, packed: PackedVideo) -> None:
    """Write the sidecar, atomically."""
    layout = packed.layout
    views = []
    for placement in layout.placements:
        key = (placement.name, placement.kind)
        views.append(
            {
                "name": placement.name,
                "kind": placement.kind,
                "file": packed.files[key],
                "pix_fmt": packed.pix_fmts[key],
                "x": placement.x,
                "y": placement.y,
                "width": placement.width,
                "height": placement.height,
                "source_width": placement.source_width,
                "source_height": placement.source_height,
                "decimation": list(placement.decimation),
            }
        )
    document = {
        "format": FORMAT_NAME,
        "version": VERSION,
        "layout": layout.kind,
        "width": layout.width,
        "height": layout.height,
        "pix_fmt": packed.pix_fmt,
        "frames": packed.frames,
        "views": views,
    }
    with atomic_output(path, "w") as handle:
        json.dump(document, handle, indent=1)
        handle.write("\n")


def _field(entry: dict, key: str, kind, path: Path, where: str):
    if key not in entry:
        raise ConfigError(f"{where} has no {key!r}", path=path, key=key)
    value = entry[key]
    if kind is int and (isinstance(value, bool) or not isinstance(value, int)):
        raise ConfigError(
            f"{where}: {key} must be a whole number, got {value!r}", path=path, key=key
        )
    if kind is str and not isinstance(value, str):
        raise ConfigError(f"{where}: {key} must be text, got {value!r}", path=path, key=key)
    return value


def _is_bare_file_name(name: str) -> bool:
    """Whether ``name`` is a file name alone, as a sidecar records a view's file: no
    folder part (on POSIX or Windows), not ``.`` or ``..``, not empty. Unpacking writes
    the views under these names inside the output folder, so a sidecar cannot send a
    view anywhere else (onto the packed video, or outside the folder)."""
    return (
        name not in ("", ".", "..")
        and PurePosixPath(name).name == name
        and PureWindowsPath(name).name == name
    )


def repeated_file(
    files: Mapping[tuple[str, str], str],
) -> tuple[tuple[str, str], tuple[str, str]] | None:
    """The first two views of ``files`` ((name, kind) -> file name) that share a file
    name, or None: unpacking restores every view under its name in one folder."""
    seen: dict[str, tuple[str, str]] = {}
    for key, file in files.items():
        if file in seen:
            return seen[file], key
        seen[file] = key
    return None


def _pixel_format(pix_fmt: str, path: Path, where: str) -> YuvFormat:
    """The format a sidecar's ``pix_fmt`` names, or a ConfigError naming the sidecar."""
    try:
        return YuvFormat.from_pix_fmt(2, 2, pix_fmt)
    except UsageError as error:
        raise ConfigError(f"{where}: {error.message}", path=path, key="pix_fmt") from None


def _check_source_size(placement: Placement, path: Path) -> None:
    """A view's own size must be positive and what its decimation makes of it must be
    its size in the frame, or unpacking would hand the writer planes of another shape."""
    for packed_field, source_field, factor in (
        ("width", "source_width", placement.decimation[0]),
        ("height", "source_height", placement.decimation[1]),
    ):
        packed, source = getattr(placement, packed_field), getattr(placement, source_field)
        if source < 1:
            raise ConfigError(
                f"view {placement.name}: {source_field} must be positive, got {source}",
                path=path,
                key=source_field,
            )
        if -(-source // factor) != packed:
            raise ConfigError(
                f"view {placement.name}: {source_field} {source} at decimation "
                f"{factor} takes {-(-source // factor)} samples in the frame, not "
                f"the view's {packed_field} {packed}",
                path=path,
                key=source_field,
            )


def read_sidecar(path: str | os.PathLike) -> PackedVideo:
    """Read and check a sidecar.

    Raises
    ------
    ConfigError
        Not JSON, not an mvtools pack sidecar, a missing or mistyped field, views
        that overlap or leave the frame or are listed twice, a view whose own size does
        not give its size in the frame, an unknown pixel format or one the packed frames
        cannot hold, or a view file that is not a bare file name or is another view's
        too (naming the view and the field).
    """
    path = Path(path)
    document = read_json(path, "pack sidecar")
    if not isinstance(document, dict) or document.get("format") != FORMAT_NAME:
        raise ConfigError(f'not an mvtools pack sidecar (no "format": "{FORMAT_NAME}")', path=path)
    if document.get("version") != VERSION:
        raise ConfigError(
            f"sidecar version {document.get('version')!r}; this mvtools reads version {VERSION}",
            path=path,
            key="version",
        )
    kind = _field(document, "layout", str, path, "the sidecar")
    if kind not in LAYOUTS:
        raise ConfigError(
            f"layout {kind!r} is not one of {', '.join(LAYOUTS)}", path=path, key="layout"
        )
    width = _field(document, "width", int, path, "the sidecar")
    height = _field(document, "height", int, path, "the sidecar")
    pix_fmt = _field(document, "pix_fmt", str, path, "the sidecar")
    packed_format = _pixel_format(pix_fmt, path, "the sidecar")
    frames = _field(document, "frames", int, path, "the sidecar")
    entries = document.get("views")
    if not isinstance(entries, list) or not entries:
        raise ConfigError("the sidecar lists no views", path=path, key="views")
    placements, files, pix_fmts = [], {}, {}
    for index, entry in enumerate(entries):
        where = f"view {index}"
        if not isinstance(entry, dict):
            raise ConfigError(f"{where} is not an object", path=path, key="views")
        numbers = {
            key: _field(entry, key, int, path, where)
            for key in ("x", "y", "width", "height", "source_width", "source_height")
        }
        name = _field(entry, "name", str, path, where)
        view_kind = _field(entry, "kind", str, path, f"view {name}")
        if view_kind not in KINDS:
            raise ConfigError(
                f"view {name}: kind {view_kind!r} is not one of {', '.join(KINDS)}",
                path=path,
                key="kind",
            )
        if (name, view_kind) in files:
            raise ConfigError(f"{view_kind} {name} is listed twice", path=path, key="name")
        decimation = entry.get("decimation", [1, 1])
        if (
            not isinstance(decimation, list)
            or len(decimation) != 2
            or any(factor not in (1, 2) for factor in decimation)
        ):
            raise ConfigError(
                f"view {name}: decimation must be two factors of 1 or 2, got {decimation!r}",
                path=path,
                key="decimation",
            )
        placement = Placement(name=name, kind=view_kind, decimation=tuple(decimation), **numbers)
        if (
            placement.x < 0
            or placement.y < 0
            or placement.x + placement.width > width
            or placement.y + placement.height > height
        ):
            raise ConfigError(
                f"view {name} ({placement.width}x{placement.height} at "
                f"{placement.x},{placement.y}) leaves the {width}x{height} frame",
                path=path,
                key="views",
            )
        for other in placements:
            if (
                placement.x < other.x + other.width
                and other.x < placement.x + placement.width
                and placement.y < other.y + other.height
                and other.y < placement.y + placement.height
            ):
                raise ConfigError(f"views {other.name} and {name} overlap", path=path, key="views")
        _check_source_size(placement, path)
        placements.append(placement)
        file = _field(entry, "file", str, path, f"view {name}")
        if not _is_bare_file_name(file):
            raise ConfigError(
                f"view {name}: {file!r} is not a bare file name: a sidecar "
                "names the views' files inside the output folder (no folder "
                "part, no '..', not absolute)",
                path=path,
                key="file",
            )
        files[(name, view_kind)] = file
        repeated = repeated_file(files)
        if repeated is not None:
            first, second = (view for view, _ in repeated)
            raise ConfigError(
                f"views {first} and {second} both name {file!r}: one would overwrite the other",
                path=path,
                key="file",
            )
        view_pix_fmt = _field(entry, "pix_fmt", str, path, f"view {name}")
        view_format = _pixel_format(view_pix_fmt, path, f"view {name}")
        # what pack writes, and what unpacking can restore: the packed frames' samples,
        # with their chroma or none (a depth map's luma)
        if view_format.bits != packed_format.bits or view_format.chroma not in (
            packed_format.chroma,
            "400",
        ):
            raise ConfigError(
                f"view {name}: pix_fmt {view_pix_fmt} does not fit the packed "
                f"{pix_fmt} frames: a view has their bit depth, and their chroma "
                "or none",
                path=path,
                key="pix_fmt",
            )
        pix_fmts[(name, view_kind)] = view_pix_fmt
    layout = Layout(kind=kind, width=width, height=height, placements=tuple(placements))
    return PackedVideo(
        layout=layout, pix_fmt=pix_fmt, frames=frames, files=files, pix_fmts=pix_fmts
    )
