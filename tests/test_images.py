"""Still images and PFM (mvtools.io.images)."""

import struct

import cv2
import numpy as np
import pytest
from shared_data import shared_data

from mvtools.errors import DataError, UsageError
from mvtools.io.images import read_image, read_pfm, write_image, write_pfm

# ----------------------------------------------------------------------------- PFM


def test_read_hand_made_grey_pfm_rows_bottom_to_top(tmp_path):
    # Stored rows: bottom row (3, 4) first, then the top row (1, inf); little-endian.
    data = b"Pf\n2 2\n-1.0\n" + struct.pack("<4f", 3.0, 4.0, 1.0, float("inf"))
    path = tmp_path / "hand.pfm"
    path.write_bytes(data)
    image = read_pfm(path)
    assert image.dtype == np.float32 and image.shape == (2, 2)
    np.testing.assert_array_equal(image, [[1.0, np.inf], [3.0, 4.0]])


def test_read_big_endian_colour_pfm(tmp_path):
    # Positive scale: big-endian. 1x2 colour image, bottom pixel stored first.
    data = b"PF\n1 2\n1.000000\n" + struct.pack(">6f", 0.5, 0.25, 0.125, 1.0, 2.0, 3.0)
    path = tmp_path / "be.pfm"
    path.write_bytes(data)
    image = read_image(path)
    assert image.shape == (2, 1, 3)
    np.testing.assert_array_equal(image[0, 0], [1.0, 2.0, 3.0])
    np.testing.assert_array_equal(image[1, 0], [0.5, 0.25, 0.125])


def test_middlebury_style_header_with_spaces(tmp_path):
    # Middlebury 2014 writes "Pf\n<w> <h>\n-1\n"; some writers put everything on one line.
    path = tmp_path / "mb.pfm"
    path.write_bytes(b"Pf 3 1 -1\n" + struct.pack("<3f", 1.5, np.inf, -2.0))
    np.testing.assert_array_equal(read_pfm(path), [[1.5, np.inf, -2.0]])


def test_write_pfm_bytes_and_round_trip(tmp_path):
    image = np.array([[1.0, 2.0], [3.0, np.inf]], dtype=np.float64)
    path = tmp_path / "out.pfm"
    write_image(path, image)
    assert path.read_bytes() == b"Pf\n2 2\n-1\n" + struct.pack("<4f", 3.0, np.inf, 1.0, 2.0)
    colour = np.random.default_rng(0).random((5, 7, 3)).astype(np.float32)
    colour[2, 3, 1] = np.nan
    write_pfm(tmp_path / "c.pfm", colour)
    np.testing.assert_array_equal(read_pfm(tmp_path / "c.pfm"), colour)


def test_damaged_pfm(tmp_path):
    path = tmp_path / "short.pfm"
    path.write_bytes(b"Pf\n4 4\n-1\n" + bytes(12))
    with pytest.raises(DataError, match="needs 64 bytes of samples, the file has 12") as info:
        read_pfm(path)
    assert str(path) in str(info.value)
    path.write_bytes(b"P5\n4 4\n255\n" + bytes(16))
    with pytest.raises(DataError, match="not a PFM file"):
        read_pfm(path)


# ----------------------------------------------------------------------------- OpenCV formats


def test_png_16_bit_round_trip(tmp_path):
    rng = np.random.default_rng(3)
    grey = rng.integers(0, 65536, (9, 13)).astype(np.uint16)
    grey[0, 0] = 65535
    colour = rng.integers(0, 65536, (9, 13, 3)).astype(np.uint16)
    write_image(tmp_path / "g.png", grey)
    write_image(tmp_path / "c.png", colour)
    got = read_image(tmp_path / "g.png")
    assert got.dtype == np.uint16
    np.testing.assert_array_equal(got, grey)
    np.testing.assert_array_equal(read_image(tmp_path / "c.png"), colour)


