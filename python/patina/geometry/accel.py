"""Ray tracing against triangle meshes through Patina's SAH kd-tree (`patina._core.Accel`).

This module is the checked, friendly face of the C++ tracer: it concatenates several
meshes into one tree and maps the tracer's global triangle ids back to (mesh, triangle),
converts ray arrays to what the kernels take, and rejects bad rays with a message
that names the argument and the ray before any C++ runs.

Ray order matters for speed, not for results: with packets of width K the tracer
takes rays [i, i + K) as one packet, so neighbouring rays should be coherent
(`scenes.pinhole_rays` orders a camera's rays in 2x2 / 4x2 pixel tiles for that).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from patina.geometry.mesh import Mesh
from patina.native import _core
from patina.widths import core_width


@dataclass(frozen=True, eq=False)
class Hits:
    """Closest hits of n rays, in ray order.

    t: (n,) float32 ray parameter (hit point = origin + t * direction), inf on a miss.
    prim: (n,) int32 triangle id over all meshes (in the order they were given), -1 on a miss.
    mesh: (n,) int32 index of the mesh hit, -1 on a miss.
    local_prim: (n,) int32 triangle id within that mesh (its row in `Mesh.indices`), -1 on a miss.
    u, v: (n,) float32 barycentrics: hit point = (1 - u - v) * v0 + u * v1 + v * v2.
    normal: (n, 3) float32 unit geometric normal, normalize(cross(v1 - v0, v2 - v0)), whichever
        side the ray came from; zero on a miss.
    """

    t: np.ndarray
    prim: np.ndarray
    mesh: np.ndarray
    local_prim: np.ndarray
    u: np.ndarray
    v: np.ndarray
    normal: np.ndarray

    @property
    def hit(self) -> np.ndarray:
        """(n,) bool: the ray hit something."""
        return self.prim >= 0

    def __len__(self) -> int:
        return int(self.t.shape[0])

    def points(self, origins: np.ndarray, directions: np.ndarray) -> np.ndarray:
        """(n, 3) float64 hit points origin + t * direction; NaN rows for misses."""
        t = np.where(self.hit, self.t.astype(np.float64), np.nan)
        return np.asarray(origins, np.float64) + t[:, None] * np.asarray(directions, np.float64)


def _ray_array(a: Any, arg: str, n: int | None = None) -> np.ndarray:
    """(n, 3) C-contiguous float32, or ValueError naming `arg`."""
    x = np.asarray(a)
    if x.dtype.kind not in "fiu":
        raise ValueError(f"{arg}: must be real numbers, got dtype {x.dtype}")
    if x.ndim != 2 or x.shape[1] != 3:
        raise ValueError(f"{arg}: must have shape (n, 3), got {x.shape}")
    if n is not None and x.shape[0] != n:
        raise ValueError(f"{arg}: has {x.shape[0]} rays, origins has {n}")
    with np.errstate(over="ignore", invalid="ignore"):
        return np.ascontiguousarray(x, dtype=np.float32)


def _first_bad(bad: np.ndarray) -> int | None:
    return int(np.argmax(bad)) if bad.any() else None


def _check_rays(origins: np.ndarray, directions: np.ndarray) -> None:
    """Finite origins; finite, non-zero directions. The message names the first bad ray."""
    i = _first_bad(~np.isfinite(origins).all(axis=1))
    if i is not None:
        raise ValueError(f"origins: ray {i} has origin {tuple(origins[i].tolist())}, which is not finite")
    d = directions
    i = _first_bad(~np.isfinite(d).all(axis=1) | ~(d != 0).any(axis=1))
    if i is not None:
        raise ValueError(f"directions: ray {i} has direction {tuple(d[i].tolist())}, not a finite non-zero vector")


def _tmax_array(tmax: Any, n: int) -> np.ndarray:
    """(n,) float32 from a scalar or an array; NaN is refused (inf means unbounded)."""
    x = np.asarray(tmax)
    if x.dtype.kind not in "fiu":
        raise ValueError(f"tmax: must be real numbers, got dtype {x.dtype}")
    if x.ndim == 0:
        x = np.full(n, x, np.float32)
    elif x.shape != (n,):
        raise ValueError(f"tmax: must be a number or have shape ({n},), got {x.shape}")
    x = np.ascontiguousarray(x, dtype=np.float32)
    i = _first_bad(np.isnan(x))
    if i is not None:
        raise ValueError(f"tmax: ray {i} has tmax NaN")
    return x


def _check_tmin(tmin: float) -> float:
    value = float(tmin)
    if not np.isfinite(value) or value < 0:
        raise ValueError(f"tmin: must be finite and >= 0, got {tmin}")
    return value


def _check_threads(threads: int) -> int:
    if int(threads) != threads or threads < 0:
        raise ValueError(f"threads: must be an integer >= 0 (0 = all cores), got {threads!r}")
    return int(threads)


def _concatenate(meshes: Sequence[Mesh]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """One vertex and one index array for all meshes, and per-mesh triangle offsets (len + 1)."""
    tri_offsets = np.zeros(len(meshes) + 1, np.int64)
    tri_offsets[1:] = np.cumsum([m.triangle_count for m in meshes])
    vert_offsets = np.cumsum([0] + [m.vertex_count for m in meshes])
    if vert_offsets[-1] > np.iinfo(np.int32).max:
        raise ValueError(f"meshes: {vert_offsets[-1]} vertices in all are more than int32 indices can address")
    if len(meshes) == 1:
        return meshes[0].vertices, meshes[0].indices, tri_offsets
    vertices = np.concatenate([m.vertices for m in meshes] + [np.zeros((0, 3), np.float32)])
    indices = np.concatenate(
        [m.indices + np.int32(o) for m, o in zip(meshes, vert_offsets[:-1])] + [np.zeros((0, 3), np.int32)]
    )
    return np.ascontiguousarray(vertices), np.ascontiguousarray(indices, dtype=np.int32), tri_offsets


class Accel:
    """A kd-tree over one mesh or several (concatenated in the order given), ready to trace;
    and, built when first asked for, an 8-wide BVH over the same triangles (`bvh=True`).

    max_leaf, max_depth: build limits, 0 for the C++ defaults. threads: build threads, 0 = all.
    The tree is static: build a new Accel when the geometry changes.
    """

    def __init__(self, meshes: Mesh | Sequence[Mesh], max_leaf: int = 0, max_depth: int = 0, threads: int = 0) -> None:
        self.meshes: tuple[Mesh, ...] = (meshes,) if isinstance(meshes, Mesh) else tuple(meshes)
        for i, m in enumerate(self.meshes):
            if not isinstance(m, Mesh):
                raise TypeError(f"meshes: item {i} is a {type(m).__name__}, not a patina Mesh")
        for arg, value in (("max_leaf", max_leaf), ("max_depth", max_depth)):
            if int(value) != value or value < 0:
                raise ValueError(f"{arg}: must be an integer >= 0 (0 = default), got {value!r}")
        vertices, indices, self.offsets = _concatenate(self.meshes)
        # kept alive here whatever the C++ side does with the buffers
        self._vertices, self._indices = vertices, indices
        self.core = _core.Accel(
            vertices, indices, max_leaf=int(max_leaf), max_depth=int(max_depth), threads=_check_threads(threads)
        )

    # --- build statistics ---------------------------------------------------------------

    @property
    def triangle_count(self) -> int:
        return int(self.core.triangle_count)

    @property
    def node_count(self) -> int:
        return int(self.core.node_count)

    @property
    def leaf_count(self) -> int:
        return int(self.core.leaf_count)

    @property
    def depth(self) -> int:
        return int(self.core.depth)

    @property
    def build_seconds(self) -> float:
        return float(self.core.build_seconds)

    def stats(self) -> dict[str, Any]:
        """JSON-ready build statistics."""
        return {
            "meshes": [m.name for m in self.meshes],
            "triangles": self.triangle_count,
            "nodes": self.node_count,
            "leaves": self.leaf_count,
            "depth": self.depth,
            "build_seconds": self.build_seconds,
            # beyond the documented contract: reported when the C++ side has them
            **{k: int(getattr(self.core, k)) for k in ("empty_leaf_count", "leaf_references") if hasattr(self.core, k)},
        }

    def __repr__(self) -> str:
        return (
            f"Accel({len(self.meshes)} meshes, {self.triangle_count} triangles, "
            f"{self.node_count} nodes, depth {self.depth})"
        )

    # --- queries ------------------------------------------------------------------------

    def _rays(self, origins: Any, directions: Any) -> tuple[np.ndarray, np.ndarray]:
        o = _ray_array(origins, "origins")
        d = _ray_array(directions, "directions", len(o))
        return o, d

    @staticmethod
    def _call(query: Any, o: np.ndarray, d: np.ndarray, **kwargs: Any) -> Any:
        """Runs a C++ query. It checks every ray in one fast pass; only when that fails are the
        rays checked again here, to name the argument and the bad values in the message."""
        try:
            return query(o, d, **kwargs)
        except ValueError:
            _check_rays(o, d)
            raise

    def split_prim(self, prim: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Global triangle ids -> (mesh index, triangle id within the mesh); -1, -1 for -1."""
        prim = np.asarray(prim)
        hit = prim >= 0
        if len(self.meshes) == 1:
            mesh = np.where(hit, 0, -1).astype(np.int32)
            return mesh, prim.astype(np.int32, copy=True)
        # searchsorted on the upper ends skips empty meshes: their range is empty
        mesh = np.searchsorted(self.offsets[1:], prim, side="right").astype(np.int32)
        local = prim - self.offsets[np.minimum(mesh, len(self.meshes) - 1)]
        return np.where(hit, mesh, -1).astype(np.int32), np.where(hit, local, -1).astype(np.int32)

    def intersect(
        self,
        origins: Any,
        directions: Any,
        tmax: Any = None,
        tmin: float = 0.0,
        width: int | None = None,
        threads: int = 0,
        bvh: bool = False,
    ) -> Hits:
        """Closest hit of each ray with t in (tmin, tmax]; directions need not be unit length.

        tmax: None (unbounded), a number, or an (n,) array. width: None (the widest the CPU
        runs), 1, 4 or 8; results do not depend on it. threads: 0 = all cores. bvh: trace
        one ray at a time through the 8-wide BVH (built on first use; faster for incoherent
        rays), where a tie goes to the least triangle id.
        """
        o, d = self._rays(origins, directions)
        tmax_arr = None if tmax is None else _tmax_array(tmax, len(o))
        t, prim, u, v, normal = self._call(
            self.core.intersect,
            o,
            d,
            tmin=_check_tmin(tmin),
            tmax=tmax_arr,
            width=core_width(width),
            threads=_check_threads(threads),
            bvh=bool(bvh),
        )
        mesh, local = self.split_prim(prim)
        return Hits(t=t, prim=prim, mesh=mesh, local_prim=local, u=u, v=v, normal=normal)

    def occluded(
        self,
        origins: Any,
        directions: Any,
        tmax: Any,
        tmin: float = 0.0,
        width: int | None = None,
        threads: int = 0,
        bvh: bool = False,
    ) -> np.ndarray:
        """(n,) bool: something lies on the ray with t in (tmin, tmax) (shadow rays; any hit).
        bvh: through the 8-wide BVH, one ray at a time."""
        o, d = self._rays(origins, directions)
        return np.asarray(
            self._call(
                self.core.occluded,
                o,
                d,
                tmax=_tmax_array(tmax, len(o)),
                tmin=_check_tmin(tmin),
                width=core_width(width),
                threads=_check_threads(threads),
                bvh=bool(bvh),
            ),
            dtype=bool,
        )
