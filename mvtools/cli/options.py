"""Options shared by every program, and the edge where errors become exit codes."""

from __future__ import annotations

import contextlib
import functools
import logging
import math
import os
import re
import signal
import sys
import threading
import time

import click

from mvtools import __version__
from mvtools.errors import MvtoolsError
from mvtools.io.abort import abort
from mvtools.io.guard import file_guard
from mvtools.kernels import announce_compilation
from mvtools.params import Kind, param_specs

LOG = logging.getLogger("mvtools")

#: The environment variable naming the file that finished programs add their time to.
TIME_LOG = "MVTOOLS_TIME_LOG"


def _set_log_level(ctx: click.Context, verbose: int, quiet: int) -> None:
    level = logging.INFO + 10 * (quiet - verbose)
    # Errors are always shown: -q can hide information and warnings, not failures.
    level = min(max(level, logging.DEBUG), logging.ERROR)
    handler = logging.StreamHandler(sys.stderr)
    program = ctx.command_path or "mvtools"
    handler.setFormatter(_ProgramFormatter(program))
    LOG.handlers[:] = [handler]
    LOG.setLevel(level)
    LOG.propagate = False


class _ProgramFormatter(logging.Formatter):
    """``mvtools-synthesize: warning: ...`` and ``...: debug: ...``; plain information
    carries no level word."""

    def __init__(self, program: str):
        super().__init__()
        self.program = program

    def format(self, record: logging.LogRecord) -> str:
        message = _cut_long_tokens(record.getMessage())
        if record.levelno >= logging.WARNING or record.levelno < logging.INFO:
            return f"{self.program}: {record.levelname.lower()}: {message}"
        return f"{self.program}: {message}"


def program(function):
    """Decorate a click callback: add -v/-q, and make it the one edge where failures
    become one-line messages and exit codes.

    - :class:`~mvtools.errors.MvtoolsError`: its ``exit_code`` (2 for usage and config
      errors, 1 for data errors); operating-system errors on files (permission, disk
      full): 1.
    - ``ValueError``: the algorithm layer's word for an argument it cannot use (a depth
      range, a threshold, a baseline the options gave it), so a usage error: 2.
    - SIGINT: 130; SIGTERM (what make, timeout, CI runners and schedulers send): 143. Both
      remove the temporary files of unfinished outputs and end the process at once.

    ``-v`` adds the traceback of a failure to the log, as debug detail. The run is one
    :func:`mvtools.io.guard.file_guard` scope: no output may name an input or another
    output.
    """

    @click.version_option(__version__, prog_name="mvtools")
    @click.option("-v", "--verbose", count=True, help="More messages on stderr (repeatable).")
    @click.option("-q", "--quiet", count=True, help="Fewer messages on stderr (repeatable).")
    @click.pass_context
    @functools.wraps(function)
    def wrapper(ctx: click.Context, verbose: int, quiet: int, **kwargs):
        _set_log_level(ctx, verbose, quiet)
        announce_compilation()
        LOG.debug(
            "mvtools %s, Python %s, numba threading layers %s, OMP_WAIT_POLICY %s",
            __version__,
            sys.version.split()[0],
            os.environ.get("NUMBA_THREADING_LAYER")
            or os.environ.get("NUMBA_THREADING_LAYER_PRIORITY"),
            os.environ.get("OMP_WAIT_POLICY"),
        )
        start = time.perf_counter()
        try:
            with _end_on_signals(), file_guard():
                result = function(**kwargs)
        except MvtoolsError as error:
            _fail(ctx, error, str(error), error.exit_code)
        except OSError as error:
            where = f"{error.filename}: " if error.filename else ""
            _fail(ctx, error, f"{where}{error.strerror or error}", 1)
        except ValueError as error:
            _fail(ctx, error, str(error), 2)
        _log_time(ctx, time.perf_counter() - start)
        LOG.debug("done in %.2f s", time.perf_counter() - start)
        return result

    return wrapper


#: The signals that end a run, and the word for each in its message.
ENDING_SIGNALS = {signal.SIGINT: "interrupted", signal.SIGTERM: "terminated"}


