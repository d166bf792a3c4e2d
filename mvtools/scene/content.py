"""What the synthetic scene is made of: textures, primitives, motion.

World coordinates follow the camera convention of :mod:`mvtools.geometry.camera`
for a camera at the origin with ``R = I``: x to the right, y *down*, z forward,
in metres. The ground is therefore the plane ``y = +ground_y`` below the cameras.

Every primitive intersects rays analytically and carries a texture evaluated in
surface coordinates (metres along the surface), so a surface point has the same
colour from every viewpoint. Shading is Lambertian under one directional light:
view-independent too. Moving primitives translate by ``velocity`` metres per
frame and carry their texture along.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Protocol

import numba
import numpy as np

# Ray parameters below this are the ray's own origin (self-intersection guard).
_T_MIN = 1e-9

Texture = Callable[[np.ndarray, np.ndarray], np.ndarray]
"""A texture maps surface coordinates ``s, t`` (each shape (N,), metres) to RGB
in [0, 1], shape (N, 3)."""


# --------------------------------------------------------------------------- textures

_MASK32 = np.uint64(0xFFFFFFFF)


@numba.njit(cache=True, nogil=True)
def _lattice_hash(i, j, seed):
    """A well-mixed 32-bit value per integer lattice point (murmur3 finaliser)."""
    h = (
        (np.uint64(i & 0xFFFFFFFF) * np.uint64(0x8DA6B343))
        ^ (np.uint64(j & 0xFFFFFFFF) * np.uint64(0xD8163841))
        ^ seed
    ) & _MASK32
    h ^= h >> np.uint64(16)
    h = (h * np.uint64(0x85EBCA6B)) & _MASK32
    h ^= h >> np.uint64(13)
    h = (h * np.uint64(0xC2B2AE35)) & _MASK32
    return h ^ (h >> np.uint64(16))


@numba.njit(cache=True, nogil=True)
def _fractal_kernel(s, t, seeds, scales, offsets, weights):
    # A compiled loop: the numpy form of this sum (per octave, per corner, per
    # channel temporaries) made texturing ten times slower than ray casting.
    out = np.zeros((s.shape[0], 3))
    for k in range(seeds.shape[0]):
        for p in range(s.shape[0]):
            x = s[p] * scales[k] + offsets[k]
            y = t[p] * scales[k] + 1.6 * offsets[k]
            xf = np.floor(x)
            yf = np.floor(y)
            fx = x - xf
            fy = y - yf
            i = np.int64(xf)
            j = np.int64(yf)
            # Quintic fade: C2-continuous noise, no creases at lattice lines.
            wx = fx * fx * fx * (fx * (fx * 6.0 - 15.0) + 10.0)
            wy = fy * fy * fy * (fy * (fy * 6.0 - 15.0) + 10.0)
            h00 = _lattice_hash(i, j, seeds[k])
            h10 = _lattice_hash(i + 1, j, seeds[k])
            h01 = _lattice_hash(i, j + 1, seeds[k])
            h11 = _lattice_hash(i + 1, j + 1, seeds[k])
            for c in range(3):
                shift = np.uint64(8 * c)
                v00 = np.float64((h00 >> shift) & np.uint64(255))
                v10 = np.float64((h10 >> shift) & np.uint64(255))
                v01 = np.float64((h01 >> shift) & np.uint64(255))
                v11 = np.float64((h11 >> shift) & np.uint64(255))
                top = v00 + (v10 - v00) * wx
                bottom = v01 + (v11 - v01) * wx
                out[p, c] += weights[k] * (top + (bottom - top) * wy) * (1.0 / 255.0)
    return out


def fractal_noise(
    s: np.ndarray,
    t: np.ndarray,
    *,
    seed: int,
    frequency: float = 1.0,
    octaves: int = 1,
    persistence: float = 0.5,
) -> np.ndarray:
    """Three channels of smooth fractal value noise.

    Octave ``k`` is value noise on a lattice of spacing ``1 / (frequency * 2**k)``
    with weight ``persistence**k``; lattice values are bytes of a hash of the
    lattice point, interpolated with the quintic fade (C2-continuous).

    Parameters
    ----------
    s, t : ndarray, shape (N,)
        Surface coordinates.
    seed : int
        Selects an independent noise field.
    frequency : float
        Lattice cells per unit of ``s, t`` of the coarsest octave.
    octaves : int
    persistence : float

    Returns
    -------
    ndarray, shape (N, 3)
        The weighted mean over octaves, in [0, 1] (1 octave: plain value noise).
    """
    k = np.arange(octaves)
    weights = persistence ** k.astype(np.float64)
    # Octave seeds mixed in Python (unbounded ints), then cut to 32 bits.
    seeds = np.array([((seed * 131 + j) * 0x9E3779B1) & 0xFFFFFFFF for j in k], dtype=np.uint64)
    total = _fractal_kernel(
        np.ascontiguousarray(s, dtype=np.float64).reshape(-1),
        np.ascontiguousarray(t, dtype=np.float64).reshape(-1),
        seeds,
        frequency * 2.0**k,
        0.37 * k,
        weights,
    )
    return total / weights.sum()


@dataclass(frozen=True)
class NoiseTexture:
    """Coloured fractal value noise with an optional structured pattern.

    Channel 0 of the noise mixes ``colors[0]`` and ``colors[1]``, channel 1
    modulates brightness by ``1 ± contrast``, channel 2 adds a faint hue jitter.
    Octave ``k`` has ``frequency * 2**k`` lattice cells per metre and weight
    ``persistence**k``; keep the finest octave coarser than two pixels on the
    nearest surface (anti-aliasing is by supersampling only).

    The pattern ("checker", "stripes" or "bricks", period in metres) darkens
    part of the surface by ``pattern_strength``: sharp, structured edges that
    stereo matching and colour checks can latch onto.
    """

    seed: int
    colors: tuple[tuple[float, float, float], tuple[float, float, float]]
    frequency: float = 1.0
    octaves: int = 5
    persistence: float = 0.7
    contrast: float = 0.45
    pattern: str | None = None
    pattern_period: float = 0.5
    pattern_strength: float = 0.25

    def __post_init__(self):
        if self.pattern not in (None, "checker", "stripes", "bricks"):
            raise ValueError(
                f"pattern must be None, 'checker', 'stripes' or 'bricks', got {self.pattern!r}"
            )
        if self.octaves < 1 or self.frequency <= 0 or self.pattern_period <= 0:
            raise ValueError("octaves must be >= 1, frequency and pattern_period > 0")

    def __call__(self, s: np.ndarray, t: np.ndarray) -> np.ndarray:
        s = np.asarray(s, dtype=np.float64)
        t = np.asarray(t, dtype=np.float64)
        noise = fractal_noise(
            s,
            t,
            seed=self.seed,
            frequency=self.frequency,
            octaves=self.octaves,
            persistence=self.persistence,
        )
        # A weighted mean of independent values concentrates near 0.5: stretch back.
        noise = np.clip(0.5 + 2.0 * (noise - 0.5), 0.0, 1.0)
        low, high = (np.asarray(c, dtype=np.float64) for c in self.colors)
        rgb = low + (high - low) * noise[:, :1]
        rgb = rgb * (1.0 + self.contrast * (2.0 * noise[:, 1:2] - 1.0))
        rgb = rgb + 0.06 * (noise[:, 2:3] - 0.5) * np.array([1.0, -0.5, -0.5])
        if self.pattern is not None:
            rgb = rgb * (1.0 - self.pattern_strength * self._pattern(s, t))[:, None]
        return np.clip(rgb, 0.0, 1.0)

    def _pattern(self, s: np.ndarray, t: np.ndarray) -> np.ndarray:
        a = s / self.pattern_period
        b = t / self.pattern_period
        if self.pattern == "checker":
            return ((np.floor(a) + np.floor(b)) % 2.0).astype(np.float64)
        if self.pattern == "stripes":
            return (np.floor(a) % 2.0).astype(np.float64)
        # bricks: rows of height period/2, alternate rows shifted by half a brick,
        # mortar lines one tenth of a period wide.
        row = np.floor(2.0 * b)
        along = a + 0.5 * (row % 2.0)
        mortar_h = (2.0 * b - row) < 0.2
        mortar_v = (along - np.floor(along)) < 0.1
        return (mortar_h | mortar_v).astype(np.float64)


@dataclass(frozen=True)
class UniformTexture:
    """One colour everywhere."""

    color: tuple[float, float, float]

    def __call__(self, s: np.ndarray, t: np.ndarray) -> np.ndarray:
        return np.broadcast_to(np.asarray(self.color, dtype=np.float64), (np.size(s), 3)).copy()


# --------------------------------------------------------------------------- primitives


class Primitive(Protocol):
    """What the renderer needs from a shape."""

    name: str
    texture: Texture
    velocity: np.ndarray

    def intersect(self, origins: np.ndarray, directions: np.ndarray) -> np.ndarray:
        """Ray parameter of the nearest hit in front of the origins (N, 3) along the
        directions (N, 3) (not necessarily unit), inf for a miss, shape (N,)."""

    def surface(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Unit normals (N, 3) and texture coordinates (N, 2) of surface points (N, 3)."""

    def translated(self, offset: np.ndarray) -> Primitive:
        """The same primitive moved by ``offset`` (3,), texture moving along."""


