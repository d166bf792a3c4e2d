"""PSNR, YUV-PSNR, SSIM and IV-PSNR against hand-computed values."""

from __future__ import annotations

import math

import cv2
import numpy as np
import pytest
from shared_data import shared_data

from mvtools.metrics import (
    frame_scores,
    global_color_shift,
    iv_psnr,
    plane_psnr,
    psnr,
    ssim,
    yuv_psnr,
)

# ---------------------------------------------------------------------------- PSNR


def test_psnr_of_tiny_planes_by_hand():
    ref = np.array([[0, 10], [20, 30]], dtype=np.uint8)
    test = np.array([[1, 10], [18, 33]], dtype=np.uint8)
    # differences -1, 0, 2, -3 -> squares 1, 0, 4, 9 -> MSE = 14 / 4 = 3.5
    assert psnr(ref, test, max_value=255) == pytest.approx(10 * math.log10(255**2 / 3.5))
    # uint8 must not wrap: 0 - 1 is -1, not 255
    assert psnr(test, ref, max_value=255) == pytest.approx(10 * math.log10(255**2 / 3.5))


def test_psnr_identical_planes_is_infinite():
    plane = np.arange(12, dtype=np.uint8).reshape(3, 4)
    assert psnr(plane, plane.copy(), max_value=255) == math.inf


def test_psnr_mask_scores_only_selected_samples():
    ref = np.array([[0, 10], [20, 30]], dtype=np.uint8)
    test = np.array([[1, 10], [18, 33]], dtype=np.uint8)
    mask = np.array([[True, True], [True, False]])
    # squares 1, 0, 4 -> MSE = 5 / 3
    assert psnr(ref, test, max_value=255, mask=mask) == pytest.approx(
        10 * math.log10(255**2 * 3 / 5)
    )
    # the only error masked out: identical where scored
    assert (
        psnr(ref, test, max_value=255, mask=np.array([[False, True], [False, False]])) == math.inf
    )
    with pytest.raises(ValueError, match="no sample"):
        psnr(ref, test, max_value=255, mask=np.zeros((2, 2), bool))


def test_plane_psnr_uses_10_bit_peak():
    ref = np.array([[1000, 0], [512, 7]], dtype=np.uint16)
    test = np.array([[1004, 0], [512, 7]], dtype=np.uint16)
    # one difference of 4 over 4 samples: MSE = 16 / 4 = 4, peak 2^10 - 1 = 1023
    (value,) = plane_psnr((ref,), (test,), bits=10)
    assert value == pytest.approx(10 * math.log10(1023**2 / 4))


def _planes_with_mse(mse_y, mse_u, mse_v):
    """4:2:0 frame pair (luma 4x4) whose planes have the given integer-step MSEs."""
    ref = (
        np.full((4, 4), 100, np.uint8),
        np.full((2, 2), 128, np.uint8),
        np.full((2, 2), 128, np.uint8),
    )
    # a constant offset k gives MSE k^2
    test = tuple(
        (plane + math.isqrt(m)).astype(np.uint8) for plane, m in zip(ref, (mse_y, mse_u, mse_v))
    )
    return ref, test


def test_yuv_psnr_weights_luma_six_to_one():
    ref, test = _planes_with_mse(4, 16, 1)
    p_y = 10 * math.log10(255**2 / 4)
    p_u = 10 * math.log10(255**2 / 16)
    p_v = 10 * math.log10(255**2 / 1)
    assert plane_psnr(ref, test, bits=8) == pytest.approx((p_y, p_u, p_v))
    assert yuv_psnr(ref, test, bits=8) == pytest.approx((6 * p_y + p_u + p_v) / 8)


def test_plane_psnr_mask_reaches_subsampled_chroma():
    ref = (
        np.full((4, 4), 50, np.uint8),
        np.full((2, 2), 128, np.uint8),
        np.full((2, 2), 128, np.uint8),
    )
    test = [plane.copy() for plane in ref]
    test[1][0, 0] = 138  # error 10 in the chroma sample covering luma rows 0-1, cols 0-1
    test[1][1, 1] = 130  # error 2 in the sample covering luma rows 2-3, cols 2-3
    mask = np.ones((4, 4), bool)
    mask[1, 0] = False  # one luma sample of the top-left 2x2 block is out
    p_y, p_u, p_v = plane_psnr(ref, test, bits=8, mask=mask)
    assert p_y == math.inf and p_v == math.inf
    # the top-left chroma sample is dropped: squares 0, 0, 4 over 3 samples
    assert p_u == pytest.approx(10 * math.log10(255**2 * 3 / 4))


