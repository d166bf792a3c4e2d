"""Running the programs in tests, and the one-line error rule they are held to."""

from __future__ import annotations

import subprocess
import sys

import click
from click.testing import CliRunner


def run(*args, cwd=None):
    """``python -m mvtools ARGS`` in a new interpreter: (exit code, stdout, stderr)."""
    completed = subprocess.run(
        [sys.executable, "-m", "mvtools", *map(str, args)], capture_output=True, text=True, cwd=cwd
    )
    return completed.returncode, completed.stdout, completed.stderr


def invoke(command: click.Command, *args):
    """A program's command in-process (no interpreter start-up): (exit code, stdout,
    stderr). Exceptions other than the program's own exit propagate, so a crash is
    never mistaken for an exit code."""
    result = CliRunner().invoke(command, [str(arg) for arg in args])
    if result.exception is not None and not isinstance(result.exception, SystemExit):
        raise result.exception
    return result.exit_code, result.stdout, result.stderr


def assert_one_line_error(stderr: str, *fragments: str) -> None:
    """Exactly one error line, holding every fragment, and no traceback."""
    lines = [line for line in stderr.splitlines() if "error:" in line]
    assert len(lines) == 1, stderr
    assert "Traceback" not in stderr
    for fragment in fragments:
        assert fragment in lines[0], lines[0]
