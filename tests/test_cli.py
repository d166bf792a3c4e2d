"""The programs end to end: results against hand-computed values, and bad input
giving one line naming the place at fault, the right exit code and no output."""

from __future__ import annotations

import importlib.metadata
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from program_runner import assert_one_line_error, invoke, run
from shared_data import shared_data

from mvtools.cli.main import PROGRAMS, program_command
from mvtools.io.images import read_image, write_image
from mvtools.io.yuv import YuvFormat, read_frame, write_video

KENDO_ZNEAR, KENDO_ZFAR = 448.251214, 11206.280350


def leftovers(folder: Path) -> list[str]:
    return sorted(path.name for path in folder.iterdir())


@pytest.mark.slow
def test_every_program_states_its_purpose():
    for name in (
        "calibrate",
        "rectify",
        "colorcorrect",
        "estimate-depth",
        "synthesize",
        "pack",
        "evaluate",
        "convert",
        "inspect",
    ):
        code, out, _ = run(name, "--help")
        assert code == 0 and len(out.splitlines()) > 3, name


# --------------------------------------------------------------------- evaluate


def _grey_video(path: Path, values: list[int], shape=(8, 6)) -> YuvFormat:
    fmt = YuvFormat(shape[1], shape[0])
    write_video(
        path, fmt, [tuple(np.full(s, v, np.uint8) for s in fmt.plane_shapes) for v in values]
    )
    return fmt


def test_evaluate_psnr_per_frame_and_mean(tmp_path):
    # Frame 0 identical; frame 1 luma off by 5 everywhere: MSE 25, PSNR 10 log10(255^2/25).
    ref, test = tmp_path / "ref_6x8_yuv420p.yuv", tmp_path / "test_6x8_yuv420p.yuv"
    _grey_video(ref, [100, 100])
    fmt = YuvFormat(6, 8)
    frames = [tuple(np.full(s, 100, np.uint8) for s in fmt.plane_shapes)]
    frames.append((np.full((8, 6), 105, np.uint8),) + frames[0][1:])
    write_video(test, fmt, frames)
    code, out, err = run("evaluate", ref, test, "--metric", "psnr", "--json")
    assert code == 0, err
    result = json.loads(out)
    expected = 10 * np.log10(255**2 / 25)
    assert result["frames"][0]["Y-PSNR"] == "inf"
    assert result["frames"][1]["Y-PSNR"] == pytest.approx(expected)
    assert result["frames"][1]["U-PSNR"] == "inf"
    assert result["mean"]["Y-PSNR"] == "inf"


def test_evaluate_disparity_against_middlebury_ground_truth(tmp_path):
    teddy = shared_data("middlebury", "2003", "teddy")
    gt = read_image(teddy / "disp2.png").astype(np.float32) / 4
    shifted = tmp_path / "shifted.pfm"
    write_image(shifted, gt + 1.5)
    code, out, err = run("evaluate", "--disparity", teddy / "disp2.png", shifted, "--json")
    assert code == 0, err
    result = json.loads(out)
    assert result["gt_scale"] == 4  # found from the set table
    assert result["bad_all"] == {"1": 100.0, "2": 0.0}
    assert result["bad_nonocc"] == {"1": 100.0, "2": 0.0}
    assert result["nonocc_pixels"] < result["known_pixels"]


