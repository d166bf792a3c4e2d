"""Programs whose implementation has not landed yet.

Each one already states its purpose in ``--help`` and accepts its future arguments, but
says that it is not implemented and exits with code 2. When a program lands, its own
module replaces its entry here.
"""

from __future__ import annotations

import click

from mvtools.cli.options import ProgramCommand, program
from mvtools.errors import UsageError

PLANNED = {
    "pack": (
        "Pack views into frame-compatible layouts and texture+depth atlases, unpack them, "
        "and run compression experiments with real encoders.", 7),
}


def planned_command(name: str) -> click.Command:
    purpose, issue = PLANNED[name]

    @click.command(name=name, cls=ProgramCommand,
                   help=f"{purpose}\n\nNot implemented yet (issue #{issue}).",
                   context_settings={"ignore_unknown_options": True})
    @click.argument("arguments", nargs=-1, type=click.UNPROCESSED)
    @program
    def command(arguments):
        raise UsageError(f"{name} is not implemented yet (issue #{issue})")

    return command
