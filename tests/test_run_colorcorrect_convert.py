"""The run functions of ``colorcorrect`` and ``convert`` called from Python: a grey
mismatch of known gain and offset removed, depth codes through z and disparity computed
by hand and back, and the same bytes as the programs write for the same input."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from program_runner import invoke

from mvtools.cli import colorcorrect, convert
from mvtools.errors import UsageError
from mvtools.io.images import read_image, write_image
from mvtools.io.luts import read_lut
from mvtools.io.yuv import YuvFormat, open_video, write_video
from mvtools.run import (
    ColourCorrectionOptions,
    DepthValues,
    convert_video,
    correct_colours,
    depth_video_to_pfm,
    images_to_video,
    pfm_to_depth_video,
    video_to_images,
)

LINE = Path(__file__).resolve().parent.parent / "sample_data" / "line"
TEXTURE = "v{}_texture_256x192_yuv420p.yuv"
GREY = YuvFormat(64, 32, chroma="400")


def _planes(path: Path, fmt: YuvFormat) -> list[list[np.ndarray]]:
    with open_video(path, fmt) as video:
        return [[np.array(plane) for plane in frame] for frame in video]


# --------------------------------------------------------------------------- colorcorrect


@pytest.fixture
def grey_pair(tmp_path) -> dict[str, Path]:
    """A reference whose codes 16..207 each cover 10 or 11 pixels, and a view that saw
    the same scene with half the gain and 20 codes of offset: code v became v // 2 + 20
    (rounded down)."""
    reference = (16 + np.arange(GREY.width * GREY.height) * 192 // 2048).reshape(32, 64)
    reference = reference.astype(np.uint8)
    frames = {"ref": [[reference]] * 2, "dim": [[(reference // 2 + 20).astype(np.uint8)]] * 2}
    paths = {}
    for name, planes in frames.items():
        paths[name] = tmp_path / f"{name}_64x32_gray.yuv"
        write_video(paths[name], GREY, planes)
    return paths


def test_a_known_gain_and_offset_are_removed(grey_pair, tmp_path):
    views = {"dim": grey_pair["dim"], "ref": grey_pair["ref"]}
    outputs = {name: tmp_path / "out" / path.name for name, path in views.items()}
    calls = []
    result = correct_colours(
        views,
        outputs,
        ColourCorrectionOptions(reference="ref", space="yuv"),
        progress=lambda done, total: calls.append((done, total)),
    )
    # two frames of each of two views, counted over both
    assert calls == [(1, 4), (2, 4), (3, 4), (4, 4)]
    assert result.method == "histograms" and result.reference == "ref"
    dim, ref = result.views
    reference = _planes(grey_pair["ref"], GREY)[0][0].astype(float)
    # before: the mean of v // 2 + 20 against the mean of v
    before = abs(np.mean(reference // 2 + 20) - np.mean(reference))
    assert dim.before == pytest.approx(before)
    assert dim.after < 1.0 < before
    assert (ref.before, ref.after) == (0.0, 0.0)
    # each held code goes back to the reference codes that became it (within smoothing)
    held = np.unique(reference // 2 + 20).astype(int)
    origin = np.array([np.mean(reference[reference // 2 + 20 == code]) for code in held])
    assert np.max(np.abs(dim.table[0][held] - origin)) <= 2.0
    corrected = _planes(outputs["dim"], GREY)
    assert len(corrected) == 2
    assert np.mean(np.abs(corrected[1][0].astype(float) - reference)) <= 1.5
    # the tables written are those returned; the reference keeps its codes
    np.testing.assert_allclose(read_lut(tmp_path / "out" / "dim.lut.txt")[0], dim.table, atol=1e-3)
    np.testing.assert_array_equal(_planes(outputs["ref"], GREY)[0][0], reference)


def test_correct_colours_writes_the_programs_bytes_and_scores(tmp_path):
    views = {f"cam{view}": LINE / TEXTURE.format(view) for view in (1, 2)}
    by_program = tmp_path / "program"
    code, stdout, stderr = invoke(
        colorcorrect.command,
        *(part for name, path in views.items() for part in ("--view", name, path)),
        "--frames",
        2,
        "-o",
        by_program,
    )
    assert code == 0, stderr
    outputs = {name: tmp_path / "library" / path.name for name, path in views.items()}
    result = correct_colours(views, outputs, ColourCorrectionOptions(), frame_count=2)
    # the middle view (cam2) is the reference by default
    assert result.reference == "cam2"
    for name, path in views.items():
        assert outputs[name].read_bytes() == (by_program / path.name).read_bytes()
        for suffix in (".lut.txt", ".cube"):
            library = (tmp_path / "library" / f"{name}{suffix}").read_bytes()
            assert library == (by_program / f"{name}{suffix}").read_bytes()
    printed = stdout.splitlines()[1:]
    assert [line.split()[:4] for line in printed] == [
        [view.name, result.method, f"{view.before:.2f}", f"{view.after:.2f}"]
        for view in result.views
    ]


def test_the_chart_target_needs_a_chart():
    with pytest.raises(ValueError, match="chart"):
        ColourCorrectionOptions(target="chart")


# --------------------------------------------------------------------------- convert

#: Codes of an 8-bit depth map, Znear 2 and Zfar 10: 1/z = v/255 (1/2 - 1/10) + 1/10.
CODES = np.array([[0, 255, 51, 102]], dtype=np.uint8)
Z = np.array([[10.0, 2.0, 1 / (0.2 * 0.4 + 0.1), 1 / (0.4 * 0.4 + 0.1)]])


@pytest.fixture
def depth_video(tmp_path) -> Path:
    path = tmp_path / "depth_4x1_gray.yuv"
    write_video(path, YuvFormat(4, 1, chroma="400"), [[CODES], [CODES[:, ::-1].copy()]])
    return path


def test_depth_codes_give_the_z_and_disparity_computed_by_hand(depth_video, tmp_path):
    written = depth_video_to_pfm(depth_video, tmp_path / "z_%d.pfm", DepthValues("z", (2.0, 10.0)))
    assert written == [tmp_path / "z_0.pfm", tmp_path / "z_1.pfm"]
    np.testing.assert_allclose(read_image(written[0]), Z, rtol=1e-6)
    np.testing.assert_allclose(read_image(written[1]), Z[:, ::-1], rtol=1e-6)
    # disparity = focal * baseline / z: 100 px and 0.1 give 10 / z
    disparity = DepthValues("disparity", (2.0, 10.0), focal=100.0, baseline=0.1)
    written = depth_video_to_pfm(depth_video, tmp_path / "d_%d.pfm", disparity, frame_count=1)
    np.testing.assert_allclose(read_image(written[0]), 10.0 / Z, rtol=1e-6)
    # and back to the codes the video holds
    back = tmp_path / "back_4x1_gray.yuv"
    fmt = pfm_to_depth_video(written, back, disparity, out_pix_fmt="gray")
    assert fmt == YuvFormat(4, 1, chroma="400")
    assert back.read_bytes() == CODES.tobytes()


def test_depth_bit_depth_change_keeps_v_over_vmax(depth_video, tmp_path):
    output = tmp_path / "deep.yuv"
    calls = []
    fmt = convert_video(
        depth_video,
        output,
        out_pix_fmt="gray16le",
        depth=True,
        progress=lambda done, total: calls.append((done, total)),
    )
    assert calls == [(1, 2), (2, 2)]
    deep = _planes(output, fmt)
    # 65535 / 255 = 257 exactly
    np.testing.assert_array_equal(deep[0][0], CODES.astype(np.uint16) * 257)
    np.testing.assert_array_equal(deep[1][0], CODES[:, ::-1].astype(np.uint16) * 257)


def test_grey_pictures_become_luma_with_grey_chroma_and_come_back(tmp_path):
    pictures = []
    for index in range(2):
        picture = np.arange(32, dtype=np.uint8).reshape(4, 8) * 7 + index
        pictures.append(tmp_path / f"p{index}.png")
        write_image(pictures[-1], picture)
    video = tmp_path / "grey.yuv"
    fmt = images_to_video(pictures, video, out_pix_fmt="yuv420p")
    assert fmt == YuvFormat(8, 4)
    frames = _planes(video, fmt)
    for index, (luma, u, v) in enumerate(frames):
        np.testing.assert_array_equal(luma, np.arange(32).reshape(4, 8) * 7 + index)
        assert (u == 128).all() and (v == 128).all()
    written = video_to_images(
        video, tmp_path / "f%02d.png", size=(8, 4), pix_fmt="yuv420p", depth=True
    )
    assert written == [tmp_path / "f00.png", tmp_path / "f01.png"]
    for picture, again in zip(pictures, written):
        np.testing.assert_array_equal(read_image(again), read_image(picture))


def test_several_frames_need_a_numbered_name(depth_video, tmp_path):
    with pytest.raises(UsageError, match="numbered output name"):
        video_to_images(depth_video, tmp_path / "frame.png", depth=True)
    assert not (tmp_path / "frame.png").exists()


def test_convert_video_writes_the_programs_bytes(tmp_path):
    source = LINE / TEXTURE.format(0)
    code, _, stderr = invoke(
        convert.command, source, "-o", tmp_path / "program.yuv", "--out-pix-fmt", "yuv444p10le"
    )
    assert code == 0, stderr
    convert_video(source, tmp_path / "library.yuv", out_pix_fmt="yuv444p10le")
    assert (tmp_path / "library.yuv").read_bytes() == (tmp_path / "program.yuv").read_bytes()
