"""`patina bench --only profile`: where a preview render's time goes, stage by stage, per SIMD width.

The wavefront integrator times each of its stages per thread (render/integrators/stage_timer.h,
`RenderJob.stage_times()`). This group renders the bench's preview scene (the same as
`render.preview.w*`) on one thread at width 1 and at each wide width, runs interleaved,
and takes each stage's median time. Records: per stage and per kind of work (traversal,
shading, lights, bookkeeping), ratio = the width-1 time / the wide width's (the stage's
own SIMD speedup), value = the wide width's nanoseconds per camera sample. The table
printed with them is the breakdown docs/performance.md quotes.
"""

from __future__ import annotations

import os
import statistics
import sys
import time

from patina.bench.mitsuba_split import mitsuba_split_records
from patina.bench.records import Record, simd_widths
from patina.bench.render import llvm_variant_works, preview_scene
from patina.bundled import materials_path
from patina.native import _core
from patina.render.run import PreparedScene, path_depth
from patina.scene.reading import load_scene, with_overrides
from patina.scene.types import Scene

# What each stage is, by the kind of work the issue splits the time into.
KINDS: dict[str, tuple[str, ...]] = {
    "traversal": ("trace_camera", "trace_secondary", "trace_shadow"),
    "shading": ("shade_light", "shade_sample"),
    "lights": ("emission", "light_sample"),
    "bookkeeping": (
        "camera_rays",
        "ray_gather",
        "shading_points",
        "group_material",
        "light_select",
        "light_to_local",
        "shadow_queue",
        "bsdf_uniforms",
        "path_update",
        "shadow_resolve",
        "sampler_film",
    ),
    # the radiance cache at the first hit (integrators cache, cache-guided), its own rays included
    "cache": (
        "cache_place",
        "cache_build",
        "cache_surfels",
        "cache_reproject",
        "cache_holes",
        "cache_integrate",
        "cache_split",
    ),
}


def stage_seconds(prep: PreparedScene, scene: Scene, simd: int) -> dict[str, float]:
    """One single-thread render's CPU seconds per stage, plus sampler_film (the pixel sampler and
    film between batches: the work items' time not in a stage) and total (the items' time)."""
    options = _core.RenderOptions(
        spp=scene.render.spp,
        max_depth=path_depth(scene),
        seed=scene.render.seed,
        threads=1,
        width=simd,
        stage_clock="cpu",  # the thread's CPU time: a shared machine's waits for a core left out
    )
    job = _core.RenderJob(prep.core, options)
    job.start()
    job.wait()
    times = job.stage_times()
    out = dict(times.stages)
    out["sampler_film"] = max(times.item_seconds - sum(out.values()), 0.0)
    out["total"] = times.item_seconds
    return out


def median_stage_seconds(
    prep: PreparedScene, scene: Scene, widths: list[int], repeat: int
) -> dict[int, dict[str, float]]:
    """Per width, each stage's median over `repeat` renders, widths interleaved so drift hits all alike."""
    runs: dict[int, list[dict[str, float]]] = {w: [] for w in widths}
    for _ in range(repeat):
        for w in widths:
            runs[w].append(stage_seconds(prep, scene, w))
    return {w: {k: statistics.median(r[k] for r in runs[w]) for k in runs[w][0]} for w in widths}


def kind_seconds(stages: dict[str, float]) -> dict[str, float]:
    return {kind: sum(stages[s] for s in names) for kind, names in KINDS.items()}


def breakdown_table(medians: dict[int, dict[str, float]]) -> str:
    """Milliseconds per stage at each width, the share of that width's total, and each wide
    width's speedup over width 1; the kinds of work and the total below."""
    widths = sorted(medians)
    head = f"{'stage':<16}" + "".join(f" {f'w{w} ms':>9} {'%':>5}" for w in widths)
    head += "".join(f" {f'w1/w{w}':>7}" for w in widths[1:])
    lines = [head]

    def row(name: str, values: dict[int, float], totals: dict[int, float]) -> str:
        text = f"{name:<16}" + "".join(f" {values[w] * 1e3:9.1f} {100 * values[w] / totals[w]:5.1f}" for w in widths)
        return text + "".join(f" {values[1] / values[w] if values[w] > 0 else float('nan'):7.2f}" for w in widths[1:])

    totals = {w: medians[w]["total"] for w in widths}
    for kind, names in KINDS.items():
        for s in names:
            lines.append(row(s, {w: medians[w][s] for w in widths}, totals))
        lines.append(row(f"= {kind}", {w: kind_seconds(medians[w])[kind] for w in widths}, totals))
    lines.append(row("total", totals, totals))
    return "\n".join(lines)


def _profile_records(
    prefix: str, scene: Scene, prep: PreparedScene, label: str, repeat: int, stages: bool
) -> list[Record]:
    """The scene's breakdown at width 1 and each wide width (the table on stderr); records per
    kind of work (and per stage: `stages`), named `{prefix}.kind.<kind>.w<N>` / `.stage.`."""
    wide = [w for w in simd_widths() if w in (4, 8, 16)]  # 16 where the CPU runs it (AVX-512)
    t0 = time.perf_counter()
    medians = median_stage_seconds(prep, scene, [1, *wide], repeat)
    print(f"profile: {label}, 1 thread, median stage times ({time.perf_counter() - t0:.0f} s)", file=sys.stderr)
    print(breakdown_table(medians), file=sys.stderr)
    samples = scene.camera.width * scene.camera.height * scene.render.spp
    records = []
    for w in wide:
        kinds_1, kinds_w = kind_seconds(medians[1]), kind_seconds(medians[w])
        parts = [(f"kind.{k}", kinds_1[k], kinds_w[k]) for k in KINDS]
        if stages:
            parts += [(f"stage.{s}", medians[1][s], medians[w][s]) for names in KINDS.values() for s in names]
        for name, base, cand in parts:
            if cand <= 0 or base <= 0:
                continue  # a stage this scene never runs
            records.append(
                Record(
                    f"{prefix}.{name}.w{w}",
                    f"{label}: {name.split('.', 1)[1]} at SIMD width {w}, 1 thread",
                    "the same stage at width 1",
                    base / cand,
                    cand / samples * 1e9,
                    "ns/sample",
                )
            )
    return records


def bench_profile(repeat: int, quick: bool) -> list[Record]:
    """The `profile` group: the stage breakdown of the preview render and of the gold sphere (the
    scene of render.vs_mitsuba) at width 1 and each wide width; then, where Mitsuba's llvm_ad_rgb
    runs, its lead split by its own switches (bench/mitsuba_split.py)."""
    runs = max(repeat // 2, 1)
    scene, prep, label = preview_scene(quick)
    records = _profile_records("render.profile", scene, prep, label, runs, stages=True)
    w, h = (32, 24) if quick else (128, 96)
    gold = with_overrides(load_scene(materials_path("scenes", "conductor-sphere.json")), width=w, height=h, spp=128)
    label = f"conductor-sphere {w}x{h}, 128 spp, direct"
    records += _profile_records("render.profile.gold", gold, PreparedScene(gold), label, runs, stages=False)
    try:
        import mitsuba as _  # noqa: F401
    except ImportError:
        print("patina bench: Mitsuba 3 is not installed: no render.profile.mitsuba records", file=sys.stderr)
        return records
    if not llvm_variant_works():
        print("patina bench: Mitsuba's llvm_ad_rgb does not run here: no render.profile.mitsuba", file=sys.stderr)
        return records
    return records + mitsuba_split_records(repeat, quick, os.cpu_count() or 1)