def _vec(value) -> np.ndarray:
    return np.asarray(value, dtype=np.float64).reshape(3)


def _unit(value) -> np.ndarray:
    v = _vec(value)
    norm = np.linalg.norm(v)
    if norm == 0:
        raise ValueError("a direction vector must not be zero")
    return v / norm


def _plane_hit(origins, directions, point, normal) -> np.ndarray:
    denom = directions @ normal
    with np.errstate(divide="ignore", invalid="ignore"):
        t = ((point - origins) @ normal) / denom
    return np.where((np.abs(denom) > 1e-15) & (t > _T_MIN), t, np.inf)


@dataclass(frozen=True, eq=False)
class Plane:
    """An infinite plane through ``point``; ``normal`` should face the cameras.

    Texture coordinates are metres along ``u_axis`` and ``normal x u_axis`` from ``point``.
    """

    name: str
    point: np.ndarray
    normal: np.ndarray
    u_axis: np.ndarray
    texture: Texture
    velocity: np.ndarray = field(default_factory=lambda: np.zeros(3))

    def __post_init__(self):
        normal = _unit(self.normal)
        u = _vec(self.u_axis)
        u = _unit(u - (u @ normal) * normal)
        object.__setattr__(self, "point", _vec(self.point))
        object.__setattr__(self, "normal", normal)
        object.__setattr__(self, "u_axis", u)
        object.__setattr__(self, "velocity", _vec(self.velocity))

    def intersect(self, origins, directions):
        return _plane_hit(origins, directions, self.point, self.normal)

    def surface(self, points):
        rel = points - self.point
        v_axis = np.cross(self.normal, self.u_axis)
        uv = np.stack([rel @ self.u_axis, rel @ v_axis], axis=-1)
        return np.broadcast_to(self.normal, points.shape), uv

    def translated(self, offset):
        return dataclasses.replace(self, point=self.point + offset)


