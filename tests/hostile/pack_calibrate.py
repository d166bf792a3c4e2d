"""pack, calibrate and colorcorrect under careless and hostile use: sidecars that name
files outside the output folder, outputs that name inputs or each other, colour-chart
files of the wrong shape, and the bad inputs and options that already fail cleanly."""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path

import numpy as np

from hostile import SAMPLE, Case, copy_sample, together, write
from mvtools.io.images import read_image, write_image

VIEW0 = "v0_texture_256x192_yuv420p.yuv"
VIEW1 = "v1_texture_256x192_yuv420p.yuv"
VIEW2 = "v2_texture_256x192_yuv420p.yuv"
VIEWS = copy_sample(VIEW0, VIEW1)
PACK_TWO = ("pack", "--view", "a", VIEW0, "--view", "b", VIEW1)
FRAME_BYTES = 256 * 192 * 3 // 2

# --- pack ----------------------------------------------------------------------------
# A packed video of two 256x192 views side by side (black frames) and its sidecar.
PACKED = "packed_512x192_yuv420p.yuv"
SIDECAR = "packed_512x192_yuv420p.json"
UNPACK = ("pack", "--unpack", PACKED, "-o", "out")
UNPACKED = ("out/a_256x192_yuv420p.yuv", "out/b_256x192_yuv420p.yuv")


def _view_entry(name: str, x: int) -> dict:
    return {
        "name": name,
        "kind": "texture",
        "file": f"{name}_256x192_yuv420p.yuv",
        "pix_fmt": "yuv420p",
        "x": x,
        "y": 0,
        "width": 256,
        "height": 192,
        "source_width": 256,
        "source_height": 192,
        "decimation": [1, 1],
    }


def packed(
    first: dict | None = None,
    second: dict | None = None,
    *,
    frames: int = 1,
    video_bytes: int | None = None,
) -> Callable[[Path], None]:
    """A ``files`` function writing the packed video and its sidecar, the sidecar's two
    views changed by ``first`` and ``second`` (a callable value gets the working folder)."""

    def files(target: Path) -> None:
        size = 2 * FRAME_BYTES * frames if video_bytes is None else video_bytes
        (target / PACKED).write_bytes(bytes(size))
        views = [_view_entry("a", 0), _view_entry("b", 256)]
        for view, changes in zip(views, (first or {}, second or {})):
            view.update(
                {key: value(target) if callable(value) else value for key, value in changes.items()}
            )
        (target / SIDECAR).write_text(
            json.dumps(
                {
                    "format": "mvtools-pack",
                    "version": 1,
                    "layout": "grid",
                    "width": 512,
                    "height": 192,
                    "pix_fmt": "yuv420p",
                    "frames": frames,
                    "views": views,
                }
            )
        )

    return files


def victim(target: Path) -> None:
    (target / "victim.yuv").write_bytes(b"not yours to overwrite")


def sample_at(sample: str, *names: str) -> Callable[[Path], None]:
    """The sample line rig's file ``sample`` under each of ``names`` (folder/file)."""

    def files(target: Path) -> None:
        for name in names:
            (target / name).parent.mkdir(parents=True, exist_ok=True)
            (target / name).write_bytes((SAMPLE / "line" / sample).read_bytes())

    return files


