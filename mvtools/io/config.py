"""Configuration files of VSRS and DERS, command-line overrides and file lookup.

Syntax, as the reference programs read it: one ``Key Value`` pair a line,
separated by spaces or tabs; ``#`` starts a comment; blank lines are skipped; keys
are case-sensitive. Where the reference programs misbehave this module does not:

- a line with more words than ``Key Value`` is an error naming the line (the
  reference silently stops reading the file there). A value that contains spaces,
  tabs or ``#`` is written in double quotes, ``"D:\\My videos\\left.yuv"``
  (the reference programs cannot read such a value in any form; none of the
  files shipped with them needs it);
- Windows line endings leave no carriage return in values;
- a key given twice is warned about (the last one wins, as in the reference);
- unknown keys are warned about with the nearest known key.

Values keep the text of the file; :func:`load_params` converts and validates them
into :class:`mvtools.params.VsrsParams` or :class:`mvtools.params.DersParams` and
returns beside them where each came from, so later errors can name file, line and key
(:meth:`mvtools.io.loaded_config.LoadedConfig.entry`).
"""

from __future__ import annotations

import difflib
import logging
import os
import re
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path, PureWindowsPath
from typing import Any, TypeVar

import mvtools
from mvtools.errors import ConfigError, UsageError
from mvtools.io.atomic import atomic_output, output_folder_exists
from mvtools.io.files import read_text
from mvtools.params import (
    DersParams,
    ParamError,
    ParamSpec,
    VsrsParams,
    format_value,
    param_specs,
)

logger = logging.getLogger(__name__)

#: ``ConfigEntry.path`` of values given on the command line.
COMMAND_LINE = "<command line>"
#: ``ConfigEntry.path`` of default values (see
#: :meth:`mvtools.io.loaded_config.LoadedConfig.entry`).
DEFAULT = "<default>"

P = TypeVar("P")


@dataclass(frozen=True)
class ConfigEntry:
    """One ``Key Value`` setting and where it was given.

    Attributes
    ----------
    key : str
        The key as written.
    value : str
        The value's text (quotes removed); ``""`` when the line has no value.
    path : str
        The configuration file as it was named, or :data:`COMMAND_LINE`, or :data:`DEFAULT`.
    line : int or None
        1-based line number in ``path``; None for the command line and defaults.
    """

    key: str
    value: str
    path: str
    line: int | None

    @property
    def folder(self) -> Path | None:
        """Absolute folder of the configuration file; None when not from a file."""
        if self.path in (COMMAND_LINE, DEFAULT):
            return None
        return Path(self.path).absolute().parent

    @property
    def place(self) -> str:
        """``path:line`` (or just ``path``), for messages."""
        return self.path if self.line is None else f"{self.path}:{self.line}"

    def error(self, message: str, cls: type[UsageError] = ConfigError) -> UsageError:
        """An error located at this entry's file, line and key."""
        return cls(message, path=self.path, line=self.line, key=self.key)


# A value is one word, or double quotes around anything but a double quote. The
# closing quote must end the word so that `"a"b` is not silently read as `a`.
_WORD = re.compile(r'"(?P<quoted>[^"]*)"(?=[\s#]|$)|(?P<bare>[^\s#"][^\s#]*)')
_SPACE = re.compile(r"\s*")


def _split_words(text: str, path: str, line: int) -> list[str]:
    """The words of one line before its comment."""
    words: list[str] = []
    position = _SPACE.match(text).end()
    while position < len(text) and text[position] != "#":
        match = _WORD.match(text, position)
        if match is None:
            raise ConfigError(f"unbalanced double quote in {text.strip()!r}", path=path, line=line)
        quoted = match.group("quoted")
        words.append(quoted if quoted is not None else match.group("bare"))
        position = _SPACE.match(text, match.end()).end()
    return words


