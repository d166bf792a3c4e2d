"""synthesize and estimate-depth refuse an output that names an input before any work:
the one error line is all they print (the table of ``tests/hostile/synthesize_depth.py``
checks the line itself)."""

from __future__ import annotations

import pytest
from hostile import LINE_SYNTHESIS
from hostile.synthesize_depth import DERS_CONFIG, LINE_DERS, SYNTHESIS_CONFIG
from program_runner import invoke

from mvtools.cli.main import cli


@pytest.mark.parametrize(
    "files, args",
    [
        (LINE_DERS, ("estimate-depth", DERS_CONFIG, "-o", "cameras.txt")),
        (LINE_DERS, ("estimate-depth", DERS_CONFIG, "-o", "v1_texture_256x192_yuv420p.yuv")),
        (LINE_SYNTHESIS, ("synthesize", SYNTHESIS_CONFIG, "-o", "cameras.txt")),
        (
            LINE_SYNTHESIS,
            (
                "synthesize",
                SYNTHESIS_CONFIG,
                "-o",
                "out.yuv",
                "--output-depth",
                "v3_depth_256x192_yuv420p.yuv",
            ),
        ),
    ],
    ids=[
        "estimate-depth onto the cameras",
        "estimate-depth onto a view",
        "synthesize onto the cameras",
        "synthesize --output-depth onto a depth map",
    ],
)
def test_an_output_onto_an_input_fails_before_any_work(files, args, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    files(tmp_path)
    code, _, err = invoke(cli, *args)
    assert code == 2
    assert len(err.splitlines()) == 1 and "would overwrite an input" in err, err
