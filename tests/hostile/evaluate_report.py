"""evaluate, report, bitrate and rectify: outputs onto inputs, bad ranges and thresholds,
damaged build folders, frame rates that are not numbers."""

import json
from pathlib import Path

from hostile import SAMPLE, Case, copy_sample, together, write

REF, TEST = "v1_texture_256x192_yuv420p.yuv", "v2_texture_256x192_yuv420p.yuv"
VIDEOS = copy_sample(REF, TEST)
VIDEO = ("evaluate", REF, TEST, "--frames", "1")

TRUTH, ESTIMATE = "v1_depth_256x192_yuv420p.yuv", "v2_depth_256x192_yuv420p.yuv"
DEPTHS = copy_sample(TRUTH, ESTIMATE, "cameras.txt")
DEPTH = (
    "evaluate",
    "--depth",
    TRUTH,
    ESTIMATE,
    "--cameras",
    "cameras.txt",
    "--camera",
    "cam1",
    "--neighbour",
    "cam2",
    "--frames",
    "1",
)
RANGES = ("--reference-depth-range", "2", "13", "--test-depth-range", "2", "13")


def _pgm(width: int, height: int, offset: int = 0) -> bytes:
    """An 8-bit PGM of disparities 10..59 (+ offset): a ground truth or an estimate."""
    values = bytes((10 + offset + index % 50) for index in range(width * height))
    return f"P5\n{width} {height}\n255\n".encode() + values


#: A map of 0 everywhere: as ground truth no pixel known, as a mask none non-occluded.
UNKNOWN = b"P5\n64 48\n255\n" + bytes(64 * 48)
MAPS = together(
    write("gt.pgm", _pgm(64, 48)),
    write("estimate.pgm", _pgm(64, 48, 1)),
    write("small.pgm", _pgm(64, 40)),
)
DISPARITY = ("evaluate", "--disparity", "gt.pgm", "estimate.pgm", "--gt-scale", "1")

RIG_TEXTURES = ("v0_texture_256x192_yuv420p.yuv", "v1_texture_256x192_yuv420p.yuv")
RIG_DEPTHS = ("v0_depth_256x192_gray16le.yuv", "v1_depth_256x192_gray16le.yuv")
RIG_FILES = copy_sample("cameras.txt", *RIG_TEXTURES, *RIG_DEPTHS, folder="distorted")
RECTIFY_TEXTURES = (
    "rectify",
    "cameras.txt",
    "--frames",
    "1",
    "--view",
    "cam0",
    RIG_TEXTURES[0],
    "--view",
    "cam1",
    RIG_TEXTURES[1],
)
RECTIFY_DEPTHS = (
    "rectify",
    "cameras.txt",
    "--frames",
    "1",
    "--depth",
    "cam0",
    RIG_DEPTHS[0],
    "--depth",
    "cam1",
    RIG_DEPTHS[1],
)


def _copy_into(folder: str, *names: str):
    """A ``files`` function copying sample_data/distorted files into a sub-folder."""

    def files(target: Path) -> None:
        (target / folder).mkdir()
        copy_sample(*names, folder="distorted")(target / folder)

    return files


def _calibration_report(**changes) -> str:
    """A calibration report.json as mvtools calibrate writes one, with ``changes``."""
    camera = {
        "name": "cam0",
        "K": [[240.0, 0, 127.5], [0, 240.0, 95.5], [0, 0, 1]],
        "distortion": {"K1": 0.0, "K2": 0.0},
        "rms_px": 0.2,
        "captures_used": ["a", "b"],
        "capture_rms_px": {"a": 0.2, "b": 0.3},
    }
    return json.dumps({"baselines_m": {}, "cameras": [camera], **changes})


def _errors_json(bins: list[str]) -> str:
    """The JSON of mvtools evaluate --disparity with a histogram of ``bins``."""
    return json.dumps(
        {
            "histogram": {"bins": bins, "pixels": [9, 1], "percent": [90.0, 10.0]},
            "bad_all": {"1": 10.0, "2": 5.0},
            "mean_abs_error": 0.4,
            "rms_error": 0.6,
        }
    )


def _in_build(name: str, content: str | bytes):
    """A ``files`` function writing one file into the build folder ``build``."""
    return write(f"build/{name}", content)


def _video_in_build(target: Path) -> None:
    (target / "build").mkdir()
    copy_sample(REF)(target / "build")