def _depth_case(tmp_path: Path):
    """Two cameras 0.2 apart with fx 100 (disparity = 20 / z); 16-bit depth videos of
    2 frames, 4x8 pixels, Znear 1, Zfar 100: the truth has z 4 (5 px) on the left half
    and z 2 (10 px) on the right, the test the same left half and 11.5 px on the right."""
    from mvtools.geometry.camera import Camera
    from mvtools.geometry.depth import z_to_depth
    from mvtools.io.cameras import write_cameras

    K = np.array([[100.0, 0, 4], [0, 100.0, 2], [0, 0, 1]])
    cameras = tmp_path / "cameras.txt"
    write_cameras(cameras, [Camera("a", K), Camera("b", K, t=np.array([0.2, 0, 0]))])
    fmt = YuvFormat(8, 4, "400", 16)
    videos = {}
    for name, right_disparity in (("truth", 10.0), ("test", 11.5)):
        z = np.where(np.arange(8) < 4, 4.0, 20.0 / right_disparity) * np.ones((4, 1))
        videos[name] = tmp_path / f"{name}_8x4_gray16le.yuv"
        write_video(videos[name], fmt, [(z_to_depth(z, 1.0, 100.0, bits=16),)] * 2)
    return cameras, videos


def test_evaluate_depth_videos_as_disparities_towards_the_neighbour(tmp_path):
    cameras, videos = _depth_case(tmp_path)
    # the test's range from its sidecar, as estimate-depth writes it
    (tmp_path / (videos["test"].name + ".json")).write_text(
        json.dumps({"NearestDepthValue": 1.0, "FarthestDepthValue": 100.0, "DepthType": 0})
    )
    code, out, err = run(
        "evaluate",
        "--depth",
        videos["truth"],
        videos["test"],
        "--reference-depth-range",
        1,
        100,
        "--cameras",
        cameras,
        "--camera",
        "a",
        "--neighbour",
        "b",
        "--json-file",
        tmp_path / "errors.json",
    )
    assert code == 0, err
    assert "  mean    50.000     0.000     0.750" in out
    result = json.loads((tmp_path / "errors.json").read_text())
    assert result["focal"] == 100 and result["baseline"] == pytest.approx(0.2)
    # a 16-bit step is 20 * 0.99 / 65535 = 0.0003 px
    for frame in result["frames"]:
        assert frame["bad 1"] == 50.0 and frame["bad 2"] == 0.0
        assert frame["mean abs"] == pytest.approx(0.75, abs=1e-3)
    histogram = result["histogram"]
    assert histogram["bins"] == ["0-0.25", "0.25-0.5", "0.5-1", "1-2", "2-4", "4-8", ">= 8"]
    assert histogram["pixels"] == [32, 0, 0, 32, 0, 0, 0]
    assert histogram["percent"][3] == 50.0


@pytest.mark.parametrize(
    "change, fragments",
    [
        (("--test-depth-range", None), ("--test-depth-range", "test_8x4_gray16le.yuv.json")),
        (("--neighbour", "c"), ("--neighbour", "no camera 'c'", "cameras.txt")),
        (("--camera", None), ("--depth needs --camera",)),
    ],
)
def test_evaluate_depth_bad_input(tmp_path, change, fragments):
    cameras, videos = _depth_case(tmp_path)
    options = {
        "--reference-depth-range": (1, 100),
        "--test-depth-range": (1, 100),
        "--cameras": (cameras,),
        "--camera": ("a",),
        "--neighbour": ("b",),
    }
    option, value = change
    if value is None:
        del options[option]
    else:
        options[option] = (value,)
    code, out, err = run(
        "evaluate",
        "--depth",
        videos["truth"],
        videos["test"],
        *(item for key, values in options.items() for item in (key, *values)),
    )
    assert code == 2 and out == ""
    assert_one_line_error(err, *fragments)


# --------------------------------------------------------------------- convert


def test_convert_images_to_yuv444_and_back_is_lossless_for_grey(tmp_path):
    rng = np.random.default_rng(1)
    images = []
    for index in range(2):
        grey = rng.integers(16, 236, size=(6, 10), dtype=np.uint8)
        write_image(tmp_path / f"in{index}.png", grey)
        images.append(grey)
    video = tmp_path / "v.y4m"
    code, _, err = run(
        "convert", tmp_path / "in0.png", tmp_path / "in1.png", "-o", video, "--out-pix-fmt", "gray"
    )
    assert code == 0, err
    for index, grey in enumerate(images):
        assert np.array_equal(read_frame(video, index=index)[0], grey)


