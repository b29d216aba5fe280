"""A lighting project computed: the grids its standard lays out, the illuminance (exact direct
from point, spot and goniometric luminaires; sampled area light and interreflections with
`indirect`) times the maintenance factor, the standard's figures and the checks.

Every grid must lie over the scene's geometry (a grid beyond it measures light on nothing):
refused naming the project's key. A luminaire at or below the observer's eye cannot be
rated for TI: refused naming the scene's light.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from patina.errors import FormatError
from patina.kernel_arrays import as_float32
from patina.lighting.classes import Check, check, road_class
from patina.lighting.direct import PlacedSource, is_delta
from patina.lighting.grids import RuleGrid, en12193_grids, en12464_grid
from patina.lighting.indirect_cache import BOUND, RESOLUTION, CacheSettings, cached_indirect
from patina.lighting.indoor import area_figures, ugr
from patina.lighting.project import Project
from patina.lighting.road import Interreflected, check_luminaires_for_ti, evaluate_road
from patina.lighting.rtable import read_rtable
from patina.lighting.sensors import Sensors
from patina.lighting.ugr_table import UgrTable, luminous_area, ugr_table
from patina.photometry.luminaire import load_luminaire
from patina.render import illuminance as il
from patina.render.prepare import PreparedScene
from patina.scene.reading import load_scene
from patina.scene.types import LuminaireLight, Scene
from patina.widths import core_width

GEOMETRY_SLACK = 1e-3  # m a grid may reach past the scene's outermost surface (rounding)


@dataclass
class Plane:
    """A computed grid: its rule, values (nz, nx) and what they are."""

    name: str
    grid: RuleGrid
    values: np.ndarray
    label: str = "illuminance (lx)"


@dataclass
class Result:
    project: Project
    scene: Scene
    planes: list[Plane] = field(default_factory=list)
    figures: dict[str, float | None] = field(default_factory=dict)
    checks: list[Check] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    inputs: list[tuple[str, str]] = field(default_factory=list)
    ugr_tables: list[UgrTable] = field(default_factory=list)  # indoors: each luminaire file's

    def as_json(self) -> dict[str, Any]:
        return {
            "project": self.project.path,
            "standard": self.project.standard,
            "maintenance_factor": self.project.maintenance,
            "interreflections": interreflections(self.project),
            "figures": self.figures,
            "checks": [c.as_json() for c in self.checks],
            "grids": [{"name": p.name, **p.grid.as_json(), "values": p.values.tolist()} for p in self.planes],
            "notes": self.notes,
            "ugr_tables": [t.to_json() for t in self.ugr_tables],
        }


def _check_inside(project: Project, prepared: PreparedScene, grid: RuleGrid, key: str) -> None:
    tri = np.asarray(prepared.accel.triangles).reshape(-1, 3)
    if not len(tri):
        raise FormatError(project.scene, "shapes", "no geometry to lay a grid on")
    lo, hi = tri.min(axis=0) - GEOMETRY_SLACK, tri.max(axis=0) + GEOMETRY_SLACK
    for axis, values, name in ((0, grid.x, "x"), (2, grid.z, "z")):
        if values.min() < lo[axis] or values.max() > hi[axis]:
            raise FormatError(
                project.path,
                key,
                f"the grid reaches {name} = {values.min():g}..{values.max():g} m, beyond the scene's geometry "
                f"({name} = {lo[axis] + GEOMETRY_SLACK:g}..{hi[axis] - GEOMETRY_SLACK:g} m)",
            )


def _illuminance(project: Project, scene: Scene, grid: RuleGrid, progress: bool) -> np.ndarray:
    g = il.Grid(grid.x[0], grid.z[0], grid.x[-1], grid.z[-1], len(grid.x), len(grid.z), grid.y)
    report = il.compute(
        scene,
        g,
        samples=project.samples,
        progress=progress,
        indirect=project.indirect != "none",
        indirect_cache=project.indirect == "cache",
    )
    return np.asarray(report.lux, np.float64) * project.maintenance


def shown_path(path: str, project: Project) -> str:
    """A file as the report names it: relative to the project file's folder (as the project's
    author wrote it; the report goes to a client, not this machine's absolute paths)."""
    return os.path.relpath(path, os.path.dirname(os.path.abspath(project.path)))


