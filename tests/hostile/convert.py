"""``convert`` and the readers under it (images, raw YUV, Y4M) under careless use."""

from collections.abc import Callable
from pathlib import Path

import numpy as np

from hostile import SAMPLE, Case, copy_sample, together, write

VIDEO = "v1_texture_256x192_yuv420p.yuv"
FRAME = 256 * 192 * 3 // 2
VIDEO_FILE = copy_sample(VIDEO)


def _sample_frames(count: int = 3) -> bytes:
    return (SAMPLE / "line" / VIDEO).read_bytes()[: count * FRAME]


def y4m(
    name: str, frames: int = 3, *, header: str = "W256 H192 F25:1 C420jpeg", cut: int = 0
) -> Callable[[Path], None]:
    """A ``files`` function writing a Y4M file of the sample video's first ``frames``
    frames (``cut`` bytes short)."""

    def files(target: Path) -> None:
        data = _sample_frames(frames)
        body = b"".join(b"FRAME\n" + data[i * FRAME : (i + 1) * FRAME] for i in range(frames))
        content = f"YUV4MPEG2 {header}\n".encode("ascii") + body
        (target / name).write_bytes(content[: len(content) - cut])

    return files


def pfm(name: str, values) -> Callable[[Path], None]:
    """A ``files`` function writing a one-channel little-endian PFM."""
    values = np.asarray(values, dtype="<f4")
    header = f"Pf\n{values.shape[1]} {values.shape[0]}\n-1\n".encode("ascii")
    return write(name, header + values[::-1].tobytes())