@pytest.mark.slow
def test_convert_depth_8_to_16_bit_keeps_meaning_and_z_is_exact(tmp_path):
    fmt = YuvFormat(4, 2)
    luma = np.array([[0, 255, 128, 1], [254, 2, 64, 200]], np.uint8)
    write_video(
        tmp_path / "d8.yuv",
        fmt,
        [(luma, np.full((1, 2), 128, np.uint8), np.full((1, 2), 128, np.uint8))],
    )
    code, _, err = run(
        "convert",
        tmp_path / "d8.yuv",
        "--size",
        "4x2",
        "--depth",
        "--out-pix-fmt",
        "gray16le",
        "-o",
        tmp_path / "d16.yuv",
    )
    assert code == 0, err
    d16 = read_frame(tmp_path / "d16.yuv", YuvFormat(4, 2, "400", 16))[0]
    assert np.array_equal(d16, luma.astype(np.uint16) * 257)  # 65535 / 255 = 257 exactly
    code, _, err = run(
        "convert",
        tmp_path / "d16.yuv",
        "--size",
        "4x2",
        "--pix-fmt",
        "gray16le",
        "--depth",
        "--to",
        "z",
        "--depth-range",
        2,
        10,
        "-o",
        tmp_path / "z.pfm",
    )
    assert code == 0, err
    z = read_image(tmp_path / "z.pfm")
    # 1/z = v/vmax (1/znear - 1/zfar) + 1/zfar, by hand for v = 0, vmax, 128*257.
    assert z[0, 0] == pytest.approx(10) and z[0, 1] == pytest.approx(2)
    assert z[0, 2] == pytest.approx(1 / (128 / 255 * (0.5 - 0.1) + 0.1), rel=1e-6)
    code, _, err = run(
        "convert",
        tmp_path / "z.pfm",
        "--from",
        "z",
        "--depth-range",
        2,
        10,
        "-o",
        tmp_path / "back_4x2_yuv420p.yuv",
    )
    assert code == 0, err
    assert np.array_equal(read_frame(tmp_path / "back_4x2_yuv420p.yuv")[0], luma)


@pytest.mark.slow
def test_convert_negative_depth_range_gives_signed_z_and_positive_disparity(tmp_path):
    """Poznan's convention: Znear -2, Zfar -10; 1/z = v/255 (1/Znear - 1/Zfar) + 1/Zfar."""
    fmt = YuvFormat(2, 2)
    luma = np.array([[0, 255], [128, 64]], np.uint8)
    chroma = np.full((1, 1), 128, np.uint8)
    write_video(tmp_path / "d.yuv", fmt, [(luma, chroma, chroma)])
    common = ("--size", "2x2", "--depth", "--depth-range", -2, -10)
    code, _, err = run(
        "convert", tmp_path / "d.yuv", *common, "--to", "z", "-o", tmp_path / "z.pfm"
    )
    assert code == 0, err
    z = read_image(tmp_path / "z.pfm")
    expected = 1 / (luma / 255 * (-0.5 + 0.1) - 0.1)
    np.testing.assert_allclose(z, expected, rtol=1e-6)
    assert z[0, 0] == pytest.approx(-10) and z[0, 1] == pytest.approx(-2)
    code, _, err = run(
        "convert",
        tmp_path / "d.yuv",
        *common,
        "--to",
        "disparity",
        "--focal",
        100,
        "--baseline",
        0.5,
        "-o",
        tmp_path / "disparity.pfm",
    )
    assert code == 0, err
    np.testing.assert_allclose(read_image(tmp_path / "disparity.pfm"), -50 / expected, rtol=1e-6)
    for quantity, source in (("z", "z.pfm"), ("disparity", "disparity.pfm")):
        extra = ("--focal", 100, "--baseline", 0.5) if quantity == "disparity" else ()
        code, _, err = run(
            "convert",
            tmp_path / source,
            "--from",
            quantity,
            "--depth-range",
            -2,
            -10,
            *extra,
            "-o",
            tmp_path / f"back_{quantity}_2x2_yuv420p.yuv",
        )
        assert code == 0, err
        assert np.array_equal(read_frame(tmp_path / f"back_{quantity}_2x2_yuv420p.yuv")[0], luma)


