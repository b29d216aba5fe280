"""Built-in meshes for preview scenes: sphere, plane, a shader-ball-like preview object, a car panel.

Every shape comes with what shading needs: unit shading normals (smooth where the surface
is, split along creases), unit tangents orthogonal to them (a smooth field where one
exists, for anisotropic materials) and, for open sheets, uvs. Closed shapes are built by
revolving 2-D profiles about the y axis, and sheets by tessellating parametric patches:
no booleans, so the output is exact and the same on every machine.

Closed shapes are watertight with outward winding, counting vertices at the same position
as one: along a crease each side has its own copy of the crease vertices (with its own
normal), at bit-identical positions, so rays find no cracks. The preview object is
several closed shells (pedestal, two shell caps, core) that touch or overlap slightly
where they join, as modelled objects do.
"""

from __future__ import annotations

import itertools
import math
import os
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from patina.geometry.mesh import Mesh, load_mesh

# A profile piece: (K, 2) points (r, y) and (K, 2) unit normals in the (r, y) half-plane.
Piece = tuple[np.ndarray, np.ndarray]


@dataclass(frozen=True, eq=False)
class ShapeMesh:
    """A triangle mesh with shading frames.

    vertices (V, 3) float32; indices (T, 3) int32, counter-clockwise seen from outside;
    normals (V, 3) float32 unit shading normals; tangents (V, 3) float32 unit, orthogonal
    to the normals; uvs (V, 2) float32 in [0, 1], or None where a closed shape would need
    a seam.
    """

    vertices: np.ndarray
    indices: np.ndarray
    normals: np.ndarray
    tangents: np.ndarray
    uvs: np.ndarray | None = None

    @property
    def triangle_count(self) -> int:
        return int(self.indices.shape[0])

    @property
    def bounds(self) -> np.ndarray:
        """(2, 3) float32: lower and upper corner."""
        return np.stack([self.vertices.min(axis=0), self.vertices.max(axis=0)])

    def mesh(self, name: str = "shape") -> Mesh:
        """The positions and triangles as the ray tracer takes them."""
        return Mesh(self.vertices, self.indices, name)

    def trimesh(self) -> Any:
        """A trimesh.Trimesh of the same vertices and triangles (order kept), for checks and export."""
        import trimesh

        return trimesh.Trimesh(self.vertices, self.indices, process=False)


def _unit(v: np.ndarray) -> np.ndarray:
    n = np.linalg.norm(v, axis=-1, keepdims=True)
    return v / np.where(n > 0, n, 1.0)


def _orthogonal_tangents(normals: np.ndarray, preferred: np.ndarray) -> np.ndarray:
    """preferred (V, 3) projected onto each normal's plane; where that fails, a fixed axis projected instead."""
    t = preferred - np.sum(preferred * normals, axis=1, keepdims=True) * normals
    bad = np.linalg.norm(t, axis=1) < 1e-6
    if bad.any():
        axis = np.where(np.abs(normals[bad, 0:1]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 0.0, 1.0]])
        t[bad] = axis - np.sum(axis * normals[bad], axis=1, keepdims=True) * normals[bad]
    return _unit(t)


def _finish(
    vertices: np.ndarray, indices: np.ndarray, normals: np.ndarray, tangents: np.ndarray, uvs: np.ndarray | None
) -> ShapeMesh:
    n = _unit(np.asarray(normals, np.float64))
    t = _orthogonal_tangents(n, np.asarray(tangents, np.float64))
    arrays = [np.ascontiguousarray(a, np.float32) for a in (vertices, n, t)]
    for a in arrays:
        a.flags.writeable = False
    idx = np.ascontiguousarray(indices, np.int32)
    idx.flags.writeable = False
    uv = None
    if uvs is not None:
        uv = np.ascontiguousarray(uvs, np.float32)
        uv.flags.writeable = False
    return ShapeMesh(arrays[0], idx, arrays[1], arrays[2], uv)


def _concatenate(parts: Sequence[ShapeMesh]) -> ShapeMesh:
    offsets = np.cumsum([0] + [len(p.vertices) for p in parts[:-1]])
    return _finish(
        np.concatenate([p.vertices for p in parts]),
        np.concatenate([p.indices + o for p, o in zip(parts, offsets)]),
        np.concatenate([p.normals for p in parts]),
        np.concatenate([p.tangents for p in parts]),
        None,
    )


