"""Views to PLY point clouds and back: the run functions of ``mvtools pointcloud``.

:func:`views_to_ply` turns one frame of texture-plus-depth views into one PLY file
(:func:`mvtools.synthesis.pointcloud.points_from_views`); :func:`ply_to_views` renders a
PLY file into a camera and writes the texture (YUV 4:2:0) and optionally the depth map
(:func:`mvtools.synthesis.pointcloud.render_point_cloud`). Colours are RGB of BT.601
limited range, as the synthesis's RGB working space (ColorSpace 1,
:func:`mvtools.synthesis.working.to_working`). The algorithm modules are imported when a
run starts, so this module is cheap to import.
"""

from __future__ import annotations

import logging
import os
from collections.abc import Sequence

import numpy as np

from mvtools.errors import DataError, UsageError
from mvtools.geometry.camera import Camera
from mvtools.geometry.depth import DepthCoding
from mvtools.io.yuv import frame_from_luma
from mvtools.run.synthesize import ReferenceVideo, texture_format

__all__ = ["ReferenceVideo", "ply_to_views", "views_to_ply"]

LOG = logging.getLogger(__name__)


def _rgb8(planes, bits: int) -> np.ndarray:
    """A texture frame as 8-bit RGB (BT.601 limited range; deeper samples scaled)."""
    from mvtools.color.space import yuv_to_rgb

    rgb = yuv_to_rgb(planes, bits=bits)
    if bits == 8:
        return rgb
    scaled = rgb.astype(np.float64) * (255.0 / (2**bits - 1))
    return np.clip(np.floor(scaled + 0.5), 0, 255).astype(np.uint8)


def views_to_ply(
    views: Sequence[ReferenceVideo],
    output: str | os.PathLike,
    *,
    frame: int = 0,
    merge_tolerance: float | None = None,
    precision: str = "single",
):
    """Write frame ``frame`` of ``views`` as one coloured point cloud.

    Parameters
    ----------
    views : sequence of ReferenceVideo
        Each camera (facing the scene, :func:`mvtools.geometry.depth.facing_camera`)
        with its texture and depth readers and depth coding, in merging order.
    output : path
        The PLY file, written atomically.
    frame : int
        The frame of every video to take.
    merge_tolerance : float, optional
        Relative depth difference under which a point of a later view is one of an
        earlier view (default
        :data:`mvtools.synthesis.pointcloud.DEFAULT_MERGE_TOLERANCE`).
    precision : {"single", "double"}
        Of the positions in the file.

    Returns
    -------
    PointCloud
        The cloud written.

    Raises
    ------
    UsageError
        ``frame`` beyond a video (``key="--frame"``).
    DataError
        A grey texture, textures of different bit depths, a depth video of another
        size than its texture.
    """
    from mvtools.geometry.projection import depth_along_axis, pixel_grid
    from mvtools.io.ply import write_ply
    from mvtools.synthesis.pointcloud import DEFAULT_MERGE_TOLERANCE, points_from_views

    if not views:
        raise UsageError("no view given")
    bits = texture_format([view.texture for view in views]).bits
    arrays = []
    for view in views:
        for reader in (view.texture, view.depth):
            if frame >= len(reader):
                raise UsageError(
                    f"frame {frame} asked, the video has {len(reader)}",
                    path=reader.path,
                    key="--frame",
                )
        if view.depth.format.size != view.texture.format.size:
            raise DataError(
                f"the depth video is {view.depth.format.width}x{view.depth.format.height}, "
                f"its texture {view.texture.format.width}x{view.texture.format.height}",
                path=view.depth.path,
            )
        rgb = _rgb8(view.texture.read(frame), bits)
        z = view.coding.z(view.depth.read(frame)[0])
        if view.coding.depth_type == 1:
            u, v = pixel_grid(z.shape[1], z.shape[0])
            with np.errstate(divide="ignore", invalid="ignore"):
                z = depth_along_axis(view.camera, u, v, z, depth_type=1)
        arrays.append((view.camera, rgb, z))
    tolerance = DEFAULT_MERGE_TOLERANCE if merge_tolerance is None else merge_tolerance
    cloud = points_from_views(arrays, merge_tolerance=tolerance)
    write_ply(output, cloud.points, cloud.colors, precision=precision)
    LOG.info(
        "%d points from %s (frame %d)",
        len(cloud),
        ", ".join(view.camera.name for view in views),
        frame,
    )
    return cloud


def ply_to_views(
    ply: str | os.PathLike,
    camera: Camera,
    *,
    size: tuple[int, int],
    texture,
    depth=None,
    depth_coding: DepthCoding | None = None,
    hole_filling: str | None = "background",
    splatting: str = "bilinear",
):
    """Render a PLY point cloud into ``camera`` and write one frame.

    Parameters
    ----------
    ply : path
        Read with :func:`mvtools.io.ply.read_ply`.
    camera : Camera
        Facing the scene, in the cloud's world.
    size : (width, height)
    texture : writer
        Gets the view as 8-bit YUV 4:2:0 (an object with ``format`` and
        ``write(planes)``, as :class:`mvtools.io.yuv.VideoWriter`).
    depth : writer, optional
        Gets the depth map along the camera's axis coded by ``depth_coding``, in the
        writer's format (8-bit 4:2:0 with chroma 128, or 16-bit grey ...).
    depth_coding : DepthCoding
        Needed with ``depth``; DepthType 0.
    hole_filling, splatting : str
        As :func:`mvtools.synthesis.pointcloud.render_point_cloud`.

    Returns
    -------
    holes : ndarray of bool, shape (H, W)
        The pixels no point reached (before filling).
    """
    from mvtools.color.space import rgb_to_yuv
    from mvtools.io.ply import read_ply
    from mvtools.synthesis.pointcloud import PointCloud, render_point_cloud

    if depth is not None and depth_coding is None:
        raise ValueError("a depth writer needs a depth coding")
    if depth is not None and depth_coding.depth_type != 0:
        raise ValueError("rendered depth maps are along the camera axis (DepthType 0)")
    points, colors = read_ply(ply)
    rgb, z, holes = render_point_cloud(
        PointCloud(points, colors),
        camera,
        size=size,
        hole_filling=hole_filling,
        splatting=splatting,
    )
    texture.write(rgb_to_yuv(np.clip(rgb / 255.0, 0.0, 1.0), chroma="420", bits=8))
    if depth is not None:
        depth.write(frame_from_luma(depth.format, depth_coding.values(z)))
    LOG.info(
        "%d points rendered into %s, %d holes filled (%.1f %%)",
        len(points),
        camera.name,
        int(holes.sum()),
        100.0 * holes.mean(),
    )
    return holes
