"""The batch's tasks: pure functions of (input file, step, settings, seed) that read files and
write files, so they run the same in this process and on any Dask worker that shares the file
system. No C++ object crosses a task boundary; what a task returns is a small JSON-able dict.

Outputs go to OUT/materials/NAME/: validate.json, fit.json (the ranking: best model on top),
preview.png (the table | its best fit, same camera and seed) and report/ (index.html and its
figures, patina.plot.report). Each is written atomically, then the step's manifest
(patina.batch.manifest); a step whose manifest matches is not run again.

Bad input (a table that cannot be read, a fit that cannot be made: FormatError, ValueError) is
the task's result, `failed` with its one-line message, recorded in the manifest so a rerun
reports it again without redoing it. Anything else (an OSError, a bug) propagates: Dask runs
the task again (retries), and the batch reports it as failed if it keeps failing.
"""

from __future__ import annotations

import json
import os
import time
from collections.abc import Callable
from dataclasses import replace
from typing import Any

import numpy as np

from patina.atomic import write_text
from patina.batch.library import Material, Settings
from patina.batch.manifest import checksum, up_to_date, write_manifest
from patina.bundled import studio_environment
from patina.file_names import engine_path, printable
from patina.fitting import compare, recommended, write_ranking
from patina.plot.fits import read_fits
from patina.plot.lobes import LobeOptions
from patina.plot.report import write_report
from patina.render.images import write_png
from patina.render.run import render
from patina.scene import parse_scene, with_overrides
from patina.scene.preview import preview_scene_dict
from patina.table import load_brdf, validate

# A step reads the outputs of these earlier steps (when they are among the steps run) ...
NEEDS = {"validate": (), "fit": (), "preview": ("fit",), "report": ("fit",)}
# ... and cannot run without these: a preview shows the best fit; a report is made without fits
BLOCKED_BY = {"preview": ("fit",)}
FIT_FILE = "fit.json"
PREVIEW_FILE = "preview.png"
REPORT_DIR = "report"
StepOutput = tuple[dict[str, Any], list[str]]  # (the result's data, the outputs written, relative to the folder)


def material_folder(out_dir: str, material: Material) -> str:
    return os.path.join(out_dir, "materials", material.name)


def result(material: Material, step: str, status: str, message: str = "", **data: Any) -> dict[str, Any]:
    """A task's result. status: ok, failed (message: the one-line error) or blocked (an earlier
    step it needs failed); reused: true when the manifest showed it already done."""
    return {"material": material.name, "step": step, "status": status, "message": message, "reused": False, **data}


def one_line(e: BaseException) -> str:
    text = str(e).strip().splitlines()
    return text[0] if text else type(e).__name__


# ---------------------------------------------------------------- the steps


def _validate(material: Material, settings: Settings, folder: str, threads: int, fitted: bool) -> StepOutput:
    report = validate(load_brdf(material.path))
    write_text(os.path.join(folder, "validate.json"), json.dumps(report.as_json(), indent=2))
    data = {"ok": report.ok, "problems": report.problems}
    return data, ["validate.json"]


def _de(metrics: dict[str, float]) -> dict[str, float]:
    return {"ciede2000_mean": metrics["ciede2000_mean"], "ciede2000_p95": metrics["ciede2000_p95"]}


def _fit(material: Material, settings: Settings, folder: str, threads: int, fitted: bool) -> StepOutput:
    brdf = load_brdf(material.path)
    ranked = compare(
        brdf, list(settings.models), starts=settings.starts, seed=settings.seed, loss=settings.loss, threads=threads
    )
    write_ranking(ranked, os.path.join(folder, FIT_FILE))
    best = ranked[0]  # the recommended fit when it passes the thresholds, else the least bad
    chosen = recommended(ranked)
    data = {
        "best_model": best.model,
        "recommended": chosen.model if chosen else None,  # None: no fit passes the thresholds
        "usable": best.usable,
        "problems": best.problems,
        "converged": best.converged,
        "loss": best.metrics["loss"],
        **_de(best.metrics),
        "ranking": [dict(model=r.model, loss=r.metrics["loss"], usable=r.usable, **_de(r.metrics)) for r in ranked],
    }
    return data, [FIT_FILE]


