import ast
import functools
import sys
from pathlib import Path

import pytest

# The helpers beside the tests (shared_data) import as plain modules.
sys.path.insert(0, str(Path(__file__).resolve().parent))


@functools.cache
def _module_calls(path: str) -> tuple[dict[str, set[str]], set[str]]:
    """For each function of a test module, the names it calls or takes as arguments
    (fixtures), and the names of the module-level constants that call shared_data."""
    tree = ast.parse(Path(path).read_text())
    uses: dict[str, set[str]] = {}
    constants: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            names = {n.id for n in ast.walk(node) if isinstance(n, ast.Name)}
            names |= {a.arg for a in node.args.args}
            uses.setdefault(node.name, set()).update(names)
    for node in tree.body:
        if isinstance(node, ast.Assign) and any(
            isinstance(n, ast.Name) and n.id == "shared_data" for n in ast.walk(node.value)
        ):
            constants |= {t.id for t in node.targets if isinstance(t, ast.Name)}
    return uses, constants


def _reads_published_data(path: str, function: str) -> bool:
    uses, constants = _module_calls(path)
    seen, todo = set(), [function]
    while todo:
        name = todo.pop()
        if name in seen:
            continue
        seen.add(name)
        called = uses.get(name, set())
        if "shared_data" in called or called & constants:
            return True
        todo.extend(called & uses.keys())
    return False


def pytest_collection_modifyitems(items):
    """Mark ``data`` every test that reads the published material (``../shared/data``):
    its function, or a function or fixture of its module that it uses, calls
    :func:`shared_data.shared_data`. ``make test-fast`` leaves them out."""
    for item in items:
        function = getattr(item, "originalname", None) or item.name
        if item.path.suffix == ".py" and _reads_published_data(str(item.path), function):
            item.add_marker(pytest.mark.data)
