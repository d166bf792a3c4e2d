"""Raw YUV and Y4M reading and writing (mvtools.io.yuv)."""

from fractions import Fraction

import numpy as np
import pytest
from shared_data import shared_data

from mvtools.errors import DataError, UsageError
from mvtools.io.yuv import (
    YuvFormat,
    format_from_name,
    frame_from_luma,
    guess_format,
    open_video,
    open_writer,
    read_frame,
    write_video,
)

FORMATS = [(chroma, bits) for chroma in ("420", "444", "400", "422") for bits in (8, 10, 16)]


def random_frames(fmt, count, seed=0):
    rng = np.random.default_rng(seed)
    native = np.uint8 if fmt.bits == 8 else np.uint16
    return [
        tuple(
            rng.integers(0, fmt.max_value + 1, shape).astype(native) for shape in fmt.plane_shapes
        )
        for _ in range(count)
    ]


def mapped_on_file(array):
    """True when the array's memory is a np.memmap (not a copy)."""
    while array is not None:
        if isinstance(array, np.memmap):
            return True
        array = array.base
    return False


def assert_frames_equal(got, expected):
    assert len(got) == len(expected)
    for got_planes, expected_planes in zip(got, expected):
        assert len(got_planes) == len(expected_planes)
        for a, b in zip(got_planes, expected_planes):
            assert a.shape == b.shape
            np.testing.assert_array_equal(a, b)


# ----------------------------------------------------------------------------- YuvFormat


def test_plane_shapes_and_frame_bytes_of_odd_size():
    # 33x17: chroma of 4:2:0 is ceil(17/2) x ceil(33/2) = 9 x 17.
    assert YuvFormat(33, 17).plane_shapes == ((17, 33), (9, 17), (9, 17))
    assert YuvFormat(33, 17).frame_bytes == 561 + 2 * 153
    assert YuvFormat(33, 17, "420", 10).frame_bytes == 2 * (561 + 2 * 153)
    assert YuvFormat(33, 17, "444", 8).frame_bytes == 3 * 561
    assert YuvFormat(33, 17, "400", 16).plane_shapes == ((17, 33),)
    assert YuvFormat(33, 17, "400", 16).frame_bytes == 2 * 561
    assert YuvFormat(33, 17, "422", 8).plane_shapes == ((17, 33), (17, 17), (17, 17))
    assert YuvFormat(33, 17, "420", 12).max_value == 4095
    assert YuvFormat(4, 4, "420", 10).dtype == np.dtype("<u2")
    assert YuvFormat(4, 4).dtype == np.dtype(np.uint8)


@pytest.mark.parametrize(
    "pix_fmt, chroma, bits",
    [
        ("yuv420p", "420", 8),
        ("yuv420p10le", "420", 10),
        ("yuv420p16le", "420", 16),
        ("yuv444p", "444", 8),
        ("yuv444p12le", "444", 12),
        ("yuv422p", "422", 8),
        ("gray", "400", 8),
        ("gray10le", "400", 10),
        ("gray16le", "400", 16),
    ],
)
def test_pix_fmt_names(pix_fmt, chroma, bits):
    fmt = YuvFormat.from_pix_fmt(8, 6, pix_fmt)
    assert (fmt.chroma, fmt.bits) == (chroma, bits)
    assert fmt.pix_fmt == pix_fmt


def test_yuv400p_is_gray_and_unknown_pix_fmt_lists_supported():
    assert YuvFormat.from_pix_fmt(8, 6, "yuv400p") == YuvFormat(8, 6, "400", 8)
    with pytest.raises(UsageError, match=r"rgb24.*supported: yuv420p, yuv420p10le.*gray16le"):
        YuvFormat.from_pix_fmt(8, 6, "rgb24")
    with pytest.raises(UsageError, match="big-endian"):
        YuvFormat.from_pix_fmt(8, 6, "yuv420p10be")
    with pytest.raises(UsageError, match="bit depth"):
        YuvFormat(8, 6, "420", 9)
    with pytest.raises(UsageError, match="width"):
        YuvFormat(0, 6)


def test_with_changes_fields():
    assert YuvFormat(8, 6).with_(bits=16, chroma="400") == YuvFormat(8, 6, "400", 16)


# ----------------------------------------------------------------------------- names