def _inputs(project: Project, scene: Scene) -> list[tuple[str, str]]:
    files = sorted({shown_path(light.file, project) for light in scene.lights if isinstance(light, LuminaireLight)})
    rows = [
        ("project", os.path.basename(project.path)),
        ("scene", shown_path(project.scene, project)),
        ("luminaire files", ", ".join(files) or "none (point and spot lights)"),
        ("luminaires", str(sum(is_delta(light) for light in scene.lights))),
        (
            "maintenance factor",
            f"{project.maintenance:.3f}"
            + (
                f" = {' x '.join(f'{k} {v:g}' for k, v in project.maintenance_parts.items())}"
                if project.maintenance_parts
                else " (none given)"
            ),
        ),
        ("interreflections", interreflections(project)),
    ]
    return rows


def interreflections(project: Project) -> str:
    """How the project's interreflections were computed, with the settings (the report's inputs);
    a road's say that they reach its illuminance grids, not its luminance."""
    if project.indirect == "cache":
        how = (
            f"radiance cache: cache points among the grid's points, each {RESOLUTION} x {RESOLUTION} texel paths, "
            f"gathered by the points within error bound {BOUND:g}"
        )
    elif project.indirect == "paths":
        how = f"sensor paths, {project.samples} per point"
    else:
        return "no (direct only)"
    if project.standard == "en13201":
        how += "; in the illuminance grids only: the luminance from the r-table is direct (EN 13201-3's method)"
    return how


def run(project: Project, progress: bool = False) -> Result:
    scene = load_scene(project.scene)
    prepared = PreparedScene(scene)
    result = Result(project, scene, inputs=_inputs(project, scene))
    if project.standard == "en12464-1":
        _indoor(project, scene, prepared, result, progress)
    elif project.standard == "en13201":
        _road(project, scene, prepared, result)
    else:
        _sport(project, scene, prepared, result, progress)
    return result


def _indoor(project: Project, scene: Scene, prepared: PreparedScene, result: Result, progress: bool) -> None:
    room = en12464_grid(*project.room, project.height, project.wall_band, where="room")
    _check_inside(project, prepared, room, "room")
    task = en12464_grid(*project.task_area, project.height, where="task_area") if project.task_area else room
    e_room = _illuminance(project, scene, room, progress)
    e_task = _illuminance(project, scene, task, progress) if task is not room else e_room
    result.inputs.append(("grids", f"{room.rule}; task area: {task.rule}"))
    result.planes.append(Plane("room", room, e_room))
    if task is not room:
        result.planes.append(Plane("task area", task, e_task))
    t = area_figures(e_task)
    result.figures.update({"Em": t.em, "Emin": t.e_min, "Emax": t.e_max, "U0": t.u0})
    if project.task_area:
        x0, z0, x1, z1 = project.task_area
        pts = room.points()
        outside = ~((pts[:, 0] >= x0) & (pts[:, 0] <= x1) & (pts[:, 2] >= z0) & (pts[:, 2] <= z1))
        if outside.any():
            s = area_figures(e_room.ravel()[outside])
            result.figures.update({"Em surrounding": s.em, "U0 surrounding": s.u0})
    if project.eye is not None:
        result.figures["UGR"] = _ugr(project, scene, prepared, result)
    result.ugr_tables = _ugr_tables(scene, result)
    if project.ra is not None:
        result.figures["Ra"] = project.ra
    elif "Ra" in project.requirements:
        result.notes.append(
            'Ra: the luminaires\' colour rendering index is not in their photometric files; give it as "ra"'
        )
    result.checks = check(project.requirements, result.figures)


def _ugr_tables(scene: Scene, result: Result) -> list[UgrTable]:
    """The tabular method's table of each luminaire file (type C with a luminous area; the others
    named in a note), for the reader to compare the installation with the catalogue's rooms."""
    tables = []
    for path in sorted({light.file for light in scene.lights if isinstance(light, LuminaireLight)}):
        try:
            tables.append(ugr_table(load_luminaire(path)))
        except FormatError as e:
            result.notes.append(f"UGR table of {e.path}: not computed ({e.problem})")
    return tables


def eye_paths(project: Project) -> int:
    """The sensor paths of the interreflected light at the UGR observer's eye (one point: at
    least 1024, so that the background luminance is not the noisy part of UGR)."""
    return max(project.samples, 1024)


