"""Bitrates for planning a multiview system: the raw bitrate of a camera array (the chapter's
eq. 1.7) and the compressed estimate per codec generation (the chapter's eq. 1.21-1.22).

The compressed estimate scales a codec's typical bitrate for one HD view (1920x1080,
25 frames/s, 8-bit 4:2:0, broadcast quality) by the pixel rate, and multiplies by the
number of views for simulcast: each generation needs about half the rate of the one
before (MPEG-2, AVC, HEVC, VVC), HEVC about 4 Mbit/s per HD view. These are
planning figures, not measurements: `mvtools pack --encode` measures.
"""

from __future__ import annotations

import math

__all__ = ["CHROMA_SAMPLES", "HD_BITRATES", "compressed_bitrate", "raw_bitrate"]

# Samples per pixel, luma plus both chroma planes.
CHROMA_SAMPLES = {"420": 1.5, "422": 2.0, "444": 3.0, "400": 1.0}

# Typical bit/s of one 1920x1080 25 frames/s 8-bit 4:2:0 view at broadcast quality.
HD_BITRATES = {"mpeg2": 16e6, "avc": 8e6, "hevc": 4e6, "vvc": 2e6}
_HD_PIXEL_RATE = 1920 * 1080 * 25


def _check(width, height, fps, views):
    if width < 1 or height < 1 or not 0 < fps < math.inf or views < 1:
        raise ValueError(
            f"need a positive size, frame rate and view count, got {width}x{height}, "
            f"{fps} frames/s, {views} views"
        )


def raw_bitrate(
    width: int, height: int, *, fps: float, views: int = 1, bits: int = 8, chroma: str = "420"
) -> float:
    """Bit/s of uncompressed video from ``views`` cameras (the chapter's eq. 1.7).

    ``width * height * samples per pixel * bits * fps * views``; nine HD cameras at
    8-bit 4:2:0 and 25 frames/s give 5.6 Gbit/s.
    """
    _check(width, height, fps, views)
    if chroma not in CHROMA_SAMPLES:
        raise ValueError(f"chroma must be one of {', '.join(CHROMA_SAMPLES)}, got {chroma!r}")
    return width * height * CHROMA_SAMPLES[chroma] * bits * fps * views


def compressed_bitrate(
    width: int, height: int, *, fps: float, views: int = 1, codec: str = "hevc"
) -> float:
    """Estimated bit/s of ``views`` views coded one by one (simulcast) with ``codec``
    (the chapter's eq. 1.21-1.22): ten HD views with HEVC need about 40 Mbit/s."""
    _check(width, height, fps, views)
    if codec not in HD_BITRATES:
        raise ValueError(f"codec must be one of {', '.join(HD_BITRATES)}, got {codec!r}")
    return HD_BITRATES[codec] * width * height * fps / _HD_PIXEL_RATE * views
