"""``mvtools rectify`` end to end on the sample scene's array as built (cameras turned by
up to 0.5 degree, lens distortion), on a published MPEG camera file, and on bad input.

The measure of a rectification is what it is for: view synthesis in 1D mode on the
rectified views must do at least as well as general mode on the views as built
(measured: 36.4 dB against 30.5 dB Y-PSNR for camera 2 from cameras 1 and 3).
"""

from __future__ import annotations

import contextlib
import shutil
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner
from program_runner import assert_one_line_error, invoke
from shared_data import shared_data

from mvtools.cli import rectify
from mvtools.cli.main import cli
from mvtools.geometry.lens import project_points
from mvtools.geometry.projection import backproject, project
from mvtools.io.cameras import read_cameras
from mvtools.io.yuv import YuvFormat, open_video
from mvtools.metrics import psnr

SAMPLE = Path(__file__).resolve().parent.parent / "sample_data"
DISTORTED = SAMPLE / "distorted"
TEXTURE = "v{}_texture_256x192_yuv420p.yuv"
DEPTH = "v{}_depth_256x192_gray16le.yuv"


def program(*args, cwd: Path):
    with contextlib.chdir(cwd):
        result = CliRunner().invoke(cli, [str(arg) for arg in args])
    if result.exception is not None and not isinstance(result.exception, SystemExit):
        raise result.exception
    assert result.exit_code == 0, result.stderr
    return result.stdout


def synthesis_config(folder: Path, mode: int) -> Path:
    """The sample line's VSRS configuration for camera 2 from cameras 1 and 3, reading
    the 16-bit depth maps, in 1D (1) or general (0) mode."""
    lines = []
    for line in (SAMPLE / "line" / "synthesize_cam2.cfg").read_text().splitlines():
        line = line.replace("depth_256x192_yuv420p", "depth_256x192_gray16le")
        if line.startswith("SynthesisMode"):
            line = f"SynthesisMode {mode}"
        lines.append(line)
    path = folder / f"synthesize_mode{mode}.cfg"
    path.write_text("\n".join(lines) + "\n")
    return path


def mean_luma_psnr(reference: Path, test: Path) -> float:
    fmt = YuvFormat(256, 192)
    with open_video(reference, fmt) as truth, open_video(test, fmt) as result:
        return float(np.mean([psnr(a[0], b[0], max_value=255) for a, b in zip(truth, result)]))


@pytest.fixture(scope="module")
def rectified(tmp_path_factory):
    out = tmp_path_factory.mktemp("rectified")
    arguments = [DISTORTED / "cameras.txt", "-o", out, "--depth-range", 2, 13]
    for view in (1, 2, 3):
        arguments += ["--view", f"cam{view}", DISTORTED / TEXTURE.format(view)]
    for view in (1, 3):
        arguments += ["--depth", f"cam{view}", DISTORTED / DEPTH.format(view)]
    code, stdout, stderr = invoke(rectify.command, *arguments)
    assert code == 0, stderr
    return out, stdout


def test_rectified_cameras_share_orientation_and_intrinsics(rectified):
    out, stdout = rectified
    cameras = read_cameras(out / "cameras.txt")
    assert list(cameras) == ["cam1", "cam2", "cam3"]
    for camera in cameras.values():
        np.testing.assert_array_equal(camera.R, np.eye(3))
        np.testing.assert_array_equal(camera.K, cameras["cam1"].K)
        assert camera.K[0, 0] == camera.K[1, 1]
        np.testing.assert_array_equal(camera.distortion, 0.0)
    # the centres, 0.1 m apart on a line, are turned with the world but stay on a line
    # along x, as far apart as they were
    centres = np.array([camera.t for camera in cameras.values()])
    np.testing.assert_allclose(np.diff(centres[:, 0]), 0.1, rtol=1e-9)
    np.testing.assert_allclose(centres[:, 1:] - centres[0, 1:], 0.0, atol=1e-12)
    assert "cam2" in stdout


def test_points_project_to_the_same_row_in_every_rectified_camera(rectified):
    out, _ = rectified
    cameras = list(read_cameras(out / "cameras.txt").values())
    rng = np.random.default_rng(5)
    points = np.column_stack(
        [rng.uniform(-1, 1, 200), rng.uniform(-0.7, 0.7, 200), rng.uniform(2, 13, 200)]
    )
    rows = np.array([project(camera, points)[0][:, 1] for camera in cameras])
    assert np.max(np.abs(rows - rows[0])) < 1e-9


