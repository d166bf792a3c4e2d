"""``mvtools synthesize`` end to end on the sample scene, whose every view is exactly known.

The synthesized camera 2 is scored against the real view 2 (``v2_texture``). The
thresholds sit far above what a broken warp gives: copying a neighbouring view
instead of synthesizing scores 19-21 dB, a warp with a wrong sign or baseline lower
still. Bad input must give one line naming the place at fault, the right exit code
and no output file.
"""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from mirrored_world import write_mirrored_cameras
from shared_data import shared_data
from synthesize_runner import run_synthesize

from mvtools.errors import DataError
from mvtools.geometry.depth import depth_to_z, z_to_depth
from mvtools.geometry.projection import backproject, pixel_grid
from mvtools.io.cameras import read_cameras
from mvtools.io.yuv import YuvFormat, frame_from_luma, open_video, write_video
from mvtools.metrics import psnr
from mvtools.synthesis import pipeline

SAMPLE = Path(__file__).resolve().parent.parent / "sample_data"
LINE, ARC = SAMPLE / "line", SAMPLE / "arc"
FORMAT = YuvFormat(256, 192)
ZNEAR, ZFAR = 2.0, 13.0
OUTPUT = "synthesized_v2_texture_256x192_yuv420p.yuv"

# Mean Y-PSNR of camera 2 over the 3 frames: measured 41.0 dB (line, 1D mode) and
# 36.8 dB (arc, general mode); copying view 1 instead gives 21.3 and 19.0 dB.
LINE_MIN_PSNR = 39.0
ARC_MIN_PSNR = 35.0


run = run_synthesize


def assert_one_line_error(stderr: str, *fragments: str) -> None:
    lines = [line for line in stderr.splitlines() if "error:" in line.lower()]
    assert len(lines) == 1, stderr
    assert "Traceback" not in stderr
    for fragment in fragments:
        assert fragment in lines[0], lines[0]


def frames_of(path: Path, fmt: YuvFormat = FORMAT) -> list[tuple[np.ndarray, ...]]:
    with open_video(path, fmt) as video:
        return [tuple(np.array(plane) for plane in frame) for frame in video]


def mean_luma_psnr(
    reference: Path, test: Path, fmt: YuvFormat = FORMAT, *, start: int = 0
) -> float:
    truth = frames_of(reference, fmt)[start:]
    result = frames_of(test, fmt)
    assert len(result) <= len(truth)
    return float(
        np.mean([psnr(ref[0], out[0], max_value=fmt.max_value) for ref, out in zip(truth, result)])
    )


def copy_psnr(folder: Path) -> float:
    """Y-PSNR of simply copying view 1 as view 2: what no synthesis must fall to."""
    return mean_luma_psnr(
        folder / "v2_texture_256x192_yuv420p.yuv", folder / "v1_texture_256x192_yuv420p.yuv"
    )


# --------------------------------------------------------------------- quality


@pytest.mark.parametrize(
    "folder, minimum",
    [(LINE, LINE_MIN_PSNR), (ARC, ARC_MIN_PSNR)],
    ids=["line-1d-mode", "arc-general-mode"],
)
def test_sample_scene_camera_2_matches_the_real_view(tmp_path, folder, minimum):
    code, _, err = run(folder / "synthesize_cam2.cfg", "--data-dir", folder, cwd=tmp_path)
    assert code == 0, err
    score = mean_luma_psnr(folder / "v2_texture_256x192_yuv420p.yuv", tmp_path / OUTPUT)
    assert len(frames_of(tmp_path / OUTPUT)) == 3
    assert score >= minimum
    assert score >= copy_psnr(folder) + 10


