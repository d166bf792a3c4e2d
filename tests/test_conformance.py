"""Conformance over the corpus of MPEG camera files: the synthetic scene rendered through
each sequence's own cameras, its depth maps written in that sequence's convention, then
``synthesize`` and ``estimate-depth`` scored against the exact renders.

For every camera file of ``mpeg/vsrs_camera_parameters`` and the Kendo and Poznan Hall 2
folders, a left / virtual / right triple of its cameras (the shipped configuration's
where there is one) is scaled to a picture about 256 pixels wide (fx, fy, cx, cy and the
size together, so the geometry is exact). Textured planes are put at four inverse depths
inside the sequence's range, in front of every camera of the triple: planes of constant
depth along the virtual camera's axis (DepthType 0) or of constant world z (DepthType 1).

The depth maps are written here, independently of :mod:`mvtools.geometry.depth`: the
signed ``z`` of a surface point is computed through the file's own camera
(``x_cam = R (X - t)``, ``z = x_cam[2]``, negative for Poznan) or is its world z, and the
value is ``v = vmax (1/z - 1/Zfar) / (1/Znear - 1/Zfar)`` rounded half up.

A synthesized view is scored by its Y-PSNR against the render over the pixels that some
reference sees (disocclusions and the picture's edges excluded); an estimated depth map
by the share of the pixels seen by both neighbours whose 8-bit value is within
:data:`DEPTH_TOLERANCE` of the truth. The same runs with the range negated, with Znear and
Zfar exchanged in the written maps, or with the rotations transposed in the camera file
score far below the thresholds.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest
from program_runner import assert_one_line_error, invoke
from shared_data import shared_data
from synthesize_runner import run_synthesize

from mvtools.cli.estimate_depth import command as estimate_depth_command
from mvtools.color.space import rgb_to_yuv
from mvtools.geometry.camera import Camera
from mvtools.geometry.depth import facing_camera
from mvtools.geometry.lens import pixel_rays, project_points
from mvtools.io.cameras import get_camera, read_cameras, write_cameras
from mvtools.io.config import load_params, read_config, write_config
from mvtools.io.yuv import YuvFormat, frame_from_luma, read_frame, write_video
from mvtools.params import DersParams, VsrsParams
from mvtools.scene import (
    NoiseTexture,
    Plane,
    Rectangle,
    Scene,
    render,
)

pytestmark = pytest.mark.slow  # `make test-fast` leaves these out

#: Y-PSNR (dB) every synthesized view reaches over the pixels the references see.
SYNTHESIS_THRESHOLD = 30.0
#: Share of the pixels both neighbours see whose estimated 8-bit depth value is within
#: DEPTH_TOLERANCE of the truth.
DEPTH_THRESHOLD = 0.8
DEPTH_TOLERANCE = 8
#: Inverse-depth fractions (0 far, 1 near) of the usable part of a range: the background
#: plane, then three cards.
LAYERS = (0.1, 0.4, 0.65, 0.9)
#: Centres and half sizes of the cards in the virtual picture (fractions of its size).
CARDS = (((0.3, 0.35), (0.16, 0.18)), ((0.68, 0.45), (0.14, 0.2)), ((0.45, 0.72), (0.18, 0.14)))

HALL2_RANGE = (-23.394160, -172.531931)
KENDO_RANGE = (448.251214, 11206.280350)


@dataclass(frozen=True)
class Sequence:
    """One sequence of the corpus as the suite renders it.

    Attributes
    ----------
    name : str
    cameras : str
        Camera file, relative to ``mpeg/``.
    size : (width, height)
        The sequence's picture size.
    scale : float
        Render size / sequence size.
    depth_type : {0, 1}
    ranges : ((znear, zfar), (znear, zfar))
        Of the left and the right depth maps, signed as the files mean them.
    triple : (left, virtual, right)
        Camera names.
    config : str
        The VSRS configuration run (relative to ``mpeg/``): the sequence's own, else the
        one of the sequence it was shot with (same rig, same files family), else the
        generic shipped one; its own cameras, files, size, range and DepthType are given
        on the command line.
    own_config : bool
        Whether ``config`` is the sequence's own (its range and DepthType then come from it).
    """

    name: str
    cameras: str
    size: tuple[int, int]
    scale: float
    depth_type: int
    ranges: tuple[tuple[float, float], tuple[float, float]]
    triple: tuple[str, str, str]
    config: str
    own_config: bool


def _same(depth_range):
    return (depth_range, depth_range)


def _derived_range(path: str, triple) -> tuple[float, float]:
    """For a sequence with no configuration of its own or of its rig: DepthType 0,
    positive, disparities of 48 (Znear) and 3 (Zfar) pixels between the left and right
    cameras at the sequence's size."""
    cameras = read_cameras(shared_data("mpeg", *path.split("/")))
    left, _, right = (cameras[name] for name in triple)
    focal_baseline = left.fx * np.linalg.norm(right.t - left.t)
    return (float(focal_baseline / 48.0), float(focal_baseline / 3.0))