PACK_CASES = [
    # a sidecar names files inside the output folder only, each once
    Case(
        "pack unpack, a sidecar view file outside -o",
        UNPACK,
        2,
        rf"{SIDECAR}: file: view a: '\.\./victim\.yuv' is not a bare file name",
        together(packed({"file": "../victim.yuv"}), victim),
    ),
    Case(
        "pack unpack, a sidecar view file naming the packed video",
        UNPACK,
        2,
        rf"{SIDECAR}: file: view a: .* is not a bare file name",
        packed({"file": f"../{PACKED}"}),
    ),
    Case(
        "pack unpack, a sidecar view file in a subfolder",
        UNPACK,
        2,
        rf"{SIDECAR}: file: view b: 'sub/b\.yuv' is not a bare file name",
        packed(second={"file": "sub/b.yuv"}),
    ),
    Case(
        "pack unpack, a sidecar view file given by an absolute path",
        UNPACK,
        2,
        rf"{SIDECAR}: file: view a: .*victim\.yuv' is not a bare file name",
        together(packed({"file": lambda target: str(target / "victim.yuv")}), victim),
    ),
    Case(
        "pack unpack, a sidecar view file '..'",
        UNPACK,
        2,
        rf"{SIDECAR}: file: view a: '\.\.' is not a bare file name",
        packed({"file": ".."}),
    ),
    Case(
        "pack unpack, a sidecar view file with a backslash",
        UNPACK,
        2,
        rf"{SIDECAR}: file: view a: .* is not a bare file name",
        packed({"file": "..\\victim.yuv"}),
    ),
    Case(
        "pack unpack, two sidecar views with one file",
        UNPACK,
        2,
        rf"{SIDECAR}: file: views a and b both name 'a_256x192_yuv420p\.yuv'",
        packed(second={"file": "a_256x192_yuv420p.yuv"}),
    ),
    Case(
        "pack unpack, a sidecar view wider than its placement",
        UNPACK,
        2,
        rf"{SIDECAR}: source_width: view a: source_width 400 .* width 256",
        packed({"source_width": 400}),
    ),
    Case(
        "pack unpack, a sidecar view shorter than its placement",
        UNPACK,
        2,
        rf"{SIDECAR}: source_height: view b: source_height 100 .* height 192",
        packed(second={"source_height": 100}),
    ),
    Case(
        "pack unpack, a halved sidecar view of the wrong source size",
        UNPACK,
        2,
        rf"{SIDECAR}: source_width: view a: source_width 256 at decimation 2 .* width 256",
        packed({"decimation": [2, 1]}),
    ),
    Case(
        "pack unpack, a sidecar view of another bit depth",
        UNPACK,
        2,
        rf"{SIDECAR}: pix_fmt: view b: pix_fmt gray16le does not fit the packed yuv420p",
        packed(second={"pix_fmt": "gray16le"}),
    ),
    Case(
        "pack unpack, a sidecar view of an unknown pixel format",
        UNPACK,
        2,
        rf"{SIDECAR}: pix_fmt: view a: unknown pixel format 'rgb24'",
        packed({"pix_fmt": "rgb24"}),
    ),
    Case(
        "pack unpack, a sidecar view listed twice",
        UNPACK,
        2,
        rf"{SIDECAR}: name: texture a is listed twice",
        packed(second={"name": "a"}),
    ),
    Case(
        "pack unpack, a sidecar whose frame count disagrees",
        UNPACK,
        1,
        rf"{PACKED}: the packed video has 2 frames, its sidecar .* says 1",
        packed(video_bytes=4 * FRAME_BYTES),
    ),
    Case(
        "pack unpack, a truncated packed video",
        UNPACK,
        1,
        rf"{PACKED}: .*truncated",
        packed(video_bytes=3 * FRAME_BYTES),
    ),
    Case(
        "pack unpack, no sidecar",
        ("pack", "--unpack", "lone_512x192_yuv420p.yuv", "-o", "out"),
        2,
        r"lone_512x192_yuv420p\.yuv: no sidecar",
        write("lone_512x192_yuv420p.yuv", bytes(2 * FRAME_BYTES)),
    ),
    Case(
        "pack unpack, a sidecar that is not JSON",
        (*UNPACK, "--sidecar", "bad.json"),
        2,
        r"bad\.json:1: invalid JSON",
        together(packed(), write("bad.json", "{views")),
    ),
    Case(
        "pack unpack, a sidecar of another program",
        (*UNPACK, "--sidecar", "other.json"),
        2,
        r"other\.json: not an mvtools pack sidecar",
        together(packed(), write("other.json", '{"cameras": []}')),
    ),
    Case(
        "pack unpack -o onto a file",
        ("pack", "--unpack", PACKED, "-o", "notes.txt"),
        2,
        r"notes\.txt: the output folder is not a folder",
        together(packed(), write("notes.txt", "mine")),
    ),
    Case(
        "pack unpack into the packed video's folder, a view named as the packed video",
        ("pack", "--unpack", PACKED, "-o", "."),
        2,
        rf"{PACKED}: the output would overwrite an input",
        packed({"file": PACKED}),
    ),
    Case(
        "pack unpack with --view",
        (*UNPACK, "--view", "a", VIEW0),
        2,
        r"give no --view",
        together(packed(), VIEWS),
    ),
    Case("pack unpack, a good run", UNPACK, 0, files=packed(), outputs=UNPACKED),
    # outputs that name inputs or each other
    Case(
        "pack -o with the sidecar's name",
        (*PACK_TWO, "-o", "p.json"),
        2,
        r"p\.json: the sidecar \(--sidecar\) is already the packed video \(-o\)",
        VIEWS,
    ),
    Case(
        "pack --sidecar equal to -o",
        (*PACK_TWO, "-o", "p.yuv", "--sidecar", "p.yuv"),
        2,
        r"p\.yuv: the sidecar \(--sidecar\) is already the packed video \(-o\)",
        VIEWS,
    ),
    Case(
        "pack --sidecar onto an input view",
        (*PACK_TWO, "-o", "p.yuv", "--sidecar", VIEW0),
        2,
        rf"{VIEW0}: the sidecar \(--sidecar\) would overwrite an input",
        VIEWS,
    ),
    Case(
        "pack -o onto an input view",
        (*PACK_TWO, "-o", VIEW1),
        2,
        rf"{VIEW1}: the packed video \(-o\) would overwrite an input",
        VIEWS,
    ),
    Case(
        "pack into a missing folder",
        (*PACK_TWO, "-o", "nowhere/p.yuv"),
        2,
        r"nowhere: the output folder does not exist",
        VIEWS,
    ),
    Case(
        "pack two views of one file name",
        ("pack", "--view", "a", f"a/{VIEW0}", "--view", "b", f"b/{VIEW0}", "-o", "p.yuv"),
        2,
        rf"b/{VIEW0}: --view b: .*same file name as --view a",
        sample_at(VIEW0, f"a/{VIEW0}", f"b/{VIEW0}"),
    ),
    # bad options and inputs
    Case("pack without views", ("pack", "-o", "p.yuv"), 2, r"give the views to pack"),
    Case(
        "pack three views side by side",
        (*PACK_TWO, "--view", "c", VIEW2, "--layout", "side-by-side", "-o", "p.yuv"),
        2,
        r"holds two views, got 3",
        copy_sample(VIEW0, VIEW1, VIEW2),
    ),
    Case(
        "pack a view twice",
        (*PACK_TWO, "--view", "a", VIEW1, "-o", "p.yuv"),
        2,
        r"given twice",
        VIEWS,
    ),
    Case(
        "pack an unknown layout",
        (*PACK_TWO, "--layout", "diagonal", "-o", "p.yuv"),
        2,
        r"diagonal",
        VIEWS,
    ),
    Case(
        "pack a frame size too small",
        (*PACK_TWO, "--frame-size", "256x192", "-o", "p.yuv"),
        2,
        r"more than the 256x192 frame",
        VIEWS,
    ),
    Case(
        "pack a missing view",
        (*PACK_TWO, "-o", "p.yuv"),
        2,
        rf"{VIEW1}: no such",
        copy_sample(VIEW0),
    ),
    Case(
        "pack a truncated view",
        (*PACK_TWO, "-o", "p.yuv"),
        1,
        rf"{VIEW1}: .*truncated",
        together(copy_sample(VIEW0), write(VIEW1, bytes(FRAME_BYTES + 100))),
    ),
    Case(
        "pack, a good run", (*PACK_TWO, "-o", "p.yuv"), 0, files=VIEWS, outputs=("p.yuv", "p.json")
    ),
]

