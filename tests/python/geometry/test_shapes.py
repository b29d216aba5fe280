"""Built-in shapes (patina.geometry.shapes): shading frames, watertightness, bounds, and that the tracer hits them."""

from __future__ import annotations

import math

import numpy as np
import pytest
import trimesh
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

import patina
from patina.geometry import shapes
from patina.geometry.shapes import ShapeMesh

CLOSED = {
    "sphere": shapes.sphere,
    "sphere_small": lambda: shapes.sphere(2.5, detail=8),
    "ball": shapes.preview_ball,
    "ball_coarse": lambda: shapes.preview_ball(segments=24, step_deg=15.0),
}
OPEN = {
    "plane": shapes.plane,
    "plane_divided": lambda: shapes.plane((3.0, 1.0), divisions=4),
    "panel": shapes.car_panel,
    "panel_coarse": lambda: shapes.car_panel((1.0, 1.0), divisions=(12, 8)),
}
ALL = {**CLOSED, **OPEN}


@pytest.fixture(scope="module", params=sorted(ALL))
def shape(request: pytest.FixtureRequest) -> ShapeMesh:
    return ALL[request.param]()


def face_normals(s: ShapeMesh) -> tuple[np.ndarray, np.ndarray]:
    v = s.vertices.astype(np.float64)[s.indices]
    cross = np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0])
    area = 0.5 * np.linalg.norm(cross, axis=1)
    return cross / np.maximum(2 * area, 1e-300)[:, None], area


def merged(s: ShapeMesh) -> trimesh.Trimesh:
    """The mesh with vertices at the same position counted once (crease copies joined)."""
    tm = trimesh.Trimesh(s.vertices, s.indices, process=False)
    tm.merge_vertices(merge_tex=True, merge_norm=True)
    return tm


def test_arrays_have_the_documented_types(shape: ShapeMesh) -> None:
    v = len(shape.vertices)
    assert shape.vertices.dtype == np.float32 and shape.vertices.shape == (v, 3)
    assert shape.indices.dtype == np.int32 and shape.indices.shape[1] == 3
    assert shape.normals.dtype == np.float32 and shape.normals.shape == (v, 3)
    assert shape.tangents.dtype == np.float32 and shape.tangents.shape == (v, 3)
    assert shape.indices.min() >= 0 and shape.indices.max() < v
    if shape.uvs is not None:
        assert shape.uvs.dtype == np.float32 and shape.uvs.shape == (v, 2)
        assert shape.uvs.min() >= 0.0 and shape.uvs.max() <= 1.0
    assert 0 < shape.triangle_count <= 60_000


def test_frames_are_unit_and_orthogonal(shape: ShapeMesh) -> None:
    n = shape.normals.astype(np.float64)
    t = shape.tangents.astype(np.float64)
    np.testing.assert_allclose(np.linalg.norm(n, axis=1), 1.0, atol=1e-6)
    np.testing.assert_allclose(np.linalg.norm(t, axis=1), 1.0, atol=1e-6)
    assert np.abs(np.sum(n * t, axis=1)).max() < 1e-6


def test_normals_agree_with_the_winding(shape: ShapeMesh) -> None:
    """Every corner's shading normal on the side the triangle faces: outward for closed shapes."""
    fn, area = face_normals(shape)
    assert area.min() > 1e-9  # no degenerate triangles
    assert np.all(np.diff(np.sort(shape.indices, axis=1), axis=1) > 0)
    dots = np.einsum("tkj,tj->tk", shape.normals.astype(np.float64)[shape.indices], fn)
    assert dots.min() > 0.5