def test_rgb_order_at_the_file_edge(tmp_path):
    red = np.zeros((2, 3, 3), np.uint8)
    red[..., 0] = 255
    write_image(tmp_path / "red.png", red)
    # OpenCV itself stores channels as BGR: red is its third channel.
    raw = cv2.imdecode(np.fromfile(tmp_path / "red.png", np.uint8), cv2.IMREAD_UNCHANGED)
    assert raw[0, 0].tolist() == [0, 0, 255]
    assert read_image(tmp_path / "red.png")[0, 0].tolist() == [255, 0, 0]
    grey = read_image(tmp_path / "red.png", grayscale=True)
    assert grey.shape == (2, 3) and grey[0, 0] == 76  # 0.299 * 255


def test_pgm_8_and_16_bit(tmp_path):
    # Netpbm: a 16-bit PGM stores samples big-endian.
    path = tmp_path / "hand.pgm"
    path.write_bytes(b"P5\n3 1\n65535\n" + bytes([0x01, 0x02, 0xFF, 0xFF, 0x00, 0x07]))
    image = read_image(path)
    assert image.dtype == np.uint16
    assert image.tolist() == [[0x0102, 0xFFFF, 7]]
    write_image(tmp_path / "out16.pgm", image)
    np.testing.assert_array_equal(read_image(tmp_path / "out16.pgm"), image)
    eight = np.arange(12, dtype=np.uint8).reshape(3, 4)
    write_image(tmp_path / "out8.pgm", eight)
    assert (tmp_path / "out8.pgm").read_bytes().endswith(eight.tobytes())
    np.testing.assert_array_equal(read_image(tmp_path / "out8.pgm"), eight)


def test_jpeg_round_trip_is_close(tmp_path):
    y, x = np.mgrid[0:32, 0:48]
    image = np.stack([x * 5, y * 7, (x + y) * 3], axis=-1).astype(np.uint8)
    write_image(tmp_path / "a.jpg", image, jpeg_quality=100)
    got = read_image(tmp_path / "a.jpg")
    assert got.shape == image.shape and got.dtype == np.uint8
    assert np.abs(got.astype(int) - image).mean() < 2


def test_missing_and_undecodable_images(tmp_path):
    with pytest.raises(UsageError, match="no such image") as info:
        read_image(tmp_path / "nothing.png")
    assert "nothing.png" in str(info.value)
    bad = tmp_path / "bad.png"
    bad.write_bytes(b"this is not a png")
    with pytest.raises(DataError, match="cannot decode") as info:
        read_image(bad)
    assert "bad.png" in str(info.value)


def test_write_image_refuses_what_the_format_cannot_hold(tmp_path):
    with pytest.raises(ValueError, match="uint8"):
        write_image(tmp_path / "a.jpg", np.zeros((2, 2), np.uint16))
    with pytest.raises(ValueError, match="float"):
        write_image(tmp_path / "a.png", np.zeros((2, 2), np.float32))
    with pytest.raises(ValueError, match="shape"):
        write_image(tmp_path / "a.png", np.zeros((2, 2, 4), np.uint8))
    with pytest.raises(UsageError, match=r"'\.xyz'"):
        write_image(tmp_path / "a.xyz", np.zeros((2, 2), np.uint8))
    assert list(tmp_path.iterdir()) == []


def test_write_image_replaces_existing_file_without_leftovers(tmp_path):
    path = tmp_path / "x.png"
    write_image(path, np.zeros((2, 2), np.uint8))
    write_image(path, np.full((2, 2), 9, np.uint8))
    assert read_image(path).tolist() == [[9, 9], [9, 9]]
    assert [p.name for p in tmp_path.iterdir()] == ["x.png"]


def test_middlebury_ground_truth_reads_at_published_size():
    disparity = read_image(shared_data("middlebury", "2001", "tsukuba", "disp3.pgm"))
    assert disparity.shape == (288, 384) and disparity.dtype == np.uint8
    left = read_image(shared_data("middlebury", "2003", "teddy", "im2.png"))
    assert left.shape == (375, 450, 3)
