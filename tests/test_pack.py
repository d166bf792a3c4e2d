"""Frame-compatible packing: bit-exact round trips for every layout (odd view counts and
odd sizes included), halved layouts, the sidecar, ``mvtools pack`` end to end, and bad
input."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from program_runner import assert_one_line_error, invoke

from mvtools.cli import pack
from mvtools.errors import ConfigError
from mvtools.io.sidecar import read_sidecar
from mvtools.io.yuv import YuvFormat, open_video, write_video
from mvtools.metrics import psnr
from mvtools.pack import pack_frame, plan_layout, unpack_frame

LINE = Path(__file__).resolve().parent.parent / "sample_data" / "line"
TEXTURE = "v{}_texture_256x192_yuv420p.yuv"
DEPTH = "v{}_depth_256x192_yuv420p.yuv"


def random_frame(rng, width, height, chroma="420", bits=8):
    fmt = YuvFormat(width, height, chroma=chroma, bits=bits)
    return [rng.integers(0, 2**bits, shape, dtype=fmt.dtype) for shape in fmt.plane_shapes]


CASES = [
    ("side-by-side", 2, 0),
    ("top-bottom", 2, 0),
    ("grid", 1, 0),
    ("grid", 3, 0),
    ("grid", 5, 0),
    ("grid", 16, 0),
    ("atlas", 3, 3),
    ("atlas", 5, 2),
]


@pytest.mark.parametrize("layout, count, depths", CASES)
@pytest.mark.parametrize("width, height", [(256, 192), (255, 191), (17, 9)])
@pytest.mark.parametrize("chroma, bits", [("420", 8), ("422", 10), ("444", 8)])
def test_round_trip_is_bit_exact(layout, count, depths, width, height, chroma, bits):
    rng = np.random.default_rng(count * 1000 + width)
    views = {
        (f"v{i}", "texture"): random_frame(rng, width, height, chroma, bits) for i in range(count)
    }
    views.update(
        {(f"v{i}", "depth"): random_frame(rng, width, height, "400", bits) for i in range(depths)}
    )
    plan = plan_layout(
        [(f"v{i}", (width, height)) for i in range(count)],
        layout=layout,
        depths=[(f"v{i}", (width, height)) for i in range(depths)],
    )
    assert plan.width % 8 == 0 and plan.height % 8 == 0
    for placement in plan.placements:
        assert placement.x % 2 == 0 and placement.y % 2 == 0
    packed = pack_frame(plan, views, chroma=chroma, bits=bits)
    restored = unpack_frame(plan, packed, chroma=chroma)
    assert restored.keys() == views.keys()
    for key, planes in views.items():
        for original, back in zip(planes, restored[key]):
            np.testing.assert_array_equal(back, original)


def test_views_of_different_sizes_share_a_grid_exactly():
    rng = np.random.default_rng(7)
    sizes = {"a": (64, 48), "b": (33, 21), "c": (50, 60)}
    views = {(name, "texture"): random_frame(rng, *size) for name, size in sizes.items()}
    plan = plan_layout(list(sizes.items()), layout="grid")
    restored = unpack_frame(plan, pack_frame(plan, views, chroma="420", bits=8), chroma="420")
    for key, planes in views.items():
        for original, back in zip(planes, restored[key]):
            np.testing.assert_array_equal(back, original)


def test_sixteen_hd_views_fill_an_8k_frame():
    plan = plan_layout(
        [(f"v{i}", (1920, 1080)) for i in range(16)], layout="grid", frame_size=(7680, 4320)
    )
    assert (plan.width, plan.height) == (7680, 4320)
    corners = {(placement.x, placement.y) for placement in plan.placements}
    assert corners == {(1920 * column, 1080 * row) for row in range(4) for column in range(4)}
    with pytest.raises(ValueError, match="more than the 7680x4320 frame"):
        plan_layout(
            [(f"v{i}", (1920, 1080)) for i in range(17)], layout="grid", frame_size=(7680, 4320)
        )


@pytest.mark.parametrize("layout, axis", [("side-by-side", 1), ("top-bottom", 0)])
def test_halved_layouts_restore_smooth_pictures(layout, axis):
    # a ramp along the halved axis comes back within one code: averaging pairs and
    # interpolating between their centres is exact on straight lines, up to rounding
    ramp = np.add.outer(np.arange(96), np.arange(128)).astype(np.uint8)
    fmt = YuvFormat(128, 96)
    frame = [
        ramp,
        np.full(fmt.plane_shapes[1], 100, np.uint8),
        np.full(fmt.plane_shapes[2], 150, np.uint8),
    ]
    plan = plan_layout([("a", (128, 96)), ("b", (128, 96))], layout=layout, half=True)
    assert (plan.width, plan.height) == (128, 96)
    assert plan.placements[1].decimation == ((2, 1) if axis == 1 else (1, 2))
    restored = unpack_frame(
        plan,
        pack_frame(plan, {("a", "texture"): frame, ("b", "texture"): frame}, chroma="420", bits=8),
        chroma="420",
    )
    inner = (slice(1, -1), slice(1, -1))
    difference = np.abs(restored[("a", "texture")][0].astype(int) - ramp.astype(int))
    assert difference[inner].max() <= 1
    assert np.all(restored[("b", "texture")][1] == 100)


def test_layout_arguments_are_checked():
    with pytest.raises(ValueError, match="two views"):
        plan_layout([("a", (8, 8))], layout="side-by-side")
    with pytest.raises(ValueError, match="atlas"):
        plan_layout([("a", (8, 8))], layout="grid", depths=[("a", (8, 8))])
    with pytest.raises(ValueError, match="halving"):
        plan_layout([("a", (8, 8))], layout="grid", half=True)
    with pytest.raises(ValueError, match="distinct"):
        plan_layout([("a", (8, 8)), ("a", (8, 8))], layout="grid")


def video_bytes(path: Path) -> bytes:
    return path.read_bytes()


def test_pack_and_unpack_the_sample_views_and_depth_maps(tmp_path):
    arguments = []
    for view in range(5):
        arguments += [
            "--view",
            f"cam{view}",
            LINE / TEXTURE.format(view),
            "--depth",
            f"cam{view}",
            LINE / DEPTH.format(view),
        ]
    packed = tmp_path / "atlas_768x768_yuv420p.yuv"
    code, _, stderr = invoke(pack.command, *arguments, "--layout", "atlas", "-o", packed)
    assert code == 0, stderr
    sidecar = json.loads(packed.with_suffix(".json").read_text())
    assert sidecar["layout"] == "atlas" and len(sidecar["views"]) == 10
    with open_video(packed, YuvFormat(sidecar["width"], sidecar["height"])) as video:
        assert len(video) == 3
    code, _, stderr = invoke(pack.command, "--unpack", packed, "-o", tmp_path / "views")
    assert code == 0, stderr
    for view in range(5):
        for name in (TEXTURE.format(view), DEPTH.format(view)):
            assert video_bytes(tmp_path / "views" / name) == video_bytes(LINE / name)


def test_halved_side_by_side_of_the_sample_pair(tmp_path):
    packed = tmp_path / "sbs.yuv"
    code, _, stderr = invoke(
        pack.command,
        "--view",
        "left",
        LINE / TEXTURE.format(1),
        "--view",
        "right",
        LINE / TEXTURE.format(3),
        "--layout",
        "side-by-side",
        "--half",
        "-o",
        packed,
    )
    assert code == 0, stderr
    assert read_sidecar(packed.with_suffix(".json")).layout.width == 256
    assert invoke(pack.command, "--unpack", packed, "-o", tmp_path / "views")[0] == 0
    fmt = YuvFormat(256, 192)
    with (
        open_video(LINE / TEXTURE.format(1), fmt) as original,
        open_video(tmp_path / "views" / TEXTURE.format(1), fmt) as restored,
    ):
        # half the columns are gone: smooth parts survive, fine texture does not
        assert 25.0 < psnr(original.read(0)[0], restored.read(0)[0], max_value=255) < 60.0


def test_a_frame_size_too_small_for_the_grid(tmp_path):
    code, _, stderr = invoke(
        pack.command,
        *[
            arg
            for view in range(5)
            for arg in ("--view", f"cam{view}", LINE / TEXTURE.format(view))
        ],
        "--frame-size",
        "512x384",
        "-o",
        tmp_path / "p.yuv",
    )
    assert code == 2
    assert_one_line_error(stderr, "512x384")
    assert not (tmp_path / "p.yuv").exists()


def test_views_of_different_pixel_formats(tmp_path):
    grey = tmp_path / "g_256x192_gray.yuv"
    write_video(grey, YuvFormat(256, 192, chroma="400"), [[np.zeros((192, 256), np.uint8)]])
    code, _, stderr = invoke(
        pack.command,
        "--view",
        "a",
        LINE / TEXTURE.format(0),
        "--view",
        "b",
        grey,
        "-o",
        tmp_path / "p.yuv",
    )
    assert code == 1
    assert_one_line_error(stderr, "pixel format")


def test_unpack_needs_a_sidecar_that_fits(tmp_path):
    packed = tmp_path / "p.yuv"
    assert (
        invoke(
            pack.command,
            "--view",
            "a",
            LINE / TEXTURE.format(0),
            "--view",
            "b",
            LINE / TEXTURE.format(1),
            "-o",
            packed,
        )[0]
        == 0
    )
    lone = tmp_path / "lone.yuv"
    lone.write_bytes(packed.read_bytes())
    code, _, stderr = invoke(pack.command, "--unpack", lone, "-o", tmp_path / "out")
    assert code == 2
    assert_one_line_error(stderr, "sidecar")
    # a sidecar whose frame count disagrees with the video
    document = json.loads(packed.with_suffix(".json").read_text())
    document["frames"] = 7
    wrong = tmp_path / "wrong.json"
    wrong.write_text(json.dumps(document))
    code, _, stderr = invoke(
        pack.command, "--unpack", packed, "--sidecar", wrong, "-o", tmp_path / "out"
    )
    assert code == 1
    assert_one_line_error(stderr, "7")
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").iterdir())


def test_sidecar_errors_name_the_view(tmp_path):
    packed = tmp_path / "p.yuv"
    assert (
        invoke(
            pack.command,
            "--view",
            "a",
            LINE / TEXTURE.format(0),
            "--view",
            "b",
            LINE / TEXTURE.format(1),
            "-o",
            packed,
        )[0]
        == 0
    )
    document = json.loads(packed.with_suffix(".json").read_text())
    document["views"][1]["x"] = 10
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(document))
    with pytest.raises(ConfigError, match="views a and b overlap"):
        read_sidecar(bad)
    del document["views"][1]["width"]
    bad.write_text(json.dumps(document))
    with pytest.raises(ConfigError, match="no 'width'"):
        read_sidecar(bad)
