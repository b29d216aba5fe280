"""Triangle meshes as the ray tracer takes them: float32 vertices and int32 triangles.

Files are read with trimesh (Patina has no mesh parser of its own); whatever trimesh
cannot read, or reads into something the tracer cannot use, becomes a `FormatError`
naming the file, the place and the problem, never a traceback.
"""

from __future__ import annotations

import io
import os
import warnings
from typing import Any

import numpy as np

from patina.errors import FormatError

_INT32_MAX = np.iinfo(np.int32).max
_TEXT_FORMATS = ("obj", "off")
# What load_mesh reads, by file name suffix.
MESH_FORMATS = ("obj", "ply", "stl", "off", "glb", "gltf")


class MeshError(ValueError):
    """A mesh's arrays are unusable: `where` (an argument, a vertex, a triangle) and `problem`."""

    def __init__(self, name: str, where: str, problem: str) -> None:
        self.name = name
        self.where = where
        self.problem = problem
        super().__init__(f"mesh '{name}': {where}: {problem}")


def _rows_of_three(values: Any, name: str, what: str, kinds: str, kinds_word: str, shape_word: str) -> np.ndarray:
    """`values` as an array of shape (N, 3) and a dtype kind in `kinds`; empty input passes as is."""
    a = np.asarray(values)
    if a.size == 0:
        return a
    if a.dtype.kind not in kinds:
        raise MeshError(name, what, f"must be {kinds_word}, got dtype {a.dtype}")
    if a.ndim != 2 or a.shape[1] != 3:
        raise MeshError(name, what, f"must have shape {shape_word}, got {a.shape}")
    return a


def _as_vertices(vertices: Any, name: str) -> np.ndarray:
    """(V, 3) C-contiguous float32, every coordinate finite *after* the cast (1e39 is inf in float32)."""
    a = _rows_of_three(vertices, name, "vertices", "fiu", "real numbers", "(V, 3)")
    if a.size == 0:
        return np.zeros((0, 3), np.float32)
    if a.shape[0] > _INT32_MAX:
        raise MeshError(name, "vertices", f"{a.shape[0]} vertices are more than int32 indices can address")
    with np.errstate(over="ignore", invalid="ignore"):
        v = np.ascontiguousarray(a, dtype=np.float32)
    bad = ~np.isfinite(v).all(axis=1)
    if bad.any():
        i = int(np.argmax(bad))
        raise MeshError(name, f"vertex {i}", f"is not finite as float32: {tuple(a[i].tolist())}")
    return v


def _as_indices(indices: Any, vertex_count: int, name: str) -> np.ndarray:
    """(T, 3) C-contiguous int32, every index in [0, vertex_count)."""
    a = _rows_of_three(indices, name, "indices", "iu", "integers", "(T, 3)")
    if a.size == 0:
        return np.zeros((0, 3), np.int32)
    if a.shape[0] > _INT32_MAX:
        raise MeshError(name, "indices", f"{a.shape[0]} triangles are more than int32 ids can number")
    bad = ((a < 0) | (a >= vertex_count)).any(axis=1)
    if bad.any():
        t = int(np.argmax(bad))
        row = a[t]
        k = int(np.argmax((row < 0) | (row >= vertex_count)))
        raise MeshError(name, f"triangle {t}", f"refers to vertex {int(row[k])}, the mesh has {vertex_count} vertices")
    return np.ascontiguousarray(a, dtype=np.int32)


class Mesh:
    """A named triangle mesh: `vertices` (V, 3) float32 and `indices` (T, 3) int32.

    Triangles are numbered in the order of `indices`; that number is what the tracer
    reports as `prim`. Degenerate (zero-area) triangles are allowed, they are never hit.
    An empty mesh (no vertices, no triangles) is allowed too. Arrays are read-only so a
    built `Accel` cannot go stale behind the caller's back.
    """

    def __init__(self, vertices: Any, indices: Any, name: str = "mesh") -> None:
        self.name = str(name)
        self.vertices = _as_vertices(vertices, self.name)
        self.indices = _as_indices(indices, len(self.vertices), self.name)
        self.vertices.flags.writeable = False
        self.indices.flags.writeable = False

    @classmethod
    def from_trimesh(cls, tm: Any, name: str | None = None) -> Mesh:
        """From a `trimesh.Trimesh`, keeping its vertex and face order."""
        label = name if name is not None else (tm.metadata.get("name") or "mesh")
        return cls(np.asarray(tm.vertices), np.asarray(tm.faces), label)

    @property
    def triangle_count(self) -> int:
        return int(self.indices.shape[0])

    @property
    def vertex_count(self) -> int:
        return int(self.vertices.shape[0])

    @property
    def bounds(self) -> np.ndarray:
        """(2, 3) float32: lower and upper corner; for an empty mesh +inf and -inf (an empty box)."""
        if self.vertex_count == 0:
            return np.array([[np.inf] * 3, [-np.inf] * 3], np.float32)
        return np.stack([self.vertices.min(axis=0), self.vertices.max(axis=0)])

    def triangles(self) -> np.ndarray:
        """(T, 3, 3) float32 corner positions, triangle by triangle (for references and peers)."""
        return self.vertices[self.indices]

    def __repr__(self) -> str:
        return f"Mesh({self.name!r}, {self.vertex_count} vertices, {self.triangle_count} triangles)"