# --- calibrate -----------------------------------------------------------------------
CAPTURES = ("capture00.png", "capture04.png", "capture06.png")


def captures(camera: str, folder: str, names=CAPTURES) -> Callable[[Path], None]:
    """Captures of the sample rig's ``camera`` (which sees the board in them) in ``folder``."""

    def files(target: Path) -> None:
        (target / folder).mkdir(parents=True, exist_ok=True)
        for name in names:
            (target / folder / name).write_bytes(
                (SAMPLE / "checkerboard" / camera / name).read_bytes()
            )

    return files


RIG = together(captures("cam2", "cam2"), captures("cam3", "cam3"))


def copy_of(name: str, copy: str) -> Callable[[Path], None]:
    """A copy of the working folder's file ``name`` as ``copy``."""

    def files(target: Path) -> None:
        (target / copy).write_bytes((target / name).read_bytes())

    return files


def smaller_capture(name: str) -> Callable[[Path], None]:
    """Replace capture ``name`` by its top-left quarter."""

    def files(target: Path) -> None:
        write_image(target / name, read_image(target / name)[:240, :320])

    return files


CALIBRATE = ("calibrate", "cam2", "cam3", "--board", "9x6", "--square", "0.05")

CALIBRATE_CASES = [
    Case(
        "calibrate --json equal to -o",
        (*CALIBRATE, "-o", "c.txt", "--json", "c.txt"),
        2,
        r"c\.txt: the JSON camera file \(--json\) and the camera file \(-o\) are one file",
        RIG,
    ),
    Case(
        "calibrate -o in the --report folder with the report's name",
        (*CALIBRATE, "-o", "rep/report.json", "--report", "rep"),
        2,
        r"rep/report\.json: the report \(--report\) and the camera file \(-o\) are one file",
        together(RIG, lambda target: (target / "rep").mkdir()),
    ),
    Case(
        "calibrate --report onto a file",
        (*CALIBRATE, "-o", "c.txt", "--report", "notes.txt"),
        2,
        r"--report.*notes\.txt' is a file",
        together(RIG, write("notes.txt", "mine")),
    ),
    Case(
        "calibrate --report's corner picture onto a capture",
        (*CALIBRATE, "-o", "c.txt", "--report", "cam2"),
        2,
        r"cam2/cam2_corners\.png: the corner picture of cam2 \(--report\) would overwrite an "
        "input",
        together(
            RIG,
            copy_of("cam2/capture00.png", "cam2/cam2_corners.png"),
            copy_of("cam3/capture00.png", "cam3/cam3_corners.png"),
        ),
    ),
    Case(
        "calibrate -o onto a capture image",
        (*CALIBRATE, "-o", "cam2/capture04.png"),
        2,
        r"cam2/capture04\.png: the camera file \(-o\) would overwrite an input",
        RIG,
    ),
    Case(
        "calibrate --json onto a capture image",
        (*CALIBRATE, "-o", "c.txt", "--json", "cam3/capture00.png"),
        2,
        r"cam3/capture00\.png: the JSON camera file \(--json\) would overwrite an input",
        RIG,
    ),
    Case(
        "calibrate into a missing folder",
        (*CALIBRATE, "-o", "nowhere/c.txt"),
        2,
        r"nowhere: the output folder does not exist",
        RIG,
    ),
    Case(
        "calibrate --json into a missing folder",
        (*CALIBRATE, "-o", "c.txt", "--json", "nowhere/c.json"),
        2,
        r"nowhere: the output folder does not exist",
        RIG,
    ),
    Case(
        "calibrate a missing capture folder",
        ("calibrate", "cam2", "cam9", "--board", "9x6", "--square", "0.05", "-o", "c.txt"),
        2,
        r"cam9: no such folder, image pattern or video",
        RIG,
    ),
    Case(
        "calibrate an empty capture folder",
        (*CALIBRATE, "-o", "c.txt"),
        2,
        r"cam3: the folder holds no images",
        together(captures("cam2", "cam2"), captures("cam3", "cam3", names=())),
    ),
    Case(
        "calibrate a pattern that matches nothing",
        ("calibrate", "cam2/*.jpg", "--board", "9x6", "--square", "0.05", "-o", "c.txt"),
        2,
        r"cam2/\*\.jpg: no image matches the pattern",
        RIG,
    ),
    Case(
        "calibrate a capture that is not an image",
        (*CALIBRATE, "-o", "c.txt"),
        1,
        r"cam3/capture04\.png: cannot decode the image",
        together(RIG, write("cam3/capture04.png", b"\x89PNG broken")),
    ),
    Case(
        "calibrate captures of different sizes",
        (*CALIBRATE, "-o", "c.txt"),
        1,
        r"cam3/capture06\.png: cam3: capture is 320x240, the camera's earlier captures 640x480",
        together(RIG, smaller_capture("cam3/capture06.png")),
    ),
    Case(
        "calibrate different capture counts",
        (*CALIBRATE, "-o", "c.txt"),
        2,
        r"different numbers of captures \(cam2 3, cam3 2\)",
        together(captures("cam2", "cam2"), captures("cam3", "cam3", names=CAPTURES[:2])),
    ),
    Case(
        "calibrate a truncated capture video",
        ("calibrate", "cam_640x480_gray.yuv", "--board", "9x6", "--square", "0.05", "-o", "c.txt"),
        1,
        r"cam_640x480_gray\.yuv: .*truncated",
        write("cam_640x480_gray.yuv", bytes(640 * 480 + 7)),
    ),
    Case(
        "calibrate a bad --board",
        ("calibrate", "cam2", "--board", "9", "--square", "0.05", "-o", "c.txt"),
        2,
        r"COLUMNSxROWS",
        RIG,
    ),
    Case(
        "calibrate a zero --square",
        ("calibrate", "cam2", "--board", "9x6", "--square", "0", "-o", "c.txt"),
        2,
        r"--square",
        RIG,
    ),
    Case(
        "calibrate an unknown --reference",
        (*CALIBRATE, "--reference", "cam7", "-o", "c.txt"),
        2,
        r"--reference cam7: no such camera",
        RIG,
    ),
    Case(
        "calibrate too few --names",
        (*CALIBRATE, "--names", "left", "-o", "c.txt"),
        2,
        r"--names gives 1 names for 2 cameras",
        RIG,
    ),
    Case(
        "calibrate, a good run",
        (*CALIBRATE, "-o", "c.txt", "--json", "c.json", "-q"),
        0,
        files=RIG,
        outputs=("c.txt", "c.json"),
    ),
]

