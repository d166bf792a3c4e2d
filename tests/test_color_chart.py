"""Colorimetry (mvtools.color.colorimetry), colour-chart correction (mvtools.color.chart,
mvtools.color.chart_correction) and the chart files (mvtools.io.color_charts),
against published numbers: Sharma, Wu and Dalal's CIEDE2000 pairs, Lindbloom's sRGB and
Bradford matrices, colour-science's ColorChecker values and OpenCV's ccm tests; and a
synthetic photograph of a ColorChecker with a known camera response."""

import json
from dataclasses import replace

import cv2
import numpy as np
import pytest
from chart_scene import CORNERS, MISMATCH, photograph
from shared_data import REPO_ROOT, shared_data

from mvtools.color.chart import GREY_PATCHES, detect_chart, sample_patches
from mvtools.color.chart_correction import fit_chart_correction
from mvtools.color.colorimetry import (
    SRGB_TO_XYZ,
    WHITE_D50,
    WHITE_D65,
    XYZ_TO_SRGB,
    bradford_matrix,
    delta_e_2000,
    gamma_to_linear,
    lab_to_linear_rgb,
    lab_to_xyz,
    linear_rgb_to_lab,
    linear_to_gamma,
    linear_to_srgb,
    srgb_to_linear,
    xyz_to_lab,
)
from mvtools.errors import ConfigError, DataError
from mvtools.io.color_charts import ColorChart, read_colorchecker, read_colorchecker_srgb

CHARTS_JSON = "CCS_COLOURCHECKERS_colour_science_0.4.7.json"
SRGB_CSV = "ColorChecker24_after_Nov2014_sRGB8bit_Bradford_D50toD65.csv"

# Sharma, Wu, Dalal, "The CIEDE2000 color-difference formula: implementation notes,
# supplementary test data, and mathematical observations", Color Res. Appl. 30(1) 2005,
# Table 1: L1, a1, b1, L2, a2, b2, delta E 2000 (all 34 pairs).
SHARMA_PAIRS = [
    (50.0000, 2.6772, -79.7751, 50.0000, 0.0000, -82.7485, 2.0425),
    (50.0000, 3.1571, -77.2803, 50.0000, 0.0000, -82.7485, 2.8615),
    (50.0000, 2.8361, -74.0200, 50.0000, 0.0000, -82.7485, 3.4412),
    (50.0000, -1.3802, -84.2814, 50.0000, 0.0000, -82.7485, 1.0000),
    (50.0000, -1.1848, -84.8006, 50.0000, 0.0000, -82.7485, 1.0000),
    (50.0000, -0.9009, -85.5211, 50.0000, 0.0000, -82.7485, 1.0000),
    (50.0000, 0.0000, 0.0000, 50.0000, -1.0000, 2.0000, 2.3669),
    (50.0000, -1.0000, 2.0000, 50.0000, 0.0000, 0.0000, 2.3669),
    (50.0000, 2.4900, -0.0010, 50.0000, -2.4900, 0.0009, 7.1792),
    (50.0000, 2.4900, -0.0010, 50.0000, -2.4900, 0.0010, 7.1792),
    (50.0000, 2.4900, -0.0010, 50.0000, -2.4900, 0.0011, 7.2195),
    (50.0000, 2.4900, -0.0010, 50.0000, -2.4900, 0.0012, 7.2195),
    (50.0000, -0.0010, 2.4900, 50.0000, 0.0009, -2.4900, 4.8045),
    (50.0000, -0.0010, 2.4900, 50.0000, 0.0010, -2.4900, 4.8045),
    (50.0000, -0.0010, 2.4900, 50.0000, 0.0011, -2.4900, 4.7461),
    (50.0000, 2.5000, 0.0000, 50.0000, 0.0000, -2.5000, 4.3065),
    (50.0000, 2.5000, 0.0000, 73.0000, 25.0000, -18.0000, 27.1492),
    (50.0000, 2.5000, 0.0000, 61.0000, -5.0000, 29.0000, 22.8977),
    (50.0000, 2.5000, 0.0000, 56.0000, -27.0000, -3.0000, 31.9030),
    (50.0000, 2.5000, 0.0000, 58.0000, 24.0000, 15.0000, 19.4535),
    (50.0000, 2.5000, 0.0000, 50.0000, 3.1736, 0.5854, 1.0000),
    (50.0000, 2.5000, 0.0000, 50.0000, 3.2972, 0.0000, 1.0000),
    (50.0000, 2.5000, 0.0000, 50.0000, 1.8634, 0.5757, 1.0000),
    (50.0000, 2.5000, 0.0000, 50.0000, 3.2592, 0.3350, 1.0000),
    (60.2574, -34.0099, 36.2677, 60.4626, -34.1751, 39.4387, 1.2644),
    (63.0109, -31.0961, -5.8663, 62.8187, -29.7946, -4.0864, 1.2630),
    (61.2901, 3.7196, -5.3901, 61.4292, 2.2480, -4.9620, 1.8731),
    (35.0831, -44.1164, 3.7933, 35.0232, -40.0716, 1.5901, 1.8645),
    (22.7233, 20.0904, -46.6940, 23.0331, 14.9730, -42.5619, 2.0373),
    (36.4612, 47.8580, 18.3852, 36.2715, 50.5065, 21.2231, 1.4146),
    (90.8027, -2.0831, 1.4410, 91.1528, -1.6435, 0.0447, 1.4441),
    (90.9257, -0.5406, -0.9208, 88.6381, -0.8985, -0.7239, 1.5381),
    (6.7747, -0.2908, -2.4247, 5.8714, -0.0985, -2.2286, 0.6377),
    (2.0776, 0.0795, -1.1350, 0.9033, -0.0636, -0.5514, 0.9082),
]