@pytest.mark.parametrize(
    "folder, minimum",
    [(LINE, LINE_MIN_PSNR), (ARC, ARC_MIN_PSNR)],
    ids=["line-1d-mode", "arc-general-mode"],
)
def test_negative_depth_ranges_of_a_mirrored_world(tmp_path, folder, minimum):
    """Poznan's convention: the same rig in the world mirrored through its origin, with
    the depth ranges negated, synthesizes the same view."""
    data = tmp_path / "data"
    shutil.copytree(folder, data)
    write_mirrored_cameras(data / "cameras.txt", data / "cameras.txt")
    negated = [
        f"{side}{end}DepthValue={-value:g}"
        for side in ("Left", "Right")
        for end, value in (("Nearest", ZNEAR), ("Farthest", ZFAR))
    ]
    code, _, err = run(data / "synthesize_cam2.cfg", *negated, "--frames", 1, cwd=tmp_path)
    assert code == 0, err
    score = mean_luma_psnr(folder / "v2_texture_256x192_yuv420p.yuv", tmp_path / OUTPUT)
    assert score >= minimum
    assert score >= copy_psnr(folder) + 10


def test_one_reference_given_as_left_and_right_extrapolates(tmp_path):
    # Camera 2 from camera 1 alone: the disocclusions are filled, the rest is warped.
    code, _, err = run(
        ARC / "synthesize_cam2.cfg",
        "RightCameraName=cam1",
        "RightViewImageName=v1_texture_256x192_yuv420p.yuv",
        "RightDepthMapName=v1_depth_256x192_yuv420p.yuv",
        "--data-dir",
        ARC,
        cwd=tmp_path,
    )
    assert code == 0, err
    score = mean_luma_psnr(ARC / "v2_texture_256x192_yuv420p.yuv", tmp_path / OUTPUT)
    # Measured 30.4 dB (copying view 1: 19.0 dB).
    assert score >= 28.5


def test_more_than_two_references_with_view_option(tmp_path):
    # Cameras 0, 1, 3 and 4 together: the two far ones add little, but must not spoil.
    views = []
    for index in (0, 4):
        views += [
            "--view",
            f"cam{index}",
            ARC / f"v{index}_texture_256x192_yuv420p.yuv",
            "--depth",
            f"cam{index}",
            ARC / f"v{index}_depth_256x192_yuv420p.yuv",
        ]
    code, _, err = run(
        ARC / "synthesize_cam2.cfg",
        *views,
        "--depth-range",
        ZNEAR,
        ZFAR,
        "--frames",
        1,
        cwd=tmp_path,
    )
    assert code == 0, err
    score = mean_luma_psnr(ARC / "v2_texture_256x192_yuv420p.yuv", tmp_path / OUTPUT)
    assert score >= ARC_MIN_PSNR - 1


def test_16_bit_depth_maps_by_name(tmp_path):
    code, _, err = run(
        LINE / "synthesize_cam2.cfg",
        "LeftDepthMapName=v1_depth_256x192_gray16le.yuv",
        "RightDepthMapName=v3_depth_256x192_gray16le.yuv",
        "--output-depth",
        "depth_256x192_gray16le.yuv",
        "--data-dir",
        LINE,
        cwd=tmp_path,
    )
    assert code == 0, err
    assert (
        mean_luma_psnr(LINE / "v2_texture_256x192_yuv420p.yuv", tmp_path / OUTPUT) >= LINE_MIN_PSNR
    )
    # The depth output has the input depth maps' format: 16-bit luma only.
    depth_format = YuvFormat(256, 192, "400", 16)
    written = frames_of(tmp_path / "depth_256x192_gray16le.yuv", depth_format)
    truth = frames_of(LINE / "v2_depth_256x192_gray16le.yuv", depth_format)
    assert len(written) == 3
    z_written = depth_to_z(written[0][0], ZNEAR, ZFAR, bits=16)
    z_truth = depth_to_z(truth[0][0], ZNEAR, ZFAR, bits=16)
    assert np.mean(np.abs(z_written / z_truth - 1) < 0.02) > 0.9


def test_10_bit_textures_give_a_10_bit_output(tmp_path):
    fmt10 = YuvFormat(256, 192, bits=10)
    for index in (1, 3):
        frames = frames_of(ARC / f"v{index}_texture_256x192_yuv420p.yuv")
        write_video(
            tmp_path / f"v{index}_256x192_yuv420p10le.yuv",
            fmt10,
            [tuple(plane.astype(np.uint16) * 4 for plane in frame) for frame in frames],
        )
    output = "out_256x192_yuv420p10le.yuv"
    code, _, err = run(
        ARC / "synthesize_cam2.cfg",
        "LeftViewImageName=v1_256x192_yuv420p10le.yuv",
        "RightViewImageName=v3_256x192_yuv420p10le.yuv",
        "-o",
        output,
        "--data-dir",
        ARC,
        cwd=tmp_path,
    )
    assert code == 0, err
    written = frames_of(tmp_path / output, fmt10)
    assert len(written) == 3
    truth = frames_of(ARC / "v2_texture_256x192_yuv420p.yuv")
    score = np.mean(
        [
            psnr(ref[0].astype(np.uint16) * 4, out[0], max_value=1023)
            for ref, out in zip(truth, written)
        ]
    )
    assert score >= ARC_MIN_PSNR