# ---------------------------------------------------------------------------- SSIM


def test_ssim_identical_is_one():
    rng = np.random.default_rng(1)
    plane = rng.integers(0, 256, (32, 40), dtype=np.uint8)
    assert ssim(plane, plane.copy(), max_value=255) == 1.0


def test_ssim_constant_planes_by_hand():
    ref = np.full((16, 20), 100, np.uint8)
    test = np.full((16, 20), 120, np.uint8)
    # no variance: SSIM = (2 mu_x mu_y + C1) / (mu_x^2 + mu_y^2 + C1), C1 = (0.01 * 255)^2
    c1 = (0.01 * 255) ** 2
    expected = (2 * 100 * 120 + c1) / (100**2 + 120**2 + c1)
    assert ssim(ref, test, max_value=255) == pytest.approx(expected, rel=1e-12)


def test_ssim_single_window_matches_the_formula_written_out():
    # An 11x11 plane holds exactly one full window: the map has one value.
    rng = np.random.default_rng(2)
    x = rng.integers(0, 256, (11, 11)).astype(np.float64)
    y = np.clip(x + rng.normal(0, 20, x.shape), 0, 255)
    offsets = np.arange(11) - 5
    w = np.exp(-(offsets[:, None] ** 2 + offsets[None, :] ** 2) / (2 * 1.5**2))
    w /= w.sum()
    mx, my = (w * x).sum(), (w * y).sum()
    vx, vy = (w * (x - mx) ** 2).sum(), (w * (y - my) ** 2).sum()
    cxy = (w * (x - mx) * (y - my)).sum()
    c1, c2 = (0.01 * 255) ** 2, (0.03 * 255) ** 2
    expected = (2 * mx * my + c1) * (2 * cxy + c2) / ((mx**2 + my**2 + c1) * (vx + vy + c2))
    assert ssim(x, y, max_value=255) == pytest.approx(expected, rel=1e-9)


def test_ssim_decreases_with_noise():
    rng = np.random.default_rng(3)
    base = cv2.GaussianBlur(rng.uniform(0, 255, (64, 64)), (0, 0), 3)
    values = [
        ssim(base, base + rng.normal(0, sigma, base.shape), max_value=255) for sigma in (2, 8, 32)
    ]
    assert 1 > values[0] > values[1] > values[2]


# ---------------------------------------------------------------------------- IV-PSNR


def _cap(width, height, bits=8):
    """IV-PSNR of identical frames: the reference counts a zero SSD as 1."""
    return 10 * math.log10((2**bits - 1) ** 2 * width * height)