def _render_material(material_file: str, settings: Settings, folder: str, threads: int) -> np.ndarray:
    obj = preview_scene_dict(material_file, settings.env or studio_environment(), settings.shape, coat=False)
    scene = parse_scene(obj, os.path.join(folder, "(preview)"))
    scene = with_overrides(scene, spp=settings.spp, seed=settings.seed, width=settings.width, height=settings.height)
    rendered = render(scene, threads=threads)
    if not rendered.complete:  # Ctrl-C stopped it after a pass: not the preview asked for, write nothing
        raise KeyboardInterrupt
    return rendered.rgb


def _preview(material: Material, settings: Settings, folder: str, threads: int, fitted: bool) -> StepOutput:
    measured = _render_material(material.path, settings, folder, threads)
    best_fit = _render_material(os.path.join(folder, FIT_FILE), settings, folder, threads)
    gap = np.ones((measured.shape[0], max(2, settings.width // 80), 3), np.float32)  # a white rule between
    write_png(os.path.join(folder, PREVIEW_FILE), np.concatenate([measured, gap, best_fit], axis=1))
    return {"image": PREVIEW_FILE}, [PREVIEW_FILE]


def _report(material: Material, settings: Settings, folder: str, threads: int, fitted: bool) -> StepOutput:
    brdf = load_brdf(material.path)
    fit_path = os.path.join(folder, FIT_FILE)
    fits = read_fits(fit_path) if fitted else []  # not a fit.json left by an earlier run
    target = os.path.join(folder, REPORT_DIR)
    skipped: list[str] = []
    write_report(brdf, target, fits, lobes=LobeOptions() if settings.lobes else None, on_skip=skipped.append)
    outputs = sorted(os.path.join(REPORT_DIR, n) for n in os.listdir(target) if not n.startswith("."))
    return {"page": os.path.join(REPORT_DIR, "index.html"), "notes": skipped}, outputs


# (material, settings, its folder, threads, whether this run's fit succeeded) -> (result data, outputs)
STEP_FUNCTIONS: dict[str, Callable[[Material, Settings, str, int, bool], StepOutput]] = {
    "validate": _validate,
    "fit": _fit,
    "preview": _preview,
    "report": _report,
}


# ---------------------------------------------------------------- the task


def run_task(
    step: str, material: Material, settings: Settings, out_dir: str, threads: int, *earlier: dict[str, Any]
) -> dict[str, Any]:
    """Runs one step for one material, or reuses its outputs when the manifest matches.
    `earlier`: the results of the steps it needs (NEEDS), in that order; a failed one blocks it
    (BLOCKED_BY) or is left out (a report without fits)."""
    started = time.perf_counter()
    for r in earlier:
        if r["step"] in BLOCKED_BY.get(step, ()) and r["status"] != "ok":
            why = "failed" if r["status"] == "failed" else "did not run"
            return result(material, step, "blocked", f"not run: the {r['step']} step {why}")
    fitted = any(r["step"] == "fit" and r["status"] == "ok" for r in earlier if "fit" in NEEDS[step])
    folder = material_folder(out_dir, material)
    os.makedirs(folder, exist_ok=True)
    input_sum = checksum(material.path)
    inputs = {FIT_FILE: checksum(os.path.join(folder, FIT_FILE))} if fitted else {}
    chosen = settings.for_step(step)
    recorded = up_to_date(folder, step, input_sum, inputs, chosen)
    if recorded is not None and input_sum:
        return {**recorded, "reused": True}
    readable = material.path
    try:
        # a name that is not UTF-8 reaches the engine through a UTF-8 alias (file_names.engine_path)
        with engine_path(material.path) as readable:
            data, outputs = STEP_FUNCTIONS[step](replace(material, path=readable), settings, folder, threads, fitted)
    except ValueError as e:  # FormatError among them: the input is what it is, a retry would fail again
        message = one_line(e).replace(readable, printable(material.path))
        outcome = result(material, step, "failed", message, seconds=time.perf_counter() - started)
        write_manifest(folder, step, material.path, input_sum, inputs, chosen, [], outcome)
        return outcome
    outcome = result(material, step, "ok", seconds=time.perf_counter() - started, **data)
    write_manifest(folder, step, material.path, input_sum, inputs, chosen, outputs, outcome)
    return outcome
