"""Run functions: one per program, the Python API of the programs.

Each takes opened readers and writers (or paths) and an options dataclass, works over
a frame range frame by frame (:func:`mvtools.run.stream.stream_frames`) and reports
progress through a callback; it is also the unit of work a Dask task runs. The
programs of :mod:`mvtools.cli` parse their arguments and configuration files, call
one of these and print.

Names are imported from their modules on first use, so ``import mvtools.run`` is cheap.
"""

from __future__ import annotations

from mvtools.lazy import attach

#: Each exported name and the module of this package that defines it.
_EXPORTS: dict[str, str] = {
    "stream_frames": "stream",
    "ProgressCallback": "stream",
    "synthesize_video": "synthesize",
    "synthesize_config": "synthesize",
    "ReferenceVideo": "synthesize",
    "rectify_video": "rectify",
    "rectify_videos": "rectify",
    "RectifyOptions": "rectify",
    "RectifiedArray": "rectify",
    "calibrate_rig": "calibrate",
    "CalibrateOptions": "calibrate",
    "CalibratedRig": "calibrate",
    "write_rig_cameras": "calibrate",
    "write_rig_report": "calibrate",
    "estimate_depth_video": "depth",
    "estimate_depth_config": "depth",
    "estimate_pair_disparity": "depth",
    "estimate_views_disparity": "depth",
    "FurtherView": "depth",
    "correct_colours": "colorcorrect",
    "ColourCorrectionOptions": "colorcorrect",
    "ColourCorrection": "colorcorrect",
    "ViewCorrection": "colorcorrect",
    "convert_video": "convert",
    "video_to_images": "convert",
    "depth_video_to_pfm": "convert",
    "pfm_to_depth_video": "convert",
    "images_to_video": "convert",
    "DepthValues": "convert",
    "evaluate_videos": "evaluate",
    "score_videos": "evaluate",
    "evaluate_disparity": "evaluate",
    "evaluate_depth_videos": "evaluate",
    "DisparityGeometry": "evaluate",
    "disparity_geometry": "evaluate",
    "pack_views": "pack",
    "unpack_views": "pack",
    "PackOptions": "pack",
    "PackedViews": "pack",
    "pack_frames": "pack",
    "write_unpacked": "pack",
    "rd_experiment": "encode",
    "EncoderSettings": "encode",
    "navigate_video": "navigate",
    "navigate_files": "navigate",
    "NavigationOptions": "navigate",
    "output_streams": "navigate",
    "views_to_ply": "pointcloud",
    "ply_to_views": "pointcloud",
}

__getattr__, __dir__, __all__ = attach(__name__, _EXPORTS)
