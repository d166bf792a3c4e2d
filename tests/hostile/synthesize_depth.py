"""synthesize and estimate-depth (DERS mode and stereo pairs), their configuration and
camera files."""

from __future__ import annotations

import cv2
import numpy as np

from hostile import LINE_SYNTHESIS, SAMPLE, Case, copy_sample, together, write

LINE = SAMPLE / "line"
SYNTHESIS_CONFIG = "synthesize_cam2.cfg"
DERS_CONFIG = "depth_cam2.cfg"
OUT = "out_256x192_yuv420p.yuv"
FRAME_BYTES = 256 * 192 * 3 // 2

#: The sample line rig's depth estimation inputs: configuration, cameras, views 1 to 3.
LINE_DERS = copy_sample(
    DERS_CONFIG,
    "cameras.txt",
    "v1_texture_256x192_yuv420p.yuv",
    "v2_texture_256x192_yuv420p.yuv",
    "v3_texture_256x192_yuv420p.yuv",
)

_CAM1_K = "cam1\n240.0 0.0 127.5\n0.0 240.0 95.5\n0.0 0.0 1.0\n0.0\n0.0\n"
_CAMERAS = (LINE / "cameras.txt").read_text()
assert _CAM1_K in _CAMERAS
#: cam1 (line 11) with K all zeros, as a camera file exported without intrinsics has.
ZERO_K_CAMERAS = write(
    "cameras.txt", _CAMERAS.replace(_CAM1_K, "cam1\n0 0 0\n0 0 0\n0 0 0\n0.0\n0.0\n")
)
#: cam1's block one number short (a K2 line lost).
SHORT_CAMERAS = write("cameras.txt", _CAMERAS.replace(_CAM1_K, _CAM1_K[:-4]))
_JSON = (LINE / "cameras.json").read_text()
_CAM1_JSON = '"Name": "cam1",'
ZERO_FOCAL_JSON = write(
    "cameras.json",
    _JSON[: _JSON.index(_CAM1_JSON)]
    + _JSON[_JSON.index(_CAM1_JSON) :].replace('"Focal": [240.0, 240.0]', '"Focal": [0, 0]', 1),
)


def _config(name: str, replace: dict[str, str] | None = None, add: str = ""):
    """A ``files`` function writing sample configuration ``name`` with whole lines
    replaced (by their key) and lines added at the end."""
    lines = (LINE / name).read_text().splitlines(keepends=True)
    for key, line in (replace or {}).items():
        index = next(i for i, text in enumerate(lines) if text.split(" ", 1)[0] == key)
        lines[index] = line + "\n"
    return write(name, "".join(lines) + add)


def _truncated(name: str, frames: float):
    return write(name, (LINE / name).read_bytes()[: int(frames * FRAME_BYTES)])


_, _PNG = cv2.imencode(".png", np.tile(np.arange(48, dtype=np.uint8), (32, 1)))
PAIR = together(write("left.png", _PNG.tobytes()), write("right.png", _PNG.tobytes()))
PAIR_ARGS = ("estimate-depth", "--left", "left.png", "--right", "right.png", "--disparities", "8")

#: A token of 10 MB, as a file that is not text (or a runaway generator) holds.
HUGE = "A" * 10_000_000
#: The one error line: the file and line named, the token cut to a reasonable length.
SHORT_LINE = r"^(?=.{0,400}$)"

