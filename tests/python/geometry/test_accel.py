"""The kd-tree tracer through patina.Accel: against a brute-force double-precision
reference, across packet widths, against Embree (embreex), and on the cases that break
kd-trees (rays through vertices and edges, rays lying in split planes, degenerate
triangles, empty scenes, bad input)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import patina
from patina.geometry import benchmark_geometry as scenes
from patina.geometry.accel import Accel, Hits
from patina.geometry.mesh import Mesh
from patina.native import _core
from patina.widths import WIDTHS as ALL_WIDTHS

CoreAccel = _core.Accel  # these tests need the C++ tracer; fail loudly at import without it

WIDTHS = [w for w in ALL_WIDTHS if _core.width_supported(w)]
PACKETS = [w for w in WIDTHS if w > 1]

# --- a plain reference: Moller-Trumbore in double precision over every triangle --------


# Below 1e-4, the cosine between ray and plane no longer widens tolerances.
MIN_COS = 1e-4
# How near an edge (mt_pairs' margin, scene units) a hit may go either way.
EDGE_EPS = 2e-6
# How near tmin or tmax (relative, floor 1) a hit may go either way.
T_EPS = 1e-6


def mt_pairs(tris: np.ndarray, o: np.ndarray, d: np.ndarray) -> tuple[np.ndarray, ...]:
    """Ray/triangle tests pairwise over broadcast shapes: t, u, v, margin.

    t is inf where the ray is parallel to the plane or the triangle has zero area. margin is
    the hit point's distance to the nearest edge (> 0 inside, < 0 outside) times the cosine
    between ray and normal: float32 errors of a few ulps across the plane move a grazing
    ray's hit by as much divided by that cosine, and barycentrics of slivers are
    ill-conditioned, so a distance, so scaled, is the fair measure of "near an edge".
    """
    tris = np.asarray(tris, np.float64)
    o = np.asarray(o, np.float64)
    d = np.asarray(d, np.float64)
    v0, v1, v2 = tris[..., 0, :], tris[..., 1, :], tris[..., 2, :]
    e1, e2 = v1 - v0, v2 - v0
    p = np.cross(d, e2)
    det = np.sum(e1 * p, axis=-1)
    twice_area = np.linalg.norm(np.cross(e1, e2), axis=-1)
    d_len = np.linalg.norm(d, axis=-1)
    cos = np.abs(det) / np.maximum(twice_area * d_len, 1e-300)
    ok = (twice_area > 0) & (cos > 1e-12)
    inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
    s = o - v0
    u = np.sum(s * p, axis=-1) * inv
    q = np.cross(s, e1)
    v = np.sum(d * q, axis=-1) * inv
    t = np.where(ok, np.sum(e2 * q, axis=-1) * inv, np.inf)
    # barycentric times the height over the opposite edge = distance to that edge
    lengths = [np.linalg.norm(v2 - v1, axis=-1), np.linalg.norm(e2, axis=-1), np.linalg.norm(e1, axis=-1)]
    dist = [b * twice_area / np.maximum(h, 1e-300) for b, h in zip((1 - u - v, u, v), lengths)]
    margin = np.minimum(np.minimum(dist[0], dist[1]), dist[2]) * np.maximum(cos, MIN_COS)
    return t, u, v, np.where(ok, margin, -np.inf)


def mt_all(tris: np.ndarray, o: np.ndarray, d: np.ndarray, eps: float, tmin=0.0, tmax=None) -> np.ndarray:
    """(n, T) t of every ray against every triangle, inf where not hit in (tmin, tmax].

    eps > 0 counts hits up to eps outside the edges (loose), eps < 0 only those |eps|
    inside (strict); eps is a `margin` as mt_pairs defines it. Loose also takes hits up to
    T_EPS (relative) outside (tmin, tmax], strict only those T_EPS inside: a ray that starts
    on a surface may or may not hit it at t = 0.
    """
    n = len(o)
    tmax = np.full(n, np.inf) if tmax is None else np.broadcast_to(np.asarray(tmax, np.float64), (n,))
    slack = np.sign(eps) * T_EPS
    tmin = tmin - slack * (1 + abs(tmin))
    with np.errstate(invalid="ignore"):
        tmax = np.where(np.isinf(tmax), tmax, tmax + slack * (1 + np.abs(tmax)))
    out = np.empty((n, len(tris)))
    step = max(1, 400_000 // max(len(tris), 1))
    for a in range(0, n, step):
        b = min(n, a + step)
        t, _, _, margin = mt_pairs(tris[None], o[a:b, None], d[a:b, None])
        good = (margin >= -eps) & (t > tmin) & (t <= tmax[a:b, None])
        out[a:b] = np.where(good, t, np.inf)
    return out


def tol(t: np.ndarray, rtol: float, cos: np.ndarray | float = 1.0) -> np.ndarray:
    """Tolerance on t (and on hit positions) for float32 tracing.

    Relative, with a floor because float32 errors scale with the scene (about 1 here) rather
    than with t; divided by the cosine between ray and normal, because a grazing ray turns a
    tiny error across the plane into a large one along the ray.
    """
    return rtol * (np.abs(t) + 1.0) / np.maximum(np.abs(cos), MIN_COS)


def plane_cos(tris: np.ndarray, prim: np.ndarray, d: np.ndarray) -> np.ndarray:
    """|cos| of the angle between each ray and the normal of its triangle (1 where prim < 0)."""
    tri = tris[np.maximum(prim, 0)].astype(np.float64)
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    c = np.abs(np.sum(n * d, axis=1)) / (np.linalg.norm(n, axis=1) * np.linalg.norm(d, axis=1) + 1e-300)
    return np.where(prim >= 0, c, 1.0)


def check_against_reference(mesh: Mesh, o, d, hits: Hits, tmin=0.0, tmax=None, rtol=1e-5) -> None:
    """Every clear hit is found; every reported hit is real and the closest, up to edge ties.

    A hit within EDGE_EPS of an edge (as mt_pairs measures it) may go to either triangle
    or, on an open edge, be missed; a tie between two triangles at the same t may go to either.
    """
    tris = mesh.triangles()
    o = np.asarray(o, np.float64)
    d = np.asarray(d, np.float64)
    loose = mt_all(tris, o, d, EDGE_EPS, tmin, tmax)
    strict = mt_all(tris, o, d, -EDGE_EPS, tmin, tmax)
    t_loose = loose.min(axis=1) if tris.size else np.full(len(o), np.inf)
    t_strict = strict.min(axis=1) if tris.size else np.full(len(o), np.inf)

    must_hit = np.isfinite(t_strict)
    assert hits.hit[must_hit].all(), f"rays {np.flatnonzero(must_hit & ~hits.hit)[:10]} missed a clear hit"
    assert np.all(hits.t[~hits.hit] == np.inf)
    assert np.all(hits.prim[~hits.hit] == -1)

    i = np.flatnonzero(hits.hit)
    t = hits.t[i].astype(np.float64)
    t_own = loose[i, hits.prim[i]]
    nearest = np.where(np.isfinite(t_strict[i]), np.argmin(strict[i], axis=1), -1) if tris.size else -np.ones(0, int)
    cos = np.minimum(plane_cos(tris, hits.prim[i], d[i]), plane_cos(tris, nearest, d[i]))
    assert np.all(np.abs(t - t_own) <= tol(t_own, rtol, cos)), "reported t is not where the ray meets that triangle"
    assert np.all(t >= t_loose[i] - tol(t_loose[i], rtol, cos)), "a hit before the reported one was skipped"
    assert np.all(t <= t_strict[i] + tol(t_strict[i], rtol, cos)), "the reported hit is behind a clear hit"

    # barycentrics and normal follow the documented conventions
    tri = tris[hits.prim[i]].astype(np.float64)
    u, v = hits.u[i, None].astype(np.float64), hits.v[i, None].astype(np.float64)
    from_uv = (1 - u - v) * tri[:, 0] + u * tri[:, 1] + v * tri[:, 2]
    from_t = o[i] + t[:, None] * d[i]
    assert np.all(np.linalg.norm(from_uv - from_t, axis=1) <= tol(t, rtol, cos))
    n_ref = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    n_ref /= np.linalg.norm(n_ref, axis=1, keepdims=True)
    assert np.allclose(hits.normal[i], n_ref, atol=1e-4)
    assert np.all(hits.normal[~hits.hit] == 0)


def assert_same_hits(mesh: Mesh, o, d, a: tuple[np.ndarray, np.ndarray], b: tuple[np.ndarray, np.ndarray], rtol):
    """Two tracers agree: same triangle and t, except ties (two triangles at the same t) and
    grazing hits near an edge (10 EDGE_EPS), which one may report and the other miss."""
    (ta, pa), (tb, pb) = a, b
    tris = mesh.triangles()
    d64 = np.asarray(d, np.float64)
    same = pa == pb
    both = same & (pa >= 0)
    cos = plane_cos(tris, pa, d64)
    assert np.all(np.abs(ta[both] - tb[both]) <= tol(tb[both], rtol, cos[both])), "t differs on the same triangle"
    diff = np.flatnonzero(~same)
    assert len(diff) < len(pa) / 2, f"{len(diff)} of {len(pa)} rays disagree"
    for k in diff:
        ends = [(t, p) for t, p in ((ta[k], pa[k]), (tb[k], pb[k])) if p >= 0]
        margins = [mt_pairs(tris[p], o[k], d[k])[3] for _, p in ends]
        if len(ends) == 2:  # a tie: both triangles are met at the same t
            c = plane_cos(tris, np.array([pa[k], pb[k]]), d64[[k, k]]).min()
            assert abs(ends[0][0] - ends[1][0]) <= tol(ends[1][0], rtol, c), f"ray {k}: not a tie"
            assert min(margins) >= -10 * EDGE_EPS, f"ray {k}: a reported triangle is not on the ray"
        else:  # one hit, one miss: only a grazing hit on an edge may differ
            assert abs(margins[0]) <= 10 * EDGE_EPS, f"ray {k}: a clear hit was missed by one tracer"


# --- scenes --------------------------------------------------------------------------------


def _small_scenes() -> dict[str, Mesh]:
    return {
        "icosphere": scenes.icosphere(320),
        "soup": scenes.triangle_soup(300, seed=5),
        "thin": scenes.thin_triangles(300, seed=6),
        "boxes": scenes.box_field(300, seed=7),
    }


SMALL = _small_scenes()


def _random_rays_for(mesh: Mesh, n: int, seed: int) -> scenes.Rays:
    lo, hi = mesh.bounds.astype(np.float64)
    pad = 0.25 * (hi - lo)
    return scenes.random_rays(n, seed, lo - pad, hi + pad)


def _aimed_rays(mesh: Mesh, n: int, seed: int) -> scenes.Rays:
    """Rays from outside through random points on random triangles (most of them hit)."""
    rng = np.random.default_rng(seed)
    tris = mesh.triangles().astype(np.float64)
    k = rng.integers(0, len(tris), n)
    w = rng.dirichlet([1, 1, 1], n)
    target = np.einsum("nj,njk->nk", w, tris[k])
    lo, hi = mesh.bounds.astype(np.float64)
    centre, radius = (lo + hi) / 2, np.linalg.norm(hi - lo)
    origin = centre + radius * scenes._unit(rng.normal(size=(n, 3)))
    return scenes._rays(origin, target - origin)


# --- brute force -------------------------------------------------------------------------


@pytest.mark.parametrize("name", sorted(SMALL))
@pytest.mark.parametrize("width", WIDTHS)
@pytest.mark.parametrize("bvh", [False, True])
def test_random_rays_match_brute_force(name, width, bvh):
    mesh = SMALL[name]
    accel = Accel(mesh)
    for rays in (_random_rays_for(mesh, 3001, 11), _aimed_rays(mesh, 1003, 12)):
        hits = accel.intersect(*rays, width=width, bvh=bvh)
        check_against_reference(mesh, *rays, hits)


@pytest.mark.parametrize("width", WIDTHS)
@pytest.mark.parametrize("bvh", [False, True])
def test_tmin_and_tmax_match_brute_force(width, bvh):
    mesh = SMALL["icosphere"]
    rays = _aimed_rays(mesh, 2001, 13)
    rng = np.random.default_rng(14)
    tmax = rng.uniform(0.5, 5.0, len(rays.origins)).astype(np.float32)
    for tmin in (0.0, 1.5, 2.5):
        hits = Accel(mesh).intersect(*rays, tmin=tmin, tmax=tmax, width=width, bvh=bvh)
        assert np.all(hits.t[hits.hit] > tmin)
        check_against_reference(mesh, *rays, hits, tmin=tmin, tmax=tmax)


@pytest.mark.parametrize("max_leaf,max_depth", [(1, 0), (0, 1), (0, 4), (16, 0), (1, 64)])
def test_build_options_do_not_change_results(max_leaf, max_depth):
    mesh = SMALL["boxes"]
    accel = Accel(mesh, max_leaf=max_leaf, max_depth=max_depth)
    if max_depth:
        assert accel.depth <= max_depth
    rays = _random_rays_for(mesh, 2001, 15)
    for width in WIDTHS:
        check_against_reference(mesh, *rays, accel.intersect(*rays, width=width))


def test_t_is_the_ray_parameter():
    """Directions need not be unit length: t scales inversely, the hit stays the same."""
    mesh = SMALL["icosphere"]
    accel = Accel(mesh)
    o, d = _aimed_rays(mesh, 500, 16)
    unit = accel.intersect(o, d, width=1)
    scaled = accel.intersect(o, d * 2.5, width=1)
    assert np.array_equal(unit.prim, scaled.prim)
    assert np.allclose(scaled.t[unit.hit] * 2.5, unit.t[unit.hit], rtol=1e-5)


# --- packets against single rays -----------------------------------------------------------


def _assert_widths_agree(mesh: Mesh, accel: Accel, o: np.ndarray, d: np.ndarray) -> None:
    """Same hits at every width: same triangle and t, except that a tie (two triangles at the
    same t, as a ray through a shared edge meets them) may go either way."""
    ref = accel.intersect(o, d, width=1)
    for width in PACKETS:
        got = accel.intersect(o, d, width=width)
        same = got.prim == ref.prim
        both = ref.hit & got.hit
        assert np.array_equal(got.hit, ref.hit), f"width {width}: hit and miss differ"
        assert np.all(np.abs(got.t[both] - ref.t[both]) <= 1e-6 * np.abs(ref.t[both]))
        ties = np.flatnonzero(~same)
        t, _, _, margin = mt_pairs(mesh.triangles()[got.prim[ties]], o[ties], d[ties])
        assert np.all(margin >= -EDGE_EPS), f"width {width}: a reported triangle is not on the ray"
        cos = plane_cos(mesh.triangles(), got.prim[ties], d[ties].astype(np.float64))
        assert np.all(np.abs(t - got.t[ties]) <= tol(t, 1e-5, cos))
        assert np.allclose(got.u[same & both], ref.u[same & both], atol=1e-6)
        assert np.allclose(got.v[same & both], ref.v[same & both], atol=1e-6)
        assert np.allclose(got.normal[same], ref.normal[same], atol=1e-6)
        occ = accel.occluded(o, d, tmax=np.inf, width=width)
        assert np.array_equal(occ, ref.hit)


@pytest.fixture(scope="module")
def medium_scenes() -> dict[str, tuple[Mesh, Accel, tuple[tuple[float, ...], ...]]]:
    """(mesh, accel, camera (eye, target)) for scenes large enough to have deep trees."""
    out = {}
    for name, mesh, eye, target in (
        ("icosphere", scenes.icosphere(5000), (0.3, -3.0, 0.8), (0, 0, 0)),
        ("boxes", scenes.box_field(20_000, seed=8), (0.2, -2.2, 1.2), (0, 0, 0)),
        ("thin", scenes.thin_triangles(5000, seed=9), (0.5, -1.2, 0.6), (0.5, 0.5, 0.5)),
    ):
        out[name] = (mesh, Accel(mesh), (eye, target))
    return out


@pytest.mark.parametrize("name", ["icosphere", "boxes", "thin"])
@pytest.mark.parametrize("count", [64 * 48, 64 * 48 - 3, 4093])
def test_packets_match_single_rays_coherent(medium_scenes, name, count):
    """Camera rays in tile order; counts that leave a partial packet at the end."""
    mesh, accel, (eye, target) = medium_scenes[name]
    o, d = scenes.pinhole_rays(64, 64, eye, target, 45.0)
    _assert_widths_agree(mesh, accel, o[:count], d[:count])


@pytest.mark.parametrize("name", ["icosphere", "boxes", "thin"])
def test_packets_match_single_rays_incoherent(medium_scenes, name):
    mesh, accel, (eye, target) = medium_scenes[name]
    _assert_widths_agree(mesh, accel, *_random_rays_for(mesh, 5003, 17))
    primary = scenes.pinhole_rays(48, 40, eye, target, 45.0)
    bounce = scenes.diffuse_bounce_rays(accel, primary, seed=18)
    assert len(bounce.origins) > 100
    _assert_widths_agree(mesh, accel, *bounce)


@pytest.mark.parametrize("name", ["icosphere", "boxes", "thin"])
def test_bvh_gives_the_same_hits_at_every_width_and_the_kd_trees_t(medium_scenes, name):
    """The BVH: bit-identical hits at every width (ties go to the least triangle id); where it
    reports the kd-tree's triangle, the same t, u, v (the same watertight arithmetic)."""
    mesh, accel, (eye, target) = medium_scenes[name]
    primary = scenes.pinhole_rays(48, 40, eye, target, 45.0)
    for o, d in (_random_rays_for(mesh, 5003, 17), scenes.diffuse_bounce_rays(accel, primary, seed=18), primary):
        ref = accel.intersect(o, d, width=1, bvh=True)
        for width in WIDTHS:
            got = accel.intersect(o, d, width=width, bvh=True)
            for field in ("t", "prim", "u", "v"):
                assert np.array_equal(getattr(got, field), getattr(ref, field)), f"width {width}: {field} differs"
            tmax = np.where(ref.hit, ref.t * np.float32(1.001), np.float32(10.0)).astype(np.float32)
            assert np.array_equal(accel.occluded(o, d, tmax, width=width, bvh=True), ref.hit)
            assert not accel.occluded(o, d, ref.t * np.float32(0.999), width=width, bvh=True)[ref.hit].any()
        kd = accel.intersect(o, d, width=1)
        assert np.array_equal(kd.hit, ref.hit)
        same = kd.prim == ref.prim
        assert same.mean() > 0.99
        assert np.array_equal(kd.t[same], ref.t[same]) and np.array_equal(kd.u[same], ref.u[same])
        np.testing.assert_allclose(kd.t[~same], ref.t[~same], rtol=1e-6)  # ties


