"""Outputs that name inputs, outputs in folders that do not exist."""

from hostile import LINE_SYNTHESIS, Case, copy_sample

VIDEO = "v1_texture_256x192_yuv420p.yuv"

CASES = [
    Case(
        "convert onto its input",
        ("convert", VIDEO, "-o", VIDEO),
        2,
        rf"{VIDEO}: the output would overwrite an input",
        copy_sample(VIDEO),
    ),
    Case(
        "convert into a missing folder",
        ("convert", VIDEO, "-o", f"nowhere/{VIDEO}"),
        2,
        r"nowhere: the output folder does not exist",
        copy_sample(VIDEO),
    ),
    Case(
        "synthesize -o onto the camera file",
        ("synthesize", "synthesize_cam2.cfg", "-o", "cameras.txt"),
        2,
        r"cameras.txt: the output would overwrite an input",
        LINE_SYNTHESIS,
    ),
    Case(
        "synthesize, the configuration's output key onto the configuration",
        ("synthesize", "synthesize_cam2.cfg", "OutputVirtualViewImageName=synthesize_cam2.cfg"),
        2,
        r"synthesize_cam2.cfg.*overwrite an input",
        LINE_SYNTHESIS,
    ),
    Case(
        "synthesize --output-depth onto the configuration",
        (
            "synthesize",
            "synthesize_cam2.cfg",
            "-o",
            "out_256x192_yuv420p.yuv",
            "--output-depth",
            "synthesize_cam2.cfg",
        ),
        2,
        r"synthesize_cam2.cfg.*overwrite an input",
        LINE_SYNTHESIS,
    ),
    Case(
        "synthesize, a good run",
        (
            "synthesize",
            "synthesize_cam2.cfg",
            "-q",
            "--frames",
            "1",
            "-o",
            "out_256x192_yuv420p.yuv",
        ),
        0,
        files=LINE_SYNTHESIS,
        outputs=("out_256x192_yuv420p.yuv",),
    ),
]