# Lindbloom's sRGB (D65 = ASTM E308) and Bradford matrices for his D65 and D50 whites.
LINDBLOOM_SRGB_TO_XYZ = [
    [0.4124564, 0.3575761, 0.1804375],
    [0.2126729, 0.7151522, 0.0721750],
    [0.0193339, 0.1191920, 0.9503041],
]
LINDBLOOM_XYZ_TO_SRGB = [
    [3.2404542, -1.5371385, -0.4985314],
    [-0.9692660, 1.8760108, 0.0415560],
    [0.0556434, -0.2040259, 1.0572252],
]
LINDBLOOM_D65, LINDBLOOM_D50 = [0.95047, 1.0, 1.08883], [0.96422, 1.0, 0.82521]
LINDBLOOM_D65_TO_D50 = [
    [1.0478112, 0.0228866, -0.0501270],
    [0.0295424, 0.9904844, -0.0170491],
    [-0.0092345, 0.0150436, 0.7521316],
]
LINDBLOOM_D50_TO_D65 = [
    [0.9555766, -0.0230393, 0.0631636],
    [-0.0282895, 1.0099416, 0.0210077],
    [0.0122982, -0.0204830, 1.3299098],
]


@pytest.fixture(scope="module")
def chart() -> ColorChart:
    return read_colorchecker(shared_data("color", "colour_science", CHARTS_JSON))


@pytest.fixture(scope="module")
def chart_srgb() -> np.ndarray:
    """The sRGB (D65) values of "ColorChecker24 - After November 2014", in [0, 1]."""
    _, values = read_colorchecker_srgb(shared_data("color", "colour_science", SRGB_CSV))
    return values / 255.0


@pytest.fixture(scope="module")
def opencv():
    with open(shared_data("color", "opencv_ccm", "opencv_ccm_expected_values.json")) as file:
        return json.load(file)


# ---------------------------------------------------------------- colorimetry


def test_ciede2000_published_pairs():
    pairs = np.array(SHARMA_PAIRS)
    for first, second in ((pairs[:, :3], pairs[:, 3:6]), (pairs[:, 3:6], pairs[:, :3])):
        # Published to 4 decimals: agreement to half a unit of the last one.
        np.testing.assert_allclose(delta_e_2000(first, second), pairs[:, 6], rtol=0, atol=5e-5)
    assert delta_e_2000([50.0, 2.5, 0.0], [50.0, 2.5, 0.0]) == 0.0


