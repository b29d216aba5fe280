"""`patina plot`: figures and an index.html for a table, its validation and any number of fits.

In-plane slices (the one slice plotter, slices.py, with the fits overlaid), polar plots of the
incidence plane (polar.py), and a 3-D lobe view (lobes.py, pyvista off-screen) that is skipped,
with the reason on the page, where it cannot be rendered. The page is a Jinja2 template installed
with the package (templates/report.html.j2, its stylesheet report.css inlined so that index.html
and its PNGs are all a colleague needs); every file is written to a temporary name and renamed.
"""

from __future__ import annotations

import json
import math
import os
import re
from collections.abc import Callable, Sequence
from typing import Any

import jinja2

from patina.atomic import write_text
from patina.plot.fits import Fit
from patina.plot.lobes import LobeOptions, render_lobes
from patina.plot.polar import plot_incidence_polar
from patina.plot.slices import plot_inplane_slices
from patina.table.brdf import Brdf
from patina.table.validation import Report, format_report, validate

DEFAULT_LOBES = LobeOptions()
REPORT_STEPS = 4  # slices, polar plots, 3-D lobes, validation and the page
TEMPLATES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "templates")

# A fit's metrics (fitting/search.py) as a reader names them, with how their values read.
METRICS: dict[str, tuple[str, str]] = {
    "ciede2000_mean": ("CIEDE2000 mean (ΔE00)", "de"),
    "ciede2000_p95": ("CIEDE2000, 95th percentile (ΔE00)", "de"),
    "relative_error_median": ("relative error, median", "percent"),
    "relative_error_p95": ("relative error, 95th percentile", "percent"),
    "rmse": ("RMS error of f (1/sr)", "g"),
    "loss": ("loss on the samples fitted", "g"),
    "loss_all_samples": ("loss on all samples", "g"),
}
_PARAMETERS = {
    "rho": "diffuse albedo ρ",  # noqa: RUF001 (a label for readers)
    "f0": "specular reflectance F0",
    "w": "lobe weight",
    "alpha": "roughness α",  # noqa: RUF001 (a label for readers)
    "alpha_x": "roughness αx",  # noqa: RUF001 (a label for readers)
    "alpha_y": "roughness αy",  # noqa: RUF001 (a label for readers)
    "exponent": "exponent n",
    "nu": "exponent nu",
    "nv": "exponent nv",
    "cxy": "Lafortune Cx = Cy",
    "cx": "Lafortune Cx",
    "cy": "Lafortune Cy",
    "cz": "Lafortune Cz",
    "coat_alpha": "clear coat roughness α",  # noqa: RUF001 (a label for readers)
    "coat_eta": "clear coat index of refraction",
}
_CHANNELS = {"r": "red", "g": "green", "b": "blue"}


def parameter_label(name: str) -> str:
    """rho_r -> 'diffuse albedo (rho), red'; alpha_2_g -> 'roughness (alpha), lobe 2, green'; others stay."""
    m = re.fullmatch(r"(coat_alpha|coat_eta|[a-z0-9]+?(?:_[xy])?)(?:_(\d))?(?:_([rgb]))?", name)
    if not m or m.group(1) not in _PARAMETERS:
        return name
    parts = [_PARAMETERS[m.group(1)]]
    if m.group(2):
        parts.append(f"lobe {m.group(2)}")
    if m.group(3):
        parts.append(_CHANNELS[m.group(3)])
    return ", ".join(parts)


def _number(value: Any, style: str = "g") -> str:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return str(value)
    if not math.isfinite(value):
        return str(value)
    if style == "percent":
        return f"{100 * value:.3g} %"
    if style == "de":
        return f"{value:.2f}"
    return f"{value:.4g}"


def _validation_rows(report: Report) -> tuple[list[dict[str, Any]], str]:
    """format_report's lines (what `patina validate` prints) as table rows: status, check, result, details.
    Parsed from the printed form so that the page and the command say the same, whatever checks there are."""
    rows: list[dict[str, Any]] = []
    result = ""
    for line in format_report(report).splitlines()[1:]:
        m = re.match(r"  (ok  |FAIL)  (\S+)\s+(.*)$", line)
        if m:
            rows.append({"ok": m.group(1) == "ok  ", "check": m.group(2), "text": m.group(3), "details": []})
        elif line.startswith("result:"):
            result = line.removeprefix("result:").strip()
        elif rows and line.startswith("    ") and not line.lstrip().startswith("- "):
            rows[-1]["details"].append(line.strip())
    return rows, result


def _metrics(doc: dict[str, Any]) -> dict[str, Any]:
    """A fit's metrics; fit files are read for their model and parameters, so what else they hold is
    shown only where it has the shape patina fit writes (a hand-edited file is not an error here)."""
    m = doc.get("metrics")
    return m if isinstance(m, dict) else {}


def _listed(doc: dict[str, Any], key: str) -> list[Any]:
    v = doc.get(key)
    return v if isinstance(v, list) else []


