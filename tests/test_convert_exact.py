"""``convert`` sample for sample: what only changes the container or the bit depth
keeps every sample ffmpeg keeps, and changes the others as ffmpeg's swscale does.

The reference is the ffmpeg on the path, run on the same input: the test says where
mvtools and ffmpeg part, not what either should do.
"""

from __future__ import annotations

import shutil
import subprocess

import numpy as np
import pytest
from program_runner import assert_one_line_error, invoke, run

from mvtools.cli.main import cli
from mvtools.color.levels import requantize
from mvtools.io.yuv import YuvFormat

FFMPEG = shutil.which("ffmpeg")
needs_ffmpeg = pytest.mark.skipif(FFMPEG is None, reason="ffmpeg is not installed")

#: Odd sizes: the last chroma column and row cover one luma sample, and the rows do
#: not end on the 8x8 tile of the dither.
WIDTH, HEIGHT = 37, 29


def _random_video(path, pix_fmt: str, frames: int = 2, seed: int = 0) -> YuvFormat:
    fmt = YuvFormat.from_pix_fmt(WIDTH, HEIGHT, pix_fmt)
    samples = fmt.frame_bytes // fmt.bytes_per_sample * frames
    values = np.random.default_rng(seed).integers(0, fmt.max_value + 1, samples)
    path.write_bytes(values.astype(fmt.dtype).tobytes())
    return fmt


def _ffmpeg(source, source_fmt: str, output, pix_fmt: str) -> bytes:
    demuxer = (
        []
        if source.suffix == ".y4m"
        else ["-f", "rawvideo", "-pix_fmt", source_fmt, "-s", f"{WIDTH}x{HEIGHT}"]
    )
    subprocess.run(
        [
            FFMPEG,
            "-v",
            "error",
            "-y",
            *demuxer,
            "-i",
            str(source),
            "-f",
            "rawvideo",
            "-pix_fmt",
            pix_fmt,
            str(output),
        ],
        check=True,
    )
    return output.read_bytes()


def _convert(*args) -> None:
    code, _, err = invoke(cli, "convert", "-q", *map(str, args))
    assert code == 0, err


FORMATS = ["yuv420p", "yuv422p", "yuv444p", "gray", "yuv420p10le", "yuv444p16le", "gray16le"]


@pytest.mark.parametrize("pix_fmt", FORMATS)
def test_raw_to_y4m_and_back_is_byte_identical(tmp_path, pix_fmt):
    source = tmp_path / f"in_{WIDTH}x{HEIGHT}_{pix_fmt}.yuv"
    _random_video(source, pix_fmt)
    _convert(source, "-o", tmp_path / "v.y4m")
    _convert(tmp_path / "v.y4m", "-o", tmp_path / f"back_{WIDTH}x{HEIGHT}_{pix_fmt}.yuv")
    _convert(source, "-o", tmp_path / "copy.yuv")
    assert (tmp_path / f"back_{WIDTH}x{HEIGHT}_{pix_fmt}.yuv").read_bytes() == source.read_bytes()
    assert (tmp_path / "copy.yuv").read_bytes() == source.read_bytes()


def test_y4m_to_y4m_keeps_every_byte_and_the_frame_rate(tmp_path):
    fmt = _random_video(tmp_path / "planes.yuv", "yuv420p")
    data = (tmp_path / "planes.yuv").read_bytes()
    header = f"YUV4MPEG2 W{WIDTH} H{HEIGHT} F30000:1001 Ip A1:1 C420jpeg XYSCSS=420JPEG\n"
    frames = [data[i : i + fmt.frame_bytes] for i in range(0, len(data), fmt.frame_bytes)]
    source = header.encode("ascii") + b"".join(b"FRAME\n" + frame for frame in frames)
    (tmp_path / "in.y4m").write_bytes(source)
    _convert(tmp_path / "in.y4m", "-o", tmp_path / "out.y4m")
    assert (tmp_path / "out.y4m").read_bytes() == source


