"""Lazy exports of a package: a name is imported from its module on first use.

A package's ``__init__`` lists what it exports and where each name lives, and
:func:`attach` gives it the module-level ``__getattr__`` and ``__dir__`` (PEP 562)
that import the defining module when the name is first asked for. ``import
mvtools.synthesis`` thus costs nothing until a function is used, so a program's
``--help`` does not load numba, OpenCV or SciPy.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Iterable, Mapping


def attach(
    package: str, exports: Mapping[str, str], *, eager: Iterable[str] = ()
) -> tuple[Callable[[str], object], Callable[[], list[str]], list[str]]:
    """``__getattr__``, ``__dir__`` and ``__all__`` of a package that exports lazily.

    Parameters
    ----------
    package : str
        The package's ``__name__``.
    exports : mapping of str to str
        Each exported name and the module of the package that defines it.
    eager : iterable of str, keyword-only
        Names the package binds itself (listed in ``__all__`` too).

    Returns
    -------
    tuple
        ``(__getattr__, __dir__, __all__)``, to assign at the package's top level.

    Examples
    --------
    >>> from mvtools.lazy import attach
    >>> getattr_, dir_, all_ = attach("mvtools.geometry", {"Camera": "camera"})
    >>> all_
    ['Camera']
    >>> getattr_("Camera").__module__
    'mvtools.geometry.camera'
    """
    names = sorted([*exports, *eager])

    def __getattr__(name: str) -> object:
        if name not in exports:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        return getattr(importlib.import_module(f"{package}.{exports[name]}"), name)

    def __dir__() -> list[str]:
        return names

    return __getattr__, __dir__, names