def test_threads_do_not_change_results(medium_scenes):
    mesh, accel, _ = medium_scenes["boxes"]
    o, d = _random_rays_for(mesh, 20_011, 19)
    one = accel.intersect(o, d, threads=1)
    two = accel.intersect(o, d, threads=2)
    for field in ("t", "prim", "u", "v", "normal"):
        assert np.array_equal(getattr(one, field), getattr(two, field))
    assert np.array_equal(accel.occluded(o, d, 0.5, threads=1), accel.occluded(o, d, 0.5, threads=2))
    rebuilt = Accel(mesh, threads=1)
    assert np.array_equal(rebuilt.intersect(o, d).prim, one.prim)


# --- occlusion -----------------------------------------------------------------------------


@pytest.mark.parametrize("width", WIDTHS)
def test_occluded_iff_hit_before_tmax(medium_scenes, width):
    mesh, accel, _ = medium_scenes["boxes"]
    o, d = _random_rays_for(mesh, 8003, 20)
    ref = accel.intersect(o, d, width=1)
    rng = np.random.default_rng(21)
    finite_t = np.where(ref.hit, ref.t, 1.0)
    tmax = (finite_t * rng.uniform(0.5, 1.5, len(o))).astype(np.float32)
    occ = accel.occluded(o, d, tmax, width=width)
    clear = np.abs(ref.t - tmax) > 1e-5 * tmax  # away from the boundary t == tmax
    assert np.array_equal(occ[clear], (ref.t < tmax)[clear])
    # a scalar tmax, infinite tmax and a tmin beyond every hit
    assert np.array_equal(accel.occluded(o, d, np.inf, width=width), ref.hit)
    assert np.array_equal(accel.occluded(o, d, 2.0, width=width)[ref.t < 1.9], np.ones(np.sum(ref.t < 1.9), bool))
    assert not accel.occluded(o, d, np.inf, tmin=100.0, width=width).any()
    beyond = accel.intersect(o, d, tmin=0.3, width=width)
    assert np.array_equal(accel.occluded(o, d, np.inf, tmin=0.3, width=width), beyond.hit)


