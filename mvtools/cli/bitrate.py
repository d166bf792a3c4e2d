"""``mvtools bitrate``: raw and compressed bitrates of a camera array, for planning."""

from __future__ import annotations

import click

from mvtools.cli.options import POSITIVE, ProgramCommand, parse_size, program
from mvtools.pack.bitrate import (
    CHROMA_SAMPLES,
    HD_BITRATES,
    compressed_bitrate,
    raw_bitrate,
)


@click.command(name="bitrate", cls=ProgramCommand)
@click.option(
    "--size",
    callback=parse_size,
    required=True,
    metavar="WxH",
    help="Picture size of a view, e.g. 1920x1080.",
)
@click.option("--fps", type=POSITIVE, required=True, help="Frames per second.")
@click.option(
    "--views",
    type=click.IntRange(min=1),
    default=1,
    show_default=True,
    help="Number of cameras (views).",
)
@click.option(
    "--bits", type=click.IntRange(8, 16), default=8, show_default=True, help="Bits per sample."
)
@click.option(
    "--chroma",
    type=click.Choice(tuple(CHROMA_SAMPLES)),
    default="420",
    show_default=True,
    help="Chroma subsampling.",
)
@program
def command(size, fps, views, bits, chroma):
    """The raw bitrate of VIEWS cameras (the chapter's eq. 1.7) and the compressed estimate for
    simulcast with each codec generation (the chapter's eq. 1.21-1.22: about half the rate per
    generation, HEVC about 4 Mbit/s per HD view at 25 frames/s)."""
    width, height = size
    raw = raw_bitrate(width, height, fps=fps, views=views, bits=bits, chroma=chroma)
    lines = [
        f"raw: {raw / 1e9:.3f} Gbit/s ({views} x {width}x{height}, {bits}-bit {chroma}, "
        f"{fps:g} frames/s)"
    ]
    for codec in HD_BITRATES:
        rate = compressed_bitrate(width, height, fps=fps, views=views, codec=codec)
        lines.append(
            f"{codec:6s} simulcast: {rate / 1e6:8.1f} Mbit/s (compression {raw / rate:.0f}:1)"
        )
    click.echo("\n".join(lines))