def test_srgb_transfer_function():
    # IEC 61966-2-1: the segments meet at 0.04045 -> 0.04045 / 12.92 = 0.0031308;
    # ((0.5 + 0.055) / 1.055) ** 2.4 = 0.2140411; 128/255 -> 0.2158605.
    np.testing.assert_allclose(
        srgb_to_linear([0.0, 0.04045, 0.5, 128 / 255, 1.0]),
        [0.0, 0.0031308050, 0.2140411405, 0.2158605001, 1.0],
        atol=1e-10,
    )
    np.testing.assert_allclose(linear_to_srgb(0.0031308), 0.04044994, atol=1e-8)
    codes = np.arange(256) / 255.0
    np.testing.assert_allclose(linear_to_srgb(srgb_to_linear(codes)), codes, atol=1e-12)
    np.testing.assert_allclose(srgb_to_linear(-codes), -srgb_to_linear(codes))
    # The plain gamma: 0.5 ** 2.2 = 0.2176376.
    np.testing.assert_allclose(gamma_to_linear(0.5), 0.2176376408, atol=1e-10)
    np.testing.assert_allclose(
        linear_to_gamma(gamma_to_linear(codes, gamma=1.8), gamma=1.8), codes, atol=1e-12
    )


def test_srgb_and_bradford_matrices_are_the_published_ones():
    np.testing.assert_allclose(SRGB_TO_XYZ, LINDBLOOM_SRGB_TO_XYZ, atol=5e-8)
    np.testing.assert_allclose(XYZ_TO_SRGB, LINDBLOOM_XYZ_TO_SRGB, atol=5e-8)
    np.testing.assert_allclose(
        bradford_matrix(LINDBLOOM_D65, LINDBLOOM_D50), LINDBLOOM_D65_TO_D50, atol=5e-8
    )
    np.testing.assert_allclose(
        bradford_matrix(LINDBLOOM_D50, LINDBLOOM_D65), LINDBLOOM_D50_TO_D65, atol=5e-8
    )
    np.testing.assert_allclose(
        bradford_matrix(WHITE_D65, WHITE_D50) @ WHITE_D65, WHITE_D50, atol=1e-15
    )
    np.testing.assert_allclose(SRGB_TO_XYZ @ np.ones(3), WHITE_D65, atol=1e-15)


def test_lab_of_the_published_charts(chart):
    # colour-science's CIELAB of each ColorChecker 24 under its own illuminant
    # (D50 and, for the 1976 chart, C).
    path = shared_data("color", "colour_science", CHARTS_JSON)
    for name in (
        "ColorChecker 1976",
        "ColorChecker 2005",
        "BabelColor Average",
        "ColorChecker24 - Before November 2014",
        "ColorChecker24 - After November 2014",
    ):
        published = read_colorchecker(path, chart=name)
        lab = xyz_to_lab(published.xyz, white=published.white_xyz)
        np.testing.assert_allclose(lab, published.lab, atol=1e-9, err_msg=name)
        np.testing.assert_allclose(
            lab_to_xyz(lab, white=published.white_xyz), published.xyz, atol=1e-12, err_msg=name
        )


def test_srgb_lab_round_trips(chart, chart_srgb):
    rng = np.random.default_rng(0)
    linear = rng.uniform(0, 1, (500, 3))
    for white in (WHITE_D50, WHITE_D65, chart.white_xyz):
        np.testing.assert_allclose(
            lab_to_linear_rgb(linear_rgb_to_lab(linear, white=white), white=white),
            linear,
            atol=1e-12,
        )
    # White is L* 100 neutral in any white it is adapted to; black is 0.
    np.testing.assert_allclose(
        linear_rgb_to_lab([[1.0, 1.0, 1.0], [0.0, 0.0, 0.0]]),
        [[100.0, 0.0, 0.0], [0.0, 0.0, 0.0]],
        atol=1e-12,
    )
    # colour-science's 8-bit sRGB of the chart (Bradford D50 -> D65) from its CIELAB, to
    # 0.15 codes (0.04 but for yellow's low blue); cyan is outside the gamut: red clipped.
    ours = linear_to_srgb(lab_to_linear_rgb(chart.lab, white=chart.white_xyz)) * 255
    cyan = chart.patch_names.index("cyan")
    in_gamut = np.arange(24) != cyan
    np.testing.assert_allclose(ours[in_gamut], chart_srgb[in_gamut] * 255, atol=0.15)
    assert chart_srgb[cyan, 0] == 0 and ours[cyan, 0] < 0


# ---------------------------------------------------------------- chart files