# --- profiles and revolution ---------------------------------------------------------------


def _line(a: Sequence[float], b: Sequence[float]) -> Piece:
    """A straight profile segment; its normal is the tangent turned clockwise (outside on the right)."""
    p = np.array([a, b], np.float64)
    d = p[1] - p[0]
    n = _unit(np.array([d[1], -d[0]]))
    return p, np.array([n, n])


def _arc(center: Sequence[float], radius: float, a0: float, a1: float, step: float) -> Piece:
    """A circular arc from angle a0 to a1 (radians); counter-clockwise arcs face away from the centre."""
    count = max(2, math.ceil(abs(a1 - a0) / step) + 1)
    a = np.linspace(a0, a1, count)
    radial = np.stack([np.cos(a), np.sin(a)], axis=1)
    points = np.asarray(center, np.float64) + radius * radial
    return points, math.copysign(1.0, a1 - a0) * radial


def _chains(pieces: Sequence[Piece], crease_cos: float = math.cos(math.radians(1.0))) -> list[Piece]:
    """Joins consecutive pieces into smooth chains; where normals disagree, a crease starts a new chain.

    Each piece must start where the previous one ends; the start is snapped to that end so
    both copies of a crease vertex are bit-identical.
    """
    chains: list[list[Piece]] = []
    for given, normals in pieces:
        points = given.copy()
        if chains:
            last_points, last_normals = chains[-1][-1]
            if np.max(np.abs(points[0] - last_points[-1])) > 1e-9:
                raise ValueError(f"profile piece starts at {points[0]}, the previous one ends at {last_points[-1]}")
            points[0] = last_points[-1]
            if float(np.dot(normals[0], last_normals[-1])) >= crease_cos:
                chains[-1].append((points[1:], normals[1:]))
                continue
        chains.append([(points, normals)])
    return [(np.concatenate([p for p, _ in c]), np.concatenate([n for _, n in c])) for c in chains]


POLE_RADIUS = 1e-12  # profile points this close to the axis become one pole vertex
MIN_RADIUS = 1e-9  # a smaller sphere's rings fall within POLE_RADIUS of the axis


def _revolve(pieces: Sequence[Piece], segments: int) -> ShapeMesh:
    """Revolves a profile (r >= 0, y) about the y axis; points with r = 0 become single pole vertices.

    Profiles are walked with the solid on the left (counter-clockwise around the region in
    the (r, y) half-plane), which makes the triangles face outward. Tangents run along the
    parallels (the direction of increasing azimuth), a smooth field away from the poles.
    """
    phi = 2 * math.pi * np.arange(segments) / segments
    cos, sin = np.cos(phi), np.sin(phi)
    verts: list[np.ndarray] = []
    norms: list[np.ndarray] = []
    tans: list[np.ndarray] = []
    faces: list[np.ndarray] = []
    count = 0
    for points, normals in _chains(pieces):
        rows: list[np.ndarray] = []  # vertex ids of each profile point: 1 (pole) or `segments`
        for (r, y), (nr, ny) in zip(points, normals):
            if r <= POLE_RADIUS:
                verts.append(np.array([[0.0, y, 0.0]]))
                norms.append(np.array([[0.0, math.copysign(1.0, ny), 0.0]]))
                tans.append(np.array([[1.0, 0.0, 0.0]]))
                rows.append(np.array([count]))
                count += 1
            else:
                verts.append(np.stack([r * cos, np.full(segments, y), r * sin], axis=1))
                norms.append(np.stack([nr * cos, np.full(segments, ny), nr * sin], axis=1))
                tans.append(np.stack([-sin, np.zeros(segments), cos], axis=1))
                rows.append(count + np.arange(segments))
                count += segments
        for a, b in itertools.pairwise(rows):
            if len(a) == 1 and len(b) == 1:
                continue
            if len(a) == 1:
                faces.append(np.stack([np.full(segments, a[0]), b, np.roll(b, -1)], axis=1))
            elif len(b) == 1:
                faces.append(np.stack([a, np.full(segments, b[0]), np.roll(a, -1)], axis=1))
            else:
                a1, b1 = np.roll(a, -1), np.roll(b, -1)
                faces.append(np.stack([a, b, b1], axis=1))
                faces.append(np.stack([a, b1, a1], axis=1))
    if not faces:  # every profile point within POLE_RADIUS of the axis
        raise ValueError(f"the revolved profile lies within {POLE_RADIUS:g} of its axis: it has no triangles")
    return _finish(np.concatenate(verts), np.concatenate(faces), np.concatenate(norms), np.concatenate(tans), None)


