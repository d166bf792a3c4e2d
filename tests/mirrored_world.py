"""A rig's world mirrored through its origin, the convention of the Poznan sequences.

``X -> -X`` moves every camera centre to ``-t`` and keeps the rotations: each camera
sees the same picture, and every depth along a camera axis changes sign, so the depth
ranges of such a rig are negative. Written here from the file format alone, so tests
of the programs do not lean on the code they test.
"""

from __future__ import annotations

from pathlib import Path

from mvtools.io.cameras import read_cameras


def write_mirrored_cameras(source: Path, target: Path) -> None:
    """The camera file ``source`` with every centre negated, written to ``target``."""
    blocks = []
    for camera in read_cameras(source).values():
        rows = [" ".join(f"{value:.17g}" for value in row) for row in camera.K]
        rows += ["0", "0"]
        rows += [
            " ".join(f"{value:.17g}" for value in (*camera.R[i], -camera.t[i])) for i in range(3)
        ]
        blocks.append(f"{camera.name}\n" + "\n".join(rows) + "\n")
    target.write_text("\n".join(blocks))
