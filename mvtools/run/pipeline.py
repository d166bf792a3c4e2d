"""``mvtools run``: a pipeline's chain over a sequence as Dask tasks.

A pipeline (:mod:`mvtools.io.pipeline`) becomes tasks with their dependencies, as the
Makefile chain's targets: per chunk of frames, the array's ``rectify`` and
``colorcorrect`` (:func:`mvtools.run.rectify.rectify_videos`,
:func:`mvtools.run.colorcorrect.correct_colours`, every chunk fitting its tables to frame
0); per camera and per chunk of frames, ``estimate-depth`` of the
camera from its neighbours along the array (:func:`mvtools.run.depth.estimate_depth_config`)
and ``synthesize`` of each inner camera from its neighbours' textures and estimated depth
(:func:`mvtools.run.synthesize.synthesize_config`), each chunk's frames one task; then the
chunks of a video concatenated, and ``evaluate`` of each synthesized view against the
camera's own (:func:`mvtools.run.evaluate.evaluate_videos`). A chunk starts from a frame
that the run functions estimate afresh (they re-run the warm-up frames TemporalEnhancement
needs before a chunk's first frame), so the concatenated chunks are the bytes of one run
over all frames, whatever the chunk size and the machines.

Scheduling is Dask's (``distributed``): Dask's synchronous scheduler in this process with
one worker, else a :class:`distributed.LocalCluster` of one single-threaded worker process
per worker asked for, or an existing cluster's scheduler. Workers read and write the
paths of the pipeline, which must be the same file system for all of them; every output
is written under a temporary name by the worker that makes it and renamed when complete,
so a task re-run after its worker died writes the same bytes over nothing partial.
As ``make``, a task whose outputs exist and are newer than all its inputs (and whose
upstream tasks need not run) is not run again.
"""

from __future__ import annotations

import contextlib
import dataclasses
import json
import logging
import os
import shutil
import sys
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path

from mvtools.errors import UsageError
from mvtools.io.abort import undone_on_abort
from mvtools.io.atomic import atomic_output
from mvtools.io.depth_sidecar import depth_sidecar_path
from mvtools.io.pipeline import PipelineSpec, fill
from mvtools.io.yuv import format_from_name

__all__ = ["PipelineOptions", "Task", "pipeline_tasks", "run_pipeline"]

LOG = logging.getLogger(__name__)

#: Folder of the output folder where the chunks of the videos are kept (for re-runs).
CHUNKS_FOLDER = "chunks"

#: ``progress(tasks_done, tasks_total, frames_done, frames_total)``
PipelineProgress = Callable[[int, int, int, int], None]


@dataclass(frozen=True)
class PipelineOptions:
    """How ``mvtools run`` runs a pipeline.

    Attributes
    ----------
    chunk : int, optional
        Frames per task (0: whole videos); default the pipeline's ``chunk``.
    frames : int, optional
        Frames to process from frame 0; default the pipeline's ``frames``, else all
        frames of the shortest texture video.
    workers : int, optional
        Single-threaded workers, one core each: the processes of the local cluster
        (default: one per core); 1 runs the tasks one after the other in this process
        (Dask's synchronous scheduler), its numba kernels on one thread.
    scheduler : str, optional
        Address of an existing Dask scheduler (``tcp://HOST:8786``) instead.
    """

    chunk: int | None = None
    frames: int | None = None
    workers: int | None = None
    scheduler: str | None = None


@dataclass(frozen=True)
class Task:
    """One unit of work: ``function(*arguments)`` writes ``outputs`` from ``inputs``;
    ``frames``: the frames it makes, for progress; ``needs``: the keys of the tasks that
    make its inputs (:func:`pipeline_tasks` finds them)."""

    key: str
    function: Callable
    arguments: tuple
    inputs: tuple[Path, ...]
    outputs: tuple[Path, ...]
    frames: int = 0
    needs: tuple[str, ...] = ()


# --------------------------------------------------------------------------- task functions
# Module-level functions: a worker process unpickles them by name.