@dataclass(frozen=True, eq=False)
class Rectangle:
    """A planar rectangle: ``center`` plus ``a * half_u + b * half_v`` for ``|a|, |b| <= 1``.

    ``half_u`` and ``half_v`` must be orthogonal; the normal is ``half_u x half_v``
    normalised. Texture coordinates are metres from the centre along both axes.
    """

    name: str
    center: np.ndarray
    half_u: np.ndarray
    half_v: np.ndarray
    texture: Texture
    velocity: np.ndarray = field(default_factory=lambda: np.zeros(3))

    def __post_init__(self):
        for key in ("center", "half_u", "half_v", "velocity"):
            object.__setattr__(self, key, _vec(getattr(self, key)))
        lu, lv = np.linalg.norm(self.half_u), np.linalg.norm(self.half_v)
        if lu == 0 or lv == 0 or abs(self.half_u @ self.half_v) > 1e-9 * lu * lv:
            raise ValueError("half_u and half_v must be non-zero and orthogonal")

    @property
    def normal(self) -> np.ndarray:
        return _unit(np.cross(self.half_u, self.half_v))

    def intersect(self, origins, directions):
        t = _plane_hit(origins, directions, self.center, self.normal)
        finite = np.isfinite(t)
        rel = origins + np.where(finite, t, 0.0)[:, None] * directions - self.center
        a = rel @ self.half_u / (self.half_u @ self.half_u)
        b = rel @ self.half_v / (self.half_v @ self.half_v)
        return np.where(finite & (np.abs(a) <= 1.0) & (np.abs(b) <= 1.0), t, np.inf)

    def surface(self, points):
        rel = points - self.center
        uv = np.stack([rel @ _unit(self.half_u), rel @ _unit(self.half_v)], axis=-1)
        return np.broadcast_to(self.normal, points.shape), uv

    def translated(self, offset):
        return dataclasses.replace(self, center=self.center + offset)