def test_depth_type_1_world_z_depth_maps(tmp_path):
    # The arc's cameras turn by 5 degrees: world z differs from depth along each axis.
    # The same scene given as world-z depth maps (DepthType 1) gives the same view.
    cameras = read_cameras(ARC / "cameras.txt")
    depth_format = YuvFormat(256, 192, "400", 16)
    u, v = pixel_grid(256, 192)
    for index in (1, 3):
        frames = frames_of(ARC / f"v{index}_depth_256x192_gray16le.yuv", depth_format)
        world = [
            backproject(cameras[f"cam{index}"], u, v, depth_to_z(frame[0], ZNEAR, ZFAR, bits=16))[
                ..., 2
            ]
            for frame in frames
        ]
        write_video(
            tmp_path / f"w{index}_256x192_gray16le.yuv",
            depth_format,
            [(z_to_depth(z, 1.0, 20.0, bits=16),) for z in world],
        )
    common = ["--data-dir", ARC, "--frames", 1]
    code, _, err = run(
        ARC / "synthesize_cam2.cfg",
        "LeftDepthMapName=v1_depth_256x192_gray16le.yuv",
        "RightDepthMapName=v3_depth_256x192_gray16le.yuv",
        "-o",
        "camera_z.yuv",
        *common,
        cwd=tmp_path,
    )
    assert code == 0, err
    world_settings = [
        "DepthType=1",
        "LeftDepthMapName=w1_256x192_gray16le.yuv",
        "RightDepthMapName=w3_256x192_gray16le.yuv",
        "--left-nearest-depth-value",
        1,
        "--left-farthest-depth-value",
        20,
        "--right-nearest-depth-value",
        1,
        "--right-farthest-depth-value",
        20,
    ]
    code, _, err = run(
        ARC / "synthesize_cam2.cfg",
        *world_settings,
        "-o",
        "world_z.yuv",
        "--output-depth",
        "world_depth.yuv",
        *common,
        cwd=tmp_path,
    )
    assert code == 0, err
    truth = frames_of(ARC / "v2_texture_256x192_yuv420p.yuv")[0][0]
    camera_z = frames_of(tmp_path / "camera_z.yuv")[0][0]
    world_z = frames_of(tmp_path / "world_z.yuv")[0][0]
    assert psnr(truth, world_z, max_value=255) >= psnr(truth, camera_z, max_value=255) - 0.5
    # The depth output holds world z too (camera 2 looks along world z: the same values).
    written = depth_to_z(
        frames_of(tmp_path / "world_depth.yuv", depth_format)[0][0], 1.0, 20.0, bits=16
    )
    real = depth_to_z(
        frames_of(ARC / "v2_depth_256x192_gray16le.yuv", depth_format)[0][0], ZNEAR, ZFAR, bits=16
    )
    assert np.mean(np.abs(written / real - 1) < 0.02) > 0.9


def test_json_cameras_give_the_same_view(tmp_path):
    code, _, err = run(ARC / "synthesize_cam2.cfg", "--frames", 1, cwd=tmp_path)
    assert code == 0, err
    text_cameras = (tmp_path / OUTPUT).read_bytes()
    code, _, err = run(
        ARC / "synthesize_cam2.cfg",
        "CameraParameterFile=cameras.json",
        "--frames",
        1,
        "--data-dir",
        ARC,
        cwd=tmp_path,
    )
    assert code == 0, err
    reference = frames_of_bytes(text_cameras)
    result = frames_of(tmp_path / OUTPUT)
    # The JSON file stores the same cameras in other axes (rounding differs in the
    # last digits): the pictures agree to within rounding of a few samples.
    assert psnr(reference[0][0], result[0][0], max_value=255) > 50