def read_config(path: str | os.PathLike) -> dict[str, ConfigEntry]:
    """Read a VSRS/DERS configuration file.

    Parameters
    ----------
    path : str or path-like
        The configuration file.

    Returns
    -------
    dict of str to ConfigEntry
        By key, in the order of the file. A key given twice is warned about and
        the last one wins.

    Raises
    ------
    UsageError
        The file does not exist or cannot be read.
    ConfigError
        A line holds more than ``Key Value``, or an unbalanced double quote.
    """
    name = os.fspath(path)
    entries: dict[str, ConfigEntry] = {}
    # Split on "\n" only: a stray "\r" is whitespace to _split_words, so CRLF
    # files leave no carriage return in a value.
    for number, text in enumerate(read_text(path, "configuration file").split("\n"), start=1):
        words = _split_words(text, name, number)
        if not words:
            continue
        if len(words) > 2:
            raise ConfigError(
                f"{len(words)} words before the comment, expected 'Key Value'; "
                "write a value that holds spaces in double quotes",
                path=name,
                line=number,
                key=words[0],
            )
        key = words[0]
        if not key:
            raise ConfigError("empty key", path=name, line=number)
        entry = ConfigEntry(key, words[1] if len(words) == 2 else "", name, number)
        _remember(entries, entry)
    return entries


def read_htm_config(path: str | os.PathLike) -> dict[str, ConfigEntry]:
    """Read a 3D-HTM encoder configuration (``Key : Value ...  # comment`` lines).

    The HTM reference encoder's syntax: the key, a colon, then a value that may hold
    several words (GOP structure lines such as ``Frame1 : B 8 1 0.442 ...``); ``#``
    starts a comment. mvtools reads these files to inspect them (frame size, number
    of views, bit depths), the values stay text.

    Raises
    ------
    ConfigError
        A line with words but no ``:`` after its key.
    """
    name = os.fspath(path)
    entries: dict[str, ConfigEntry] = {}
    for number, text in enumerate(read_text(path, "HTM configuration file").split("\n"), start=1):
        text = text.split("#", 1)[0].strip()
        if not text:
            continue
        key, colon, value = text.partition(":")
        if not colon or not key.strip():
            raise ConfigError(f"expected 'Key : Value', got {text!r}", path=name, line=number)
        _remember(entries, ConfigEntry(key.strip(), " ".join(value.split()), name, number))
    return entries


def _remember(entries: dict[str, ConfigEntry], entry: ConfigEntry) -> None:
    """Add ``entry``; warn when it replaces one from the same source."""
    previous = entries.get(entry.key)
    if previous is not None:
        where = f"on lines {previous.line} and {entry.line}" if entry.line is not None else "twice"
        logger.warning(
            "%s: %s given %s; the last one (%r) wins", entry.place, entry.key, where, entry.value
        )
    entries[entry.key] = entry


def parse_overrides(args: Iterable[str]) -> dict[str, ConfigEntry]:
    """Read command-line settings ``Key=Value`` as the reference programs take them.

    Apply them after the file: ``entries.update(parse_overrides(args))``.

    Parameters
    ----------
    args : iterable of str
        Items such as ``"Precision=4"``; ``"Key="`` gives an empty value.

    Returns
    -------
    dict of str to ConfigEntry
        By key, with ``path`` :data:`COMMAND_LINE` and ``line`` None.

    Raises
    ------
    UsageError
        An item without ``=`` or without a key.
    """
    entries: dict[str, ConfigEntry] = {}
    for item in args:
        key, sep, value = item.partition("=")
        key = key.strip()
        if not sep or not key or re.search(r"[\s#\"]", key):
            raise UsageError(f"malformed setting {item!r}, expected Key=Value", path=COMMAND_LINE)
        _remember(entries, ConfigEntry(key, value.strip(), COMMAND_LINE, None))
    return entries


def override_entries(cls: type, values: Mapping[str, Any]) -> dict[str, ConfigEntry]:
    """Command-line entries for typed option values, by field name.

    For a command-line program whose options are derived from
    :func:`mvtools.params.param_specs`: ``entries.update(override_entries(cls, options))``
    then :func:`load_params`, so options, ``Key=Value`` items and the file all go
    through the same conversion and validation. ``None`` means "not given".

    Raises
    ------
    KeyError
        A name that is not a field of ``cls`` (a programming error).
    """
    specs = {spec.name: spec for spec in param_specs(cls)}
    return {
        specs[name].key: ConfigEntry(specs[name].key, format_value(value), COMMAND_LINE, None)
        for name, value in values.items()
        if value is not None
    }


_INTEGER = re.compile(r"[+-]?\d+")
_NUMBER = re.compile(r"[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?")


