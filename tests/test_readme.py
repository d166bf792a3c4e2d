"""Every example of the README runs as written (issue 18).

The README's ``sh`` and ``python`` code blocks are read from README.md, in order, and each
command (a shell line with its continuation lines; a whole python block) runs in a
subprocess with the installed programs first on ``PATH``, in that order, each within
``SECONDS_PER_EXAMPLE``. The examples are written to run from the repository root after
``make demo`` and to write under ``build/``. Here they run from a stand-in for the
repository root in a temporary folder: its ``sample_data`` and ``configs`` are links to the
repository's, its ``build/demo`` and ``build/published`` links to the repository's outputs
of ``make demo`` and ``make published``, its ``../shared/data`` a link to the published
material (``tests/shared_data.py``), so that the examples' outputs land in the temporary
folder.

An example that reads the demo's outputs first runs ``make demo`` in the repository when
the demo has not run (CI runs it before the tests); one that reads a file of
``make published`` first has ``make`` bring that file up to date. An example that names
published material is skipped when the material is absent, or fails under
``MVTOOLS_REQUIRE_DATA=1``. A python block written as an interactive session (``>>>``)
runs as a doctest, its printed results checked. A block whose last line before the opening
fence is ``<!-- readme-test: skip (reason) -->`` is not run: the few examples that take minutes, need material nobody ships, or are the
test suite itself.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import pytest
from shared_data import REPO_ROOT, data_root, shared_data

pytestmark = pytest.mark.slow  # `make test-fast` leaves these out

README = REPO_ROOT / "README.md"
SECONDS_PER_EXAMPLE = 60
FENCE = re.compile(r"^```(\w*)\s*$")
SKIP = re.compile(r"^<!--\s*readme-test:\s*skip\s*\((.+)\)\s*-->$")
ASSIGNMENT = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*=\S*$")
PUBLISHED = re.compile(r"\.\./shared/data/([^\s\"'$]*)")
DOCTEST_PROMPT = re.compile(r"^>>> ", re.MULTILINE)
MADE = re.compile(r"\bbuild/(demo|published)/([^\s\"'$*?\[{]*)")
# what calls the encoders: the encode program, and any program writing an MP4
ENCODED = re.compile(r"\bmvtools encode\b|\.mp4\b")
# the demo's last output: the demo has run when it is there
DEMO_DONE = REPO_ROOT / "build" / "demo" / "report.html"
# the repository's inputs the examples read, linked into the stand-in root
LINKED = ("sample_data", "configs")


@dataclass(frozen=True)
class Example:
    """One command of the README: where it starts, its language, its text."""

    line: int
    language: str
    # assignments earlier in the same shell block (``L=sample_data/line``)
    prelude: str
    text: str
    skip_reason: str | None

    @property
    def name(self) -> str:
        first = self.text.splitlines()[0]
        return f"README.md:{self.line} {first[:60]}"


def shell_commands(lines: list[tuple[int, str]]):
    """The commands of a shell block as (line, text): continuation lines joined,
    comment lines dropped."""
    command: list[str] = []
    start = 0
    for number, line in lines:
        if not command:
            if not line.strip() or line.lstrip().startswith("#"):
                continue
            start = number
        command.append(line)
        if not line.rstrip().endswith("\\"):
            yield start, "\n".join(command)
            command = []
    if command:
        yield start, "\n".join(command)


def readme_examples(text: str) -> list[Example]:
    """Every example of the README's ``sh`` and ``python`` blocks, in order."""
    examples: list[Example] = []
    language = None
    skip_reason = None
    block: list[tuple[int, str]] = []
    previous = ""
    for number, line in enumerate(text.splitlines(), start=1):
        fence = FENCE.match(line)
        if language is None:
            if fence:
                language = fence.group(1)
                block = []
                marker = SKIP.match(previous.strip())
                skip_reason = marker.group(1) if marker else None
            elif line.strip():
                previous = line
            continue
        if not fence:
            block.append((number, line))
            continue
        if language == "python":
            examples.append(
                Example(block[0][0], "python", "", "\n".join(t for _, t in block), skip_reason)
            )
        elif language == "sh":
            prelude: list[str] = []
            for start, command in shell_commands(block):
                if ASSIGNMENT.match(command):
                    prelude.append(command)
                else:
                    examples.append(Example(start, "sh", "\n".join(prelude), command, skip_reason))
        language = None
        previous = ""
    return examples


EXAMPLES = readme_examples(README.read_text())