CASES = [
    # evaluate
    Case(
        "evaluate --json-file onto the reference",
        (*VIDEO, "--json-file", REF),
        2,
        rf"{REF}: the output would overwrite an input",
        VIDEOS,
    ),
    Case(
        "evaluate --json-file onto the test video",
        (*VIDEO, "--json-file", TEST),
        2,
        rf"{TEST}: the output would overwrite an input",
        VIDEOS,
    ),
    Case(
        "evaluate --depth --json-file onto the camera file",
        (*DEPTH, *RANGES, "--json-file", "cameras.txt"),
        2,
        r"cameras.txt: the output would overwrite an input",
        DEPTHS,
    ),
    Case(
        "evaluate --json-file into a missing folder",
        (*VIDEO, "--json-file", "nowhere/s.json"),
        2,
        r"nowhere: the output folder does not exist",
        VIDEOS,
    ),
    Case(
        "evaluate --disparity --json-file into a missing folder",
        (*DISPARITY, "--json-file", "nowhere/s.json"),
        2,
        r"nowhere: the output folder does not exist",
        MAPS,
    ),
    Case(
        "evaluate --json-file, a good run",
        (*VIDEO, "--json-file", "scores.json"),
        0,
        files=VIDEOS,
        outputs=("scores.json",),
    ),
    Case(
        "evaluate of a missing test video",
        ("evaluate", REF, "nosuch_256x192_yuv420p.yuv"),
        2,
        r"nosuch_256x192_yuv420p.yuv",
        VIDEOS,
    ),
    Case(
        "evaluate of videos of two sizes",
        ("evaluate", REF, "other_128x96_yuv420p.yuv"),
        1,
        r"other_128x96_yuv420p.yuv: the test video is 128x96",
        together(VIDEOS, write("other_128x96_yuv420p.yuv", bytes(128 * 96 * 3 // 2))),
    ),
    Case(
        "evaluate of a video shorter than one frame",
        ("evaluate", REF, "short_256x192_yuv420p.yuv"),
        1,
        r"short_256x192_yuv420p.yuv",
        together(VIDEOS, write("short_256x192_yuv420p.yuv", bytes(1000))),
    ),
    Case(
        "evaluate --start-frame past the end",
        (*VIDEO, "--start-frame", "99"),
        2,
        r"--start-frame 99 is past the end",
        VIDEOS,
    ),
    Case("evaluate --frames 0", (*VIDEO[:3], "--frames", "0"), 2, r"--frames", VIDEOS),
    Case("evaluate --metric unknown", (*VIDEO, "--metric", "vmaf"), 2, r"--metric", VIDEOS),
    Case(
        "evaluate --disparity and --depth",
        (*DISPARITY, "--depth"),
        2,
        r"--disparity and --depth exclude each other",
        MAPS,
    ),
    Case(
        "evaluate --disparity --threshold -1",
        (*DISPARITY, "--threshold", "-1"),
        2,
        r"--threshold: .*-1",
        MAPS,
    ),
    Case(
        "evaluate --disparity --threshold nan",
        (*DISPARITY, "--threshold", "nan"),
        2,
        r"'--threshold': 'nan' is not a finite number",
        MAPS,
    ),
    Case(
        "evaluate --disparity --gt-scale 0",
        (*DISPARITY[:-1], "0"),
        2,
        r"scale must be positive",
        MAPS,
    ),
    Case(
        "evaluate --disparity without a scale for an unknown set",
        DISPARITY[:-2],
        2,
        r"gt.pgm: .*--gt-scale",
        MAPS,
    ),
    Case(
        "evaluate --disparity of maps of two sizes",
        ("evaluate", "--disparity", "gt.pgm", "small.pgm", "--gt-scale", "1"),
        1,
        r"small.pgm: the disparity map is 64x40, the ground truth 64x48",
        MAPS,
    ),
    Case(
        "evaluate --disparity of a file that is no image",
        ("evaluate", "--disparity", "gt.pgm", "notes.png", "--gt-scale", "1"),
        1,
        r"notes.png: cannot decode the image",
        together(MAPS, write("notes.png", "notes\n")),
    ),
    Case(
        "evaluate --disparity against a ground truth without a known pixel",
        ("evaluate", "--disparity", "zero.pgm", "estimate.pgm", "--gt-scale", "1"),
        1,
        r"zero.pgm: no pixel has known ground truth",
        together(MAPS, write("zero.pgm", UNKNOWN)),
    ),
    Case(
        "evaluate --disparity --nonocc of no non-occluded pixel",
        (*DISPARITY, "--nonocc", "zero.pgm"),
        1,
        r"gt.pgm: no known pixel is non-occluded",
        together(MAPS, write("zero.pgm", UNKNOWN)),
    ),
    Case(
        "evaluate --disparity --nonocc missing",
        (*DISPARITY, "--nonocc", "occl.png"),
        2,
        r"occl.png",
        MAPS,
    ),
    Case(
        "evaluate --disparity, a good run",
        (*DISPARITY, "--json-file", "d.errors.json"),
        0,
        files=MAPS,
        outputs=("d.errors.json",),
    ),
    Case(
        "evaluate --depth --reference-depth-range 13 2",
        (*DEPTH, "--reference-depth-range", "13", "2", "--test-depth-range", "2", "13"),
        2,
        r"--reference-depth-range: Znear 13 is farther than Zfar 2",
        DEPTHS,
    ),
    Case(
        "evaluate --depth --test-depth-range 0 13",
        (*DEPTH, "--reference-depth-range", "2", "13", "--test-depth-range", "0", "13"),
        2,
        r"--test-depth-range: Znear must be finite and not 0",
        DEPTHS,
    ),
    Case(
        "evaluate --depth --threshold -1",
        (*DEPTH, *RANGES, "--threshold", "-1"),
        2,
        r"--threshold: .*-1",
        DEPTHS,
    ),
    Case(
        "evaluate --depth without --cameras",
        DEPTH[:4] + RANGES + ("--camera", "cam1"),
        2,
        r"--depth needs --cameras",
        DEPTHS,
    ),
    Case(
        "evaluate --depth --neighbour not in the camera file",
        (*DEPTH[:-4], "--neighbour", "cam9", *RANGES),
        2,
        r"cameras.txt: --neighbour: no camera 'cam9'",
        DEPTHS,
    ),
    Case(
        "evaluate --depth --camera and --neighbour alike",
        (*DEPTH[:-4], "--neighbour", "cam1", *RANGES),
        2,
        r"cameras.txt: cameras 'cam1' and 'cam1' are at the same place",
        DEPTHS,
    ),
    Case(
        "evaluate --depth, a camera of a negative focal length",
        (*DEPTH, *RANGES),
        2,
        r"cameras.txt: camera 'cam1' has fx -240",
        together(
            DEPTHS,
            lambda target: (target / "cameras.txt").write_text(
                (target / "cameras.txt").read_text().replace("cam1\n240.0", "cam1\n-240.0")
            ),
        ),
    ),
    Case(
        "evaluate --depth without a range or a sidecar",
        DEPTH,
        2,
        rf"{TRUTH}: the depth range is unknown: give --reference-depth-range",
        DEPTHS,
    ),
    Case(
        "evaluate --depth, a sidecar that is not JSON",
        (*DEPTH, "--test-depth-range", "2", "13"),
        2,
        rf"{TRUTH}.json:1: invalid JSON",
        together(DEPTHS, write(f"{TRUTH}.json", "{NearestDepthValue: 2")),
    ),
    Case(
        "evaluate --depth, a sidecar without NearestDepthValue",
        (*DEPTH, "--test-depth-range", "2", "13"),
        2,
        rf"{TRUTH}.json: no NearestDepthValue",
        together(DEPTHS, write(f"{TRUTH}.json", "[2, 13]")),
    ),
    Case(
        "evaluate --depth, a good run",
        (*DEPTH, *RANGES, "--json-file", "v.errors.json"),
        0,
        files=DEPTHS,
        outputs=("v.errors.json",),
    ),
    # report
    Case("report of a missing folder", ("report", "build"), 2, r"build: no such folder"),
    Case(
        "report -o into a missing folder",
        ("report", "build", "-o", "nowhere/r.html"),
        2,
        r"nowhere: the output folder does not exist",
        _in_build("a.scores", "frame Y\n"),
    ),
    Case(
        "report, a malformed errors.json",
        ("report", "build"),
        2,
        r"build/v2.errors.json:1: invalid JSON",
        _in_build("v2.errors.json", '{"histogram": '),
    ),
    Case(
        "report, an errors.json whose histogram is not one",
        ("report", "build"),
        2,
        r"build/v2.errors.json: .*histogram",
        _in_build("v2.errors.json", json.dumps({"histogram": 3, "mean": {}})),
    ),
    Case(
        "report, a malformed report.json",
        ("report", "build"),
        2,
        r"build/report.json:1: invalid JSON",
        _in_build("report.json", "{'modes': "),
    ),
    Case(
        "report, a calibration report.json without cameras",
        ("report", "build"),
        2,
        r"build/report.json: .*cameras",
        _in_build("report.json", '{"baselines_m": {}}'),
    ),
    Case(
        "report, a calibration report.json of a camera without K",
        ("report", "build"),
        2,
        r"build/report.json: .*K",
        _in_build("report.json", _calibration_report().replace('"K"', '"k"')),
    ),
    Case(
        "report, a compression report.json whose rates are text",
        ("report", "build"),
        2,
        r"build/report.json: ",
        _in_build(
            "report.json",
            json.dumps(
                {
                    "modes": {
                        "simulcast": [{"qp": 22, "kbps": "fast", "mean_texture_yuv_psnr": 40.0}]
                    }
                }
            ),
        ),
    ),
    Case(
        "report, a binary scores file",
        ("report", "build"),
        1,
        r"build/a.scores: ",
        _in_build("a.scores", bytes(range(256)) * 4),
    ),
    Case(
        "report, a picture that is no image",
        ("report", "build"),
        1,
        r"build/x.png: cannot decode the image",
        _in_build("x.png", "notes\n"),
    ),
    Case(
        "report, a truncated video",
        ("report", "build"),
        1,
        rf"build/{REF}: 80000 bytes is not a whole number",
        _in_build(REF, (SAMPLE / "line" / REF).read_bytes()[:80000]),
    ),
    Case(
        "report, an errors.json of a histogram of other bins",
        ("report", "build"),
        2,
        r"build/b.errors.json: .*bins are not",
        together(
            _in_build("a.errors.json", _errors_json(["0-1", ">= 1"])),
            _in_build("b.errors.json", _errors_json(["0-2", ">= 2"])),
        ),
    ),
    Case(
        "report, a good run of depth errors",
        ("report", "build"),
        0,
        files=together(
            _in_build("a.errors.json", _errors_json(["0-1", ">= 1"])),
            _in_build("b.errors.json", _errors_json(["0-1", ">= 1"])),
        ),
        outputs=("build/report.html",),
    ),
    Case(
        "report -o onto the report.json it reads",
        ("report", "build", "-o", "build/report.json"),
        2,
        r"build/report.json: the output would overwrite an input",
        _in_build("report.json", _calibration_report()),
    ),
    Case(
        "report -o onto a picture it shows",
        ("report", "build", "-o", f"build/{REF}"),
        2,
        rf"build/{REF}: the output would overwrite an input",
        _video_in_build,
    ),
    Case(
        "report, a good run of a calibration",
        ("report", "build"),
        0,
        files=_in_build("report.json", _calibration_report()),
        outputs=("build/report.html",),
    ),
    # bitrate
    Case("bitrate --fps nan", ("bitrate", "--size", "1920x1080", "--fps", "nan"), 2, r"--fps"),
    Case("bitrate --fps inf", ("bitrate", "--size", "1920x1080", "--fps", "inf"), 2, r"--fps"),
    Case("bitrate --fps 0", ("bitrate", "--size", "1920x1080", "--fps", "0"), 2, r"--fps"),
    Case("bitrate --fps -25", ("bitrate", "--size", "1920x1080", "--fps", "-25"), 2, r"--fps"),
    Case("bitrate --size 0x1080", ("bitrate", "--size", "0x1080", "--fps", "25"), 2, r"--size"),
    Case("bitrate --size 1920", ("bitrate", "--size", "1920", "--fps", "25"), 2, r"--size"),
    Case(
        "bitrate --views 0",
        ("bitrate", "--size", "1920x1080", "--fps", "25", "--views", "0"),
        2,
        r"--views",
    ),
    Case(
        "bitrate --bits 7",
        ("bitrate", "--size", "1920x1080", "--fps", "25", "--bits", "7"),
        2,
        r"--bits",
    ),
    Case("bitrate without --size", ("bitrate", "--fps", "25"), 2, r"--size"),
    Case("bitrate, a good run", ("bitrate", "--size", "1920x1080", "--fps", "25"), 0),
    # rectify
    Case(
        "rectify --cameras-out onto an input video",
        (*RECTIFY_TEXTURES, "-o", "out", "--cameras-out", RIG_TEXTURES[0]),
        2,
        rf"{RIG_TEXTURES[0]}: the output would overwrite an input",
        RIG_FILES,
    ),
    Case(
        "rectify --cameras-out onto the camera file",
        (*RECTIFY_TEXTURES, "-o", "out", "--cameras-out", "cameras.txt"),
        2,
        r"cameras.txt: the output would overwrite an input",
        RIG_FILES,
    ),
    Case(
        "rectify --cameras-out onto a rectified video",
        (*RECTIFY_TEXTURES, "-o", "out", "--cameras-out", f"out/{RIG_TEXTURES[1]}"),
        2,
        rf"out/{RIG_TEXTURES[1]}",
        RIG_FILES,
    ),
    Case(
        "rectify --cameras-out into a missing folder",
        (*RECTIFY_TEXTURES, "-o", "out", "--cameras-out", "nowhere/cameras.txt"),
        2,
        r"nowhere: the output folder does not exist",
        RIG_FILES,
    ),
    Case(
        "rectify -o the inputs' folder",
        (*RECTIFY_TEXTURES, "-o", "."),
        2,
        rf"{RIG_TEXTURES[0]}: the output would overwrite an input",
        RIG_FILES,
    ),
    Case(
        "rectify, two inputs of one name",
        (
            "rectify",
            "cameras.txt",
            "--frames",
            "1",
            "--view",
            "cam0",
            RIG_TEXTURES[0],
            "--view",
            "cam1",
            f"other/{RIG_TEXTURES[0]}",
            "-o",
            "out",
        ),
        2,
        r"would both be written to out/" + RIG_TEXTURES[0],
        together(RIG_FILES, _copy_into("other", RIG_TEXTURES[0])),
    ),
    Case(
        "rectify, one video for two cameras",
        (
            "rectify",
            "cameras.txt",
            "--frames",
            "1",
            "--view",
            "cam0",
            RIG_TEXTURES[0],
            "--view",
            "cam1",
            RIG_TEXTURES[0],
            "-o",
            "out",
        ),
        2,
        r"would both be written to out/" + RIG_TEXTURES[0],
        RIG_FILES,
    ),
    Case(
        "rectify --depth-range 13 2",
        (*RECTIFY_DEPTHS, "--depth-range", "13", "2", "-o", "out"),
        2,
        r"--depth-range: Znear 13 is farther than Zfar 2",
        RIG_FILES,
    ),
    Case(
        "rectify --depth-range 13 2 with textures only",
        (*RECTIFY_TEXTURES, "--depth-range", "13", "2", "-o", "out"),
        2,
        r"--depth-range: Znear 13 is farther than Zfar 2",
        RIG_FILES,
    ),
    Case(
        "rectify --depth without --depth-range",
        (*RECTIFY_DEPTHS, "-o", "out"),
        2,
        r"--depth-range",
        RIG_FILES,
    ),
    Case(
        "rectify of a missing camera file",
        (*RECTIFY_TEXTURES[:1], "nosuch.txt", *RECTIFY_TEXTURES[2:], "-o", "out"),
        2,
        r"nosuch.txt",
        RIG_FILES,
    ),
    Case(
        "rectify --view of a camera not in the file",
        (
            "rectify",
            "cameras.txt",
            "--view",
            "cam0",
            RIG_TEXTURES[0],
            "--view",
            "cam9",
            RIG_TEXTURES[1],
            "-o",
            "out",
        ),
        2,
        r"cameras.txt: .*cam9",
        RIG_FILES,
    ),
    Case(
        "rectify --view of a missing video",
        (
            "rectify",
            "cameras.txt",
            "--view",
            "cam0",
            RIG_TEXTURES[0],
            "--view",
            "cam1",
            "nosuch_256x192_yuv420p.yuv",
            "-o",
            "out",
        ),
        2,
        r"nosuch_256x192_yuv420p.yuv",
        RIG_FILES,
    ),
    Case(
        "rectify --view of videos of two sizes",
        (
            "rectify",
            "cameras.txt",
            "--view",
            "cam0",
            RIG_TEXTURES[0],
            "--view",
            "cam1",
            "small_128x96_yuv420p.yuv",
            "-o",
            "out",
        ),
        1,
        r"the cameras differ in picture size",
        together(RIG_FILES, write("small_128x96_yuv420p.yuv", bytes(128 * 96 * 3 // 2))),
    ),
    Case(
        "rectify --view of a video shorter than one frame",
        (
            "rectify",
            "cameras.txt",
            "--view",
            "cam0",
            RIG_TEXTURES[0],
            "--view",
            "cam1",
            "short_256x192_yuv420p.yuv",
            "-o",
            "out",
        ),
        1,
        r"short_256x192_yuv420p.yuv",
        together(RIG_FILES, write("short_256x192_yuv420p.yuv", bytes(1000))),
    ),
    Case(
        "rectify --start-frame past the end",
        (*RECTIFY_TEXTURES, "--start-frame", "9", "-o", "out"),
        2,
        r"--start-frame 9 is past the end",
        RIG_FILES,
    ),
    Case(
        "rectify --alpha 2",
        (*RECTIFY_TEXTURES, "--alpha", "2", "-o", "out"),
        2,
        r"--alpha",
        RIG_FILES,
    ),
    Case(
        "rectify, a good run",
        (*RECTIFY_TEXTURES, "-o", "out"),
        0,
        files=RIG_FILES,
        outputs=(*(f"out/{name}" for name in RIG_TEXTURES), "out/cameras.txt"),
    ),
]