@dataclass(frozen=True, eq=False)
class Sphere:
    """A sphere; texture coordinates are arc lengths (longitude, latitude) with the
    seam at the back (+z side), invisible from cameras looking along +z."""

    name: str
    center: np.ndarray
    radius: float
    texture: Texture
    velocity: np.ndarray = field(default_factory=lambda: np.zeros(3))

    def __post_init__(self):
        object.__setattr__(self, "center", _vec(self.center))
        object.__setattr__(self, "velocity", _vec(self.velocity))
        if self.radius <= 0:
            raise ValueError(f"sphere radius must be > 0, got {self.radius}")

    def intersect(self, origins, directions):
        oc = origins - self.center
        a = np.einsum("ij,ij->i", directions, directions)
        b = np.einsum("ij,ij->i", oc, directions)
        c = np.einsum("ij,ij->i", oc, oc) - self.radius**2
        disc = b * b - a * c
        root = np.sqrt(np.maximum(disc, 0.0))
        near = (-b - root) / a
        far = (-b + root) / a
        t = np.where(near > _T_MIN, near, far)
        return np.where((disc >= 0) & (t > _T_MIN), t, np.inf)

    def surface(self, points):
        rel = points - self.center
        normal = rel / np.linalg.norm(rel, axis=-1, keepdims=True)
        longitude = np.arctan2(normal[:, 0], -normal[:, 2])
        latitude = np.arcsin(np.clip(normal[:, 1], -1.0, 1.0))
        return normal, self.radius * np.stack([longitude, latitude], axis=-1)

    def translated(self, offset):
        return dataclasses.replace(self, center=self.center + offset)


