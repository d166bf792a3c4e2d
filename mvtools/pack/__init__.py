"""Frame-compatible packing of views and depth maps (the chapter's section 1.6): layouts, packing
and unpacking of frames."""

from mvtools.pack.frames import pack_frame, unpack_frame
from mvtools.pack.layout import LAYOUTS, Layout, Placement, plan_layout

__all__ = [
    "LAYOUTS",
    "Layout",
    "Placement",
    "pack_frame",
    "plan_layout",
    "unpack_frame",
]