@needs_ffmpeg
@pytest.mark.parametrize("pix_fmt", ["yuv420p", "yuv422p", "yuv420p10le"])
def test_y4m_to_raw_is_ffmpegs_rawvideo(tmp_path, pix_fmt):
    source = tmp_path / f"in_{WIDTH}x{HEIGHT}_{pix_fmt}.yuv"
    _random_video(source, pix_fmt)
    _convert(source, "-o", tmp_path / "v.y4m")
    _convert(tmp_path / "v.y4m", "-o", tmp_path / f"ours_{WIDTH}x{HEIGHT}_{pix_fmt}.yuv")
    theirs = _ffmpeg(tmp_path / "v.y4m", pix_fmt, tmp_path / "theirs.yuv", pix_fmt)
    assert (tmp_path / f"ours_{WIDTH}x{HEIGHT}_{pix_fmt}.yuv").read_bytes() == theirs


DEPTHS = [
    ("yuv420p", "yuv420p10le"),
    ("yuv420p10le", "yuv420p"),
    ("yuv444p", "yuv444p16le"),
    ("yuv444p16le", "yuv444p"),
    ("yuv422p10le", "yuv422p16le"),
    ("yuv422p16le", "yuv422p10le"),
    ("yuv420p12le", "yuv420p"),
    ("yuv420p16le", "yuv420p12le"),
]


@needs_ffmpeg
@pytest.mark.parametrize(("source_fmt", "target_fmt"), DEPTHS)
def test_bit_depth_change_is_ffmpegs(tmp_path, source_fmt, target_fmt):
    source = tmp_path / f"in_{WIDTH}x{HEIGHT}_{source_fmt}.yuv"
    _random_video(source, source_fmt)
    _convert(source, "--out-pix-fmt", target_fmt, "-o", tmp_path / "ours.yuv")
    theirs = _ffmpeg(source, source_fmt, tmp_path / "theirs.yuv", target_fmt)
    assert (tmp_path / "ours.yuv").read_bytes() == theirs


@needs_ffmpeg
@pytest.mark.parametrize(
    ("from_bits", "to_bits"),
    [
        (9, 8),
        (10, 8),
        (12, 9),
        (12, 8),
        (14, 9),
        (14, 8),
        (16, 9),
        (16, 8),
        (16, 14),
        (8, 14),
        (9, 16),
    ],
)
def test_requantize_is_swscale_for_every_shift(tmp_path, from_bits, to_bits):
    # Depths the files do not carry (9, 14 bits) reach every dither matrix (1..8 bits dropped).
    def pix_fmt(bits):
        return "yuv444p" if bits == 8 else f"yuv444p{bits}le"

    def dtype(bits):
        return np.dtype(np.uint8 if bits == 8 else "<u2")

    planes = (
        np.random.default_rng(from_bits * to_bits)
        .integers(0, 2**from_bits, (3, HEIGHT, WIDTH))
        .astype(dtype(from_bits))
    )
    (tmp_path / "in.yuv").write_bytes(planes.tobytes())
    theirs = _ffmpeg(
        tmp_path / "in.yuv", pix_fmt(from_bits), tmp_path / "out.yuv", pix_fmt(to_bits)
    )
    ours = np.stack([requantize(plane, from_bits, to_bits) for plane in planes])
    assert ours.astype(dtype(to_bits)).tobytes() == theirs


@pytest.mark.parametrize(
    ("shallow", "deep"),
    [("yuv420p", "yuv420p10le"), ("yuv444p", "yuv444p16le"), ("yuv420p10le", "yuv420p16le")],
)
def test_deeper_and_back_gives_every_sample_back(tmp_path, shallow, deep):
    source = tmp_path / f"in_{WIDTH}x{HEIGHT}_{shallow}.yuv"
    _random_video(source, shallow)
    deeper = tmp_path / f"deep_{WIDTH}x{HEIGHT}_{deep}.yuv"
    _convert(source, "--out-pix-fmt", deep, "-o", deeper)
    _convert(deeper, "--out-pix-fmt", shallow, "-o", tmp_path / "back.yuv")
    assert (tmp_path / "back.yuv").read_bytes() == source.read_bytes()


def test_a_damaged_png_gives_one_line_and_no_opencv_log(tmp_path):
    # In a new process: OpenCV logs from C++ onto file descriptor 2, which the in-process
    # runner of the hostile-use table does not see.
    (tmp_path / "bad.png").write_bytes(b"\x89PNG\r\n\x1a\n" + b"x" * 40)
    code, _, err = run("convert", "bad.png", "-o", "o.yuv", cwd=tmp_path)
    assert code == 1
    assert_one_line_error(err, "bad.png: cannot decode the image")
    assert len(err.splitlines()) == 1, err
