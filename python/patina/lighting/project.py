"""A lighting project file: the scene, the standard and what the standard needs to be checked
(docs/lighting.md). JSON; every path relative to the file; every problem a FormatError naming
the key.

    {"scene": "../scenes/office-en12464.json", "standard": "en12464-1",
     "room": [x0, z0, x1, z1], "task_area": [x0, z0, x1, z1], "height": 0.75, "wall_band": true,
     "maintenance": {"LLMF": 0.9, "LSF": 1, "LMF": 0.9, "RSMF": 0.95},
     "requirements": {"Em": 500, "U0": 0.6, "UGR": 19, "Ra": 80}, "ra": 80,
     "observer": {"eye": [x, 1.2, z], "azimuth": 90}, "indirect": "cache", "samples": 64}

    {"scene": "../scenes/road-en13201.json", "standard": "en13201", "class": "M5",
     "road": {"kerb_x": -3.5, "lanes": 2, "lane_width": 3.5, "field_start": 0, "spacing": 30, "verge": 3},
     "rtable": "../rtables/synthetic-road.rtab", "maintenance": {"LLMF": 0.9, "LMF": 0.9}}

    {"scene": "pitch.json", "standard": "en12193",
     "field": {"length": 105, "width": 68, "spacing": 5, "margin": 5}, "requirements": {"Em": 200, "U0": 0.6}}
"""

from __future__ import annotations

import json
import math
import os
from dataclasses import dataclass, field
from typing import Any

from patina.errors import FormatError
from patina.lighting.classes import indoor_requirements, road_class
from patina.lighting.grids import Road
from patina.lighting.indoor import maintenance_factor

STANDARDS = ("en12464-1", "en13201", "en12193")
KEYS = {
    "en12464-1": {"room", "task_area", "height", "wall_band", "requirements", "ra", "observer"},
    "en13201": {"road", "rtable", "class"},
    "en12193": {"field", "height", "requirements"},
}
COMMON = {"scene", "standard", "maintenance", "indirect", "samples"}
MAX_SAMPLES = 1 << 16
# "indirect": how the interreflections are computed. true means the radiance cache: a lighting
# engineer asks for interreflections and expects them fast and accurate, and the cache gives the
# sensor paths' error about 9 to 10 times sooner (docs/lighting.md); "paths" keeps the sensor paths.
INDIRECT = {False: "none", True: "cache", "none": "none", "cache": "cache", "paths": "paths"}


@dataclass
class Project:
    path: str
    scene: str
    standard: str
    maintenance: float = 1.0
    maintenance_parts: dict[str, float] = field(default_factory=dict)
    indirect: str = "none"  # a value of INDIRECT
    samples: int = 64
    # en12464-1 / en12193
    room: tuple[float, float, float, float] | None = None
    task_area: tuple[float, float, float, float] | None = None
    height: float = 0.75
    wall_band: bool = True
    requirements: dict[str, tuple[str, float]] = field(default_factory=dict)
    ra: float | None = None
    eye: tuple[float, float, float] | None = None
    azimuth: float = 0.0
    # en13201
    road: Road | None = None
    verge: float = 0.0
    rtable: str | None = None
    road_class: str | None = None
    # en12193
    field_size: tuple[float, float, float, float] | None = None  # length, width, spacing, margin


def _number(path: str, key: str, value: Any, lo: float = -math.inf, hi: float = math.inf) -> float:
    if (
        isinstance(value, bool)
        or not isinstance(value, int | float)
        or not math.isfinite(value)
        or not lo <= value <= hi
    ):
        raise FormatError(path, key, f"expected a number in [{lo:g}, {hi:g}], got {json.dumps(value)[:40]}")
    return float(value)


def _rect(path: str, key: str, value: Any) -> tuple[float, float, float, float]:
    if not isinstance(value, list) or len(value) != 4:
        raise FormatError(path, key, "expected [x0, z0, x1, z1] in metres")
    x0, z0, x1, z1 = (_number(path, f"{key}[{i}]", v) for i, v in enumerate(value))
    if not (x1 > x0 and z1 > z0):
        raise FormatError(path, key, "expected x1 > x0 and z1 > z0")
    return x0, z0, x1, z1


def _object(path: str, key: str, value: Any, allowed: set[str], required: set[str] = frozenset()) -> dict:
    if not isinstance(value, dict):
        raise FormatError(path, key, "expected an object")
    for k in value:
        if k not in allowed:
            raise FormatError(path, f"{key}.{k}", f"unknown key (expected {', '.join(sorted(allowed))})")
    for k in sorted(required):
        if k not in value:
            raise FormatError(path, f"{key}.{k}", "missing")
    return value


def _indirect(path: str, value: Any) -> str:
    if not isinstance(value, bool | str) or value not in INDIRECT:
        expected = 'expected true (the radiance cache), false, "cache" or "paths"'
        raise FormatError(path, "indirect", f"{expected}, got {json.dumps(value)[:40]}")
    return INDIRECT[value]