def _transform(shape: ShapeMesh, rotation: np.ndarray, offset: Sequence[float]) -> ShapeMesh:
    r = np.asarray(rotation, np.float64)
    v = shape.vertices.astype(np.float64) @ r.T + np.asarray(offset, np.float64)
    return _finish(v, shape.indices, shape.normals @ r.T, shape.tangents @ r.T, shape.uvs)


def _rotation_z(degrees: float) -> np.ndarray:
    a = math.radians(degrees)
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


# --- the shapes -----------------------------------------------------------------------------


def sphere(radius: float = 1.0, detail: int = 64) -> ShapeMesh:
    """A sphere centred at the origin: `detail` rings pole to pole, 2 * detail segments around y.

    4 detail (detail - 1) triangles (16,128 by default). Normals are exactly radial, tangents
    run along the parallels. Watertight; uvs None (a closed surface has no seam-free uvs).
    Bounding box [-radius, radius]^3 for even detail (odd detail has no equator ring).
    """
    if not radius >= MIN_RADIUS or detail < 2:
        raise ValueError(f"sphere: need radius >= {MIN_RADIUS:g} and detail >= 2, got {radius:g}, {detail}")
    return _revolve([_arc((0.0, 0.0), radius, -math.pi / 2, math.pi / 2, math.pi / detail)], 2 * detail)


def plane(size: tuple[float, float] = (2.0, 2.0), divisions: int = 1) -> ShapeMesh:
    """A w x d rectangle in the xz plane at y = 0, centred, normal +y, tangent +x; uv = (x / w, z / d) + 0.5.

    divisions x divisions squares, two triangles each.
    """
    w, d = (float(s) for s in size)
    if w <= 0 or d <= 0 or divisions < 1:
        raise ValueError(f"plane: need a positive size and divisions >= 1, got {size}, {divisions}")
    u = np.linspace(0.0, 1.0, divisions + 1)
    uu, vv = np.meshgrid(u, u, indexing="ij")  # uu along x, vv along z
    vertices = np.stack([(uu - 0.5) * w, np.zeros_like(uu), (vv - 0.5) * d], axis=-1).reshape(-1, 3)
    faces = _grid_faces(divisions + 1, divisions + 1)
    n = len(vertices)
    return _finish(
        vertices,
        faces,
        np.tile([0.0, 1.0, 0.0], (n, 1)),
        np.tile([1.0, 0.0, 0.0], (n, 1)),
        np.stack([uu.ravel(), vv.ravel()], axis=1),
    )


def _grid_faces(nu: int, nv: int) -> np.ndarray:
    """Triangles of an nu x nv vertex grid (C order, v fastest), wound so that d/dv x d/du faces out."""
    i, j = np.meshgrid(np.arange(nu - 1), np.arange(nv - 1), indexing="ij")
    a = (i * nv + j).ravel()
    b, c, d = a + 1, a + nv + 1, a + nv
    return np.concatenate([np.stack([a, b, c], axis=1), np.stack([a, c, d], axis=1)])


# The preview object's dimensions (units; y up, resting on y = 0).
BALL_CENTER_Y = 1.18
BALL_OUTER = 0.80  # outer shell radius: the top is at 1.98
BALL_INNER = 0.70  # the shell's inside, seen through the band
BALL_CORE = 0.62  # the inner core
BAND = (-18.0, 10.0)  # latitudes (deg) of the band cut out of the shell, in the shell's own frame
BALL_TILT = 20.0  # the shell and band are tilted about z by this much, as on a shader ball


