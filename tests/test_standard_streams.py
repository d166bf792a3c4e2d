"""``-`` as a video input or output: a Y4M stream on standard input or output, so the
programs sit in pipes with ffmpeg and ffplay; a file named ``-`` is never written."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from program_runner import assert_one_line_error

from mvtools.io.yuv import YuvFormat, open_video, open_writer

REPO = Path(__file__).resolve().parent.parent
LINE = REPO / "sample_data" / "line"


def _frames(count: int = 3):
    """Frames whose every sample is known: Y = 10 * frame + row, U = 100 + frame, V = 200."""
    fmt = YuvFormat(16, 12)
    frames = []
    for index in range(count):
        y = np.repeat(np.arange(12, dtype=np.uint8)[:, None] + 20 * index, 16, axis=1)
        chroma = (np.full((6, 8), 100 + index, np.uint8), np.full((6, 8), 200, np.uint8))
        frames.append((y, *chroma))
    return fmt, frames


def _y4m_bytes(frames) -> bytes:
    header = b"YUV4MPEG2 W16 H12 F25:1 Ip A1:1 C420jpeg XYSCSS=420JPEG\n"
    return header + b"".join(b"FRAME\n" + b"".join(p.tobytes() for p in f) for f in frames)


def _mvtools(*args, stdin: bytes = b"", cwd=None):
    return subprocess.run(
        [sys.executable, "-m", "mvtools", *map(str, args)],
        input=stdin,
        capture_output=True,
        cwd=cwd,
    )


def test_a_writer_of_dash_streams_y4m_to_standard_output(tmp_path):
    _, frames = _frames()
    script = (
        "import numpy as np, sys\n"
        "from mvtools.io.yuv import YuvFormat, open_writer\n"
        f"frames = {[[p.tolist() for p in f] for f in frames]!r}\n"
        "with open_writer('-', YuvFormat(16, 12)) as writer:\n"
        "    for f in frames: writer.write(tuple(np.array(p, np.uint8) for p in f))\n"
    )
    out = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, check=True, cwd=tmp_path
    ).stdout
    assert out == _y4m_bytes(frames)
    assert list(tmp_path.iterdir()) == []  # no file named '-'


def test_standard_input_is_read_as_y4m_and_its_copy_removed(tmp_path, monkeypatch):
    _, frames = _frames()
    spool = tmp_path / "tmp"
    spool.mkdir()
    monkeypatch.setenv("TMPDIR", str(spool))
    reference = tmp_path / "same_16x12_yuv420p.yuv"
    reference.write_bytes(b"".join(b"".join(p.tobytes() for p in f) for f in frames))
    done = _mvtools("evaluate", reference, "-", "--json", stdin=_y4m_bytes(frames))
    assert done.returncode == 0, done.stderr
    scores = json.loads(done.stdout)
    # The stream's three frames are the file's exactly.
    assert [frame["Y-PSNR"] for frame in scores["frames"]] == ["inf"] * 3
    assert [frame["YUV-PSNR"] for frame in scores["frames"]] == ["inf"] * 3
    assert list(spool.iterdir()) == []


@pytest.mark.slow
def test_a_pipe_from_synthesize_into_evaluate_scores_as_the_file_does(tmp_path):
    synthesized = _mvtools("synthesize", LINE / "synthesize_cam2.cfg", "-q", "-o", "-")
    assert synthesized.returncode == 0, synthesized.stderr
    assert synthesized.stdout.startswith(b"YUV4MPEG2 W256 H192 ")
    reference = LINE / "v2_texture_256x192_yuv420p.yuv"
    piped = _mvtools("evaluate", reference, "-", "--json", stdin=synthesized.stdout)
    assert piped.returncode == 0, piped.stderr
    # The stream holds the frames of the raw synthesized file exactly.
    raw = tmp_path / "v2_256x192_yuv420p.yuv"
    with (
        open_video(_write(tmp_path / "s.y4m", synthesized.stdout)) as reader,
        open_writer(raw, reader.format) as writer,
    ):
        for frame in reader:
            writer.write(frame)
    direct = _mvtools("evaluate", reference, raw, "--json")
    assert piped.stdout.replace(b'"-"', b"X") == direct.stdout.replace(f'"{raw}"'.encode(), b"X")
    assert not (REPO / "-").exists()


def _write(path: Path, data: bytes) -> Path:
    path.write_bytes(data)
    return path


def test_standard_input_that_is_not_y4m_is_one_line(tmp_path):
    reference = tmp_path / "r_16x12_yuv420p.yuv"
    reference.write_bytes(bytes(288))
    done = _mvtools("evaluate", reference, "-", stdin=bytes(288))
    assert done.returncode == 1
    assert_one_line_error(done.stderr.decode(), "standard input is not a Y4M stream")
    assert list(tmp_path.iterdir()) == [reference]


@pytest.mark.slow
@pytest.mark.skipif(shutil.which("ffmpeg") is None, reason="ffmpeg is not installed")
def test_ffmpeg_piped_into_a_configuration_input_synthesizes_as_the_file_does(tmp_path):
    view = LINE / "v1_texture_256x192_yuv420p.yuv"
    ffmpeg = ["ffmpeg", "-loglevel", "error", "-s", "256x192", "-pix_fmt", "yuv420p"]
    stream = subprocess.run(
        [*ffmpeg, "-f", "rawvideo", "-i", view, "-f", "yuv4mpegpipe", "-"],
        capture_output=True,
        check=True,
    ).stdout
    config = LINE / "synthesize_cam2.cfg"
    piped = _mvtools("synthesize", config, "LeftViewImageName=-", "-q", "-o", "-", stdin=stream)
    assert piped.returncode == 0, piped.stderr
    from_file = _mvtools("synthesize", config, "-q", "-o", "-")
    assert piped.stdout == from_file.stdout


def test_convert_reads_and_writes_standard_streams(tmp_path):
    """``convert - -o raw.yuv`` stores the piped Y4M's samples; ``convert raw.yuv -o -``
    streams them back as the same Y4M, and no file named '-' appears."""
    _, frames = _frames()
    stream = _y4m_bytes(frames)
    raw = tmp_path / "raw_16x12_yuv420p.yuv"
    stored = _mvtools("convert", "-", "-o", raw, stdin=stream, cwd=tmp_path)
    assert stored.returncode == 0, stored.stderr
    assert raw.read_bytes() == b"".join(p.tobytes() for f in frames for p in f)
    streamed = _mvtools("convert", raw, "-o", "-", cwd=tmp_path)
    assert streamed.returncode == 0, streamed.stderr
    assert streamed.stdout == stream
    assert sorted(p.name for p in tmp_path.iterdir()) == [raw.name]
