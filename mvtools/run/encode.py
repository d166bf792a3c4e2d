"""Rate-distortion experiments with a real HEVC encoder: the run function of ``mvtools
encode``.

:func:`rd_experiment` codes the views (and depth maps) at every QP, simulcast (every
stream on its own) and packed (all in one grid or atlas, :mod:`mvtools.run.pack`),
decodes them and scores them; with both modes it gives the Bjontegaard deltas of
packing against simulcast, and with a VSRS configuration it scores the virtual view
synthesized from the decoded views against the one synthesized from the originals, as
MPEG evaluates compressed multiview plus depth (section 1.6 of "Multiview video:
acquisition, processing, compression, and virtual view rendering"). The encoders are
Debian's ``x265`` and ``ffmpeg`` programs (:mod:`mvtools.io.encoders`); the synthesis
runs in this process (:func:`mvtools.run.synthesize.synthesize_config`), and the
Bjontegaard fits (SciPy) are imported when the report is made, so this module is
cheap to import.
"""

from __future__ import annotations

import contextlib
import json
import math
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from mvtools.errors import DataError, UsageError
from mvtools.io.atomic import atomic_output
from mvtools.io.encoders import ENCODERS, decode_hevc, encode_hevc, program_path
from mvtools.io.inputs import frame_range, open_input_video
from mvtools.io.loaded_config import load_config
from mvtools.io.yuv import YuvFormat, open_video, open_writer
from mvtools.pack import plan_layout
from mvtools.params import VsrsParams
from mvtools.run.evaluate import score_videos
from mvtools.run.pack import pack_frames, write_unpacked
from mvtools.run.stream import ProgressCallback
from mvtools.run.synthesize import synthesize_config

#: The ways of coding the streams: each on its own, or all in one packed video; the
#: first is the anchor of the Bjontegaard deltas.
MODES = ("simulcast", "packed")

# The VsrsParams fields of each reference view's texture and depth map, by the field
# of its camera's name.
_SYNTHESIS_INPUTS = {
    "left_camera_name": ("left_view_image_name", "left_depth_map_name"),
    "right_camera_name": ("right_view_image_name", "right_depth_map_name"),
}


@dataclass(frozen=True)
class EncoderSettings:
    """How :func:`rd_experiment` codes the streams.

    Attributes
    ----------
    encoder : {"x265", "ffmpeg"}
        x265, or ffmpeg's libx265; ffmpeg decodes in both cases.
    preset : str
        The x265 preset.
    fps : float
        Frame rate, for the bitrates.
    depth_qp_offset : int
        QP of the depth streams relative to the textures' (simulcast), clipped to 0-51.
    """

    encoder: str = "x265"
    preset: str = "medium"
    fps: float = 25.0
    depth_qp_offset: int = 0

    def __post_init__(self):
        if self.encoder not in ENCODERS:
            raise ValueError(f"encoder must be one of {', '.join(ENCODERS)}")
        if not (math.isfinite(self.fps) and self.fps > 0):
            raise ValueError(f"the frame rate must be positive and finite, got {self.fps}")