@pytest.mark.parametrize(
    "name, expected",
    [
        ("kendo_1024x768_yuv420p.yuv", YuvFormat(1024, 768, "420", 8)),
        ("seq_1024x768.yuv", YuvFormat(1024, 768, "420", 8)),
        ("v0_texture_1920x1080_yuv420p10le.yuv", YuvFormat(1920, 1080, "420", 10)),
        ("v0_depth_1920x1080_yuv420p16le.yuv", YuvFormat(1920, 1080, "420", 16)),
        ("depth_640x480_gray.yuv", YuvFormat(640, 480, "400", 8)),
        ("depth_640x480_gray16le.yuv", YuvFormat(640, 480, "400", 16)),
        ("depth_640x480_gray10le.yuv", YuvFormat(640, 480, "400", 10)),
        ("tex_33x17_yuv444p.yuv", YuvFormat(33, 17, "444", 8)),
        ("kendo_ori_I_1.yuv", None),
    ],
)
def test_format_from_name(name, expected):
    assert format_from_name(f"/some/dir/{name}") == expected


def test_unsupported_pix_fmt_in_name_is_an_error():
    with pytest.raises(UsageError, match="yuv411p"):
        format_from_name("a_640x480_yuv411p.yuv")
    with pytest.raises(UsageError, match="big-endian"):
        format_from_name("a_640x480_gray16be.yuv")


# ----------------------------------------------------------------------------- round trips


@pytest.mark.parametrize("chroma, bits", FORMATS)
@pytest.mark.parametrize("suffix", [".yuv", ".y4m"])
def test_round_trip_every_format(tmp_path, chroma, bits, suffix):
    fmt = YuvFormat(33, 17, chroma, bits)
    frames = random_frames(fmt, 3, seed=bits)
    path = tmp_path / f"video{suffix}"
    assert write_video(path, fmt, frames) == 3
    if suffix == ".yuv":
        assert path.stat().st_size == 3 * fmt.frame_bytes
    with open_video(path, fmt if suffix == ".yuv" else None) as reader:
        assert reader.format == fmt
        assert len(reader) == reader.num_frames == 3
        got = list(reader)
    assert_frames_equal(got, frames)


def test_samples_above_8_bits_are_little_endian_in_low_bits(tmp_path):
    # Hand-made yuv420p10le 2x2 frame: Y 1, 2, 3, 1023; U 512; V 4.
    raw = bytes([1, 0, 2, 0, 3, 0, 0xFF, 0x03, 0x00, 0x02, 4, 0])
    path = tmp_path / "hand_2x2_yuv420p10le.yuv"
    path.write_bytes(raw)
    y, u, v = read_frame(path)
    np.testing.assert_array_equal(y, [[1, 2], [3, 1023]])
    assert u.tolist() == [[512]] and v.tolist() == [[4]]
    # And the writer produces exactly those bytes.
    out = tmp_path / "out.yuv"
    write_video(out, YuvFormat(2, 2, "420", 10), [(y, u, v)])
    assert out.read_bytes() == raw


def test_gray16_bytes_and_big_endian_input_array(tmp_path):
    path = tmp_path / "d.yuv"
    luma = np.array([[0x0102, 0xFFFE]], dtype=">u2")  # byte order of the array must not matter
    write_video(path, YuvFormat(2, 1, "400", 16), [(luma,)])
    assert path.read_bytes() == bytes([0x02, 0x01, 0xFE, 0xFF])
    assert read_frame(path, YuvFormat(2, 1, "400", 16))[0].tolist() == [[0x0102, 0xFFFE]]


def test_memory_mapped_frames_of_a_multi_frame_file(tmp_path):
    fmt = YuvFormat(7, 5, "420", 10)
    frames = [
        tuple(
            np.full(shape, 100 * index + plane, np.uint16)
            for plane, shape in enumerate(fmt.plane_shapes)
        )
        for index in range(6)
    ]
    path = tmp_path / "many_7x5_yuv420p10le.yuv"
    write_video(path, fmt, frames)
    with open_video(path) as reader:
        assert reader.num_frames == 6
        y, u, v = reader.read(4)
        assert not y.flags.writeable
        assert mapped_on_file(y) and mapped_on_file(v)
        assert (y == 400).all() and (u == 401).all() and (v == 402).all()
        assert [int(f[0][0, 0]) for f in reader.frames(start=2, count=3)] == [200, 300, 400]
        assert [int(f[2][0, 0]) for f in reader] == [2, 102, 202, 302, 402, 502]
        with pytest.raises(UsageError, match=r"frame 6 does not exist.*6 frames"):
            reader.read(6)
        with pytest.raises(UsageError, match="6 frames"):
            list(reader.frames(start=4, count=3))
    assert reader.closed


