"""Validation like the CIE 171:2006 test cases (docs/lighting-validation.md), against analytic
results computed here:

- a Lambertian rectangle parallel to the plane, a corner above the points, and one standing
  on the plane: E = pi L F with F the differential form factor of the polygon by Lambert's
  contour integral (exact for any planar polygon);
- a closed box of uniform reflectance rho around an isotropic source of flux Phi: the mean
  interreflected illuminance over all its surfaces is rho Phi / (S (1 - rho)) exactly;
- a scaled-down Ward (1990) benchmark room against a radiosity solve written here.
(The point-source case is tests/python/lighting/test_direct.py's.)
"""

from __future__ import annotations

import math
import os

import numpy as np
import pytest

from patina.native import _core
from patina.render import illuminance as il
from patina.render.prepare import PreparedScene
from patina.scene.reading import parse_scene
from repo_paths import ROOT


def polygon_form_factor(points: np.ndarray, normals: np.ndarray, polygon: np.ndarray) -> np.ndarray:
    """Differential form factor from elements at `points` (n, 3) facing `normals` to a planar
    polygon (corners (k, 3), either winding, wholly in front): Lambert's contour integral
    F = |sum over edges of angle(v_i, v_i+1) n . unit(v_i x v_i+1)| / (2 pi)."""
    v = polygon[None, :, :] - points[:, None, :]
    w = np.roll(v, -1, axis=1)
    cross = np.cross(v, w)
    norm = np.linalg.norm(cross, axis=2)
    angle = np.arctan2(norm, np.einsum("nkj,nkj->nk", v, w))
    with np.errstate(invalid="ignore", divide="ignore"):
        term = np.where(norm > 0, angle * np.einsum("nkj,nj->nk", cross, normals) / norm, 0.0)
    return np.abs(term.sum(axis=1)) / (2 * np.pi)


def scene(shapes: list, lights: list, albedo: float = 0.5, max_depth: int = 8):
    obj = {
        "version": 1,
        "camera": {"position": [0, 5, 5], "look_at": [0, 0, 0], "width": 8, "height": 8},
        "render": {"integrator": "path", "max_depth": max_depth, "seed": 3},
        "materials": {"m": {"type": "lambert", "albedo": albedo}},
        "shapes": shapes,
        "lights": lights,
    }
    return parse_scene(obj, os.path.join(ROOT, "validation.json"))


FLOOR = [{"type": "plane", "material": "m", "size": [40, 40]}]


def test_form_factor_of_the_contour_integral_matches_the_textbook_parallel_rectangle():
    # the catalogued closed form for a rectangle a x b at height h, a corner above the element
    a, b, h = 2.0, 1.0, 1.5
    x, y = a / h, b / h
    closed = (
        x / math.sqrt(1 + x * x) * math.atan(y / math.sqrt(1 + x * x))
        + y / math.sqrt(1 + y * y) * math.atan(x / math.sqrt(1 + y * y))
    ) / (2 * math.pi)
    rect = np.array([[0, h, 0], [a, h, 0], [a, h, b], [0, h, b]], float)
    assert polygon_form_factor(np.zeros((1, 3)), np.array([[0.0, 1, 0]]), rect)[0] == pytest.approx(closed, rel=1e-12)


def test_a_lambertian_rectangle_parallel_to_the_plane_with_a_corner_above_the_point():
    a, b, h, lum = 2.0, 1.0, 1.5, 1000.0
    quad = {"type": "quad", "center": [a / 2, h, b / 2], "u": [a / 2, 0, 0], "v": [0, 0, b / 2], "luminance": lum}
    grid = il.parse_grid("0,0,1.5,1.5,8,8")  # the corner at the origin, and points off it
    report = il.compute(scene(FLOOR, [quad]), grid, samples=1024)
    _, _, pts = grid.points()
    rect = np.array([[0, h, 0], [a, h, 0], [a, h, b], [0, h, b]], float)
    expected = math.pi * lum * polygon_form_factor(pts.astype(float), np.tile([0.0, 1, 0], (len(pts), 1)), rect)
    rel = report.lux.ravel() / expected - 1
    # 1024 area-light samples a point: each estimate's own spread is about 1 % (rms)
    assert abs(rel.mean()) < 0.003 and np.sqrt(np.mean(rel**2)) < 0.015


def test_a_lambertian_rectangle_standing_on_the_plane():
    c, a, b, lum = 1.0, 1.5, 2.0, 1000.0  # the rectangle x = c, y 0..a, z 0..b, facing -x
    quad = {"type": "quad", "center": [c, a / 2, b / 2], "u": [0, 0, b / 2], "v": [0, a / 2, 0], "luminance": lum}
    grid = il.parse_grid("-1.5,0,0.5,2,8,8")
    report = il.compute(scene(FLOOR, [quad]), grid, samples=1024)
    _, _, pts = grid.points()
    rect = np.array([[c, 0, 0], [c, a, 0], [c, a, b], [c, 0, b]], float)
    expected = math.pi * lum * polygon_form_factor(pts.astype(float), np.tile([0.0, 1, 0], (len(pts), 1)), rect)
    rel = report.lux.ravel() / expected - 1
    # seen at grazing angles the rectangle's area samples spread more: about 3 % rms at 1024
    assert abs(rel.mean()) < 0.005 and np.sqrt(np.mean(rel**2)) < 0.05