P = "vsrs_camera_parameters/"
C = "vsrs_configs/"
HALL2_CONFIG = "poznan_hall2/config/VSRS/vsrs_poznanhall2_ori.cfg"
KENDO_CONFIG = "kendo/config/VSRS/vsrs_kendo_ori.cfg"
GENERIC_CONFIG = C + "ViewSynthesis.cfg"

# name, camera file, size, scale, DepthType, ranges (or None: derived), triple, config, own
_TABLE = [
    (
        "ak",
        P + "cam_param_ak.txt",
        (640, 480),
        0.4,
        0,
        None,
        ("param_ak26", "inter_ak2627", "param_ak27"),
        GENERIC_CONFIG,
        False,
    ),
    (
        "balloons",
        P + "cam_param_balloons.txt",
        (1024, 768),
        0.25,
        0,
        _same(KENDO_RANGE),
        ("param_balloons01", "param_balloons02", "param_balloons03"),
        KENDO_CONFIG,
        False,
    ),
    (
        "butterfly",
        P + "cam_param_bbb_butterfly2_arc+Znear-far.txt",
        (1280, 768),
        0.25,
        1,
        ((0.464901, -2.424092), (0.512292, -2.491080)),
        ("param_ptm06", "param_ptm10", "param_ptm13"),
        C + "ViewSynthesis_butterfly.cfg",
        True,
    ),
    (
        "book",
        P + "cam_param_book_reg.txt",
        (1024, 768),
        0.25,
        1,
        ((23.344623, 54.470788), (23.175928, 54.077165)),
        ("param_book007", "param_book008", "param_book010"),
        C + "ViewSynthesis_book.cfg",
        True,
    ),
    (
        "champ",
        P + "cam_param_champ.txt",
        (1280, 960),
        0.2,
        0,
        _same((2281.357719, 7045.261474)),
        ("param_champ38", "param_champ39", "param_champ41"),
        C + "ViewSynthesis_champagne.cfg",
        False,
    ),
    (
        "champagne",
        P + "cam_param_champagne.txt",
        (1280, 960),
        0.2,
        0,
        _same((2281.357719, 7045.261474)),
        ("param_champ38", "param_champ39", "param_champ41"),
        C + "ViewSynthesis_champagne.cfg",
        True,
    ),
    (
        "dog",
        P + "cam_param_dog.txt",
        (1280, 960),
        0.2,
        1,
        _same((3907.725727, 8221.650623)),
        ("param_dog38", "param_dog39", "param_dog41"),
        C + "ViewSynthesis_dog.cfg",
        True,
    ),
    (
        "doorflowers",
        P + "cam_param_doorflowers_reg.txt",
        (1024, 768),
        0.25,
        0,
        ((20.948175, 79.603063), (20.804398, 79.056712)),
        ("param_doorflowers007", "param_doorflowers008", "param_doorflowers010"),
        C + "ViewSynthesis_doorflowers.cfg",
        True,
    ),
    (
        "kendo_txt",
        P + "cam_param_kendo.txt",
        (1024, 768),
        0.25,
        0,
        _same(KENDO_RANGE),
        ("param_kendo01", "param_kendo02", "param_kendo03"),
        KENDO_CONFIG,
        False,
    ),
    (
        "laptop",
        P + "cam_param_laptop_reg.txt",
        (1024, 768),
        0.25,
        1,
        ((23.393445, 54.584705), (23.331668, 54.440560)),
        ("param_laptop007", "param_laptop008", "param_laptop010"),
        C + "ViewSynthesis_laptop.cfg",
        True,
    ),
    (
        "lovebird1",
        P + "cam_param_lovebird1.txt",
        (1024, 768),
        0.25,
        1,
        _same((1418.292789, 156012.206895)),
        ("param_loveb1_005", "param_loveb1_006", "param_loveb1_008"),
        C + "ViewSynthesis_lovebird1.cfg",
        True,
    ),
    (
        "lovebird1_original",
        P + "cam_param_lovebird1_original.txt",
        (1024, 768),
        0.25,
        0,
        None,
        ("param_loveb1_005", "param_loveb1_006", "param_loveb1_008"),
        C + "ViewSynthesis_lovebird1.cfg",
        False,
    ),
    (
        "lovebird2",
        P + "cam_param_lovebird2.txt",
        (720, 576),
        1 / 3,
        1,
        _same((3733.743119, 112012.293585)),
        ("param_loveb2_005", "param_loveb2_006", "param_loveb2_008"),
        C + "ViewSynthesis_lovebird2.cfg",
        True,
    ),
    (
        "lovebird2_original",
        P + "cam_param_lovebird2_original.txt",
        (720, 576),
        1 / 3,
        0,
        None,
        ("param_loveb2_005", "param_loveb2_006", "param_loveb2_008"),
        C + "ViewSynthesis_lovebird2.cfg",
        False,
    ),
    (
        "news",
        P + "cam_param_news.txt",
        (1024, 768),
        0.25,
        1,
        _same((3393.977060, 7542.171244)),
        ("param_news03", "param_news05", "param_news06"),
        C + "ViewSynthesis_news.cfg",
        True,
    ),
    (
        "news_orig",
        P + "cam_param_news_orig.txt",
        (1024, 768),
        0.25,
        1,
        _same((3393.977060, 7542.171244)),
        ("param_news03", "param_news05", "param_news06"),
        C + "ViewSynthesis_news.cfg",
        False,
    ),
    (
        "outdoor",
        P + "cam_param_outdoor_reg.txt",
        (1024, 768),
        0.25,
        1,
        ((5.971234, 191.079475), (5.927299, 189.673574)),
        ("param_outdoor007", "param_outdoor008", "param_outdoor010"),
        C + "ViewSynthesis_moabit.cfg",
        True,
    ),
    (
        "pantomime",
        P + "cam_param_pantomime.txt",
        (1280, 960),
        0.2,
        1,
        _same((3907.725727, 8221.650623)),
        ("param_ptm38", "param_ptm39", "param_ptm41"),
        C + "ViewSynthesis_pantomime.cfg",
        True,
    ),
    (
        "poznan_carpark",
        P + "cam_param_poznan_carpark.txt",
        (1920, 1088),
        0.125,
        0,
        _same(HALL2_RANGE),
        ("param_cam3", "param_cam4", "param_cam5"),
        HALL2_CONFIG,
        False,
    ),
    (
        "poznan_hall1",
        P + "cam_param_poznan_hall1.txt",
        (1920, 1088),
        0.125,
        0,
        _same(HALL2_RANGE),
        ("param_cam5", "param_cam6", "param_cam7"),
        HALL2_CONFIG,
        False,
    ),
    (
        "poznan_hall2_txt",
        P + "cam_param_poznan_hall2.txt",
        (1920, 1088),
        0.125,
        0,
        _same(HALL2_RANGE),
        ("param_cam5", "param_cam6", "param_cam7"),
        HALL2_CONFIG,
        False,
    ),
    (
        "poznan_street",
        P + "cam_param_poznan_street.txt",
        (1920, 1088),
        0.125,
        0,
        _same(HALL2_RANGE),
        ("param_cam3", "param_cam4", "param_cam5"),
        HALL2_CONFIG,
        False,
    ),
    (
        "rena",
        P + "cam_param_rena.txt",
        (640, 480),
        0.4,
        0,
        None,
        ("param_rena38", "inter_rena3839", "param_rena39"),
        GENERIC_CONFIG,
        False,
    ),
    (
        "hall2",
        "poznan_hall2/config/VSRS/cam_param_poznanhall2.cfg",
        (1920, 1088),
        0.125,
        0,
        ((-23.394160, -172.531931), (-23.394175, -172.532039)),
        ("param_cam5", "param_cam6", "param_cam7"),
        HALL2_CONFIG,
        True,
    ),
    (
        "kendo",
        "kendo/config/VSRS/cam_param_kendo.cfg",
        (1024, 768),
        0.25,
        0,
        _same(KENDO_RANGE),
        ("param_kendo01", "param_kendo02", "param_kendo03"),
        KENDO_CONFIG,
        True,
    ),
]


