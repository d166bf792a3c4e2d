"""``mvtools run`` (issue 21): the sample chain as Dask tasks, on this process, a local
cluster, and a real scheduler with two worker processes (one of them killed mid-run):
every output the bytes of the programs run one after the other over whole videos."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from program_runner import run

pytestmark = pytest.mark.slow  # `make test-fast` leaves these out

ROOT = Path(__file__).resolve().parent.parent
PIPELINE = ROOT / "configs" / "sample_line_pipeline.toml"
LINE = ROOT / "sample_data" / "line"
VIDEOS = [f"v{i}_depth_256x192_yuv420p.yuv" for i in range(5)] + [
    f"v{i}_synthesized_256x192_yuv420p.yuv" for i in (1, 2, 3)
]
#: Seconds a test waits for a Dask process or a run before failing.
PATIENCE = 120


@pytest.fixture(scope="module")
def serial(tmp_path_factory) -> Path:
    """The chain as the programs make it, one run each over all frames: camera 2's
    depth from its DERS configuration as shipped, then every depth and view through
    the pipeline with one worker and whole videos; camera 2's depth must be the
    program's own."""
    folder = tmp_path_factory.mktemp("serial")
    code, _, err = run("run", PIPELINE, "-o", folder, "--workers", "1", "--chunk", "0", "-q")
    assert code == 0, err
    program = folder / "program_v2_depth_256x192_yuv420p.yuv"
    code, _, err = run("estimate-depth", LINE / "depth_cam2.cfg", "-o", program, "-q")
    assert code == 0, err
    assert program.read_bytes() == (folder / VIDEOS[2]).read_bytes()
    # camera 2 synthesized by the program from the estimated depth of cameras 1 and 3
    program = folder / "program_v2_synthesized_256x192_yuv420p.yuv"
    code, _, err = run(
        "synthesize",
        LINE / "synthesize_cam2.cfg",
        f"LeftDepthMapName={folder / VIDEOS[1]}",
        f"RightDepthMapName={folder / VIDEOS[3]}",
        "-o",
        program,
        "-q",
    )
    assert code == 0, err
    assert program.read_bytes() == (folder / VIDEOS[6]).read_bytes()
    return folder


def _same_outputs(folder: Path, serial: Path) -> None:
    for name in VIDEOS:
        assert (folder / name).read_bytes() == (serial / name).read_bytes(), name
    for index in (1, 2, 3):
        name = f"v{index}_synthesized.scores.json"
        assert (
            json.loads((folder / name).read_text())["mean"]
            == json.loads((serial / name).read_text())["mean"]
        )
    assert not list(folder.rglob("*.part"))


def test_a_local_cluster_in_chunks_of_one_frame_gives_the_serial_bytes(tmp_path, serial):
    code, _, err = run("run", PIPELINE, "-o", tmp_path, "--workers", "2", "--chunk", "1")
    assert code == 0, err
    _same_outputs(tmp_path, serial)
    # progress: tasks, frames, rate
    assert "tasks 40/40, frames: 24/24 done" in err


def test_a_second_run_makes_only_what_is_older_than_its_inputs(tmp_path, serial):
    arguments = ("run", PIPELINE, "-o", tmp_path, "--workers", "1", "--chunk", "2")
    code, _, err = run(*arguments)
    assert code == 0, err
    made = {path: path.stat().st_mtime_ns for path in tmp_path.rglob("*") if path.is_file()}
    code, _, err = run(*arguments)
    assert code == 0, err
    assert "32 tasks, 32 up to date" in err
    assert {path: path.stat().st_mtime_ns for path in made} == made
    # camera 4's depth made again: camera 3's synthesis reads it, and its score
    os.utime(tmp_path / VIDEOS[4], (0, 0))
    code, _, err = run(*arguments)
    assert code == 0, err
    # made again: the concatenation of its chunks, then camera 3's synthesis (two chunks
    # and their concatenation) and score
    assert "32 tasks, 27 up to date" in err
    _same_outputs(tmp_path, serial)


def _changed_pipeline(tmp_path: Path, old: str, new: str) -> Path:
    """The sample pipeline with ``old`` replaced by ``new``, in ``tmp_path``."""
    pipeline = tmp_path / "broken.toml"
    text = PIPELINE.read_text().replace('"../sample_data', f'"{ROOT}/sample_data')
    pipeline.write_text(text.replace(old, new))
    return pipeline


