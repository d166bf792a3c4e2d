"""Peak resident memory and CPU time of one program run, whatever the memory of the
process that starts it.

Linux hands a process started by (v)fork and exec a peak resident size (``ru_maxrss``) of
at least the peak of the memory it was started from: a program started by a test process
or by the benchmark runner, grown to 2 GB by earlier work, reports 2 GB, and two runs of
different lengths then look equally flat. Run through this file, a program is started by a
fresh interpreter that imports nothing beyond the standard library (about 10 MiB), which
writes the program's own figures, those of its descendants included, to a JSON report:

    python tests/process_peak.py REPORT [--limit-mib N] -- COMMAND ...

``--limit-mib`` stops the program once its resident size passes N MiB (the report says
so). The launcher exits with the program's exit code (128 + the signal when one ended it).
"""

from __future__ import annotations

import json
import os
import sys
import time
from dataclasses import dataclass
from pathlib import Path


@dataclass(frozen=True)
class Usage:
    """What one measured run used."""

    peak_mib: float
    cpu_seconds: float
    exit_code: int
    stopped: bool


def measured(command, report: Path, *, limit_mib: float | None = None) -> list[str]:
    """``command`` (a list of program and arguments) run through this file, its usage
    written to ``report`` (read it with :func:`read_usage`)."""
    limit = ["--limit-mib", str(limit_mib)] if limit_mib is not None else []
    return [sys.executable, __file__, str(report), *limit, "--", *map(str, command)]


def read_usage(report: Path) -> Usage:
    """The usage that a run of :func:`measured` wrote."""
    return Usage(**json.loads(Path(report).read_text()))


def _resident_mib(pid: int) -> float:
    # VmRSS of /proc/PID/status, 0 once the process is gone
    try:
        with open(f"/proc/{pid}/status") as status:
            for line in status:
                if line.startswith("VmRSS:"):
                    return int(line.split()[1]) / 1024
    except OSError:
        pass
    return 0.0


def _launch(arguments: list[str]) -> int:
    report, arguments = Path(arguments[0]), arguments[1:]
    limit_mib = None
    if arguments[:1] == ["--limit-mib"]:
        limit_mib, arguments = float(arguments[1]), arguments[2:]
    if arguments[:1] != ["--"] or len(arguments) < 2:
        raise SystemExit(f"usage: {__file__} REPORT [--limit-mib N] -- COMMAND ...")
    command = arguments[1:]
    # posix_spawn, not subprocess: the program starts from this small interpreter's memory
    pid = os.posix_spawnp(command[0], command, os.environ)
    stopped = False
    while True:
        done, status, usage = os.wait4(pid, 0 if limit_mib is None else os.WNOHANG)
        if done:
            break
        if not stopped and _resident_mib(pid) > limit_mib:
            os.kill(pid, 9)
            stopped = True
        time.sleep(0.1)
    code = os.waitstatus_to_exitcode(status)
    code = 128 - code if code < 0 else code
    # ru_maxrss: KiB on Linux, bytes on macOS
    peak_mib = usage.ru_maxrss / (2**20 if sys.platform == "darwin" else 2**10)
    figures = Usage(peak_mib, usage.ru_utime + usage.ru_stime, code, stopped)
    report.write_text(json.dumps(figures.__dict__))
    return code


if __name__ == "__main__":
    sys.exit(_launch(sys.argv[1:]))