def sequence(name: str) -> Sequence:
    """The row ``name`` of the corpus, with a derived range where it has none."""
    row = next(row for row in _TABLE if row[0] == name)
    _, path, size, scale, depth_type, ranges, triple, config, own = row
    if ranges is None:
        ranges = _same(_derived_range(path, triple))
    return Sequence(name, path, size, scale, depth_type, ranges, triple, config, own)


NAMES = [row[0] for row in _TABLE]


# --------------------------------------------------------------------------- the rig


def scaled(camera: Camera, scale: float, size: tuple[int, int]) -> Camera:
    """``camera`` for a picture ``scale`` times the size: pixel centres at integers, so
    ``u' = scale (u + 0.5) - 0.5``."""
    K = camera.K.copy()
    K[:2] *= scale
    K[:2, 2] += 0.5 * scale - 0.5
    return dataclasses.replace(camera, K=K, size=size)


@dataclass
class Rig:
    """The scaled file cameras of a triple and the cameras facing its ranges."""

    files: list[Camera]
    facing: list[Camera]
    size: tuple[int, int]


def rig_of(seq: Sequence) -> Rig:
    cameras = read_cameras(shared_data("mpeg", *seq.cameras.split("/")))
    size = tuple(round(s * seq.scale) for s in seq.size)
    files = [scaled(get_camera(cameras, name), seq.scale, size) for name in seq.triple]
    # Every camera of a view set faces the scene by the left range, as synthesize turns them.
    facing = [facing_camera(camera, seq.ranges[0], depth_type=seq.depth_type) for camera in files]
    return Rig(files, facing, size)