def _pedestal(step: float) -> list[Piece]:
    """A disc with a bevelled rim, a concave cove and a stem that ends inside the shell's wall."""
    cove_center, cove_r = (0.30, 0.23), 0.14
    return [
        _line((0.0, 0.0), (0.55, 0.0)),
        _line((0.55, 0.0), (0.55, 0.07)),
        _line((0.55, 0.07), (0.50, 0.09)),
        _line((0.50, 0.09), (0.30, 0.09)),
        _arc(cove_center, cove_r, -math.pi / 2, -math.pi, step),
        _line((0.16, 0.23), (0.16, 0.44)),
        _line((0.16, 0.44), (0.0, 0.44)),
    ]


def _shell_cap(upper: bool, step: float) -> list[Piece]:
    """One cap of the cut shell, centred at the origin: inner sphere, rounded lip, outer sphere."""
    lip_r = (BALL_OUTER - BALL_INNER) / 2
    mid = (BALL_OUTER + BALL_INNER) / 2
    if upper:
        edge = math.radians(BAND[1])
        c = (mid * math.cos(edge), mid * math.sin(edge))
        # inner sphere from the pole down to the band, the lip bulging into the band, outer sphere back up
        return [
            _arc((0.0, 0.0), BALL_INNER, math.pi / 2, edge, step),
            _arc(c, lip_r, edge + math.pi, edge + 2 * math.pi, step),
            _arc((0.0, 0.0), BALL_OUTER, edge, math.pi / 2, step),
        ]
    edge = math.radians(BAND[0])
    c = (mid * math.cos(edge), mid * math.sin(edge))
    return [
        _arc((0.0, 0.0), BALL_OUTER, -math.pi / 2, edge, step),
        _arc(c, lip_r, edge, edge + math.pi, step),
        _arc((0.0, 0.0), BALL_INNER, edge, -math.pi / 2, step),
    ]


def preview_ball(segments: int = 96, step_deg: float = 6.0) -> ShapeMesh:
    """A material-preview object in the spirit of a shader ball, resting on y = 0, 1.98 units tall.

    A bevelled pedestal (radius 0.55) with a concave cove and a stem carries a sphere shell
    (outer radius 0.80, inner 0.70, centre y = 1.18) from which a band between latitudes
    -18 and +10 deg is cut, its edges rounded; through the band an inner core sphere
    (radius 0.62) shows inside the shell's concave wall. The shell is tilted 20 deg about z,
    so the band rises towards +x. Creases (the pedestal's rim and bevel, the stem's end) are
    sharp; the rest is smooth. `segments` around the axis and one profile point every
    `step_deg` of turning (28,440 triangles by default). Centred on the y axis; bounding box
    about [-0.80, 0, -0.79] to [0.80, 1.98, 0.79]. Four closed shells: pedestal, upper and
    lower shell caps, core (the stem's end is buried in the lower cap's wall).
    """
    if segments < 8 or not 0.5 <= step_deg <= 30.0:
        raise ValueError(f"preview_ball: need segments >= 8 and 0.5 <= step_deg <= 30, got {segments}, {step_deg}")
    step = math.radians(step_deg)
    tilt = _rotation_z(BALL_TILT)
    centre = (0.0, BALL_CENTER_Y, 0.0)
    parts = [
        _revolve(_pedestal(step), segments),
        _transform(_revolve(_shell_cap(True, step), segments), tilt, centre),
        _transform(_revolve(_shell_cap(False, step), segments), tilt, centre),
        _transform(sphere(BALL_CORE, max(4, round(math.pi / step))), np.eye(3), centre),
    ]
    return _concatenate(parts)