# --- against Embree ------------------------------------------------------------------------


def _embree(mesh: Mesh, o: np.ndarray, d: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    from embreex import rtcore_scene as rtcs
    from embreex.mesh_construction import TriangleMesh

    scene = rtcs.EmbreeScene()
    TriangleMesh(scene, mesh.triangles())
    res = scene.run(o, d, output=1)
    prim = res["primID"].astype(np.int32)
    t = np.where(prim >= 0, res["tfar"], np.inf).astype(np.float32)
    return t, prim


@pytest.mark.parametrize("which", ["icosphere", "boxes"])
def test_agrees_with_embree(which):
    pytest.importorskip("embreex")
    if which == "icosphere":
        mesh, eye, target = scenes.icosphere(80_000), (0.3, -3.0, 0.8), (0.0, 0.0, 0.0)
    else:
        mesh, eye, target = scenes.box_field(60_000, seed=10), (0.2, -2.2, 1.2), (0.0, 0.0, 0.0)
    accel = Accel(mesh)
    primary = scenes.pinhole_rays(160, 160, eye, target, 50.0)
    ray_sets = [primary, _random_rays_for(mesh, 20_000, 22), scenes.diffuse_bounce_rays(accel, primary, seed=23)]
    for o, d in ray_sets:
        theirs = _embree(mesh, o, d)
        for width in WIDTHS:
            hits = accel.intersect(o, d, width=width)
            assert_same_hits(mesh, o, d, (hits.t, hits.prim), theirs, rtol=1e-4)


# --- watertightness ------------------------------------------------------------------------


@pytest.mark.parametrize("target", [300, 80_000])
def test_no_ray_leaks_out_of_a_closed_sphere(target):
    """From inside a closed icosphere every ray hits it, including rays aimed exactly at its
    vertices and at the midpoints of its edges (where a non-watertight test lets rays slip)."""
    import trimesh

    level = round(math.log(target / 20, 4))
    tm = trimesh.creation.icosphere(subdivisions=level)
    mesh = Mesh.from_trimesh(tm)
    accel = Accel(mesh)
    verts = mesh.vertices.astype(np.float64)
    edges = np.asarray(tm.edges_unique)
    aims = np.vstack([verts, (verts[edges[:, 0]] + verts[edges[:, 1]]) / 2])
    rng = np.random.default_rng(24)
    origins = [np.zeros(3), np.array([0.1, -0.2, 0.3]), *(rng.uniform(-0.5, 0.5, (2, 3)))]
    for origin in origins:
        o = np.broadcast_to(origin, aims.shape).astype(np.float32)
        d = (aims - origin).astype(np.float32)  # the exact vertex direction from the origin
        random_o = np.broadcast_to(origin, (5000, 3)).astype(np.float32)
        random_d = rng.normal(size=(5000, 3)).astype(np.float32)
        for width in WIDTHS:
            hits = accel.intersect(o, d, width=width)
            leaks = np.flatnonzero(~hits.hit)
            assert len(leaks) == 0, f"width {width}, origin {origin}: rays {leaks[:8]} leaked"
            assert np.allclose(hits.t, 1.0, atol=2e-3), "a ray aimed at the surface hit it elsewhere"
            assert accel.intersect(random_o, random_d, width=width).hit.all()
            assert accel.occluded(o, d, np.inf, width=width).all()


# --- axis-aligned geometry and rays in split planes -----------------------------------------


def _aligned_boxes() -> Mesh:
    """Axis-aligned boxes of distinct heights on a 3 x 3 grid: many faces share planes."""
    import trimesh

    parts = []
    heights = [0.25, 0.5, 0.75, 1.0, 0.375, 0.625, 0.875, 0.125, 1.25]
    for k, h in enumerate(heights):
        i, j = divmod(k, 3)
        box = trimesh.creation.box(extents=(0.5, 0.5, h))
        box.apply_translation((i + 0.25, j + 0.25, h / 2))
        parts.append(box)
    return Mesh.from_trimesh(trimesh.util.concatenate(parts), "aligned")


def _in_plane_rays(mesh: Mesh) -> scenes.Rays:
    """Rays lying exactly in planes of the boxes' faces, along the axes and the diagonals."""
    coords = [np.unique(mesh.vertices[:, a].astype(np.float64)) for a in range(3)]
    origins, dirs = [], []
    for a in range(3):
        b, c = (a + 1) % 3, (a + 2) % 3
        in_plane = []
        for db, dc in ((1, 0), (-1, 0), (0, 1), (0, -1), (1, 1), (1, -1), (-1, 1), (2, 1)):
            v = np.zeros(3)
            v[b], v[c] = db, dc
            in_plane.append(v)
        for plane in coords[a]:
            for pb in [-1.0, 0.1, *coords[b][::2], 3.7]:
                for pc in [-1.0, 0.3, *coords[c][1::2], 3.9]:
                    p = np.zeros(3)
                    p[a], p[b], p[c] = plane, pb, pc
                    for v in in_plane:
                        origins.append(p)
                        dirs.append(v)
    return scenes._rays(np.array(origins), np.array(dirs))


@pytest.mark.parametrize("width", WIDTHS)
def test_rays_in_axis_planes_match_brute_force(width):
    mesh = _aligned_boxes()
    accel = Accel(mesh)
    rays = _in_plane_rays(mesh)
    assert len(rays.origins) > 2000
    check_against_reference(mesh, *rays, accel.intersect(*rays, width=width))
    # axis-parallel rays from generic points, and from points on the planes
    rng = np.random.default_rng(25)
    o = rng.uniform(-0.5, 3.5, (3000, 3))
    o[::2, 2] = rng.choice(np.unique(mesh.vertices[:, 2]), 1500)
    d = np.zeros((3000, 3))
    axis = rng.integers(0, 3, 3000)
    d[np.arange(3000), axis] = rng.choice([-1.0, 1.0], 3000)
    rays2 = scenes._rays(o, d)
    check_against_reference(mesh, *rays2, accel.intersect(*rays2, width=width))


# --- degenerate input ----------------------------------------------------------------------


def _with_degenerates() -> tuple[Mesh, np.ndarray]:
    """A small box field plus zero-area triangles (collinear in float32 too, repeated corner, a point);
    returns the mesh and the ids of the degenerate triangles."""
    base = SMALL["boxes"]
    v = base.vertices.astype(np.float64)
    extra_v = np.array(
        [[0, 0, 0.25], [0.5, 0.5, 0.375], [1, 1, 0.5], [-0.3, 0.2, 0.1], [0.4, -0.6, 0.5], [0.1, 0.1, 0.1]], np.float64
    )
    k = len(v)
    extra_i = np.array([[k, k + 1, k + 2], [k + 3, k + 3, k + 4], [k + 5, k + 5, k + 5], [k + 4, k + 3, k + 4]])
    # a degenerate triangle built from an existing box edge: it lies exactly on real geometry
    edge_tri = np.array([[base.indices[0, 0], base.indices[0, 1], base.indices[0, 1]]])
    indices = np.vstack([base.indices, extra_i, edge_tri])
    degenerate = np.arange(base.triangle_count, len(indices))
    return Mesh(np.vstack([v, extra_v]), indices, "degenerate"), degenerate


@pytest.mark.parametrize("width", WIDTHS)
def test_degenerate_triangles_are_never_hit(width):
    mesh, degenerate = _with_degenerates()
    accel = Accel(mesh)
    rng = np.random.default_rng(26)
    # rays through points on the degenerate triangles, from every side
    tris = mesh.triangles()[degenerate].astype(np.float64)
    w = rng.dirichlet([1, 1, 1], 3000)
    target = np.einsum("nj,njk->nk", w, tris[rng.integers(0, len(tris), 3000)])
    origin = target + 2 * scenes._unit(rng.normal(size=(3000, 3)))
    for rays in (scenes._rays(origin, target - origin), _random_rays_for(mesh, 3000, 27)):
        hits = accel.intersect(*rays, width=width)
        assert not np.isin(hits.prim, degenerate).any()
        assert np.all(np.isfinite(hits.t[hits.hit]))
        check_against_reference(mesh, *rays, hits)
    only = Mesh(mesh.vertices, mesh.indices[degenerate], "only-degenerate")
    assert not Accel(only).intersect(*_random_rays_for(only, 1000, 28), width=width).hit.any()


@pytest.mark.parametrize("width", WIDTHS)
def test_empty_scene_misses_everything(width):
    rays = scenes.random_rays(37, 29, (-1, -1, -1), (1, 1, 1))
    for accel in (Accel(Mesh(np.zeros((0, 3)), np.zeros((0, 3), int), "empty")), Accel([])):
        assert accel.triangle_count == 0
        hits = accel.intersect(*rays, width=width)
        assert not hits.hit.any()
        assert np.all(hits.t == np.inf) and np.all(hits.prim == -1) and np.all(hits.mesh == -1)
        assert not accel.occluded(*rays, np.inf, width=width).any()


def test_zero_rays():
    accel = Accel(SMALL["icosphere"])
    hits = accel.intersect(np.zeros((0, 3)), np.zeros((0, 3)))
    assert len(hits) == 0 and hits.normal.shape == (0, 3)
    assert accel.occluded(np.zeros((0, 3)), np.zeros((0, 3)), 1.0).shape == (0,)


# --- several meshes ------------------------------------------------------------------------


def test_several_meshes_report_mesh_and_local_triangle():
    import trimesh

    left = Mesh.from_trimesh(trimesh.creation.icosphere(2).apply_translation((-2, 0, 0)), "left")
    empty = Mesh(np.zeros((0, 3)), np.zeros((0, 3), int), "nothing")
    right = Mesh.from_trimesh(trimesh.creation.box().apply_translation((2, 0, 0)), "right")
    accel = Accel([left, empty, right])
    assert accel.triangle_count == left.triangle_count + right.triangle_count
    assert list(accel.offsets) == [0, 320, 320, 332]
    o = np.array([[-2, -5, 0], [2, -5, 0.1], [0, -5, 0], [2, 5, 0.2]], np.float32)
    d = np.array([[0, 1, 0], [0, 1, 0], [0, 1, 0], [0, -1, 0]], np.float32)
    hits = accel.intersect(o, d)
    assert hits.hit.tolist() == [True, True, False, True]
    assert hits.mesh.tolist() == [0, 2, -1, 2]
    assert hits.local_prim[2] == -1
    assert np.array_equal(hits.prim[hits.hit], accel.offsets[hits.mesh[hits.hit]] + hits.local_prim[hits.hit])
    # the local triangle is the one each mesh alone reports
    alone = Accel(right).intersect(o[[1, 3]], d[[1, 3]])
    assert hits.local_prim[[1, 3]].tolist() == alone.prim.tolist()
    assert np.allclose(hits.t[[1, 3]], [4.5, 4.5])


def test_stats():
    accel = Accel(SMALL["boxes"])
    s = accel.stats()
    assert s["triangles"] == SMALL["boxes"].triangle_count
    assert 0 < accel.leaf_count < accel.node_count
    assert accel.depth >= 1 and accel.build_seconds >= 0
    assert "triangles" in repr(accel)


# --- bad input -----------------------------------------------------------------------------


@pytest.fixture(scope="module")
def small_accel() -> Accel:
    return Accel(SMALL["icosphere"])


def _rays(n=8):
    return scenes.random_rays(n, 30, (-2, -2, -2), (2, 2, 2))


@pytest.mark.parametrize("bad", [np.nan, np.inf, 0.0])
def test_bad_direction_names_the_ray(small_accel, bad):
    o, d = _rays()
    d = d.copy()
    d[3] = bad
    with pytest.raises(ValueError, match=r"directions: ray 3\b"):
        small_accel.intersect(o, d)
    with pytest.raises(ValueError, match=r"directions: ray 3\b"):
        small_accel.occluded(o, d, 1.0)


def test_bad_origin_names_the_ray(small_accel):
    o, d = _rays()
    o = o.copy()
    o[5, 1] = np.nan
    with pytest.raises(ValueError, match=r"origins: ray 5\b"):
        small_accel.intersect(o, d)


def test_the_core_checks_rays_too():
    """The C++ layer refuses bad rays by itself (naming the ray), whatever calls it."""
    mesh = SMALL["icosphere"]
    core = CoreAccel(mesh.vertices, mesh.indices)
    o, d = _rays()
    d = d.copy()
    d[6] = 0
    with pytest.raises(ValueError, match="6"):
        core.intersect(o, d)
    o2 = o.copy()
    o2[2, 0] = np.inf
    with pytest.raises(ValueError, match="2"):
        core.occluded(o2, _rays()[1], 1.0)


def test_the_core_checks_meshes_too():
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32)
    with pytest.raises(ValueError, match="refers to vertex 99"):
        CoreAccel(v, np.array([[0, 1, 99]], np.int32))
    bad = v.copy()
    bad[1, 2] = np.nan
    with pytest.raises(ValueError, match=r"vertex 1\b"):
        CoreAccel(bad, np.array([[0, 1, 2]], np.int32))