@dataclass(frozen=True, eq=False)
class Box:
    """An axis-aligned box between ``minimum`` and ``maximum``.

    Each face is textured in its two in-plane world axes, offset per face so
    that no two faces look alike.
    """

    name: str
    minimum: np.ndarray
    maximum: np.ndarray
    texture: Texture
    velocity: np.ndarray = field(default_factory=lambda: np.zeros(3))

    def __post_init__(self):
        for key in ("minimum", "maximum", "velocity"):
            object.__setattr__(self, key, _vec(getattr(self, key)))
        if np.any(self.maximum <= self.minimum):
            raise ValueError("box maximum must exceed minimum on every axis")

    def intersect(self, origins, directions):
        with np.errstate(divide="ignore", invalid="ignore"):
            t1 = (self.minimum - origins) / directions
            t2 = (self.maximum - origins) / directions
        # fmin/fmax skip the NaN of 0/0 (ray parallel to a slab, origin on its face).
        t_enter = np.fmax.reduce(np.fmin(t1, t2), axis=-1)
        t_exit = np.fmin.reduce(np.fmax(t1, t2), axis=-1)
        t = np.where(t_enter > _T_MIN, t_enter, t_exit)
        return np.where((t_enter <= t_exit) & (t > _T_MIN), t, np.inf)

    def surface(self, points):
        gaps = np.concatenate(
            [np.abs(points - self.minimum), np.abs(points - self.maximum)], axis=-1
        )
        face = np.argmin(gaps, axis=-1)  # 0..2 min faces, 3..5 max faces
        axis = face % 3
        normal = np.zeros_like(points)
        normal[np.arange(len(points)), axis] = np.where(face < 3, -1.0, 1.0)
        rel = points - self.minimum
        # In-plane axes per face normal axis: x -> (z, y), y -> (x, z), z -> (x, y).
        first = np.array([2, 0, 0])[axis]
        second = np.array([1, 2, 1])[axis]
        rows = np.arange(len(points))
        uv = np.stack([rel[rows, first] + 7.0 * face, rel[rows, second]], axis=-1)
        return normal, uv

    def translated(self, offset):
        return dataclasses.replace(
            self, minimum=self.minimum + offset, maximum=self.maximum + offset
        )


@dataclass(frozen=True, eq=False)
class Cylinder:
    """A capped cylinder with a vertical axis (world y), from ``top_y`` down to ``bottom_y``.

    ``center`` is a point on the axis (its y is ignored). Texture coordinates:
    arc length and height on the side, offset x/z on the caps.
    """

    name: str
    center: np.ndarray
    radius: float
    top_y: float
    bottom_y: float
    texture: Texture
    velocity: np.ndarray = field(default_factory=lambda: np.zeros(3))

    def __post_init__(self):
        object.__setattr__(self, "center", _vec(self.center))
        object.__setattr__(self, "velocity", _vec(self.velocity))
        if self.radius <= 0 or self.bottom_y <= self.top_y:
            raise ValueError("cylinder needs radius > 0 and bottom_y > top_y (y points down)")

    def intersect(self, origins, directions):
        ox = origins[:, 0] - self.center[0]
        oz = origins[:, 2] - self.center[2]
        oy = origins[:, 1]
        dx, dy, dz = directions[:, 0], directions[:, 1], directions[:, 2]
        a = dx * dx + dz * dz
        b = ox * dx + oz * dz
        c = ox * ox + oz * oz - self.radius**2
        disc = b * b - a * c
        # Vertical rays (a = 0) and horizontal ones (dy = 0) give inf/NaN here,
        # masked out below.
        with np.errstate(divide="ignore", invalid="ignore"):
            side = (-b - np.sqrt(np.maximum(disc, 0.0))) / a
            y = oy + side * dy
            best = np.where(
                (disc >= 0) & (a > 0) & (side > _T_MIN) & (y >= self.top_y) & (y <= self.bottom_y),
                side,
                np.inf,
            )
            for cap_y in (self.top_y, self.bottom_y):
                t = (cap_y - oy) / dy
                px = ox + t * dx
                pz = oz + t * dz
                ok = (dy != 0) & (t > _T_MIN) & (px * px + pz * pz <= self.radius**2)
                best = np.minimum(best, np.where(ok, t, np.inf))
        return best

    def surface(self, points):
        rx = points[:, 0] - self.center[0]
        rz = points[:, 2] - self.center[2]
        radial = np.hypot(rx, rz)
        cap_gap = np.minimum(
            np.abs(points[:, 1] - self.top_y), np.abs(points[:, 1] - self.bottom_y)
        )
        on_cap = cap_gap < np.abs(radial - self.radius)
        top = np.abs(points[:, 1] - self.top_y) < np.abs(points[:, 1] - self.bottom_y)
        safe = np.where(radial > 0, radial, 1.0)
        normal = np.stack([rx / safe, np.zeros_like(rx), rz / safe], axis=-1)
        normal[on_cap] = 0.0
        normal[on_cap, 1] = np.where(top[on_cap], -1.0, 1.0)
        side_uv = np.stack([self.radius * np.arctan2(rx, -rz), points[:, 1] - self.top_y], axis=-1)
        cap_uv = np.stack([rx + 11.0, rz], axis=-1)
        return normal, np.where(on_cap[:, None], cap_uv, side_uv)

    def translated(self, offset):
        return dataclasses.replace(
            self,
            center=self.center + offset,
            top_y=self.top_y + offset[1],
            bottom_y=self.bottom_y + offset[1],
        )


