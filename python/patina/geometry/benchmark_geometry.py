"""Deterministic test and benchmark geometry, and the rays to shoot at it.

Everything here is made in memory (with trimesh and numpy, no files) from a seed, so a
benchmark or a test sees the same triangles and rays on every machine and every run.

Scenes: `icosphere` (a closed, evenly tessellated sphere), `box_field` (a ground quad
crowded with randomly sized and rotated boxes: many occluders, depth complexity),
`triangle_soup` (small random triangles filling a cube), `thin_triangles` (long slivers,
which straddle many kd-tree splits), `sphere_of` (a sphere with about n triangles, for
build-time series).

Rays: `pinhole_rays` (a camera's primary rays, ordered in pixel tiles so that packets are
coherent), `random_rays` (incoherent rays through a box), `diffuse_bounce_rays` (secondary
rays: cosine-distributed directions from the primary hits).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from typing import TYPE_CHECKING, NamedTuple

import numpy as np

from patina.geometry.mesh import Mesh

if TYPE_CHECKING:
    from patina.geometry.accel import Accel, Hits


class Rays(NamedTuple):
    """origins and directions, (n, 3) float32 each; directions unit length."""

    origins: np.ndarray
    directions: np.ndarray


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def _rays(origins: np.ndarray, directions: np.ndarray) -> Rays:
    """float32, C-contiguous, directions normalised in double before the cast."""
    return Rays(
        np.ascontiguousarray(origins, dtype=np.float32),
        np.ascontiguousarray(_unit(np.asarray(directions, np.float64)), dtype=np.float32),
    )


# --- geometry -----------------------------------------------------------------------------


def icosphere(target_triangles: int = 80_000, radius: float = 1.0) -> Mesh:
    """A closed icosphere with the subdivision level whose 20 * 4**s triangles are nearest the target.

    80_000 gives level 6: 81_920 triangles, 40_962 vertices.
    """
    import trimesh

    level = max(0, round(math.log(max(target_triangles, 1) / 20, 4)))
    return Mesh.from_trimesh(trimesh.creation.icosphere(subdivisions=level, radius=radius), f"icosphere{level}")


def _box_template() -> tuple[np.ndarray, np.ndarray]:
    """trimesh's unit cube centred at the origin: 8 corners, 12 outward-wound triangles."""
    import trimesh

    box = trimesh.creation.box(extents=(1.0, 1.0, 1.0))
    return np.asarray(box.vertices, np.float64), np.asarray(box.faces, np.int64)


