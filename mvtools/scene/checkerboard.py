"""Synthetic calibration captures: a checkerboard seen by an imperfect rig.

The ground truth is everything a calibration should recover: intrinsics, lens
distortion and poses of the cameras, poses of the board, and the exact image
position of every inner corner (projected through the distortion).

Board coordinates follow OpenCV's ``calibrateCamera`` object points: the first
inner corner at the origin, x along a row of ``inner_corners[0]`` corners, y
along the columns, the board in the plane z = 0. A pose ``(R, t)`` maps board
to world: ``X_world = R @ X_board + t``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mvtools.geometry.camera import Camera
from mvtools.geometry.lens import project_points
from mvtools.scene.content import Plane, Rectangle, Scene, UniformTexture
from mvtools.scene.render import quantize, render
from mvtools.scene.rigs import axis_angle_rotation, intrinsics, linear_rig, perturb_rig


@dataclass(frozen=True)
class Checkerboard:
    """A printed checkerboard with a light border.

    Attributes
    ----------
    inner_corners : (columns, rows)
        Inner corners per row and per column, OpenCV's ``patternSize``; the
        board has one more square than corners each way.
    square_size : float
        Side of a square (metres).
    border : float
        Width of the light margin around the squares (metres).
    dark, light : float
        Grey levels of the squares and the margin, in [0, 1].
    """

    inner_corners: tuple[int, int] = (9, 6)
    square_size: float = 0.05
    border: float = 0.04
    # 0.08 and 0.92 of 255 are no rounding ties (0.1 and 0.9 are: 25.5, 229.5).
    dark: float = 0.08
    light: float = 0.92

    def __post_init__(self):
        if min(self.inner_corners) < 2 or self.square_size <= 0 or self.border < 0:
            raise ValueError("need at least 2x2 inner corners, square_size > 0, border >= 0")

    def object_points(self) -> np.ndarray:
        """Inner corners in board coordinates, row by row, shape (columns * rows, 3)."""
        columns, rows = self.inner_corners
        j, i = np.mgrid[0:rows, 0:columns]
        return np.stack([i.ravel(), j.ravel(), np.zeros(i.size)], axis=-1) * self.square_size

    @property
    def center(self) -> np.ndarray:
        """The middle of the board in board coordinates, shape (3,)."""
        columns, rows = self.inner_corners
        return np.array([(columns - 1) / 2.0, (rows - 1) / 2.0, 0.0]) * self.square_size

    @property
    def extent(self) -> tuple[float, float]:
        """Width and height of the whole board including the border (metres)."""
        columns, rows = self.inner_corners
        return (
            (columns + 1) * self.square_size + 2 * self.border,
            (rows + 1) * self.square_size + 2 * self.border,
        )

    def __call__(self, s: np.ndarray, t: np.ndarray) -> np.ndarray:
        """Grey RGB at board-centred coordinates ``s, t`` (each (N,)), shape (N, 3).

        Used as the texture of :meth:`primitive`, whose texture coordinates are
        measured from the board centre.
        """
        columns, rows = self.inner_corners
        x = np.asarray(s) / self.square_size + (columns - 1) / 2.0
        y = np.asarray(t) / self.square_size + (rows - 1) / 2.0
        inside = (x >= -1) & (x < columns) & (y >= -1) & (y < rows)
        dark = inside & ((np.floor(x) + np.floor(y)) % 2 == 0)
        grey = np.where(dark, self.dark, self.light)
        return np.repeat(grey[:, None], 3, axis=1)

    def primitive(self, rotation: np.ndarray, translation: np.ndarray) -> Rectangle:
        """The board placed at pose ``(rotation, translation)`` as a scene primitive."""
        rotation = np.asarray(rotation, dtype=np.float64)
        width, height = self.extent
        return Rectangle(
            "checkerboard",
            center=rotation @ self.center + translation,
            half_u=rotation[:, 0] * width / 2.0,
            half_v=rotation[:, 1] * height / 2.0,
            texture=self,
        )


@dataclass(eq=False)
class CheckerboardCaptures:
    """Rendered calibration captures with their ground truth.

    Attributes
    ----------
    cameras : list of Camera
        The true cameras (K, distortion, pose, size).
    board : Checkerboard
    rotations : ndarray, shape (P, 3, 3)
        Board-to-world rotation per capture.
    translations : ndarray, shape (P, 3)
        Board origin (first inner corner) in world coordinates per capture.
    images : ndarray, shape (C, P, H, W), uint8
        Grey capture of camera ``c`` at instant ``p``.
    corners : ndarray, shape (C, P, N, 2)
        Exact pixel position of every inner corner (order of
        :meth:`Checkerboard.object_points`), also for boards partly out of view.
    visible : ndarray, shape (C, P), bool
        True where every inner corner lies inside the image with a margin, in
        front of the camera.
    """

    cameras: list
    board: Checkerboard
    rotations: np.ndarray
    translations: np.ndarray
    images: np.ndarray
    corners: np.ndarray
    visible: np.ndarray


def calibration_rig(
    *,
    n: int = 5,
    size: tuple[int, int] = (640, 480),
    focal: float | None = None,
    baseline: float = 0.1,
    seed: int = 0,
) -> list[Camera]:
    """A rig of ``n`` nearly parallel cameras, as built: rotations up to 2 degrees,
    principal points within 12 px of the centre, focal lengths within 3 % of
    ``focal`` (default ``0.875 * width``, 560 px at 640, a 60 degree field of view;
    fx and fy within 0.3 %), k1 in [-0.1, 0.1] and k2 in [-0.02, 0.02]."""
    width, height = size
    focal = 0.875 * width if focal is None else focal
    K = intrinsics(fx=focal, cx=(width - 1) / 2.0, cy=(height - 1) / 2.0)
    nominal = linear_rig(n, baseline=baseline, K=K, size=size)
    return perturb_rig(
        nominal,
        seed=seed,
        rotation_degrees=2.0,
        principal_point_pixels=12.0,
        focal_fraction=0.03,
        k1_range=(-0.1, 0.1),
        k2_range=(-0.02, 0.02),
    )


def corner_visibility(
    cameras, board: Checkerboard, rotations, translations, *, margin: float = 10.0
) -> tuple[np.ndarray, np.ndarray]:
    """Projected inner corners and full-visibility flags.

    Returns
    -------
    corners : ndarray, shape (C, P, N, 2)
    visible : ndarray, shape (C, P), bool
    """
    points = board.object_points()
    corners = np.empty((len(cameras), len(rotations), len(points), 2))
    visible = np.zeros((len(cameras), len(rotations)), dtype=bool)
    for c, camera in enumerate(cameras):
        width, height = camera.size
        for p, (rotation, translation) in enumerate(zip(rotations, translations)):
            uv, z = project_points(camera, points @ np.asarray(rotation).T + translation)
            corners[c, p] = uv
            visible[c, p] = bool(
                np.all(z > 0)
                and np.all(uv >= margin)
                and np.all(uv[:, 0] <= width - 1 - margin)
                and np.all(uv[:, 1] <= height - 1 - margin)
            )
    return corners, visible


def board_poses(
    count: int,
    cameras,
    board: Checkerboard,
    *,
    seed: int,
    tilt_degrees: tuple[float, float] = (10.0, 40.0),
    roll_degrees: float = 20.0,
    distance: tuple[float, float] = (0.7, 1.1),
    lateral: float = 0.3,
    min_views: int = 2,
    max_attempts: int = 10000,
) -> tuple[np.ndarray, np.ndarray]:
    """Random, well-conditioned board poses in front of the rig.

    Each pose tilts the board out of the image plane by an angle drawn from
    ``tilt_degrees`` about a random in-plane axis, rolls it by up to
    ``roll_degrees`` in its plane, and places its centre at a depth drawn from
    ``distance`` with lateral offsets up to ``lateral * depth`` (so the board
    leaves the outer cameras' view now and then). Poses seen in full by fewer
    than ``min_views`` cameras are drawn again.

    Returns
    -------
    rotations : ndarray, shape (count, 3, 3)
    translations : ndarray, shape (count, 3)
    """
    rng = np.random.default_rng(seed)
    rig_center = np.mean([camera.t for camera in cameras], axis=0)
    rotations, translations = [], []
    for _ in range(max_attempts):
        if len(rotations) == count:
            break
        heading = rng.uniform(0.0, 2.0 * np.pi)
        tilt = axis_angle_rotation(
            (np.cos(heading), np.sin(heading), 0.0), rng.uniform(*tilt_degrees)
        )
        rotation = tilt @ axis_angle_rotation(
            (0.0, 0.0, 1.0), rng.uniform(-roll_degrees, roll_degrees)
        )
        depth = rng.uniform(*distance)
        center = rig_center + np.array(
            [
                rng.uniform(-lateral, lateral) * depth,
                rng.uniform(-lateral, lateral) * depth * 0.75,
                depth,
            ]
        )
        translation = center - rotation @ board.center
        _, visible = corner_visibility(cameras, board, rotation[None], translation[None])
        if visible.sum() >= min_views:
            rotations.append(rotation)
            translations.append(translation)
    if len(rotations) < count:
        raise ValueError(
            f"found only {len(rotations)} of {count} board poses seen by "
            f"{min_views} cameras in {max_attempts} attempts"
        )
    return np.array(rotations), np.array(translations)


def capture_checkerboard(
    cameras,
    board: Checkerboard,
    rotations,
    translations,
    *,
    samples: int = 8,
    noise: float = 1.0,
    backdrop: float = 0.45,
    seed: int | tuple[int, ...] = 0,
) -> CheckerboardCaptures:
    """Render every camera at every board pose.

    Parameters
    ----------
    cameras : sequence of Camera
        With sizes; the captures use each camera's distortion.
    board : Checkerboard
    rotations : ndarray, shape (P, 3, 3)
    translations : ndarray, shape (P, 3)
    samples : int
        Supersampling per axis at square edges (adaptive: uniform areas are exact).
    noise : float
        Standard deviation of the added Gaussian noise, in grey levels (0-255).
    backdrop : float
        Grey level of the flat wall 3 m behind the rig's origin.
    seed : int or sequence of int
        Seed of the noise; camera ``c`` at pose ``p`` draws from ``(*seed, c, p)``.

    Returns
    -------
    CheckerboardCaptures
    """
    rotations = np.asarray(rotations, dtype=np.float64).reshape(-1, 3, 3)
    translations = np.asarray(translations, dtype=np.float64).reshape(-1, 3)
    wall = Plane(
        "backdrop",
        point=(0.0, 0.0, 3.0),
        normal=(0.0, 0.0, -1.0),
        u_axis=(1.0, 0.0, 0.0),
        texture=UniformTexture((backdrop,) * 3),
    )
    sizes = {tuple(camera.size) for camera in cameras}
    if len(sizes) != 1:
        raise ValueError(f"all cameras need the same size, got {sorted(sizes)}")
    width, height = sizes.pop()
    images = np.empty((len(cameras), len(rotations), height, width), dtype=np.uint8)
    for p, (rotation, translation) in enumerate(zip(rotations, translations)):
        scene = Scene((wall, board.primitive(rotation, translation)))
        for c, camera in enumerate(cameras):
            grey = render(scene, camera, samples=samples, adaptive_tolerance=1e-9).color[..., 0]
            rng = np.random.default_rng([*np.atleast_1d(seed).tolist(), c, p])
            images[c, p] = quantize(grey + rng.normal(0.0, noise / 255.0, grey.shape))
    corners, visible = corner_visibility(cameras, board, rotations, translations)
    return CheckerboardCaptures(
        cameras=list(cameras),
        board=board,
        rotations=rotations,
        translations=translations,
        images=images,
        corners=corners,
        visible=visible,
    )