@pytest.fixture(scope="module")
def tsukuba_420():
    """Tsukuba view 3 as 8-bit YUV 4:2:0 (OpenCV's BT.601 conversion), 384x288."""
    bgr = cv2.imread(str(shared_data("middlebury", "2001", "tsukuba", "tsukuba3.png")))
    height, width = bgr.shape[:2]
    i420 = cv2.cvtColor(bgr, cv2.COLOR_BGR2YUV_I420)
    quarter = (height // 2, width // 2)
    return (
        i420[:height],
        i420[height : height + height // 4].reshape(quarter),
        i420[height + height // 4 :].reshape(quarter),
    )


@pytest.fixture(scope="module")
def tsukuba_444():
    bgr = cv2.imread(str(shared_data("middlebury", "2001", "tsukuba", "tsukuba3.png")))
    ycrcb = cv2.cvtColor(bgr, cv2.COLOR_BGR2YCrCb)
    return ycrcb[..., 0], ycrcb[..., 2], ycrcb[..., 1]


def _shift_right(plane, pixels):
    """Content moved right, the left edge column repeated into the gap."""
    return np.concatenate([np.repeat(plane[:, :1], pixels, axis=1), plane[:, :-pixels]], axis=1)


def test_iv_psnr_identical_frames_are_infinite(tsukuba_420):
    assert iv_psnr(tsukuba_420, tsukuba_420, bits=8) == math.inf
    # One sample off by one is no longer identical: finite.
    test = tuple(plane.copy() for plane in tsukuba_420)
    test[0][0, 0] += 1
    assert math.isfinite(iv_psnr(tsukuba_420, test, bits=8))


@pytest.mark.parametrize("offset", [2, 3])
def test_iv_psnr_ignores_global_offset_within_one_percent(tsukuba_420, offset):
    test = tuple(plane + np.uint8(offset) for plane in tsukuba_420)
    assert max(int(p.max()) for p in tsukuba_420) + offset <= 255  # no clipping
    # plain PSNR sees the offset: 10 log10(255^2 / offset^2) = 42.1 dB for +2
    assert yuv_psnr(tsukuba_420, test, bits=8) == pytest.approx(10 * math.log10(255**2 / offset**2))
    # 1 % of 255 rounds to 3: the whole offset is compensated
    assert iv_psnr(tsukuba_420, test, bits=8) == pytest.approx(_cap(384, 288))


def test_iv_psnr_compensates_offsets_only_up_to_one_percent(tsukuba_420):
    plus4 = tuple(plane + np.uint8(4) for plane in tsukuba_420)
    plus10 = tuple(plane + np.uint8(10) for plane in tsukuba_420)
    # +4: 3 compensated, a residual of at most 1 code value remains
    assert 10 * math.log10(255**2 / 1) - 0.01 < iv_psnr(tsukuba_420, plus4, bits=8) < 60
    # +10: 3 compensated, residual 7: at most 10 log10(255^2 / 7^2) = 31.2 dB per pixel
    # before the window search finds closer neighbours; far below the +3 cap
    value = iv_psnr(tsukuba_420, plus10, bits=8)
    assert yuv_psnr(tsukuba_420, plus10, bits=8) < value < 40


def test_global_color_shift_is_clipped_to_one_percent():
    ref = np.full((3, 2, 2), 500, np.int64)
    assert global_color_shift(ref, ref + 12, bits=10).tolist() == [10, 10, 10]  # 10.23 -> 10
    assert global_color_shift(ref, ref - 12, bits=10).tolist() == [-10, -10, -10]
    assert global_color_shift(ref, ref + 9, bits=10).tolist() == [9, 9, 9]
    assert global_color_shift(ref, ref + 5, bits=8).tolist() == [3, 3, 3]  # 2.55 -> 3
    # the mean difference, rounded: (1 + 1 + 1 + 0) / 4 = 0.75 -> 1
    test = ref.copy()
    test[:, :1, :] += 1
    test[:, 1, 0] += 1
    assert global_color_shift(ref, test, bits=8).tolist() == [1, 1, 1]


def test_iv_psnr_forgives_a_one_pixel_shift(tsukuba_444):
    shifted = tuple(_shift_right(plane, 1) for plane in tsukuba_444)
    plain = yuv_psnr(tsukuba_444, shifted, bits=8)
    assert iv_psnr(tsukuba_444, shifted, bits=8) > plain + 15


def test_iv_psnr_forgives_a_one_chroma_sample_shift_in_420(tsukuba_420):
    y, u, v = tsukuba_420
    shifted = (_shift_right(y, 2), _shift_right(u, 1), _shift_right(v, 1))
    assert iv_psnr(tsukuba_420, shifted, bits=8) > yuv_psnr(tsukuba_420, shifted, bits=8) + 15


def _dot_frame(x, width=12):
    """4:4:4 frame, one row: luma 0 with a 100 at column x, flat chroma."""
    y = np.zeros((1, width), np.uint8)
    y[0, x] = 100
    return y, np.full((1, width), 128, np.uint8), np.full((1, width), 128, np.uint8)


def test_iv_psnr_window_search_by_hand():
    ref = _dot_frame(4)
    # Moved by 1 px (inside the +-2 window): every pixel finds its exact match in
    # both directions, all SSDs are 0 -> counted as 1.
    assert iv_psnr(ref, _dot_frame(5), bits=8) == pytest.approx(_cap(12, 1))
    # Moved by 3 px: the dot at x=4 sees only zeros in test columns 2..6, and the
    # test dot at x=7 only zeros in ref columns 5..9; every other pixel (0) has a 0
    # in its window. Mean difference 0 -> no colour shift. Each direction:
    # SSD_Y = 100^2, SSD_U = SSD_V = 0 -> 1, over W*H = 12 pixels.
    p_y = 10 * math.log10(255**2 * 12 / 100**2)
    p_c = 10 * math.log10(255**2 * 12 / 1)
    assert iv_psnr(ref, _dot_frame(7), bits=8) == pytest.approx((4 * p_y + p_c + p_c) / 6)


def _iv_psnr_literal(ref_planes, test_planes, bits):
    """The reference software's loops, transcribed pixel by pixel (slow, tiny frames only)."""
    height, width = ref_planes[0].shape
    max_value = 2**bits - 1

    def full(planes):
        out = []
        for plane in planes:
            plane = np.asarray(plane, dtype=np.int64)
            fy, fx = height // plane.shape[0], width // plane.shape[1]
            out.append(
                [[int(plane[y // fy, x // fx]) for x in range(width)] for y in range(height)]
            )
        return out

    ref, test = full(ref_planes), full(test_planes)
    limit = round(0.01 * max_value)
    shift = []
    for c in range(3):
        total = sum(test[c][y][x] - ref[c][y][x] for y in range(height) for x in range(width))
        shift.append(max(-limit, min(limit, round(total / (width * height)))))

    def quality(src, dst, g):
        ssd = [0, 0, 0]
        for y in range(height):
            for x in range(width):
                p = [src[c][y][x] + g[c] for c in range(3)]
                best, best_sq = None, None
                for yy in range(y - 2, y + 3):
                    for xx in range(x - 2, x + 3):
                        cy, cx = min(max(yy, 0), height - 1), min(max(xx, 0), width - 1)
                        sq = [(p[c] - dst[c][cy][cx]) ** 2 for c in range(3)]
                        err = 4 * sq[0] + sq[1] + sq[2]
                        if best is None or err < best:
                            best, best_sq = err, sq
                for c in range(3):
                    ssd[c] += best_sq[c]
        psnrs = [10 * math.log10(max_value**2 * width * height / max(s, 1)) for s in ssd]
        return (4 * psnrs[0] + psnrs[1] + psnrs[2]) / 6

    return min(quality(ref, test, shift), quality(test, ref, [-g for g in shift]))


@pytest.mark.parametrize("seed, bits", [(0, 8), (1, 8), (2, 8), (3, 16)])
def test_iv_psnr_matches_the_reference_loops_on_random_420_frames(seed, bits):
    # Few distinct sample values make many ties in the window search, so the
    # raster-order tie rule and the joint 4:1:1 choice are exercised (seeds 0 and 2
    # give a different value with a "<=" tie rule).
    rng = np.random.default_rng(seed)
    step = 2 ** (bits - 8)
    ref = (rng.integers(0, 4, (6, 8)), rng.integers(0, 3, (3, 4)), rng.integers(0, 3, (3, 4)))
    test = tuple(plane + rng.integers(0, 3, plane.shape) for plane in ref)
    ref, test = ([(plane * step).astype(np.uint16) for plane in frame] for frame in (ref, test))
    assert iv_psnr(ref, test, bits=bits) == pytest.approx(
        _iv_psnr_literal(ref, test, bits), abs=1e-9
    )


def test_iv_psnr_rejects_bad_input():
    frame = _dot_frame(4)
    with pytest.raises(ValueError, match="Y, U, V"):
        iv_psnr(frame[:1], frame[:1], bits=8)
    with pytest.raises(ValueError, match="outside"):
        iv_psnr(frame, (frame[0].astype(np.uint16) * 3,) + frame[1:], bits=8)
    with pytest.raises(ValueError, match="integer"):
        iv_psnr(frame, tuple(p.astype(np.float32) for p in frame), bits=8)


def test_frame_scores_by_name_and_by_hand():
    reference = (
        np.full((4, 6), 100, np.uint8),
        np.full((2, 3), 128, np.uint8),
        np.full((2, 3), 128, np.uint8),
    )
    test = (reference[0] + np.uint8(5), *reference[1:])
    scores = frame_scores(reference, test, bits=8, metrics=("psnr",))
    assert list(scores) == ["Y-PSNR", "U-PSNR", "V-PSNR", "YUV-PSNR"]
    assert scores["Y-PSNR"] == pytest.approx(10 * math.log10(255**2 / 25))
    assert scores["U-PSNR"] == math.inf
    # luma alone: no YUV-PSNR
    assert list(frame_scores(reference[:1], test[:1], bits=8, metrics=("psnr",))) == ["Y-PSNR"]
    with pytest.raises(ValueError, match="unknown metric 'vmaf'"):
        frame_scores(reference, test, bits=8, metrics=("psnr", "vmaf"))