def one_dimensional(views: Views) -> bool:
    """Rectified-parallel: equal rotations, and centres on a line along the cameras' x
    axis to within a quarter of a pixel of parallax at the nearest surface."""
    rig = views.rig
    left = rig.files[0]
    if max(np.abs(camera.R - left.R).max() for camera in rig.files) > 1e-9:
        return False
    nearest = min(render_.depth.min() for render_ in views.renders)
    offsets = [left.R @ (camera.t - left.t) for camera in rig.files[1:]]
    return max(left.fx * np.hypot(*offset[1:]) / nearest for offset in offsets) < 0.25


# --------------------------------------------------------------------------- the scene


def _plane_of(seq: Sequence, rig: Rig, z: float) -> tuple[np.ndarray, float]:
    """Normal ``n`` and offset ``c`` of the plane ``n . X = c`` of the file's signed depth z."""
    if seq.depth_type == 1:
        return np.array([0.0, 0.0, 1.0]), z
    virtual = rig.files[1]
    normal = virtual.R[2]
    return normal, float(normal @ virtual.t + z)


def _hit(camera: Camera, plane, u: float, v: float) -> tuple[np.ndarray, float]:
    """Point of ``plane`` on the ray of pixel (u, v) of facing ``camera``, and its depth."""
    normal, offset = plane
    ray = pixel_rays(camera, np.array([u]), np.array([v]))[0]
    depth = (offset - normal @ camera.t) / (normal @ ray)
    return camera.t + depth * ray, float(depth)


def usable_inverse_depths(seq: Sequence, rig: Rig) -> tuple[float, float]:
    """``1/z`` bounds inside both ranges whose planes lie in front of every camera's
    principal ray (DepthType 1 ranges may reach behind the cameras)."""
    inverse = [sorted((1.0 / znear, 1.0 / zfar)) for znear, zfar in seq.ranges]
    low, high = max(b[0] for b in inverse), min(b[1] for b in inverse)
    grid = np.linspace(low, high, 401)[1:-1]
    grid = grid[grid != 0]

    def in_front(w):
        plane = _plane_of(seq, rig, 1.0 / w)
        return all(_hit(camera, plane, camera.cx, camera.cy)[1] > 0 for camera in rig.facing)

    usable = [w for w in grid if in_front(w)]
    assert usable, f"{seq.name}: no plane of the range lies in front of the cameras"
    return min(usable), max(usable)


def layer_depths(seq: Sequence, rig: Rig) -> list[float]:
    """Signed file depths of the background and the three cards."""
    low, high = usable_inverse_depths(seq, rig)
    return [1.0 / (low + fraction * (high - low)) for fraction in LAYERS]


