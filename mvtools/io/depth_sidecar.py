"""The JSON sidecar of a depth video: what its values mean, written beside it as
``OUTPUT.json`` by ``mvtools estimate-depth`` and read by ``mvtools evaluate --depth``::

    {
      "camera": "cam2",
      "NearestDepthValue": 2.0,
      "FarthestDepthValue": 13.0,
      "DepthType": 0,
      "pix_fmt": "yuv420p",
      "width": 64,
      "height": 48
    }

``FarthestDepthValue`` null means an infinite Zfar. Only ``NearestDepthValue`` is
required on reading (``DepthType`` is 0 and Zfar infinite when absent); the other keys
describe the video.
"""

from __future__ import annotations

import json
import math
import os
from dataclasses import dataclass
from pathlib import Path

from mvtools.errors import ConfigError
from mvtools.io.atomic import atomic_output
from mvtools.io.files import read_json

__all__ = [
    "SIDECAR_WHAT",
    "DepthSidecar",
    "depth_sidecar_path",
    "read_depth_sidecar",
    "write_depth_sidecar",
]

#: The sidecar in messages.
SIDECAR_WHAT = "depth values' description (OUTPUT.json)"


@dataclass(frozen=True, kw_only=True)
class DepthSidecar:
    """What a depth video's values mean.

    Attributes
    ----------
    nearest, farthest : float
        Znear and Zfar, the depths of the largest and the smallest value (Zfar may be
        inf).
    depth_type : {0, 1}
        Depth along the camera's axis (0) or from the world origin (1).
    camera : str, optional
        The camera whose depth the video holds.
    pix_fmt : str, optional
        The video's pixel format (``yuv420p``, ``gray16le``...).
    width, height : int, optional
        The video's size.
    """

    nearest: float
    farthest: float
    depth_type: int = 0
    camera: str | None = None
    pix_fmt: str | None = None
    width: int | None = None
    height: int | None = None

    @property
    def depth_range(self) -> tuple[float, float]:
        """(Znear, Zfar)."""
        return self.nearest, self.farthest


def depth_sidecar_path(video: str | os.PathLike) -> Path:
    """The sidecar of a depth video: its name with ``.json`` added.

    Examples
    --------
    >>> depth_sidecar_path("out/depth.yuv").as_posix()
    'out/depth.yuv.json'
    """
    video = Path(video)
    return video.with_name(video.name + ".json")


def write_depth_sidecar(path: str | os.PathLike, sidecar: DepthSidecar) -> None:
    """Write ``sidecar`` to ``path`` atomically, as indented JSON ending in a newline."""
    document = {
        "camera": sidecar.camera,
        "NearestDepthValue": sidecar.nearest,
        "FarthestDepthValue": sidecar.farthest if math.isfinite(sidecar.farthest) else None,
        "DepthType": sidecar.depth_type,
        "pix_fmt": sidecar.pix_fmt,
        "width": sidecar.width,
        "height": sidecar.height,
    }
    with atomic_output(path, "w", what=SIDECAR_WHAT) as handle:
        json.dump(document, handle, indent=2)
        handle.write("\n")


def read_depth_sidecar(path: str | os.PathLike) -> DepthSidecar:
    """Read a depth sidecar.

    Raises
    ------
    ConfigError
        Invalid JSON, or no ``NearestDepthValue``, naming the file.
    """
    document = read_json(path)
    if not isinstance(document, dict) or "NearestDepthValue" not in document:
        raise ConfigError("no NearestDepthValue in the sidecar", path=path)
    far = document.get("FarthestDepthValue")
    return DepthSidecar(
        nearest=float(document["NearestDepthValue"]),
        farthest=math.inf if far is None else float(far),
        depth_type=document.get("DepthType", 0),
        camera=document.get("camera"),
        pix_fmt=document.get("pix_fmt"),
        width=document.get("width"),
        height=document.get("height"),
    )
