"""``mvtools run``: a pipeline file's chain over a sequence, on a Dask cluster."""

from __future__ import annotations

import click

from mvtools.cli.options import ProgramCommand, program
from mvtools.cli.progress import Progress
from mvtools.errors import UsageError
from mvtools.io.pipeline import read_pipeline
from mvtools.run.pipeline import PipelineOptions, run_pipeline


@click.command(name="run", cls=ProgramCommand)
@click.argument("pipeline", type=click.Path(dir_okay=False))
@click.option(
    "-o",
    "--output",
    "output_folder",
    required=True,
    type=click.Path(file_okay=False),
    help="Folder of the outputs (made if missing); the chunks go to its chunks/ folder.",
)
@click.option(
    "--chunk",
    type=click.IntRange(min=0),
    default=None,
    help="Frames per task (0: whole videos; default: the pipeline's chunk).",
)
@click.option(
    "--frames",
    type=click.IntRange(min=1),
    default=None,
    help="Number of frames from frame 0 (default: the pipeline's frames, else all).",
)
@click.option(
    "--workers",
    type=click.IntRange(min=1),
    default=None,
    help="Single-threaded workers, one core each: the processes of the local cluster "
    "(default: one per core); 1 runs the tasks one after the other in this process "
    "(Dask's synchronous scheduler) on one core.",
)
@click.option(
    "--scheduler",
    default=None,
    metavar="ADDRESS",
    help="An existing Dask cluster's scheduler (tcp://HOST:8786) instead of a local "
    "cluster; its workers must see the pipeline's paths (a shared file system) and run "
    "the same mvtools.",
)
@program
def command(pipeline, output_folder, chunk, frames, workers, scheduler):
    """Run the chain a PIPELINE file describes over a sequence: the depth of every
    camera from its neighbours, each inner camera synthesized from its neighbours and
    scored against its own view, per camera and per chunk of frames as Dask tasks.

    The outputs are the bytes of one serial run of each program over all frames,
    whatever the chunks and the workers; outputs newer than their inputs are not made
    again. The pipeline file's keys are described in docs/pipeline.md.

    \b
    mvtools run configs/sample_line_pipeline.toml -o build/run
    mvtools run configs/sample_line_pipeline.toml -o build/run --workers 1
    mvtools run configs/sample_line_pipeline.toml -o build/run --scheduler tcp://HOST:8786
    """
    if workers is not None and scheduler is not None:
        raise UsageError("--workers and --scheduler exclude each other", key="--workers")
    spec = read_pipeline(pipeline)
    progress = Progress(None, "frames")

    def report(tasks_done, tasks_total, frames_done, frames_total):
        progress.label = f"tasks {tasks_done}/{tasks_total}, frames"
        progress(frames_done, frames_total)

    run_pipeline(
        spec,
        output_folder,
        PipelineOptions(chunk=chunk, frames=frames, workers=workers, scheduler=scheduler),
        progress=report,
    )
