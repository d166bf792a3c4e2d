"""``mvtools encode``: rate-distortion experiments with a real HEVC encoder, simulcast
against frame-compatible packing, with Bjontegaard deltas and the MPEG evaluation of
compressed multiview plus depth through view synthesis."""

from __future__ import annotations

import click

from mvtools.cli.options import (
    POSITIVE,
    ProgramCommand,
    depth_video_option,
    frame_range_options,
    program,
    video_format_options,
    view_option,
)
from mvtools.cli.progress import Progress
from mvtools.io.encoders import ENCODERS
from mvtools.run.encode import MODES, EncoderSettings, rd_experiment


@click.command(name="encode", cls=ProgramCommand)
@view_option("The texture video of camera NAME (repeatable).", required=True)
@depth_video_option(
    "The depth video of camera NAME (repeatable): simulcast codes it as a stream of "
    "its own, packing puts it into the atlas."
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
    report = rd_experiment(
        views,
        qps,
        out_dir,
        depths=depths,
        modes=modes or MODES,
        settings=EncoderSettings(
            encoder=encoder, preset=preset, fps=fps, depth_qp_offset=depth_qp_offset
        ),
        synthesis_config=synthesis_config,
        size=size,
        pix_fmt=pix_fmt,
        start_frame=start_frame,
        frame_count=frame_count,
        progress=Progress(None, "rate points done"),
    )
    click.echo(_table(report))


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