@pytest.mark.parametrize(
    "o_shape,d_shape,arg",
    [
        ((8, 3), (7, 3), "directions"),
        ((8, 2), (8, 3), "origins"),
        ((8, 3), (8,), "directions"),
        ((3,), (3,), "origins"),
    ],
)
def test_mismatched_shapes(small_accel, o_shape, d_shape, arg):
    with pytest.raises(ValueError, match=arg):
        small_accel.intersect(np.ones(o_shape), np.ones(d_shape))


def test_bad_tmax_tmin_width_threads(small_accel, monkeypatch):
    o, d = _rays()
    with pytest.raises(ValueError, match="tmax"):
        small_accel.intersect(o, d, tmax=np.ones(7))
    with pytest.raises(ValueError, match="tmax: ray 2"):
        small_accel.occluded(o, d, np.array([1, 1, np.nan, 1, 1, 1, 1, 1]))
    with pytest.raises(ValueError, match="tmin"):
        small_accel.intersect(o, d, tmin=np.nan)
    for width in (0, 2, 3, 32):
        with pytest.raises(ValueError, match="width"):
            small_accel.intersect(o, d, width=width)
    with pytest.raises(ValueError, match="threads"):
        small_accel.intersect(o, d, threads=-1)
    monkeypatch.setattr(patina.geometry.accel._core, "width_supported", lambda w: w != 8)
    with pytest.raises(ValueError, match="8-wide SIMD is not supported"):
        small_accel.intersect(o, d, width=8)


