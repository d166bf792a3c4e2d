"""``mvtools encode``: rate-distortion experiments with a real HEVC encoder, simulcast
against frame-compatible packing, with Bjontegaard deltas and the MPEG evaluation of
compressed multiview plus depth through view synthesis."""

from __future__ import annotations

import contextlib
import json
import logging
import sys
from pathlib import Path

import click
import numpy as np

from mvtools.cli.options import (
    POSITIVE,
    ProgramCommand,
    frame_range_options,
    program,
    video_format_options,
)
from mvtools.cli.pack import write_packed, write_unpacked
from mvtools.cli.progress import Progress
from mvtools.errors import DataError, UsageError
from mvtools.io.abort import run_program
from mvtools.io.atomic import atomic_output
from mvtools.io.encoders import ENCODERS, decode_hevc, encode_hevc, program_path
from mvtools.io.inputs import frame_range, open_input_video
from mvtools.io.loaded_config import load_config
from mvtools.io.yuv import YuvFormat, open_video, open_writer
from mvtools.metrics import bd_psnr, bd_rate
from mvtools.pack import plan_layout
from mvtools.params import VsrsParams, param_specs
from mvtools.run.evaluate import score_videos

LOG = logging.getLogger("mvtools")
MODES = ("simulcast", "packed")
_SYNTHESIS_INPUTS = {
    "left_camera_name": ("left_view_image_name", "left_depth_map_name"),
    "right_camera_name": ("right_view_image_name", "right_depth_map_name"),
}


@click.command(name="encode", cls=ProgramCommand)
@click.option(
    "--view",
    "views",
    multiple=True,
    nargs=2,
    required=True,
    metavar="NAME VIDEO",
    help="A texture view (repeatable).",
)
@click.option(
    "--depth",
    "depths",
    multiple=True,
    nargs=2,
    metavar="NAME VIDEO",
    help="A view's depth map (repeatable): simulcast codes it as a stream of its own, "
    "packing puts it into the atlas.",
)
@click.option(
    "--qp",
    "qps",
    multiple=True,
    type=click.IntRange(0, 51),
    required=True,
    help="A quantisation parameter (repeatable; four or more give Bjontegaard deltas).",
)
@click.option(
    "--mode",
    "modes",
    multiple=True,
    type=click.Choice(MODES),
    help="simulcast: every view and depth map coded on its own; packed: all in one "
    "grid (or atlas with depth maps) coded as one video (repeatable; default "
    "both, compared by their Bjontegaard deltas).",
)
@click.option(
    "--depth-qp-offset",
    type=int,
    default=0,
    show_default=True,
    help="QP of the depth streams relative to the textures' (simulcast).",
)
@click.option(
    "--encoder",
    type=click.Choice(ENCODERS),
    default="x265",
    show_default=True,
    help="x265 (Debian package x265) or ffmpeg's libx265 (package ffmpeg); ffmpeg "
    "decodes in both cases.",
)
@click.option("--preset", default="medium", show_default=True, help="x265 preset.")
@click.option(
    "--fps", type=POSITIVE, default=25.0, show_default=True, help="Frame rate, for the bitrates."
)
@click.option(
    "--synthesize",
    "synthesis_config",
    type=click.Path(dir_okay=False),
    default=None,
    help="A VSRS configuration whose reference views are among the views: its "
    "virtual view is synthesized from the decoded views and depth maps and scored "
    "(PSNR, IV-PSNR) against the one synthesized from the originals.",
)
@click.option(
    "-o",
    "--out-dir",
    required=True,
    type=click.Path(file_okay=False),
    help="Folder for the bitstreams, decoded videos and report.json.",
)
@video_format_options
@frame_range_options
@program
def command(
    views,
    depths,
    qps,
    modes,
    depth_qp_offset,
    encoder,
    preset,
    fps,
    synthesis_config,
    out_dir,
    size,
    pix_fmt,
    start_frame,
    frame_count,
):
    """Encode the views at every QP, decode them, and report per QP the bitrate and the
    Y-PSNR and YUV-PSNR (6:1:1) of every view; with two modes, the Bjontegaard deltas of
    packing against simulcast (BD-rate and BD-PSNR, cubic and piecewise-cubic)."""
    # both programs are needed (ffmpeg decodes): say so before anything is written
    for name in dict.fromkeys((encoder, "ffmpeg")):
        program_path(name)
    modes = tuple(dict.fromkeys(modes)) or MODES
    qps = sorted(set(qps))
    out = Path(out_dir)
    streams = [(name, "texture", Path(path)) for name, path in views]
    streams += [(name, "depth", Path(path)) for name, path in depths]
    if len({(name, kind) for name, kind, _ in streams}) != len(streams):
        raise UsageError("a view or depth map is given twice")
    synthesis = _synthesis_inputs(synthesis_config, streams) if synthesis_config else None
    with contextlib.ExitStack() as stack:
        videos = {
            (name, kind): stack.enter_context(open_input_video(path, size, pix_fmt))
            for name, kind, path in streams
        }
        frames = frame_range(list(videos.values()), start_frame, frame_count)
        _check_formats(videos)
        out.mkdir(parents=True, exist_ok=True)
        originals = _trimmed(videos, frames, out / "original")
    results = {}
    progress = Progress(len(modes) * len(qps), "rate points done")
    for mode in modes:
        for qp in qps:
            folder = out / mode / f"qp{qp}"
            folder.mkdir(parents=True, exist_ok=True)
            run = _simulcast if mode == "simulcast" else _packed
            point = run(
                originals,
                folder,
                qp=qp,
                depth_qp_offset=depth_qp_offset,
                encoder=encoder,
                preset=preset,
                fps=fps,
                frames=len(frames),
            )
            point["scores"] = _scores(originals, point["decoded"])
            if synthesis is not None:
                point["synthesis"] = _synthesis_scores(
                    synthesis, point["decoded"], out, folder, len(frames)
                )
            results.setdefault(mode, []).append({"qp": qp, **point})
            progress.advance()
    report = _report(results, modes, qps)
    with atomic_output(out / "report.json", "w") as handle:
        json.dump(report, handle, indent=1, default=str)
        handle.write("\n")
    click.echo(_table(report))


