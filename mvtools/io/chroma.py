"""The chroma formats of planar YUV pictures: how many luma samples a chroma sample covers.

4:2:0 halves the chroma planes both ways, 4:2:2 horizontally, 4:4:4 keeps them at the luma
size and 4:0:0 has none (grey pictures, depth maps). A halved plane of an odd size rounds
up: the chroma of a ``W x H`` 4:2:0 picture is ``ceil(W/2) x ceil(H/2)``, as ffmpeg and the
MPEG reference programs store it.
"""

from __future__ import annotations

__all__ = ["CHROMA_FORMATS", "CHROMA_SUBSAMPLING", "chroma_plane_shape"]

#: Luma samples per chroma sample, (horizontally, vertically); None: no chroma planes.
CHROMA_SUBSAMPLING: dict[str, tuple[int, int] | None] = {
    "420": (2, 2),
    "422": (2, 1),
    "444": (1, 1),
    "400": None,
}

#: The chroma formats, by their ffmpeg-style names.
CHROMA_FORMATS = tuple(CHROMA_SUBSAMPLING)


def chroma_plane_shape(luma_shape: tuple[int, int], chroma: str) -> tuple[int, int] | None:
    """(rows, columns) of each chroma plane of a picture.

    Parameters
    ----------
    luma_shape : (rows, columns)
        The luma plane's shape.
    chroma : {"420", "422", "444", "400"}

    Returns
    -------
    (rows, columns) or None
        None for 4:0:0, which has no chroma planes.

    Raises
    ------
    KeyError
        For a name not in :data:`CHROMA_FORMATS`.

    Examples
    --------
    >>> chroma_plane_shape((1081, 1921), "420")
    (541, 961)
    >>> chroma_plane_shape((1080, 1920), "422")
    (1080, 960)
    """
    factors = CHROMA_SUBSAMPLING[chroma]
    if factors is None:
        return None
    rows, columns = luma_shape
    horizontal, vertical = factors
    return -(-rows // vertical), -(-columns // horizontal)
