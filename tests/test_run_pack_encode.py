"""The run functions of ``pack`` and ``encode`` called from Python: packed frames of
hand-made views against placements computed by hand, unpacking back to the input bytes,
and a rate-distortion experiment whose bitrates are the bitstreams' sizes and whose
scores are the PSNR of the decoded files."""

from __future__ import annotations

import json
import os
import shutil
from pathlib import Path

import numpy as np
import pytest

from mvtools.errors import DataError, UsageError
from mvtools.io.yuv import YuvFormat, open_video, open_writer, write_video
from mvtools.run import (
    EncoderSettings,
    PackOptions,
    pack_views,
    rd_experiment,
    unpack_views,
)

TEXTURE = YuvFormat(8, 4)
DEPTH = YuvFormat(8, 4, chroma="400")

needs_encoders = pytest.mark.skipif(
    (shutil.which("x265") is None or shutil.which("ffmpeg") is None)
    and os.environ.get("MVTOOLS_REQUIRE_DATA") != "1",
    reason="x265 and ffmpeg are not installed (.ci/run installs them)",
)


def _frames(rng, fmt: YuvFormat, low: int, high: int, count: int = 2) -> list[list[np.ndarray]]:
    """``count`` frames of samples in ``low .. high - 1``, so that each view's samples
    are told apart from the others' and from the packed frame's padding (16 and 128)."""
    return [
        [rng.integers(low, high, shape, dtype=np.uint8) for shape in fmt.plane_shapes]
        for _ in range(count)
    ]


@pytest.fixture
def views(tmp_path) -> dict:
    """Two 8x4 4:2:0 views and their 8x4 grey depth maps, 2 frames each: their files,
    by (name, kind), and their frames."""
    rng = np.random.default_rng(18)
    frames = {
        ("a", "texture"): _frames(rng, TEXTURE, 30, 60),
        ("b", "texture"): _frames(rng, TEXTURE, 160, 190),
        ("a", "depth"): _frames(rng, DEPTH, 60, 90),
        ("b", "depth"): _frames(rng, DEPTH, 200, 230),
    }
    paths = {}
    for (name, kind), planes in frames.items():
        fmt = TEXTURE if kind == "texture" else DEPTH
        paths[(name, kind)] = tmp_path / "in" / f"{name}_{kind}_8x4_{fmt.pix_fmt}.yuv"
        paths[(name, kind)].parent.mkdir(exist_ok=True)
        write_video(paths[(name, kind)], fmt, planes)
    return {"paths": paths, "frames": frames}


def _read(path: Path, fmt: YuvFormat) -> list[list[np.ndarray]]:
    with open_video(path, fmt) as video:
        return [[np.array(plane) for plane in frame] for frame in video]


def test_a_side_by_side_frame_holds_each_view_at_its_place(views, tmp_path):
    paths, frames = views["paths"], views["frames"]
    output = tmp_path / "sbs.yuv"
    packed = pack_views(
        {"a": paths[("a", "texture")], "b": paths[("b", "texture")]},
        output,
        PackOptions(layout="side-by-side"),
    )
    # two 8x4 views side by side: 16x4, padded to the 8-sample block: 16x8
    assert (packed.layout.width, packed.layout.height) == (16, 8)
    assert packed.format == YuvFormat(16, 8)
    assert packed.frames == range(2) and packed.sidecar == tmp_path / "sbs.json"
    for index, planes in enumerate(_read(output, packed.format)):
        a, b = frames[("a", "texture")][index], frames[("b", "texture")][index]
        luma = np.full((8, 16), 16, np.uint8)  # black padding below the views
        luma[0:4, 0:8], luma[0:4, 8:16] = a[0], b[0]
        np.testing.assert_array_equal(planes[0], luma)
        for plane in (1, 2):
            chroma = np.full((4, 8), 128, np.uint8)
            chroma[0:2, 0:4], chroma[0:2, 4:8] = a[plane], b[plane]
            np.testing.assert_array_equal(planes[plane], chroma)