def _convert(entry: ConfigEntry, spec: ParamSpec) -> Any:
    """The typed value of an entry (ranges are checked by the parameter class)."""
    if spec.type is int:
        if not _INTEGER.fullmatch(entry.value):
            raise entry.error(f"{entry.value!r} is not an integer")
        return int(entry.value)
    if spec.type is float:
        if not _NUMBER.fullmatch(entry.value):
            raise entry.error(f"{entry.value!r} is not a number")
        return float(entry.value)
    return entry.value


def load_params(
    cls: type[P], entries: Mapping[str, ConfigEntry]
) -> tuple[P, dict[str, ConfigEntry]]:
    """Typed, validated parameters from configuration entries.

    Parameters
    ----------
    cls : type
        :class:`mvtools.params.VsrsParams` or :class:`mvtools.params.DersParams`.
    entries : mapping of str to ConfigEntry
        From :func:`read_config`, updated with :func:`parse_overrides`.

    Returns
    -------
    params : cls
        Keys absent from ``entries`` take their defaults. Unknown keys are logged
        as warnings with the nearest known key, and ignored.
    sources : dict of str to ConfigEntry
        Field name -> the entry that gave its value; fields absent take their
        defaults. :class:`mvtools.io.loaded_config.LoadedConfig` keeps it to name
        the file, line and key of a value that later proves wrong.

    Raises
    ------
    ConfigError
        A value that is not of the key's type, out of its range, or inconsistent
        with another; the message names the file, line and key.
    """
    specs = {spec.key: spec for spec in param_specs(cls)}
    _check_program(cls, entries)
    values: dict[str, Any] = {}
    sources: dict[str, ConfigEntry] = {}
    for key, entry in entries.items():
        spec = specs.get(key)
        if spec is None:
            nearest = difflib.get_close_matches(key, list(specs), n=1)
            hint = f" (did you mean {nearest[0]!r}?)" if nearest else ""
            logger.warning("%s: unknown key %r%s, ignored", entry.place, key, hint)
            continue
        values[spec.name] = _convert(entry, spec)
        sources[spec.name] = entry
        logger.debug("%s: %s = %s", entry.place, key, format_value(values[spec.name]))
    try:
        params = cls(**values)
    except ParamError as err:
        # Point at the first key involved that an entry gave; defaults have no line.
        given = [entries[key] for key in err.keys if key in entries]
        if given:
            raise given[0].error(err.message) from None
        raise ConfigError(err.message, key=err.key) from None
    return params, sources


#: Keys of their own that make a file the other program's configuration (at least this
#: many, and more than keys of the program reading it): 20 "unknown key" warnings would
#: say it less clearly.
OTHER_PROGRAM_KEYS = 3


def _check_program(cls: type, entries: Mapping[str, ConfigEntry]) -> None:
    """A ConfigError if ``entries`` are another program's configuration (DERS's given to
    VSRS's reader or the reverse), naming the file and some of its keys."""
    own = {spec.key for spec in param_specs(cls)}
    for other in (VsrsParams, DersParams):
        if other is cls:
            continue
        theirs = {spec.key for spec in param_specs(other)}
        only_theirs = [entry for key, entry in entries.items() if key in theirs - own]
        only_own = [key for key in entries if key in own - theirs]
        if len(only_theirs) >= OTHER_PROGRAM_KEYS and len(only_theirs) > len(only_own):
            shown = ", ".join(entry.key for entry in only_theirs[:3])
            raise ConfigError(
                f"this is a {other.program} configuration ({shown}, ...), not a {cls.program} one",
                path=only_theirs[0].path,
            )


def _split_path(value: str) -> tuple[Path | None, tuple[str, ...]]:
    """A configuration path as (native path or None, components after the anchor).

    Both separators are accepted. A Windows drive or UNC path has no native form
    off Windows (None); its components still serve for the lookup of tails.
    """
    windows = PureWindowsPath(value)
    parts = windows.parts[1:] if windows.anchor else windows.parts
    if windows.drive and os.name != "nt":
        return None, parts
    if windows.anchor:
        return Path(windows.anchor.replace("\\", "/")).joinpath(*parts), parts
    return Path(*parts), parts