def read_project(path: str, standard: str | None = None) -> Project:
    """Reads and checks a project file; `standard` (the --standard option) must agree with it."""
    try:
        with open(path, encoding="utf-8") as f:
            doc = json.load(f)
    except FileNotFoundError:
        raise FormatError(path, "", "no such file") from None
    except (json.JSONDecodeError, UnicodeDecodeError) as e:
        raise FormatError(path, f"line {getattr(e, 'lineno', 1)}", "not JSON") from None
    if not isinstance(doc, dict):
        raise FormatError(path, "", "expected a JSON object")
    std = doc.get("standard")
    if std not in STANDARDS:
        raise FormatError(path, "standard", f"expected one of {', '.join(STANDARDS)}, got {json.dumps(std)[:40]}")
    if standard is not None and standard != std:
        raise FormatError("command line", "--standard", f"'{standard}', but {path} is an {std} project")
    for k in doc:
        if k not in COMMON | KEYS[std]:
            raise FormatError(path, k, f"unknown key for {std} (expected {', '.join(sorted(COMMON | KEYS[std]))})")
    if not isinstance(doc.get("scene"), str):
        raise FormatError(path, "scene", "expected the scene file's path")
    here = os.path.dirname(os.path.abspath(path))
    scene = os.path.normpath(os.path.join(here, doc["scene"]))
    if not os.path.isfile(scene):
        raise FormatError(path, "scene", f"no such file: {doc['scene']}")
    parts = _object(path, "maintenance", doc.get("maintenance", {}), {"LLMF", "LSF", "LMF", "RSMF"})
    p = Project(path, scene, std, maintenance_factor(parts, path), dict(parts))
    if "indirect" in doc:
        p.indirect = _indirect(path, doc["indirect"])
    if "samples" in doc:
        p.samples = int(_number(path, "samples", doc["samples"], 1, MAX_SAMPLES))
    if std == "en12464-1":
        if "room" not in doc:
            raise FormatError(path, "room", "missing: the room's inside [x0, z0, x1, z1]")
        p.room = _rect(path, "room", doc["room"])
        if "task_area" in doc:
            p.task_area = _rect(path, "task_area", doc["task_area"])
            r, t = p.room, p.task_area
            if t[0] < r[0] or t[1] < r[1] or t[2] > r[2] or t[3] > r[3]:
                raise FormatError(path, "task_area", "reaches outside the room")
        p.height = _number(path, "height", doc.get("height", 0.75), 0, 100)
        if not isinstance(doc.get("wall_band", True), bool):
            raise FormatError(path, "wall_band", "expected true or false")
        p.wall_band = doc.get("wall_band", True)
        p.requirements = indoor_requirements(
            _object(path, "requirements", doc.get("requirements", {}), {"Em", "U0", "UGR", "Ra"}), path
        )
        if "ra" in doc:
            p.ra = _number(path, "ra", doc["ra"], 0, 100)
        if "observer" in doc:
            obs = _object(path, "observer", doc["observer"], {"eye", "azimuth"}, {"eye"})
            eye = obs["eye"]
            if not isinstance(eye, list) or len(eye) != 3:
                raise FormatError(path, "observer.eye", "expected [x, y, z] in metres")
            p.eye = tuple(_number(path, f"observer.eye[{i}]", v) for i, v in enumerate(eye))
            p.azimuth = _number(path, "observer.azimuth", obs.get("azimuth", 0.0), -360, 360)
    elif std == "en13201":
        keys = {"kerb_x", "lanes", "lane_width", "field_start", "spacing", "verge"}
        road = _object(path, "road", doc.get("road"), keys, keys - {"verge"})
        lanes = _number(path, "road.lanes", road["lanes"], 1, 12)
        if lanes != int(lanes):
            raise FormatError(path, "road.lanes", "expected a whole number of lanes")
        p.road = Road(
            _number(path, "road.kerb_x", road["kerb_x"]),
            int(lanes),
            _number(path, "road.lane_width", road["lane_width"], 1, 10),
            _number(path, "road.field_start", road["field_start"]),
            _number(path, "road.spacing", road["spacing"], 1, 200),
        )
        p.verge = _number(path, "road.verge", road.get("verge", 0.0), 0, 100)
        if not isinstance(doc.get("rtable"), str):
            raise FormatError(path, "rtable", "expected the r-table file's path (docs/lighting.md)")
        p.rtable = os.path.normpath(os.path.join(here, doc["rtable"]))
        if not isinstance(doc.get("class"), str):
            raise FormatError(path, "class", "expected an EN 13201-2 class (M1-M6, C0-C5, P1-P6)")
        try:
            road_class(doc["class"])
        except FormatError as e:
            raise FormatError(path, "class", e.problem) from None
        p.road_class = doc["class"].strip().upper()
    else:
        fld = _object(
            path, "field", doc.get("field"), {"length", "width", "spacing", "margin"}, {"length", "width", "spacing"}
        )
        length = _number(path, "field.length", fld["length"], 1, 1000)
        width = _number(path, "field.width", fld["width"], 1, 1000)
        spacing = _number(path, "field.spacing", fld["spacing"], 0.1, 50)
        margin = _number(path, "field.margin", fld.get("margin", 0.0), 0, 100)
        p.field_size = (length, width, spacing, margin)
        p.height = _number(path, "height", doc.get("height", 0.0), 0, 100)
        p.requirements = indoor_requirements(
            _object(path, "requirements", doc.get("requirements", {}), {"Em", "U0"}), path
        )
    return p