def test_read_colorchecker(chart):
    assert chart.name == "ColorChecker24 - After November 2014"
    assert chart.layout == (6, 4) and len(chart.patch_names) == 24
    assert chart.patch_names[0] == "dark skin" and chart.patch_names[18] == "white 9.5 (.05 D)"
    assert chart.patch_names[23] == "black 2 (1.5 D)"
    # X-Rite's published L*a*b* (D50) of dark skin and the white patch, after 2014.
    np.testing.assert_allclose(chart.lab[0], [37.54, 14.37, 14.92], atol=1e-9)
    np.testing.assert_allclose(chart.lab[18], [95.19, -1.03, 2.93], atol=1e-9)
    np.testing.assert_allclose(chart.white_xy, [0.345702914918791, 0.358538596679933])
    names, values = read_colorchecker_srgb(shared_data("color", "colour_science", SRGB_CSV))
    assert names == chart.patch_names
    np.testing.assert_array_equal(values[0], [115.70, 79.30, 65.00])


def test_two_publications_of_the_2005_chart_agree(opencv):
    published = read_colorchecker(
        shared_data("color", "colour_science", CHARTS_JSON), chart="ColorChecker 2005"
    )
    np.testing.assert_allclose(
        published.lab, opencv["reference_Lab_D50_2deg_ColorChecker2005"], atol=0.05
    )


def test_malformed_chart_files(tmp_path):
    path = tmp_path / "charts.json"
    good = {
        "name": "c",
        "illuminant_xy": [0.3457, 0.3585],
        "rows": 1,
        "columns": 2,
        "patches": {
            "a": {"XYZ": [0.1, 0.1, 0.1], "Lab_under_chart_illuminant": [37, 0, 0]},
            "b": {"XYZ": [0.2, 0.2, 0.2], "Lab_under_chart_illuminant": [51, 0, 0]},
        },
    }
    path.write_text(json.dumps({"c": good}))
    assert read_colorchecker(path, chart="c").layout == (2, 1)
    with pytest.raises(ConfigError, match="no chart 'x' in the file \\(charts: 'c'\\)"):
        read_colorchecker(path, chart="x")
    path.write_text('{"c": {\n"rows": 1,,}}')
    with pytest.raises(ConfigError) as error:
        read_colorchecker(path, chart="c")
    assert error.value.line == 2 and str(error.value).startswith(f"{path}:2: invalid JSON")
    broken = json.loads(json.dumps(good))
    broken["patches"]["b"]["XYZ"] = [0.2, "x", 0.2]
    path.write_text(json.dumps({"c": broken}))
    with pytest.raises(ConfigError, match="c: b: XYZ must be a list of 3 finite numbers"):
        read_colorchecker(path, chart="c")
    broken = dict(good, rows=2)
    path.write_text(json.dumps({"c": broken}))
    with pytest.raises(ConfigError, match="2 x 2 = 4 patches, got 2"):
        read_colorchecker(path, chart="c")

    csv = tmp_path / "chart.csv"
    for text, line, message in (
        ("name,R,G,B\n", 1, "header must be 'patch,R,G,B'"),
        ("patch,R,G,B\na,1,2,3\nb,1,2\n", 3, "expected 4 fields"),
        ("patch,R,G,B\na,1,x,3\n", 2, "must be numbers"),
        ("patch,R,G,B\na,1,2,300\n", 2, r"must be in \[0, 255\]"),
        ("patch,R,G,B\na,1,2,3\na,1,2,3\n", 3, "appears twice"),
    ):
        csv.write_text(text)
        with pytest.raises(ConfigError, match=message) as error:
            read_colorchecker_srgb(csv)
        assert error.value.line == line and error.value.path == str(csv)


# ---------------------------------------------------------------- OpenCV's ccm tests (bar 3)


def test_chain_reproduces_opencv_linear_references(opencv):
    reference = np.array(opencv["reference_Lab_D50_2deg_ColorChecker2005"])
    np.testing.assert_allclose(
        lab_to_linear_rgb(reference), opencv["expected_ref_linear_rgb"], atol=1e-8
    )
    measured = np.array(opencv["measured_rgb_0_255_gamma_encoded"]) / 255
    np.testing.assert_allclose(
        gamma_to_linear(measured), opencv["expected_src_linear_rgb"], atol=1e-8
    )
    # The fitted curve is a 256-entry table: its interpolation agrees to 1e-5.
    correction = fit_chart_correction(measured, reference)
    np.testing.assert_allclose(
        replace(correction, matrix=np.eye(3)).apply_linear(measured),
        opencv["expected_src_linear_rgb"],
        atol=1e-5,
    )