@pytest.mark.parametrize("name", sorted(CLOSED))
def test_closed_shapes_are_watertight_and_outward(name: str) -> None:
    s = CLOSED[name]()
    tm = merged(s)
    assert tm.is_watertight
    assert tm.is_winding_consistent
    # each connected shell encloses positive volume (outward winding), and is a sphere topologically
    faces = np.asarray(tm.faces)
    edges = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    graph = coo_matrix((np.ones(len(edges)), (edges[:, 0], edges[:, 1])), shape=(len(tm.vertices),) * 2)
    count, label = connected_components(graph, directed=False)
    assert count == (1 if name.startswith("sphere") else 4)
    v = np.asarray(tm.vertices)[faces]
    signed = np.einsum("ti,ti->t", v[:, 0], np.cross(v[:, 1], v[:, 2])) / 6.0
    for k in range(count):
        mine = label[faces[:, 0]] == k
        assert signed[mine].sum() > 1e-3
    assert tm.euler_number == 2 * count


@pytest.mark.parametrize("radius,detail", [(1.0, 64), (2.5, 8), (0.01, 4), (0.3, 5)])
def test_sphere_normals_are_radial(radius: float, detail: int) -> None:
    s = shapes.sphere(radius, detail)
    v = s.vertices.astype(np.float64)
    np.testing.assert_allclose(np.linalg.norm(v, axis=1), radius, rtol=1e-6)
    np.testing.assert_allclose(s.normals, v / radius, atol=2e-6)
    if detail % 2 == 0:  # an equator ring, and vertices on the x and z axes
        np.testing.assert_allclose(s.bounds, [[-radius] * 3, [radius] * 3], rtol=1e-6)
    else:
        np.testing.assert_allclose(s.bounds[:, 1], [-radius, radius], rtol=1e-6)
    assert s.triangle_count == 4 * detail * (detail - 1)
    assert s.uvs is None


def test_plane_layout() -> None:
    s = shapes.plane((3.0, 1.0), divisions=4)
    np.testing.assert_allclose(s.bounds, [[-1.5, 0.0, -0.5], [1.5, 0.0, 0.5]])
    np.testing.assert_array_equal(s.normals, np.tile([0.0, 1.0, 0.0], (len(s.vertices), 1)))
    fn, area = face_normals(s)
    np.testing.assert_allclose(fn, np.tile([0.0, 1.0, 0.0], (len(fn), 1)), atol=1e-12)
    assert area.sum() == pytest.approx(3.0)
    np.testing.assert_allclose(s.uvs, np.stack([s.vertices[:, 0] / 3 + 0.5, s.vertices[:, 2] + 0.5], axis=1))


def test_ball_bounds_and_proportions() -> None:
    s = shapes.preview_ball()
    lo, hi = s.bounds.astype(np.float64)
    assert lo[1] == 0.0
    assert hi[1] == pytest.approx(1.98, abs=0.01)
    assert abs(lo[0] + hi[0]) < 0.02 and abs(lo[2] + hi[2]) < 0.02  # centred on the y axis
    assert 0.75 < hi[0] <= 0.8 + 1e-6 and 0.75 < hi[2] <= 0.8 + 1e-6
    # the core shows through the band: some vertices of the core sphere (radius 0.62 about y = 1.18)
    d = np.linalg.norm(s.vertices.astype(np.float64) - [0.0, 1.18, 0.0], axis=1)
    assert np.sum(np.abs(d - 0.62) < 1e-5) > 1000
    # sharp creases exist (the pedestal's rim): positions shared by vertices with different normals
    _, inverse, counts = np.unique(s.vertices, axis=0, return_inverse=True, return_counts=True)
    shared = counts[inverse.ravel()] > 1
    assert shared.any()


