"""Materials out to renderers: Mitsuba 3, pbrt-v4, MaterialX (OpenPBR), glTF, USD, Blender and
RGL tensor files (docs/export.md). The source (a fit.json, a ranking, a measured table, a
scene's material: source) becomes an AnalyticMaterial (material), refitted to the target's
model where it is not one (refit), written by the target's writer (targets and one module per
target), with its error against the source in a sidecar FILE.export.json. A measured table
for Mitsuba or pbrt, and anything for `rgl`, is written as an RGL tensor file instead, and
Mitsuba's and pbrt's `measured` material reading it (measured)."""

from __future__ import annotations

import importlib.util
import json
import os
from typing import Any

from patina.atomic import write_text
from patina.errors import FormatError
from patina.export.material import AnalyticMaterial, Coat, Lobe
from patina.export.measured import MEASURED_TARGETS, export_measured
from patina.export.mitsuba import mitsuba_eval, to_mitsuba_dict
from patina.export.refit import (
    MAX_REFIT_DE,
    Reference,
    RefitError,
    error_metrics,
    fit_reference,
    measure,
    needs_refit,
    refit,
    table_reference,
)
from patina.export.source import Source, load_source
from patina.export.targets import TARGETS
from patina.table import load_brdf


def prepare(
    source: Source, target: str, reference: Reference | None = None, progress: bool = False
) -> AnalyticMaterial:
    """The material the target writes: the source itself, or its refit against `reference`
    (default: the source fit evaluated densely); RefitError if that fails."""
    t = TARGETS[target]
    why = needs_refit(source, t.max_lobes, t.distributions)
    if not why:
        return source.exact
    material = refit(source, source.name, reference or fit_reference(source.evaluate), progress)
    material.notes.insert(0, f"refitted: {why}")
    return material


TARGET_PAIRS = 2000


def _in_target(reference: Reference, material: AnalyticMaterial, target: str) -> dict[str, Any] | None:
    """The written material as the target itself evaluates it, against the source: Mitsuba 3
    where its package is installed (the other targets have no evaluator here); None otherwise."""
    if target != "mitsuba" or importlib.util.find_spec("mitsuba") is None:
        return None
    wi, wo, values = reference(TARGET_PAIRS, 11)
    exported = mitsuba_eval(to_mitsuba_dict(material), wi, wo)
    return {"evaluator": "mitsuba scalar_rgb", **error_metrics(values, exported, wi[:, 2])}


def _measured_against(source: Source) -> str:
    if source.table is not None:
        return "the table's own samples"
    return "the source fit, evaluated at dense direction pairs"


def export(
    spec: str, target: str, out: str, table: str | None = None, progress: bool = False, **options: Any
) -> dict[str, Any]:
    """Writes MATERIAL `spec` for `target` to `out` and its sidecar `out`.export.json; returns
    the sidecar's contents. `table`: the measured table the fit came from, which the refit and
    the errors are then measured against. `channels` (rgl, and a table to mitsuba or pbrt):
    "spectral" (default) or "rgb". ValueError for an unknown target; FormatError for bad input."""
    if target not in TARGETS:
        raise ValueError(f"unknown target '{target}' (known: {', '.join(TARGETS)})")
    channels = options.pop("channels", None)
    source = load_source(spec)
    if target == "rgl" or (source.table is not None and target in MEASURED_TARGETS):
        if table:
            raise ValueError("--table is for an analytic export's refit; an RGL tensor file is MATERIAL resampled")
        if target == "pbrt" and channels == "rgb":
            raise ValueError("pbrt-v4's measured material reads spectral files only: leave out --channels rgb")
        report = export_measured(source, target, out, channels or "spectral", progress)
        write_text(f"{out}.export.json", json.dumps(report, indent=2))
        return report
    if channels:
        raise ValueError(
            f"--channels is for an RGL tensor file (--to rgl, or a table to {' or '.join(MEASURED_TARGETS)})"
        )
    if table:
        reference = table_reference(load_brdf(table))
    elif source.table is not None:
        reference = table_reference(source.table)  # a table to an analytic target: refitted against its samples
    else:
        reference = fit_reference(source.evaluate)
    try:
        material = prepare(source, target, reference, progress)
    except RefitError as e:
        raise FormatError(source.path, "", f"{target} cannot hold {source.model} and {e}") from None
    metrics = measure(reference, material)
    if material is not source.exact and metrics["ciede2000_mean"] > MAX_REFIT_DE:
        problem = f"the refit's mean CIEDE2000 {metrics['ciede2000_mean']:.1f} is above {MAX_REFIT_DE:g}"
        raise FormatError(source.path, "", f"{target} cannot hold {source.model}: {problem}")
    notes = list(material.notes)
    TARGETS[target].write(material, out, notes, options)
    in_target = _in_target(reference, material, target)
    report = {
        "target": target,
        "out": os.fspath(out),
        "source": source.path,
        "source_model": source.model,
        "measured_against": table or _measured_against(source),
        "material": material.as_json(),
        "refitted": material is not source.exact,
        "error_against_source": metrics,
        "target_error_against_source": in_target,
        "notes": notes,
    }
    write_text(f"{out}.export.json", json.dumps(report, indent=2))
    return report


__all__ = ["TARGETS", "AnalyticMaterial", "Coat", "Lobe", "RefitError", "export", "load_source", "to_mitsuba_dict"]