# --- colorcorrect --------------------------------------------------------------------
CHART = "ColorChecker24 - After November 2014"
TO_CHART = (
    "colorcorrect",
    "--view",
    "cam",
    VIEW0,
    "--target",
    "chart",
    "--chart-reference",
    "chart.json",
    "-o",
    "out",
)
CORRECT_TWO = ("colorcorrect", "--view", "cam0", VIEW0, "--view", "cam1", VIEW1)


def _chart(**changes) -> dict:
    """A CCS_COLOURCHECKERS document of one 6 x 4 chart, its entry changed by ``changes``."""
    entry = {
        "illuminant_xy": [0.3457, 0.3585],
        "rows": 4,
        "columns": 6,
        "patches": {
            f"patch {index}": {
                "XYZ": [index / 30] * 3,
                "Lab_under_chart_illuminant": [50.0, 0.0, 0.0],
            }
            for index in range(24)
        },
    }
    entry.update(changes)
    return {CHART: entry}


def chart_file(document) -> Callable[[Path], None]:
    return together(copy_sample(VIEW0), write("chart.json", json.dumps(document)))


PATCHES = _chart()[CHART]["patches"]


def _picture(offset: int) -> np.ndarray:
    """A small RGB picture with every code of a ramp in each channel."""
    ramp = np.add.outer(np.arange(48), np.arange(64)).astype(np.uint8) + offset
    return np.stack([ramp, ramp // 2 + 60, 255 - ramp], axis=-1)


COLORCORRECT_CASES = [
    # colour-chart files of the wrong shape: the file, the key, and the shape needed
    Case(
        "colorcorrect, a chart file that is a list",
        TO_CHART,
        2,
        r"chart\.json: expected an object of charts by name .*CCS_COLOURCHECKERS.*got a list",
        chart_file([1, 2]),
    ),
    Case(
        "colorcorrect, a chart that is a list",
        TO_CHART,
        2,
        rf"chart\.json: {CHART}: the chart must be an object of illuminant_xy \[x, y\], rows, "
        r"columns and patches, got a list",
        chart_file({CHART: [1, 2]}),
    ),
    Case(
        "colorcorrect, a chart of spectral distributions",
        TO_CHART,
        2,
        rf"chart\.json: {CHART}: the chart must be an object of illuminant_xy \[x, y\], rows, "
        r"columns and patches, got an object of 'dark skin'",
        chart_file({CHART: {"dark skin": {"wavelengths": [380.0], "values": [0.05]}}}),
    ),
    Case(
        "colorcorrect, chart patches as a list",
        TO_CHART,
        2,
        rf"chart\.json: {CHART}: patches: .*an object of patch name to .*XYZ.*got a list",
        chart_file(_chart(patches=list(PATCHES.items()))),
    ),
    Case(
        "colorcorrect, too few chart patches",
        TO_CHART,
        2,
        rf"chart\.json: {CHART}: patches: columns x rows = 6 x 4 = 24 patches, got 23",
        chart_file(_chart(patches=dict(list(PATCHES.items())[:23]))),
    ),
    Case(
        "colorcorrect, a chart patch that is a list",
        TO_CHART,
        2,
        rf"chart\.json: {CHART}: patch 3: .*an object of XYZ .*got a list",
        chart_file(_chart(patches={**PATCHES, "patch 3": [1, 2, 3]})),
    ),
    Case(
        "colorcorrect, a chart patch of two XYZ numbers",
        TO_CHART,
        2,
        rf"chart\.json: {CHART}: patch 3: XYZ must be a list of 3 finite numbers",
        chart_file(
            _chart(patches={**PATCHES, "patch 3": {**PATCHES["patch 3"], "XYZ": [0.1, 0.1]}})
        ),
    ),
    Case(
        "colorcorrect, a chart without rows",
        TO_CHART,
        2,
        rf"chart\.json: {CHART}: rows must be a positive integer, missing",
        chart_file(
            {CHART: {key: value for key, value in _chart()[CHART].items() if key != "rows"}}
        ),
    ),
    Case(
        "colorcorrect, an unknown chart",
        (*TO_CHART, "--chart-name", "Mine"),
        2,
        rf"chart\.json: no chart 'Mine' in the file \(charts: '{CHART}'\)",
        chart_file(_chart()),
    ),
    Case(
        "colorcorrect, a chart file that is not JSON",
        TO_CHART,
        2,
        r"chart\.json:1: invalid JSON",
        together(copy_sample(VIEW0), write("chart.json", "{charts")),
    ),
    Case(
        "colorcorrect to a chart without --chart-reference",
        ("colorcorrect", "--view", "cam", VIEW0, "--target", "chart", "-o", "out"),
        2,
        r"needs --chart-reference",
        copy_sample(VIEW0),
    ),
    # outputs that name inputs or each other
    Case(
        "colorcorrect -o the views' folder",
        (*CORRECT_TWO, "-o", "."),
        2,
        rf"{VIEW0}: the corrected video .* would overwrite an input: give it another name or folder",
        VIEWS,
    ),
    Case(
        "colorcorrect pictures into their own folder",
        ("colorcorrect", "--view", "l", "l.png", "--view", "r", "r.png", "-o", "."),
        2,
        r"l\.png: the corrected picture .* would overwrite an input",
        together(
            lambda target: write_image(target / "l.png", _picture(0)),
            lambda target: write_image(target / "r.png", _picture(40)),
        ),
    ),
    Case(
        "colorcorrect, a table onto the camera file",
        (*CORRECT_TWO, "--cameras", "out/cam1.lut.txt", "--depth-range", "2", "13", "-o", "out"),
        2,
        r"out/cam1\.lut\.txt: the table .* would overwrite an input",
        together(VIEWS, sample_at("cameras.txt", "out/cam1.lut.txt")),
    ),
    Case(
        "colorcorrect two views of one file name",
        (
            "colorcorrect",
            "--view",
            "cam0",
            f"a/{VIEW0}",
            "--view",
            "cam1",
            f"b/{VIEW0}",
            "-o",
            "out",
        ),
        2,
        rf"b/{VIEW0}: --view cam1: .*same file name as --view cam0",
        sample_at(VIEW0, f"a/{VIEW0}", f"b/{VIEW0}"),
    ),
    # bad options and inputs
    Case(
        "colorcorrect one view",
        ("colorcorrect", "--view", "cam0", VIEW0, "-o", "out"),
        2,
        r"at least two views",
        VIEWS,
    ),
    Case(
        "colorcorrect a view twice",
        (*CORRECT_TWO, "--view", "cam0", VIEW1, "-o", "out"),
        2,
        r"a view is given twice",
        VIEWS,
    ),
    Case(
        "colorcorrect an unknown --reference",
        (*CORRECT_TWO, "--reference", "cam7", "-o", "out"),
        2,
        r"--reference cam7: no such view",
        VIEWS,
    ),
    Case(
        "colorcorrect --depth without --cameras",
        (*CORRECT_TWO, "--depth", "cam0", VIEW0, "-o", "out"),
        2,
        r"--depth needs --cameras",
        VIEWS,
    ),
    Case(
        "colorcorrect bad --chart-corners",
        (*TO_CHART, "--chart-corners", "cam", "1,2,3"),
        2,
        r"give eight numbers",
        chart_file(_chart()),
    ),
    Case(
        "colorcorrect a missing view",
        (*CORRECT_TWO, "-o", "out"),
        2,
        rf"{VIEW1}: no such",
        copy_sample(VIEW0),
    ),
    Case(
        "colorcorrect a truncated view",
        (*CORRECT_TWO, "-o", "out"),
        1,
        rf"{VIEW1}: .*truncated",
        together(copy_sample(VIEW0), write(VIEW1, bytes(FRAME_BYTES + 100))),
    ),
    Case(
        "colorcorrect views of different sizes",
        (
            "colorcorrect",
            "--view",
            "cam0",
            VIEW0,
            "--view",
            "cam1",
            "s_128x96_yuv420p.yuv",
            "-o",
            "out",
        ),
        1,
        r"the views differ in size or format",
        together(copy_sample(VIEW0), write("s_128x96_yuv420p.yuv", bytes(128 * 96 * 3 // 2))),
    ),
    Case(
        "colorcorrect a constant view",
        (*CORRECT_TWO, "-o", "out"),
        1,
        rf"{VIEW1}: view cam1 is constant",
        together(copy_sample(VIEW0), write(VIEW1, bytes([100]) * FRAME_BYTES)),
    ),
    Case(
        "colorcorrect, a good run",
        (*CORRECT_TWO, "-o", "out", "-q"),
        0,
        files=VIEWS,
        outputs=(
            f"out/{VIEW0}",
            f"out/{VIEW1}",
            "out/cam0.lut.txt",
            "out/cam1.lut.txt",
            "out/cam0.cube",
            "out/cam1.cube",
        ),
    ),
]

CASES = PACK_CASES + CALIBRATE_CASES + COLORCORRECT_CASES