def test_one_d_synthesis_on_rectified_views_beats_general_mode_on_the_views_as_built(
    rectified, tmp_path
):
    out, _ = rectified
    program("synthesize", synthesis_config(out, 1), "-o", "synthesized.yuv", "-q", cwd=out)
    rectified_score = mean_luma_psnr(out / TEXTURE.format(2), out / "synthesized.yuv")
    built = tmp_path / "built"
    shutil.copytree(DISTORTED, built)
    program("synthesize", synthesis_config(built, 0), "-o", "synthesized.yuv", "-q", cwd=built)
    built_score = mean_luma_psnr(built / TEXTURE.format(2), built / "synthesized.yuv")
    assert rectified_score >= built_score
    # measured 36.4 dB; a rectification with a wrong row or scale loses several dB
    assert rectified_score > 35.0


def test_keep_world_keeps_the_centres_and_a_common_rotation(tmp_path):
    code, _, stderr = invoke(
        rectify.command,
        DISTORTED / "cameras.txt",
        "--camera",
        "cam0",
        "--camera",
        "cam4",
        "--camera-size",
        "256x192",
        "--keep-world",
        "-o",
        tmp_path,
    )
    assert code == 0, stderr
    source = read_cameras(DISTORTED / "cameras.txt")
    result = read_cameras(tmp_path / "cameras.txt")
    np.testing.assert_array_equal(result["cam0"].R, result["cam4"].R)
    for name in ("cam0", "cam4"):
        np.testing.assert_allclose(result[name].t, source[name].t, atol=1e-12)
    # x along the baseline, which runs along world x here
    np.testing.assert_allclose(result["cam0"].R[0], [1.0, 0.0, 0.0], atol=1e-12)


def test_frame_range_streams_only_the_frames_asked(tmp_path):
    code, _, stderr = invoke(
        rectify.command,
        DISTORTED / "cameras.txt",
        "-o",
        tmp_path,
        "--view",
        "cam1",
        DISTORTED / TEXTURE.format(1),
        "--view",
        "cam3",
        DISTORTED / TEXTURE.format(3),
        "--start-frame",
        1,
        "--frames",
        1,
    )
    assert code == 0, stderr
    size = (tmp_path / TEXTURE.format(1)).stat().st_size
    assert size == 256 * 192 * 3 // 2


def test_published_linear_array_rectifies_to_one_orientation(tmp_path):
    camera_file = shared_data("mpeg", "vsrs_camera_parameters", "cam_param_poznan_street.txt")
    names = [f"param_cam{index}" for index in range(9)]
    code, stdout, stderr = invoke(
        rectify.command,
        camera_file,
        "--camera-size",
        "1920x1088",
        *(arg for name in names for arg in ("--camera", name)),
        "-o",
        tmp_path,
    )
    assert code == 0, stderr
    cameras = read_cameras(tmp_path / "cameras.txt")
    assert list(cameras) == names
    for camera in cameras.values():
        np.testing.assert_array_equal(camera.R, np.eye(3))
        np.testing.assert_array_equal(camera.K, cameras[names[0]].K)
    assert all(name in stdout for name in names)


@pytest.mark.parametrize(
    "arguments, code, fragment",
    [
        (["--camera", "cam1", "--camera", "nosuch", "--camera-size", "256x192"], 2, "nosuch"),
        (["--camera", "cam1", "--camera", "cam3"], 2, "no picture size"),
        ([], 2, "--camera"),
        (
            [
                "--view",
                "cam1",
                str(DISTORTED / TEXTURE.format(1)),
                "--camera",
                "cam3",
                "--camera",
                "cam4",
                "--camera-size",
                "256x192",
            ],
            2,
            "not among the cameras",
        ),
        (
            [
                "--depth",
                "cam1",
                str(DISTORTED / DEPTH.format(1)),
                "--camera",
                "cam1",
                "--camera",
                "cam3",
                "--camera-size",
                "256x192",
            ],
            2,
            "--depth-range",
        ),
        (
            ["--camera", "cam1", "--camera", "cam3", "--camera-size", "256x192", "--alpha", "2"],
            2,
            "--alpha",
        ),
        (["--camera", "cam1", "--camera-size", "256x192"], 2, "two cameras"),
        (
            [
                "--camera",
                "cam1",
                "--camera",
                "cam3",
                "--camera-size",
                "320x240",
                "--view",
                "cam1",
                str(DISTORTED / TEXTURE.format(1)),
            ],
            1,
            "cam3 320x240",
        ),
    ],
)
def test_bad_input_is_one_line_and_writes_nothing(tmp_path, arguments, code, fragment):
    out = tmp_path / "out"
    result = invoke(rectify.command, DISTORTED / "cameras.txt", "-o", out, *arguments)
    assert result[0] == code
    assert_one_line_error(result[2], fragment)
    assert not out.exists() or not any(out.iterdir())