def test_a_failing_task_stops_the_run_with_its_one_line_error(tmp_path):
    pipeline = _changed_pipeline(tmp_path, '"cam4"]', '"cam9"]')
    out = tmp_path / "out"
    code, _, err = run("run", pipeline, "-o", out, "--workers", "1", "-q")
    assert code == 2
    assert err.count("\n") == 1 and "cam9" in err and "Traceback" not in err
    assert not [path for path in out.rglob("*") if path.name.endswith(".part")]


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ('views = ["a" "b"]\nchunk = 1\n', "broken.toml:2: "),
        ("views = []\n", "broken.toml: views: must be a list of camera names"),
        ("colour = 1\n", "broken.toml: colour: unknown key"),
    ],
)
def test_a_bad_pipeline_file_is_one_line_naming_file_line_and_key(tmp_path, text, message):
    pipeline = tmp_path / "broken.toml"
    pipeline.write_text('cameras = "c.txt"\n' + text)
    code, _, err = run("run", pipeline, "-o", tmp_path / "out")
    assert code == 2
    assert err.count("\n") == 1 and message in err, err


def test_an_output_template_must_name_each_camera_apart(tmp_path):
    pipeline = _changed_pipeline(tmp_path, 'output = "v{index}_depth', 'output = "depth')
    code, _, err = run("run", pipeline, "-o", tmp_path / "out")
    assert code == 2 and "estimate-depth.output" in err and "two cameras" in err


# --------------------------------------------------------------------------- a real cluster


class Cluster:
    """``dask scheduler`` and two ``dask worker`` processes on localhost, each worker
    a process of its own without a nanny (killed, it stays dead)."""

    def __init__(self, folder: Path):
        dask = Path(sys.executable).parent / "dask"
        scheduler_file = folder / "scheduler.json"
        logs = folder / "logs"
        logs.mkdir()
        self.processes: list[subprocess.Popen] = []
        self.processes.append(
            self._start(
                [dask, "scheduler", "--host", "127.0.0.1", "--port", "0",
                 "--dashboard-address", ":0", "--scheduler-file", scheduler_file],
                logs / "scheduler.log", folder,
            )
        )  # fmt: skip
        deadline = time.monotonic() + PATIENCE
        while not scheduler_file.exists():
            assert time.monotonic() < deadline, (logs / "scheduler.log").read_text()
            time.sleep(0.2)
        self.address = json.loads(scheduler_file.read_text())["address"]
        self.workers = [
            self._start(
                [dask, "worker", self.address, "--nthreads", "1", "--no-nanny",
                 "--name", f"worker{i}", "--dashboard-address", ":0"],
                logs / f"worker{i}.log", folder,
            )
            for i in range(2)
        ]  # fmt: skip
        self.processes += self.workers
        from distributed import Client

        with Client(self.address, timeout=PATIENCE) as client:
            client.wait_for_workers(2, timeout=PATIENCE)

    @staticmethod
    def _start(command, log: Path, cwd: Path) -> subprocess.Popen:
        with open(log, "w") as handle:
            return subprocess.Popen(
                [str(part) for part in command], stdout=handle, stderr=subprocess.STDOUT, cwd=cwd
            )

    def stop(self) -> None:
        # the workers first: a worker whose scheduler is gone waits to reconnect
        for process in reversed(self.processes):
            if process.poll() is None:
                process.terminate()
            try:
                process.wait(timeout=10)
            except subprocess.TimeoutExpired:
                process.kill()
                process.wait()


@pytest.fixture
def cluster(tmp_path):
    cluster = Cluster(tmp_path)
    yield cluster
    cluster.stop()


def test_a_scheduler_and_two_worker_processes_give_the_serial_bytes(tmp_path, cluster, serial):
    out = tmp_path / "out"
    code, _, err = run("run", PIPELINE, "-o", out, "--scheduler", cluster.address, "--chunk", "1")
    assert code == 0, err
    _same_outputs(out, serial)