@contextlib.contextmanager
def _end_on_signals():
    """Within the block, SIGINT and SIGTERM end the process: the unfinished outputs' temporary
    files are removed and child programs killed (:func:`mvtools.io.abort.abort`), one line
    is logged, and the exit code is 128 + the signal's number, as shells report it.

    The process ends in the handler rather than by raising: the handler may run inside a
    callback from C code (numba compiling a kernel), where a raised exception is printed
    and ignored and the run would go on; and a half-built compiler object crashes the
    interpreter's clean-up (SIGSEGV) if the process unwinds from there.
    """
    if threading.current_thread() is not threading.main_thread():
        yield  # signals reach the main thread only; its caller handles them
        return

    def end(signum, frame):
        abort()
        LOG.error("%s: unfinished outputs were removed", ENDING_SIGNALS[signum])
        for stream in (sys.stdout, sys.stderr):
            with contextlib.suppress(Exception):
                stream.flush()
        os._exit(128 + signum)

    previous = {signum: signal.signal(signum, end) for signum in ENDING_SIGNALS}
    try:
        yield
    finally:
        for signum, handler in previous.items():
            signal.signal(signum, handler)


#: Longer runs of non-blank characters are cut in every message (a 10 MB token in a bad
#: file); file paths stay whole.
LONGEST_SHOWN = 256


def _fail(ctx: click.Context, error: BaseException, message: str, exit_code: int) -> None:
    LOG.debug("the failure in full:", exc_info=error)
    LOG.error("%s", message)
    ctx.exit(exit_code)


def _cut_long_tokens(message: str) -> str:
    def cut(match: re.Match) -> str:
        token = match.group(0)
        return f"{token[:60]}... ({len(token)} characters)"

    return re.sub(rf"\S{{{LONGEST_SHOWN + 1},}}", cut, message)


def _log_time(ctx: click.Context, seconds: float) -> None:
    """With ``MVTOOLS_TIME_LOG=FILE`` in the environment, a finished program appends a
    line ``seconds<TAB>program<TAB>its last argument`` (usually the output): a pipeline
    can then tell what each stage cost."""
    log = os.environ.get(TIME_LOG)
    if not log:
        return
    arguments = sys.argv[1:]
    with open(log, "a", encoding="utf-8") as handle:
        handle.write(f"{seconds:.2f}\t{ctx.command_path}\t{arguments[-1] if arguments else ''}\n")


class _OneLineUsageError(click.ClickException):
    """A command-line mistake shown as the one line every program error is."""

    exit_code = 2

    def __init__(self, program_name: str, message: str):
        super().__init__(message)
        self.program_name = program_name

    def show(self, file=None) -> None:
        click.echo(
            f"{self.program_name}: error: {self.format_message()} (--help lists the options)",
            err=True,
            file=file,
        )


class ProgramCommand(click.Command):
    """A program's command: unknown options, bad option values and missing arguments give
    one ``PROGRAM: error: ...`` line and exit code 2, as configuration errors do, instead
    of click's usage block."""

    def parse_args(self, ctx: click.Context, args: list[str]) -> list[str]:
        try:
            return super().parse_args(ctx, args)
        except click.UsageError as error:
            raise _OneLineUsageError(ctx.command_path, error.format_message()) from None


class FiniteFloat(click.FloatRange):
    """A float option, optionally in a range, that is finite: click's FloatRange lets NaN
    through every bound (every comparison with NaN is false) and ``inf`` through open
    upper ones. ``infinity=True`` admits +-inf (a Zfar at infinity), never NaN."""

    name = "float"

    def __init__(self, *args, infinity: bool = False, **kwargs):
        super().__init__(*args, **kwargs)
        self.infinity = infinity

    def convert(self, value, param, ctx):
        number = super().convert(value, param, ctx)
        if math.isnan(number) or (math.isinf(number) and not self.infinity):
            self.fail(
                f"{value!r} is not a {'number' if self.infinity else 'finite number'}", param, ctx
            )
        return number

    def _describe_range(self) -> str:
        return "" if self.min is None and self.max is None else super()._describe_range()


#: A finite float option.
FINITE = FiniteFloat()
#: A finite float option above 0.
POSITIVE = FiniteFloat(min=0, min_open=True)
#: A depth (Znear, Zfar): any number but NaN; Zfar may be infinite.
DEPTH = FiniteFloat(infinity=True)


data_dir_option = click.option(
    "--data-dir",
    "data_dirs",
    multiple=True,
    type=click.Path(file_okay=False, exists=True),
    help="Folder where relative input paths of the config file are also looked for "
    "(repeatable; after the current folder and the config file's folder).",
)

overrides_argument = click.argument("overrides", nargs=-1, metavar="[Key=Value]...")


def parse_size(ctx, param, value):
    if value is None:
        return None
    try:
        width, height = (int(part) for part in value.lower().split("x"))
    except ValueError:
        raise click.BadParameter(f"{value!r} is not WIDTHxHEIGHT (e.g. 1024x768)") from None
    if width < 1 or height < 1:
        raise click.BadParameter(f"{value!r}: width and height must be positive")
    return width, height


