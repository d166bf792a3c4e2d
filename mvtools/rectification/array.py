"""Lens distortion removal and rectification of a pair or a linear array of cameras.

Rectification (the chapter's fig. 1.16) turns every camera about its own centre to one common
orientation and gives them all the same intrinsics, so that the epipolar lines of
any two views become the same image rows:

- the x axis follows the line through the camera centres (the principal direction of
  the centres, for a pair the baseline), pointing the way the cameras' own x axes
  point on average: from the first camera to the last for an array numbered from
  left to right, and still to the right for one numbered from right to left
  (Lovebird), whose pictures would otherwise turn upside down;
- the z axis is the mean optical axis made orthogonal to x, and ``y = cross(z, x)``;
- the intrinsics are ``fx = fy = f``, no skew, one principal point for all cameras.

Only when the centres lie exactly on one line do all rows agree; ``centre_offsets``
reports how far each centre is from the fitted line.

The output focal length and principal point follow ``alpha`` as in
``cv2.stereoRectify`` and ``cv2.getOptimalNewCameraMatrix``. The outline of every
source picture (its border sampled every half pixel, undistorted exactly with
:func:`mvtools.geometry.lens.undistort_normalized`, turned into the output
orientation) bounds the region each camera sees. With ``alpha = 0`` the output
rectangle is the largest one of the output's aspect ratio centred on the inner
rectangle of the outlines (the centre of the band that lies within every outline's
left, right, top and bottom edges) that lies inside every camera's region, so that
every output pixel of every camera samples inside its source picture; with
``alpha = 1`` it is the smallest one centred on the bounding box of all outlines that
holds them all, so that no source pixel is lost; in between its centre and size
are interpolated linearly. The principal point is common to all cameras even when
their own principal points differ: the constraints are per camera, the rectangle
is one.

Pixel centres are at integer coordinates; a picture of ``W x H`` pixels covers
``[0, W - 1] x [0, H - 1]`` (positions where bilinear sampling reads no sample
from outside).
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import cv2
import numpy as np

from mvtools.errors import DataError
from mvtools.geometry.camera import Camera
from mvtools.geometry.lens import project_points, undistort_normalized

__all__ = ["EDGE_TOLERANCE", "Rectification", "cameras_between", "rectify_cameras", "undistortion"]

# Positions this close outside a picture (pixels) still count as inside: float32
# maps of a 2000-pixel picture are exact to about 1e-4.
EDGE_TOLERANCE = 1e-3

# Spacing of the samples on a picture's border (pixels): chords this short depart
# from the undistorted border curve by far less than EDGE_TOLERANCE.
_BORDER_STEP = 0.5

# Pixels mapped per block: bounds the float64 temporaries at a few tens of MB.
_BLOCK_PIXELS = 1 << 18


@dataclass(eq=False)
class Rectification:
    """Cameras turned and resampled to a common model, and the maps that do it.

    Attributes
    ----------
    cameras : list of Camera
        The output cameras: ``K`` (``fx = fy``, no skew; common to all cameras after
        :func:`rectify_cameras`), ``R`` (common after :func:`rectify_cameras`), the
        original centres ``t``, zero distortion, ``size`` the output size; name and
        ``depth_range`` kept.
    maps : list of (ndarray, ndarray)
        Per camera ``(map_x, map_y)``, float32 of shape (H_out, W_out): the source
        (original, distorted) pixel each output pixel samples, for ``cv2.remap``
        (``cv2.initUndistortRectifyMap``).
    homographies : list of ndarray, shape (3, 3)
        Per camera, undistorted source pixel to output pixel:
        ``K_out R_out R_src^T K_src^-1``.
    valid_fraction : list of float
        Per camera, the fraction of output pixels that sample inside the source
        picture (within :data:`EDGE_TOLERANCE`).
    kept_fraction : list of float
        Per camera, the fraction of source pixels that land inside the output picture.
    centre_offsets : ndarray, shape (C,)
        Distance of each centre from the fitted common line, in the unit of the
        centres; zero means exact 1D geometry. NaN after :func:`undistortion`, which
        fits no line.
    rotation_degrees : list of float
        Per camera, the angle it was turned by.
    sources : list of Camera
        The input cameras.
    """

    cameras: list[Camera]
    maps: list[tuple[np.ndarray, np.ndarray]]
    homographies: list[np.ndarray]
    valid_fraction: list[float]
    kept_fraction: list[float]
    centre_offsets: np.ndarray
    rotation_degrees: list[float]
    sources: list[Camera]

    def rectify_points(self, points_px, camera_index: int) -> np.ndarray:
        """Output pixel positions of source (distorted) pixel positions: the inverse of the maps.

        Parameters
        ----------
        points_px : array_like, shape (N, 2)
            ``(u, v)`` in the original picture of camera ``camera_index``.
        camera_index : int

        Returns
        -------
        ndarray, shape (N, 2)
            ``(u, v)`` in the output picture; NaN for rays behind the output camera.
        """
        points = np.asarray(points_px, dtype=np.float64)
        if points.ndim != 2 or points.shape[1] != 2:
            raise ValueError(f"points_px must have shape (N, 2), got {points.shape}")
        if not 0 <= camera_index < len(self.cameras):
            raise ValueError(
                f"camera_index must be in 0..{len(self.cameras) - 1}, got {camera_index}"
            )
        return _to_output(
            self.sources[camera_index], self.cameras[camera_index], points[:, 0], points[:, 1]
        )


# --------------------------------------------------------------------------- arguments


def _check_cameras(cameras, minimum: int) -> list[Camera]:
    cameras = list(cameras)
    if len(cameras) < minimum:
        raise ValueError(
            f"need at least {minimum} camera{'s' if minimum > 1 else ''}, got {len(cameras)}"
        )
    for camera in cameras:
        if camera.size is None:
            raise ValueError(
                f"camera {camera.name!r} has no size; set camera.size = "
                "(width, height) of its pictures"
            )
        width, height = camera.size
        if width < 2 or height < 2:
            raise ValueError(
                f"camera {camera.name!r}: picture size must be at least 2x2, got {width}x{height}"
            )
    return cameras


def _check_alpha(alpha: float) -> float:
    if not 0.0 <= alpha <= 1.0:
        raise ValueError(
            f"alpha must be in [0, 1] (0: only valid pixels, 1: all source pixels), got {alpha}"
        )
    return float(alpha)


def _check_size(size) -> tuple[int, int]:
    width, height = (int(s) for s in size)
    if width < 2 or height < 2:
        raise ValueError(f"output size must be at least 2x2, got {width}x{height}")
    return width, height


def _common_size(cameras: list[Camera], size) -> tuple[int, int]:
    if size is not None:
        return _check_size(size)
    sizes = {tuple(camera.size) for camera in cameras}
    if len(sizes) > 1:
        raise ValueError(
            f"the cameras' picture sizes differ ({sorted(sizes)}); pass "
            "size=(width, height) for the output"
        )
    return _check_size(sizes.pop())


# --------------------------------------------------------------------------- geometry


def _rotation_degrees(rotation: np.ndarray) -> float:
    # atan2 of sine and cosine stays accurate for the tiny angles of a built rig.
    skew = rotation - rotation.T
    sine = np.linalg.norm([skew[2, 1], skew[0, 2], skew[1, 0]]) / 2.0
    return float(np.degrees(np.arctan2(sine, (np.trace(rotation) - 1.0) / 2.0)))


def _common_orientation(cameras: list[Camera]) -> tuple[np.ndarray, np.ndarray]:
    """The rectified rotation (world to camera) and each centre's distance from the line."""
    centres = np.stack([camera.t for camera in cameras])
    scale = max(np.abs(centres).max(), np.ptp(centres, axis=0).max())
    for i in range(len(cameras)):
        for j in range(i + 1, len(cameras)):
            if np.linalg.norm(centres[i] - centres[j]) <= 1e-9 * scale:
                raise ValueError(
                    f"cameras {cameras[i].name!r} and {cameras[j].name!r} have "
                    f"the same centre {centres[i].tolist()}; rectification needs "
                    "distinct centres on a line"
                )
    offsets_from_mean = centres - centres.mean(axis=0)
    direction = np.linalg.svd(offsets_from_mean)[2][0]
    if direction @ np.mean([camera.R[0] for camera in cameras], axis=0) < 0:
        direction = -direction
    mean_axis = np.mean([camera.R[2] for camera in cameras], axis=0)
    forward = mean_axis - (mean_axis @ direction) * direction
    if np.linalg.norm(forward) < 1e-6:
        raise ValueError(
            "the cameras look along the line through their centres; a linear "
            "array must look across it"
        )
    forward /= np.linalg.norm(forward)
    rotation = np.stack([direction, np.cross(forward, direction), forward])
    across = offsets_from_mean - np.outer(offsets_from_mean @ direction, direction)
    return rotation, np.linalg.norm(across, axis=1)