def _started_run(out: Path, *options) -> subprocess.Popen:
    """``mvtools run`` of the sample pipeline in chunks of one frame, once it has written
    its first chunk (the others being made)."""
    running = subprocess.Popen(
        [sys.executable, "-m", "mvtools", "run", str(PIPELINE), "-o", str(out), "--chunk", "1",
         *options],
        stderr=subprocess.PIPE, text=True,
    )  # fmt: skip
    deadline = time.monotonic() + PATIENCE
    while not list(out.glob("chunks/*/*.yuv")):
        assert time.monotonic() < deadline and running.poll() is None
        time.sleep(0.05)
    return running


def test_a_worker_killed_mid_run_loses_and_corrupts_nothing(tmp_path, cluster, serial):
    out = tmp_path / "out"
    running = _started_run(out, "--scheduler", cluster.address)
    os.kill(cluster.workers[0].pid, signal.SIGKILL)
    _, err = running.communicate(timeout=PATIENCE)
    assert running.returncode == 0, err
    assert cluster.workers[0].poll() is not None  # it did die mid-run
    _same_outputs(out, serial)


def test_sigterm_stops_the_workers_and_leaves_no_temporary_file(tmp_path):
    import psutil

    out = tmp_path / "out"
    running = _started_run(out, "--workers", "2")
    workers = psutil.Process(running.pid).children(recursive=True)
    running.send_signal(signal.SIGTERM)
    _, err = running.communicate(timeout=PATIENCE)
    assert running.returncode == 143
    assert err.endswith("\nmvtools run: error: terminated: unfinished outputs were removed\n")
    assert "Traceback" not in err and "Warning" not in err
    _, alive = psutil.wait_procs(workers, timeout=10)
    assert not alive
    assert not list(out.rglob("*.part"))


def test_the_chain_from_the_array_as_built_gives_the_programs_bytes(tmp_path):
    # rectify, colorcorrect, estimate-depth, synthesize, evaluate: a local cluster in chunks
    # of one frame against the programs run one after the other over whole videos
    out = tmp_path / "pipeline"
    code, _, err = run(
        "run", ROOT / "configs" / "sample_distorted_pipeline.toml", "-o", out, "--workers", "2"
    )
    assert code == 0, err
    distorted = ROOT / "sample_data" / "distorted"
    textures = [f"v{i}_texture_256x192_yuv420p.yuv" for i in range(5)]
    rectified, corrected = tmp_path / "rectified", tmp_path / "corrected"
    views = [("--view", f"cam{i}", distorted / name) for i, name in enumerate(textures)]
    code, _, err = run(
        "rectify", distorted / "cameras.txt", "-o", rectified, *(a for v in views for a in v), "-q"
    )
    assert code == 0, err
    views = [("--view", f"cam{i}", rectified / name) for i, name in enumerate(textures)]
    code, _, err = run(
        "colorcorrect", "--reference", "cam2", "--cameras", rectified / "cameras.txt",
        "--depth-range", "2", "13", "-o", corrected, *(a for v in views for a in v), "-q",
    )  # fmt: skip
    assert code == 0, err
    for folder in (rectified, corrected):
        made = sorted(path.name for path in folder.iterdir())
        assert made == sorted(path.name for path in (out / folder.name).iterdir())
        for name in made:
            assert (folder / name).read_bytes() == (out / folder.name / name).read_bytes(), name
    depth = tmp_path / "v2_depth_256x192_yuv420p.yuv"
    code, _, err = run(
        "estimate-depth", LINE / "depth_cam2.cfg", f"FileCameraParameter={rectified / 'cameras.txt'}",
        *(f"File{side}ViewImage={corrected / textures[i]}"
          for side, i in (("Left", 1), ("Center", 2), ("Right", 3))),
        "-o", depth, "-q",
    )  # fmt: skip
    assert code == 0, err
    assert depth.read_bytes() == (out / depth.name).read_bytes()
    scores = json.loads((out / "v2_synthesized.scores.json").read_text())["mean"]
    assert scores["Y-PSNR"] > 35  # measured 39.08 dB: camera 2 from its neighbours


def test_an_unreachable_scheduler_is_one_line_and_leaves_nothing(tmp_path):
    # port 9 (discard): nothing listens there; the client gives up after its 10 s
    out = tmp_path / "made" / "out"
    code, _, err = run("run", PIPELINE, "-o", out, "--scheduler", "tcp://127.0.0.1:9", "-q")
    assert code == 2
    assert err.count("\n") == 1 and "--scheduler: cannot reach the scheduler" in err
    assert not (tmp_path / "made").exists()
