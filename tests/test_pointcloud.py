"""Views with depth as point clouds (the chapter's fig. 1.10) and clouds rendered back.

Truth: hand-computed points and z-buffers, the input views themselves (a cloud rendered
into its own camera), the synthesizer's view of a neighbouring camera, the depth
formula written out from K, R, t, and plyfile reading the files."""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
import plyfile
import pytest

from mvtools.cli.pointcloud import command
from mvtools.color.space import rgb_to_yuv, yuv_to_rgb
from mvtools.geometry.camera import Camera
from mvtools.geometry.depth import DepthCoding
from mvtools.io.camera_files import read_camera_file
from mvtools.io.yuv import YuvFormat, open_video, read_frame
from mvtools.metrics.psnr import psnr
from mvtools.run.pointcloud import ReferenceVideo, views_to_ply
from mvtools.synthesis.pipeline import Synthesizer
from mvtools.synthesis.pointcloud import PointCloud, points_from_views, render_point_cloud
from mvtools.synthesis.views import ReferenceView, SynthesisOptions
from mvtools.synthesis.working import from_working, to_working
from tests.program_runner import assert_one_line_error, invoke
from tests.shared_data import shared_data

LINE = Path(__file__).resolve().parent.parent / "sample_data" / "line"
SIZE = (256, 192)
CODING = DepthCoding((2.0, 13.0), 8)


def _line_view(index: int, frame: int = 0):
    texture = read_frame(LINE / f"v{index}_texture_256x192_yuv420p.yuv", index=frame)
    depth = read_frame(LINE / f"v{index}_depth_256x192_yuv420p.yuv", index=frame)[0]
    return texture, CODING.z(depth)


def _luma(rgb):
    return rgb_to_yuv(np.clip(rgb / 255.0, 0.0, 1.0), chroma="420")[0]


@pytest.fixture(scope="module")
def line_cameras():
    return read_camera_file(LINE / "cameras.txt")