def _suffix_format(path: str) -> str:
    """The mesh format the file name asks for, among those trimesh reads.

    Archives, point clouds and 2-D drawings that trimesh also reads are refused: they
    are not meshes, and archives can unpack to any size.
    """
    import trimesh

    known = [f for f in MESH_FORMATS if f in trimesh.available_formats()]
    suffix = os.path.splitext(path)[1].lower().lstrip(".")
    if suffix in known:
        return suffix
    shown = f"'.{suffix}'" if suffix else "(no suffix)"
    raise FormatError(path, "file name", f"unknown mesh format {shown} (known: {', '.join(known)})")


def _text_source(path: str, fmt: str) -> Any:
    """The path, or for a text format that is not UTF-8 the bytes re-encoded from Latin-1.

    trimesh guesses the encoding of non-UTF-8 text only with an optional package Patina does
    not depend on; an OBJ with an accented comment from a European lab is common enough.
    """
    if fmt not in _TEXT_FORMATS:
        return path
    with open(path, "rb") as f:
        data = f.read()
    try:
        data.decode("utf-8")
        return path
    except UnicodeDecodeError:
        return io.BytesIO(data.decode("latin-1").encode("utf-8"))


def _read_trimesh(path: str, fmt: str) -> Any:
    """trimesh's reading of the file as one mesh; any exception it raises means the file is bad."""
    import trimesh

    try:
        source = _text_source(path, fmt)
        # process=False keeps the file's vertex and triangle order (so `prim` numbers match it)
        # and leaves non-finite values for our own check to report; numpy's warnings on such
        # values inside trimesh would only repeat what that check says.
        with warnings.catch_warnings(), np.errstate(all="ignore"):
            warnings.simplefilter("ignore", RuntimeWarning)
            return trimesh.load(
                source,
                file_type=fmt,
                force="mesh",
                process=False,
                resolver=trimesh.resolvers.FilePathResolver(path),
            )
    except ImportError:
        # trimesh reached for its optional encoding guesser: the bytes are not UTF-8 text
        raise FormatError(
            path, f"{fmt.upper()} reader", f"neither a binary {fmt.upper()} file nor UTF-8 text"
        ) from None
    except Exception as e:  # a third-party parser may raise anything on a damaged file
        detail = str(e).strip().splitlines()[0] if str(e).strip() else type(e).__name__
        raise FormatError(path, f"{fmt.upper()} reader", f"cannot read the file: {detail}") from None


def load_mesh(path: str | os.PathLike[str], name: str | None = None) -> Mesh:
    """Read OBJ, PLY, STL, GLB/glTF, OFF... with trimesh; a scene becomes one mesh, transforms applied.

    Raises `FormatError` (a ValueError) for a missing or unreadable file, an unknown
    format, a file with no triangles, or vertices that are not finite.
    """
    p = os.fspath(path)
    if not os.path.exists(p):
        raise FormatError(p, "", "no such file")
    if not os.path.isfile(p):
        raise FormatError(p, "", "not a regular file")
    if os.path.getsize(p) == 0:
        raise FormatError(p, "", "empty file")
    fmt = _suffix_format(p)
    tm = _read_trimesh(p, fmt)
    if not hasattr(tm, "faces") or not hasattr(tm, "vertices"):
        raise FormatError(p, f"{fmt.upper()} reader", f"no triangle mesh in the file (read as {type(tm).__name__})")
    label = name if name is not None else os.path.splitext(os.path.basename(p))[0]
    try:
        mesh = Mesh(np.asarray(tm.vertices), np.asarray(tm.faces), label)
    except MeshError as e:
        raise FormatError(p, e.where, e.problem) from None
    if mesh.triangle_count == 0:
        raise FormatError(p, f"{fmt.upper()} reader", "the file holds no triangles")
    return mesh