def _estimate_depth(config: Path, overrides: dict, output: Path) -> str:
    from mvtools.run.depth import estimate_depth_config

    estimate_depth_config(config, overrides=overrides, output=output)
    return os.fspath(output)


def _synthesize(config: Path, overrides: dict, output: Path) -> str:
    from mvtools.run.synthesize import synthesize_config

    synthesize_config(config, overrides=overrides, output=output)
    return os.fspath(output)


def _array_program(
    program: str,
    camera_file: Path,
    names: list[str],
    textures: list[Path],
    settings: dict,
    out_dir: Path,
    start: int,
    count: int,
) -> str:
    """``rectify`` or ``colorcorrect`` of the array's textures into ``out_dir``, with the
    stage's ``settings``."""
    from mvtools.io.camera_files import read_camera_file
    from mvtools.io.cameras import get_camera

    file_cameras = read_camera_file(camera_file)
    cameras = [get_camera(file_cameras, name, path=camera_file) for name in names]
    if program == "rectify":
        from mvtools.run.rectify import RectifyOptions, rectify_videos

        rectify_videos(
            cameras,
            out_dir=out_dir,
            textures=dict(zip(names, textures)),
            options=RectifyOptions(alpha=settings.get("alpha", 0.0)),
            start_frame=start,
            frame_count=count,
            camera_file=camera_file,
        )
        return os.fspath(out_dir)
    from mvtools.run.colorcorrect import ColourCorrectionOptions, correct_colours

    out_dir.mkdir(parents=True, exist_ok=True)
    depth_range = settings.get("depth-range")
    correct_colours(
        dict(zip(names, textures)),
        {name: out_dir / texture.name for name, texture in zip(names, textures)},
        # every chunk fits its tables to frame 0, as one run over all frames does
        ColourCorrectionOptions(
            reference=settings.get("reference"), space=settings.get("space", "rgb"), estimate_from=0
        ),
        cameras=dict(zip(names, cameras)),
        depth_range=tuple(depth_range) if depth_range is not None else None,
        start_frame=start,
        frame_count=count,
    )
    return os.fspath(out_dir)


def _concatenate(chunks: list[Path], output: Path) -> str:
    """The chunks' bytes one after the other into ``output`` (one chunk: a copy)."""
    with atomic_output(output) as handle:
        for chunk in chunks:
            with open(chunk, "rb") as source:
                shutil.copyfileobj(source, handle, 1 << 20)
    return os.fspath(output)


def _evaluate(reference: Path, test: Path, output: Path) -> str:
    from mvtools.run.evaluate import evaluate_videos

    scores = evaluate_videos(reference, test)
    with atomic_output(output, "w") as handle:
        json.dump(scores, handle, indent=2)
        handle.write("\n")
    return os.fspath(output)


#: The loggers of the programs a task runs: their per-run messages (what is estimated,
#: the depth range written) are debug detail of a pipeline, whose progress is its own.
_PROGRAM_LOGGERS = ("mvtools.run.depth", "mvtools.run.synthesize", "mvtools.run.evaluate")


def _call(function: Callable, arguments: tuple, *_needs):
    # the dependencies' results come as further arguments: they only order the tasks
    loggers = [logging.getLogger(name) for name in _PROGRAM_LOGGERS]
    levels = [logger.level for logger in loggers]
    if not logging.getLogger("mvtools").isEnabledFor(logging.DEBUG):
        for logger in loggers:
            logger.setLevel(logging.WARNING)
    try:
        return function(*arguments)
    finally:
        for logger, level in zip(loggers, levels):
            logger.setLevel(level)


# --------------------------------------------------------------------------- tasks


