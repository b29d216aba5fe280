"""`patina lighting report`: the bundled office and road projects end to end (HTML, plans,
result.json), and bad input (exit 2, one line naming the file or option)."""

from __future__ import annotations

import json
import os

import pytest

from patina.cli import main
from repo_paths import ROOT

PROJECTS = os.path.join(ROOT, "materials", "lighting")
SCENES = os.path.join(ROOT, "materials", "scenes")
ROAD = os.path.join(PROJECTS, "road-en13201.json")
OFFICE = os.path.join(PROJECTS, "office-en12464.json")


def test_the_road_report_passes_its_class_and_writes_every_part(tmp_path, capsys):
    out = tmp_path / "road"
    assert main(["lighting", "report", ROAD, "--standard", "en13201", "--out", str(out), "--no-pdf", "--quiet"]) == 0
    result = json.loads((out / "result.json").read_text())
    assert {c["figure"] for c in result["checks"]} == {"L_av", "U0", "Ul", "TI", "EIR"}
    assert all(c["pass"] for c in result["checks"])
    page = (out / "index.html").read_text()
    assert "M5" in page and "plan-1.png" in page and "synthetic-road.rtab" in page
    # the inputs as the project names them, not this machine's paths (the page goes to a client)
    assert "<td>../luminaires/streetlight.ies</td>" in page and "<td>../scenes/road-en13201.json</td>" in page
    assert ROOT not in page
    assert result["ugr_tables"] == [] and "UGR tables" not in page
    assert (out / "plan-1.png").read_bytes()[:4] == b"\x89PNG"
    # a second run refuses to overwrite without --force
    assert main(["lighting", "report", ROAD, "--standard", "en13201", "--out", str(out), "--no-pdf"]) == 2
    assert "--force" in capsys.readouterr().err


def test_the_office_report_exits_1_when_a_requirement_fails(tmp_path):
    project = json.loads(open(OFFICE).read())
    project.update(indirect=False, requirements={"Em": 5000}, scene=os.path.join(PROJECTS, project["scene"]))
    path = tmp_path / "office.json"
    path.write_text(json.dumps(project))
    out = tmp_path / "office"
    assert main(["lighting", "report", str(path), "--standard", "en12464-1", "--out", str(out), "--no-pdf"]) == 1
    result = json.loads((out / "result.json").read_text())
    checks = result["checks"]
    assert checks == [checks[0]] and checks[0]["figure"] == "Em" and checks[0]["pass"] is False
    # the luminaire's UGR table by the tabular method, in result.json and on the page
    (table,) = result["ugr_tables"]
    assert table["source"].endswith("downlight.ies") and len(table["rows"]) == 190
    page = (out / "index.html").read_text()
    # the reflectances of ceiling, walls and floor stacked in the header
    assert "UGR tables of the luminaires" in page and "12H x 8H" in page and "0.3<br>0.3<br>0.2" in page
    assert "No interreflections: direct light only." in page


def test_the_office_report_says_its_interreflections_came_from_the_radiance_cache(tmp_path):
    out = tmp_path / "office"
    assert main(["lighting", "report", OFFICE, "--standard", "en12464-1", "--out", str(out), "--no-pdf"]) == 0
    page = " ".join((out / "index.html").read_text().split())  # the template's line breaks as spaces
    assert "every luminaire's included) from the radiance cache" in page
    assert "16 \N{MULTIPLICATION SIGN} 16 path-traced texels" in page and "\N{LESS-THAN OR EQUAL TO} 0.5" in page


def _project(tmp_path, base: str, **changes) -> str:
    doc = json.loads(open(base).read())
    doc["scene"] = os.path.join(PROJECTS, doc["scene"])
    if "rtable" in doc:
        doc["rtable"] = os.path.join(PROJECTS, doc["rtable"])
    doc.update(changes)
    path = tmp_path / "p.json"
    path.write_text(json.dumps(doc))
    return str(path)


