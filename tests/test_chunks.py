"""Long sequences split into frame chunks that run in parallel: the chunks' outputs,
concatenated, are the bytes of one run over all frames (issue 8), for every program that
works frame by frame."""

from __future__ import annotations

from pathlib import Path

import pytest
from program_runner import invoke

from mvtools.cli import colorcorrect, estimate_depth, pack, rectify, synthesize

pytestmark = pytest.mark.slow  # `make test-fast` leaves these out

SAMPLE = Path(__file__).resolve().parent.parent / "sample_data"
LINE, DISTORTED = SAMPLE / "line", SAMPLE / "distorted"
TEXTURE = "v{}_texture_256x192_yuv420p.yuv"
# The sample videos have 3 frames: chunks of frames 0-1 and 2, and of 0 and 1-2.
CHUNKINGS = [((0, 2), (2, 1)), ((0, 1), (1, 2))]


def rectify_run(out: Path, chunk):
    return invoke(
        rectify.command,
        DISTORTED / "cameras.txt",
        "-o",
        out,
        *chunk,
        "--view",
        "cam1",
        DISTORTED / TEXTURE.format(1),
        "--view",
        "cam3",
        DISTORTED / TEXTURE.format(3),
    ), out / TEXTURE.format(1)


def colorcorrect_run(out: Path, chunk):
    # every chunk estimates its tables from the same frame
    return invoke(
        colorcorrect.command,
        "--estimate-from",
        0,
        "-o",
        out,
        *chunk,
        *(
            arg
            for view in (1, 2, 3)
            for arg in ("--view", f"cam{view}", DISTORTED / TEXTURE.format(view))
        ),
    ), out / TEXTURE.format(3)


def pack_run(out: Path, chunk):
    out.mkdir(parents=True, exist_ok=True)
    return invoke(
        pack.command,
        "-o",
        out / "grid.yuv",
        *chunk,
        *(
            arg
            for view in range(5)
            for arg in ("--view", f"cam{view}", LINE / TEXTURE.format(view))
        ),
    ), out / "grid.yuv"


def _config_range(chunk):
    if not chunk:
        return []
    start, count = chunk[1], chunk[3]
    return [f"StartFrame={start}", f"TotalNumberOfFrames={count}"]


def estimate_depth_run(out: Path, chunk, *settings):
    out.mkdir(parents=True, exist_ok=True)
    output = out / "depth_256x192_yuv420p.yuv"
    return invoke(
        estimate_depth.command,
        LINE / "depth_cam2.cfg",
        *_config_range(chunk),
        *settings,
        f"FileOutputDepthMapImage={output}",
        "--data-dir",
        LINE,
        "-q",
    ), output


def synthesize_run(out: Path, chunk, *settings):
    out.mkdir(parents=True, exist_ok=True)
    output = out / "synthesized_256x192_yuv420p.yuv"
    return invoke(
        synthesize.command,
        LINE / "synthesize_cam2.cfg",
        *_config_range(chunk),
        *settings,
        "--data-dir",
        LINE,
        "-o",
        output,
        "-q",
    ), output


# The programs whose frames can depend on the frames before them, with and without the
# settings that make them so: a chunk then takes in the earlier frames (all of them, or
# those since the last multiple of TemporalRefreshPeriod).
# With Threshold 1, four fifths of the sample scene's 8x8 blocks are static from frame to frame.
TEMPORAL_DEPTH = ("TemporalEnhancement=1", "Threshold=1")
FRAME_RANGE_CASES = {
    "synthesize-temporal-filter": (synthesize_run, ("TemporalImprovementOption=1",)),
    "synthesize-frame-by-frame": (synthesize_run, ("TemporalImprovementOption=0",)),
    "estimate-depth-frame-by-frame": (estimate_depth_run, ()),
    "estimate-depth-temporal": (estimate_depth_run, TEMPORAL_DEPTH),
    "estimate-depth-temporal-refresh-2": (
        estimate_depth_run,
        TEMPORAL_DEPTH + ("TemporalRefreshPeriod=2",),
    ),
}


def _chunked_bytes(tmp_path: Path, run, chunking, *settings) -> bytes:
    pieces = b""
    for index, (start, count) in enumerate(chunking):
        (code, _, stderr), output = run(
            tmp_path / f"chunk{index}", ["--start-frame", start, "--frames", count], *settings
        )
        assert code == 0, stderr
        pieces += output.read_bytes()
    return pieces


def _whole_bytes(out: Path, run, *settings) -> bytes:
    (code, _, stderr), whole = run(out, [], *settings)
    assert code == 0, stderr
    return whole.read_bytes()


@pytest.mark.parametrize(
    "run", [rectify_run, colorcorrect_run, pack_run], ids=lambda run: run.__name__[:-4]
)
@pytest.mark.parametrize("chunking", CHUNKINGS)
def test_chunks_concatenate_to_one_run(tmp_path, run, chunking):
    assert _chunked_bytes(tmp_path, run, chunking) == _whole_bytes(tmp_path / "whole", run)


@pytest.mark.parametrize("case", FRAME_RANGE_CASES)
@pytest.mark.parametrize("chunking", CHUNKINGS)
def test_chunks_of_temporal_runs_concatenate_to_one_run(tmp_path, case, chunking):
    run, settings = FRAME_RANGE_CASES[case]
    assert _chunked_bytes(tmp_path, run, chunking, *settings) == _whole_bytes(
        tmp_path / "whole", run, *settings
    )


@pytest.mark.parametrize(
    "run, settings, off",
    [
        (synthesize_run, ("TemporalImprovementOption=1",), "TemporalImprovementOption=0"),
        (estimate_depth_run, TEMPORAL_DEPTH, "TemporalEnhancement=0"),
    ],
)
def test_the_temporal_settings_change_the_later_frames(tmp_path, run, settings, off):
    """The temporal chunks above test something: with the setting on, frames after the
    first differ from a frame-by-frame run (and the first frame does not)."""
    on_bytes = _whole_bytes(tmp_path / "on", run, *settings)
    off_bytes = _whole_bytes(tmp_path / "off", run, *settings, off)
    frame = len(on_bytes) // 3
    assert on_bytes[:frame] == off_bytes[:frame]
    assert on_bytes[frame : 2 * frame] != off_bytes[frame : 2 * frame]
    assert on_bytes[2 * frame :] != off_bytes[2 * frame :]


def test_a_refresh_period_estimates_its_frames_afresh(tmp_path):
    """With TemporalRefreshPeriod 2, frame 2 is estimated as if it were the first."""
    refreshed = _whole_bytes(
        tmp_path / "refreshed", estimate_depth_run, *TEMPORAL_DEPTH, "TemporalRefreshPeriod=2"
    )
    frame_by_frame = _whole_bytes(tmp_path / "off", estimate_depth_run, "TemporalEnhancement=0")
    frame = len(refreshed) // 3
    assert refreshed[2 * frame :] == frame_by_frame[2 * frame :]
    assert refreshed[frame : 2 * frame] != frame_by_frame[frame : 2 * frame]