def _check_formats(videos) -> None:
    for (name, kind), video in videos.items():
        if video.format.bits > 12:
            raise DataError(
                f"{kind} {name} has {video.format.bits}-bit samples; HEVC codes 8 "
                "to 12 bits: convert it with mvtools convert --out-pix-fmt",
                path=video.path,
            )


def _trimmed(videos, frames, folder: Path) -> dict:
    """The frames to code of every stream, as files of their own (the encoders read
    whole files)."""
    folder.mkdir(parents=True, exist_ok=True)
    originals = {}
    for (name, kind), video in videos.items():
        path = folder / Path(video.path).name
        with open_writer(path, video.format) as writer:
            for index in frames:
                writer.write(video.read(index))
        originals[(name, kind)] = (path, video.format)
    return originals


def _code(source: Path, fmt: YuvFormat, folder: Path, *, qp, encoder, preset, fps):
    bitstream = folder / (source.stem + ".hevc")
    size = encode_hevc(source, fmt, bitstream, qp=qp, encoder=encoder, preset=preset, fps=fps)
    decoded = folder / source.name
    decode_hevc(bitstream, decoded, fmt)
    return size, decoded


def _simulcast(originals, folder, *, qp, depth_qp_offset, encoder, preset, fps, frames) -> dict:
    sizes, decoded = {}, {}
    for key, (path, fmt) in originals.items():
        stream_qp = min(51, max(0, qp + (depth_qp_offset if key[1] == "depth" else 0)))
        sizes[key], decoded[key] = _code(
            path, fmt, folder, qp=stream_qp, encoder=encoder, preset=preset, fps=fps
        )
    seconds = frames / fps
    rates = {
        kind: sum(size for (_, k), size in sizes.items() if k == kind) * 8 / seconds / 1000
        for kind in ("texture", "depth")
    }
    return {
        "kbps": rates["texture"] + rates["depth"],
        "texture_kbps": rates["texture"],
        "depth_kbps": rates["depth"],
        "decoded": decoded,
    }