# --------------------------------------------------------------------------- scene


@dataclass(frozen=True, eq=False)
class Scene:
    """Primitives, lighting and the depth bounds that hold for the supplied rigs.

    Attributes
    ----------
    primitives : tuple of Primitive
        The shapes; the nearest hit along a ray wins.
    light : ndarray, shape (3,), or None
        Direction *towards* the light (normalised); None means no shading.
    ambient : float
        Brightness of a surface facing away from the light; a surface facing it
        gets 1. Shading = ambient + (1 - ambient) * max(0, n . light).
    znear, zfar : float
        Depth bounds (metres along the camera axis) of every surface seen by the
        default rigs, with a margin; the depth-map range of the sample data.
    """

    primitives: tuple
    light: np.ndarray | None = None
    ambient: float = 1.0
    znear: float = 0.1
    zfar: float = 100.0

    def __post_init__(self):
        object.__setattr__(self, "primitives", tuple(self.primitives))
        if self.light is not None:
            object.__setattr__(self, "light", _unit(self.light))
        if not 0.0 <= self.ambient <= 1.0:
            raise ValueError(f"ambient must be in [0, 1], got {self.ambient}")
        if not 0 < self.znear < self.zfar:
            raise ValueError(f"need 0 < znear < zfar, got {self.znear}, {self.zfar}")

    def at_frame(self, frame: int) -> Scene:
        """The scene at ``frame``: every primitive moved by ``frame * velocity``."""
        moved = tuple(
            p.translated(frame * p.velocity) if np.any(p.velocity) else p for p in self.primitives
        )
        return dataclasses.replace(self, primitives=moved)

    def shading(self, normals: np.ndarray) -> np.ndarray:
        """Lambertian brightness factor per normal, shape (N,)."""
        if self.light is None:
            return np.ones(len(normals))
        return self.ambient + (1.0 - self.ambient) * np.maximum(normals @ self.light, 0.0)


def _rotation_y(degrees: float) -> np.ndarray:
    a = np.radians(degrees)
    return np.array([[np.cos(a), 0.0, np.sin(a)], [0.0, 1.0, 0.0], [-np.sin(a), 0.0, np.cos(a)]])


def _rotation_x(degrees: float) -> np.ndarray:
    a = np.radians(degrees)
    return np.array([[1.0, 0.0, 0.0], [0.0, np.cos(a), -np.sin(a)], [0.0, np.sin(a), np.cos(a)]])


GROUND_Y = 1.0
"""The ground plane of :func:`default_scene` is ``y = GROUND_Y`` (1 m below the cameras)."""