def video_format_options(function):
    """``--size WxH`` and ``--pix-fmt`` for raw YUV inputs (names and Y4M carry their own)."""
    function = click.option(
        "--pix-fmt",
        default=None,
        metavar="NAME",
        help="Pixel format of raw YUV inputs, ffmpeg names: yuv420p (default when only the "
        "size is given and the file size agrees), yuv420p10le, yuv444p, gray, gray16le...",
    )(function)
    return click.option(
        "--size",
        callback=parse_size,
        default=None,
        metavar="WxH",
        help="Picture size of raw YUV inputs whose name does not carry it (name_1024x768_yuv420p.yuv).",
    )(function)


def frame_range_options(function):
    """``--start-frame`` and ``--frames``, as VSRS's StartFrame and TotalNumberOfFrames."""
    function = click.option(
        "--frames",
        "frame_count",
        type=click.IntRange(min=1),
        default=None,
        help="Number of frames to process (default: all).",
    )(function)
    return click.option(
        "--start-frame",
        type=click.IntRange(min=0),
        default=0,
        show_default=True,
        help="First frame to process.",
    )(function)


def depth_range_option(name: str = "--depth-range", *, of: str = "the depth maps", default=None):
    """``--depth-range ZNEAR ZFAR``: the one spelling of a depth map's Znear and Zfar
    (``--output-depth-range``, ``--reference-depth-range`` where a program has two)."""
    return click.option(
        name,
        nargs=2,
        type=DEPTH,
        default=None,
        metavar="ZNEAR ZFAR",
        help=f"Znear (depth value 255) and Zfar (depth value 0) of {of}"
        + (f" (default: {default})." if default else "."),
    )


def _by_camera(what: str):
    """A click callback: ``NAME VIDEO`` pairs to a mapping, in order, each camera once."""

    def callback(ctx, param, pairs):
        by_camera: dict[str, str] = {}
        for name, video in pairs:
            if name in by_camera:
                raise click.BadParameter(f"{what} is given twice: camera {name}")
            by_camera[name] = video
        return by_camera

    return callback


def view_option(help: str, *, required: bool = False):
    """``--view NAME VIDEO`` (repeatable): the texture video of camera NAME, in every
    program that takes views; the program gets a mapping of camera name to video."""
    return click.option(
        "--view",
        "views",
        multiple=True,
        nargs=2,
        required=required,
        metavar="NAME VIDEO",
        callback=_by_camera("a view"),
        help=help,
    )


def depth_video_option(help: str):
    """``--depth NAME VIDEO`` (repeatable): the depth video of camera NAME, as a mapping."""
    return click.option(
        "--depth",
        "depths",
        multiple=True,
        nargs=2,
        metavar="NAME VIDEO",
        callback=_by_camera("a depth map"),
        help=help,
    )


transposed_rotation_option = click.option(
    "--transposed-rotation",
    is_flag=True,
    help="Camera parameter files store R transposed (camera to world), as VSRS 3.5 did.",
)


def param_options(params_class: type, secondary_names: dict[str, tuple[str, ...]] | None = None):
    """Decorator adding one option per key of a program's parameters: ``--search-level``
    for SearchLevel, ``--precision`` for Precision ...

    Every option defaults to None (not given), so that only the options on the command
    line override the configuration file and its ``Key=Value`` items.

    Parameters
    ----------
    params_class : type
        :class:`mvtools.params.VsrsParams` or :class:`mvtools.params.DersParams`.
    secondary_names : dict, optional
        Field name -> further option names (``{"total_number_of_frames": ("--frames",)}``).
    """
    secondary_names = secondary_names or {}

    def decorate(function):
        for spec in reversed(param_specs(params_class)):
            if spec.choices is not None:
                # as the command line spells them: SearchLevel 2, not 2.0
                kind = click.Choice(
                    [
                        f"{choice:g}" if isinstance(choice, float) else str(choice)
                        for choice in spec.choices
                    ]
                )
            else:
                kind = {int: int, float: float, str: str}[spec.type]
            metavar = "FILE" if spec.kind is not Kind.VALUE else None
            names = (f"--{spec.name.replace('_', '-')}", *secondary_names.get(spec.name, ()))
            function = click.option(
                *names,
                spec.name,
                type=kind,
                default=None,
                metavar=metavar,
                help=f"{spec.key}: {spec.help}.",
            )(function)
        return function

    return decorate