def rd_experiment(
    views: Mapping[str, str | os.PathLike],
    qps: Sequence[int],
    out_dir: str | os.PathLike,
    *,
    depths: Mapping[str, str | os.PathLike] | None = None,
    modes: Sequence[str] = MODES,
    settings: EncoderSettings = EncoderSettings(),
    synthesis_config: str | os.PathLike | None = None,
    size: tuple[int, int] | None = None,
    pix_fmt: str | None = None,
    start_frame: int = 0,
    frame_count: int | None = None,
    progress: ProgressCallback | None = None,
) -> dict:
    """Code the views at every QP in every mode, decode and score them, and write the
    report.

    The folder gets ``original/`` (the frames coded, and the virtual view synthesized
    from them), ``MODE/qpQP/`` (bitstreams, decoded streams, the packed video, the
    virtual view synthesized from the decoded streams) and ``report.json``, the
    report returned.

    Parameters
    ----------
    views : mapping of str to path
        Each texture view's name and video.
    qps : sequence of int
        Quantisation parameters, 0-51; four or more give Bjontegaard deltas.
    out_dir : path
        The output folder; made if missing.
    depths : mapping of str to path, optional
        Depth maps of views: simulcast codes each as a stream of its own, packing puts
        them into an atlas.
    modes : sequence of {"simulcast", "packed"}
        Both give the Bjontegaard deltas of packing against simulcast.
    settings : EncoderSettings
    synthesis_config : path, optional
        A VSRS configuration whose reference views (textures and depth maps) are among
        the views; its virtual view is synthesized and scored at every point.
    size, pix_fmt : optional
        The videos' size and pixel format when their names or headers do not say.
    start_frame, frame_count : int
        The frames coded; ``frame_count`` None for all that every video has.
    progress : callable, optional
        ``progress(done, total)`` after each rate point (a mode at a QP).

    Returns
    -------
    dict
        ``"qps"``: the QPs, ascending; ``"modes"``: per mode a list of points, one per
        QP, each with ``"qp"``, ``"kbps"``, ``"texture_kbps"`` and ``"depth_kbps"``
        (simulcast; None when packed), ``"scores"`` (per stream ``"NAME KIND"`` the mean
        ``"y_psnr"`` and ``"yuv_psnr"``, dB), ``"mean_texture_y_psnr"``,
        ``"mean_texture_yuv_psnr"`` and with a configuration ``"synthesis"``
        (``"y_psnr"``, ``"iv_psnr"``); with both modes and four QPs or more
        ``"bjontegaard"``: per method (``"cubic"``, ``"pchip"``) ``"bd_rate_percent"``
        and ``"bd_psnr_db"``, on the mean texture YUV-PSNR.

    Raises
    ------
    UsageError
        A missing encoder program (with how to install it), or a configuration whose
        reference views are not among the views.
    DataError
        Samples of more than 12 bits, or a failed encoder.
    ValueError
        No QP, a QP outside 0-51, or an unknown mode.
    """
    modes = tuple(dict.fromkeys(modes))
    if not modes or any(mode not in MODES for mode in modes):
        raise ValueError(f"modes must be some of {', '.join(MODES)}, got {modes}")
    qps = sorted(set(qps))
    if not qps or not all(0 <= qp <= 51 for qp in qps):
        raise ValueError(f"give one QP or more, each 0-51, got {qps}")
    # both programs are needed (ffmpeg decodes): say so before anything is written
    for name in dict.fromkeys((settings.encoder, "ffmpeg")):
        program_path(name)
    out = Path(out_dir)
    streams = {(name, "texture"): Path(path) for name, path in views.items()}
    streams.update({(name, "depth"): Path(path) for name, path in (depths or {}).items()})
    synthesis = _synthesis_inputs(synthesis_config, streams) if synthesis_config else None
    with contextlib.ExitStack() as stack:
        videos = {
            key: stack.enter_context(open_input_video(path, size, pix_fmt))
            for key, path in streams.items()
        }
        frames = frame_range(list(videos.values()), start_frame, frame_count)
        _check_formats(videos)
        out.mkdir(parents=True, exist_ok=True)
        originals = _trimmed(videos, frames, out / "original")
    results = {}
    total = len(modes) * len(qps)
    for mode in modes:
        for qp in qps:
            folder = out / mode / f"qp{qp}"
            folder.mkdir(parents=True, exist_ok=True)
            run = _simulcast if mode == "simulcast" else _packed
            point = run(originals, folder, qp=qp, settings=settings, frames=len(frames))
            point["scores"] = _scores(originals, point["decoded"])
            if synthesis is not None:
                point["synthesis"] = _synthesis_scores(
                    synthesis, point["decoded"], out, folder, len(frames)
                )
            results.setdefault(mode, []).append({"qp": qp, **point})
            if progress is not None:
                progress(sum(map(len, results.values())), total)
    report = _report(results, modes, qps)
    with atomic_output(out / "report.json", "w") as handle:
        json.dump(report, handle, indent=1, default=str)
        handle.write("\n")
    return report


def _check_formats(videos) -> None:
    for (name, kind), video in videos.items():
        if video.format.bits > 12:
            raise DataError(
                f"{kind} {name} has {video.format.bits}-bit samples; HEVC codes 8 "
                "to 12 bits: convert it with mvtools convert --out-pix-fmt",
                path=video.path,
            )


def _trimmed(videos, frames: range, folder: Path) -> dict:
    """The frames to code of every stream, as files of their own (the encoders read
    whole files): (path, format) by (name, kind)."""
    folder.mkdir(parents=True, exist_ok=True)
    originals = {}
    for (name, kind), video in videos.items():
        path = folder / Path(video.path).name
        with open_writer(path, video.format) as writer:
            for index in frames:
                writer.write(video.read(index))
        originals[(name, kind)] = (path, video.format)
    return originals


