"""Frame-compatible layouts: where each view goes in a packed frame (the chapter's fig. 1.52).

A :class:`Layout` places views (textures, and depth maps for atlases) at luma offsets
of one larger frame. Offsets and sizes of every placement are even, so that the chroma
of 4:2:0 and 4:2:2 views lands on whole chroma samples of the packed frame and each
view's chroma block is its own: without decimation a packed view comes back bit-exact.
The packed frame is padded to a multiple of the encoder's block size.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = ["LAYOUTS", "Layout", "Placement", "plan_layout"]

LAYOUTS = ("side-by-side", "top-bottom", "grid", "atlas")
KINDS = ("texture", "depth")


def _even(value: int) -> int:
    return value + (value & 1)


@dataclass(frozen=True)
class Placement:
    """One view in the packed frame.

    Attributes
    ----------
    name : str
    kind : {"texture", "depth"}
    x, y : int
        Luma offset of the view's top-left sample in the packed frame (even).
    width, height : int
        Size of the view in the packed frame, after decimation.
    source_width, source_height : int
        Size of the view itself.
    decimation : (int, int)
        Horizontal and vertical factor (1: full resolution, 2: halved).
    """

    name: str
    kind: str
    x: int
    y: int
    width: int
    height: int
    source_width: int
    source_height: int
    decimation: tuple[int, int] = (1, 1)


@dataclass(frozen=True)
class Layout:
    """Views placed in a packed frame of ``width`` x ``height`` luma samples."""

    kind: str
    width: int
    height: int
    placements: tuple[Placement, ...]

    def placement(self, name: str, kind: str = "texture") -> Placement:
        for placement in self.placements:
            if placement.name == name and placement.kind == kind:
                return placement
        raise KeyError(f"no {kind} {name!r} in the layout")


def _check_views(views, what):
    views = [(str(name), (int(size[0]), int(size[1]))) for name, size in views]
    names = [name for name, _ in views]
    if len(set(names)) != len(names):
        raise ValueError(f"{what} names must be distinct, got {names}")
    for name, (width, height) in views:
        if width < 1 or height < 1:
            raise ValueError(f"{what} {name!r} has size {width}x{height}")
    return views


def _rows_of(views, columns, kind, decimation, origin_y, cell):
    """Views in rows of ``columns`` cells of ``cell`` = (width, height), from ``origin_y``."""
    placements = []
    cell_width, cell_height = cell
    for index, (name, (width, height)) in enumerate(views):
        row, column = divmod(index, columns)
        packed = (-(-width // decimation[0]), -(-height // decimation[1]))
        placements.append(
            Placement(
                name=name,
                kind=kind,
                x=column * cell_width,
                y=origin_y + row * cell_height,
                width=packed[0],
                height=packed[1],
                source_width=width,
                source_height=height,
                decimation=decimation,
            )
        )
    return placements


def plan_layout(
    views,
    *,
    layout: str,
    depths=(),
    columns: int | None = None,
    half: bool = False,
    block: int = 8,
    frame_size: tuple[int, int] | None = None,
) -> Layout:
    """Where each view goes.

    Parameters
    ----------
    views : sequence of (name, (width, height))
        The texture views, in order.
    layout : keyword-only {"side-by-side", "top-bottom", "grid", "atlas"}
        Two views next to each other or one above the other; a grid of any number of
        views (``columns`` per row, by default the count nearest a square); or an atlas:
        the textures' grid above, the depth maps' grid below.
    depths : keyword-only sequence of (name, (width, height))
        Depth maps, for ``"atlas"`` only.
    columns : keyword-only int, optional
        Views per row of a grid or atlas.
    half : keyword-only bool
        Halve the views along the packing direction as stereo broadcasting does:
        horizontally for side-by-side, vertically for top-bottom.
    block : keyword-only int
        The packed frame's size is a multiple of this (the encoder's block size); even.
    frame_size : keyword-only (width, height), optional
        A packed frame size to keep to (e.g. 7680x4320 for 16 HD views); the views
        must fit in it.

    Returns
    -------
    Layout
    """
    if layout not in LAYOUTS:
        raise ValueError(f"layout must be one of {', '.join(LAYOUTS)}, got {layout!r}")
    if block < 2 or block % 2:
        raise ValueError(f"block must be an even size of at least 2, got {block}")
    views = _check_views(views, "view")
    depths = _check_views(depths, "depth map")
    if not views:
        raise ValueError("no views to pack")
    if depths and layout != "atlas":
        raise ValueError(f"depth maps go into an atlas, not a {layout} layout")
    if half and layout not in ("side-by-side", "top-bottom"):
        raise ValueError("halving is for side-by-side and top-bottom layouts")
    if layout in ("side-by-side", "top-bottom"):
        if len(views) != 2:
            raise ValueError(f"a {layout} layout holds two views, got {len(views)}")
        columns = 2 if layout == "side-by-side" else 1
    elif columns is None:
        columns = math.ceil(math.sqrt(len(views)))
    if columns < 1:
        raise ValueError(f"columns must be at least 1, got {columns}")
    decimation = (1, 1)
    if half:
        decimation = (2, 1) if layout == "side-by-side" else (1, 2)
    everything = views + depths
    # one cell size for all: views of different sizes keep their own size inside it
    cell = (
        _even(max(-(-width // decimation[0]) for _, (width, _) in everything)),
        _even(max(-(-height // decimation[1]) for _, (_, height) in everything)),
    )
    placements = _rows_of(views, columns, "texture", decimation, 0, cell)
    texture_rows = -(-len(views) // columns)
    placements += _rows_of(depths, columns, "depth", decimation, texture_rows * cell[1], cell)
    rows = texture_rows + -(-len(depths) // columns)
    width = min(columns, max(len(views), len(depths))) * cell[0]
    height = rows * cell[1]
    if frame_size is None:
        frame_size = (-(-width // block) * block, -(-height // block) * block)
    elif frame_size[0] < width or frame_size[1] < height:
        raise ValueError(
            f"{len(views)} views{f' and {len(depths)} depth maps' if depths else ''}"
            f" in {columns} columns take {width}x{height} samples, more than the "
            f"{frame_size[0]}x{frame_size[1]} frame"
        )
    elif frame_size[0] % 2 or frame_size[1] % 2:
        raise ValueError(f"the packed frame size must be even, got {frame_size}")
    return Layout(
        kind=layout,
        width=int(frame_size[0]),
        height=int(frame_size[1]),
        placements=tuple(placements),
    )