def test_ball_is_hit_from_every_direction() -> None:
    """Rays from a sphere around the ball aimed at a point inside the core all hit."""
    s = shapes.preview_ball()
    accel = patina.Accel([s.mesh("ball")])
    rng = np.random.default_rng(1)
    d = rng.normal(size=(4000, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    target = np.array([0.0, 1.0, 0.0])
    origins = target - 5.0 * d
    hits = accel.intersect(origins.astype(np.float32), d.astype(np.float32))
    assert hits.hit.all()


def test_every_ball_triangle_is_intersectable() -> None:
    """A ray from just off each triangle's centroid, along its normal reversed, hits that triangle first."""
    s = shapes.preview_ball()
    accel = patina.Accel([s.mesh("ball")])
    fn, _ = face_normals(s)
    centroid = s.vertices.astype(np.float64)[s.indices].mean(axis=1)
    hits = accel.intersect((centroid + 1e-3 * fn).astype(np.float32), (-fn).astype(np.float32))
    assert hits.hit.all()
    assert np.mean(hits.local_prim == np.arange(s.triangle_count)) > 0.999
    np.testing.assert_allclose(np.median(hits.t), 1e-3, rtol=1e-2)


def test_panel_faces_z_with_a_feature_line() -> None:
    w, h = 2.0, 1.2
    s = shapes.car_panel((w, h))
    lo, hi = s.bounds.astype(np.float64)
    np.testing.assert_allclose(lo[:2], [-w / 2, -h / 2], atol=1e-6)
    np.testing.assert_allclose(hi[:2], [w / 2, h / 2], atol=1e-6)
    assert lo[2] == pytest.approx(-hi[2], abs=1e-6) and hi[2] > 0.05  # curved, bbox centred
    assert s.normals[:, 2].min() > 0.8
    assert not merged(s).is_watertight
    # doubly curved: the normal turns along x and along y
    assert np.ptp(s.normals[:, 0]) > 0.1 and np.ptp(s.normals[:, 1]) > 0.1
    # the feature line: one row of positions carried by two vertices whose normals differ by > 1 deg
    _, inverse, counts = np.unique(s.vertices, axis=0, return_inverse=True, return_counts=True)
    inverse = inverse.ravel()
    twins = np.nonzero(counts[inverse] == 2)[0]
    assert len(twins) > 100
    partner: dict[int, list[int]] = {}
    for i in twins:
        partner.setdefault(int(inverse[i]), []).append(int(i))
    angles = [math.degrees(math.acos(min(1.0, float(np.dot(s.normals[a], s.normals[b]))))) for a, b in partner.values()]
    assert min(angles) > 1.0
    # tangents follow +x
    assert s.tangents[:, 0].min() > 0.9


def test_from_file_gives_smooth_outward_frames(tmp_path) -> None:
    s = shapes.sphere(1.5, detail=12)
    path = tmp_path / "ball.obj"
    trimesh.Trimesh(s.vertices, s.indices, process=False).export(path)
    loaded = shapes.from_file(path)
    assert loaded.triangle_count == s.triangle_count
    n = loaded.normals.astype(np.float64)
    np.testing.assert_allclose(np.linalg.norm(n, axis=1), 1.0, atol=1e-6)
    radial = loaded.vertices / np.linalg.norm(loaded.vertices, axis=1, keepdims=True)
    assert np.sum(n * radial, axis=1).min() > 0.99
    assert np.abs(np.sum(n * loaded.tangents, axis=1)).max() < 1e-6
    assert np.linalg.norm(loaded.tangents, axis=1).min() > 0.999


def test_from_file_rejects_bad_files(tmp_path) -> None:
    bad = tmp_path / "bad.obj"
    bad.write_text("v 0 0 0\nv 1 0 0\nf 1 2 7\n")
    with pytest.raises(patina.FormatError):
        shapes.from_file(bad)
    with pytest.raises(patina.FormatError):
        shapes.from_file(tmp_path / "missing.obj")


@pytest.mark.parametrize(
    "make",
    [
        lambda: shapes.sphere(0.0),
        lambda: shapes.sphere(1.0, detail=1),
        lambda: shapes.plane((0.0, 1.0)),
        lambda: shapes.preview_ball(segments=4),
        lambda: shapes.car_panel((1.0, -1.0)),
    ],
)
def test_bad_parameters_raise(make) -> None:
    with pytest.raises(ValueError):
        make()