def test_fitted_ccm_beats_opencv(opencv):
    reference = np.array(opencv["reference_Lab_D50_2deg_ColorChecker2005"])
    measured = np.array(opencv["measured_rgb_0_255_gamma_encoded"]) / 255
    correction = fit_chart_correction(measured, reference, linearization="gamma", gamma=2.2)
    # Both matrices on OpenCV's linear values, through the same chain to CIELAB (D50).
    linear = gamma_to_linear(measured)
    ours = delta_e_2000(linear_rgb_to_lab(linear @ correction.matrix), reference)
    # The correction's own figures go through its curve table, linear between codes.
    np.testing.assert_allclose(ours, correction.delta_e, atol=5e-3)
    print(f"\nbar 3: mean CIEDE2000 ours {ours.mean():.4f} (max {ours.max():.4f})", end="")
    for key in ("expected_ccm_opencv_photo_module_5x", "expected_ccm_opencv_contrib_mcc_module"):
        theirs = delta_e_2000(linear_rgb_to_lab(linear @ np.array(opencv[key])), reference)
        print(f", {key} {theirs.mean():.4f} (max {theirs.max():.4f})", end="")
        assert ours.mean() <= theirs.mean()
    assert correction.used.all() and correction.matrix.shape == (3, 3)


def test_opencv_mcc_gold_loss(opencv):
    # OpenCV's loss is the root mean square CIEDE2000 with both sides in CIELAB (D65),
    # the linear sRGB's own white; the reference reaches it through Bradford from D50.
    storage = cv2.FileStorage(
        str(shared_data("color", "opencv_ccm", "mcc_ccm_test.yml")), cv2.FILE_STORAGE_READ
    )
    charts, ccm = storage.getNode("chartsRGB").mat(), storage.getNode("ccm").mat()
    storage.release()
    measured = charts[:, 1].reshape(24, 3) / 255
    reference = np.array(opencv["reference_Lab_D50_2deg_ColorChecker2005"])
    corrected = linear_rgb_to_lab(gamma_to_linear(measured) @ ccm, white=WHITE_D65)
    target = linear_rgb_to_lab(lab_to_linear_rgb(reference), white=WHITE_D65)
    loss = np.sqrt(np.mean(delta_e_2000(corrected, target) ** 2))
    np.testing.assert_allclose(loss, opencv["mcc_ccm_test_yml"]["gold_loss"], rtol=0, atol=1e-9)


# ---------------------------------------------------------------- a synthetic photograph


def test_synthetic_chart_detected_sampled_and_corrected(chart, chart_srgb):
    image = photograph(chart_srgb, CORNERS)
    corners = detect_chart(image)
    assert corners is not None
    error = np.abs(corners - CORNERS).max()
    assert error < 2.0

    truth = MISMATCH.apply(chart_srgb) * 255
    for where in (CORNERS, corners):
        assert np.abs(sample_patches(image, where) - truth).max() < 1.0
    measured = sample_patches(image, corners) / 255

    uncorrected = delta_e_2000(
        linear_rgb_to_lab(srgb_to_linear(measured), white=chart.white_xyz), chart.lab
    )
    correction = fit_chart_correction(
        measured, chart.lab, linearization="grey-curve", white=chart.white_xyz
    )
    print(
        f"\nsynthetic: corners within {error:.3f} px; mean CIEDE2000 uncorrected "
        f"{uncorrected.mean():.3f} (max {uncorrected.max():.3f}), corrected "
        f"{correction.delta_e.mean():.3f} (max {correction.delta_e.max():.3f})",
        end="",
    )
    assert correction.delta_e.mean() < 1.5
    assert correction.delta_e.mean() < uncorrected.mean() / 5
    assert correction.used.all() and correction.curve.shape == (3, 256)
    assert np.all(np.diff(correction.curve, axis=1) >= 0)
    # The greys come out neutral at the reference lightness.
    greys = linear_rgb_to_lab(
        correction.apply_linear(measured[list(GREY_PATCHES)]), white=chart.white_xyz
    )
    np.testing.assert_allclose(greys[:, 0], chart.lab[list(GREY_PATCHES), 0], atol=1.0)

    # apply gives the display colours of apply_linear where those are in gamut.
    linear = correction.apply_linear(measured)
    in_gamut = np.all((linear >= 0) & (linear <= 1), axis=1)
    displayed = delta_e_2000(
        linear_rgb_to_lab(srgb_to_linear(correction.apply(measured)), white=chart.white_xyz),
        chart.lab,
    )
    np.testing.assert_allclose(displayed[in_gamut], correction.delta_e[in_gamut], atol=1e-9)
    assert in_gamut.sum() >= 20
    whole = correction.apply(image / 255.0)
    assert whole.shape == image.shape and whole.min() >= 0 and whole.max() <= 1

    affine = fit_chart_correction(
        measured, chart.lab, linearization="grey-curve", model="4x3", white=chart.white_xyz
    )
    assert affine.matrix.shape == (4, 3) and affine.delta_e.mean() < 1.5