def box_shapes(w: float, h: float, d: float) -> list:
    """A closed box x in [-w/2, w/2], y in [0, h], z in [-d/2, d/2], every face facing in."""
    placements = [
        ([w, d], None, [0, 0, 0]),
        ([w, d], [[1, 0, 0], 180], [0, h, 0]),
        ([w, h], [[1, 0, 0], 90], [0, h / 2, -d / 2]),
        ([w, h], [[1, 0, 0], -90], [0, h / 2, d / 2]),
        ([h, d], [[0, 0, 1], -90], [-w / 2, h / 2, 0]),
        ([h, d], [[0, 0, 1], 90], [w / 2, h / 2, 0]),
    ]
    shapes = []
    for size, rotate, translate in placements:
        transform = {"translate": translate} if rotate is None else {"rotate": rotate, "translate": translate}
        shapes.append({"type": "plane", "material": "m", "size": size, "transform": transform})
    return shapes


def box_sensors(w: float, h: float, d: float, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """n x n sensors at cell centres on each face, inward normals, and each one's area."""
    pts, nrm, area = [], [], []
    c = (np.arange(n) + 0.5) / n - 0.5
    u, v = np.meshgrid(c, c, indexing="ij")
    u, v = u.ravel(), v.ravel()
    one = np.ones_like(u)
    faces = [
        (np.stack([u * w, 0 * one, v * d], 1), [0, 1, 0], w * d),
        (np.stack([u * w, h * one, v * d], 1), [0, -1, 0], w * d),
        (np.stack([u * w, (v + 0.5) * h, -d / 2 * one], 1), [0, 0, 1], w * h),
        (np.stack([u * w, (v + 0.5) * h, d / 2 * one], 1), [0, 0, -1], w * h),
        (np.stack([-w / 2 * one, (v + 0.5) * h, u * d], 1), [1, 0, 0], h * d),
        (np.stack([w / 2 * one, (v + 0.5) * h, u * d], 1), [-1, 0, 0], h * d),
    ]
    for p, normal, face_area in faces:
        pts.append(p)
        nrm.append(np.tile(normal, (len(p), 1)))
        area.append(np.full(len(p), face_area / len(p)))
    as_f32 = [np.ascontiguousarray(np.concatenate(a), np.float32) for a in (pts, nrm)]
    return as_f32[0], as_f32[1], np.concatenate(area)


def interreflected(prepared: PreparedScene, pts, nrm, samples: int, depth: int) -> np.ndarray:
    """The sensor kernel's interreflections alone (its direct estimate uses the same streams)."""
    total = np.asarray(_core.sensor_illuminance(prepared.core, pts, nrm, samples, 5, 0, 0, depth), np.float64)
    return total - _core.sensor_illuminance(prepared.core, pts, nrm, samples, 5, 0, 0, 0)


@pytest.mark.parametrize("rho", [0.3, 0.7])
def test_a_closed_box_of_uniform_reflectance_reflects_rho_phi_over_s_one_minus_rho(rho):
    w, h, d, cd = 4.0, 2.5, 3.0, 1000.0
    s = scene(box_shapes(w, h, d), [{"type": "point", "position": [0.7, 1.9, -0.4], "intensity_cd": cd}], rho, 64)
    pts, nrm, area = box_sensors(w, h, d, 10)
    e = interreflected(PreparedScene(s), pts, nrm, 128, il.sensor_depth(s))
    phi, total_area = 4 * math.pi * cd, 2 * (w * d + w * h + h * d)
    expected = rho * phi / (total_area * (1 - rho))
    assert (e * area).sum() / area.sum() == pytest.approx(expected, rel=0.01)


# --- Ward's benchmark room, scaled for the suite ----------------------------------------------
# The full room (docs/lighting-validation.md): 10 x 6 x 3 m, a 0.5 m square source of exitance
# 31.416 W/m^2 at the ceiling's centre, reflectances ceiling 0.7, walls 0.5, floor 0.3, points
# every 0.5 m from 0.25 m on the floor. Here: the same room, source and reflectances; the floor
# points every 1 m from 0.5 m and 0.5 m radiosity patches keep the test to seconds.
ROOM = (10.0, 3.0, 6.0)
RHO = {"floor": 0.3, "ceiling": 0.7, "walls": 0.5}
SOURCE_RADIANCE = 31.416 / math.pi  # W/m^2/sr: a Lambertian exitance of 31.416 W/m^2


def room_patches(step: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Square patches of the room's inside: corners (p, 4, 3), centres, inward normals, rho."""
    w, h, d = ROOM
    corners, normals, rho = [], [], []

    def face(origin, du, dv, nu, nv, normal, r):
        for i in range(nu):
            for j in range(nv):
                o = origin + i * du + j * dv
                corners.append([o, o + du, o + du + dv, o + dv])
                normals.append(normal)
                rho.append(r)

    ex, ey, ez = np.eye(3)
    nx, ny, nz = round(w / step), round(h / step), round(d / step)
    face(np.zeros(3), ex * step, ez * step, nx, nz, ey, RHO["floor"])
    face(np.array([0, h, 0]), ex * step, ez * step, nx, nz, -ey, RHO["ceiling"])
    face(np.zeros(3), ex * step, ey * step, nx, ny, ez, RHO["walls"])
    face(np.array([0, 0, d]), ex * step, ey * step, nx, ny, -ez, RHO["walls"])
    face(np.zeros(3), ez * step, ey * step, nz, ny, ex, RHO["walls"])
    face(np.array([w, 0, 0]), ez * step, ey * step, nz, ny, -ex, RHO["walls"])
    c = np.asarray(corners, float)
    return c, c.mean(axis=1), np.asarray(normals, float), np.asarray(rho, float)


def radiosity_floor_lux(points: np.ndarray, step: float) -> np.ndarray:
    """Direct + interreflected illuminance (in Patina's lux: 683 x W/m^2) on the floor points
    by a radiosity solve: patch-centre form factors by the contour integral, (I - rho F) B = rho E0."""
    w, h, d = ROOM
    corners, centres, normals, rho = room_patches(step)
    src = np.array([[w / 2 - 0.25, h, d / 2 - 0.25], [w / 2 + 0.25, h, d / 2 - 0.25],
                    [w / 2 + 0.25, h, d / 2 + 0.25], [w / 2 - 0.25, h, d / 2 + 0.25]])  # fmt: skip
    # the source hangs just below the ceiling: the ceiling behind it gets no light
    under = (np.abs(centres[:, 0] - w / 2) < 0.25) & (np.abs(centres[:, 2] - d / 2) < 0.25) & (normals[:, 1] < 0)
    lit = ~(normals[:, 1] < 0)  # the ceiling sees the source edge-on
    e0 = np.zeros(len(centres))
    e0[lit] = math.pi * SOURCE_RADIANCE * polygon_form_factor(centres[lit], normals[lit], src)
    f = np.zeros((len(centres), len(centres)))
    for j in range(len(centres)):
        facing = np.einsum("ij,j->i", centres - centres[j], normals[j]) > 1e-9  # in front of patch j
        facing &= np.einsum("ij,ij->i", centres[j] - centres, normals) > 1e-9  # and j in front of them
        f[facing, j] = polygon_form_factor(centres[facing], normals[facing], corners[j])
    r = np.where(under, 0.0, rho)
    b = np.linalg.solve(np.eye(len(centres)) - r[:, None] * f, r * e0)  # exitance of each patch
    up = np.tile([0.0, 1, 0], (len(points), 1))
    e = math.pi * SOURCE_RADIANCE * polygon_form_factor(points, up, src)
    walls_and_ceiling = normals[:, 1] <= 0
    for j in np.nonzero(walls_and_ceiling)[0]:
        e += b[j] * polygon_form_factor(points, up, corners[j])
    return 683.0 * e


def ward_errors(point_step: float, patch_step: float, samples: int) -> np.ndarray:
    """Patina's floor illuminance with interreflections over the radiosity solve's, less 1, at
    floor points every `point_step` from half of it (tools/ward_room.py runs the full room)."""
    w, h, d = ROOM
    light = {"type": "quad", "center": [0, h - 1e-3, 0], "u": [0.25, 0, 0], "v": [0, 0, 0.25],
             "radiance": SOURCE_RADIANCE}  # fmt: skip
    shapes = [dict(s, material=name) for s, name in zip(box_shapes(w, h, d), ["floor", "ceiling", *["walls"] * 4])]
    s = parse_scene(
        {
            "version": 1,
            "camera": {"position": [0, 1.5, 0], "look_at": [1, 1.5, 0], "width": 8, "height": 8},
            "render": {"integrator": "path", "max_depth": 64, "seed": 1},
            "materials": {k: {"type": "lambert", "albedo": v} for k, v in RHO.items()},
            "shapes": shapes,
            "lights": [light],
        },
        os.path.join(ROOT, "ward.json"),
    )
    half = point_step / 2
    nx, nz = round(w / point_step), round(d / point_step)
    grid = il.parse_grid(f"{-w / 2 + half},{-d / 2 + half},{w / 2 - half},{d / 2 - half},{nx},{nz}")
    report = il.compute(s, grid, samples=samples, indirect=True)
    _, _, pts = grid.points()
    room_pts = pts.astype(float) + np.array([w / 2, 0, d / 2])  # the solve's room starts at the origin
    return report.lux.ravel() / radiosity_floor_lux(room_pts, patch_step) - 1


def test_wards_benchmark_room_against_a_radiosity_solve():
    rel = ward_errors(point_step=1.0, patch_step=0.5, samples=2048)
    assert np.abs(rel).max() < 0.02, rel