def _code(source: Path, fmt: YuvFormat, folder: Path, *, qp: int, settings: EncoderSettings):
    """The bitstream's size in bytes and the decoded video of ``source`` coded at ``qp``."""
    bitstream = folder / (source.stem + ".hevc")
    size = encode_hevc(
        source,
        fmt,
        bitstream,
        qp=qp,
        encoder=settings.encoder,
        preset=settings.preset,
        fps=settings.fps,
    )
    decoded = folder / source.name
    decode_hevc(bitstream, decoded, fmt)
    return size, decoded


def _simulcast(originals, folder: Path, *, qp: int, settings: EncoderSettings, frames: int):
    sizes, decoded = {}, {}
    for key, (path, fmt) in originals.items():
        offset = settings.depth_qp_offset if key[1] == "depth" else 0
        sizes[key], decoded[key] = _code(
            path, fmt, folder, qp=min(51, max(0, qp + offset)), settings=settings
        )
    seconds = frames / settings.fps
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


def _packed(originals, folder: Path, *, qp: int, settings: EncoderSettings, frames: int):
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
        with open_writer(packed, packed_format) as writer:
            pack_frames(writer, readers, layout, range(frames))
    (folder / "decoded").mkdir(exist_ok=True)
    size, decoded_packed = _code(
        packed, packed_format, folder / "decoded", qp=qp, settings=settings
    )
    targets = {key: (folder / path.name, fmt) for key, (path, fmt) in originals.items()}
    with open_video(decoded_packed, packed_format) as video:
        write_unpacked(video, layout, targets, range(frames))
    decoded = {key: path for key, (path, _) in targets.items()}
    rate = size * 8 / (frames / settings.fps) / 1000
    return {"kbps": rate, "texture_kbps": None, "depth_kbps": None, "decoded": decoded}


def _scores(originals, decoded) -> dict:
    """Mean over frames of each stream's Y-PSNR and YUV-PSNR against its original."""
    scores = {}
    for key, (path, fmt) in originals.items():
        with open_video(path, fmt) as reference, open_video(decoded[key], fmt) as test:
            mean = score_videos(reference, test, range(len(reference)), ("psnr",))["mean"]
        scores[f"{key[0]} {key[1]}"] = {"y_psnr": mean["Y-PSNR"], "yuv_psnr": mean.get("YUV-PSNR")}
    return scores


def _synthesis_inputs(config: str | os.PathLike, streams: Mapping) -> dict:
    """Which stream, by (name, kind), stands for each input of the VSRS configuration,
    and the size of its virtual view."""
    params = load_config(VsrsParams, config).params
    by_field = {}
    for camera_field, (texture_field, depth_field) in _SYNTHESIS_INPUTS.items():
        camera = getattr(params, camera_field)
        for field, kind in ((texture_field, "texture"), (depth_field, "depth")):
            if (camera, kind) not in streams:
                raise UsageError(
                    f"--synthesize {config}: its {camera_field} {camera} has no "
                    f"--{'view' if kind == 'texture' else 'depth'} {camera} here"
                )
            by_field[field] = (camera, kind)
    return {
        "config": Path(config),
        "inputs": by_field,
        "size": (params.source_width, params.source_height),
    }


def _synthesize(config: Path, output: Path, inputs: Mapping[str, Path], frames: int) -> None:
    """The virtual view of ``config`` from the first ``frames`` frames of ``inputs``
    (files by VsrsParams field), as ``mvtools synthesize CONFIG Key=Value... -o
    OUTPUT`` writes it: the fields replace the file's keys."""
    synthesize_config(
        config,
        overrides={**inputs, "start_frame": 0, "total_number_of_frames": frames},
        output=output,
    )


def _synthesis_scores(synthesis: dict, decoded: dict, out: Path, folder: Path, frames: int) -> dict:
    """PSNR and IV-PSNR of the virtual view synthesized from the ``decoded`` streams
    against the one synthesized from the originals (made at the first point)."""
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
    fmt = YuvFormat(*synthesis["size"])
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
        from mvtools.metrics.bjontegaard import bd_psnr, bd_rate

        anchor, test = (report["modes"][mode] for mode in MODES)
        rates = [[point["kbps"] for point in points] for points in (anchor, test)]
        quality = [
            [point["mean_texture_yuv_psnr"] for point in points] for points in (anchor, test)
        ]
        report["bjontegaard"] = {
            method: {
                "bd_rate_percent": bd_rate(
                    rates[0], quality[0], rates[1], quality[1], method=method
                ),
                "bd_psnr_db": bd_psnr(rates[0], quality[0], rates[1], quality[1], method=method),
            }
            for method in ("cubic", "pchip")
        }
    return report