def test_exact_srgb_chart_needs_no_correction(chart, chart_srgb):
    correction = fit_chart_correction(
        chart_srgb, chart.lab, linearization="srgb", white=chart.white_xyz
    )
    np.testing.assert_allclose(correction.matrix, np.eye(3), atol=1e-3)
    # Only cyan, clipped in the published sRGB, is off.
    cyan = chart.patch_names.index("cyan")
    assert np.delete(correction.delta_e, cyan).max() < 0.05


@pytest.mark.parametrize("turn", ["half turn", "quarter turn", "three quarter turns"])
def test_turned_chart(chart_srgb, turn):
    # Corners of the chart upright; a portrait quadrilateral for the quarter turns.
    corners = {
        "half turn": np.roll(CORNERS, 2, axis=0),
        "quarter turn": np.array([[230.0, 25.0], [225.0, 220.0], [95.0, 215.0], [90.0, 20.0]]),
        "three quarter turns": np.array(
            [[95.0, 215.0], [90.0, 20.0], [230.0, 25.0], [225.0, 220.0]]
        ),
    }[turn]
    found = detect_chart(photograph(chart_srgb, corners, seed=1))
    assert found is not None and np.abs(found - corners).max() < 2.0


@pytest.mark.slow
def test_no_chart():
    rng = np.random.default_rng(0)
    checkerboard = cv2.imread(
        str(REPO_ROOT / "sample_data" / "checkerboard" / "cam0" / "capture00.png")
    )
    assert checkerboard is not None
    for image in (
        rng.integers(0, 256, (240, 320, 3), dtype=np.uint8),
        np.full((240, 320, 3), 0.5),
        cv2.cvtColor(checkerboard, cv2.COLOR_BGR2RGB),
    ):
        assert detect_chart(image) is None


def test_bad_arguments(chart):
    image = np.zeros((240, 320, 3), np.uint8)
    with pytest.raises(ValueError, match="RGB image"):
        detect_chart(image[..., 0])
    with pytest.raises(ValueError, match="clockwise"):
        sample_patches(image, CORNERS[::-1])
    with pytest.raises(ValueError, match="4 finite"):
        sample_patches(image, CORNERS[:3])
    with pytest.raises(ValueError, match="fraction"):
        sample_patches(image, CORNERS, fraction=0)
    with pytest.raises(ValueError, match="layout"):
        sample_patches(image, CORNERS, layout=(0, 4))
    with pytest.raises(ValueError, match="outside"):
        sample_patches(image, CORNERS + 200)
    measured = np.full((24, 3), 0.5)
    with pytest.raises(ValueError, match=r"display RGB in \[0, 1\]"):
        fit_chart_correction(measured * 255, chart.lab)
    with pytest.raises(ValueError, match="shape"):
        fit_chart_correction(measured[:20], chart.lab)
    with pytest.raises(ValueError, match="linearization"):
        fit_chart_correction(measured, chart.lab, linearization="log")
    with pytest.raises(ValueError, match="model"):
        fit_chart_correction(measured, chart.lab, model="3x4")
    with pytest.raises(ValueError, match="gamma"):
        fit_chart_correction(measured, chart.lab, gamma=0)
    with pytest.raises(DataError, match="saturation"):
        fit_chart_correction(np.ones((24, 3)), chart.lab)
    with pytest.raises(DataError, match=r"grey patches all measure 0\.5"):
        fit_chart_correction(measured, chart.lab, linearization="grey-curve")
    with pytest.raises(ValueError, match="shape"):
        delta_e_2000([50, 0], [50, 0])
