"""The umbrella program ``mvtools`` and the separate executables mvtools-PROGRAM."""

from __future__ import annotations

import click

from mvtools import __version__
from mvtools.cli import (bitrate, calibrate, colorcorrect, convert, encode, estimate_depth,
                         evaluate, inspect, pack, rectify, report, scene, synthesize)

PROGRAMS: dict[str, click.Command] = {
    "evaluate": evaluate.command,
    "convert": convert.command,
    "inspect": inspect.command,
    "scene": scene.command,
    "synthesize": synthesize.command,
    "estimate-depth": estimate_depth.command,
    "calibrate": calibrate.command,
    "rectify": rectify.command,
    "colorcorrect": colorcorrect.command,
    "pack": pack.command,
    "encode": encode.command,
    "bitrate": bitrate.command,
    "report": report.command,
}


@click.group(commands=PROGRAMS, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="mvtools")
def cli():
    """Multiview video tools: calibration, rectification, colour correction, depth
    estimation, view synthesis, packing, evaluation and conversion.

    Reads MPEG camera parameter files and VSRS/DERS configuration files unmodified and
    exchanges raw YUV files. Each program is also installed as mvtools-PROGRAM.
    """


def _standalone(name: str):
    def main():
        PROGRAMS[name].main(prog_name=f"mvtools-{name}",
                            help_option_names=["-h", "--help"])

    main.__name__ = f"{name.replace('-', '_')}_cli"
    return main


calibrate_cli = _standalone("calibrate")
rectify_cli = _standalone("rectify")
colorcorrect_cli = _standalone("colorcorrect")
encode_cli = _standalone("encode")
bitrate_cli = _standalone("bitrate")
report_cli = _standalone("report")
estimate_depth_cli = _standalone("estimate-depth")
synthesize_cli = _standalone("synthesize")
pack_cli = _standalone("pack")
evaluate_cli = _standalone("evaluate")
convert_cli = _standalone("convert")
inspect_cli = _standalone("inspect")
scene_cli = _standalone("scene")