def test_an_atlas_unpacks_to_the_input_bytes(views, tmp_path):
    paths, frames = views["paths"], views["frames"]
    output = tmp_path / "atlas.yuv"
    packed = pack_views(
        {"a": paths[("a", "texture")], "b": paths[("b", "texture")]},
        output,
        PackOptions(layout="atlas", columns=2),
        depths={"a": paths[("a", "depth")], "b": paths[("b", "depth")]},
    )
    # the textures' row above the depth maps' row: 16x8, a multiple of the block already
    assert packed.format == YuvFormat(16, 8)
    first = _read(output, packed.format)[0]
    np.testing.assert_array_equal(first[0][4:8, 0:8], frames[("a", "depth")][0][0])
    np.testing.assert_array_equal(first[0][4:8, 8:16], frames[("b", "depth")][0][0])
    # grey depth maps have mid-grey chroma in the atlas
    assert np.all(first[1][2:4] == 128) and np.all(first[2][2:4] == 128)
    restored = unpack_views(output, tmp_path / "views")
    assert restored == {key: tmp_path / "views" / path.name for key, path in paths.items()}
    for key, path in paths.items():
        assert restored[key].read_bytes() == path.read_bytes()


def test_readers_in_a_writer_out_and_a_frame_range(views, tmp_path):
    paths, frames = views["paths"], views["frames"]
    calls = []
    packed_format = YuvFormat(8, 8)  # two 8x4 views one above the other
    with (
        open_video(paths[("a", "texture")], TEXTURE) as a,
        open_video(paths[("b", "texture")], TEXTURE) as b,
    ):
        with open_writer(tmp_path / "tb.yuv", packed_format) as writer:
            packed = pack_views(
                {"a": a, "b": b},
                writer,
                PackOptions(layout="top-bottom"),
                sidecar=tmp_path / "layout.json",
                start_frame=1,
                frame_count=1,
                progress=lambda done, total: calls.append((done, total)),
            )
        with (
            open_writer(tmp_path / "wrong.yuv", YuvFormat(16, 8)) as writer,
            pytest.raises(ValueError, match="packed frames are"),
        ):
            pack_views({"a": a, "b": b}, writer, PackOptions(layout="top-bottom"))
    assert packed.frames == range(1, 2) and calls == [(1, 1)]
    [planes] = _read(tmp_path / "tb.yuv", packed_format)
    np.testing.assert_array_equal(planes[0][0:4], frames[("a", "texture")][1][0])
    np.testing.assert_array_equal(planes[0][4:8], frames[("b", "texture")][1][0])
    np.testing.assert_array_equal(planes[1][2:4], frames[("b", "texture")][1][1])
    # the sidecar asked for describes the one frame packed
    restored = unpack_views(tmp_path / "tb.yuv", tmp_path / "views", sidecar=packed.sidecar)
    frame = frames[("b", "texture")][1]
    assert restored[("b", "texture")].read_bytes() == b"".join(plane.tobytes() for plane in frame)


def test_bad_views_and_packed_videos(views, tmp_path):
    paths = views["paths"]
    elsewhere = tmp_path / "elsewhere" / paths[("a", "texture")].name
    elsewhere.parent.mkdir()
    shutil.copy(paths[("a", "texture")], elsewhere)
    with pytest.raises(UsageError, match="--view b: the same file name as --view a"):
        pack_views({"a": paths[("a", "texture")], "b": elsewhere}, tmp_path / "p.yuv")
    # a grey picture as a texture next to a 4:2:0 one
    with pytest.raises(DataError, match="differ in pixel format"):
        pack_views({"a": paths[("a", "texture")], "b": paths[("b", "depth")]}, tmp_path / "p.yuv")
    assert not (tmp_path / "p.yuv").exists()
    with pytest.raises(UsageError, match="no sidecar"):
        unpack_views(paths[("a", "texture")], tmp_path / "out")
    pack_views({"a": paths[("a", "texture")]}, tmp_path / "p.yuv")
    with (
        open_video(tmp_path / "p.yuv", YuvFormat(8, 8, chroma="444")) as video,
        pytest.raises(DataError, match="its sidecar"),
    ):
        unpack_views(video, tmp_path / "out")


