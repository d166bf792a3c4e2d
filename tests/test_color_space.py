"""YUV <-> RGB and chroma resampling (mvtools.color.space)."""

import numpy as np
import pytest

from mvtools.color.space import downsample_chroma, rgb_to_yuv, upsample_chroma, yuv_to_rgb


def pixel_yuv(rgb, **options):
    planes = rgb_to_yuv(
        np.array([[rgb]], dtype=np.uint8 if max(rgb) < 256 else np.uint16), chroma="444", **options
    )
    return tuple(int(p[0, 0]) for p in planes)


# Hand computation, BT.601 (Kr 0.299, Kb 0.114), limited range at 8 bits:
# Y = 16 + 219 Y', U = 128 + 224 (B' - Y') / 1.772, V = 128 + 224 (R' - Y') / 1.402.
@pytest.mark.parametrize(
    "rgb, yuv",
    [
        ((255, 0, 0), (81, 90, 240)),  # Y 16 + 65.481 = 81.48; U 128 - 37.80 = 90.2; V 240
        ((0, 255, 0), (145, 54, 34)),  # Y 16 + 128.55 = 144.55; U 128 - 74.2; V 128 - 93.8
        ((0, 0, 255), (41, 240, 110)),  # Y 16 + 24.97 = 40.97; U 240; V 128 - 18.2
        ((255, 255, 255), (235, 128, 128)),
        ((0, 0, 0), (16, 128, 128)),
        ((128, 128, 128), (126, 128, 128)),  # 16 + 219 * 128 / 255 = 125.93
    ],
)
def test_bt601_limited_8_bit(rgb, yuv):
    assert pixel_yuv(rgb) == yuv


def test_limited_range_scales_with_bit_depth():
    # 10 bits: 16 -> 64, 235 -> 940, 128 -> 512; 16 bits: times 256.
    white10 = rgb_to_yuv(np.full((1, 1, 3), 1023, np.uint16), chroma="444", bits=10)
    assert [int(p[0, 0]) for p in white10] == [940, 512, 512]
    black16 = rgb_to_yuv(np.zeros((1, 1, 3), np.uint8), chroma="444", bits=16)
    assert [int(p[0, 0]) for p in black16] == [4096, 32768, 32768]
    # 8-bit RGB input to 10-bit output: red Y = 4 * 81.48 = 325.9, U = 4 * 90.20 = 360.8.
    assert pixel_yuv((255, 0, 0), bits=10) == (326, 361, 960)


def test_full_range_and_bt709():
    # Full range: Y = 255 Y' = 76.2; U = 128 - 255 * 0.1687 = 84.97; V = 128 + 127.5 -> clipped 255.
    assert pixel_yuv((255, 0, 0), full_range=True) == (76, 85, 255)
    assert pixel_yuv((255, 255, 255), full_range=True) == (255, 128, 128)
    # BT.709 (Kr 0.2126, Kb 0.0722): Y 16 + 46.56 = 62.56; U 128 - 224 * 0.2126 / 1.8556 = 102.3.
    assert pixel_yuv((255, 0, 0), matrix="bt709") == (63, 102, 240)


def test_yuv_to_rgb_hand_values():
    def rgb_of(y, u, v, **options):
        planes = tuple(np.array([[value]], np.uint8) for value in (y, u, v))
        return yuv_to_rgb(planes, **options)[0, 0].tolist()

    assert rgb_of(235, 128, 128) == [255, 255, 255]
    assert rgb_of(16, 128, 128) == [0, 0, 0]
    assert rgb_of(126, 128, 128) == [128, 128, 128]  # 255 * 110 / 219 = 128.08
    # R = 255 (65/219 + 1.402 * 112/224) = 254.4; G, B slightly below 0 are clipped.
    assert rgb_of(81, 90, 240) == [254, 0, 0]
    assert rgb_of(255, 128, 128) == [255, 255, 255]  # 255 * 239 / 219 = 278.3: clipped
    assert rgb_of(255, 128, 128, full_range=True) == [255, 255, 255]


@pytest.mark.parametrize("bits", [8, 10, 16])
def test_round_trip_444_within_one_code(bits):
    rng = np.random.default_rng(bits)
    native = np.uint8 if bits == 8 else np.uint16
    step = 2 ** (bits - 8)
    # Random YUV inside the RGB gamut (mid luma, low saturation) ...
    y = rng.integers(100 * step, 150 * step, (40, 50))
    u, v = rng.integers(118 * step, 139 * step, (2, 40, 50))
    planes = tuple(p.astype(native) for p in (y, u, v))
    back = rgb_to_yuv(yuv_to_rgb(planes, bits=bits), chroma="444", bits=bits)
    for original, again in zip(planes, back):
        assert np.abs(original.astype(int) - again).max() <= 1
    # ... and YUV of random RGB over the whole range.
    rgb = rng.integers(0, 2**bits, (40, 50, 3)).astype(native)
    planes = rgb_to_yuv(rgb, chroma="444", bits=bits)
    back = rgb_to_yuv(yuv_to_rgb(planes, bits=bits), chroma="444", bits=bits)
    for original, again in zip(planes, back):
        assert np.abs(original.astype(int) - again).max() <= 1


