"""The lighting report a client can read: an HTML page (Jinja2, the material report's style,
patina/plot/templates/report.css) with the inputs, the pass / fail table with margins, every
figure, a plan per grid (patina.lighting.plan) and the method; result.json with every value;
and a PDF of the page printed by headless Chromium when it is installed."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import tempfile

import jinja2

from patina.atomic import write_text
from patina.lighting.calculation import Result, eye_paths, shown_path
from patina.lighting.indirect_cache import BOUND, RESOLUTION
from patina.lighting.plan import write_plan
from patina.lighting.scene_luminaires import plan_luminaires
from patina.lighting.ugr_table import REFLECTANCES
from patina.native import _core

HERE = os.path.dirname(os.path.abspath(__file__))
TEMPLATES = [os.path.join(HERE, "templates"), os.path.join(HERE, "..", "plot", "templates")]
CHROMIUM = ("chromium", "chromium-browser", "google-chrome")
PDF_SECONDS = 120
STANDARD_NAMES = {
    "en12464-1": "EN 12464-1 (light and lighting of work places, indoor)",
    "en13201": "EN 13201-2 / -3 (road lighting: classes and calculation)",
    "en12193": "EN 12193 (sports lighting)",
}


def _fmt(value: float | None) -> str:
    if value is None:
        return "—"
    return f"{value:.3g}" if abs(value) < 100 else f"{value:.0f}"


def write_report(result: Result, out_dir: str, pdf: bool = True) -> list[str]:
    """Writes index.html, the plans, result.json (and report.pdf); returns the notes to print."""
    os.makedirs(out_dir, exist_ok=True)
    lums = plan_luminaires(result.scene)
    plans = []
    for i, plane in enumerate(result.planes):
        name = f"plan-{i + 1}.png"
        v = plane.values
        title = f"{plane.name}: min {v.min():.3g}, mean {v.mean():.3g}, max {v.max():.3g}"
        write_plan(os.path.join(out_dir, name), v, plane.grid.x, plane.grid.z, title, lums, plane.label)
        plans.append({"file": name, "caption": f"{plane.name} — {plane.grid.rule}; {plane.label}, maintained."})
    write_text(os.path.join(out_dir, "result.json"), json.dumps(result.as_json(), indent=1) + "\n")
    checks = [
        {
            "figure": c.figure,
            "value": _fmt(c.value),
            "requirement": ("≥ " if c.kind == "min" else "≤ ") + f"{c.limit:g}",
            "status": {True: "pass", False: "FAIL", None: "not computed"}[c.passed],
            "css": {True: "ok", False: "bad", None: ""}[c.passed],
            "margin": "—" if c.margin is None else f"{c.margin:+.1%}",
        }
        for c in result.checks
    ]
    env = jinja2.Environment(
        loader=jinja2.FileSystemLoader(TEMPLATES),
        autoescape=True,
        undefined=jinja2.StrictUndefined,
        trim_blocks=True,
        lstrip_blocks=True,
    )
    std = result.project.standard
    page = env.get_template("lighting.html.j2").render(
        title=os.path.basename(result.project.path),
        project=os.path.basename(result.project.path),
        standard_name=STANDARD_NAMES[std],
        all_pass=all(c.passed for c in result.checks),
        checks=checks,
        notes=result.notes,
        figures=[(k, _fmt(v)) for k, v in result.figures.items()],
        inputs=result.inputs,
        plans=plans,
        standard=std,
        indirect=result.project.indirect,
        samples=result.project.samples,
        eye_paths=eye_paths(result.project),
        resolution=RESOLUTION,
        bound=f"{BOUND:g}",
        reflectances=[f"{c:g}/{w:g}/{f:g}" for c, w, f in REFLECTANCES],
        ugr_tables=[
            {
                "source": shown_path(t.source, result.project),
                "caption": t.caption(),
                "rows": [(room, [f"{v:.1f}" for v in cross + end]) for room, cross, end in t.rows()],
            }
            for t in result.ugr_tables
        ],
        version=_core.__version__,
    )
    index = os.path.join(out_dir, "index.html")
    write_text(index, page)
    return [print_pdf(index, os.path.join(out_dir, "report.pdf"))] if pdf else []


def chromium() -> str | None:
    return next((p for p in map(shutil.which, CHROMIUM) if p), None)


def print_pdf(html: str, pdf: str) -> str:
    """The page printed to PDF by headless Chromium (through a temporary file and a rename)."""
    exe = chromium()
    if exe is None:
        return f"no PDF: none of {', '.join(CHROMIUM)} is installed (the HTML page is complete)"
    fd, tmp = tempfile.mkstemp(suffix=".pdf", dir=os.path.dirname(os.path.abspath(pdf)))
    os.close(fd)
    with tempfile.TemporaryDirectory() as profile:
        cmd = [
            exe,
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            f"--user-data-dir={profile}",
            "--no-pdf-header-footer",
            f"--print-to-pdf={tmp}",
            "file://" + os.path.abspath(html),
        ]
        try:
            done = subprocess.run(cmd, capture_output=True, timeout=PDF_SECONDS, check=False).returncode == 0
        except subprocess.TimeoutExpired:
            done = False
    if not done or os.path.getsize(tmp) == 0:  # a half-printed file is no PDF
        os.unlink(tmp)
        return f"no PDF: {os.path.basename(exe)} did not print the page"
    os.chmod(tmp, 0o644)  # mkstemp makes it private; an ordinary file's mode
    os.replace(tmp, pdf)
    return f"wrote {pdf}"
