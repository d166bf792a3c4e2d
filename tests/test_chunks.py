"""Long sequences split into frame chunks that run in parallel: the chunks' outputs,
concatenated, are the bytes of one run over all frames (issue 8), for every program that
works frame by frame."""

from __future__ import annotations

from pathlib import Path

import pytest

from mvtools.cli import colorcorrect, estimate_depth, pack, rectify, synthesize
from program_runner import invoke

SAMPLE = Path(__file__).resolve().parent.parent / "sample_data"
LINE, DISTORTED = SAMPLE / "line", SAMPLE / "distorted"
TEXTURE = "v{}_texture_256x192_yuv420p.yuv"
# The sample videos have 3 frames: chunks of frames 0-1 and 2, and of 0 and 1-2.
CHUNKINGS = [((0, 2), (2, 1)), ((0, 1), (1, 2))]


def rectify_run(out: Path, chunk):
    return invoke(rectify.command, DISTORTED / "cameras.txt", "-o", out, *chunk,
                  "--texture", "cam1", DISTORTED / TEXTURE.format(1),
                  "--texture", "cam3", DISTORTED / TEXTURE.format(3)), out / TEXTURE.format(1)


def colorcorrect_run(out: Path, chunk):
    # every chunk estimates its tables from the same frame
    return invoke(colorcorrect.command, "--estimate-from", 0, "-o", out, *chunk,
                  *(arg for view in (1, 2, 3) for arg in
                    ("--view", f"cam{view}", DISTORTED / TEXTURE.format(view)))), \
        out / TEXTURE.format(3)


def pack_run(out: Path, chunk):
    out.mkdir(parents=True, exist_ok=True)
    return invoke(pack.command, "-o", out / "grid.yuv", *chunk,
                  *(arg for view in range(5) for arg in
                    ("--view", f"cam{view}", LINE / TEXTURE.format(view)))), out / "grid.yuv"


def _config_range(chunk):
    if not chunk:
        return []
    start, count = chunk[1], chunk[3]
    return [f"StartFrame={start}", f"TotalNumberOfFrames={count}"]


def estimate_depth_run(out: Path, chunk):
    out.mkdir(parents=True, exist_ok=True)
    output = out / "depth_256x192_yuv420p.yuv"
    return invoke(estimate_depth.command, LINE / "depth_cam2.cfg", *_config_range(chunk),
                  f"FileOutputDepthMapImage={output}", "--data-dir", LINE, "-q"), output


def synthesize_run(out: Path, chunk):
    # TemporalImprovementOption smooths depth over all earlier frames: a chunk cannot
    # know them, so frame-by-frame synthesis is what chunks reproduce
    out.mkdir(parents=True, exist_ok=True)
    output = out / "synthesized_256x192_yuv420p.yuv"
    return invoke(synthesize.command, LINE / "synthesize_cam2.cfg", *_config_range(chunk),
                  "TemporalImprovementOption=0", "--data-dir", LINE, "-o", output, "-q"), output


@pytest.mark.parametrize("run", [rectify_run, colorcorrect_run, pack_run, estimate_depth_run,
                                 synthesize_run], ids=lambda run: run.__name__[:-4])
@pytest.mark.parametrize("chunking", CHUNKINGS)
def test_chunks_concatenate_to_one_run(tmp_path, run, chunking):
    (code, _, stderr), whole = run(tmp_path / "whole", [])
    assert code == 0, stderr
    pieces = b""
    for index, (start, count) in enumerate(chunking):
        (code, _, stderr), output = run(tmp_path / f"chunk{index}",
                                        ["--start-frame", start, "--frames", count])
        assert code == 0, stderr
        pieces += output.read_bytes()
    assert pieces == whole.read_bytes()
