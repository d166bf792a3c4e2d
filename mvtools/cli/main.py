"""The umbrella program ``mvtools`` and the separate executables mvtools-PROGRAM."""

from __future__ import annotations

import importlib

import click

from mvtools import __version__

#: Each program's module under mvtools.cli. A program's module is imported when the
#: program runs (or its help is asked for): a call of one program does not pay for the
#: imports of the others (OpenCV, SciPy, the numba kernels), about a second a call.
PROGRAMS: dict[str, str] = {
    "evaluate": "evaluate",
    "convert": "convert",
    "inspect": "inspect",
    "scene": "scene",
    "synthesize": "synthesize",
    "estimate-depth": "estimate_depth",
    "calibrate": "calibrate",
    "rectify": "rectify",
    "colorcorrect": "colorcorrect",
    "pack": "pack",
    "encode": "encode",
    "bitrate": "bitrate",
    "report": "report",
    "pointcloud": "pointcloud",
    "navigate": "navigate",
    "run": "run",
}


def program_command(name: str) -> click.Command:
    """The click command of program ``name`` (a key of :data:`PROGRAMS`)."""
    return importlib.import_module(f"mvtools.cli.{PROGRAMS[name]}").command


class _ProgramGroup(click.Group):
    """The umbrella command, which imports a program's module only when it is called."""

    def list_commands(self, ctx):
        return list(PROGRAMS)

    def get_command(self, ctx, name):
        return program_command(name) if name in PROGRAMS else None


@click.group(cls=_ProgramGroup, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="mvtools")
def cli():
    """Multiview video tools: calibration, rectification, colour correction, depth
    estimation, view synthesis, packing, evaluation and conversion.

    Reads MPEG camera parameter files and VSRS/DERS configuration files unmodified and
    exchanges raw YUV files. Each program is also installed as mvtools-PROGRAM.
    """


def _standalone(name: str):
    def main():
        program_command(name).main(prog_name=f"mvtools-{name}", help_option_names=["-h", "--help"])

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
pointcloud_cli = _standalone("pointcloud")
navigate_cli = _standalone("navigate")
run_cli = _standalone("run")