def _frame_count(spec: PipelineSpec, frames: int | None) -> int:
    counts = []
    for index, view in enumerate(spec.views):
        texture = spec.texture(index)
        fmt = format_from_name(texture)
        if fmt is None:
            raise UsageError(
                "the texture's name does not give its size and format "
                "(NAME_WIDTHxHEIGHT_yuv420p.yuv)",
                path=texture,
            )
        if not texture.is_file():
            raise UsageError(f"no such texture video (camera {view})", path=texture)
        counts.append(texture.stat().st_size // fmt.frame_bytes)
    available = min(counts)
    if available == 0:
        raise UsageError("a texture video holds no whole frame", path=spec.texture(0))
    if frames is not None and frames > available:
        raise UsageError(
            f"{frames} frames asked for, the texture videos hold {available}", key="--frames"
        )
    return frames or available


def _ranges(frames: int, chunk: int) -> list[tuple[int, int]]:
    """(first frame, number of frames) of each task: all frames, or chunks of ``chunk``."""
    if chunk in (0, None) or chunk >= frames:
        return [(0, frames)]
    return [(start, min(chunk, frames - start)) for start in range(0, frames, chunk)]


def _chunked(
    key: str,
    function: Callable,
    arguments: Callable[[Path, int, int], tuple],
    folder: Path,
    videos: list[str],
    copied: list[str],
    *,
    frames: int,
    chunk: int,
    inputs: tuple[Path, ...],
    chunks_folder: Path,
) -> list[Task]:
    """The tasks of a program that writes videos (``videos``, by name) and files that
    are the same for every frame range (``copied``: a depth video's sidecar, a camera
    file, colour tables) into ``folder``: ``arguments(folder, start, count)`` gives its
    arguments over a frame range. One task over all frames into ``folder``, or one per
    chunk of ``chunk`` frames into a folder of ``chunks_folder``, then each video
    concatenated and each of the other files copied from the first chunk."""
    ranges = _ranges(frames, chunk)
    names = [*videos, *copied]
    if len(ranges) == 1:
        outputs = tuple(folder / name for name in names)
        return [Task(key, function, arguments(folder, 0, frames), inputs, outputs, frames)]
    tasks = []
    for start, count in ranges:
        chunk_folder = chunks_folder / f"{key.replace(':', '_')}_from{start}"
        outputs = tuple(chunk_folder / name for name in names)
        tasks.append(
            Task(f"{key}:from{start}", function, arguments(chunk_folder, start, count), inputs,
                 outputs, count)
        )  # fmt: skip
    joined = []
    for index, name in enumerate(names):
        sources = [task.outputs[index] for task in (tasks if name in videos else tasks[:1])]
        joined.append(
            Task(f"{key}:{name}", _concatenate, (sources, folder / name), tuple(sources),
                 (folder / name,))
        )  # fmt: skip
    return tasks + joined


def pipeline_tasks(
    spec: PipelineSpec, output_folder: str | os.PathLike, options: PipelineOptions
) -> list[Task]:
    """The tasks of a pipeline, in an order that runs every task after its ``needs``.

    Parameters
    ----------
    spec : PipelineSpec
    output_folder : path
        Where the outputs go (the chunks in its ``chunks`` folder).
    options : PipelineOptions

    Returns
    -------
    list of Task
    """
    output_folder = Path(output_folder).absolute()
    frames = _frame_count(spec, options.frames if options.frames is not None else spec.frames)
    chunk = spec.chunk if options.chunk is None else options.chunk
    views = spec.views
    textures = [spec.texture(index).absolute() for index in range(len(views))]
    cameras = spec.cameras.absolute()
    tasks: list[Task] = []

    def chunked(key, function, arguments, folder, videos, copied, inputs) -> None:
        tasks.extend(
            _chunked(key, function, arguments, folder, videos, copied, frames=frames,
                     chunk=chunk, inputs=inputs, chunks_folder=output_folder / CHUNKS_FOLDER)
        )  # fmt: skip

    def output(stage: str, index: int) -> Path:
        return output_folder / fill(spec.stages[stage].output, index, views[index])

    # The array's stages: a folder of every camera's texture (under its input's name) and
    # the files of the whole array, which the next stages read: the rectified camera file,
    # each view's colour tables (the reference's the identity).
    for name, copied in (
        ("rectify", ["cameras.txt"]),
        ("colorcorrect", [f"{v}{s}" for v in views for s in (".lut.txt", ".cube")]),
    ):
        if name not in spec.stages:
            continue
        folder = output_folder / spec.stages[name].output
        chunked(
            name,
            _array_program,
            lambda target, start, count, cameras=cameras, textures=textures, name=name: (
                name, cameras, list(views), textures, spec.stages[name].settings, target,
                start, count,
            ),
            folder,
            [texture.name for texture in textures],
            copied,
            (cameras, *textures),
        )  # fmt: skip
        textures = [folder / texture.name for texture in textures]
        if name == "rectify":
            cameras = folder / "cameras.txt"

    def configured(key, function, config, overrides, output, copied, inputs) -> None:
        # a program run from its configuration with ``overrides`` and a frame range
        chunked(
            key,
            function,
            lambda target, start, count: (
                config,
                {**overrides, "start_frame": start, "total_number_of_frames": count},
                target / output.name,
            ),
            output.parent,
            [output.name],
            copied,
            inputs,
        )

    if "estimate-depth" in spec.stages:
        config = spec.stages["estimate-depth"].config.absolute()
        for index, view in enumerate(views):
            overrides = {
                "file_camera_parameter": os.fspath(cameras),
                "center_camera_name": view,
                "file_center_view_image": os.fspath(textures[index]),
            }
            # MatchDirection: 1 the left neighbour alone, 2 the right one, 3 both
            direction = 0
            for side, other, bit in (("left", index - 1, 1), ("right", index + 1, 2)):
                inside = 0 <= other < len(views)
                overrides[f"{side}_camera_name"] = views[other] if inside else ""
                overrides[f"file_{side}_view_image"] = os.fspath(textures[other]) if inside else ""
                direction |= bit if inside else 0
            overrides["match_direction"] = direction
            depth = output("estimate-depth", index)
            matched = [i for i in (index - 1, index, index + 1) if 0 <= i < len(views)]
            configured(
                f"estimate-depth:{view}",
                _estimate_depth,
                config,
                overrides,
                depth,
                [depth_sidecar_path(depth).name],
                (config, cameras, *(textures[i] for i in matched)),
            )
    if "synthesize" in spec.stages:
        config = spec.stages["synthesize"].config.absolute()
        for index in range(1, len(views) - 1):
            left, right = index - 1, index + 1
            depths = [output("estimate-depth", i) for i in (left, right)]
            overrides = {
                "camera_parameter_file": os.fspath(cameras),
                "left_camera_name": views[left],
                "virtual_camera_name": views[index],
                "right_camera_name": views[right],
                "left_view_image_name": os.fspath(textures[left]),
                "right_view_image_name": os.fspath(textures[right]),
                "left_depth_map_name": os.fspath(depths[0]),
                "right_depth_map_name": os.fspath(depths[1]),
            }
            synthesized = output("synthesize", index)
            configured(
                f"synthesize:{views[index]}",
                _synthesize,
                config,
                overrides,
                synthesized,
                [],
                (config, cameras, textures[left], textures[right], *depths),
            )
            if "evaluate" in spec.stages:
                scores = output("evaluate", index)
                tasks.append(
                    Task(f"evaluate:{views[index]}", _evaluate,
                         (textures[index], synthesized, scores), (textures[index], synthesized),
                         (scores,))
                )  # fmt: skip
    return _with_needs(tasks)


def _with_needs(tasks: list[Task]) -> list[Task]:
    """The tasks, each with the keys of the tasks that make its inputs (tasks come in an
    order that makes a file before reading it). No two tasks may write one file, and no
    output may name an input of the pipeline (a file read before a task makes it)."""
    made_by: dict[Path, str] = {}
    for task in tasks:
        for path in task.outputs:
            if path in made_by:
                raise UsageError(f"two tasks ({made_by[path]}, {task.key}) write it", path=path)
            made_by[path] = task.key
    made: set[Path] = set()
    linked = []
    for task in tasks:
        for path in task.inputs:
            if path in made_by and path not in made:
                raise UsageError(
                    f"the output of {made_by[path]} would replace an input of {task.key}",
                    path=path,
                )
        made.update(task.outputs)
        needs = tuple(dict.fromkeys(made_by[path] for path in task.inputs if path in made_by))
        linked.append(dataclasses.replace(task, needs=needs))
    return linked


# --------------------------------------------------------------------------- running


def _stale(tasks: list[Task]) -> list[Task]:
    """The tasks to run, as make decides: outputs missing or older than an input, or an
    upstream task to run."""
    stale: set[str] = set()
    for task in tasks:
        if any(need in stale for need in task.needs):
            stale.add(task.key)
            continue
        try:
            oldest = min(path.stat().st_mtime for path in task.outputs)
        except FileNotFoundError:
            stale.add(task.key)
            continue
        newest = max((path.stat().st_mtime for path in task.inputs if path.exists()), default=0)
        if oldest < newest:
            stale.add(task.key)
    return [task for task in tasks if task.key in stale]


def run_pipeline(
    spec: PipelineSpec,
    output_folder: str | os.PathLike,
    options: PipelineOptions = PipelineOptions(),
    *,
    progress: PipelineProgress | None = None,
) -> list[Path]:
    """Run a pipeline's tasks (:func:`pipeline_tasks`) on Dask.

    Parameters
    ----------
    spec : PipelineSpec
    output_folder : path
        The folder of the outputs, made if missing (and removed again if the run fails
        before it holds any).
    options : PipelineOptions
    progress : callable, optional
        ``progress(tasks_done, tasks_total, frames_done, frames_total)`` after each task.

    Returns
    -------
    list of Path
        The outputs of the pipeline (made now or up to date already).

    Raises
    ------
    UsageError, ConfigError, DataError
        A bad pipeline or option, or the first task that failed, as its program would
        report it. Outputs being made are not left behind half written.
    """
    output_folder = Path(output_folder)
    if output_folder.exists() and not output_folder.is_dir():
        raise UsageError("is a file, not a folder", path=output_folder, key="--output")
    tasks = pipeline_tasks(spec, output_folder, options)
    to_run = _stale(tasks)
    LOG.info(
        "%d tasks, %d up to date; %d frames to make",
        len(tasks),
        len(tasks) - len(to_run),
        sum(task.frames for task in to_run),
    )
    # the folders the outputs need, made now and removed again, if still empty, when the
    # run fails: a failed run leaves nothing behind
    made = sorted(
        {folder for task in to_run for path in task.outputs for folder in path.parents
         if not folder.exists()},
        key=lambda folder: len(folder.parts),
    )  # fmt: skip
    for folder in made:
        folder.mkdir(exist_ok=True)
    try:
        clusters: list = []  # the local cluster, once it runs
        with undone_on_abort(lambda: _stop_workers_and_clean(clusters, to_run, made)):
            if to_run:
                _execute(to_run, options, progress, clusters)
    except BaseException:
        _remove_unfinished(to_run, made)
        raise
    _remove_unfinished(to_run, [])
    chunks = output_folder.absolute() / CHUNKS_FOLDER
    return [path for task in tasks for path in task.outputs if chunks not in path.parents]


def _graph(tasks: list[Task]) -> dict:
    """The tasks as a Dask graph: ``key: (_call, function, arguments, *needs)``."""
    keys = {task.key for task in tasks}
    return {
        task.key: (_call, task.function, task.arguments, *(n for n in task.needs if n in keys))
        for task in tasks
    }


class _Tally:
    def __init__(self, tasks: list[Task], progress: PipelineProgress | None):
        self.frames = {task.key: task.frames for task in tasks}
        self.total_frames = sum(self.frames.values())
        self.done_tasks = 0
        self.done_frames = 0
        self.progress = progress

    def done(self, key: str) -> None:
        self.done_tasks += 1
        self.done_frames += self.frames.get(key, 0)
        LOG.debug("done: %s", key)
        if self.progress is not None:
            self.progress(self.done_tasks, len(self.frames), self.done_frames, self.total_frames)


def _execute(tasks: list[Task], options: PipelineOptions, progress, clusters: list) -> None:
    graph = _graph(tasks)
    tally = _Tally(tasks, progress)
    if options.scheduler is None and options.workers == 1:
        import dask
        import numba
        from dask.callbacks import Callback

        def posttask(key, result, dsk, state, worker_id):
            tally.done(key)

        # one worker, one core, as each worker of a cluster
        threads = numba.get_num_threads()
        numba.set_num_threads(1)
        try:
            with Callback(posttask=posttask):
                dask.get(graph, list(graph))
        finally:
            numba.set_num_threads(threads)
        return
    with _client(options, clusters) as client:
        from distributed import as_completed

        futures = client.get(graph, list(graph), sync=False)
        try:
            for future in as_completed(futures):
                if future.status == "error":
                    future.result()  # raises the task's own error
                tally.done(future.key)
        except BaseException:
            client.cancel(futures)
            raise


@contextlib.contextmanager
def _client(options: PipelineOptions, clusters: list) -> Iterator:
    """A Dask client of the scheduler the options name, or of a local cluster (added to
    ``clusters`` while it runs)."""
    from distributed import Client, LocalCluster

    if options.scheduler is not None:
        start = time.perf_counter()
        try:
            client = Client(options.scheduler, timeout="10s")
        except OSError as error:
            raise UsageError(
                f"cannot reach the scheduler at {options.scheduler}: {error}", key="--scheduler"
            ) from None
        LOG.info(
            "scheduler %s: %d workers (%.1f s)",
            options.scheduler,
            len(client.scheduler_info()["workers"]),
            time.perf_counter() - start,
        )
        with client:
            yield client
        return
    workers = options.workers or os.cpu_count() or 1
    # multiprocessing's resource tracker, which takes the -W options of this process,
    # would warn of the semaphores it cleans up after a run stopped by a signal
    sys.warnoptions.append("ignore::UserWarning:multiprocessing.resource_tracker")
    # One single-threaded process per worker: the numba kernels' own threads would only
    # compete with the other workers' for the cores. Without Dask's MALLOC_TRIM_THRESHOLD_
    # for the worker processes: setting it turns off glibc's adaptive mmap threshold, so
    # every frame-sized array is mapped afresh and its pages faulted in again, which
    # made a depth task twice as slow (2.2 s against 1.3 s for 8 frames of the sample).
    import dask.config

    environment = {"OMP_NUM_THREADS": 1, "MKL_NUM_THREADS": 1, "OPENBLAS_NUM_THREADS": 1}
    with (
        dask.config.set({"distributed.nanny.pre-spawn-environ": environment}),
        LocalCluster(
            n_workers=workers,
            threads_per_worker=1,
            processes=True,
            dashboard_address=None,
            silence_logs=logging.CRITICAL,
            env={"NUMBA_NUM_THREADS": "1"},
        ) as cluster,
        Client(cluster) as client,
    ):
        LOG.info("local cluster: %d worker processes", workers)
        clusters.append(cluster)
        try:
            yield client
        finally:
            clusters.remove(cluster)


def _stop_workers_and_clean(clusters: list, tasks: list[Task], folders: list[Path]) -> None:
    """What a signal that stops the run undoes: the local cluster's worker processes
    (this process's children) killed, their nannies told first not to start them again,
    then their temporary files removed."""
    import multiprocessing

    for cluster in clusters:
        for nanny in cluster.workers.values():
            nanny.close_gracefully()
    for child in multiprocessing.active_children():
        child.kill()
    for child in multiprocessing.active_children():
        child.join(5)
    _remove_unfinished(tasks, folders)


def _remove_unfinished(tasks: list[Task], folders: list[Path]) -> None:
    """Temporary files of outputs whose writer was killed (a lost worker): the atomic
    writes' ``.NAME.*.part``; then those of ``folders`` (made by the run, parents first)
    that are empty."""
    for task in tasks:
        for path in task.outputs:
            for unfinished in path.parent.glob(f".{path.name}.*.part"):
                with contextlib.suppress(FileNotFoundError):
                    unfinished.unlink()
    for folder in reversed(folders):
        with contextlib.suppress(OSError):
            folder.rmdir()