def default_scene(*, seed: int = 0) -> Scene:
    """The sample-data scene: a room-like set seen from about z = 0 looking along +z.

    - background wall: plane z = 10, bricks over noise;
    - ground: plane y = 1 (y points down), tiles over noise;
    - a slanted panel on the right (z 5.5 to 7.5, turned 35 degrees about y);
    - a cylinder on the left (z about 6), static;
    - a box standing on the ground (z 4.3 to 5.1), moving left 5 cm per frame;
    - a sphere resting on the ground (centre z 3.2), moving right 4 cm per frame;
    - a small tilted card floating in front (z about 2.6), moving down 2 cm per frame.

    At 240 px focal length the movements are 2-3 px per frame. ``seed`` changes
    the textures only; geometry and depth bounds are fixed. ``znear = 2``,
    ``zfar = 13`` bound what the default rigs (:mod:`mvtools.scene.rigs`) see.
    """

    def texture(k, colors, **kw):
        return NoiseTexture(seed=seed * 1000 + k, colors=colors, **kw)

    panel_rotation = _rotation_y(-35.0)
    card_rotation = _rotation_y(20.0) @ _rotation_x(-30.0)
    primitives = (
        Plane(
            "background",
            point=(0.0, 0.0, 10.0),
            normal=(0.0, 0.0, -1.0),
            u_axis=(1.0, 0.0, 0.0),
            texture=texture(
                1,
                ((0.70, 0.45, 0.35), (0.85, 0.80, 0.70)),
                frequency=0.7,
                octaves=6,
                pattern="bricks",
                pattern_period=0.8,
                pattern_strength=0.35,
            ),
        ),
        Plane(
            "ground",
            point=(0.0, GROUND_Y, 0.0),
            normal=(0.0, -1.0, 0.0),
            u_axis=(1.0, 0.0, 0.0),
            texture=texture(
                2,
                ((0.25, 0.40, 0.20), (0.60, 0.55, 0.35)),
                frequency=1.0,
                octaves=6,
                pattern="checker",
                pattern_period=1.0,
                pattern_strength=0.2,
            ),
        ),
        Rectangle(
            "panel",
            center=(1.9, 0.0, 6.5),
            half_u=panel_rotation @ np.array([0.9, 0.0, 0.0]),
            half_v=panel_rotation @ np.array([0.0, 1.0, 0.0]),
            texture=texture(
                3,
                ((0.20, 0.30, 0.60), (0.70, 0.75, 0.90)),
                frequency=2.0,
                octaves=5,
                pattern="stripes",
                pattern_period=0.15,
                pattern_strength=0.3,
            ),
        ),
        Cylinder(
            "cylinder",
            center=(-1.6, 0.0, 6.0),
            radius=0.4,
            top_y=-0.9,
            bottom_y=GROUND_Y,
            texture=texture(4, ((0.55, 0.20, 0.15), (0.95, 0.70, 0.30)), frequency=3.0, octaves=5),
        ),
        Box(
            "box",
            minimum=(0.3, 0.2, 4.3),
            maximum=(1.1, GROUND_Y, 5.1),
            texture=texture(
                5,
                ((0.40, 0.30, 0.20), (0.90, 0.85, 0.60)),
                frequency=3.0,
                octaves=5,
                pattern="checker",
                pattern_period=0.2,
                pattern_strength=0.3,
            ),
            velocity=(-0.05, 0.0, 0.0),
        ),
        Sphere(
            "sphere",
            center=(-0.8, GROUND_Y - 0.45, 3.2),
            radius=0.45,
            texture=texture(6, ((0.15, 0.45, 0.55), (0.90, 0.90, 0.50)), frequency=4.0, octaves=4),
            velocity=(0.04, 0.0, 0.0),
        ),
        Rectangle(
            "card",
            center=(0.15, -0.45, 2.6),
            half_u=card_rotation @ np.array([0.22, 0.0, 0.0]),
            half_v=card_rotation @ np.array([0.0, 0.15, 0.0]),
            texture=texture(
                7,
                ((0.85, 0.25, 0.30), (0.95, 0.90, 0.85)),
                frequency=8.0,
                octaves=4,
                pattern="stripes",
                pattern_period=0.05,
                pattern_strength=0.4,
            ),
            velocity=(0.0, 0.02, 0.0),
        ),
    )
    return Scene(primitives, light=(-0.4, -0.7, -0.6), ambient=0.55, znear=2.0, zfar=13.0)
