"""``mvtools scene``: write the synthetic sample data with its exact ground truth."""

from __future__ import annotations

import contextlib
import json
from pathlib import Path

import click
import numpy as np

import mvtools
from mvtools.cli.options import FiniteFloat, ProgramCommand, parse_size, program
from mvtools.cli.progress import Progress
from mvtools.color.space import rgb_to_yuv
from mvtools.errors import UsageError
from mvtools.geometry.depth import z_to_depth
from mvtools.io.atomic import atomic_output
from mvtools.io.cameras import write_cameras
from mvtools.io.config import write_config
from mvtools.io.images import write_image
from mvtools.io.json_cameras import write_json_cameras
from mvtools.io.pose_trace import POSE_TRACE_CONVENTIONS
from mvtools.io.yuv import YuvFormat, frame_from_luma, open_writer
from mvtools.params import DersParams, VsrsParams

PARTS = ("line", "arc", "distorted", "checkerboard")
# Board poses of the distorted array's own captures: its pictures are small (256x192 by
# default), so the board fills fewer of them than the 640x480 rig's.
DISTORTED_CAPTURES = 20


@click.command(name="scene", cls=ProgramCommand)
@click.argument("out_dir", type=click.Path(file_okay=False))
@click.option(
    "--size",
    callback=parse_size,
    default="256x192",
    show_default=True,
    metavar="WxH",
    help="Picture size of the rig views (multiples of 8).",
)
@click.option(
    "--frames",
    type=click.IntRange(min=1),
    default=3,
    show_default=True,
    help="Frames per view; the foreground objects move 2-3 px per frame.",
)
@click.option(
    "--views",
    type=click.IntRange(min=3),
    default=5,
    show_default=True,
    help="Cameras per rig (and in the calibration rig).",
)
@click.option(
    "--seed",
    type=int,
    default=0,
    show_default=True,
    help="Seed of the textures, the lens/colour imperfections and the board poses.",
)
@click.option(
    "--samples",
    type=click.IntRange(1, 16),
    default=4,
    show_default=True,
    help="Anti-aliasing: samples x samples rays per pixel.",
)
@click.option(
    "--captures",
    type=click.IntRange(min=1),
    default=12,
    show_default=True,
    help="Checkerboard poses of the calibration captures.",
)
@click.option(
    "--capture-size",
    callback=parse_size,
    default="640x480",
    show_default=True,
    metavar="WxH",
    help="Picture size of the calibration captures (at least 64x48).",
)
@click.option(
    "--capture-noise",
    type=FiniteFloat(min=0),
    default=0.0,
    show_default=True,
    help="Standard deviation of the noise added to the captures (grey levels); "
    "noise-free captures compress ten times better, which keeps sample_data small.",
)
@click.option(
    "--part",
    "parts",
    multiple=True,
    type=click.Choice(PARTS),
    help="Write only this part (repeatable; default: all).",
)
@click.option(
    "--path",
    "pose_trace",
    type=click.Path(dir_okay=False, exists=True),
    default=None,
    help="Render only the scene along this pose trace (docs/pose-trace.md) with the rig "
    "cameras' intrinsics: OUT_DIR/path_texture_WxH_yuv420p.yuv, frame k of the scene at "
    "pose k (frame 0 with --still); the truth of an mvtools navigate path.",
)
@click.option(
    "--pose-convention",
    type=click.Choice(POSE_TRACE_CONVENTIONS),
    default="omaf",
    show_default=True,
    help="Axes of the --path pose trace's angles.",
)
@click.option("--still", is_flag=True, help="Every pose of --path sees frame 0 of the scene.")
@program
def command(
    out_dir,
    size,
    frames,
    views,
    seed,
    samples,
    captures,
    capture_size,
    capture_noise,
    parts,
    pose_trace,
    pose_convention,
    still,
):
    """Render the synthetic multiview scene into OUT_DIR, with exact ground truth.

    \b
    line/          5 parallel cameras (1D mode): textures, depth maps, cameras,
                   a VSRS and a DERS configuration for the middle camera
    arc/           the same for 5 cameras on an arc (general mode)
    distorted/     the line as built: lens distortion, small rotations, colour mismatch
    checkerboard/  calibration captures of a 5-camera rig and their truth
    README.md, truth.json

    The same options give the same bytes.
    """
    width, height = size
    if width % 8 or height % 8:
        raise UsageError(
            f"--size {width}x{height}: width and height must be multiples of 8 (4:2:0 "
            "chroma, VSRS row alignment)"
        )
    if capture_size[0] < 64 or capture_size[1] < 48:
        raise UsageError(f"--capture-size {capture_size[0]}x{capture_size[1]}: at least 64x48")
    # the scene's renderer compiles numba kernels: loaded for a run, not for --help
    from mvtools.scene import calibration_rig, default_scene, random_color_mismatches, sample_rigs

    parts = parts or PARTS
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    scene = default_scene(seed=seed)
    depth_range = (scene.znear, scene.zfar)
    rigs = sample_rigs(width, height, n=views, depth_range=depth_range, seed=seed)
    if pose_trace is not None:
        _write_path(out, scene, rigs["line"][0], pose_trace, pose_convention, still, samples)
        return
    mismatches = random_color_mismatches(views, seed=seed, reference=views // 2)
    rig_parts = [part for part in PARTS[:3] if part in parts]
    progress = Progress(len(rig_parts) * views * frames, "views")
    for part in rig_parts:
        folder = out / part
        folder.mkdir(exist_ok=True)
        distorted = part == "distorted"
        _write_views(
            folder,
            rigs[part],
            scene,
            frames=frames,
            samples=samples,
            mismatches=mismatches if distorted else None,
            depth8=not distorted,
            progress=progress,
        )
        write_cameras(folder / "cameras.txt", rigs[part])
        if not distorted:
            # The MPEG-I JSON format holds no lens distortion.
            write_json_cameras(
                folder / "cameras.json", rigs[part], depth_range=depth_range, frame_count=frames
            )
            _write_configs(
                folder,
                rigs[part],
                width=width,
                height=height,
                frames=frames,
                depth_range=depth_range,
                general=part == "arc",
            )
        if distorted:
            # the array's own calibration captures, for the chain capture -> calibrate ->
            # rectify: boards near the middle of the line, seen by most of its cameras
            _write_checkerboard(
                folder / "checkerboard",
                rigs[part],
                count=DISTORTED_CAPTURES,
                noise=capture_noise,
                seed=seed + 2,
                distance=(0.6, 0.9),
                lateral=0.15,
            )
    if "checkerboard" in parts:
        _write_checkerboard(
            out / "checkerboard",
            calibration_rig(n=views, size=tuple(capture_size), seed=seed),
            count=captures,
            noise=capture_noise,
            seed=seed + 1,
        )
    _write_json(
        out / "truth.json",
        _scene_truth(scene, rigs, mismatches, width=width, height=height, frames=frames, seed=seed),
    )
    with atomic_output(out / "README.md", "w") as handle:
        handle.write(
            _readme(
                scene,
                width=width,
                height=height,
                frames=frames,
                views=views,
                captures=captures,
                capture_size=tuple(capture_size),
                capture_noise=capture_noise,
                samples=samples,
                seed=seed,
            )
        )


def _write_path(out: Path, scene, template, trace, convention, still, samples) -> None:
    """The scene seen from each pose of a pose trace, with the intrinsics of ``template``."""
    from mvtools.io.pose_trace import read_pose_trace
    from mvtools.scene import render

    cameras = read_pose_trace(trace, convention=convention, template=template)
    width, height = template.size
    progress = Progress(len(cameras), "poses")
    with open_writer(
        out / f"path_texture_{width}x{height}_yuv420p.yuv", YuvFormat(width, height)
    ) as video:
        for k, camera in enumerate(cameras):
            result = render(scene, camera, frame=0 if still else k, samples=samples)
            video.write(rgb_to_yuv(result.color))
            progress.advance()


def _texture_name(index: int, width: int, height: int) -> str:
    return f"v{index}_texture_{width}x{height}_yuv420p.yuv"


def _depth_name(index: int, width: int, height: int, pix_fmt: str) -> str:
    return f"v{index}_depth_{width}x{height}_{pix_fmt}.yuv"


def _write_views(folder: Path, cameras, scene, *, frames, samples, mismatches, depth8, progress):
    """Texture (4:2:0), 8-bit depth (4:2:0, chroma 128) and 16-bit depth (4:0:0) per view."""
    from mvtools.scene import render

    znear, zfar = scene.znear, scene.zfar
    for index, camera in enumerate(cameras):
        width, height = camera.size
        texture_format = YuvFormat(width, height)
        depth16_format = YuvFormat(width, height, chroma="400", bits=16)
        with contextlib.ExitStack() as stack:
            texture = stack.enter_context(
                open_writer(folder / _texture_name(index, width, height), texture_format)
            )
            depth16 = stack.enter_context(
                open_writer(
                    folder / _depth_name(index, width, height, depth16_format.pix_fmt),
                    depth16_format,
                )
            )
            depth8 = (
                stack.enter_context(
                    open_writer(
                        folder / _depth_name(index, width, height, texture_format.pix_fmt),
                        texture_format,
                    )
                )
                if depth8
                else None
            )
            for frame in range(frames):
                result = render(scene, camera, frame=frame, samples=samples)
                color = (
                    result.color if mismatches is None else mismatches[index].apply(result.color)
                )
                texture.write(rgb_to_yuv(color))
                depth16.write((z_to_depth(result.depth, znear, zfar, bits=16),))
                if depth8 is not None:
                    depth8.write(
                        frame_from_luma(
                            texture_format, z_to_depth(result.depth, znear, zfar, bits=8)
                        )
                    )
                progress.advance()


def _write_configs(folder: Path, cameras, *, width, height, frames, depth_range, general):
    """VSRS: the middle camera from its neighbours; DERS: the middle camera's depth."""
    middle = len(cameras) // 2
    left, center, right = cameras[middle - 1], cameras[middle], cameras[middle + 1]
    znear, zfar = depth_range
    common = {
        "depth_type": 0,
        "source_width": width,
        "source_height": height,
        "start_frame": 0,
        "total_number_of_frames": frames,
    }
    vsrs = VsrsParams(
        **common,
        left_nearest_depth_value=znear,
        left_farthest_depth_value=zfar,
        right_nearest_depth_value=znear,
        right_farthest_depth_value=zfar,
        camera_parameter_file="cameras.txt",
        left_camera_name=left.name,
        virtual_camera_name=center.name,
        right_camera_name=right.name,
        left_view_image_name=_texture_name(middle - 1, width, height),
        right_view_image_name=_texture_name(middle + 1, width, height),
        left_depth_map_name=_depth_name(middle - 1, width, height, "yuv420p"),
        right_depth_map_name=_depth_name(middle + 1, width, height, "yuv420p"),
        output_virtual_view_image_name=f"synthesized_v{middle}_texture_{width}x{height}_yuv420p.yuv",
        synthesis_mode=0 if general else 1,
    )
    write_config(folder / f"synthesize_{center.name}.cfg", vsrs)
    if general:
        # Converging cameras have no single disparity: search z directly.
        search = {
            "nearest_search_depth_value": znear,
            "farthest_search_depth_value": zfar,
            "number_of_depth_steps": 128,
        }
    else:
        # Disparity to the farther neighbour (BaselineBasis 1) over the scene's z range.
        baseline = max(abs(center.t[0] - left.t[0]), abs(right.t[0] - center.t[0]))
        lowest = int(np.floor(center.fx * baseline / zfar))
        highest = int(np.ceil(center.fx * baseline / znear))
        search = {
            "minimum_value_of_disparity_search_range": lowest,
            "maximum_value_of_disparity_search_range": highest,
            "minimum_value_of_disparity_range": lowest,
            "maximum_value_of_disparity_range": highest,
        }
    ders = DersParams(
        **common,
        **search,
        left_camera_name=left.name,
        center_camera_name=center.name,
        right_camera_name=right.name,
        file_left_view_image=_texture_name(middle - 1, width, height),
        file_center_view_image=_texture_name(middle, width, height),
        file_right_view_image=_texture_name(middle + 1, width, height),
        file_output_depth_map_image=f"estimated_v{middle}_depth_{width}x{height}_yuv420p.yuv",
        file_camera_parameter="cameras.txt",
        # Depth values on the same Znear/Zfar scale as the ground truth maps.
        nearest_depth_value=znear,
        farthest_depth_value=zfar,
    )
    write_config(folder / f"depth_{center.name}.cfg", ders)


def _camera_truth(camera) -> dict:
    return {
        "name": camera.name,
        "K": camera.K.tolist(),
        "R": camera.R.tolist(),
        "t": camera.t.tolist(),
        "distortion": camera.distortion.tolist(),
        "size": list(camera.size),
    }


def _scene_truth(scene, rigs, mismatches, *, width, height, frames, seed) -> dict:
    return {
        "generator": f"mvtools {mvtools.__version__} scene, seed {seed}",
        "units": "metres; pixels for K and image positions",
        "camera_convention": "x_cam = R (X - t): t is the camera centre, R world-to-camera; "
        "x right, y down, z forward; pixel centres at integer (u, v)",
        "depth": "z along each camera's axis (DepthType 0) of the pixel-centre ray; "
        "8-bit and 16-bit maps: v = round(vmax (1/z - 1/zfar) / (1/znear - 1/zfar))",
        "znear": scene.znear,
        "zfar": scene.zfar,
        "size": [width, height],
        "frames": frames,
        "rigs": {
            name: [_camera_truth(camera) for camera in cameras] for name, cameras in rigs.items()
        },
        "color_mismatch": {
            "model": "out = clip(gain * in ** gamma + offset, 0, 1) per RGB channel on [0, 1] "
            "values, before the BT.601 limited-range YUV conversion",
            "cameras": {
                camera.name: {
                    "gain": list(m.gain),
                    "offset": list(m.offset),
                    "gamma": list(m.gamma),
                }
                for camera, m in zip(rigs["distorted"], mismatches)
            },
        },
        "objects": [
            {
                "name": p.name,
                "kind": type(p).__name__.lower(),
                "velocity_per_frame": p.velocity.tolist(),
            }
            for p in scene.primitives
        ],
    }


def _write_checkerboard(folder: Path, cameras, *, count, noise, seed, **poses):
    """Captures of the board at ``count`` poses (:func:`board_poses` with ``seed`` and
    ``poses``) by ``cameras``, with their truth."""
    from mvtools.scene import Checkerboard, board_poses, capture_checkerboard

    board = Checkerboard()
    rotations, translations = board_poses(count, cameras, board, seed=seed, **poses)
    for camera in cameras:
        (folder / camera.name).mkdir(parents=True, exist_ok=True)
    progress = Progress(count, "board poses")
    poses = []
    for p, (rotation, translation) in enumerate(zip(rotations, translations)):
        # One pose at a time: progress to show, and images not all held at once.
        captured = capture_checkerboard(
            cameras, board, rotation[None], translation[None], noise=noise, seed=(seed, p)
        )
        for c, camera in enumerate(cameras):
            write_image(folder / camera.name / f"capture{p:02d}.png", captured.images[c, 0])
        poses.append(
            {
                "image": f"{{camera}}/capture{p:02d}.png",
                "rotation": rotation.tolist(),
                "translation": translation.tolist(),
                "visible": {
                    camera.name: bool(captured.visible[c, 0]) for c, camera in enumerate(cameras)
                },
                "corners": {
                    camera.name: captured.corners[c, 0].tolist() for c, camera in enumerate(cameras)
                },
            }
        )
        progress.advance()
    truth = {
        "units": "metres; pixels for K and corner positions (pixel centres at integers)",
        "camera_convention": "x_cam = R (X - t); distortion (k1, k2) in OpenCV's model",
        "board": {
            "inner_corners": list(board.inner_corners),
            "square_size": board.square_size,
            "border": board.border,
            "object_points": "corner (i, j) at (i * square_size, j * square_size, 0), "
            "row by row (i fastest), OpenCV's order",
            "pose": "X_world = rotation @ X_board + translation",
        },
        "noise_std": noise,
        "cameras": [_camera_truth(camera) for camera in cameras],
        "captures": poses,
    }
    _write_json(folder / "truth.json", truth)


def _write_json(path: Path, document: dict) -> None:
    with atomic_output(path, "w") as handle:
        handle.write(_json_text(document) + "\n")


def _json_text(value, indent: str = "") -> str:
    """JSON with one line per list of numbers (a matrix row, a corner), readable and diffable."""
    inner = indent + "  "
    if isinstance(value, dict):
        items = [
            f"{inner}{json.dumps(key)}: {_json_text(item, inner)}" for key, item in value.items()
        ]
        return "{\n" + ",\n".join(items) + "\n" + indent + "}" if items else "{}"
    if isinstance(value, list) and any(isinstance(item, (dict, list)) for item in value):
        return (
            "[\n"
            + ",\n".join(inner + _json_text(item, inner) for item in value)
            + "\n"
            + indent
            + "]"
        )
    return json.dumps(value)


def _readme(
    scene, *, width, height, frames, views, captures, capture_size, capture_noise, samples, seed
) -> str:
    middle = views // 2
    distorted_captures = DISTORTED_CAPTURES
    return f"""# mvtools sample data

Written by `mvtools scene` (mvtools {mvtools.__version__}, seed {seed}): a synthetic scene
ray-cast exactly, so every depth, camera and corner position below is known.
Rebuild with `mvtools scene OUT_DIR --size {width}x{height} --frames {frames} \
--views {views} --seed {seed} --samples {samples} --captures {captures} \
--capture-size {capture_size[0]}x{capture_size[1]} --capture-noise {capture_noise:g}`;
the same options give the same bytes.

## Scene and conventions

- Units: metres. World axes: x right, y down, z forward (the middle camera of the line
  looks along +z from the origin). The ground is the plane y = 1.
- Background wall at z = 10, ground, a slanted panel, a cylinder (static); a box, a sphere
  and a floating card move by 2-3 px per frame (`truth.json` gives their velocities).
  Textures are procedural and view-independent (Lambertian shading, no specular).
- Cameras: `x_cam = R (X - t)`, `t` the camera centre, `R` world-to-camera (VSRS 4.x),
  pixel centres at integer coordinates. Camera `i` is `cam{{i}}`, camera 0 the leftmost.
- Depth: z along each camera's own axis (DepthType 0) of the ray through the pixel
  centre; colour is the mean of {samples}x{samples} rays per pixel.
- Depth maps: Znear = {scene.znear:g}, Zfar = {scene.zfar:g} (every surface seen lies
  between); value v of vmax (255 or 65535) means
  `1/z = (v / vmax) (1/Znear - 1/Zfar) + 1/Zfar`, vmax = nearest.
- Textures: BT.601 limited-range YUV 4:2:0, 8 bit.

## Files

- `line/`: {views} parallel cameras 0.1 m apart, focal length {0.9375 * width:g} px,
  principal point at the picture centre.
  - `v{{i}}_texture_{width}x{height}_yuv420p.yuv`: {frames} frames of view i.
  - `v{{i}}_depth_{width}x{height}_yuv420p.yuv`: 8-bit depth, chroma planes 128 (MPEG).
  - `v{{i}}_depth_{width}x{height}_gray16le.yuv`: 16-bit depth, luma only.
  - `cameras.txt`: MPEG camera parameter file; `cameras.json`: MPEG-I JSON (OMAF axes).
  - `synthesize_cam{middle}.cfg`: VSRS, 1D mode, camera {middle} from cameras {middle - 1} and
    {middle + 1}; `v{middle}_texture_*` is the real view to score the result against.
  - `depth_cam{middle}.cfg`: DERS, depth of camera {middle} from its neighbours; the disparity
    range covers the scene and the output uses the same Znear/Zfar as the truth.
- `arc/`: the same for {views} cameras on an arc of radius 4.5 m, 5 degrees apart, all
  looking at (0, 0, 4.5); the VSRS configuration uses the general mode and the DERS one
  searches z from Znear to Zfar.
- `distorted/`: the line as built: each camera turned by up to 0.5 degree, principal points
  within 2 px, focal lengths within 1 %, lens distortion k1, k2 (in `cameras.txt`) and a
  colour mismatch (camera {middle} is the colour reference). Textures and 16-bit depth as
  above (depth along the ray of each distorted pixel). Ground truth for rectification and
  colour correction. `distorted/checkerboard/`: the array's own calibration captures
  (`cam{{j}}/capture{{k:02d}}.png`, {width}x{height}, {distorted_captures} board poses near the
  middle of the line, the same board) and their `truth.json`, for the chain capture ->
  calibrate -> rectify.
- `checkerboard/`: calibration captures of a {views}-camera rig (not quite parallel, fx close to
  fy, different principal points, k1 in [-0.1, 0.1]): `cam{{j}}/capture{{k:02d}}.png`, grey,
  {capture_size[0]}x{capture_size[1]}, {captures} board poses (tilted 10-40 degrees; the
  board is out of some cameras' view at some poses), Gaussian noise of
  {capture_noise:g} grey level. The board has 9x6 inner corners, 50 mm squares.
  `checkerboard/truth.json`: cameras (K, distortion, R, t), board poses and the exact
  pixel position of every inner corner in every capture (through the distortion).
- `truth.json`: all rigs' cameras (K, R, t, distortion), Znear/Zfar, the colour mismatch
  model and values, the moving objects' velocities.
"""