def layered_scene(seq: Sequence, rig: Rig) -> Scene:
    """A textured background plane and three textured cards in the virtual view."""
    virtual = rig.facing[1]
    width, height = rig.size
    primitives = []
    depths = layer_depths(seq, rig)
    for k, z in enumerate(depths):
        plane = _plane_of(seq, rig, z)
        if k == 0:
            (cu, cv), (hu, hv) = (0.5, 0.5), (0.5, 0.5)
        else:
            (cu, cv), (hu, hv) = CARDS[k - 1]
        u, v = cu * (width - 1), cv * (height - 1)
        centre, depth = _hit(virtual, plane, u, v)
        right = _hit(virtual, plane, u + hu * width, v)[0] - centre
        down = _hit(virtual, plane, u, v + hv * height)[0] - centre
        down -= (down @ right) / (right @ right) * right  # a rectangle, not a rhomb
        # About 6 pixels to a noise cell at this depth.
        texture = NoiseTexture(
            seed=7 + k,
            colors=((0.1 + 0.2 * k, 0.3, 0.7 - 0.15 * k), (0.95, 0.85 - 0.1 * k, 0.4 + 0.1 * k)),
            frequency=virtual.fx / (6.0 * depth),
            octaves=4,
            pattern="checker",
            pattern_period=12.0 * depth / virtual.fx,
        )
        if k == 0:
            primitives.append(
                Plane(
                    "background",
                    point=centre,
                    normal=plane[0],
                    u_axis=right / np.linalg.norm(right),
                    texture=texture,
                )
            )
        else:
            primitives.append(
                Rectangle(f"card{k}", center=centre, half_u=right, half_v=down, texture=texture)
            )
    return Scene(tuple(primitives), light=tuple(-virtual.R[2]), ambient=0.7)


# --------------------------------------------------------------------------- the files


def signed_z(seq: Sequence, file_camera: Camera, facing: Camera, depth: np.ndarray) -> np.ndarray:
    """The file's z of each pixel's surface point: through the file camera
    (``R (X - t)``, DepthType 0) or world z (DepthType 1)."""
    height, width = depth.shape
    v, u = np.mgrid[0:height, 0:width].astype(np.float64)
    points = facing.t + depth.reshape(-1, 1) * pixel_rays(facing, u.ravel(), v.ravel())
    if seq.depth_type == 1:
        return points[:, 2].reshape(depth.shape)
    return ((points - file_camera.t) @ file_camera.R.T)[:, 2].reshape(depth.shape)


def depth_values(z: np.ndarray, depth_range, bits: int) -> np.ndarray:
    """``v = vmax (1/z - 1/Zfar) / (1/Znear - 1/Zfar)``, rounded half up."""
    znear, zfar = depth_range
    vmax = 2**bits - 1
    values = np.floor(vmax * (1.0 / z - 1.0 / zfar) / (1.0 / znear - 1.0 / zfar) + 0.5)
    assert values.min() >= 0 and values.max() <= vmax, "the scene leaves the range"
    return values.astype(np.uint8 if bits == 8 else np.uint16)


@dataclass
class Views:
    """Renders of the triple and the files written from them."""

    seq: Sequence
    rig: Rig
    renders: list
    folder: Path
    camera_file: Path


def render_views(seq: Sequence, folder: Path) -> Views:
    rig = rig_of(seq)
    scene = layered_scene(seq, rig)
    renders = [render(scene, camera, samples=2, size=rig.size) for camera in rig.facing]
    for render_, camera in zip(renders, rig.facing):
        assert np.isfinite(render_.depth).all(), f"{seq.name}: {camera.name} sees past the scene"
    width, height = rig.size
    for role, render_ in zip(("left", "virtual", "right"), renders):
        write_video(
            folder / f"{role}_{width}x{height}_yuv420p.yuv",
            YuvFormat(width, height),
            [rgb_to_yuv(render_.color)],
        )
    camera_file = folder / "cameras.txt"
    write_cameras(camera_file, rig.files)
    return Views(seq, rig, renders, folder, camera_file)


def write_depth(views: Views, role: int, bits: int, *, swap: bool = False) -> Path:
    """The depth map of camera ``role`` (0 left, 2 right) in the sequence's convention;
    ``swap`` writes it with Znear and Zfar exchanged."""
    seq, rig = views.seq, views.rig
    depth_range = seq.ranges[0 if role == 0 else 1]
    z = signed_z(seq, rig.files[role], rig.facing[role], views.renders[role].depth)
    values = depth_values(z, depth_range, bits)
    if swap:
        values = (2**bits - 1 - values).astype(values.dtype)
    width, height = rig.size
    name = ("left", "virtual", "right")[role]
    if bits == 16:
        path = views.folder / f"{name}_depth{'_swapped' * swap}_{width}x{height}_gray16le.yuv"
        write_video(path, YuvFormat(width, height, "400", 16), [(values,)])
    else:
        path = views.folder / f"{name}_depth{'_swapped' * swap}_{width}x{height}_yuv420p.yuv"
        write_video(
            path, YuvFormat(width, height), [frame_from_luma(YuvFormat(width, height), values)]
        )
    return path


# --------------------------------------------------------------------------- scoring


def _edges(index: np.ndarray) -> np.ndarray:
    padded = np.pad(index, 1, mode="edge")
    height, width = index.shape
    edge = np.zeros(index.shape, bool)
    for dy in range(3):
        for dx in range(3):
            edge |= padded[dy : dy + height, dx : dx + width] != index
    return edge


