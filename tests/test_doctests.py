"""The Examples of the public API's docstrings run as written and print what they show.

Every module of the package whose docstrings hold an interactive example (``>>>``) is
collected; doctest compares each printed result with the one written in the docstring,
so an Example that drifts from the code fails here.
"""

from __future__ import annotations

import doctest
import importlib
import pkgutil
from pathlib import Path

import numpy as np
import pytest

import mvtools

#: Modules not imported for collection: the command-line layer holds no Examples.
_SKIPPED_PACKAGES = ("mvtools.cli",)


def _modules_with_examples() -> list[str]:
    names = []
    for info in pkgutil.walk_packages(mvtools.__path__, prefix="mvtools."):
        if info.name.startswith(_SKIPPED_PACKAGES) or info.name == "mvtools.__main__":
            continue
        spec = importlib.util.find_spec(info.name)
        if spec and spec.origin and ">>> " in Path(spec.origin).read_text(encoding="utf-8"):
            names.append(info.name)
    return names


MODULES = _modules_with_examples()


def test_the_public_packages_have_examples():
    # the packages a Python user starts from document themselves by example
    assert {"mvtools.io", "mvtools.geometry.depth", "mvtools.lazy"} <= set(MODULES)


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples_run(name: str):
    module = importlib.import_module(name)
    finder = doctest.DocTestFinder(exclude_empty=True)
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    tests = finder.find(module, name, extraglobs={"np": np})
    assert tests, f"{name} has '>>> ' but doctest found no example"
    for test in tests:
        runner.run(test)
    results = runner.summarize(verbose=False)
    assert results.failed == 0, f"{results.failed} of {results.attempted} examples of {name} failed"