def test_refuses_to_overwrite_its_input(tmp_path):
    shutil.copy(DISTORTED / "cameras.txt", tmp_path)
    shutil.copy(DISTORTED / TEXTURE.format(1), tmp_path)
    shutil.copy(DISTORTED / TEXTURE.format(3), tmp_path)
    before = (tmp_path / TEXTURE.format(1)).read_bytes()
    code, _, stderr = invoke(
        rectify.command,
        tmp_path / "cameras.txt",
        "-o",
        tmp_path,
        "--view",
        "cam1",
        tmp_path / TEXTURE.format(1),
        "--view",
        "cam3",
        tmp_path / TEXTURE.format(3),
    )
    assert code == 2
    assert_one_line_error(stderr, "overwrite")
    assert (tmp_path / TEXTURE.format(1)).read_bytes() == before


def test_undistort_keeps_each_camera_where_it_looks(tmp_path):
    code, _, stderr = invoke(
        rectify.command,
        DISTORTED / "cameras.txt",
        "--undistort",
        "--view",
        "cam4",
        DISTORTED / TEXTURE.format(4),
        "-o",
        tmp_path,
    )
    assert code == 0, stderr
    source = read_cameras(DISTORTED / "cameras.txt")["cam4"]
    result = read_cameras(tmp_path / "cameras.txt")
    assert list(result) == ["cam4"]
    np.testing.assert_allclose(result["cam4"].R, source.R, atol=1e-12)
    np.testing.assert_allclose(result["cam4"].t, source.t, atol=1e-12)
    np.testing.assert_array_equal(result["cam4"].distortion, 0.0)
    # The same ray in both pictures shows the same colour: an output pixel's ray, found
    # through the undistorted camera, meets the source picture where the lens model
    # (mvtools.geometry.lens, the renderer's own) puts it.
    with open_video(DISTORTED / TEXTURE.format(4), YuvFormat(256, 192)) as video:
        before = np.asarray(video.read(0)[0], np.float64)
    with open_video(tmp_path / TEXTURE.format(4), YuvFormat(256, 192)) as video:
        after = np.asarray(video.read(0)[0], np.float64)
    v, u = np.mgrid[20:172:7, 20:236:7]
    u, v = u.ravel().astype(np.float64), v.ravel().astype(np.float64)
    points = backproject(result["cam4"], u, v, np.full(u.shape, 5.0))
    su, sv = project_points(source, points)[0].T
    x0, y0 = np.floor(su).astype(int), np.floor(sv).astype(int)
    fx, fy = su - x0, sv - y0
    sampled = (1 - fy) * ((1 - fx) * before[y0, x0] + fx * before[y0, x0 + 1]) + fy * (
        (1 - fx) * before[y0 + 1, x0] + fx * before[y0 + 1, x0 + 1]
    )
    output = after[v.astype(int), u.astype(int)]
    # measured 0.25 grey levels (the output's own bilinear sampling); the input itself,
    # not undistorted, is 2.5 levels off at the same places
    assert np.mean(np.abs(output - sampled)) < 0.6
    assert np.mean(np.abs(before[v.astype(int), u.astype(int)] - sampled)) > 2.0


def test_virtual_cameras_between_neighbours(tmp_path):
    code, _, stderr = invoke(
        rectify.command,
        DISTORTED / "cameras.txt",
        "--camera",
        "cam1",
        "--camera",
        "cam2",
        "--camera",
        "cam3",
        "--camera-size",
        "256x192",
        "--virtual",
        3,
        "-o",
        tmp_path,
    )
    assert code == 0, stderr
    cameras = read_cameras(tmp_path / "cameras.txt")
    assert list(cameras) == [
        "cam1",
        "cam2",
        "cam3",
        "cam1_cam2_1",
        "cam1_cam2_2",
        "cam1_cam2_3",
        "cam2_cam3_1",
        "cam2_cam3_2",
        "cam2_cam3_3",
    ]
    # a quarter, a half and three quarters of the way, in the rectified frame
    for k in (1, 2, 3):
        np.testing.assert_allclose(
            cameras[f"cam1_cam2_{k}"].t,
            cameras["cam1"].t + k / 4 * (cameras["cam2"].t - cameras["cam1"].t),
            atol=1e-12,
        )
        np.testing.assert_array_equal(cameras[f"cam2_cam3_{k}"].R, np.eye(3))
        np.testing.assert_array_equal(cameras[f"cam2_cam3_{k}"].K, cameras["cam2"].K)
    code, _, stderr = invoke(
        rectify.command,
        DISTORTED / "cameras.txt",
        "--camera",
        "cam1",
        "--camera-size",
        "256x192",
        "--undistort",
        "--virtual",
        1,
        "-o",
        tmp_path / "out",
    )
    assert code == 2 and not (tmp_path / "out").exists()