def seen_by(views: Views, role: int) -> np.ndarray:
    """Pixels of the virtual view whose surface point camera ``role`` sees."""
    virtual, rig = views.renders[1], views.rig
    height, width = virtual.depth.shape
    v, u = np.mgrid[0:height, 0:width].astype(np.float64)
    points = rig.facing[1].t + virtual.depth.reshape(-1, 1) * pixel_rays(
        rig.facing[1], u.ravel(), v.ravel()
    )
    uv, z = project_points(rig.facing[role], points)
    column, row = np.floor(uv[:, 0] + 0.5), np.floor(uv[:, 1] + 0.5)
    inside = (z > 0) & (column >= 1) & (column <= width - 2) & (row >= 1) & (row <= height - 2)
    nearest = np.full(z.shape, np.inf)
    nearest[inside] = views.renders[role].depth[row[inside].astype(int), column[inside].astype(int)]
    return (inside & (np.abs(nearest - z) <= 0.01 * z)).reshape(height, width)


def off_edges(views: Views) -> np.ndarray:
    """Pixels of the virtual view whose 8 neighbours show the same surface."""
    return ~_edges(views.renders[1].object_index)


def masked_psnr(output: Path, views: Views, mask: np.ndarray) -> float:
    width, height = views.rig.size
    synthesized = read_frame(output, YuvFormat(width, height))[0].astype(np.float64)
    truth = rgb_to_yuv(views.renders[1].color)[0].astype(np.float64)
    error = np.mean((synthesized[mask] - truth[mask]) ** 2)
    return float(10.0 * np.log10(255.0**2 / max(error, 1e-10)))


# --------------------------------------------------------------------------- runs


def synthesize(views: Views, *, mode: int, bits: int, corruption: str | None = None) -> float:
    """Run ``synthesize`` with the sequence's configuration; the Y-PSNR of its output.

    ``corruption``: "negated" gives the program the ranges with the other sign,
    "swapped" writes the depth maps with Znear and Zfar exchanged, "transposed" gives
    it a camera file with every rotation transposed.
    """
    seq, (width, height) = views.seq, views.rig.size
    left, right = (write_depth(views, role, bits, swap=corruption == "swapped") for role in (0, 2))
    output = views.folder / f"synthesized_{corruption}_{mode}_{bits}_{width}x{height}_yuv420p.yuv"
    sign = -1.0 if corruption == "negated" else 1.0
    (left_near, left_far), (right_near, right_far) = np.multiply(seq.ranges, sign).tolist()
    camera_file = views.camera_file
    if corruption == "transposed":
        camera_file = views.folder / "cameras_transposed.txt"
        write_cameras(
            camera_file, [dataclasses.replace(camera, R=camera.R.T) for camera in views.rig.files]
        )
    code, _, err = run_synthesize(
        shared_data("mpeg", *seq.config.split("/")),
        f"SourceWidth={width}",
        f"SourceHeight={height}",
        "StartFrame=0",
        "TotalNumberOfFrames=1",
        f"DepthType={seq.depth_type}",
        f"SynthesisMode={mode}",
        f"CameraParameterFile={camera_file}",
        f"LeftCameraName={seq.triple[0]}",
        f"VirtualCameraName={seq.triple[1]}",
        f"RightCameraName={seq.triple[2]}",
        f"LeftViewImageName={views.folder / f'left_{width}x{height}_yuv420p.yuv'}",
        f"RightViewImageName={views.folder / f'right_{width}x{height}_yuv420p.yuv'}",
        f"LeftDepthMapName={left}",
        f"RightDepthMapName={right}",
        f"LeftNearestDepthValue={left_near!r}",
        f"LeftFarthestDepthValue={left_far!r}",
        f"RightNearestDepthValue={right_near!r}",
        f"RightFarthestDepthValue={right_far!r}",
        f"OutputVirtualViewImageName={output}",
        cwd=views.folder,
    )
    assert code == 0, err
    mask = (seen_by(views, 0) | seen_by(views, 2)) & off_edges(views)
    return masked_psnr(output, views, mask)