def frames_of_bytes(data: bytes) -> list[tuple[np.ndarray, ...]]:
    luma = FORMAT.width * FORMAT.height
    samples = np.frombuffer(data, np.uint8).reshape(-1, FORMAT.frame_bytes)
    return [(frame[:luma].reshape(FORMAT.height, FORMAT.width),) for frame in samples]


# --------------------------------------------------------------------- outputs and frames


def test_output_is_deterministic(tmp_path):
    first, second = tmp_path / "a", tmp_path / "b"
    for folder in (first, second):
        folder.mkdir()
        code, _, err = run(
            LINE / "synthesize_cam2.cfg",
            "BoundaryNoiseRemoval=1",
            "--output-depth",
            "d.yuv",
            "--output-holes",
            "h.yuv",
            cwd=folder,
        )
        assert code == 0, err
    for name in (OUTPUT, "d.yuv", "h.yuv"):
        assert (first / name).read_bytes() == (second / name).read_bytes(), name


def test_frame_range_options_and_keys(tmp_path):
    code, _, err = run(ARC / "synthesize_cam2.cfg", "-o", "all.yuv", cwd=tmp_path)
    assert code == 0, err
    everything = (tmp_path / "all.yuv").read_bytes()
    frame = FORMAT.frame_bytes
    code, _, err = run(
        ARC / "synthesize_cam2.cfg",
        "--start-frame",
        1,
        "--frames",
        1,
        "-o",
        "one.yuv",
        cwd=tmp_path,
    )
    assert code == 0, err
    assert (tmp_path / "one.yuv").read_bytes() == everything[frame : 2 * frame]
    code, _, err = run(ARC / "synthesize_cam2.cfg", "StartFrame=2", "-o", "last.yuv", cwd=tmp_path)
    assert code == 0, err
    assert "using 1" in err
    assert (tmp_path / "last.yuv").read_bytes() == everything[2 * frame :]


def test_start_frame_past_the_end(tmp_path):
    code, _, err = run(ARC / "synthesize_cam2.cfg", "StartFrame=3", cwd=tmp_path)
    assert code == 2
    assert_one_line_error(err, "past the end", "3 frames")
    assert list(tmp_path.iterdir()) == []


def test_depth_and_hole_outputs(tmp_path):
    # Camera 2 from camera 1 alone: camera 2 sits 0.1 m to the right of camera 1, so
    # a point moves left by 240 * 0.1 / z >= 1.8 px (z <= 13): no point of camera 1
    # lands in the last column of camera 2, which must be all holes.
    code, _, err = run(
        LINE / "synthesize_cam2.cfg",
        "RightCameraName=cam1",
        "RightViewImageName=v1_texture_256x192_yuv420p.yuv",
        "RightDepthMapName=v1_depth_256x192_yuv420p.yuv",
        "--output-depth",
        "d_256x192_yuv420p.yuv",
        "--output-holes",
        "holes.yuv",
        "--data-dir",
        LINE,
        cwd=tmp_path,
    )
    assert code == 0, err
    holes = frames_of(tmp_path / "holes.yuv", YuvFormat(256, 192, "400"))
    assert len(holes) == 3
    for (mask,) in holes:
        assert set(np.unique(mask)) <= {0, 255}
        assert np.all(mask[:, -1] == 255)
        assert 0 < np.mean(mask == 255) < 0.1
    # Where a view saw the scene, the virtual depth is the real depth of camera 2.
    depth = frames_of(tmp_path / "d_256x192_yuv420p.yuv")
    truth = frames_of(LINE / "v2_depth_256x192_yuv420p.yuv")
    for (mask,), written, real in zip(holes, depth, truth):
        seen = mask == 0
        assert np.all(written[1] == 128) and np.all(written[2] == 128)
        error = np.abs(written[0].astype(int) - real[0].astype(int))[seen]
        assert np.mean(error <= 1) > 0.95


