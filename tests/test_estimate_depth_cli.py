"""``mvtools estimate-depth`` in stereo-pair mode: the files it writes hold the disparity
(a synthetic pair with a known shift, Middlebury Tsukuba scored by ``mvtools evaluate``),
their encoding is exact, and bad input gives one line, the right exit code, no output."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from program_runner import assert_one_line_error, run
from program_runner import invoke as invoke_program
from shared_data import shared_data

from mvtools.cli.estimate_depth import command
from mvtools.io.images import read_image, write_image
from mvtools.run.depth import disparity_png_values

#: Bad 1.0 over all known pixels of Tsukuba. Measured with the defaults (bp, integer
#: levels): 2.59 % (PFM and PNG); winner-takes-all on absolute RGB differences: 48.9 %.
TSUKUBA_BAD1_LIMIT = 4.0


def invoke(*args):
    return invoke_program(command, *args)


def shifted_pair(disparity: int, shape=(40, 96), seed=0) -> tuple[np.ndarray, np.ndarray]:
    """Random texture and the same texture seen ``disparity`` px further left:
    ``right[y, x - d] = left[y, x]``."""
    height, width = shape
    texture = np.random.default_rng(seed).integers(
        0, 256, size=(height, width + disparity, 3), dtype=np.uint8
    )
    return texture[:, :width].copy(), texture[:, disparity : disparity + width].copy()


@pytest.fixture
def pair(tmp_path) -> tuple[Path, Path]:
    left, right = shifted_pair(5)
    write_image(tmp_path / "left.png", left)
    write_image(tmp_path / "right.png", right)
    return tmp_path / "left.png", tmp_path / "right.png"


@pytest.fixture
def known_estimate(monkeypatch):
    """A stand-in matcher returning a fixed map, to check what the files hold."""
    estimate = np.array([[0.0, 1.25, 2.5, np.nan], [3.0, np.nan, 7.875, 4.0]], np.float32)
    calls = []

    def estimate_disparity(
        left,
        right,
        *,
        max_disparity,
        min_disparity=0,
        method="bp",
        cost="ad-census",
        subpixel=False,
        segment_planes=True,
        segmentation=False,
        view="left",
    ):
        calls.append(
            (left.shape, left.dtype, max_disparity, min_disparity, method, cost, segment_planes)
        )
        height, width = left.shape[:2]
        return np.tile(estimate, (height // 2, width // 4))

    monkeypatch.setattr("mvtools.depth.stereo.estimate_disparity", estimate_disparity)
    return estimate, calls


# ------------------------------------------------------------------ what the files hold


def test_png_values_are_scaled_rounded_disparities_with_zero_for_unknown():
    disparity = np.array([[0.0, 1.25, 2.6, np.nan], [np.inf, 16.0, 0.1, 3.124]])
    expected = np.array([[0, 5, 10, 0], [0, 64, 0, 12]], np.uint16)
    np.testing.assert_array_equal(disparity_png_values(disparity, scale=4), expected)


def test_outputs_hold_the_estimate_inf_in_pfm_zero_in_png(tmp_path, pair, known_estimate):
    estimate, calls = known_estimate
    code, _, err = invoke(
        "--left",
        pair[0],
        "--right",
        pair[1],
        "--disparities",
        16,
        "--min-disparity",
        1,
        "--method",
        "local",
        "-o",
        tmp_path / "d.pfm",
        "--png",
        tmp_path / "d.png",
        "--png-scale",
        8,
    )
    assert code == 0, err
    assert calls == [((40, 96, 3), np.uint8, 16, 1, "local", "ad-census", True)]
    pfm = read_image(tmp_path / "d.pfm")
    full = np.tile(estimate, (20, 24))
    assert pfm.dtype == np.float32 and pfm.shape == (40, 96)
    np.testing.assert_array_equal(pfm, np.where(np.isnan(full), np.inf, full))
    png = read_image(tmp_path / "d.png")
    assert png.dtype == np.uint16
    np.testing.assert_array_equal(png[:2, :4], [[0, 10, 20, 0], [24, 0, 63, 32]])


def test_segment_planes_can_be_switched_off(tmp_path, pair, known_estimate):
    _, calls = known_estimate
    code, _, err = invoke(
        "--left",
        pair[0],
        "--right",
        pair[1],
        "--disparities",
        16,
        "--no-segment-planes",
        "-o",
        tmp_path / "d.pfm",
    )
    assert code == 0, err
    assert calls[0][-1] is False


def test_the_cost_is_chosen_by_name(tmp_path, pair, known_estimate):
    _, calls = known_estimate
    code, _, err = invoke(
        "--left",
        pair[0],
        "--right",
        pair[1],
        "--disparities",
        16,
        "--cost",
        "census-gradient",
        "-o",
        tmp_path / "d.pfm",
    )
    assert code == 0, err
    assert calls[0][5] == "census-gradient"


def test_grey_pictures_are_given_as_rgb(tmp_path, known_estimate):
    _, calls = known_estimate
    grey = np.arange(12 * 20, dtype=np.uint8).reshape(12, 20)
    write_image(tmp_path / "l.pgm", grey)
    write_image(tmp_path / "r.pgm", grey)
    code, _, err = invoke(
        "--left",
        tmp_path / "l.pgm",
        "--right",
        tmp_path / "r.pgm",
        "--disparities",
        4,
        "-o",
        tmp_path / "d.pfm",
        "-q",
    )
    assert code == 0, err
    assert calls[0][:2] == ((12, 20, 3), np.uint8)
    assert err == ""


def test_synthetic_shift_is_recovered_in_pfm_and_png(tmp_path, pair):
    code, _, err = invoke(
        "--left",
        pair[0],
        "--right",
        pair[1],
        "--disparities",
        16,
        "-o",
        tmp_path / "d.pfm",
        "--png",
        tmp_path / "d.png",
    )
    assert code == 0, err
    pfm, png = read_image(tmp_path / "d.pfm"), read_image(tmp_path / "d.png")
    # Pixels x < 5 of the left view are not in the right one; keep a margin of 3 px.
    inner = (slice(3, -3), slice(5 + 3, -3))
    assert np.mean(np.abs(pfm[inner] - 5) <= 0.125) > 0.95
    assert np.mean(png[inner] == 5 * 4) > 0.95


def test_the_right_views_disparity(tmp_path):
    # Cones' right view against its own ground truth (disp6): measured 8.6 % bad 1.0 over
    # all known pixels; the left view's map scores 51.9 % there
    cones = shared_data("middlebury", "2003", "cones")
    code, _, err = run(
        "estimate-depth",
        "--left",
        cones / "im2.png",
        "--right",
        cones / "im6.png",
        "--disparities",
        64,
        "--disparity-of",
        "right",
        "-o",
        tmp_path / "d.pfm",
    )
    assert code == 0, err
    code, out, err = run(
        "evaluate",
        "--disparity",
        cones / "disp6.png",
        tmp_path / "d.pfm",
        "--gt-scale",
        4,
        "--json",
    )
    assert code == 0, err
    assert json.loads(out)["bad_all"]["1"] < 12.0


def test_tsukuba_scored_by_evaluate(tmp_path):
    tsukuba = shared_data("middlebury", "2001", "tsukuba")
    code, _, err = run(
        "estimate-depth",
        "--left",
        tsukuba / "tsukuba3.png",
        "--right",
        tsukuba / "tsukuba4.png",
        "--disparities",
        16,
        "-o",
        tmp_path / "d.pfm",
        "--png",
        tmp_path / "d.png",
        "--png-scale",
        16,
    )
    assert code == 0, err
    assert "disparity estimated" in err
    scores = {}
    for name, scale in (("d.pfm", "1"), ("d.png", "16")):
        code, out, err = run(
            "evaluate",
            "--disparity",
            tsukuba / "disp3.pgm",
            tmp_path / name,
            "--disparity-scale",
            scale,
            "--json",
        )
        assert code == 0, err
        scores[name] = json.loads(out)["bad_all"]["1"]
    assert scores["d.pfm"] < TSUKUBA_BAD1_LIMIT
    assert scores["d.png"] < TSUKUBA_BAD1_LIMIT


# ------------------------------------------------------------------ bad input


@pytest.mark.parametrize(
    "args, code, fragment",
    [
        (["--disparities", 16, "--method", "magic"], 2, "'magic' is not one of 'sgm', 'bp'"),
        (
            ["--disparities", 16, "--cost", "census"],
            2,
            "'census' is not one of 'ad-census', 'census-gradient'",
        ),
        (["--disparities", 16, "--min-disparity", 16], 2, "empty disparity range"),
        (
            ["--disparities", 16, "--view", "cam0", "v0.yuv"],
            2,
            "--view: DERS options need a configuration file",
        ),
        (["--disparities", 4, "--min-disparity", 10], 2, "empty disparity range"),
        (["--disparities", 16, "--png", "{tmp}/d.png", "--min-disparity", -2], 2, "negative"),
        (["--disparities", 16, "--png", "{tmp}/d.png", "--png-scale", 0], 2, "--png-scale"),
        (["--disparities", 9000, "--png", "{tmp}/d.png", "--png-scale", 8], 2, "65535"),
        (["--disparities", 16, "--png", "{tmp}/d.tif"], 2, ".png"),
    ],
)
def test_bad_options(tmp_path, pair, known_estimate, args, code, fragment):
    args = [str(arg).replace("{tmp}", str(tmp_path)) for arg in args]
    before = sorted(tmp_path.iterdir())
    exit_code, _, err = invoke(
        "--left", pair[0], "--right", pair[1], *args, "-o", tmp_path / "d.pfm"
    )
    assert exit_code == code
    assert_one_line_error(err, fragment)
    assert sorted(tmp_path.iterdir()) == before
    assert known_estimate[1] == []


def test_missing_picture(tmp_path, pair, known_estimate):
    code, _, err = invoke(
        "--left",
        pair[0],
        "--right",
        tmp_path / "nope.png",
        "--disparities",
        16,
        "-o",
        tmp_path / "d.pfm",
    )
    assert code == 2
    assert_one_line_error(err, "nope.png")
    assert not (tmp_path / "d.pfm").exists()


def test_pictures_of_different_sizes(tmp_path, pair, known_estimate):
    write_image(tmp_path / "small.png", np.zeros((20, 96, 3), np.uint8))
    code, _, err = invoke(
        "--left",
        pair[0],
        "--right",
        tmp_path / "small.png",
        "--disparities",
        16,
        "-o",
        tmp_path / "d.pfm",
        "--png",
        tmp_path / "d.png",
    )
    assert code == 1
    assert_one_line_error(err, "small.png", "96x20", "96x40")
    assert not (tmp_path / "d.pfm").exists() and not (tmp_path / "d.png").exists()


def test_output_must_be_pfm_and_not_an_input(tmp_path, pair, known_estimate):
    code, _, err = invoke(
        "--left", pair[0], "--right", pair[1], "--disparities", 16, "-o", tmp_path / "d.png"
    )
    assert code == 2
    assert_one_line_error(err, ".pfm")
    code, _, err = invoke(
        "--left",
        pair[0],
        "--right",
        pair[1],
        "--disparities",
        16,
        "-o",
        tmp_path / "d.pfm",
        "--png",
        pair[0],
    )
    assert code == 2
    assert_one_line_error(err, "would overwrite an input")
    assert not (tmp_path / "d.pfm").exists()


def test_missing_required_option(tmp_path, pair):
    code, _, err = run(
        "estimate-depth", "--left", pair[0], "--right", pair[1], "-o", tmp_path / "d.pfm"
    )
    assert code == 2
    assert_one_line_error(err, "--disparities is required")


def test_stereo_pair_options_do_not_go_with_a_ders_configuration(tmp_path, pair):
    # The DERS mode itself is tested in test_estimate_depth_ders.py.
    config = tmp_path / "ders.cfg"
    config.write_text("DepthType 0\n")
    left, right = pair
    code, _, err = run(
        "estimate-depth", config, "--left", left, "--right", right, "-o", tmp_path / "out.pfm"
    )
    assert code == 2
    assert_one_line_error(
        err, "--left, --right: stereo-pair options cannot go with a DERS configuration"
    )
    assert not (tmp_path / "out.pfm").exists()
