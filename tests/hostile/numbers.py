"""Number options given NaN or infinity: click's ranges let them through, the
programs' number types (``mvtools.cli.options.FiniteFloat``) refuse them before any
work."""

from hostile import LINE_SYNTHESIS, Case, copy_sample

VIEW = "v1_texture_256x192_yuv420p.yuv"
NOT_FINITE = r"'{option}': '{value}' is not a finite number"

CASES = [
    Case(
        f"{program} {option} {value}",
        (program, *before, option, value, *after),
        2,
        NOT_FINITE.format(option=option, value=value),
        files,
    )
    for program, before, option, after, files in [
        ("calibrate", ("cam2", "--board", "9x6"), "--square", (), None),
        ("encode", ("--view", "v", VIEW, "--qp", "30", "-o", "."), "--fps", (), copy_sample(VIEW)),
        ("scene", ("out",), "--capture-noise", (), None),
        ("evaluate", (VIEW, VIEW), "--disparity-scale", (), copy_sample(VIEW)),
    ]
    for value in ("nan", "inf")
] + [
    Case(
        "synthesize --output-depth-range with a NaN",
        (
            "synthesize",
            "synthesize_cam2.cfg",
            "-o",
            "o_256x192_yuv420p.yuv",
            "--output-depth",
            "d_256x192_yuv420p.yuv",
            "--output-depth-range",
            "2",
            "nan",
        ),
        2,
        r"'--output-depth-range': 'nan' is not a number",
        LINE_SYNTHESIS,
    ),
    Case(
        "colorcorrect --depth-range with a NaN",
        (
            "colorcorrect",
            "--view",
            "a",
            VIEW,
            "--view",
            "b",
            VIEW,
            "--depth-range",
            "nan",
            "13",
            "-o",
            "out",
        ),
        2,
        r"'--depth-range': 'nan' is not a number",
        copy_sample(VIEW),
    ),
]