def estimate_depth(views: Views, *, corruption: str | None = None) -> float:
    """Run ``estimate-depth`` for the virtual camera in the sequence's convention (the
    left map's range, 8 bits); the share of the pixels both neighbours see within
    :data:`DEPTH_TOLERANCE` of the true value. ``corruption`` "negated" gives it the
    range with the other sign (and reads its output with it)."""
    seq, rig, (width, height) = views.seq, views.rig, views.rig.size
    sign = -1.0 if corruption == "negated" else 1.0
    znear, zfar = (sign * value for value in seq.ranges[0])
    search_near, search_far = sorted((sign / w for w in usable_inverse_depths(seq, rig)), key=abs)
    config = views.folder / f"ders_{corruption}.cfg"
    output = views.folder / f"estimated_{corruption}_{width}x{height}_yuv420p.yuv"
    write_config(
        config,
        DersParams(
            depth_type=seq.depth_type,
            source_width=width,
            source_height=height,
            total_number_of_frames=1,
            left_camera_name=seq.triple[0],
            center_camera_name=seq.triple[1],
            right_camera_name=seq.triple[2],
            file_left_view_image=f"left_{width}x{height}_yuv420p.yuv",
            file_center_view_image=f"virtual_{width}x{height}_yuv420p.yuv",
            file_right_view_image=f"right_{width}x{height}_yuv420p.yuv",
            file_output_depth_map_image=output.name,
            file_camera_parameter=views.camera_file.name,
            nearest_depth_value=znear,
            farthest_depth_value=zfar,
            nearest_search_depth_value=search_near,
            farthest_search_depth_value=search_far,
            number_of_depth_steps=64,
        ),
    )
    code, _, err = invoke(estimate_depth_command, config, "--data-dir", views.folder, "-o", output)
    assert code == 0, err
    estimated = read_frame(output, YuvFormat(width, height))[0].astype(int)
    truth = depth_values(
        signed_z(seq, rig.files[1], rig.facing[1], views.renders[1].depth), seq.ranges[0], 8
    ).astype(int)
    mask = seen_by(views, 0) & seen_by(views, 2) & off_edges(views)
    return float(np.mean(np.abs(estimated - truth)[mask] <= DEPTH_TOLERANCE))


# --------------------------------------------------------------------------- the tests


#: 1D runs that cannot match the render, and why.
@pytest.fixture(scope="module")
def corpus(tmp_path_factory):
    """``corpus(name)``: the sequence's renders and files, made once per module."""
    made = {}

    def views(name: str) -> Views:
        if name not in made:
            made[name] = render_views(sequence(name), tmp_path_factory.mktemp(name))
        return made[name]

    return views


@pytest.mark.parametrize("name", NAMES)
def test_sequence_synthesis_and_depth_match_the_render(corpus, name):
    views = corpus(name)
    scores = {"general 16-bit": synthesize(views, mode=0, bits=16)}
    if one_dimensional(views):
        scores["1D 8-bit"] = synthesize(views, mode=1, bits=8)
    else:
        scores["general 8-bit"] = synthesize(views, mode=0, bits=8)
    assert min(scores.values()) >= SYNTHESIS_THRESHOLD, scores
    assert estimate_depth(views) >= DEPTH_THRESHOLD


def test_shipped_1d_configurations_have_rectified_cameras(corpus):
    # Every shipped configuration in SynthesisMode 1 names a triple the suite runs in 1D
    # (Lovebird 1's right camera is 0.44 off the line: under a tenth of a pixel here).
    for name in NAMES:
        seq = sequence(name)
        config, _ = load_params(
            VsrsParams, read_config(shared_data("mpeg", *seq.config.split("/")))
        )
        if seq.own_config and config.synthesis_mode == 1:
            assert one_dimensional(corpus(name)), name


@pytest.mark.parametrize(
    "name, corruption",
    [
        (name, corruption)
        for name in ("hall2", "news", "kendo")
        for corruption in ("negated", "swapped")
    ]
    + [("butterfly", "transposed")],
)
def test_corrupted_conventions_fail_by_far(corpus, name, corruption):
    score = synthesize(corpus(name), mode=0, bits=16, corruption=corruption)
    # Measured: 13.5 to 20.6 dB, against 34.6 to 40.3 dB uncorrupted.
    assert score < SYNTHESIS_THRESHOLD - 8, score


@pytest.mark.parametrize("name", ["hall2", "news", "kendo"])
def test_negated_range_fails_depth_estimation_by_far(corpus, name):
    # Measured: at most 0.044 of the pixels within tolerance, against 1.0
    assert estimate_depth(corpus(name), corruption="negated") < DEPTH_THRESHOLD / 4


@pytest.mark.parametrize("name", ["hall2", "news", "kendo"])
def test_symmetric_rotations_hide_a_transposition(corpus, name):
    # Poznan and Kendo (R = I), Newspaper (R = diag(1, -1, -1)): R.T is R, so a camera
    # file written transposed is the same file; the arc of the butterfly shows it.
    assert all(np.array_equal(camera.R, camera.R.T) for camera in corpus(name).rig.files)


