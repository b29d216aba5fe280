"""patina.Mesh and load_mesh: checked arrays, files through trimesh, and bad files as FormatError."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from conftest import load_or_format_error
from patina.errors import FormatError
from patina.geometry.mesh import MESH_FORMATS, Mesh, MeshError, load_mesh

TRI_V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], np.float64)
TRI_I = np.array([[0, 1, 2], [0, 2, 3]], np.int64)


# --- Mesh ----------------------------------------------------------------------------------


def test_arrays_are_converted_and_read_only():
    m = Mesh(TRI_V, TRI_I, "two")
    assert m.vertices.dtype == np.float32 and m.indices.dtype == np.int32
    assert m.vertices.flags.c_contiguous and m.indices.flags.c_contiguous
    assert m.vertex_count == 4 and m.triangle_count == 2 and m.name == "two"
    assert np.array_equal(m.bounds, [[0, 0, 0], [1, 1, 1]])
    assert m.triangles().shape == (2, 3, 3)
    with pytest.raises(ValueError):
        m.vertices[0, 0] = 5
    # Fortran order and unsigned indices convert too
    f = Mesh(np.asfortranarray(TRI_V), TRI_I.astype(np.uint16))
    assert np.array_equal(f.indices, TRI_I)
    assert "2 triangles" in repr(m)


def test_empty_mesh_is_allowed():
    for v, i in ((np.zeros((0, 3)), np.zeros((0, 3), int)), ([], []), (TRI_V, np.zeros((0, 3), int))):
        m = Mesh(v, i)
        assert m.triangle_count == 0
    e = Mesh([], [])
    assert e.vertex_count == 0 and e.vertices.shape == (0, 3) and e.indices.shape == (0, 3)
    assert np.all(e.bounds[0] == np.inf) and np.all(e.bounds[1] == -np.inf)


@pytest.mark.parametrize(
    "vertices,indices,match",
    [
        (TRI_V[:, :2], TRI_I, r"vertices: must have shape \(V, 3\), got \(4, 2\)"),
        (TRI_V.ravel(), TRI_I, "vertices: must have shape"),
        (TRI_V.astype(complex), TRI_I, "vertices: must be real numbers"),
        (TRI_V, TRI_I[:, :2], r"indices: must have shape \(T, 3\)"),
        (TRI_V, TRI_I.astype(float), "indices: must be integers, got dtype float64"),
        (TRI_V, [[0, 1, 4]], "triangle 0: refers to vertex 4, the mesh has 4 vertices"),
        (TRI_V, [[0, 1, 2], [3, -1, 2]], "triangle 1: refers to vertex -1"),
        (TRI_V, [[0, 1, 2], [0, 1, 2**40]], "triangle 1: refers to vertex 1099511627776"),
    ],
)
def test_bad_arrays_name_the_argument_and_place(vertices, indices, match):
    with pytest.raises(ValueError, match=match):
        Mesh(vertices, indices, "bad")


@pytest.mark.parametrize("value", [np.nan, np.inf, -np.inf, 1e39])
def test_non_finite_vertex_is_named(value):
    v = TRI_V.copy()
    v[2, 1] = value
    with pytest.raises(MeshError, match=r"mesh 'm': vertex 2: is not finite") as e:
        Mesh(v, TRI_I, "m")
    assert e.value.where == "vertex 2"


def test_degenerate_triangles_are_kept():
    m = Mesh(TRI_V, [[0, 0, 1], [1, 1, 1]])
    assert m.triangle_count == 2


def test_from_trimesh_keeps_order():
    tm = trimesh.creation.icosphere(2)
    m = Mesh.from_trimesh(tm, "ico")
    assert m.name == "ico" and m.triangle_count == 320
    assert np.array_equal(m.indices, tm.faces) and np.allclose(m.vertices, tm.vertices)
    assert Mesh.from_trimesh(tm).name == "mesh"


# --- load_mesh -----------------------------------------------------------------------------


def _sorted_triangles(tris: np.ndarray) -> np.ndarray:
    """Triangles compared as a set of vertex triples, whatever the format did to the order."""
    flat = np.round(np.asarray(tris, np.float64).reshape(len(tris), 9), 5)
    return flat[np.lexsort(flat.T[::-1])]


@pytest.mark.parametrize("fmt", ["obj", "ply", "stl", "glb", "off"])
def test_load_round_trip(tmp_path, fmt):
    tm = trimesh.creation.icosphere(2)
    path = tmp_path / f"ball.{fmt}"
    tm.export(str(path))
    m = load_mesh(path)
    assert m.name == "ball" and m.triangle_count == 320
    assert np.array_equal(_sorted_triangles(m.triangles()), _sorted_triangles(tm.vertices[tm.faces]))
    assert load_mesh(str(path), name="named").name == "named"


def test_scene_is_concatenated(tmp_path):
    scene = trimesh.Scene()
    scene.add_geometry(trimesh.creation.box(), node_name="a")
    scene.add_geometry(
        trimesh.creation.icosphere(1), node_name="b", transform=trimesh.transformations.translation_matrix((3, 0, 0))
    )
    path = tmp_path / "two.glb"
    scene.export(str(path))
    m = load_mesh(path)
    assert m.triangle_count == 12 + 80
    assert m.bounds[1][0] == pytest.approx(4.0, abs=1e-5)  # the transform was applied


def test_latin1_obj(tmp_path):
    path = tmp_path / "labor.obj"
    path.write_bytes("# Messung: Glanzlack, Oberfläche\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n".encode("latin-1"))
    assert load_mesh(path).triangle_count == 1


def _expect_format_error(path, match: str | None = None) -> FormatError:
    with pytest.raises(FormatError, match=match) as e:
        load_mesh(path)
    assert str(path) in str(e.value)
    return e.value


def test_missing_file_and_directory(tmp_path):
    _expect_format_error(tmp_path / "nowhere.obj", "no such file")
    _expect_format_error(tmp_path, "not a regular file")


@pytest.mark.parametrize("fmt", MESH_FORMATS)
def test_empty_file(tmp_path, fmt):
    path = tmp_path / f"empty.{fmt}"
    path.write_bytes(b"")
    _expect_format_error(path, "empty file")


@pytest.mark.parametrize("fmt", MESH_FORMATS)
def test_garbage_bytes(tmp_path, fmt):
    path = tmp_path / f"garbage.{fmt}"
    path.write_bytes(np.random.default_rng(1).integers(0, 256, 700, dtype=np.uint8).tobytes())
    _expect_format_error(path)


def test_unknown_suffix(tmp_path):
    for name in ("mesh.xyz", "mesh.zip", "mesh"):
        path = tmp_path / name
        path.write_bytes(b"v 0 0 0\n")
        err = _expect_format_error(path, "unknown mesh format")
        assert err.where == "file name"


@pytest.mark.parametrize(
    "text,where",
    [
        ("v 0 0 0\nv 1 0 nan\nv 0 1 0\nf 1 2 3\n", "vertex 1"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 inf\nf 1 2 3\n", "vertex 2"),
        ("v 0 0 0\nv 1 0 1e39\nv 0 1 0\nf 1 2 3\n", "vertex 1"),
    ],
)
def test_non_finite_vertices_in_file(tmp_path, text, where):
    path = tmp_path / "nan.obj"
    path.write_text(text)
    err = _expect_format_error(path, "not finite")
    assert err.where == where


def test_non_finite_vertices_in_binary_formats(tmp_path):
    tm = trimesh.Trimesh(TRI_V.copy(), TRI_I, process=False)
    tm.vertices[3, 0] = np.nan
    for fmt in ("ply", "stl", "glb"):
        path = tmp_path / f"nan.{fmt}"
        tm.export(str(path))
        _expect_format_error(path, "not finite")


def test_no_triangles(tmp_path):
    path = tmp_path / "points.obj"
    path.write_text("# just points\nv 0 0 0\nv 1 0 0\n")
    _expect_format_error(path, "no triangles")
    path = tmp_path / "points.ply"
    trimesh.PointCloud(TRI_V).export(str(path))
    _expect_format_error(path)


def test_face_index_out_of_range(tmp_path):
    path = tmp_path / "bad.obj"
    path.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n")
    _expect_format_error(path)


def test_truncated_binary_files(tmp_path):
    tm = trimesh.creation.icosphere(2)
    for fmt in ("ply", "stl", "glb"):
        data = tm.export(file_type=fmt)
        for cut in (10, len(data) // 2, len(data) - 7):
            path = tmp_path / f"cut{cut}.{fmt}"
            path.write_bytes(data[:cut])
            try:
                m = load_mesh(path)
            except FormatError as e:
                assert str(path) in str(e)
            else:  # a reader may accept a prefix; what it returns must still be a valid mesh
                assert 0 < m.triangle_count <= 320


SETTINGS = settings(max_examples=120, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])


def _check_mesh(m) -> None:
    assert m.triangle_count > 0 and np.isfinite(m.vertices).all()
    assert m.indices.max() < m.vertex_count


def _load_or_format_error(content: bytes, filename: str) -> None:
    """Load `content` saved as `filename`: a FormatError naming the file, or a checked mesh."""
    load_or_format_error(content, filename, load_mesh, _check_mesh)


@SETTINGS
@given(content=st.binary(min_size=1, max_size=2048), fmt=st.sampled_from(MESH_FORMATS))
def test_random_bytes_never_escape_as_anything_but_format_error(content, fmt):
    _load_or_format_error(content, f"fuzz.{fmt}")


@SETTINGS
@given(
    data=st.data(),
    fmt=st.sampled_from(["obj", "ply", "stl", "off"]),
)
def test_damaged_valid_files(data, fmt):
    """A real file with a few bytes overwritten: FormatError or a checked mesh, nothing else."""
    base = _VALID[fmt]
    damaged = bytearray(base)
    for _ in range(data.draw(st.integers(1, 4))):
        at = data.draw(st.integers(0, len(base) - 1))
        damaged[at] = data.draw(st.integers(0, 255))
    _load_or_format_error(bytes(damaged), f"damaged.{fmt}")


_VALID = {fmt: trimesh.creation.icosphere(1).export(file_type=fmt) for fmt in ("obj", "ply", "stl", "off")}
_VALID = {k: v.encode() if isinstance(v, str) else v for k, v in _VALID.items()}