def test_read_frame_returns_writable_copy(tmp_path):
    fmt = YuvFormat(4, 2, "400", 8)
    path = tmp_path / "g.yuv"
    write_video(path, fmt, [(np.arange(8, dtype=np.uint8).reshape(2, 4),)] * 2)
    (luma,) = read_frame(path, fmt, index=1)
    luma[0, 0] = 99
    assert read_frame(path, fmt, index=1)[0][0, 0] == 0


def test_frame_from_luma_has_neutral_chroma():
    luma = np.zeros((5, 7), np.uint16)
    _y, u, v = frame_from_luma(YuvFormat(7, 5, "420", 10), luma)
    assert u.shape == v.shape == (3, 4) and (u == 512).all() and (v == 512).all()
    assert len(frame_from_luma(YuvFormat(7, 5, "400", 8), luma.astype(np.uint8))) == 1


# ----------------------------------------------------------------------------- errors


def test_truncated_file_names_size_frame_bytes_and_alternative(tmp_path):
    path = tmp_path / "depth.yuv"
    path.write_bytes(bytes(64 * 48 * 2))  # 2 grey frames, or 1 gray16le frame
    with pytest.raises(DataError) as info:
        open_video(path, YuvFormat(64, 48))
    message = str(info.value)
    assert str(path) in message
    assert "6144 bytes" in message and "4608 bytes" in message
    assert "as yuv400p (gray) it is 2 frames" in message
    assert "gray10le/12le/16le it is 1 frame" in message


def test_truncated_file_that_fits_nothing(tmp_path):
    path = tmp_path / "cut_64x48_yuv420p.yuv"
    path.write_bytes(bytes(4608 + 100))
    with pytest.raises(DataError, match=r"4708 bytes.*no format of that size fits"):
        open_video(path)