def test_output_depth_range_option(tmp_path):
    code, _, err = run(
        ARC / "synthesize_cam2.cfg",
        "--frames",
        1,
        "--output-depth",
        "d.yuv",
        "--output-depth-range",
        1.0,
        100.0,
        cwd=tmp_path,
    )
    assert code == 0, err
    written = frames_of(tmp_path / "d.yuv")[0][0]
    truth = frames_of(ARC / "v2_depth_256x192_yuv420p.yuv")[0][0]
    expected = z_to_depth(depth_to_z(truth, ZNEAR, ZFAR), 1.0, 100.0)
    assert np.mean(np.abs(written.astype(int) - expected.astype(int)) <= 1) > 0.9


# --------------------------------------------------------------------- shipped configuration


def test_shipped_kendo_config_runs_unmodified(tmp_path):
    kendo = shared_data("mpeg", "kendo")
    code, _, err = run(
        kendo / "config" / "VSRS" / "vsrs_kendo_ori.cfg", "--data-dir", kendo, cwd=tmp_path
    )
    assert code == 0, err
    assert "asked for 300 frames" in err and "using 1" in err
    fmt = YuvFormat(1024, 768)
    output = tmp_path / "kendo_syn_ori.yuv"
    assert output.stat().st_size == fmt.frame_bytes
    # Camera 2 lies between cameras 1 and 3: the synthesized view is closer to each of
    # them than they are to each other.
    view = frames_of(output, fmt)[0][0]
    one = frames_of(kendo / "kendo_ori_I_1.yuv", fmt)[0][0]
    three = frames_of(kendo / "kendo_ori_I_3.yuv", fmt)[0][0]
    apart = psnr(one, three, max_value=255)
    assert psnr(view, one, max_value=255) > apart
    assert psnr(view, three, max_value=255) > apart


@pytest.mark.slow
def test_installed_program_runs(tmp_path):
    completed = subprocess.run(
        [
            sys.executable,
            "-m",
            "mvtools",
            "synthesize",
            str(LINE / "synthesize_cam2.cfg"),
            "--frames",
            "1",
            "-q",
        ],
        capture_output=True,
        text=True,
        cwd=tmp_path,
    )
    assert completed.returncode == 0, completed.stderr
    assert completed.stderr == ""
    assert (tmp_path / OUTPUT).stat().st_size == FORMAT.frame_bytes


# --------------------------------------------------------------------- bad input


def _config_copy(tmp_path: Path, folder: Path = LINE) -> Path:
    """The sample folder's configuration and files, copied so they can be spoiled."""
    data = tmp_path / "data"
    shutil.copytree(folder, data)
    return data / "synthesize_cam2.cfg"


@pytest.mark.parametrize(
    "setting, code, fragments",
    [
        ("VirtualCameraName=cam9", 2, ("VirtualCameraName", "no camera 'cam9'")),
        ("VirtualCameraName=", 2, ("VirtualCameraName", "no camera name given")),
        ("LeftCameraName=", 2, ("LeftCameraName", "without LeftCameraName")),
        ("LeftNearestDepthValue=13", 2, ("LeftNearestDepthValue", "farther than Zfar")),
        ("LeftNearestDepthValue=-2", 2, ("LeftNearestDepthValue", "opposite signs")),
        (
            "LeftNearestDepthValue=-2 LeftFarthestDepthValue=-13",
            2,
            (
                "LeftNearestDepthValue",
                "-2 and 2 have opposite signs",
                "opposite sides of their cameras",
            ),
        ),
        ("Precision=3", 2, ("Precision", "3 is not one of 1, 2, 4")),
        ("SynthesisMode=2", 2, ("SynthesisMode", "not one of 0, 1")),
        ("ColorSpace=1", 2, ("ColorSpace", "1D mode")),
        ("LeftViewImageName=missing.yuv", 2, ("LeftViewImageName", "not found")),
        ("OutputVirtualViewImageName=", 2, ("OutputVirtualViewImageName", "no output file")),
        ("OutputVirtualViewImageName=nowhere/out.yuv", 2, ("does not exist",)),
    ],
    ids=[
        "unknown-camera",
        "no-virtual-camera",
        "no-left-camera",
        "znear-farther-than-zfar",
        "range-through-zero",
        "left-and-right-on-opposite-sides",
        "precision",
        "synthesis-mode",
        "rgb-in-1d-mode",
        "missing-file",
        "no-output",
        "output-folder",
    ],
)
def test_bad_settings(tmp_path, setting, code, fragments):
    exit_code, _, err = run(
        LINE / "synthesize_cam2.cfg", *setting.split(), "--frames", 1, cwd=tmp_path
    )
    assert exit_code == code, err
    assert_one_line_error(err, *fragments)
    assert list(tmp_path.iterdir()) == []