# --------------------------------------------------------------------- bad input


def test_truncated_yuv_names_file_and_format_and_writes_nothing(tmp_path):
    source = tmp_path / "in_16x8_yuv420p.yuv"
    source.write_bytes(bytes(16 * 8 * 3 // 2 * 2 - 7))
    out = tmp_path / "out"
    out.mkdir()
    code, _, err = run("convert", source, "-o", out / "copy.yuv")
    assert code == 1
    assert_one_line_error(err, str(source), "not a whole number")
    assert leftovers(out) == []


def test_missing_input_file(tmp_path):
    code, _, err = run(
        "evaluate", tmp_path / "nothing_8x8_yuv420p.yuv", tmp_path / "nothing_8x8_yuv420p.yuv"
    )
    assert code == 2
    assert_one_line_error(err, "nothing_8x8_yuv420p.yuv", "no such file")


def test_camera_block_with_22_numbers(tmp_path):
    cameras = tmp_path / "cams.txt"
    numbers = " ".join(["1"] * 22)
    cameras.write_text(f"camA\n{' '.join(['1'] * 23)}\n\ncamB\n{numbers}\n")
    code, _, err = run("inspect", cameras, "--as", "cameras")
    assert code == 2
    assert_one_line_error(err, f"{cameras}:4", "camB", "22")


def _kendo_config(tmp_path, text: str = "") -> Path:
    kendo = shared_data("mpeg", "kendo")
    config = tmp_path / "synth.cfg"
    config.write_text(
        "SourceWidth 1024\nSourceHeight 768\nTotalNumberOfFrames 1\n"
        f"LeftNearestDepthValue {KENDO_ZNEAR}\nLeftFarthestDepthValue {KENDO_ZFAR}\n"
        f"RightNearestDepthValue {KENDO_ZNEAR}\nRightFarthestDepthValue {KENDO_ZFAR}\n"
        f"CameraParameterFile {kendo / 'config' / 'VSRS' / 'cam_param_kendo.cfg'}\n"
        "LeftCameraName param_kendo01\nVirtualCameraName param_kendo02\n"
        "RightCameraName param_kendo03\n"
        f"LeftViewImageName {kendo / 'kendo_ori_I_1.yuv'}\n"
        f"RightViewImageName {kendo / 'kendo_ori_I_3.yuv'}\n"
        f"LeftDepthMapName {kendo / 'kendo_ori_D_1.yuv'}\n"
        f"RightDepthMapName {kendo / 'kendo_ori_D_3.yuv'}\n"
        "OutputVirtualViewImageName out.yuv\n" + text
    )
    return config


def test_valid_configuration_is_described(tmp_path):
    code, out, err = run("inspect", _kendo_config(tmp_path))
    assert code == 0, err
    assert "VSRS configuration" in out and "param_kendo02" in out


def test_unknown_camera_name(tmp_path):
    config = _kendo_config(tmp_path, "VirtualCameraName param_kendo2\n")
    code, _, err = run("inspect", config)
    assert code == 2
    assert_one_line_error(
        err, f"{config}:17", "VirtualCameraName", "param_kendo2", "did you mean 'param_kendo02'"
    )


def test_znear_not_below_zfar(tmp_path):
    config = _kendo_config(tmp_path, "LeftNearestDepthValue 20000\n")
    code, _, err = run("inspect", config)
    assert code == 2
    assert_one_line_error(err, "LeftNearestDepthValue")
    for znear, zfar, message in ((10, 5, "farther than"), (-2, 10, "opposite signs")):
        code, _, err = run(
            "convert",
            "x.pfm",
            "--from",
            "z",
            "--depth-range",
            znear,
            zfar,
            "-o",
            tmp_path / "d.yuv",
        )
        assert code == 2
        assert_one_line_error(err, "--depth-range", message)


def test_non_numeric_value(tmp_path):
    config = _kendo_config(tmp_path, "Precision half\n")
    code, _, err = run("inspect", config)
    assert code == 2
    assert_one_line_error(err, f"{config}:17", "Precision", "'half' is not an integer")


def test_missing_file_named_by_configuration(tmp_path):
    config = _kendo_config(tmp_path, "LeftViewImageName ..\\elsewhere\\left.yuv\n")
    code, _, err = run("inspect", config)
    assert code == 2
    assert_one_line_error(err, f"{config}:17", "LeftViewImageName", "not found", "tried")


def test_convert_cameras_text_to_json_and_back_keeps_projections(tmp_path):
    from mvtools.io.cameras import read_cameras

    source = shared_data("mpeg", "vsrs_camera_parameters", "cam_param_lovebird1_original.txt")
    code, _, err = run(
        "convert",
        source,
        "-o",
        tmp_path / "c.json",
        "--size",
        "1024x768",
        "--depth-range",
        2000,
        9000,
    )
    assert code == 0, err
    code, _, err = run("convert", tmp_path / "c.json", "-o", tmp_path / "c.txt")
    assert code == 0, err
    original, back = read_cameras(source), read_cameras(tmp_path / "c.txt")
    assert list(original) == list(back)
    for name, camera in original.items():
        scale = np.abs(camera.projection).max()
        assert np.allclose(back[name].projection, camera.projection, atol=1e-9 * scale)


@pytest.mark.slow
def test_time_log_records_each_finished_program(tmp_path):
    log = tmp_path / "times.tsv"
    for size in ("1920x1080", "640x480"):
        completed = subprocess.run(
            [sys.executable, "-m", "mvtools", "bitrate", "--size", size, "--fps", "25"],
            capture_output=True,
            text=True,
            env={**os.environ, "MVTOOLS_TIME_LOG": str(log)},
        )
        assert completed.returncode == 0, completed.stderr
    lines = [line.split("\t") for line in log.read_text().splitlines()]
    assert [line[1:] for line in lines] == [["mvtools bitrate", "25"]] * 2
    assert all(0 <= float(line[0]) < 60 for line in lines)


@pytest.mark.parametrize("name", sorted(PROGRAMS))
def test_every_program_states_the_installed_version(name):
    # the installed distribution's metadata, not the module's constant
    code, out, _ = invoke(program_command(name), "--version")
    assert code == 0
    assert out.strip() == f"mvtools, version {importlib.metadata.version('mvtools')}"


@pytest.mark.slow
def test_verbose_shows_the_parameters_their_sources_and_the_inputs(tmp_path):
    line = Path(__file__).resolve().parent.parent / "sample_data" / "line"
    config = line / "synthesize_cam2.cfg"
    precision_line = next(
        number
        for number, text in enumerate(config.read_text().splitlines(), start=1)
        if text.startswith("Precision")
    )
    output = tmp_path / "out_256x192_yuv420p.yuv"
    code, _, err = run("synthesize", config, "--frames", "1", "-v", "-o", output)
    assert code == 0, err
    debug = [text for text in err.splitlines() if ": debug: " in text]
    assert f"{config}:{precision_line}: Precision = 2" in "\n".join(debug)
    assert any(
        text.endswith("v1_texture_256x192_yuv420p.yuv: 256x192 yuv420p, 3 frames") for text in debug
    ), debug
    assert any(text.endswith(f"{output}: written (73728 bytes)") for text in debug), debug
    code, _, err = run("synthesize", config, "--frames", "1", "-o", output)
    assert code == 0 and ": debug: " not in err
