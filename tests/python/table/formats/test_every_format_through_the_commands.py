"""Every imported format through the table commands a user starts with (issue 29's "done
when"): `info`, `validate`, `fit`, `preview` and `convert` each take a file of each format,
and `batch` a library holding one of each, written here by the formats' test writers (or
bundled, for BSDF XML) so no test downloads."""

from __future__ import annotations

import json
import os
import shutil

import pytest

from format_writers import mbsdf_bytes, utia_values, zemax_text
from patina.cli import main
from patina.synthetic.analytic import plastic
from patina.table.formats.rgl_writer import write_rgl
from repo_paths import ROOT

MODEL = plastic(diffuse=(0.5, 0.3, 0.1), specular=0.04, roughness=0.3)
# the Zemax writer puts the model's R, G, B in whatever channels the file declares: a grey
# model keeps its X, Y, Z a colour linear sRGB can hold (the coloured one's red went above 1)
GREY = plastic(diffuse=(0.4, 0.4, 0.4), specular=0.04, roughness=0.3)
# a coarse Zemax file: its scattered points resampled once per command (~12 s at the
# writer's default angles)
COARSE = {"aoi": [0, 20, 40, 60], "azimuth": list(range(0, 181, 30)), "radial": list(range(0, 91, 10))}
SMALL = ["--spp", "2", "--width", "32", "--height", "24", "--quiet"]


def _write(folder, kind: str) -> str:
    """A file of `kind` in `folder`; the BSDF XML ones are the bundled real files."""
    if kind == "rgl":
        path = str(folder / "plastic.bsdf")
        write_rgl(path, MODEL)
    elif kind == "zemax-mono":
        path = str(folder / "vinyl.bsdf")
        open(path, "w").write(zemax_text(GREY, **COARSE))
    elif kind == "zemax-xyz":
        path = str(folder / "vinyl-xyz.bsdf")
        open(path, "w").write(zemax_text(GREY, ("TristimulusX", "TristimulusY", "TristimulusZ"), **COARSE))
    elif kind == "mdl":
        path = str(folder / "m.mbsdf")
        open(path, "wb").write(mbsdf_bytes(MODEL))
    elif kind == "utia":
        path = str(folder / "m001_test.bin")
        open(path, "wb").write(utia_values(MODEL).astype("<f8").tobytes())
    else:
        name = {"klems": "klems_aniso_high.xml", "tensor-tree": "blindsT3.xml"}[kind]
        path = os.path.join(ROOT, "materials", "radiance", name)
    return path


KINDS = ["rgl", "zemax-mono", "zemax-xyz", "mdl", "utia", "klems", "tensor-tree"]
FORMAT = {"zemax-mono": "zemax", "zemax-xyz": "zemax", "klems": "window_xml", "tensor-tree": "window_xml"}


@pytest.mark.parametrize("kind", KINDS)
def test_info_validate_fit_preview_and_convert_take_the_file(kind, tmp_path, capsys):
    path = _write(tmp_path, kind)
    assert main(["info", "--json", path]) == 0
    assert json.loads(capsys.readouterr().out)["format"] == FORMAT.get(kind, kind)
    assert main(["validate", "--json", path]) in (0, 1)  # 1: a check failed, which the report says
    assert json.loads(capsys.readouterr().out)["checks"]
    fit = tmp_path / "fit.json"
    # 1: fitted, and the verdict says why it is not usable (an isotropic model on the
    # anisotropic shade); refusing the table would be 2
    assert main(["fit", path, "--out", str(fit), "--starts", "1"]) in (0, 1)
    assert json.loads(fit.read_text())["parameters"]
    assert main(["preview", path, "--out", str(tmp_path / "p.exr"), "--png", "none", *SMALL]) == 0
    assert main(["convert", path, str(tmp_path / "t.ptab")]) == 0
    assert "wrote" in capsys.readouterr().out


def test_batch_processes_a_library_holding_every_format(tmp_path, capsys):
    library = tmp_path / "library"
    library.mkdir()
    names = []
    for kind in KINDS:
        path = _write(library, kind)
        if os.path.dirname(path) != str(library):  # a bundled file: copied in
            shutil.copy(path, library)
        names.append(os.path.basename(path))
    (library / "README.md").write_text("notes beside the tables")
    out = tmp_path / "out"
    quick = ["--models", "ggx+lambert", "--starts", "1", "--width", "24", "--height", "18", "--spp", "1"]
    assert main(["batch", str(library), "--out", str(out), "--steps", "validate,fit,preview", *quick, "--quiet"]) == 0
    summary = json.loads((out / "summary.json").read_text())
    rows = {m["name"]: m for m in summary["materials"]}
    # the two .bsdf files (an RGL tensor file and a Zemax text) told apart by their content
    assert sorted(rows) == sorted(names)
    for name, row in rows.items():
        assert row["status"] == "ok", (name, row["error"])
        assert row["best_model"] == "ggx+lambert" and os.path.isfile(out / row["preview"]), name
    assert summary["skipped_files"] == [{"file": "README.md", "reason": "not a table (a .md file)"}]