CASES = [
    # ------------------------------------------------------------------ outputs onto inputs
    Case(
        "estimate-depth -o onto the configuration",
        ("estimate-depth", DERS_CONFIG, "-o", DERS_CONFIG),
        2,
        rf"{DERS_CONFIG}: the output would overwrite an input",
        LINE_DERS,
    ),
    Case(
        "estimate-depth -o onto the camera file",
        ("estimate-depth", DERS_CONFIG, "-o", "cameras.txt"),
        2,
        r"cameras.txt: the output would overwrite an input",
        LINE_DERS,
    ),
    Case(
        "estimate-depth, the configuration's output key onto the configuration",
        ("estimate-depth", DERS_CONFIG, f"FileOutputDepthMapImage={DERS_CONFIG}"),
        2,
        rf"{DERS_CONFIG}: the output would overwrite an input",
        LINE_DERS,
    ),
    Case(
        "estimate-depth -o onto the center view",
        ("estimate-depth", DERS_CONFIG, "-o", "v2_texture_256x192_yuv420p.yuv"),
        2,
        r"v2_texture_256x192_yuv420p.yuv: the output would overwrite an input",
        LINE_DERS,
    ),
    Case(
        "estimate-depth, the output's description onto the JSON camera file",
        ("estimate-depth", DERS_CONFIG, "FileCameraParameter=cameras.json", "-o", "cameras"),
        2,
        r"cameras.json: the .*would overwrite an input",
        together(LINE_DERS, copy_sample("cameras.json")),
    ),
    Case(
        "synthesize --output-holes onto the left depth map",
        (
            "synthesize",
            SYNTHESIS_CONFIG,
            "-o",
            OUT,
            "--output-holes",
            "v1_depth_256x192_yuv420p.yuv",
        ),
        2,
        r"v1_depth_256x192_yuv420p.yuv: the .*would overwrite an input",
        LINE_SYNTHESIS,
    ),
    Case(
        "synthesize, two outputs of one name",
        ("synthesize", SYNTHESIS_CONFIG, "-o", OUT, "--output-depth", OUT),
        2,
        rf"{OUT}: .*is already the .* of this run",
        LINE_SYNTHESIS,
    ),
    Case(
        "estimate-depth --png onto the left picture",
        (*PAIR_ARGS, "-o", "d.pfm", "--png", "left.png"),
        2,
        r"left.png: the .*would overwrite an input",
        PAIR,
    ),
    Case(
        "estimate-depth, the PFM in a missing folder",
        (*PAIR_ARGS, "-o", "nowhere/d.pfm"),
        2,
        r"nowhere: the output folder does not exist",
        PAIR,
    ),
    Case(
        "estimate-depth, a disparity range wider than the pictures",
        (*PAIR_ARGS[:-1], "60", "-o", "d.pfm"),
        2,
        r"error: disparity range 0\.\.60 is not narrower than the image width 48",
        PAIR,
    ),
    Case(
        "estimate-depth, a stereo pair",
        (*PAIR_ARGS, "-q", "-o", "d.pfm", "--png", "d.png"),
        0,
        files=PAIR,
        outputs=("d.pfm", "d.png"),
    ),
    # ------------------------------------------------------------------ cameras
    Case(
        "synthesize 1D mode, a camera with K all zeros",
        ("synthesize", SYNTHESIS_CONFIG, "-o", OUT),
        2,
        r"cameras.txt:11: cam1: the intrinsic matrix K .*is singular",
        together(LINE_SYNTHESIS, ZERO_K_CAMERAS),
    ),
    Case(
        "synthesize general mode, a camera with K all zeros",
        ("synthesize", SYNTHESIS_CONFIG, "SynthesisMode=0", "-o", OUT),
        2,
        r"cameras.txt:11: cam1: the intrinsic matrix K .*is singular",
        together(LINE_SYNTHESIS, ZERO_K_CAMERAS),
    ),
    Case(
        "estimate-depth, a camera with K all zeros",
        ("estimate-depth", DERS_CONFIG, "-o", OUT),
        2,
        r"cameras.txt:11: cam1: the intrinsic matrix K .*is singular",
        together(LINE_DERS, ZERO_K_CAMERAS),
    ),
    Case(
        "synthesize, a JSON camera with focal lengths 0",
        ("synthesize", SYNTHESIS_CONFIG, "CameraParameterFile=cameras.json", "-o", OUT),
        2,
        r"cameras.json: cam1: the intrinsic matrix K .*is singular",
        together(LINE_SYNTHESIS, ZERO_FOCAL_JSON),
    ),
    Case(
        "synthesize, a camera block of 22 numbers",
        ("synthesize", SYNTHESIS_CONFIG, "-o", OUT),
        2,
        r"cameras.txt:11: cam1: camera block has 22 numbers, 23 needed",
        together(LINE_SYNTHESIS, SHORT_CAMERAS),
    ),
    Case(
        "estimate-depth, a camera block of 22 numbers",
        ("estimate-depth", DERS_CONFIG, "-o", OUT),
        2,
        r"cameras.txt:11: cam1: camera block has 22 numbers, 23 needed",
        together(LINE_DERS, SHORT_CAMERAS),
    ),
    Case(
        "synthesize, a 10 MB camera name",
        ("synthesize", SYNTHESIS_CONFIG, "-o", OUT),
        2,
        rf"{SHORT_LINE}.*cameras.txt:1: A{{60}}\.\.\. \(\d+ characters\):? camera block has 0 "
        r"numbers",
        together(LINE_SYNTHESIS, write("cameras.txt", HUGE + "\n" + _CAMERAS)),
    ),
    # ------------------------------------------------------------------ configurations
    Case(
        "synthesize, a 10 MB value",
        ("synthesize", SYNTHESIS_CONFIG, "-o", OUT),
        2,
        rf"{SHORT_LINE}.*{SYNTHESIS_CONFIG}:3: SourceWidth: 'A{{59}}\.\.\. \(\d+ "
        r"characters\) is not an integer",
        together(LINE_SYNTHESIS, _config(SYNTHESIS_CONFIG, {"SourceWidth": f"SourceWidth {HUGE}"})),
    ),
    Case(
        "estimate-depth, a 10 MB value",
        ("estimate-depth", DERS_CONFIG, "-o", OUT),
        2,
        rf"{SHORT_LINE}.*{DERS_CONFIG}:18: MaximumValueOfDisparityRange: 'A{{59}}\.\.\. "
        r"\(\d+ characters\) is not an integer",
        together(
            LINE_DERS,
            _config(
                DERS_CONFIG,
                {"MaximumValueOfDisparityRange": f"MaximumValueOfDisparityRange {HUGE}"},
            ),
        ),
    ),
    Case(
        "estimate-depth, DepthEstimationMode 1",
        ("estimate-depth", DERS_CONFIG, "-o", OUT),
        2,
        rf"{DERS_CONFIG}:40: DepthEstimationMode: mode 1 .*is not supported.*0 \(automatic\)",
        together(LINE_DERS, _config(DERS_CONFIG, {"DepthEstimationMode": "DepthEstimationMode 1"})),
    ),
    Case(
        "estimate-depth, DepthEstimationMode 3 with its files",
        (
            "estimate-depth",
            DERS_CONFIG,
            "DepthEstimationMode=3",
            "RefDepthCameraName=cam1",
            "RefDepthFile=v1_texture_256x192_yuv420p.yuv",
            "-o",
            OUT,
        ),
        2,
        r"<command line>: DepthEstimationMode: mode 3 .*is not supported.*0 \(automatic\)",
        LINE_DERS,
    ),
    Case(
        "synthesize, SourceWidth against the file names",
        ("synthesize", SYNTHESIS_CONFIG, "SourceWidth=320", "-o", OUT),
        1,
        r"v1_texture_256x192_yuv420p.yuv: LeftViewImageName: the file name says 256x192, the "
        r"configuration 320x192",
        LINE_SYNTHESIS,
    ),
    Case(
        "estimate-depth, SourceWidth against the file names",
        ("estimate-depth", DERS_CONFIG, "SourceWidth=320", "-o", OUT),
        1,
        r"v2_texture_256x192_yuv420p.yuv: FileCenterViewImage: the file name says 256x192",
        LINE_DERS,
    ),
    Case(
        "synthesize, an unknown key is a warning",
        ("synthesize", SYNTHESIS_CONFIG, "-q", "--frames", "1", "-o", OUT),
        0,
        files=together(LINE_SYNTHESIS, _config(SYNTHESIS_CONFIG, add="Precison 4\n")),
        outputs=(OUT,),
    ),
    # ------------------------------------------------------------------ damaged videos
    Case(
        "synthesize, a truncated texture",
        ("synthesize", SYNTHESIS_CONFIG, "-o", OUT),
        1,
        r"v1_texture_256x192_yuv420p.yuv: .*not a whole number of 256x192 yuv420p frames",
        together(LINE_SYNTHESIS, _truncated("v1_texture_256x192_yuv420p.yuv", 2.5)),
    ),
    Case(
        "synthesize, a truncated depth map",
        ("synthesize", SYNTHESIS_CONFIG, "-o", OUT),
        1,
        r"v3_depth_256x192_yuv420p.yuv: .*not a whole number of 256x192 yuv420p frames",
        together(LINE_SYNTHESIS, _truncated("v3_depth_256x192_yuv420p.yuv", 1.5)),
    ),
    Case(
        "estimate-depth, a truncated view",
        ("estimate-depth", DERS_CONFIG, "-o", OUT),
        1,
        r"v3_texture_256x192_yuv420p.yuv: .*not a whole number of 256x192 yuv420p frames",
        together(LINE_DERS, _truncated("v3_texture_256x192_yuv420p.yuv", 0.5)),
    ),
    # ------------------------------------------------------------------ frame ranges
    Case(
        "synthesize --start-frame past the end",
        ("synthesize", SYNTHESIS_CONFIG, "--start-frame", "3", "-o", OUT),
        2,
        r"error: --start-frame 3 is past the end: the inputs have 3 frames",
        LINE_SYNTHESIS,
    ),
    Case(
        "synthesize, StartFrame of the file past the end",
        ("synthesize", SYNTHESIS_CONFIG, "-o", OUT),
        2,
        rf"error: {SYNTHESIS_CONFIG}:5: StartFrame: 5 is past the end: the inputs have 3 frames",
        together(LINE_SYNTHESIS, _config(SYNTHESIS_CONFIG, {"StartFrame": "StartFrame 5"})),
    ),
    Case(
        "synthesize, StartFrame=7 past the end",
        ("synthesize", SYNTHESIS_CONFIG, "StartFrame=7", "-o", OUT),
        2,
        r"error: <command line>: StartFrame: 7 is past the end: the inputs have 3 frames",
        LINE_SYNTHESIS,
    ),
    Case(
        "estimate-depth, StartFrame of the file past the end",
        ("estimate-depth", DERS_CONFIG, "-o", OUT),
        2,
        rf"error: {DERS_CONFIG}:5: StartFrame: 4 is past the end: the inputs have 3 frames",
        together(LINE_DERS, _config(DERS_CONFIG, {"StartFrame": "StartFrame 4"})),
    ),
    Case(
        "estimate-depth --start-frame past the end",
        ("estimate-depth", DERS_CONFIG, "--start-frame", "9", "-o", OUT),
        2,
        r"error: --start-frame 9 is past the end: the inputs have 3 frames",
        LINE_DERS,
    ),
    Case(
        "synthesize, more frames than the inputs have, from the last",
        ("synthesize", SYNTHESIS_CONFIG, "-q", "--start-frame", "2", "--frames", "10", "-o", OUT),
        0,
        files=LINE_SYNTHESIS,
        outputs=(OUT,),
    ),
    Case(
        "estimate-depth, one frame",
        ("estimate-depth", DERS_CONFIG, "-q", "--start-frame", "2", "--frames", "1", "-o", OUT),
        0,
        files=LINE_DERS,
        outputs=(OUT, f"{OUT}.json"),
    ),
    Case(
        "synthesize given a DERS configuration",
        ("synthesize", DERS_CONFIG, "-o", OUT),
        2,
        rf"{DERS_CONFIG}: this is a DERS configuration \(CenterCameraName, .*\), not a VSRS one",
        LINE_DERS,
    ),
    Case(
        "estimate-depth given a VSRS configuration",
        ("estimate-depth", SYNTHESIS_CONFIG, "-o", OUT),
        2,
        rf"{SYNTHESIS_CONFIG}: this is a VSRS configuration \(LeftNearestDepthValue, .*\), "
        "not a DERS one",
        LINE_SYNTHESIS,
    ),
]