def test_grey_planes_give_grey_rgb_and_420_shapes():
    rng = np.random.default_rng(5)
    rgb = rng.integers(0, 256, (17, 33, 3)).astype(np.uint8)
    y, u, v = rgb_to_yuv(rgb)
    assert y.shape == (17, 33) and u.shape == v.shape == (9, 17)
    assert rgb_to_yuv(rgb, chroma="422")[1].shape == (17, 17)
    (luma,) = rgb_to_yuv(rgb, chroma="400")
    np.testing.assert_array_equal(luma, y)
    back = yuv_to_rgb((y, u, v))
    assert back.shape == (17, 33, 3) and back.dtype == np.uint8
    grey = yuv_to_rgb((np.array([[16, 235]], np.uint8),))
    assert grey.tolist() == [[[0, 0, 0], [255, 255, 255]]]


def test_constant_image_stays_constant_in_420():
    rgb = np.empty((17, 33, 3), np.uint8)
    rgb[...] = (200, 30, 90)
    y, u, v = rgb_to_yuv(rgb)
    single = [int(p[0, 0]) for p in rgb_to_yuv(rgb[:1, :1], chroma="444")]
    assert (y == single[0]).all() and (u == single[1]).all() and (v == single[2]).all()
    for method in ("bilinear", "nearest"):
        _, up_u, up_v = upsample_chroma((y, u, v), method=method)
        assert up_u.shape == (17, 33) and (up_u == single[1]).all() and (up_v == single[2]).all()


def test_downsample_chroma_hand_values():
    plane = np.array([[0, 4, 8], [2, 6, 9], [10, 10, 1]], np.uint8)
    # Blocks: (0,4,2,6) -> 3; (8,8,9,9) -> 8.5 -> 9 (halves up); (10,10,10,10) -> 10; (1,1,1,1) -> 1.
    assert downsample_chroma(plane).tolist() == [[3, 9], [10, 1]]
    assert downsample_chroma(plane, chroma="422").tolist() == [[2, 8], [4, 9], [10, 1]]
    assert downsample_chroma(plane.astype(float))[0, 1] == 8.5


def test_upsample_chroma_hand_values():
    luma = np.zeros((2, 4), np.uint8)
    chroma = np.array([[0, 100]], np.uint8)
    # Centred siting: luma x sits at chroma coordinate (x - 0.5) / 2 = -0.25, 0.25, 0.75, 1.25.
    _, u, _ = upsample_chroma((luma, chroma, chroma))
    assert u.tolist() == [[0, 25, 75, 100]] * 2
    _, u, _ = upsample_chroma((luma[:, :3], chroma, chroma), method="nearest")
    assert u.tolist() == [[0, 0, 100]] * 2


def test_upsample_chroma_into_views_of_an_image_hand_values():
    # 4:2:0, 2x2 chroma to 4x4: rows and columns each at (x - 0.5) / 2, weights 3/4, 1/4;
    # out gets unrounded values (here exact quarters) straight into the image's channels.
    luma = np.zeros((4, 4), np.uint8)
    chroma = np.array([[0, 100], [200, 30]], np.uint8)
    image = np.zeros((4, 4, 3), np.float32)
    upsample_chroma((luma, chroma, chroma), out=(image[..., 1], image[..., 2]))
    top, bottom = np.array([0.0, 25, 75, 100]), np.array([200.0, 157.5, 72.5, 30])
    expected = np.stack([top, 0.75 * top + 0.25 * bottom, 0.25 * top + 0.75 * bottom, bottom])
    np.testing.assert_array_equal(image[..., 1], expected)
    np.testing.assert_array_equal(image[..., 2], expected)
    assert not image[..., 0].any()


def test_down_then_up_reproduces_a_ramp_inside():
    # With matching (centred) siting a linear ramp survives 4:2:0 resampling exactly,
    # except in the outer luma row and column where the edge is replicated.
    rows, cols = np.mgrid[0:12, 0:16]
    ramp = 3.0 * cols + 2.0 * rows
    half = downsample_chroma(ramp)
    _, up, _ = upsample_chroma((ramp, half, half))
    np.testing.assert_allclose(up[1:-1, 1:-1], ramp[1:-1, 1:-1])


def test_invalid_arguments():
    with pytest.raises(ValueError, match="unknown colour matrix"):
        rgb_to_yuv(np.zeros((2, 2, 3), np.uint8), matrix="bt2021")
    with pytest.raises(ValueError, match=r"\(H, W, 3\)"):
        rgb_to_yuv(np.zeros((2, 2), np.uint8))
    with pytest.raises(ValueError, match="does not match luma"):
        upsample_chroma((np.zeros((4, 4)), np.zeros((3, 2)), np.zeros((3, 2))))
    with pytest.raises(ValueError, match="bits"):
        yuv_to_rgb((np.zeros((2, 2), np.uint16),), bits=17)