def _fit_context(brdf: Brdf, fits: Sequence[Fit]) -> dict[str, Any]:
    """The fits' parameters and metrics as tables, one column per fit."""
    names: list[str] = []
    for fit in fits:
        names += [n for n in fit.doc["parameters"] if n not in names]
    parameters = []
    for n in names:
        cells = []
        for fit in fits:
            v = fit.doc["parameters"].get(n)
            cells.append({"text": "" if v is None else _number(v), "bound": n in _listed(fit.doc, "at_bounds")})
        parameters.append({"name": n, "label": parameter_label(n), "cells": cells})
    keys = [k for k in METRICS if any(k in _metrics(f.doc) for f in fits)]
    for f in fits:  # metrics this page has no label for yet: shown under their key, once each
        for k, v in _metrics(f.doc).items():
            if k not in keys and isinstance(v, (int, float)):
                keys.append(k)
    metrics = []
    for k in keys:
        label, style = METRICS.get(k, (k.replace("_", " "), "g"))
        values = [_metrics(f.doc).get(k) for f in fits]
        numeric = [v for v in values if isinstance(v, (int, float)) and not isinstance(v, bool)]
        best = min(numeric) if len(numeric) > 1 else None  # every metric here is an error: lower is better
        metrics.append(
            {
                "label": label,
                "cells": [{"text": "" if v is None else _number(v, style), "best": v == best} for v in values],
            }
        )
    about = []
    for f in fits:
        d = f.doc
        notes = []
        if d.get("usable") is False:
            notes.append("not usable: " + ("; ".join(map(str, _listed(d, "problems"))) or "flagged by patina fit"))
        if _listed(d, "at_bounds"):
            notes.append("at a bound: " + ", ".join(parameter_label(str(n)) for n in _listed(d, "at_bounds")))
        if d.get("converged") is False:
            notes.append(f"not converged: {d.get('message', '')}")
        source = d.get("source")
        # By name: the path a fit records is as its command was given, relative to where it ran.
        if isinstance(source, str) and source and os.path.basename(source) != os.path.basename(brdf.source):
            notes.append(f"fitted to {os.path.basename(source)}, not to this table")
        about.append({"name": f.name, "notes": notes})
    seconds = [f.doc.get("seconds") for f in fits]
    facts = [
        ("file", "code", [{"text": os.path.basename(f.path)} for f in fits]),
        ("loss minimised", "", [{"text": str(f.doc.get("loss") or "")} for f in fits]),
        ("samples", "num", [{"text": str(f.doc.get("samples", ""))} for f in fits]),
        ("time (s)", "num", [{"text": _number(s, "g") if isinstance(s, (int, float)) else ""} for s in seconds]),
    ]
    # Rows no fit has a value for (a fit.json written by hand) are left out rather than shown empty.
    facts = [row for row in facts if any(c["text"] for c in row[2])]
    facts.append(("warnings", "", [{"text": "; ".join(a["notes"]) or "none", "bad": bool(a["notes"])} for a in about]))
    return {"parameters": parameters, "metrics": metrics, "about": about, "facts": facts}


def _lobe_view(
    brdf: Brdf,
    fits: Sequence[Fit],
    out_dir: str,
    lobes: LobeOptions | None,
    on_skip: Callable[[str], None] | None,
) -> dict[str, str]:
    """lobe3d.png (of the table and the first fit) and what the page says of it; a stale PNG from an
    earlier run is removed when none is made."""
    path = os.path.join(out_dir, "lobe3d.png")
    if lobes is None:
        why = "not requested (--no-3d)"
    else:
        view = render_lobes(brdf, fits[0].model if fits else None, path, options=lobes)
        if view.skipped is None:
            caption = view.caption + (f" The fit shown is {fits[0].name}." if len(fits) > 1 else "")
            return {"image": "lobe3d.png", "caption": caption}
        why = view.skipped
        if on_skip is not None:
            on_skip(why)
    if os.path.exists(path):
        os.remove(path)
    return {"skipped": why}


def write_report(
    brdf: Brdf,
    out_dir: str,
    fits: Sequence[Fit] = (),
    incidence: Sequence[float] = (0, 30, 60, 75),
    lobes: LobeOptions | None = DEFAULT_LOBES,
    on_skip: Callable[[str], None] | None = None,
    on_step: Callable[[int, str], None] | None = None,
) -> Report:
    """Writes the report into out_dir. lobes=None leaves out the 3-D view; on_skip hears why it could not be
    made; on_step(done, what is next) hears progress through the REPORT_STEPS steps."""
    step = on_step or (lambda done, what: None)
    os.makedirs(out_dir, exist_ok=True)
    named = [(f.name, f.model) for f in fits]
    step(0, "slices")
    slices_caption = plot_inplane_slices(brdf, os.path.join(out_dir, "slices.png"), incidence, fits=named)
    step(1, "polar plots")
    polar_caption = plot_incidence_polar(brdf, os.path.join(out_dir, "polar.png"), incidence, fits=named)
    step(2, "3-D lobes")
    lobe = _lobe_view(brdf, fits, out_dir, lobes, on_skip)
    step(3, "validation")
    report = validate(brdf)
    write_text(os.path.join(out_dir, "validate.json"), json.dumps(report.as_json(), indent=2))
    info = brdf.info()
    checks, result = _validation_rows(report)
    env = jinja2.Environment(
        loader=jinja2.FileSystemLoader(TEMPLATES),
        autoescape=True,
        undefined=jinja2.StrictUndefined,  # a name the template expects and this code forgot fails here, not blank
        trim_blocks=True,
        lstrip_blocks=True,
    )
    page = env.get_template("report.html.j2").render(
        title=os.path.basename(brdf.source) or "table",
        source=brdf.source,
        table=[
            ("format", report.format),
            ("parametrization", info["parametrization"]),
            ("grid", " × ".join(f"{a['knots']} {a['name']}" for a in info["axes"])),  # noqa: RUF001 (a label for readers)
            ("channels", f"{info['channels']} {info['channel_kind']}"),
            ("units", info["units"]),
            ("provenance", info["provenance"] or "not recorded"),
        ],
        ok=report.ok,
        result=result,
        checks=checks,
        problems=report.problems,
        fits=_fit_context(brdf, fits) if fits else None,
        fit_names=[f.name for f in fits],
        slices_caption=slices_caption,
        polar_caption=polar_caption,
        lobe=lobe,
    )
    write_text(os.path.join(out_dir, "index.html"), page)
    step(REPORT_STEPS, "done")
    return report