HAND_WRITTEN = """\
Text.

```sh
L=sample_data/line
# a comment
mvtools inspect $L/cameras.txt \\
    $L/synthesize_cam2.cfg
mvtools bitrate --views 9
```

<!-- readme-test: skip (too long) -->
```python
import mvtools
```

```
not an example
```
"""


def test_examples_are_read_with_their_assignments_continuations_and_skips():
    inspect, bitrate, python = readme_examples(HAND_WRITTEN)
    assert inspect == Example(
        6,
        "sh",
        "L=sample_data/line",
        "mvtools inspect $L/cameras.txt \\\n    $L/synthesize_cam2.cfg",
        None,
    )
    assert (bitrate.line, bitrate.prelude, bitrate.text) == (
        8,
        "L=sample_data/line",
        "mvtools bitrate --views 9",
    )
    assert python == Example(13, "python", "", "import mvtools", "too long")


def test_the_readme_has_its_examples():
    """The parser finds the README's examples: a change that hid them would pass silently."""
    commands = [example.text.split()[0] for example in EXAMPLES if example.language == "sh"]
    assert len(commands) >= 30
    assert {"make", "mvtools"} <= set(commands)


@pytest.fixture(scope="module")
def stand_in_root(tmp_path_factory) -> Path:
    """A folder that looks like the repository root after ``make demo``, outputs apart."""
    top = tmp_path_factory.mktemp("readme")
    root = top / "repo"
    (root / "build").mkdir(parents=True)
    for name in LINKED:
        (root / name).symlink_to(REPO_ROOT / name)
    for made in ("demo", "published"):
        (root / "build" / made).symlink_to(REPO_ROOT / "build" / made)
    (top / "shared").mkdir()
    (top / "shared" / "data").symlink_to(data_root())
    return root


def environment() -> dict[str, str]:
    env = dict(os.environ)
    env["PATH"] = f"{Path(sys.executable).parent}{os.pathsep}{env.get('PATH', '')}"
    return env


def make(*targets: str) -> None:
    made = subprocess.run(
        ["make", "--no-print-directory", "-s", *targets, f"DATA={data_root()}"],
        cwd=REPO_ROOT,
        capture_output=True,
        text=True,
    )
    assert made.returncode == 0, f"make {' '.join(targets)} failed:\n{made.stderr[-2000:]}"


def bring_made_inputs_up_to_date(example: Example) -> None:
    """Run ``make demo`` when the example reads the demo's outputs and the demo has not
    run; have ``make`` bring up to date the files of ``make published`` it reads."""
    named = MADE.findall(example.prelude + "\n" + example.text)
    if any(target == "demo" for target, _ in named) and not DEMO_DONE.exists():
        make("demo")
    published = sorted(
        {f"build/published/{path}" for target, path in named if target == "published"}
    )
    if published:
        make(*published)


@pytest.mark.parametrize("example", EXAMPLES, ids=[example.name for example in EXAMPLES])
def test_readme_example_runs(example: Example, stand_in_root: Path):
    if example.skip_reason:
        pytest.skip(example.skip_reason)
    if ENCODED.search(example.text):
        missing = [program for program in ("x265", "ffmpeg") if shutil.which(program) is None]
        if missing:
            pytest.skip(f"{' and '.join(missing)} not installed (.ci/run installs them)")
    for path in PUBLISHED.findall(example.prelude + "\n" + example.text):
        # the folders before a glob, or the whole path
        fixed, *globbed = re.split(r"[*?\[{]", path)
        parts = [part for part in fixed.split("/") if part]
        shared_data(*(parts[:-1] if globbed else parts))
    bring_made_inputs_up_to_date(example)
    if example.language == "python" and DOCTEST_PROMPT.search(example.text):
        # an interactive session: its printed results are checked too
        session = stand_in_root / f"readme_line{example.line}.txt"
        session.write_text(example.text + "\n")
        command = [sys.executable, "-m", "doctest", str(session)]
    elif example.language == "python":
        command = [sys.executable, "-c", example.text]
    else:
        script = "set -euo pipefail\n" + example.prelude + "\n" + example.text
        command = ["bash", "-c", script]
    try:
        run = subprocess.run(
            command,
            cwd=stand_in_root,
            env=environment(),
            capture_output=True,
            text=True,
            timeout=SECONDS_PER_EXAMPLE,
        )
    except subprocess.TimeoutExpired:
        pytest.fail(f"{example.name}: still running after {SECONDS_PER_EXAMPLE} s")
    assert run.returncode == 0, (
        f"{example.name} exited {run.returncode}:\n{example.text}\n{run.stderr[-3000:]}"
    )