def test_depth_map_of_another_size(tmp_path):
    small = YuvFormat(128, 96)
    write_video(
        tmp_path / "d_128x96_yuv420p.yuv",
        small,
        [frame_from_luma(small, np.full((96, 128), 100, np.uint8))] * 3,
    )
    write_video(
        tmp_path / "unnamed.yuv",
        small,
        [frame_from_luma(small, np.full((96, 128), 100, np.uint8))] * 3,
    )
    for name, fragment in (
        ("d_128x96_yuv420p.yuv", "the file name says 128x96"),
        ("unnamed.yuv", "not a whole number of 256x192 yuv420p frames"),
    ):
        code, _, err = run(LINE / "synthesize_cam2.cfg", f"RightDepthMapName={name}", cwd=tmp_path)
        assert code == 1, err
        assert_one_line_error(err, name, fragment)
    assert sorted(path.name for path in tmp_path.iterdir()) == [
        "d_128x96_yuv420p.yuv",
        "unnamed.yuv",
    ]


def test_mismatched_frame_counts_use_the_shortest(tmp_path):
    config = _config_copy(tmp_path)
    frames = frames_of(config.parent / "v3_depth_256x192_yuv420p.yuv")
    write_video(config.parent / "v3_depth_256x192_yuv420p.yuv", FORMAT, frames[:2])
    code, _, err = run(config, cwd=tmp_path)
    assert code == 0, err
    assert "inputs differ in length" in err and "v3_depth_256x192_yuv420p.yuv has 2" in err
    assert (tmp_path / OUTPUT).stat().st_size == 2 * FORMAT.frame_bytes


def test_bad_view_option(tmp_path):
    texture, depth = LINE / "v0_texture_256x192_yuv420p.yuv", LINE / "v0_depth_256x192_yuv420p.yuv"
    config = LINE / "synthesize_cam2.cfg"
    view = ("--view", "cam0", texture, "--depth", "cam0", depth)
    for arguments, fault, message in (
        ((*view, "--depth-range", 13, 2), "--depth-range", "Znear 13 is farther than Zfar 2"),
        (("--view", "camX", texture, "--depth", "camX", depth), "--view camX", "no camera 'camX'"),
        (("--view", "cam0", texture), "--view cam0", "give its depth video with --depth cam0"),
        (("--depth", "cam0", depth), "--depth cam0", "has no --view cam0"),
    ):
        code, _, err = run(config, *arguments, cwd=tmp_path)
        assert code == 2, arguments
        assert_one_line_error(err, fault, message)
    assert list(tmp_path.iterdir()) == []


def test_output_may_not_overwrite_an_input(tmp_path):
    config = _config_copy(tmp_path)
    before = (config.parent / "v1_texture_256x192_yuv420p.yuv").read_bytes()
    code, _, err = run(config, "-o", config.parent / "v1_texture_256x192_yuv420p.yuv", cwd=tmp_path)
    assert code == 2
    assert_one_line_error(err, "would overwrite an input")
    assert (config.parent / "v1_texture_256x192_yuv420p.yuv").read_bytes() == before


def test_failure_after_some_frames_leaves_no_output(tmp_path, monkeypatch):
    class FailingOnSecondFrame(pipeline.Synthesizer):
        calls = 0

        def frame(self, references):
            type(self).calls += 1
            if type(self).calls == 2:
                raise DataError("damaged frame", path="simulated")
            return super().frame(references)

    monkeypatch.setattr(pipeline, "Synthesizer", FailingOnSecondFrame)
    code, _, err = run(
        LINE / "synthesize_cam2.cfg",
        "--output-depth",
        "d.yuv",
        "--output-holes",
        "h.yuv",
        cwd=tmp_path,
    )
    assert code == 1
    assert_one_line_error(err, "damaged frame")
    assert list(tmp_path.iterdir()) == []