def box_field(target_triangles: int = 200_000, seed: int = 1, extent: float = 1.0) -> Mesh:
    """Boxes on a square grid over the ground quad [-extent, extent]^2 at z = 0, z up.

    Each box (12 triangles) has a random footprint (20-90 % of its cell), height and
    rotation about z, and stands on the ground. The ground quad adds 2 triangles, so the
    count is 12 * (target // 12) + 2.
    """
    rng = np.random.default_rng(seed)
    n = max(1, target_triangles // 12)
    side = math.ceil(math.sqrt(n))
    cell = 2 * extent / side
    gx, gy = np.meshgrid(np.arange(side), np.arange(side))
    cells = np.stack([gx.ravel(), gy.ravel()], axis=1)[:n]
    centre = -extent + (cells + 0.5) * cell

    size = np.empty((n, 3))
    size[:, :2] = rng.uniform(0.2, 0.9, (n, 2)) * cell / math.sqrt(2)  # fits its cell at any rotation
    size[:, 2] = rng.uniform(0.1, 1.0, n) ** 2 * 0.6 * extent
    angle = rng.uniform(0, np.pi / 2, n)
    c, s = np.cos(angle), np.sin(angle)

    corners, faces = _box_template()
    local = corners[None] * size[:, None, :]  # (n, 8, 3)
    x = c[:, None] * local[..., 0] - s[:, None] * local[..., 1] + centre[:, 0, None]
    y = s[:, None] * local[..., 0] + c[:, None] * local[..., 1] + centre[:, 1, None]
    z = local[..., 2] + size[:, 2, None] / 2
    vertices = np.stack([x, y, z], axis=-1).reshape(-1, 3)
    indices = (faces[None] + 8 * np.arange(n)[:, None, None]).reshape(-1, 3)

    e = extent
    ground_v = np.array([[-e, -e, 0], [e, -e, 0], [e, e, 0], [-e, e, 0]], np.float64)
    ground_i = np.array([[0, 1, 2], [0, 2, 3]]) + len(vertices)
    return Mesh(np.vstack([vertices, ground_v]), np.vstack([indices, ground_i]), f"box_field{n}")


def _random_frames(rng: np.random.Generator, n: int) -> tuple[np.ndarray, np.ndarray]:
    """n random orthonormal pairs (a, b), uniformly oriented."""
    a = _unit(rng.normal(size=(n, 3)))
    helper = _unit(rng.normal(size=(n, 3)))
    b = _unit(np.cross(a, helper))
    return a, b


def triangle_soup(n: int = 100_000, seed: int = 2) -> Mesh:
    """n small random triangles with centres uniform in the unit cube [0, 1]^3.

    Each triangle's corners lie within about 1.5 / n**(1/3) of its centre in random
    directions, so triangles are small but the soup, seen through, has a depth
    complexity of a few tens, and they overlap and intersect each other freely.
    """
    rng = np.random.default_rng(seed)
    scale = 1.5 / max(n, 1) ** (1 / 3)
    centre = rng.uniform(0, 1, (n, 1, 3))
    corners = centre + rng.normal(size=(n, 3, 3)) * scale / 2
    return Mesh(corners.reshape(-1, 3), np.arange(3 * n).reshape(n, 3), f"soup{n}")


def thin_triangles(n: int = 100_000, seed: int = 3) -> Mesh:
    """n long slivers (length 0.2-0.6, width 1/1000 of that) at random orientations in the unit cube.

    Long thin triangles have boxes much larger than their area: each straddles many
    kd-tree planes, which stresses the build (split clipping) and the leaf lists.
    """
    rng = np.random.default_rng(seed)
    along, across = _random_frames(rng, n)
    length = rng.uniform(0.2, 0.6, n)[:, None]
    centre = rng.uniform(0.2, 0.8, (n, 3))
    v0 = centre - along * length / 2
    v1 = centre + along * length / 2
    v2 = centre + across * length * 1e-3 + along * rng.uniform(-0.5, 0.5, (n, 1)) * length
    corners = np.stack([v0, v1, v2], axis=1)
    return Mesh(corners.reshape(-1, 3), np.arange(3 * n).reshape(n, 3), f"thin{n}")


def sphere_of(n_triangles: int) -> Mesh:
    """A latitude-longitude sphere of radius 1 with about n_triangles (within a few percent).

    For build-time series (10k .. 1M): the same shape at every size, so only the count
    changes. trimesh's UV sphere with `lat` rings and `lon = 2 * (lat - 2)` segments
    has 8 * (lat - 2)**2 triangles.
    """
    import trimesh

    k = max(2, round(math.sqrt(max(n_triangles, 32) / 8)))
    tm = trimesh.creation.uv_sphere(radius=1.0, count=[k + 2, 2 * k])
    return Mesh.from_trimesh(tm, f"sphere{len(tm.faces)}")


# --- rays ---------------------------------------------------------------------------------

# Default packet tiles: groups of 4 consecutive rays are 2x2 pixels, groups of 8 are 4x2.
PACKET_TILES: tuple[tuple[int, int], ...] = ((2, 2), (4, 2))


def pixel_order(width: int, height: int, tiles: Sequence[tuple[int, int]] = PACKET_TILES) -> np.ndarray:
    """(width * height, 2) int32 pixel coordinates (x, y) in tiled order; y = 0 is the top row.

    `tiles` are nested tile shapes (tx, ty), innermost first, each a whole multiple of
    the one before. The image is cut into outermost tiles, taken row by row (left to
    right, top to bottom); each is cut into the next smaller tiles, taken row by row;
    and so on down to the pixels of the innermost tile, row by row. With the default
    ((2, 2), (4, 2)):

        0 1 | 4 5 | 8 9 ...       rays 0-3: a 2x2 tile, rays 0-7: a 4x2 tile,
        2 3 | 6 7 | ...           so 4-ray and 8-ray packets are both square-ish.

    Where the image size is not a multiple of the outermost tile, the tiles on the right
    and bottom edges are cut short and the groups of 4 or 8 there are not full tiles.
    """
    shapes = [(int(tx), int(ty)) for tx, ty in tiles] or [(1, 1)]
    if any(tx < 1 or ty < 1 for tx, ty in shapes):
        raise ValueError(f"tiles: sizes must be positive, got {shapes}")
    for (ax, ay), (bx, by) in itertools.pairwise(shapes):
        if bx % ax or by % ay:
            raise ValueError(f"tiles: {bx}x{by} is not a whole multiple of the inner tile {ax}x{ay}")
    y, x = np.divmod(np.arange(width * height), width)
    keys = []  # most significant first: outer tile row, outer tile column, ..., pixel row, pixel column
    outer_x, outer_y = shapes[-1]
    keys += [y // outer_y, x // outer_x]
    for (px, py), (ix, iy) in zip(shapes[::-1], [*shapes[::-1][1:], (1, 1)]):
        keys += [(y % py) // iy, (x % px) // ix]
    order = np.lexsort(keys[::-1])
    return np.stack([x[order], y[order]], axis=1).astype(np.int32)


def pinhole_rays(
    width: int,
    height: int,
    eye: Sequence[float],
    target: Sequence[float],
    fov_deg: float,
    tiles: Sequence[tuple[int, int]] = PACKET_TILES,
    up: Sequence[float] = (0.0, 0.0, 1.0),
) -> Rays:
    """Primary rays of a pinhole camera through pixel centres, in `pixel_order(width, height, tiles)`.

    fov_deg is the vertical field of view; pixels are square. All origins are `eye`.
    """
    eye_v = np.asarray(eye, np.float64)
    forward = _unit(np.asarray(target, np.float64) - eye_v)
    right = _unit(np.cross(forward, np.asarray(up, np.float64)))
    down = np.cross(forward, right)
    half_h = math.tan(math.radians(fov_deg) / 2)
    half_w = half_h * width / height
    px = pixel_order(width, height, tiles).astype(np.float64)
    sx = ((px[:, 0] + 0.5) / width * 2 - 1) * half_w
    sy = ((px[:, 1] + 0.5) / height * 2 - 1) * half_h
    directions = forward + sx[:, None] * right + sy[:, None] * down
    return _rays(np.broadcast_to(eye_v, directions.shape), directions)


def random_rays(n: int, seed: int, lo: Sequence[float], hi: Sequence[float]) -> Rays:
    """Incoherent rays: origins uniform in the box [lo, hi], directions uniform on the sphere."""
    rng = np.random.default_rng(seed)
    origins = rng.uniform(np.asarray(lo, np.float64), np.asarray(hi, np.float64), (n, 3))
    return _rays(origins, rng.normal(size=(n, 3)))


def _cosine_directions(normals: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """Cosine-weighted directions about unit normals (Malley: a uniform disc lifted to the hemisphere)."""
    n = len(normals)
    r = np.sqrt(rng.uniform(0, 1, n))
    phi = rng.uniform(0, 2 * np.pi, n)
    x, y = r * np.cos(phi), r * np.sin(phi)
    z = np.sqrt(np.maximum(0.0, 1 - r * r))
    helper = np.where(np.abs(normals[:, :1]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
    t = _unit(np.cross(normals, helper))
    b = np.cross(normals, t)
    return x[:, None] * t + y[:, None] * b + z[:, None] * normals


def bounce_rays(rays: Rays, hits: Hits, seed: int = 4, eps: float = 1e-4) -> Rays:
    """One diffuse bounce from each hit of `rays`: the secondary rays a path tracer would shoot.

    Origins are the hit points moved off the surface by eps * (1 + |p|_inf) along the
    normal facing the incoming ray (so the bounce does not hit its own triangle); directions
    are cosine-distributed about that normal. Misses are dropped; the hits keep their ray
    order, so origins stay coherent while directions are not.
    """
    rng = np.random.default_rng(seed)
    hit = hits.hit
    d = np.asarray(rays.directions, np.float64)[hit]
    p = np.asarray(rays.origins, np.float64)[hit] + hits.t[hit, None].astype(np.float64) * d
    nrm = np.asarray(hits.normal, np.float64)[hit]
    facing = np.where(np.sum(nrm * d, axis=1, keepdims=True) > 0, -nrm, nrm)
    offset = eps * (1 + np.abs(p).max(axis=1, keepdims=True))
    return _rays(p + offset * facing, _cosine_directions(facing, rng))


def diffuse_bounce_rays(accel: Accel, rays: Rays, seed: int = 4, eps: float = 1e-4) -> Rays:
    """Trace `rays` with `accel`, then `bounce_rays` from their hits."""
    return bounce_rays(rays, accel.intersect(rays.origins, rays.directions), seed=seed, eps=eps)