def test_experiment_arguments_are_checked(tmp_path):
    with pytest.raises(ValueError, match="QP"):
        rd_experiment({"a": tmp_path / "a.yuv"}, [], tmp_path / "out")
    with pytest.raises(ValueError, match="QP"):
        rd_experiment({"a": tmp_path / "a.yuv"}, [52], tmp_path / "out")
    with pytest.raises(ValueError, match="modes"):
        rd_experiment({"a": tmp_path / "a.yuv"}, [30], tmp_path / "out", modes=("mvc",))
    for fps in (0.0, float("nan")):
        with pytest.raises(ValueError, match="frame rate"):
            EncoderSettings(fps=fps)
    with pytest.raises(ValueError, match="encoder"):
        EncoderSettings(encoder="x264")
    assert not (tmp_path / "out").exists()


def _y_psnr(original: np.ndarray, decoded: np.ndarray) -> float:
    mse = np.mean((original.astype(float) - decoded.astype(float)) ** 2)
    return 10 * np.log10(255**2 / mse)


@needs_encoders
def test_a_rate_distortion_experiment_on_hand_made_views(tmp_path):
    fmt = YuvFormat(64, 64)
    rng = np.random.default_rng(5)
    y, x = np.mgrid[0:64, 0:64]
    originals = {}
    for name, slope in (("a", 1), ("b", 2)):
        # a ramp with noise: coding at QP 40 loses much of the noise, QP 22 little
        frames = [
            [
                (40 + slope * (x + y) + rng.integers(0, 24, (64, 64))).astype(np.uint8),
                np.full((32, 32), 100 + 20 * slope, np.uint8),
                np.full((32, 32), 150 - 20 * slope, np.uint8),
            ]
            for _ in range(2)
        ]
        originals[name] = frames
        write_video(tmp_path / f"{name}_64x64_yuv420p.yuv", fmt, frames)
    calls = []
    out = tmp_path / "out"
    report = rd_experiment(
        {name: tmp_path / f"{name}_64x64_yuv420p.yuv" for name in originals},
        [40, 22, 40],
        out,
        settings=EncoderSettings(preset="ultrafast"),
        progress=lambda done, total: calls.append((done, total)),
    )
    assert calls == [(1, 4), (2, 4), (3, 4), (4, 4)]
    assert report["qps"] == [22, 40] and "bjontegaard" not in report
    assert json.loads((out / "report.json").read_text()) == report
    seconds = 2 / 25
    for mode, points in report["modes"].items():
        assert [point["qp"] for point in points] == [22, 40]
        assert points[0]["kbps"] > points[1]["kbps"]
        for point in points:
            folder = out / mode / f"qp{point['qp']}"
            bitstreams = (
                [folder / f"{name}_64x64_yuv420p.hevc" for name in originals]
                if mode == "simulcast"
                # two 64x64 views: a grid of two columns
                else [folder / "decoded" / "packed_128x64_yuv420p.hevc"]
            )
            size = sum(path.stat().st_size for path in bitstreams)
            assert point["kbps"] == pytest.approx(size * 8 / seconds / 1000)
            for name, frames in originals.items():
                decoded = _read(folder / f"{name}_64x64_yuv420p.yuv", fmt)
                expected = np.mean([_y_psnr(f[0], d[0]) for f, d in zip(frames, decoded)])
                score = point["scores"][f"{name} texture"]["y_psnr"]
                assert score == pytest.approx(expected)
            assert point["mean_texture_y_psnr"] == pytest.approx(
                np.mean([score["y_psnr"] for score in point["scores"].values()])
            )
    # the packed mode's view b is the right half of the decoded packed frame
    folder = out / "packed" / "qp40"
    packed = _read(folder / "decoded" / "packed_128x64_yuv420p.yuv", YuvFormat(128, 64))
    view = _read(folder / "b_64x64_yuv420p.yuv", fmt)
    for whole, part in zip(packed, view):
        np.testing.assert_array_equal(part[0], whole[0][:, 64:])
        np.testing.assert_array_equal(part[1], whole[1][:, 32:])