DEPTH = ("--depth", "--depth-range", "1", "10")
TEN_BIT = np.full(4 * 2 * 3 // 2, 64, "<u2")
TEN_BIT[3] = 4000  # above the 10-bit maximum 1023

CASES = [
    # --- what works today, kept working
    Case(
        "convert a truncated raw video",
        ("convert", "v_256x192_yuv420p.yuv", "-o", "o.y4m"),
        1,
        r"v_256x192_yuv420p.yuv: .*not a whole number of .* frames",
        write("v_256x192_yuv420p.yuv", _sample_frames(2)[:-100]),
    ),
    Case(
        "convert a raw video whose size disagrees with its name",
        ("convert", "v_320x240_yuv420p.yuv", "-o", "o.y4m"),
        1,
        r"v_320x240_yuv420p.yuv: .*not a whole number of 320x240 yuv420p frames",
        write("v_320x240_yuv420p.yuv", _sample_frames(1)),
    ),
    Case(
        "convert with an unknown --pix-fmt",
        ("convert", "v.yuv", "--size", "256x192", "--pix-fmt", "yuv411p", "-o", "o.y4m"),
        2,
        r"unknown pixel format 'yuv411p'",
        write("v.yuv", _sample_frames(1)),
    ),
    Case(
        "convert with an unknown --out-pix-fmt",
        ("convert", VIDEO, "--out-pix-fmt", "rgb24", "-o", "o.yuv"),
        2,
        r"unknown pixel format 'rgb24'",
        VIDEO_FILE,
    ),
    Case(
        "convert with a --size that is no size",
        ("convert", "v.yuv", "--size", "256x", "-o", "o.y4m"),
        2,
        r"--size.*not WIDTHxHEIGHT",
        write("v.yuv", _sample_frames(1)),
    ),
    Case(
        "convert with a --size of 0",
        ("convert", "v.yuv", "--size", "0x192", "-o", "o.y4m"),
        2,
        r"--size.*must be positive",
        write("v.yuv", _sample_frames(1)),
    ),
    Case(
        "convert a raw video without a size",
        ("convert", "v.yuv", "-o", "o.y4m"),
        2,
        r"v.yuv: picture size and pixel format unknown",
        write("v.yuv", _sample_frames(1)),
    ),
    Case(
        "convert into an unknown output type",
        ("convert", VIDEO, "-o", "o.xyz"),
        2,
        r"o.xyz: unknown output type '.xyz'",
        VIDEO_FILE,
    ),
    Case(
        "convert --start-frame past the end",
        ("convert", VIDEO, "--start-frame", "3", "-o", "o.yuv"),
        2,
        r"--start-frame 3 is past the end",
        VIDEO_FILE,
    ),
    Case(
        "convert a truncated Y4M",
        ("convert", "v.y4m", "-o", "o.yuv"),
        1,
        r"v.y4m: frame 2 is truncated",
        y4m("v.y4m", cut=10),
    ),
    Case(
        "convert a Y4M of an unsupported colour space",
        ("convert", "v.y4m", "-o", "o.yuv"),
        1,
        r"v.y4m: YUV4MPEG2 colour space C411 is not supported",
        y4m("v.y4m", header="W256 H192 C411"),
    ),
    Case(
        "convert a file that is not an image",
        ("convert", "bad.png", "-o", "o.yuv"),
        1,
        r"bad.png: cannot decode the image",
        write("bad.png", b"\x89PNG\r\n\x1a\n" + b"x" * 40),
    ),
    Case(
        "convert images of two sizes",
        ("convert", "a.pgm", "b.pgm", "-o", "o.yuv"),
        1,
        r"b.pgm: image is 2x2, the first one 4x2",
        together(
            write("a.pgm", b"P5 4 2 255\n" + bytes(8)), write("b.pgm", b"P5 2 2 255\n" + bytes(4))
        ),
    ),
    Case(
        "convert depth to z without a depth range",
        ("convert", VIDEO, "--depth", "--to", "z", "-o", "z_%03d.pfm"),
        2,
        r"--depth-range ZNEAR ZFAR is needed",
        VIDEO_FILE,
    ),
    Case(
        "convert a Y4M into raw video",
        ("convert", "v.y4m", "-o", "o_256x192_yuv420p.yuv"),
        0,
        files=y4m("v.y4m"),
        outputs=("o_256x192_yuv420p.yuv",),
    ),
    Case(
        "convert a video to 10 bits",
        ("convert", VIDEO, "--out-pix-fmt", "yuv420p10le", "-o", "o.y4m"),
        0,
        files=VIDEO_FILE,
        outputs=("o.y4m",),
    ),
    Case(
        "convert video frames to PNG images",
        ("convert", VIDEO, "--frames", "2", "-o", "f_%03d.png"),
        0,
        files=VIDEO_FILE,
        outputs=("f_000.png", "f_001.png"),
    ),
    # --- outputs that name an input, outputs in folders that do not exist
    Case(
        "convert a Y4M onto itself",
        ("convert", "v.y4m", "-o", "v.y4m"),
        2,
        r"v.y4m: the output would overwrite an input",
        y4m("v.y4m"),
    ),
    Case(
        "convert onto its input spelled another way",
        ("convert", VIDEO, "-o", f"./{VIDEO}"),
        2,
        r"the output would overwrite an input",
        VIDEO_FILE,
    ),
    Case(
        "convert a camera file onto itself",
        ("convert", "cameras.json", "-o", "cameras.json"),
        2,
        r"cameras.json: the output would overwrite an input",
        copy_sample("cameras.json"),
    ),
    Case(
        "convert to images in a missing folder",
        ("convert", VIDEO, "-o", "nowhere/f_%03d.png"),
        2,
        r"nowhere: the output folder does not exist",
        VIDEO_FILE,
    ),
    Case(
        "convert a Y4M into a missing folder",
        ("convert", "v.y4m", "-o", "no/where/o.yuv"),
        2,
        r"no/where: the output folder does not exist",
        y4m("v.y4m"),
    ),
    # --- frame-numbered output names (issue 17: tracebacks)
    Case(
        "convert to images with an unknown % field",
        ("convert", "v.y4m", "-o", "f_%q.png"),
        2,
        r"f_%q.png: -o: .*one frame number field",
        y4m("v.y4m"),
    ),
    Case(
        "convert to images with two % fields",
        ("convert", "v.y4m", "-o", "f_%d_%d.png"),
        2,
        r"f_%d_%d.png: -o: .*one frame number field",
        y4m("v.y4m"),
    ),
    Case(
        "convert to images with a literal % only",
        ("convert", VIDEO, "-o", "f_%%.png"),
        2,
        r"f_%%.png: -o: .*one frame number field",
        VIDEO_FILE,
    ),
    Case(
        "convert to images with a field that does not count",
        ("convert", VIDEO, "-o", "f_%.0s.png"),
        2,
        r"f_%.0s.png: -o: .*one frame number field",
        VIDEO_FILE,
    ),
    # --- stereo options (issue 17: tracebacks)
    Case(
        "convert depth to disparity with --baseline 0",
        (
            "convert",
            VIDEO,
            *DEPTH,
            "--to",
            "disparity",
            "--focal",
            "100",
            "--baseline",
            "0",
            "-o",
            "d_%03d.pfm",
        ),
        2,
        r"--baseline.*baseline=0",
        VIDEO_FILE,
    ),
    Case(
        "convert depth to disparity with a --focal of nan",
        (
            "convert",
            VIDEO,
            *DEPTH,
            "--to",
            "disparity",
            "--focal",
            "nan",
            "--baseline",
            "1",
            "-o",
            "d_%03d.pfm",
        ),
        2,
        r"'--focal': 'nan' is not a finite number",
        VIDEO_FILE,
    ),
    Case(
        "convert disparity images to depth with --baseline 0",
        (
            "convert",
            "d.pfm",
            "--from",
            "disparity",
            "--depth-range",
            "1",
            "10",
            "--focal",
            "100",
            "--baseline",
            "0",
            "-o",
            "o.yuv",
        ),
        2,
        r"--baseline.*baseline=0",
        pfm("d.pfm", [[10.0, 20.0], [30.0, 40.0]]),
    ),
    # --- options that contradict each other or the input (issue 17: exit 0 where an error is due)
    Case(
        "convert --to z and --from z together",
        ("convert", VIDEO, *DEPTH, "--to", "z", "--from", "z", "-o", "z_%03d.pfm"),
        2,
        r"--to.*--from",
        VIDEO_FILE,
    ),
    Case(
        "convert images with --to",
        ("convert", "z.pfm", "--to", "z", "--depth-range", "1", "10", "-o", "o.yuv"),
        2,
        r"--to .*depth video",
        pfm("z.pfm", [[2.0, 3.0], [4.0, 5.0]]),
    ),
    Case(
        "convert a video with --from",
        ("convert", VIDEO, "--from", "z", "--depth-range", "1", "10", "-o", "o.yuv"),
        2,
        r"--from .*PFM images",
        VIDEO_FILE,
    ),
    # --- data the conversion cannot use is the file's fault (exit 1, naming it)
    Case(
        "convert a z image holding NaN",
        ("convert", "z.pfm", "--from", "z", "--depth-range", "1", "10", "-o", "o.yuv"),
        1,
        r"z.pfm: .*z must not be 0 or NaN",
        pfm("z.pfm", [[2.0, np.nan], [4.0, 5.0]]),
    ),
    Case(
        "convert a disparity image holding negative values",
        (
            "convert",
            "d.pfm",
            "--from",
            "disparity",
            "--depth-range",
            "1",
            "10",
            "--focal",
            "100",
            "--baseline",
            "1",
            "-o",
            "o.yuv",
        ),
        1,
        r"d.pfm: .*disparity must be >= 0",
        pfm("d.pfm", [[10.0, -1.0], [30.0, 40.0]]),
    ),
    Case(
        "convert a 10-bit video holding a sample above 1023",
        ("convert", "v_4x2_yuv420p10le.yuv", "--out-pix-fmt", "yuv420p12le", "-o", "o.yuv"),
        1,
        r"v_4x2_yuv420p10le.yuv: frame 0: .*4000.*10-bit",
        write("v_4x2_yuv420p10le.yuv", TEN_BIT.tobytes()),
    ),
    # --- Y4M headers (issue 17: no frame, no file name)
    Case(
        "convert a Y4M holding a header and no frame",
        ("convert", "e.y4m", "-o", "o.yuv"),
        1,
        r"e.y4m: the video holds no frame",
        y4m("e.y4m", frames=0),
    ),
    Case(
        "convert a Y4M of width 0",
        ("convert", "w.y4m", "-o", "o.yuv"),
        1,
        r"w.y4m: .*width must be a positive integer, got 0",
        y4m("w.y4m", frames=0, header="W0 H192 C420jpeg"),
    ),
]