# --------------------------------------------------------------------------- shipped configurations

#: Every shipped VSRS configuration, the folder given with --data-dir (relative to
#: ``mpeg/``), and the first input the corpus lacks (None: it has them all).
SHIPPED = [
    (C + "ViewSynthesis.cfg", "vsrs_camera_parameters", "CameraParameterFile", "cam_param_bd.txt"),
    (
        C + "ViewSynthesis_book.cfg",
        "vsrs_camera_parameters",
        "LeftViewImageName",
        "BookArrival_7.yuv",
    ),
    (
        C + "ViewSynthesis_butterfly.cfg",
        "vsrs_camera_parameters",
        "CameraParameterFile",
        "BigBuckBunny_Butterfly2_Arc+Znear-far.txt",
    ),
    (
        C + "ViewSynthesis_champagne.cfg",
        "vsrs_camera_parameters",
        "LeftViewImageName",
        "cmp_38.yuv",
    ),
    (C + "ViewSynthesis_dog.cfg", "vsrs_camera_parameters", "LeftViewImageName", "dog_38.yuv"),
    (
        C + "ViewSynthesis_doorflowers.cfg",
        "vsrs_camera_parameters",
        "LeftViewImageName",
        "DoorFlowers_7.yuv",
    ),
    (
        C + "ViewSynthesis_laptop.cfg",
        "vsrs_camera_parameters",
        "LeftViewImageName",
        "LeavingLaptop_7.yuv",
    ),
    (
        C + "ViewSynthesis_lovebird1.cfg",
        "vsrs_camera_parameters",
        "LeftViewImageName",
        "lovebird1_5.yuv",
    ),
    (
        C + "ViewSynthesis_lovebird2.cfg",
        "vsrs_camera_parameters",
        "LeftViewImageName",
        "lovebird2_5.yuv",
    ),
    (
        C + "ViewSynthesis_moabit.cfg",
        "vsrs_camera_parameters",
        "CameraParameterFile",
        "cam_param_moabit_reg.txt",
    ),
    (
        C + "ViewSynthesis_news.cfg",
        "vsrs_camera_parameters",
        "LeftViewImageName",
        "Newspaper_3.yuv",
    ),
    (
        C + "ViewSynthesis_pantomime.cfg",
        "vsrs_camera_parameters",
        "LeftViewImageName",
        "ptm_38.yuv",
    ),
] + [
    (f"{folder}/config/VSRS/vsrs_{name}_{variant}.cfg", folder, "LeftViewImageName", missing)
    for folder, name, views in (
        ("kendo", "kendo", ()),
        ("poznan_hall2", "poznanhall2", (1, 2, 3, 4, 6, 8)),
    )
    for variant, missing in (
        ("matlab", "tmp_I_l.yuv"),
        ("matlab2", "tmp_I_recon_l.yuv"),
        ("matlab_WMGeneration", "tmp_I_l.yuv"),
        ("ori", None),
    )
    + tuple((f"v{view}", "tmp_I_recon_l.yuv") for view in views)
    + tuple((f"v{view}_ori", None) for view in views)
]


def test_shipped_list_is_complete():
    mpeg = shared_data("mpeg")
    shipped = {
        path.relative_to(mpeg).as_posix()
        for pattern in (
            "vsrs_configs/*.cfg",
            "kendo/config/VSRS/vsrs*.cfg",
            "poznan_hall2/config/VSRS/vsrs*.cfg",
        )
        for path in mpeg.glob(pattern)
    }
    assert shipped == {row[0] for row in SHIPPED}


@pytest.mark.parametrize(
    "config, data_dir, key, missing", SHIPPED, ids=[Path(row[0]).stem for row in SHIPPED]
)
def test_shipped_configuration_runs_unmodified(tmp_path, config, data_dir, key, missing):
    path = shared_data("mpeg", *config.split("/"))
    code, _, err = run_synthesize(
        path, "--data-dir", shared_data("mpeg", *data_dir.split("/")), cwd=tmp_path
    )
    if missing is not None:
        assert code == 2, err
        assert_one_line_error(err, f"{path}:", f"{key}: file ", missing, "not found")
        assert list(tmp_path.iterdir()) == []
        return
    assert code == 0, err
    params, _ = load_params(VsrsParams, read_config(path))
    output = tmp_path / params.output_virtual_view_image_name
    # One frame in the corpus' videos: 4:2:0, 8 bits.
    assert output.stat().st_size == params.source_width * params.source_height * 3 // 2
    assert [item.name for item in tmp_path.iterdir()] == [output.name]
