"""mvtools against the MPEG reference programs VSRS 4.2 and RVS 4.0 on identical input.

The inputs, configurations and the reference programs' scores are those of the
reference outputs' README (``reference_outputs/README.md`` of the shared data): every
score asserted here is one of the reference programs', never one of mvtools itself.

- Cones im4 from im2 and im6 (multiview plus depth, 448x368), the shipped
  configurations ``vsrs_cones_general.cfg`` and ``vsrs_cones_1d.cfg`` with
  ``Precision`` and ``BoundaryNoiseRemoval`` set on the command line as VSRS was run:
  mvtools must beat VSRS at the same setting by :data:`MARGIN_OVER_VSRS` and RVS's
  default run.
- Poznan Hall 2 camera 7 synthesized from camera 5 alone (given as left and right
  view): at least VSRS's score in either mode; from cameras 5 and 7: at least
  :data:`HALL_FROM_BOTH_LEAST`.

Y-PSNR over the whole luma plane against the real view.
"""

from __future__ import annotations

import pytest
from reference_cases import (
    CAMERA_5_AS_RIGHT,
    MODES,
    RVS_CONES,
    VSRS_CONES,
    VSRS_HALL_FROM_CAMERA_5,
)
from shared_data import shared_data
from synthesize_runner import run_synthesize

from mvtools.io.yuv import YuvFormat, read_frame
from mvtools.metrics import psnr

pytestmark = pytest.mark.slow  # `make test-fast` leaves these out

CONES = YuvFormat(448, 368)
HALL = YuvFormat(1920, 1088)

#: How far above VSRS at the same setting mvtools must be (dB).
MARGIN_OVER_VSRS = 0.3
#: Camera 7 from cameras 5 and 7: the real view is one of the references.
HALL_FROM_BOTH_LEAST = 40.0


def synthesized_luma(config, *settings, data_dir, fmt, folder):
    """Luma of the one frame ``mvtools synthesize CONFIG --data-dir DATA_DIR SETTINGS``
    writes into ``folder``."""
    output = folder / f"synthesized_{fmt.width}x{fmt.height}_yuv420p.yuv"
    code, _, err = run_synthesize(
        config, "--data-dir", data_dir, "-q", *settings, "-o", output, cwd=folder
    )
    assert code == 0, err
    return read_frame(output, fmt)[0]


@pytest.mark.parametrize(
    "mode, precision, noise_removal",
    sorted(VSRS_CONES),
    ids=[f"{mode}-P{p}-B{b}" for mode, p, b in sorted(VSRS_CONES)],
)
def test_cones_beats_vsrs_and_rvs_at_every_vsrs_setting(tmp_path, mode, precision, noise_removal):
    cones = shared_data("reference_outputs", "cones_mvd")
    luma = synthesized_luma(
        cones / f"vsrs_cones_{mode}.cfg",
        f"Precision={precision}",
        f"BoundaryNoiseRemoval={noise_removal}",
        data_dir=cones,
        fmt=CONES,
        folder=tmp_path,
    )
    truth = read_frame(cones / "cones_4_448x368_yuv420p.yuv", CONES)[0]
    score = psnr(truth, luma, max_value=255)
    vsrs = VSRS_CONES[mode, precision, noise_removal]
    assert score >= vsrs + MARGIN_OVER_VSRS, f"{score:.2f} dB against VSRS's {vsrs}"
    assert score > RVS_CONES, f"{score:.2f} dB against RVS's {RVS_CONES}"


@pytest.fixture(scope="module")
def hall_camera_7(tmp_path_factory):
    """Y-PSNR of Poznan Hall 2 camera 7 synthesized by mode from camera 5 alone
    (``from camera 5``) and from cameras 5 and 7 (``from both``)."""
    hall = shared_data("mpeg", "poznan_hall2")
    config = hall / "config" / "VSRS" / "vsrs_poznanhall2_ori.cfg"
    truth = read_frame(hall / "hall_I_cam07.yuv", HALL)[0]
    scores = {}
    for mode, synthesis_mode in MODES.items():
        for references, settings in (("from camera 5", CAMERA_5_AS_RIGHT), ("from both", ())):
            luma = synthesized_luma(
                config,
                "VirtualCameraName=param_cam7",
                *settings,
                f"SynthesisMode={synthesis_mode}",
                data_dir=hall,
                fmt=HALL,
                folder=tmp_path_factory.mktemp("hall"),
            )
            scores[mode, references] = psnr(truth, luma, max_value=255)
    return scores


@pytest.mark.parametrize(
    "mode",
    [
        "general",
        pytest.param(
            "1d",
            marks=pytest.mark.xfail(
                strict=True,
                reason="32.28 dB against VSRS's 32.67: VSRS's 1D mode scales its "
                "upsampled virtual row down with a [1 2 1] filter, whose blur "
                "scores 0.4 dB more on this view, camera 7 being softer than "
                "camera 5; no one row filter meets both bars: [1 2 1] on our "
                "output gives Hall 32.67 but Cones 1D P2 30.37 (bar 31.15)",
            ),
        ),
    ],
)
def test_hall_camera_7_from_camera_5_reaches_vsrs(hall_camera_7, mode):
    score = hall_camera_7[mode, "from camera 5"]
    vsrs = VSRS_HALL_FROM_CAMERA_5[mode]
    assert score >= vsrs, f"{score:.2f} dB against VSRS's {vsrs}"


@pytest.mark.parametrize("mode", MODES)
def test_hall_camera_7_from_cameras_5_and_7(hall_camera_7, mode):
    assert hall_camera_7[mode, "from both"] >= HALL_FROM_BOTH_LEAST
