"""The one way tests find the published test material in ``../shared/data``.

``MVTOOLS_DATA`` overrides the location. When the material is absent the test is
skipped with the reason, unless ``MVTOOLS_REQUIRE_DATA=1`` (set by ``.ci/run``), in
which case it fails: CI must never pass by skipping.
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest

REPO_ROOT = Path(__file__).resolve().parent.parent


def data_root() -> Path:
    return Path(os.environ.get("MVTOOLS_DATA", REPO_ROOT.parent / "shared" / "data"))


def shared_data(*parts: str) -> Path:
    """Path of a file or folder of the published material, or skip/fail the test."""
    path = data_root().joinpath(*parts)
    if not path.exists():
        reason = (
            f"published test material not found: {path} "
            "(set MVTOOLS_DATA to the folder holding middlebury/ and mpeg/)"
        )
        if os.environ.get("MVTOOLS_REQUIRE_DATA") == "1":
            pytest.fail(reason + "; MVTOOLS_REQUIRE_DATA=1 forbids skipping")
        pytest.skip(reason)
    return path