def test_accel_arguments():
    with pytest.raises(TypeError, match="item 1"):
        Accel([SMALL["icosphere"], np.zeros((3, 3))])
    with pytest.raises(ValueError, match="max_leaf"):
        Accel(SMALL["icosphere"], max_leaf=-1)


def test_inputs_of_any_layout_and_dtype(small_accel):
    """float64, non-contiguous and integer arrays are converted, with the same results."""
    o, d = _rays(101)
    ref = small_accel.intersect(o, d)
    wide = np.zeros((101, 6))
    wide[:, ::2] = d
    got = small_accel.intersect(o.astype(np.float64), wide[:, ::2], tmax=np.full(101, np.inf))
    assert np.array_equal(got.prim, ref.prim) and np.array_equal(got.t, ref.t)
    assert small_accel.intersect(np.array([[0, -5, 0]]), np.array([[0, 1, 0]])).hit.all()


# --- the ray generators --------------------------------------------------------------------


@pytest.mark.parametrize("w,h", [(8, 4), (16, 8), (12, 6)])
def test_pixel_order_makes_square_packets(w, h):
    px = scenes.pixel_order(w, h)
    assert sorted(map(tuple, px.tolist())) == sorted((x, y) for y in range(h) for x in range(w))
    for size, (tx, ty) in ((4, (2, 2)), (8, (4, 2))):
        for g in px.reshape(-1, size, 2):
            assert g[:, 0].max() - g[:, 0].min() == tx - 1 and g[:, 1].max() - g[:, 1].min() == ty - 1
            assert g[:, 0].min() % tx == 0 and g[:, 1].min() % ty == 0
    assert px[:4].tolist() == [[0, 0], [1, 0], [0, 1], [1, 1]]