def test_wrong_size_suggests_common_size(tmp_path):
    path = tmp_path / "hd.yuv"
    path.write_bytes(bytes(1920 * 1080 * 3 // 2))
    with pytest.raises(DataError, match="as 1920x1080 yuv420p it is 1 frame"):
        open_video(path, YuvFormat(1024, 768))


def test_empty_and_missing_files(tmp_path):
    empty = tmp_path / "e_8x8.yuv"
    empty.write_bytes(b"")
    with pytest.raises(DataError, match="empty"):
        open_video(empty)
    with pytest.raises(UsageError, match="no such file"):
        open_video(tmp_path / "missing_8x8.yuv")
    with pytest.raises(UsageError, match="size and pixel format unknown"):
        open_video(_write(tmp_path / "noname.yuv", 96))


def _write(path, size):
    path.write_bytes(bytes(size))
    return path


def test_guess_format(tmp_path):
    fmt = YuvFormat(64, 48)
    one = _write(tmp_path / "one.yuv", fmt.frame_bytes)
    assert guess_format(one, 64, 48) == fmt
    three = _write(tmp_path / "three.yuv", 3 * fmt.frame_bytes)
    assert guess_format(three, 64, 48) == fmt
    grey = _write(tmp_path / "grey.yuv", 64 * 48)
    assert guess_format(grey, 64, 48) == YuvFormat(64, 48, "400", 8)
    # The name's pixel format wins over the size.
    named = _write(tmp_path / "d_64x48_gray16le.yuv", 2 * fmt.frame_bytes)
    assert guess_format(named, 64, 48) == YuvFormat(64, 48, "400", 16)


def test_guess_format_refuses_halving_or_doubling(tmp_path):
    two = _write(tmp_path / "two.yuv", 2 * YuvFormat(64, 48).frame_bytes)
    with pytest.raises(UsageError) as info:
        guess_format(two, 64, 48)
    message = str(info.value)
    assert "--pix-fmt" in message
    assert "as yuv420p it is 2 frames" in message
    assert "as yuv420p10le/12le/16le it is 1 frame" in message
    assert "as yuv444p it is 1 frame" in message
    # Odd size: 3 grey frames or 1 yuv444p frame, and yuv420p does not fit.
    odd = _write(tmp_path / "odd.yuv", 3 * 33 * 17)
    with pytest.raises(UsageError, match=r"yuv400p \(gray\) it is 3 frames.*yuv444p it is 1 frame"):
        guess_format(odd, 33, 17)
    with pytest.raises(DataError, match="empty"):
        guess_format(_write(tmp_path / "z.yuv", 0), 64, 48)
    y4m = tmp_path / "v.y4m"
    write_video(y4m, YuvFormat(4, 4, "444", 10), random_frames(YuvFormat(4, 4, "444", 10), 2))
    assert guess_format(y4m, 4, 4) == YuvFormat(4, 4, "444", 10)


@pytest.mark.parametrize("suffix", [".yuv", ".y4m"])
def test_writer_error_leaves_nothing(tmp_path, suffix):
    fmt = YuvFormat(8, 6)
    with pytest.raises(RuntimeError), open_writer(tmp_path / f"out{suffix}", fmt) as writer:
        writer.write(random_frames(fmt, 1)[0])
        raise RuntimeError("stop")
    assert list(tmp_path.iterdir()) == []


def test_writer_validates_planes(tmp_path):
    fmt = YuvFormat(8, 6, "420", 10)
    good = random_frames(fmt, 1)[0]
    with open_writer(tmp_path / "v.yuv", fmt) as writer:
        with pytest.raises(ValueError, match="3 planes"):
            writer.write(good[:1])
        with pytest.raises(ValueError, match=r"plane U .* shape \(3, 4\)"):
            writer.write((good[0], good[0], good[2]))
        with pytest.raises(ValueError, match="uint16"):
            writer.write(tuple(p.astype(np.uint8) for p in good))
        with pytest.raises(ValueError, match="1024 above the 10-bit maximum 1023"):
            writer.write((np.full((6, 8), 1024, np.uint16), good[1], good[2]))
        writer.write(good)
    assert (tmp_path / "v.yuv").stat().st_size == fmt.frame_bytes


def test_out_of_range_frame_count_in_message(tmp_path):
    path = tmp_path / "a.y4m"
    write_video(path, YuvFormat(4, 4), random_frames(YuvFormat(4, 4), 2))
    with (
        open_video(path) as reader,
        pytest.raises(UsageError, match="frame 2 does not exist: the video has 2 frames"),
    ):
        reader.read(2)
    with pytest.raises(UsageError, match="not 4x4 yuv444p"):
        open_video(path, YuvFormat(4, 4, "444"))


# ----------------------------------------------------------------------------- Y4M


@pytest.mark.parametrize(
    "chroma, bits, tag",
    [
        ("420", 8, b"C420jpeg XYSCSS=420JPEG"),
        ("444", 8, b"C444 XYSCSS=444"),
        ("400", 8, b"Cmono"),
        ("420", 10, b"C420p10 XYSCSS=420P10"),
        ("444", 16, b"C444p16 XYSCSS=444P16"),
        ("400", 16, b"Cmono16"),
        ("422", 8, b"C422 XYSCSS=422"),
    ],
)
def test_y4m_header_as_ffmpeg_writes_it(tmp_path, chroma, bits, tag):
    fmt = YuvFormat(33, 17, chroma, bits)
    path = tmp_path / "v.y4m"
    frames = random_frames(fmt, 2)
    write_video(path, fmt, frames, frame_rate="30000/1001")
    header = b"YUV4MPEG2 W33 H17 F30000:1001 Ip A1:1 " + tag + b"\n"
    data = path.read_bytes()
    assert data.startswith(header + b"FRAME\n")
    second = len(header) + 6 + fmt.frame_bytes
    assert data[second : second + 6] == b"FRAME\n"
    assert len(data) == len(header) + 2 * (6 + fmt.frame_bytes)
    with open_video(path) as reader:
        assert reader.frame_rate == Fraction(30000, 1001)


def test_hand_written_y4m_with_frame_parameters(tmp_path):
    # 4x2 4:4:4, FRAME lines of different lengths, an X tag in the header.
    planes = [np.arange(24, dtype=np.uint8) + 30 * k for k in range(3)]
    data = (
        b"YUV4MPEG2 W4 H2 F30:1 It A0:0 C444 XVENDOR=test\n"
        + b"FRAME Ixyz\n"
        + planes[0].tobytes()
        + b"FRAME\n"
        + planes[1].tobytes()
        + b"FRAME Ixyz Xcomment=1\n"
        + planes[2].tobytes()
    )
    path = tmp_path / "hand.y4m"
    path.write_bytes(data)
    with open_video(path) as reader:
        assert reader.format == YuvFormat(4, 2, "444", 8)
        assert reader.num_frames == 3
        assert reader.frame_rate == Fraction(30)
        assert reader.interlacing == "t"
        for index in (2, 0, 1):
            y, _u, v = reader.read(index)
            np.testing.assert_array_equal(y, planes[index][:8].reshape(2, 4))
            np.testing.assert_array_equal(v, planes[index][16:].reshape(2, 4))


def test_y4m_same_frame_lines_with_parameters(tmp_path):
    # Equal-length FRAME lines carrying parameters; 4:2:0 without a C tag (420jpeg).
    fmt = YuvFormat(3, 3)
    frames = random_frames(fmt, 4, seed=7)
    body = b"".join(b"FRAME Ip\n" + b"".join(p.tobytes() for p in f) for f in frames)
    path = tmp_path / "noc.y4m"
    path.write_bytes(b"YUV4MPEG2 W3 H3 F25:1\n" + body)
    with open_video(path) as reader:
        assert reader.format == fmt
        assert_frames_equal(
            [reader.read(i) for i in (3, 1, 0, 2)], [frames[i] for i in (3, 1, 0, 2)]
        )


@pytest.mark.parametrize(
    "tag, chroma, bits",
    [
        ("420paldv", "420", 8),
        ("420mpeg2", "420", 8),
        ("420", "420", 8),
        ("mono", "400", 8),
        ("mono16", "400", 16),
        ("420p10", "420", 10),
        ("444p12", "444", 12),
    ],
)
def test_y4m_colour_space_tags(tmp_path, tag, chroma, bits):
    fmt = YuvFormat(2, 2, chroma, bits)
    path = tmp_path / "t.y4m"
    path.write_bytes(f"YUV4MPEG2 W2 H2 C{tag}\nFRAME\n".encode() + bytes(fmt.frame_bytes))
    with open_video(path) as reader:
        assert reader.format == fmt and reader.num_frames == 1


def test_y4m_unsupported_and_truncated(tmp_path):
    path = tmp_path / "a.y4m"
    path.write_bytes(b"YUV4MPEG2 W2 H2 C411\nFRAME\n" + bytes(8))
    with pytest.raises(DataError, match="C411 is not supported"):
        open_video(path)
    fmt = YuvFormat(4, 4)
    path.write_bytes(
        b"YUV4MPEG2 W4 H4 C420jpeg\n"
        + (b"FRAME\n" + bytes(fmt.frame_bytes)) * 2
        + b"FRAME\n"
        + bytes(10)
    )
    with pytest.raises(DataError, match="frame 2 is truncated: 10 of 24 bytes"):
        open_video(path)
    path.write_bytes(b"YUV4MPEG2 W4 H4\nFRAMX\n" + bytes(fmt.frame_bytes))
    with pytest.raises(DataError, match="no FRAME line"):
        open_video(path)
    path.write_bytes(b"YUV4MPEG2 H4\n")
    with pytest.raises(DataError, match="W and H"):
        open_video(path)


# ----------------------------------------------------------------------------- published material


def test_kendo_depth_is_420_with_neutral_chroma():
    path = shared_data("mpeg", "kendo", "kendo_ori_D_1.yuv")
    assert guess_format(path, 1024, 768) == YuvFormat(1024, 768)
    with open_video(path, YuvFormat(1024, 768)) as reader:
        assert reader.num_frames == 1
        y, u, v = reader.read(0)
    assert y.shape == (768, 1024) and u.shape == (384, 512)
    assert (u == 128).all() and (v == 128).all()
    assert y.min() < y.max()
