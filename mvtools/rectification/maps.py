"""Resampling through rectification maps: image planes, chroma planes, depth maps.

A map pair ``(map_x, map_y)`` gives, for every output pixel, the position in the
source image it samples (pixel centres at integer coordinates, the convention of
``cv2.remap``). Textures are sampled bilinearly; depth maps by nearest neighbour, so
that no depth value is invented between a foreground and a background surface.
"""

from __future__ import annotations

import cv2
import numpy as np

from mvtools.geometry.camera import Camera
from mvtools.geometry.lens import pixel_rays

__all__ = ["CHROMA_SITING", "chroma_maps", "rectified_depth", "remap_plane"]

# Position of chroma sample (0, 0) on the luma grid, per subsampling (horizontal,
# vertical): MPEG-2 / H.264 / HEVC default (chroma_sample_loc_type 0): co-sited
# with the even luma column, for 4:2:0 centred between the two luma rows.
CHROMA_SITING = {(1, 1): (0.0, 0.0), (2, 1): (0.0, 0.0), (2, 2): (0.0, 0.5)}

_PLANE_DTYPES = (np.uint8, np.uint16, np.float32, np.float64)


def _check_maps(map_x: np.ndarray, map_y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    map_x = np.asarray(map_x)
    map_y = np.asarray(map_y)
    if map_x.ndim != 2 or map_x.shape != map_y.shape:
        raise ValueError(
            f"map_x and map_y must be 2-D arrays of one shape, got {map_x.shape} and {map_y.shape}"
        )
    return map_x, map_y


def _check_plane(plane: np.ndarray, what: str = "plane") -> np.ndarray:
    plane = np.asarray(plane)
    if plane.ndim != 2:
        raise ValueError(f"{what} must be 2-D (H, W), got shape {plane.shape}")
    if plane.dtype.type not in _PLANE_DTYPES:
        raise ValueError(f"{what} must be uint8, uint16, float32 or float64, got {plane.dtype}")
    return plane


def _nearest_pixels(
    map_x, map_y, width: int, height: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The source pixel nearest to each map position, and whether it exists.

    Parameters
    ----------
    map_x, map_y : ndarray, shape (H_out, W_out)
        Source positions.
    width, height : int
        Size of the source image.

    Returns
    -------
    column, row : ndarray of intp, shape (H_out, W_out)
        ``floor(map + 0.5)``, clipped into the image (meaningless where not ``inside``).
    inside : ndarray of bool, shape (H_out, W_out)
        The rounded position lies in the image (NaN positions never do).
    """
    map_x, map_y = _check_maps(map_x, map_y)
    with np.errstate(invalid="ignore"):
        column = np.floor(map_x.astype(np.float64) + 0.5)
        row = np.floor(map_y.astype(np.float64) + 0.5)
        inside = (column >= 0) & (column <= width - 1) & (row >= 0) & (row <= height - 1)
    column = np.where(inside, column, 0).astype(np.intp)
    row = np.where(inside, row, 0).astype(np.intp)
    return column, row, inside


def remap_plane(plane, map_x, map_y, *, nearest: bool = False, fill=0) -> np.ndarray:
    """Resample one image plane through a map pair.

    Parameters
    ----------
    plane : ndarray, shape (H, W), uint8, uint16, float32 or float64
        The source plane (a luma or chroma plane, a depth map).
    map_x, map_y : ndarray, shape (H_out, W_out), float32 or float64
        Source position of every output sample.
    nearest : bool
        False: bilinear (``cv2.INTER_LINEAR``; samples within one pixel of the border
        blend with ``fill``). True: the value of the nearest source sample
        (``floor(map + 0.5)``), never a mix of two, for depth maps.
    fill : scalar
        Value of output samples whose position is outside the source.

    Returns
    -------
    ndarray, shape (H_out, W_out), the dtype of ``plane``
    """
    plane = _check_plane(plane)
    map_x, map_y = _check_maps(map_x, map_y)
    if nearest:
        column, row, inside = _nearest_pixels(map_x, map_y, plane.shape[1], plane.shape[0])
        return np.where(inside, plane[row, column], np.asarray(fill, dtype=plane.dtype))
    return cv2.remap(
        plane,
        map_x.astype(np.float32, copy=False),
        map_y.astype(np.float32, copy=False),
        interpolation=cv2.INTER_LINEAR,
        borderMode=cv2.BORDER_CONSTANT,
        borderValue=float(fill),
    )


def _linear_at(values: np.ndarray, positions: np.ndarray, axis: int) -> np.ndarray:
    """``values`` linearly interpolated at fractional indices ``positions`` along ``axis``,
    extrapolated from the last two samples past the end (odd picture sizes)."""
    count = values.shape[axis]
    if count == 1:
        return np.take(values, np.zeros(len(positions), dtype=np.intp), axis=axis)
    lower = np.clip(np.floor(positions).astype(np.intp), 0, count - 2)
    weight = positions - lower
    shape = [1, 1]
    shape[axis] = len(positions)
    weight = weight.reshape(shape)
    return (
        np.take(values, lower, axis=axis) * (1.0 - weight)
        + np.take(values, lower + 1, axis=axis) * weight
    )


def chroma_maps(map_x, map_y, *, subsampling: tuple[int, int]) -> tuple[np.ndarray, np.ndarray]:
    """The maps of the chroma planes, at the chroma resolution, for a luma map pair.

    Chroma sample ``(i, j)`` (row, column) sits on the luma grid at
    ``(sx j + ox, sy i + oy)`` with ``(sx, sy) = subsampling`` and ``(ox, oy)`` from
    :data:`CHROMA_SITING`: the MPEG-2 / H.264 / HEVC default siting
    (``chroma_sample_loc_type`` 0), co-sited horizontally with the even luma
    columns and, for 4:2:0, centred vertically between two luma rows
    (``oy = 0.5``). The luma map is read at the output chroma sample's luma
    position (linear interpolation between luma rows), and the source luma
    position it gives is turned back into source chroma coordinates.

    Parameters
    ----------
    map_x, map_y : ndarray, shape (H, W)
        Luma maps (source luma position of each output luma pixel).
    subsampling : (int, int)
        Horizontal and vertical chroma subsampling: (2, 2) for 4:2:0, (2, 1) for
        4:2:2, (1, 1) for 4:4:4.

    Returns
    -------
    chroma_x, chroma_y : ndarray of float32, shape (ceil(H / sy), ceil(W / sx))
        Source chroma position of each output chroma sample.
    """
    map_x, map_y = _check_maps(map_x, map_y)
    subsampling = tuple(int(s) for s in subsampling)
    if subsampling not in CHROMA_SITING:
        raise ValueError(
            f"subsampling must be (2, 2) for 4:2:0, (2, 1) for 4:2:2 or (1, 1) "
            f"for 4:4:4, got {subsampling}"
        )
    (sx, sy), (ox, oy) = subsampling, CHROMA_SITING[subsampling]
    height, width = map_x.shape
    rows = sy * np.arange(-(-height // sy)) + oy
    columns = sx * np.arange(-(-width // sx)) + ox
    out = []
    for luma_map, scale, offset in ((map_x, sx, ox), (map_y, sy, oy)):
        at_chroma = _linear_at(_linear_at(luma_map.astype(np.float64), rows, 0), columns, 1)
        out.append(((at_chroma - offset) / scale).astype(np.float32))
    return out[0], out[1]


class DepthResampler:
    """Depth maps of ``source`` resampled into ``rectified``, as depth along the new axis.

    Each output pixel takes the depth of the source pixel nearest to its map position
    (no interpolation across depth edges). That pixel's point
    ``X = t + z R_src^T K_src^-1 [x_u, y_u, 1]`` (``x_u, y_u`` its undistorted
    normalised coordinates) gets the depth ``z' = (R_rect (X - t))_z`` along the
    rectified camera's axis: ``z`` changes when the camera turns. The sampled pixels
    and their factors ``z' / z`` are found once, for every frame of a video.

    Parameters
    ----------
    source : Camera
        The camera the depth maps belong to (lens distortion included).
    rectified : Camera
        The output camera; must share ``source``'s centre.
    map_x, map_y : ndarray, shape (H_out, W_out)
        The maps from ``rectified`` to ``source`` pixels.
    fill : float
        Depth of output pixels that sample outside the source image; ``inf`` (no
        surface) becomes the farthest value under
        :func:`mvtools.geometry.depth.z_to_depth`.
    """

    def __init__(self, source: Camera, rectified: Camera, map_x, map_y, *, fill: float = np.inf):
        if source.size is None:
            raise ValueError(f"camera {source.name!r} needs its size")
        if not np.allclose(
            source.t, rectified.t, rtol=0.0, atol=1e-12 * max(1.0, float(np.abs(source.t).max()))
        ):
            raise ValueError(
                f"camera {rectified.name!r} does not share the centre of "
                f"{source.name!r}: {rectified.t.tolist()} != {source.t.tolist()}"
            )
        self.source, self.fill = source, float(fill)
        column, row, self.inside = _nearest_pixels(map_x, map_y, *source.size)
        self.column, self.row = column[self.inside], row[self.inside]
        # Each source pixel's ray, with unit depth along the source axis, measured along
        # the rectified axis: the factor that turns z into z'.
        rays = pixel_rays(source, self.column.astype(np.float64), self.row.astype(np.float64))
        self.factor = rays @ rectified.R[2]

    def __call__(self, depth_z) -> np.ndarray:
        """One depth map.

        Parameters
        ----------
        depth_z : ndarray, shape (H, W), float
            Depth along ``source``'s axis (metres, DepthType 0), ``inf`` allowed.

        Returns
        -------
        ndarray of float64, shape (H_out, W_out)
        """
        depth_z = _check_plane(depth_z, "depth_z")
        if not np.issubdtype(depth_z.dtype, np.floating):
            raise ValueError(
                f"depth_z must hold float depths z, got {depth_z.dtype} (convert "
                "depth map values with mvtools.geometry.depth.depth_to_z)"
            )
        width, height = self.source.size
        if depth_z.shape != (height, width):
            raise ValueError(
                f"depth_z has shape {depth_z.shape}, camera {self.source.name!r} "
                f"makes {width}x{height} pictures"
            )
        out = np.full(self.inside.shape, self.fill, dtype=np.float64)
        out[self.inside] = depth_z[self.row, self.column] * self.factor
        return out


def rectified_depth(
    depth_z, source: Camera, rectified: Camera, map_x, map_y, *, fill: float = np.inf
) -> np.ndarray:
    """One depth map through a :class:`DepthResampler` (which see); videos keep the
    resampler for all their frames."""
    return DepthResampler(source, rectified, map_x, map_y, fill=fill)(depth_z)
