"""Layer 1: reading and writing files. Nothing here computes on pixels.

Videos are raw planar YUV or Y4M (:mod:`mvtools.io.yuv`): a frame is a tuple of 2-D
planes, ``(Y, U, V)`` or ``(Y,)`` for grey, uint8 for 8 bits and uint16 above. Cameras
are read from and written to MPEG camera parameter files (:mod:`mvtools.io.cameras`)
and MPEG-I JSON sequence files (:mod:`mvtools.io.json_cameras`); still images are
``(H, W)`` or ``(H, W, 3)`` RGB arrays (:mod:`mvtools.io.images`).

Names are imported from their modules on first use, so ``import mvtools.io`` is cheap
(OpenCV, for one, loads when an image is first read or written).

Examples
--------
A two-frame 4:2:0 video written and read back (the name carries the format):

>>> import tempfile
>>> from pathlib import Path
>>> import numpy as np
>>> from mvtools.io import YuvFormat, open_video, write_video
>>> fmt = YuvFormat(8, 6, chroma="420", bits=8)
>>> fmt.plane_shapes
((6, 8), (3, 4), (3, 4))
>>> frames = [tuple(np.full(shape, 16 * i + k, np.uint8) for k, shape in
...           enumerate(fmt.plane_shapes)) for i in range(2)]
>>> with tempfile.TemporaryDirectory() as folder:
...     path = Path(folder) / "ramp_8x6_yuv420p.yuv"
...     write_video(path, fmt, frames)
...     with open_video(path) as reader:
...         print(reader.format, len(reader))
...         y, u, v = reader.read(1)
...         print(y.shape, u.shape, y[0, 0], u[0, 0], v[0, 0])
2
8x6 yuv420p 2
(6, 8) (3, 4) 16 17 18
"""

from __future__ import annotations

from mvtools.lazy import attach

#: Each exported name and the module of this package that defines it.
_EXPORTS: dict[str, str] = {
    "YuvFormat": "yuv",
    "VideoReader": "yuv",
    "VideoWriter": "yuv",
    "open_video": "yuv",
    "open_writer": "yuv",
    "read_frame": "yuv",
    "write_video": "yuv",
    "format_from_name": "yuv",
    "guess_format": "yuv",
    "frame_from_luma": "yuv",
    "read_cameras": "cameras",
    "write_cameras": "cameras",
    "get_camera": "cameras",
    "read_htm_cameras": "cameras",
    "read_camera_file": "camera_files",
    "write_camera_file": "camera_files",
    "CAMERA_FILE_READERS": "camera_files",
    "CAMERA_FILE_WRITERS": "camera_files",
    "read_json_cameras": "json_cameras",
    "write_json_cameras": "json_cameras",
    "read_json_sequence": "json_cameras",
    "write_json_sequence": "json_cameras",
    "JsonSequence": "json_cameras",
    "read_pose_trace": "pose_trace",
    "write_pose_trace": "pose_trace",
    "POSE_TRACE_CONVENTIONS": "pose_trace",
    "read_ply": "ply",
    "write_ply": "ply",
    "read_image": "images",
    "write_image": "images",
    "read_pfm": "images",
    "write_pfm": "images",
    "read_config": "config",
    "load_config": "loaded_config",
    "LoadedConfig": "loaded_config",
}

__getattr__, __dir__, __all__ = attach(__name__, _EXPORTS)