def _ugr(project: Project, scene: Scene, prepared: PreparedScene, result: Result) -> float | None:
    lights = [light for light in scene.lights if is_delta(light)]
    areas = []
    for light in lights:
        if isinstance(light, LuminaireLight):
            areas.append(luminous_area(load_luminaire(light.file)))
        else:
            areas.append(0.0)
    if not any(a > 0 for a in areas):
        result.notes.append("UGR: no luminaire declares a luminous area (IES width and length): not computed")
        return None
    eye = np.asarray(project.eye, np.float64)
    # L_b = E_ind / pi: the indirect vertical illuminance at the eye, facing the line of sight,
    # as the sensor kernel's interreflections
    a = math.radians(project.azimuth)
    pts = np.ascontiguousarray([eye], np.float32)
    normal = np.ascontiguousarray([[math.cos(a), 0.0, math.sin(a)]], np.float32)
    depth = il.sensor_depth(scene)
    samples, seed, width = eye_paths(project), scene.render.seed, core_width(None)
    interreflected = il.path_interreflections(prepared, pts, normal, samples, seed, width, 0, depth)
    e_ind = float(interreflected[0]) * project.maintenance
    result.figures["E_ind at the eye"] = e_ind
    if e_ind <= 0:
        result.notes.append("UGR: no interreflected light reaches the eye (background luminance 0): not computed")
        return None
    sources = [PlacedSource.of(light) for light in lights]
    value = ugr(sources, areas, eye, project.azimuth, e_ind / math.pi, prepared.accel, il.ray_offset(prepared))
    return value if math.isfinite(value) else None


def _road(project: Project, scene: Scene, prepared: PreparedScene, result: Result) -> None:
    road = project.road
    table = read_rtable(project.rtable)
    indices = [i for i, light in enumerate(scene.lights) if is_delta(light)]
    sources = [PlacedSource.of(scene.lights[i]) for i in indices]
    check_luminaires_for_ti(scene.path, sources, indices)
    _check_inside(project, prepared, road.illuminance_grid(), "road")
    offset, interreflected = il.ray_offset(prepared), _road_interreflections(project, scene, prepared)
    r = evaluate_road(sources, road, table, project.maintenance, project.verge, prepared.accel, offset, interreflected)
    lum = road.luminance_grid()
    result.planes.append(Plane("luminance, observer in lane 1", lum, r.luminance[0], "luminance (cd/m²)"))
    result.planes.append(Plane("illuminance", road.illuminance_grid(), r.illuminance))
    result.figures.update(r.figures())
    result.inputs += [
        (
            "r-table",
            f"{shown_path(project.rtable, project)} ({table.header.get('name', 'unnamed')}, Q0 {table.q0():.4f} 1/sr)",
        ),
        ("grids", f"{lum.rule}; {road.illuminance_grid().rule}"),
        ("observers", "; ".join(f"({o[0]:g}, {o[1]:g}, {o[2]:g}) m" for o in road.observers())),
        ("class", project.road_class),
    ]
    if r.eir is None:
        result.notes.append("EIR: no verge width given (road.verge): not computed")
    result.checks = check(road_class(project.road_class), result.figures)


def _road_interreflections(project: Project, scene: Scene, prepared: PreparedScene) -> Interreflected | None:
    """The interreflected lux at a road's horizontal sensor points by the project's method (the
    indoor grids' settings: patina.render.illuminance.compute), or None for direct light only."""
    if project.indirect == "none":
        return None
    depth, seed, width = il.sensor_depth(scene), scene.render.seed, core_width(None)

    def lux(points: np.ndarray) -> np.ndarray:
        sensors = Sensors.horizontal(points)
        if project.indirect == "cache":
            settings = CacheSettings(depth, seed, width=width)
            return cached_indirect(prepared.core, sensors.points, sensors.normals, settings).lux
        pts, up = as_float32(sensors.points), as_float32(sensors.normals)
        return il.path_interreflections(prepared, pts, up, project.samples, seed, width, 0, depth)

    return lux


def _sport(project: Project, scene: Scene, prepared: PreparedScene, result: Result, progress: bool) -> None:
    length, width, spacing, margin = project.field_size
    pa, ta = en12193_grids(length, width, spacing, margin, project.height)
    for name, g in (("principal area", pa), ("total area", ta)):
        _check_inside(project, prepared, g, "field")
        e = _illuminance(project, scene, g, progress)
        result.planes.append(Plane(name, g, e))
        f = area_figures(e)
        key = "" if name == "principal area" else " TA"
        result.figures.update({f"Em{key}": f.em, f"Emin{key}": f.e_min, f"U0{key}": f.u0})
    result.inputs.append(("grids", f"{pa.rule}; {ta.rule}"))
    result.checks = check(project.requirements, result.figures)