def test_one_view_gives_one_point_per_valid_pixel_at_the_hand_computed_place():
    camera = Camera("c", [[4, 0, 1.5], [0, 4, 1], [0, 0, 1]], t=[1.0, 2.0, 3.0])
    z = np.array([[2.0, np.inf, 4.0], [np.nan, -1.0, 8.0]])
    rgb = np.arange(18, dtype=np.uint8).reshape(2, 3, 3)
    cloud = points_from_views([(camera, rgb, z)])
    # X = t + z ((u - cx) / fx, (v - cy) / fy, 1) for the identity rotation
    expected = [
        [1 + 2 * -1.5 / 4, 2 + 2 * -1 / 4, 5],
        [1 + 4 * 0.5 / 4, 2 - 4 / 4, 7],
        [1 + 8 * 0.5 / 4, 2 + 0, 11],
    ]
    np.testing.assert_allclose(cloud.points, expected, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(cloud.colors, rgb.reshape(-1, 3)[[0, 2, 5]])


def test_a_second_camera_adds_only_what_the_first_does_not_hold():
    first = Camera("a", [[10, 0, 2], [0, 10, 2], [0, 0, 1]])
    second = Camera("b", [[10, 0, 2], [0, 10, 2], [0, 0, 1]])  # the same camera
    rgb = np.zeros((5, 5, 3), np.uint8)
    z = np.full((5, 5), 5.0)
    near = z.copy()
    near[2, 2] = 4.0  # 20 % nearer: another surface
    slightly = z * 1.005  # 0.5 %: the same surface at 1 %, another at 0.1 %
    assert len(points_from_views([(first, rgb, z), (second, rgb, z)])) == 25
    assert len(points_from_views([(first, rgb, z), (second, rgb, near)])) == 26
    assert len(points_from_views([(first, rgb, z), (second, rgb, slightly)])) == 25
    assert (
        len(points_from_views([(first, rgb, z), (second, rgb, slightly)], merge_tolerance=0.001))
        == 50
    )


@pytest.mark.parametrize("splatting", ["bilinear", "point", "spacing"])
def test_the_nearest_point_wins_and_points_behind_are_dropped(splatting):
    camera = Camera("c", [[2, 0, 0.5], [0, 2, 0.5], [0, 0, 1]])
    # pixel (0, 0) from (-0.25, -0.25, 1) and (-1, -1, 4); a point behind the camera
    # that would project onto pixel (1, 1)
    cloud = PointCloud(
        [[-1.0, -1.0, 4.0], [-0.25, -0.25, 1.0], [-0.25, -0.25, -1.0]],
        [[255, 0, 0], [0, 255, 0], [0, 0, 255]],
    )
    rgb, z, holes = render_point_cloud(
        cloud, camera, size=(2, 2), hole_filling=None, splatting=splatting
    )
    assert z[0, 0] == 1.0 and rgb[0, 0].tolist() == [0, 255, 0]
    assert rgb[1, 1].tolist() != [0, 0, 255]
    if splatting != "spacing":  # whose splats of lone points cover the picture
        assert holes[1, 1] and rgb[1, 1].tolist() == [0, 0, 0]


def test_the_line_scene_rendered_into_its_own_camera_is_the_view(line_cameras):
    texture, z = _line_view(1)
    cloud = points_from_views([(line_cameras["cam1"], yuv_to_rgb(texture), z)])
    assert len(cloud) == SIZE[0] * SIZE[1]
    rgb, rendered_z, holes = render_point_cloud(cloud, line_cameras["cam1"], size=SIZE)
    value = psnr(texture[0], _luma(rgb), max_value=255)
    print(f"cam1 cloud into cam1: Y-PSNR {value:.2f} dB, {holes.sum()} holes")
    assert value >= 45.0
    assert not holes.any()
    np.testing.assert_allclose(rendered_z, z, rtol=1e-12)


def test_the_line_scene_rendered_into_a_neighbour_is_as_good_as_synthesis(line_cameras):
    texture, z = _line_view(1)
    target, _ = _line_view(2)
    cloud = points_from_views([(line_cameras["cam1"], yuv_to_rgb(texture), z)])
    rgb, _, _ = render_point_cloud(cloud, line_cameras["cam2"], size=SIZE)
    ours = psnr(target[0], _luma(rgb), max_value=255)
    synthesizer = Synthesizer(
        line_cameras["cam2"],
        [line_cameras["cam1"]],
        SynthesisOptions(mode="general"),
        size=SIZE,
        depth_range=(2.0, 13.0),
    )
    result = synthesizer.frame(
        [ReferenceView(line_cameras["cam1"], to_working(texture, color_space=0, bits=8), z)]
    )
    synthesized = psnr(
        target[0], from_working(result.color, color_space=0, bits=8)[0], max_value=255
    )
    print(f"cam1 into cam2: point cloud {ours:.2f} dB, synthesize {synthesized:.2f} dB")
    assert ours >= synthesized - 1.0


def test_five_cameras_merge_into_fewer_points_and_still_render_cam2(line_cameras):
    views = []
    for index in range(5):
        texture, z = _line_view(index)
        views.append((line_cameras[f"cam{index}"], yuv_to_rgb(texture), z))
    start = time.perf_counter()
    cloud = points_from_views(views)
    seconds = time.perf_counter() - start
    one = SIZE[0] * SIZE[1]
    print(
        f"five cameras: {len(cloud)} points ({len(cloud) / one:.2f} x one camera), "
        f"{seconds * 1000:.0f} ms"
    )
    assert one < len(cloud) < 5 * one
    rgb, _, _ = render_point_cloud(cloud, line_cameras["cam2"], size=SIZE)
    value = psnr(_line_view(2)[0][0], _luma(rgb), max_value=255)
    print(f"five-camera cloud into cam2: Y-PSNR {value:.2f} dB")
    assert value >= 40.0


def test_kendo_view_1_to_ply_puts_each_pixel_where_the_depth_formula_says(tmp_path):
    kendo = shared_data("mpeg", "kendo")
    camera = read_camera_file(kendo / "config" / "VSRS" / "cam_param_kendo.cfg")["param_kendo01"]
    znear, zfar = 448.251214, 11206.280350  # vsrs_kendo_ori.cfg, Left*DepthValue
    fmt = YuvFormat(1024, 768)
    output = tmp_path / "kendo1.ply"
    with (
        open_video(kendo / "kendo_ori_I_1.yuv", fmt) as texture,
        open_video(kendo / "kendo_ori_D_1.yuv", fmt) as depth,
    ):
        start = time.perf_counter()
        views_to_ply(
            [ReferenceVideo(camera, texture, depth, DepthCoding((znear, zfar), 8))], output
        )
        seconds = time.perf_counter() - start
        values = depth.read(0)[0].astype(np.float64)
    vertex = plyfile.PlyData.read(str(output))["vertex"]
    points = np.stack([vertex[name] for name in "xyz"], axis=-1).astype(np.float64)
    print(f"Kendo view 1: {len(points)} points in {seconds:.2f} s")
    assert len(points) == 1024 * 768  # every 8-bit depth value is a valid depth
    # eq. 1.6 of the chapter and X = t + z R^T K^-1 (u, v, 1), by hand
    z = 1.0 / (values / 255.0 * (1.0 / znear - 1.0 / zfar) + 1.0 / zfar)
    v, u = np.mgrid[0:768, 0:1024].astype(np.float64)
    rays = np.stack([u, v, np.ones_like(u)], axis=-1) @ np.linalg.inv(camera.K).T @ camera.R
    expected = camera.t + z[..., None] * rays
    error = np.abs(points - expected.reshape(-1, 3)).max()
    print(f"largest position error {error:.2e} (depth range {zfar - znear:.0f})")
    assert error <= 1e-4 * (zfar - znear)


# --------------------------------------------------------------------------- program


def _to_ply(output, *extra):
    views = []
    for index in (1, 3):
        views += [
            "--view",
            f"cam{index}",
            LINE / f"v{index}_texture_256x192_yuv420p.yuv",
            "--depth",
            f"cam{index}",
            LINE / f"v{index}_depth_256x192_yuv420p.yuv",
        ]
    return invoke(
        command,
        "to-ply",
        LINE / "cameras.txt",
        *views,
        "--depth-range",
        "2",
        "13",
        *extra,
        "-o",
        output,
    )


def test_the_program_writes_a_cloud_and_renders_it_back(tmp_path):
    cloud = tmp_path / "line.ply"
    code, _, err = _to_ply(cloud, "--camera", "cam1", "--frame", "1")
    assert code == 0, err
    vertex = plyfile.PlyData.read(str(cloud))["vertex"]
    assert vertex.count == SIZE[0] * SIZE[1]
    texture = tmp_path / "cam1_256x192_yuv420p.yuv"
    depth = tmp_path / "cam1_depth_256x192_gray16le.yuv"
    code, _, err = invoke(
        command,
        "render",
        cloud,
        LINE / "cameras.txt",
        "--camera",
        "cam1",
        "--depth-range",
        "2",
        "13",
        "-o",
        texture,
        "--depth-output",
        depth,
    )
    assert code == 0, err
    expected, expected_z = _line_view(1, frame=1)
    value = psnr(expected[0], read_frame(texture)[0], max_value=255)
    print(f"program, cam1 frame 1 through PLY (float32) and back: Y-PSNR {value:.2f} dB")
    assert value >= 45.0
    z16 = DepthCoding((2.0, 13.0), 16).z(read_frame(depth)[0])
    np.testing.assert_allclose(z16, expected_z, rtol=1e-3)


def test_the_program_merges_the_views_given(tmp_path):
    cloud = tmp_path / "two.ply"
    code, _, err = _to_ply(cloud)
    assert code == 0, err
    count = plyfile.PlyData.read(str(cloud))["vertex"].count
    assert SIZE[0] * SIZE[1] < count < 2 * SIZE[0] * SIZE[1]


@pytest.mark.parametrize(
    ("arguments", "fragments"),
    [
        (["--camera", "cam2"], ["--camera cam2: no --view cam2"]),
        (["--frame", "3"], ["--frame", "frame 3 asked, the video has 3"]),
        (["--merge-tolerance", "-1"], ["--merge-tolerance"]),
    ],
)
def test_bad_to_ply_options_exit_2_leaving_no_file(tmp_path, arguments, fragments):
    cloud = tmp_path / "bad.ply"
    code, _, err = _to_ply(cloud, *arguments)
    assert code == 2
    assert_one_line_error(err, *fragments)
    assert list(tmp_path.iterdir()) == []


def test_a_view_without_depth_exits_2(tmp_path):
    code, _, err = invoke(
        command,
        "to-ply",
        LINE / "cameras.txt",
        "--view",
        "cam1",
        LINE / "v1_texture_256x192_yuv420p.yuv",
        "--depth-range",
        "2",
        "13",
        "-o",
        tmp_path / "x.ply",
    )
    assert code == 2
    assert_one_line_error(err, "--depth cam1")
    assert list(tmp_path.iterdir()) == []


def test_rendering_a_truncated_ply_exits_1_leaving_no_file(tmp_path):
    cloud = tmp_path / "line.ply"
    assert _to_ply(cloud, "--camera", "cam1")[0] == 0
    short = tmp_path / "short.ply"
    short.write_bytes(cloud.read_bytes()[:-100])
    output = tmp_path / "out_256x192_yuv420p.yuv"
    code, _, err = invoke(
        command, "render", short, LINE / "cameras.txt", "--camera", "cam1", "-o", output
    )
    assert code == 1
    assert_one_line_error(err, str(short), "of 49152: file ends")
    assert not output.exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["line.ply", "short.ply"]


@pytest.mark.parametrize(
    ("arguments", "fragments"),
    [
        (["--camera", "cam9"], ["camera 'cam9' is not in the camera file"]),
        (["--camera", "cam1", "--splatting", "round"], ["splatting must be one of"]),
        (["--camera", "cam1", "--depth-output", "d.yuv"], ["--depth-output needs"]),
    ],
)
def test_bad_render_options_exit_2_leaving_no_file(tmp_path, arguments, fragments):
    cloud = tmp_path / "line.ply"
    assert _to_ply(cloud, "--camera", "cam1")[0] == 0
    output = tmp_path / "out_256x192_yuv420p.yuv"
    code, _, err = invoke(command, "render", cloud, LINE / "cameras.txt", *arguments, "-o", output)
    assert code == 2
    assert_one_line_error(err, *fragments)
    assert [p.name for p in tmp_path.iterdir()] == ["line.ply"]


def test_an_unknown_subcommand_is_one_line_and_exit_2():
    code, _, err = invoke(command, "to-obj")
    assert code == 2
    assert_one_line_error(err, "No such command 'to-obj'")