@pytest.mark.parametrize(
    ("base", "changes", "standard", "expected"),
    [
        (ROAD, {"class": "M7"}, "en13201", "(class): no class 'M7'"),
        (ROAD, {"rtable": "/nonexistent/R3.rtab"}, "en13201", "R1-R4 / C1-C2"),
        (ROAD, {}, "en12464-1", "(--standard)"),
        (OFFICE, {"room": [-30, -2, 3, 2]}, "en12464-1", "(room): the grid reaches x"),
        (
            ROAD,
            {"road": {"kerb_x": 50, "lanes": 2, "lane_width": 3.5, "field_start": 0, "spacing": 30}},
            "en13201",
            "(road)",
        ),
        (OFFICE, {"maintenance": {"LMF": 1.5}}, "en12464-1", "(maintenance.LMF)"),
        (OFFICE, {"colour": 1}, "en12464-1", "(colour): unknown key"),
    ],
)
def test_bad_projects_exit_2_with_one_line_naming_the_place(tmp_path, capsys, base, changes, standard, expected):
    path = _project(tmp_path, base, **changes)
    assert main(["lighting", "report", path, "--standard", standard, "--out", str(tmp_path / "o"), "--no-pdf"]) == 2
    err = capsys.readouterr().err.strip()
    assert expected in err and "\n" not in err and "Traceback" not in err
    assert not (tmp_path / "o" / "index.html").exists()


def test_a_bad_rtable_is_named_with_its_line(tmp_path, capsys):
    table = tmp_path / "holes.rtab"
    table.write_text("beta: 0 90\n0 100 100\n1 50\n")
    path = _project(tmp_path, ROAD, rtable=str(table))
    assert main(["lighting", "report", path, "--standard", "en13201", "--out", str(tmp_path / "o"), "--no-pdf"]) == 2
    assert f"{table} (line 3)" in capsys.readouterr().err


def test_a_luminaire_below_the_eye_is_refused_for_ti(tmp_path, capsys):
    scene = json.loads(open(os.path.join(SCENES, "road-en13201.json")).read())
    scene["lights"][3]["position"][1] = 1.0
    for light in scene["lights"]:
        light["file"] = os.path.join(ROOT, "materials", "luminaires", "streetlight.ies")
    (tmp_path / "low.json").write_text(json.dumps(scene))
    path = _project(tmp_path, ROAD, scene=str(tmp_path / "low.json"))
    assert main(["lighting", "report", path, "--standard", "en13201", "--out", str(tmp_path / "o"), "--no-pdf"]) == 2
    assert "low.json (lights[3])" in capsys.readouterr().err


def test_an_unknown_standard_and_abbreviations_are_refused(tmp_path, capsys):
    assert main(["lighting", "report", ROAD, "--standard", "en99", "--out", str(tmp_path / "o")]) == 2
    assert "(--standard)" in capsys.readouterr().err
    assert main(["lighting", "report", ROAD, "--stand", "en13201", "--out", str(tmp_path / "o")]) == 2
    assert "--standard" in capsys.readouterr().err  # no abbreviation taken for it


def test_a_sport_field_by_en12193_principal_and_total_areas(tmp_path):
    flood = os.path.join(ROOT, "materials", "luminaires", "floodlight.ies")
    masts = [(x, z) for x in (-45.0, 45.0) for z in (-60.0, 60.0)]
    scene = {
        "version": 1,
        "camera": {"position": [0, 30, -90], "look_at": [0, 0, 0], "width": 8, "height": 8},
        "materials": {"grass": {"type": "lambert", "albedo": 0.2}},
        "shapes": [{"type": "plane", "material": "grass", "size": [130, 160]}],
        "lights": [
            {"type": "luminaire", "file": flood, "position": [x, 25, z], "aim": [-x, -25, -z], "multiplier": 40}
            for x, z in masts
        ],
    }
    (tmp_path / "pitch.json").write_text(json.dumps(scene))
    project = {
        "scene": "pitch.json",
        "standard": "en12193",
        "field": {"length": 105, "width": 68, "spacing": 5, "margin": 5},
        "requirements": {"Em": 1, "U0": 0.05},
    }
    (tmp_path / "p.json").write_text(json.dumps(project))
    out = tmp_path / "pitch"
    args = ["lighting", "report", str(tmp_path / "p.json"), "--standard", "en12193", "--out", str(out), "--no-pdf"]
    code = main(args)
    result = json.loads((out / "result.json").read_text())
    assert [g["name"] for g in result["grids"]] == ["principal area", "total area"]
    assert len(result["grids"][0]["x"]) == 14 and len(result["grids"][0]["z"]) == 21  # 68 / 5 and 105 / 5, up
    f = result["figures"]
    assert f["Em"] > 0 and f["Em TA"] > 0 and 0 < f["U0"] <= 1
    assert code == (0 if all(c["pass"] for c in result["checks"]) else 1)