def test_pixel_order_edges_and_custom_tiles():
    px = scenes.pixel_order(7, 5)  # not a multiple of the 4x2 tile: still every pixel once
    assert len({tuple(p) for p in px.tolist()}) == 35
    rows = scenes.pixel_order(4, 3, tiles=((1, 1),))  # plain row-major order
    assert rows.tolist() == [[x, y] for y in range(3) for x in range(4)]
    with pytest.raises(ValueError, match="multiple"):
        scenes.pixel_order(8, 8, tiles=((2, 2), (3, 2)))


def test_pinhole_rays_are_unit_and_centred():
    o, d = scenes.pinhole_rays(32, 16, (0, -3, 0), (0, 0, 0), 40.0)
    assert o.dtype == np.float32 and d.dtype == np.float32 and o.shape == (512, 3)
    assert np.allclose(np.linalg.norm(d, axis=1), 1, atol=1e-6)
    assert np.allclose(d.mean(axis=0) / np.linalg.norm(d.mean(axis=0)), [0, 1, 0], atol=1e-6)
    # the vertical field of view is 40 degrees: the top-row rays are about 20 degrees up
    assert math.degrees(math.asin(d[:, 2].max())) == pytest.approx(20 * 15 / 16, abs=0.5)


def test_scenes_are_deterministic_and_sized():
    assert scenes.icosphere().triangle_count == 81_920
    a, b = scenes.box_field(1200, seed=3), scenes.box_field(1200, seed=3)
    assert np.array_equal(a.vertices, b.vertices) and a.triangle_count == 1202
    assert not np.array_equal(a.vertices, scenes.box_field(1200, seed=4).vertices)
    assert scenes.triangle_soup(500).triangle_count == 500
    assert scenes.thin_triangles(500).triangle_count == 500
    for n in (10_000, 30_000):
        assert abs(scenes.sphere_of(n).triangle_count - n) <= 0.05 * n


def test_bounce_rays_leave_the_surface():
    mesh = scenes.icosphere(1280)
    accel = Accel(mesh)
    primary = scenes.pinhole_rays(32, 32, (0, -3, 0), (0, 0, 0), 45.0)
    bounce = scenes.diffuse_bounce_rays(accel, primary, seed=31)
    assert np.allclose(np.linalg.norm(bounce.directions, axis=1), 1, atol=1e-6)
    # from outside a sphere, every bounce leaves it outward and never comes back
    assert np.all(np.linalg.norm(bounce.origins, axis=1) > 0.99)
    assert not accel.intersect(*bounce).hit.any()
    again = scenes.diffuse_bounce_rays(accel, primary, seed=31)
    assert np.array_equal(again.directions, bounce.directions)