def _packed(originals, folder, *, qp, depth_qp_offset, encoder, preset, fps, frames) -> dict:
    textures = [
        (name, fmt.size) for (name, kind), (_, fmt) in originals.items() if kind == "texture"
    ]
    depth_maps = [
        (name, fmt.size) for (name, kind), (_, fmt) in originals.items() if kind == "depth"
    ]
    layout = plan_layout(textures, layout="atlas" if depth_maps else "grid", depths=depth_maps)
    texture_format = next(fmt for (_, kind), (_, fmt) in originals.items() if kind == "texture")
    packed_format = YuvFormat(
        layout.width, layout.height, chroma=texture_format.chroma, bits=texture_format.bits
    )
    packed = folder / f"packed_{layout.width}x{layout.height}_{packed_format.pix_fmt}.yuv"
    with contextlib.ExitStack() as stack:
        readers = {
            key: stack.enter_context(open_video(path, fmt))
            for key, (path, fmt) in originals.items()
        }
        with write_packed(readers, layout, packed_format, packed, range(frames)):
            pass
    (folder / "decoded").mkdir(exist_ok=True)
    size, decoded_packed = _code(
        packed, packed_format, folder / "decoded", qp=qp, encoder=encoder, preset=preset, fps=fps
    )
    targets = {key: (folder / path.name, fmt) for key, (path, fmt) in originals.items()}
    with open_video(decoded_packed, packed_format) as video:
        write_unpacked(video, layout, targets, range(frames))
    decoded = {key: path for key, (path, _) in targets.items()}
    rate = size * 8 / (frames / fps) / 1000
    return {"kbps": rate, "texture_kbps": None, "depth_kbps": None, "decoded": decoded}


def _scores(originals, decoded) -> dict:
    """Mean over frames of each stream's Y-PSNR and YUV-PSNR against its original."""
    scores = {}
    for key, (path, fmt) in originals.items():
        with open_video(path, fmt) as reference, open_video(decoded[key], fmt) as test:
            mean = score_videos(reference, test, range(len(reference)), ("psnr",))["mean"]
        scores[f"{key[0]} {key[1]}"] = {"y_psnr": mean["Y-PSNR"], "yuv_psnr": mean.get("YUV-PSNR")}
    return scores


def _synthesis_inputs(config: str, streams) -> dict:
    """Which decoded stream stands for each input of the VSRS configuration."""
    loaded = load_config(VsrsParams, config)
    params = loaded.params
    by_key = {}
    for camera_field, (texture_field, depth_field) in _SYNTHESIS_INPUTS.items():
        camera = getattr(params, camera_field)
        for field, kind in ((texture_field, "texture"), (depth_field, "depth")):
            if not any(name == camera and stream_kind == kind for name, stream_kind, _ in streams):
                raise UsageError(
                    f"--synthesize {config}: its {camera_field} {camera} has no "
                    f"--{'view' if kind == 'texture' else 'depth'} {camera} here"
                )
            by_key[field] = (camera, kind)
    return {"config": Path(config), "inputs": by_key}


def _synthesize(config: Path, output: Path, overrides: dict, frames: int) -> None:
    """``mvtools synthesize CONFIG`` with some of its keys replaced, as a Makefile runs it."""
    keys = {spec.name: spec.key for spec in param_specs(VsrsParams)}
    overrides = {**overrides, "start_frame": 0, "total_number_of_frames": frames}
    command = [
        sys.executable,
        "-m",
        "mvtools",
        "synthesize",
        str(config),
        "-q",
        "-o",
        str(output),
        *(f"{keys[field]}={value}" for field, value in overrides.items()),
    ]
    completed = run_program(command)
    if completed.returncode != 0:
        raise DataError(
            f"synthesis failed: {completed.stderr.strip().splitlines()[-1]}", path=config
        )


