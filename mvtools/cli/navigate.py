"""``mvtools navigate``: free-viewpoint video from multiview video plus depth.

A camera path (a pose trace, or keyframes interpolated), the two eyes of a headset at
each pose, or dense views between the cameras of an array, rendered from any number of
reference views (:mod:`mvtools.run.navigate`).
"""

from __future__ import annotations

import logging
from pathlib import Path

import click

from mvtools.cli.options import (
    ProgramCommand,
    depth_range_option,
    depth_video_option,
    parse_size,
    program,
    transposed_rotation_option,
    view_option,
)
from mvtools.cli.progress import Progress
from mvtools.errors import UsageError
from mvtools.io.pose_trace import POSE_TRACE_CONVENTIONS
from mvtools.params import VsrsParams
from mvtools.run.navigate import STREAM_LAYOUTS
from mvtools.synthesis.views import DEFAULT_HOLE_FILLING, FILTERS, HOLE_FILLING, PRECISIONS

LOG = logging.getLogger(__name__)

#: The interpupillary distance of ``--stereo`` without a value, in metres.
DEFAULT_IPD = 0.065


@click.command(name="navigate", cls=ProgramCommand)
@click.argument("cameras", type=click.Path(dir_okay=False, exists=True))
@view_option("The texture video of camera NAME of CAMERAS (repeatable; every view used).")
@depth_video_option("The depth video of camera NAME (repeatable; one per --view).")
@depth_range_option(default="each camera's Depth_range in an MPEG-I JSON camera file")
@click.option(
    "--pose-trace",
    type=click.Path(dir_okay=False, exists=True),
    default=None,
    help="The path as a pose trace: a CSV of X,Y,Z,Yaw,Pitch,Roll per output frame "
    "(docs/pose-trace.md).",
)
@click.option(
    "--pose-convention",
    type=click.Choice(POSE_TRACE_CONVENTIONS),
    default="omaf",
    show_default=True,
    help="Axes of the pose traces' angles: omaf as MPEG-I JSON cameras (x forward, y left, "
    "z up), mpeg as the MPEG camera files (x right, y down, z forward).",
)
@click.option(
    "--keyframe",
    "keyframes",
    multiple=True,
    metavar="NAME",
    help="A camera of CAMERAS the path passes through (repeatable, in order; default: "
    "the --view cameras in order). Positions follow a cubic spline, rotations slerp.",
)
@click.option(
    "--frames",
    type=click.IntRange(min=1),
    default=None,
    help="Output frames of a keyframe path (at least 2), or the first frames of a pose "
    "trace (it must have as many rows); with --dense the number of dense views.",
)
@click.option(
    "--extend",
    type=click.FloatRange(min=0),
    default=0.0,
    show_default=True,
    help="Continue a keyframe path beyond its first and last keyframes by this many "
    "keyframe intervals.",
)
@click.option(
    "--dense",
    is_flag=True,
    help="Dense views: the --frames cameras of the keyframe path are still cameras, each "
    "a video of its own over the input frames (a light-field display's views).",
)
@click.option(
    "--stereo",
    is_flag=True,
    help="Render a left and a right eye per pose, --ipd apart along the camera's x axis.",
)
@click.option(
    "--ipd",
    type=float,
    default=DEFAULT_IPD,
    show_default=True,
    help="Interpupillary distance of --stereo in the camera file's units (65 mm in metres; "
    "give it in the sequence's units when they are not metres).",
)
@click.option(
    "--layout",
    type=click.Choice(STREAM_LAYOUTS),
    default=None,
    help="Pack the output streams (two eyes, dense views) into one video; without it "
    "each stream gets its own file, -o holding %s for the stream's name.",
)
@click.option(
    "--static",
    is_flag=True,
    help="Static content: every output frame renders input frame --start-frame (default: "
    "output frame k renders input frame --start-frame + k).",
)
@click.option(
    "--start-frame",
    type=click.IntRange(min=0),
    default=0,
    show_default=True,
    help="First input frame read.",
)
@click.option(
    "--views-per-frame",
    type=click.IntRange(min=1),
    default=None,
    help="Reference views serving each output view, the nearest that look its way (default: all).",
)
@click.option(
    "--max-angle",
    type=click.FloatRange(min=0, max=180, min_open=True),
    default=60.0,
    show_default=True,
    help="Degrees between optical axes beyond which a reference view does not serve.",
)
@click.option(
    "--synthesis-mode",
    type=click.Choice(["0", "1"]),
    default="0",
    show_default=True,
    help="SynthesisMode: 0 general (any pose), 1 1D (poses on a rectified array's line).",
)
@click.option(
    "--precision",
    type=click.Choice([str(value) for value in PRECISIONS]),
    default=str(VsrsParams().precision),
    show_default=True,
    help="Precision: sub-pixel precision of the colour fetch.",
)
@click.option(
    "--filter",
    type=click.Choice([str(index) for index in range(len(FILTERS))]),
    default=str(VsrsParams().filter),
    show_default=True,
    help="Filter: upsampling filter, 0: bilinear, 1: bicubic, 2: AVC 6-tap.",
)
@click.option(
    "--hole-filling",
    type=click.Choice(HOLE_FILLING),
    default=DEFAULT_HOLE_FILLING,
    show_default=True,
    help="How the holes no view saw are filled.",
)
@click.option(
    "--size",
    callback=parse_size,
    default=None,
    metavar="WxH",
    help="Picture size of raw YUV inputs whose name does not carry it.",
)
@click.option(
    "--frame-rate",
    default=None,
    metavar="RATE",
    help="Frame rate of Y4M and MP4 outputs (30, 30000/1001; default 25).",
)
@click.option(
    "-o",
    "--output",
    required=True,
    type=click.Path(dir_okay=False),
    help="The output video: raw YUV, .y4m, - (Y4M on standard output) or .mp4 (H.264 by "
    "ffmpeg); with several streams and no --layout a name holding %s.",
)
@click.option(
    "--poses-output",
    type=click.Path(dir_okay=False),
    default=None,
    help="Also write the path's poses (the eyes' centres) as a pose trace in "
    "--pose-convention, for another run or another program.",
)
@transposed_rotation_option
@program
def command(cameras, views, depths, depth_range, output, transposed_rotation, **options):
    """Render a camera path, stereo pairs or dense views from the views of CAMERAS.

    CAMERAS is an MPEG camera parameter file or an MPEG-I JSON camera file; --view and
    --depth give the videos of any number of its cameras. Each output view is rendered
    from the views that look its way, nearest first: warped (general mode, or 1D on a
    rectified line), blended where their depths agree and filled.

    \b
    The path: --pose-trace FILE (a pose per output frame), or --keyframe NAME ...
    with --frames N (default: through the --view cameras). --dense makes the N
    cameras still views. --stereo renders both eyes at each pose, --ipd apart.
    """
    from mvtools.io.camera_files import read_camera_file
    from mvtools.run.navigate import (
        NavigationOptions,
        frames_after,
        navigate_files,
        output_streams,
    )
    from mvtools.run.synthesize import facing_references, synthesis_options

    all_cameras = read_camera_file(cameras, transposed_rotation=transposed_rotation)
    references = _references(all_cameras, views, depths, depth_range, cameras)
    references = facing_references(references, 0)
    poses = _poses(all_cameras, references, cameras, options)
    stereo = options["ipd"] if options["stereo"] else None
    if stereo is not None and not 0 < stereo < float("inf"):
        raise UsageError(f"must be positive, got {options['ipd']:g}", key="--ipd")
    dense_frames = None
    if options["dense"]:
        dense_frames = (
            1
            if options["static"]
            else frames_after(references, options["start_frame"], size=options["size"])
        )
    names, streams = output_streams(poses, stereo=stereo, dense_frames=dense_frames)
    frame_count = len(streams[0])
    start = options["start_frame"]
    input_frames = [start] * frame_count if options["static"] else range(start, start + frame_count)
    outputs = _outputs(output, names, options["layout"])
    params = VsrsParams(
        synthesis_mode=int(options["synthesis_mode"]),
        precision=int(options["precision"]),
        filter=int(options["filter"]),
    )
    navigation = NavigationOptions(
        synthesis=synthesis_options(params, hole_filling=options["hole_filling"]),
        views_per_frame=options["views_per_frame"],
        max_angle=options["max_angle"],
    )
    written = navigate_files(
        references,
        streams,
        navigation,
        outputs=outputs,
        input_frames=input_frames,
        layout=options["layout"],
        size=options["size"],
        frame_rate=options["frame_rate"],
        progress=Progress(None, "frames rendered"),
    )
    if options["poses_output"] is not None:
        from mvtools.io.pose_trace import write_pose_trace

        write_pose_trace(options["poses_output"], poses, convention=options["pose_convention"])
        written.append(Path(options["poses_output"]))
    LOG.info("wrote %s", ", ".join(map(str, written)))


