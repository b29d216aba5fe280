"""The library report: OUT/index.html (a gallery: one sortable row a material with its
validation, best model, CIEDE2000, the side-by-side preview and a link to its full report),
OUT/summary.json and OUT/summary.csv. Written from the tasks' results, each file atomically.
The page is a Jinja2 template installed with the package (templates/gallery.html.j2)."""

from __future__ import annotations

import csv
import io
import json
import math
import os
import posixpath
from dataclasses import asdict
from typing import Any
from urllib.parse import quote

import jinja2

from patina.atomic import write_text
from patina.batch.library import Material, Settings
from patina.batch.tasks import PREVIEW_FILE, REPORT_DIR
from patina.file_names import printable

SUMMARY_VERSION = 1
TEMPLATES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "templates")
CSV_COLUMNS = (
    "name",
    "status",
    "validation",
    "problems",
    "best_model",
    "usable",
    "ciede2000_mean",
    "ciede2000_p95",
    "preview",
    "report",
    "error",
    "file",
)


def _validation(step: dict[str, Any] | None) -> tuple[str, int | None]:
    """(what the gallery says, the number of problems found) of a validate result."""
    if step is None:
        return "not run", None
    if step["status"] != "ok":
        return step["status"], None
    n = len(step["problems"])
    return ("passed", 0) if n == 0 else (f"{n} problem{'s' if n > 1 else ''}", n)


def _finite(x: Any) -> float | None:
    return float(x) if isinstance(x, (int, float)) and math.isfinite(x) else None


def _row(material: Material, steps: dict[str, dict[str, Any]]) -> dict[str, Any]:
    here = posixpath.join("materials", material.name)
    fit = steps.get("fit") if steps.get("fit", {}).get("status") == "ok" else None
    validation, problems = _validation(steps.get("validate"))
    errors = [f"{s}: {r['message']}" for s, r in steps.items() if r["status"] == "failed"]
    done = lambda step: steps.get(step, {}).get("status") == "ok"  # noqa: E731
    return {
        "name": material.name,
        "file": material.path,
        "status": "failed" if errors else "ok",
        "error": errors[0] if errors else "",
        "validation": validation,
        "problems": problems,
        "validation_problems": steps["validate"]["problems"] if done("validate") else [],
        "best_model": fit["best_model"] if fit else None,
        "recommended": fit.get("recommended") if fit else None,  # None when no fit passes the thresholds
        "usable": fit["usable"] if fit else None,
        "ciede2000_mean": _finite(fit["ciede2000_mean"]) if fit else None,
        "ciede2000_p95": _finite(fit["ciede2000_p95"]) if fit else None,
        "ranking": fit["ranking"] if fit else [],
        "preview": posixpath.join(here, PREVIEW_FILE) if done("preview") else None,
        "report": posixpath.join(here, REPORT_DIR, "index.html") if done("report") else None,
        "steps": {
            s: {k: r.get(k) for k in ("status", "message", "reused", "seconds") if k in r} for s, r in steps.items()
        },
    }


def summarise(
    library: str,
    out_dir: str,
    materials: list[Material],
    skipped: list[tuple[str, str]],
    results: list[dict[str, Any]],
    settings: Settings,
) -> dict[str, Any]:
    """summary.json's document: the settings, a row per material, the files not read, counts."""
    steps: dict[str, dict[str, dict[str, Any]]] = {m.name: {} for m in materials}
    for r in results:
        steps[r["material"]][r["step"]] = r
    rows = [_row(m, steps[m.name]) for m in materials]
    counts = {
        "tables": len(rows),
        "ok": sum(r["status"] == "ok" for r in rows),
        "failed": sum(r["status"] == "failed" for r in rows),
        "skipped_files": len(skipped),
        "tasks": len(results),
        "tasks_run": sum(not r["reused"] and r["status"] != "blocked" for r in results),
        "tasks_reused": sum(bool(r["reused"]) for r in results),
        "tasks_failed": sum(r["status"] == "failed" for r in results),
        "tasks_blocked": sum(r["status"] == "blocked" for r in results),
    }
    return _plain(
        {
            "version": SUMMARY_VERSION,
            "library": os.path.abspath(library),
            "out": out_dir,
            "settings": asdict(settings),
            "materials": rows,
            "skipped_files": [{"file": name, "reason": why} for name, why in skipped],
            "counts": counts,
        }
    )


def _plain(value: Any) -> Any:
    """The value with every non-finite number as None: summary.json is strict JSON (no NaN)."""
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    return value


def _text(value: Any) -> Any:
    return printable(value) if isinstance(value, str) else value


def _csv(summary: dict[str, Any]) -> str:
    buffer = io.StringIO()
    writer = csv.DictWriter(buffer, fieldnames=CSV_COLUMNS, extrasaction="ignore", lineterminator="\n")
    writer.writeheader()
    for row in summary["materials"]:
        # names that are not UTF-8 as \xNN escapes: the CSV stays UTF-8 text
        writer.writerow({k: "" if row[k] is None else _text(row[k]) for k in CSV_COLUMNS})
    return buffer.getvalue()


def write_gallery(out_dir: str, summary: dict[str, Any]) -> None:
    """index.html, summary.json and summary.csv in out_dir."""
    write_text(os.path.join(out_dir, "summary.json"), json.dumps(summary, indent=2, allow_nan=False))
    write_text(os.path.join(out_dir, "summary.csv"), _csv(summary))
    env = jinja2.Environment(
        loader=jinja2.FileSystemLoader(TEMPLATES),
        autoescape=True,
        undefined=jinja2.StrictUndefined,  # a name the template expects and this code forgot fails here
        trim_blocks=True,
        lstrip_blocks=True,
    )
    # material names are file names: spaces, '#', '?', bytes that are not UTF-8 (as they are on disk)
    env.filters["url"] = lambda path: quote(os.fsencode(path))
    env.finalize = _text  # every value shown: names that are not UTF-8 as \xNN escapes, as in the CSV
    page = env.get_template("gallery.html.j2").render(
        title=f"Material library: {os.path.basename(summary['library'].rstrip(os.sep)) or summary['library']}",
        summary=summary,
        settings=summary["settings"],
    )
    write_text(os.path.join(out_dir, "index.html"), page)