def _synthesis_scores(synthesis: dict, decoded: dict, out: Path, folder: Path, frames: int) -> dict:
    reference = out / "original" / "synthesized.yuv"
    if not reference.exists():
        _synthesize(
            synthesis["config"],
            reference,
            {
                field: (out / "original" / decoded[key].name).resolve()
                for field, key in synthesis["inputs"].items()
            },
            frames,
        )
    test = folder / "synthesized.yuv"
    _synthesize(
        synthesis["config"],
        test,
        {field: decoded[key].resolve() for field, key in synthesis["inputs"].items()},
        frames,
    )
    params = load_config(VsrsParams, synthesis["config"]).params
    fmt = YuvFormat(params.source_width, params.source_height)
    with open_video(reference, fmt) as truth, open_video(test, fmt) as result:
        mean = score_videos(truth, result, range(len(truth)), ("psnr", "ivpsnr"))["mean"]
    return {"y_psnr": mean["Y-PSNR"], "iv_psnr": mean["IV-PSNR"]}


def _report(results: dict, modes, qps) -> dict:
    report = {"qps": qps, "modes": {}}
    for mode in modes:
        points = []
        for point in results[mode]:
            textures = [
                score["y_psnr"]
                for name, score in point["scores"].items()
                if name.endswith(" texture")
            ]
            weighted = [
                score["yuv_psnr"]
                for name, score in point["scores"].items()
                if name.endswith(" texture")
            ]
            points.append(
                {key: value for key, value in point.items() if key != "decoded"}
                | {
                    "mean_texture_y_psnr": float(np.mean(textures)),
                    "mean_texture_yuv_psnr": float(np.mean(weighted)),
                }
            )
        report["modes"][mode] = points
    if len(modes) == 2 and len(qps) >= 4:
        anchor, test = (report["modes"][mode] for mode in MODES)
        rates = [[point["kbps"] for point in points] for points in (anchor, test)]
        quality = [
            [point["mean_texture_yuv_psnr"] for point in points] for points in (anchor, test)
        ]
        report["bjontegaard"] = {
            f"{method}": {
                "bd_rate_percent": bd_rate(
                    rates[0], quality[0], rates[1], quality[1], method=method
                ),
                "bd_psnr_db": bd_psnr(rates[0], quality[0], rates[1], quality[1], method=method),
            }
            for method in ("cubic", "pchip")
        }
    return report


def _table(report: dict) -> str:
    lines = [
        f"{'mode':10s} {'QP':>3s} {'kbit/s':>10s} {'texture':>10s} {'depth':>9s} "
        f"{'Y-PSNR':>7s} {'YUV-PSNR':>8s}  synthesized view (PSNR / IV-PSNR)"
    ]
    for mode, points in report["modes"].items():
        for point in points:
            split = (
                ""
                if point["texture_kbps"] is None
                else f"{point['texture_kbps']:10.1f} {point['depth_kbps']:9.1f}"
            )
            synthesis = point.get("synthesis")
            lines.append(
                f"{mode:10s} {point['qp']:3d} {point['kbps']:10.1f} "
                f"{split or ' ' * 20} {point['mean_texture_y_psnr']:7.2f} "
                f"{point['mean_texture_yuv_psnr']:8.2f}"
                + (f"  {synthesis['y_psnr']:.2f} / {synthesis['iv_psnr']:.2f}" if synthesis else "")
            )
    lines.append("per stream, Y-PSNR / YUV-PSNR (dB):")
    for mode, points in report["modes"].items():
        for point in points:
            streams = "  ".join(
                f"{name} {score['y_psnr']:.2f}"
                + (f"/{score['yuv_psnr']:.2f}" if score["yuv_psnr"] is not None else "")
                for name, score in point["scores"].items()
            )
            lines.append(f"  {mode:10s} QP {point['qp']:2d}  {streams}")
    for method, deltas in report.get("bjontegaard", {}).items():
        lines.append(
            f"packed against simulcast ({method}): BD-rate "
            f"{deltas['bd_rate_percent']:+.2f} %, BD-PSNR {deltas['bd_psnr_db']:+.3f} dB "
            "(mean texture YUV-PSNR)"
        )
    return "\n".join(lines)