def resolve_input_path(
    entry: ConfigEntry, *, data_dirs: Iterable[str | os.PathLike] = (), must_exist: bool = True
) -> Path:
    """Find the file an input entry names.

    Places tried, in order (the first existing file wins):

    1. the path itself, relative to the current folder as the reference programs
       read it (backslashes are separators; a Windows drive path is skipped off
       Windows);
    2. under the configuration file's folder, then under each of ``data_dirs``:
       the path, then its tails (leading components dropped one at a time, down to
       the bare file name), so that ``..\\data\\kendo\\kendo_ori_I_1.yuv`` or
       ``I:\\FTV\\Book_arrival\\BookArrival_7.yuv`` are found once the folder
       holding them is given.

    Parameters
    ----------
    entry : ConfigEntry
        The setting, from a file, the command line or
        :meth:`mvtools.io.loaded_config.LoadedConfig.entry`.
    data_dirs : iterable of path-like
        Further folders to search (a program's ``--data-dir``).
    must_exist : bool
        If False, return the first place tried when none exists.

    Returns
    -------
    Path
        Absolute path of the file; ``-`` (standard input) for the value ``-``.

    Raises
    ------
    UsageError
        Empty value, or no file found; the message lists every place tried.
    """
    if not entry.value:
        raise entry.error("no file name given", UsageError)
    if entry.value == "-":
        return Path("-")  # standard input: a Y4M stream (mvtools.io.yuv.STANDARD_STREAM)
    native, parts = _split_path(entry.value)
    candidates: list[Path] = []
    if native is not None:
        candidates.append(native.absolute())
    folders = [entry.folder] if entry.folder is not None else []
    folders += [Path(folder).absolute() for folder in data_dirs]
    for folder in folders:
        candidates += [folder.joinpath(*parts[start:]) for start in range(len(parts))]
    candidates = list(dict.fromkeys(candidates))
    for candidate in candidates:
        if candidate.is_file():
            return candidate
    if not must_exist and candidates:
        return candidates[0]
    places = f"{len(candidates)} place{'s' if len(candidates) != 1 else ''}"
    tried = ", ".join(str(candidate) for candidate in candidates)
    raise entry.error(
        f"file '{entry.value}' not found (tried {places}: {tried}); "
        "give the folder holding it with --data-dir",
        UsageError,
    )


def resolve_output_path(entry: ConfigEntry) -> Path:
    """The file an output entry names, relative to the current folder.

    Backslashes are separators. The folder must exist; a Windows drive path is
    refused off Windows.

    Raises
    ------
    UsageError
        Empty value, a drive path off Windows, or a missing folder.
    """
    if not entry.value:
        raise entry.error("no output file name given", UsageError)
    native, _ = _split_path(entry.value)
    if native is None:
        raise entry.error(
            f"{entry.value!r} is a Windows drive path; give an output path on this system",
            UsageError,
        )
    try:
        output_folder_exists(native.parent)
    except UsageError as error:
        raise entry.error(str(error), UsageError) from None
    return native


def _value_text(spec: ParamSpec, value: Any) -> str:
    """The value as written in a file: quoted when it holds spaces or ``#``."""
    text = format_value(value)
    if text == "" or not re.search(r'[\s#]|^"', text):
        return text
    if '"' in text or "\n" in text or "\r" in text:
        raise UsageError(f"{text!r} cannot be written in a configuration file", key=spec.key)
    return f'"{text}"'


def write_config(path: str | os.PathLike, params: Any) -> None:
    """Write every parameter as a configuration file the reference programs read.

    One aligned ``Key Value # meaning`` line per key, in the order of the
    reference programs; an empty value leaves the key alone, which they read as
    empty. :func:`read_config` and :func:`load_params` give ``params`` back.

    Parameters
    ----------
    path : str or path-like
        Output file, written atomically, UTF-8 with ``\\n`` line ends.
    params : VsrsParams or DersParams
    """
    specs = param_specs(type(params))
    texts = [_value_text(spec, getattr(params, spec.name)) for spec in specs]
    key_width = max(len(spec.key) for spec in specs)
    value_width = max(len(text) for text in texts)
    lines = [f"# {params.program} configuration written by mvtools {mvtools.__version__}"]
    lines += [
        f"{spec.key:<{key_width}}  {text:<{value_width}}  # {spec.help}"
        for spec, text in zip(specs, texts)
    ]
    with atomic_output(path, "wb") as handle:
        handle.write(("\n".join(lines) + "\n").encode("utf-8"))
