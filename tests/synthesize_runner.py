"""``mvtools synthesize`` run in-process, shared by the synthesis test files."""

from __future__ import annotations

import contextlib
from pathlib import Path

from click.testing import CliRunner

from mvtools.cli.main import cli


def run_synthesize(*args, cwd: Path):
    """Run ``mvtools synthesize ARGS`` in ``cwd``: (exit code, stdout, stderr).

    Exceptions other than the program's own exit propagate, so a crash is never
    mistaken for an exit code.
    """
    with contextlib.chdir(cwd):
        result = CliRunner().invoke(cli, ["synthesize", *map(str, args)])
    if result.exception is not None and not isinstance(result.exception, SystemExit):
        raise result.exception
    return result.exit_code, result.stdout, result.stderr
