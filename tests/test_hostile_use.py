"""The programs under careless and hostile use: the table of ``tests/hostile/``.

Every row runs in-process in an empty temporary working folder holding only the
row's inputs (see :mod:`hostile` for the rules each row is held to).
"""

from __future__ import annotations

import hashlib
import importlib
import pkgutil
import re

import hostile
import pytest
from program_runner import invoke

from mvtools.cli.main import cli

CASES = [
    case
    for module in pkgutil.iter_modules(hostile.__path__)
    for case in importlib.import_module(f"hostile.{module.name}").CASES
]


def _snapshot(folder):
    return {
        path.relative_to(folder).as_posix(): hashlib.sha256(path.read_bytes()).hexdigest()
        for path in folder.rglob("*")
        if path.is_file()
    }


@pytest.mark.parametrize("case", CASES, ids=[case.name for case in CASES])
def test_hostile_use(case, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    if case.files is not None:
        case.files(tmp_path)
    before = _snapshot(tmp_path)
    folders = _folders(tmp_path)
    code, _, err = invoke(cli, *case.args)
    assert code == case.exit_code, err
    assert "Traceback" not in err
    if case.exit_code != 0:
        lines = [line for line in err.splitlines() if "error:" in line]
        assert len(lines) == 1, err
        assert re.search(case.message, lines[0]), lines[0]
    after = _snapshot(tmp_path)
    changed = {name for name in before if after.get(name) != before[name]}
    assert changed <= set(case.outputs), f"inputs changed or lost: {sorted(changed)}"
    created = set(after) - set(before)
    assert created <= set(case.outputs), f"files left: {sorted(created)}"
    if case.exit_code != 0:
        assert not (changed | created), "a failed run wrote files"
        assert _folders(tmp_path) == folders, "a failed run left folders"


def _folders(folder):
    return {path for path in folder.rglob("*") if path.is_dir()}
