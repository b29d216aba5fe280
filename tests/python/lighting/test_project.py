"""Lighting project files (patina.lighting.project): the bundled ones read, bad keys and values
refused naming the key, and damaged files fuzzed (FormatError, nothing else)."""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from conftest import load_or_format_error
from patina.errors import FormatError
from patina.lighting.project import read_project
from repo_paths import ROOT

PROJECTS = os.path.join(ROOT, "materials", "lighting")
ROAD = os.path.join(PROJECTS, "road-en13201.json")
OFFICE = os.path.join(PROJECTS, "office-en12464.json")
SETTINGS = settings(max_examples=100, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])


def test_the_bundled_projects_read():
    office = read_project(OFFICE, "en12464-1")
    assert office.maintenance == pytest.approx(0.9 * 0.9 * 0.95) and office.requirements["UGR"] == ("max", 19.0)
    road = read_project(ROAD)
    assert road.road.lanes == 2 and road.road_class == "M5" and os.path.isfile(road.rtable)


def write(tmp_path, doc: dict) -> str:
    path = tmp_path / "p.json"
    path.write_text(json.dumps(doc))
    return str(path)


@pytest.mark.parametrize(
    ("change", "key"),
    [
        ({"standard": "en99"}, "standard"),
        ({"class": "M0"}, "class"),
        ({"road": {"kerb_x": 0, "lanes": 1.5, "lane_width": 3, "field_start": 0, "spacing": 30}}, "road.lanes"),
        ({"road": {"kerb_x": 0, "lanes": 2, "lane_width": 3, "field_start": 0}}, "road.spacing"),
        ({"maintenance": {"LLMF": 0}}, "maintenance.LLMF"),
        ({"samples": 0}, "samples"),
        ({"indirect": "yes"}, "indirect"),
        ({"indirect": 1}, "indirect"),
        ({"indirect": "Cache"}, "indirect"),
        ({"indirect": None}, "indirect"),
        ({"room": [0, 0, 1, 1]}, "room"),
    ],
)
def test_bad_values_are_refused_naming_the_key(tmp_path, change, key):
    doc = json.loads(open(ROAD).read())
    doc["scene"] = os.path.join(PROJECTS, doc["scene"])
    doc.update(change)
    with pytest.raises(FormatError) as e:
        read_project(write(tmp_path, doc))
    assert e.value.where == key


@pytest.mark.parametrize(
    ("value", "indirect"), [(True, "cache"), ("cache", "cache"), ("paths", "paths"), (False, "none"), ("none", "none")]
)
def test_indirect_true_means_the_radiance_cache(tmp_path, value, indirect):
    doc = json.loads(open(OFFICE).read())
    doc["scene"] = os.path.join(PROJECTS, doc["scene"])
    doc["indirect"] = value
    assert read_project(write(tmp_path, doc)).indirect == indirect
    del doc["indirect"]
    assert read_project(write(tmp_path, doc)).indirect == "none"


def test_a_task_area_outside_the_room_is_refused(tmp_path):
    doc = json.loads(open(OFFICE).read())
    doc["scene"] = os.path.join(PROJECTS, doc["scene"])
    doc["task_area"] = [-1, -1, 9, 1]
    with pytest.raises(FormatError, match="outside the room"):
        read_project(write(tmp_path, doc))


# the paths made absolute, so the copy in a scratch folder still names the bundled scene and table
ROAD_BYTES = Path(ROAD).read_bytes().replace(b"../", (PROJECTS + "/../").encode())


def _check(project) -> None:
    assert project.standard in ("en12464-1", "en13201", "en12193") and 0 < project.maintenance <= 1


@SETTINGS
@given(cut=st.integers(min_value=0, max_value=len(ROAD_BYTES) - 1))
def test_truncated_projects_load_or_raise_format_error(cut):
    load_or_format_error(ROAD_BYTES[:cut], "p.json", read_project, _check)


@SETTINGS
@given(at=st.integers(min_value=0, max_value=len(ROAD_BYTES) - 1), value=st.integers(min_value=0, max_value=255))
def test_corrupted_projects_load_or_raise_format_error(at, value):
    data = bytearray(ROAD_BYTES)
    data[at] = value if data[at] != value else value ^ 1
    load_or_format_error(bytes(data), "p.json", read_project, _check)