def car_panel(
    size: tuple[float, float] = (2.0, 1.2),
    bulge: float = 0.10,
    crown: float = 0.05,
    crease: float = 0.015,
    crease_at: float = 0.15,
    divisions: tuple[int, int] = (160, 100),
) -> ShapeMesh:
    """A doubly curved body panel (a door or bonnet) facing +z with a sharp feature line along x.

    Over x in [-w/2, w/2], y in [-h/2, h/2] the surface is
        z = -bulge (2x/w)^2 - crown (2y/h)^2 - crease |y - y_c(x)| / (h/2),  y_c = crease_at h/2 + 0.05 x,
    convex towards +z in both directions, with a ridge (a crease in the normals) along the
    gently sloping line y = y_c(x). Two patches meet at the ridge with bit-identical
    vertices there, each with its own normals. Tangents follow dP/dx; uv = (x / w, y / h) + 0.5.
    Bounding box centred on the origin. divisions = (along x, across y for both patches).
    Open (not watertight).
    """
    w, h = (float(s) for s in size)
    nu, nv = divisions
    if w <= 0 or h <= 0 or nu < 2 or nv < 4:
        raise ValueError(f"car_panel: need a positive size and divisions >= (2, 4), got {size}, {divisions}")
    x = np.linspace(-w / 2, w / 2, nu + 1)
    yc = crease_at * h / 2 + 0.05 * x
    below = max(2, round(nv * (yc.mean() + h / 2) / h))
    patches = []
    for lo, hi, n, side in ((-h / 2, None, below, 1.0), (None, h / 2, nv - below, -1.0)):
        v = np.linspace(0.0, 1.0, n + 1)
        y0 = np.full_like(x, lo) if lo is not None else yc
        y1 = np.full_like(x, hi) if hi is not None else yc
        xx = np.repeat(x[:, None], n + 1, axis=1)
        yy = y0[:, None] + (y1 - y0)[:, None] * v[None, :]
        # d/dx and d/dy of z; on this patch |y - yc| has sign `side` (below the crease y < yc)
        dzdx = -2 * bulge * xx * 4 / (w * w) + side * crease / (h / 2) * (-0.05)
        dzdy = -2 * crown * yy * 4 / (h * h) + side * crease / (h / 2)
        zz = -bulge * (2 * xx / w) ** 2 - crown * (2 * yy / h) ** 2 - crease * np.abs(yy - yc[:, None]) / (h / 2)
        pos = np.stack([xx, yy, zz], axis=-1).reshape(-1, 3)
        nrm = np.stack([-dzdx, -dzdy, np.ones_like(zz)], axis=-1).reshape(-1, 3)
        tan = np.stack([np.ones_like(zz), np.zeros_like(zz), dzdx], axis=-1).reshape(-1, 3)
        uv = np.stack([xx / w + 0.5, yy / h + 0.5], axis=-1).reshape(-1, 2)
        # grid faces wind d/dv x d/du; here v runs along +y and u along +x, so swap to face +z
        faces = _grid_faces(nu + 1, n + 1)[:, [0, 2, 1]]
        patches.append((pos, faces, nrm, tan, uv))
    # the crease row: the top of the lower patch and the bottom of the upper one, bit-identical
    patches[1][0].reshape(nu + 1, -1, 3)[:, 0] = patches[0][0].reshape(nu + 1, -1, 3)[:, -1]
    offset = len(patches[0][0])
    pos = np.concatenate([patches[0][0], patches[1][0]])
    pos[:, 2] -= 0.5 * (pos[:, 2].max() + pos[:, 2].min())
    return _finish(
        pos,
        np.concatenate([patches[0][1], patches[1][1] + offset]),
        np.concatenate([patches[0][2], patches[1][2]]),
        np.concatenate([patches[0][3], patches[1][3]]),
        np.concatenate([patches[0][4], patches[1][4]]),
    )


def from_file(path: str | os.PathLike[str]) -> ShapeMesh:
    """A mesh file (via patina.load_mesh, so bad files raise FormatError) with smooth trimesh vertex normals.

    Vertices at the same position are merged so normals are smooth across the file's seams.
    Tangents are the x axis projected onto each normal's plane (the z axis where the normal
    is near x): smooth except around those vertices. uvs None.
    """
    import trimesh

    mesh = load_mesh(path)
    tm = trimesh.Trimesh(mesh.vertices, mesh.indices, process=False)
    tm.merge_vertices()
    normals = np.array(tm.vertex_normals, np.float64)
    lost = np.linalg.norm(normals, axis=1) < 0.5  # unreferenced or only on zero-area triangles
    normals[lost] = [0.0, 0.0, 1.0]
    tangents = np.tile([1.0, 0.0, 0.0], (len(normals), 1))
    return _finish(np.asarray(tm.vertices), np.asarray(tm.faces), normals, tangents, None)