def _border(width: int, height: int) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """A closed loop of points along the border of a picture, and which side each is on."""

    def line(start, stop):
        count = int(np.ceil(abs(stop - start) / _BORDER_STEP)) + 1
        return np.linspace(start, stop, count)[:-1]

    right, bottom = width - 1.0, height - 1.0
    top_u, right_v = line(0.0, right), line(0.0, bottom)
    bottom_u, left_v = line(right, 0.0), line(bottom, 0.0)
    u = np.concatenate([top_u, np.full_like(right_v, right), bottom_u, np.zeros_like(left_v)])
    v = np.concatenate([np.zeros_like(top_u), right_v, np.full_like(bottom_u, bottom), left_v])
    sides = {"top": v == 0.0, "bottom": v == bottom, "left": u == 0.0, "right": u == right}
    return np.stack([u, v], axis=-1), sides


def _normalized(camera: Camera, u: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Undistorted normalised coordinates of pixels of ``camera``, exact (Newton)."""
    K = camera.K
    yd = (v - K[1, 2]) / K[1, 1]
    xd = (u - K[0, 2] - K[0, 1] * yd) / K[0, 0]
    try:
        return undistort_normalized(xd, yd, camera.distortion)
    except ValueError as error:
        raise DataError(f"camera {camera.name!r}: {error}", key=camera.name) from error


def _turned(matrix: np.ndarray, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """``matrix @ [x, y, 1]`` dehomogenised, shape (N, 2); NaN where it points backwards.

    One component at a time: twenty times faster than stacking (N, 3) rays."""
    a, b, w = (matrix[i, 0] * x + matrix[i, 1] * y + matrix[i, 2] for i in range(3))
    with np.errstate(divide="ignore", invalid="ignore"):
        out = np.stack([a / w, b / w], axis=-1)
    out[~(w > 0)] = np.nan
    return out


def _to_output(source: Camera, output: Camera, u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Output pixels of source (distorted) pixels: the exact inverse of the maps."""
    return _turned(output.K @ output.R @ source.R.T, *_normalized(source, u, v))


def _inside(uv: np.ndarray, size) -> np.ndarray:
    width, height = size
    with np.errstate(invalid="ignore"):
        return (
            (uv[..., 0] >= -EDGE_TOLERANCE)
            & (uv[..., 0] <= width - 1 + EDGE_TOLERANCE)
            & (uv[..., 1] >= -EDGE_TOLERANCE)
            & (uv[..., 1] <= height - 1 + EDGE_TOLERANCE)
        )


def _pixel_blocks(width: int, height: int):
    """``(u, v)`` of every pixel of a picture, flat, in bands of rows."""
    step = max(1, _BLOCK_PIXELS // width)
    for start in range(0, height, step):
        v, u = np.mgrid[start : min(height, start + step), 0:width].astype(np.float64)
        yield u.ravel(), v.ravel()


def _chebyshev_distance(point: np.ndarray, loop: np.ndarray) -> float:
    """The smallest max-norm distance from ``point`` to the closed polyline ``loop`` (N, 2)."""
    a = loop - point
    d = np.roll(loop, -1, axis=0) - loop
    # max(|a_x + s d_x|, |a_y + s d_y|) is convex and piecewise linear in s: its minimum
    # over [0, 1] is at an end or where a term vanishes or the two terms are equal.
    with np.errstate(divide="ignore", invalid="ignore"):
        s = np.stack(
            [
                np.zeros(len(a)),
                np.ones(len(a)),
                -a[:, 0] / d[:, 0],
                -a[:, 1] / d[:, 1],
                -(a[:, 0] - a[:, 1]) / (d[:, 0] - d[:, 1]),
                -(a[:, 0] + a[:, 1]) / (d[:, 0] + d[:, 1]),
            ]
        )
    s = np.clip(np.nan_to_num(s, nan=0.0, posinf=0.0, neginf=0.0), 0.0, 1.0)
    distance = np.maximum(np.abs(a[:, 0] + s * d[:, 0]), np.abs(a[:, 1] + s * d[:, 1]))
    return float(distance.min())


def _output_intrinsics(
    sources: list[Camera],
    rotations: list[np.ndarray],
    focal: np.ndarray,
    size: tuple[int, int],
    alpha: float,
) -> np.ndarray:
    """The one output K for ``sources`` turned to ``rotations`` (module docstring).

    Outlines are measured in units of ``focal`` times the normalised image coordinates,
    divided by the output's half size: there the output picture is a square (a ball of
    the max norm) of radius ``1 / zoom``, whatever its aspect ratio.
    """
    half = np.array([(size[0] - 1) / 2.0, (size[1] - 1) / 2.0])
    outlines, sides = [], []
    for source, rotation in zip(sources, rotations):
        border, border_sides = _border(*source.size)
        outline = _turned(rotation @ source.R.T, *_normalized(source, border[:, 0], border[:, 1]))
        if np.any(np.isnan(outline)):
            turn = _rotation_degrees(rotation @ source.R.T)
            raise DataError(
                f"camera {source.name!r} would turn by {turn:.1f} degrees, so far "
                "that part of its picture lies behind the output view",
                key=source.name,
            )
        outlines.append(outline * focal / half)
        sides.append(border_sides)
    everything = np.concatenate(outlines)
    low, high = everything.min(axis=0), everything.max(axis=0)
    centre, radius = (low + high) / 2.0, float(np.max(high - low)) / 2.0
    if alpha < 1.0:
        inner_low = np.array(
            [
                max(o[s["left"], 0].max() for o, s in zip(outlines, sides)),
                max(o[s["top"], 1].max() for o, s in zip(outlines, sides)),
            ]
        )
        inner_high = np.array(
            [
                min(o[s["right"], 0].min() for o, s in zip(outlines, sides)),
                min(o[s["bottom"], 1].min() for o, s in zip(outlines, sides)),
            ]
        )
        inner_centre = (inner_low + inner_high) / 2.0
        inner_radius = min(_chebyshev_distance(inner_centre, outline) for outline in outlines)
        _check_common_view(sources, rotations, inner_centre * half / focal, inner_radius)
        centre = (1.0 - alpha) * inner_centre + alpha * centre
        radius = (1.0 - alpha) * inner_radius + alpha * radius
    f = focal / radius
    principal = half * (1.0 - centre / radius)
    return np.array([[f[0], 0.0, principal[0]], [0.0, f[1], principal[1]], [0.0, 0.0, 1.0]])


def _check_common_view(
    sources: list[Camera], rotations: list[np.ndarray], normalized: np.ndarray, radius: float
) -> None:
    """DataError unless the output ray through ``normalized`` (x, y) hits every picture
    and the rectangle about it is not empty."""
    for source, rotation in zip(sources, rotations):
        ray = rotation.T @ np.array([normalized[0], normalized[1], 1.0])
        uv, z = project_points(source, source.t + ray[None])
        if not (z[0] > 0 and _inside(uv, source.size)[0] and radius > 0):
            names = ", ".join(repr(camera.name) for camera in sources)
            raise DataError(
                f"the pictures of cameras {names} share no common region after "
                f"turning (camera {source.name!r} misses it); alpha = 1 keeps "
                "every picture whole",
                key=source.name,
            )


# --------------------------------------------------------------------------- resampling


def _maps(source: Camera, output: Camera) -> tuple[np.ndarray, np.ndarray]:
    """``cv2.initUndistortRectifyMap`` from ``output`` pixels to ``source`` pixels."""
    coefficients = source.distortion
    without_skew = source.K.copy()
    without_skew[0, 1] = 0.0
    map_x, map_y = cv2.initUndistortRectifyMap(
        without_skew,
        np.pad(coefficients, (0, 5 - coefficients.size)),
        output.R @ source.R.T,
        output.K,
        tuple(output.size),
        cv2.CV_32FC1,
    )
    # OpenCV ignores the skew of the source: u = fx x + s y + cx adds s y = s (v - cy) / fy.
    if source.K[0, 1] != 0.0:
        map_x += np.float32(source.K[0, 1] / source.K[1, 1]) * (map_y - np.float32(source.cy))
    return map_x, map_y


def _resample(
    sources: list[Camera], outputs: list[Camera], centre_offsets: np.ndarray
) -> Rectification:
    maps, homographies, valid, kept, degrees = [], [], [], [], []
    for source, output in zip(sources, outputs):
        map_x, map_y = _maps(source, output)
        inside = _inside(np.stack([map_x, map_y], axis=-1), source.size)
        kept_count = sum(
            int(np.count_nonzero(_inside(_to_output(source, output, u, v), output.size)))
            for u, v in _pixel_blocks(*source.size)
        )
        turn = output.R @ source.R.T
        maps.append((map_x, map_y))
        homographies.append(output.K @ turn @ np.linalg.inv(source.K))
        valid.append(float(np.mean(inside)))
        kept.append(kept_count / (source.size[0] * source.size[1]))
        degrees.append(_rotation_degrees(turn))
    return Rectification(
        cameras=outputs,
        maps=maps,
        homographies=homographies,
        valid_fraction=valid,
        kept_fraction=kept,
        centre_offsets=np.asarray(centre_offsets, dtype=np.float64),
        rotation_degrees=degrees,
        sources=sources,
    )


def _output_camera(source: Camera, K: np.ndarray, R: np.ndarray, size) -> Camera:
    return Camera(
        name=source.name,
        K=K,
        R=R,
        t=source.t.copy(),
        distortion=np.zeros(2),
        size=(int(size[0]), int(size[1])),
        depth_range=source.depth_range,
    )


# --------------------------------------------------------------------------- public


def rectify_cameras(cameras, *, alpha: float = 0.0, size=None) -> Rectification:
    """Rectify a pair or a linear array of cameras (module docstring).

    Parameters
    ----------
    cameras : sequence of Camera
        Two or more cameras with distinct centres, each with ``size`` set; lens
        distortion in ``distortion`` (OpenCV order; MPEG files give k1, k2).
    alpha : float in [0, 1]
        0: every output pixel of every camera samples inside its source picture;
        1: every source pixel lands inside the output picture; in between,
        interpolated.
    size : (width, height), optional
        Output picture size; defaults to the cameras' (common) size.

    Returns
    -------
    Rectification
        Cameras with one ``K`` (``fx = fy`` = the zoom chosen by ``alpha`` times the
        mean ``fy`` of the inputs) and one ``R``, their maps and figures.

    Raises
    ------
    ValueError
        Fewer than 2 cameras, a camera without size, two cameras with the same centre,
        cameras looking along their common line, ``alpha`` outside [0, 1], sizes
        that differ with no ``size`` given.
    DataError
        Lens distortion that cannot be inverted over a picture, a camera turned away
        from the common view, or (``alpha < 1``) pictures with no common region.
    """
    cameras = _check_cameras(cameras, 2)
    alpha = _check_alpha(alpha)
    size = _common_size(cameras, size)
    rotation, centre_offsets = _common_orientation(cameras)
    focal = np.full(2, np.mean([camera.fy for camera in cameras]))
    K = _output_intrinsics(cameras, [rotation] * len(cameras), focal, size, alpha)
    outputs = [_output_camera(camera, K, rotation, size) for camera in cameras]
    return _resample(cameras, outputs, centre_offsets)


def undistortion(cameras, *, alpha: float = 0.0, size=None) -> Rectification:
    """Remove the lens distortion of each camera, which keeps its own orientation.

    Each output camera gets its own ``K``: the source's ``fx`` and ``fy`` times one
    zoom, no skew, and the principal point chosen with the zoom by ``alpha`` (as in
    :func:`rectify_cameras`, for each camera alone).

    Parameters
    ----------
    cameras : sequence of Camera
        One or more cameras, each with ``size`` set.
    alpha : float in [0, 1]
        0: every output pixel samples inside the source picture; 1: every source
        pixel lands inside the output.
    size : (width, height), optional
        Output size of every camera; defaults to each camera's own size.

    Returns
    -------
    Rectification
        ``centre_offsets`` is NaN (no common line is fitted), ``rotation_degrees`` zero.
    """
    cameras = _check_cameras(cameras, 1)
    alpha = _check_alpha(alpha)
    outputs = []
    for camera in cameras:
        out_size = _check_size(camera.size if size is None else size)
        K = _output_intrinsics(
            [camera], [camera.R], np.array([camera.fx, camera.fy]), out_size, alpha
        )
        outputs.append(_output_camera(camera, K, camera.R, out_size))
    return _resample(cameras, outputs, np.full(len(cameras), np.nan))


def cameras_between(cameras, count: int) -> list[Camera]:
    """Virtual cameras evenly spaced between each pair of neighbours of a rectified array.

    Each gets its neighbours' common ``K``, ``R``, size and depth range, and a centre at
    ``k / (count + 1)`` of the way from the left neighbour to the right one
    (``k = 1 .. count``); it is named ``LEFT_RIGHT_k``. These are the virtual views of
    free-viewpoint video between the real ones.

    Parameters
    ----------
    cameras : sequence of Camera
        Rectified cameras in array order (from :func:`rectify_cameras`).
    count : int
        Virtual cameras per pair of neighbours, at least 1.

    Returns
    -------
    list of Camera
        Pair by pair, left to right.
    """
    cameras = list(cameras)
    if count < 1:
        raise ValueError(f"count must be at least 1, got {count}")
    if len(cameras) < 2:
        raise ValueError(
            f"virtual cameras go between neighbours: need 2 cameras, got {len(cameras)}"
        )
    virtual = []
    for left, right in itertools.pairwise(cameras):
        if not (np.allclose(left.K, right.K) and np.allclose(left.R, right.R)):
            raise ValueError(
                f"cameras {left.name!r} and {right.name!r} are not rectified "
                "alike (their K or R differ)"
            )
        for k in range(1, count + 1):
            fraction = k / (count + 1)
            virtual.append(
                Camera(
                    f"{left.name}_{right.name}_{k}",
                    K=left.K,
                    R=left.R,
                    t=(1 - fraction) * left.t + fraction * right.t,
                    size=left.size,
                    depth_range=left.depth_range,
                )
            )
    return virtual