def _references(all_cameras, views, depths, depth_range, cameras_path):
    from mvtools.run.synthesize import ReferenceFiles

    if not views:
        raise UsageError("give the views to render from: --view NAME VIDEO --depth NAME VIDEO")
    for name in depths.keys() - views.keys():
        raise UsageError(f"--depth {name} has no --view {name}")
    references = []
    for name, texture in views.items():
        if name not in all_cameras:
            raise UsageError(
                f"camera {name!r} is not in {cameras_path} (it has {', '.join(all_cameras)})",
                key=f"--view {name}",
            )
        if name not in depths:
            raise UsageError(f"give its depth video with --depth {name}", key=f"--view {name}")
        camera = all_cameras[name]
        znear_zfar = depth_range or camera.depth_range
        if znear_zfar is None:
            raise UsageError(
                "give the Znear and Zfar of its depth with --depth-range", key=f"--view {name}"
            )
        references.append(
            ReferenceFiles(
                camera,
                Path(texture),
                Path(depths[name]),
                tuple(znear_zfar),
                f"--view {name}",
                "--depth-range" if depth_range else f"--depth {name}",
            )
        )
    return references


def _poses(all_cameras, references, cameras_path, options):
    """The path's cameras: the pose trace's, or the keyframe path's."""
    from mvtools.geometry.pose import camera_path
    from mvtools.io.pose_trace import read_pose_trace

    template = references[0].camera
    if options["pose_trace"] is not None:
        if options["keyframes"] or options["dense"]:
            raise UsageError("a pose trace is the whole path: no --keyframe or --dense with it")
        return read_pose_trace(
            options["pose_trace"],
            convention=options["pose_convention"],
            template=template,
            frames=options["frames"],
        )
    names = options["keyframes"] or [ref.camera.name for ref in references]
    facing = {ref.camera.name: ref.camera for ref in references}
    keyframes = []
    for name in names:
        if name not in all_cameras:
            raise UsageError(
                f"camera {name!r} is not in {cameras_path} (it has {', '.join(all_cameras)})",
                key="--keyframe",
            )
        keyframes.append(facing.get(name, all_cameras[name]))
    if options["frames"] is None:
        raise UsageError("how many output frames (or dense views) the path has", key="--frames")
    if options["frames"] < 2 and len(keyframes) > 1:
        raise UsageError("a path through several keyframes needs at least 2", key="--frames")
    return camera_path(keyframes, options["frames"], extend=options["extend"])


def _outputs(output: str, names: list[str], layout: str | None) -> list[str]:
    if len(names) == 1 or layout is not None:
        if "%s" in output:
            raise UsageError("one output video: its name takes no %s", key="-o")
        return [output]
    if output.count("%s") != 1:
        raise UsageError(
            f"{len(names)} output streams ({', '.join(names)}): give a name holding %s, "
            "or --layout to pack them into one video",
            key="-o",
        )
    return [output.replace("%s", name) for name in names]
