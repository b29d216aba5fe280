"""`patina bench --only render`: the preview renderer's speed, as ratios measured in one run.

SIMD: the preview scene (car paint on the preview object, path tracing) rendered at
width 4 and 8 against the same render at width 1, one thread, one prepared scene.
Threads: all cores against one. Low-discrepancy samples: the samples a pixel Owen-scrambled
Sobol and independent numbers need to the same RMSE on the preview scene. Against Mitsuba 3:
the time each renderer needs to reach the same RMSE against a converged reference on a
scene both render (the rough gold sphere under the studio map), at the same thread count.
docs/bench.md describes the records.

Renders are timed from job start to resolved image, calling the C++ job directly:
`render.render` polls progress every 50 ms, which would blur short renders.
"""

from __future__ import annotations

import math
import os
import statistics
import subprocess
import sys
from collections.abc import Callable
from typing import Any

import numpy as np

from patina.bench.mitsuba_scenes import mitsuba_scene_dict, preview_mitsuba_scene, triangle_spheres
from patina.bench.records import Record, median_times_and_values, simd_widths
from patina.bundled import materials_path
from patina.native import _core
from patina.render.run import PreparedScene, path_depth
from patina.scene.mitsuba import to_mitsuba
from patina.scene.reading import load_scene, with_overrides
from patina.scene.types import Scene

TARGET_RMSE = 0.02  # per-pixel RMSE relative to the reference's image mean: a clean preview
# Mitsuba 3's sampler in render.vs_mitsuba*: of independent, multijitter and ldsampler (its
# (0,2)-sequence), the least error at equal time on the gold sphere (docs/bench.md)
MITSUBA_SAMPLER = "multijitter"


def _scene_path(name: str) -> str:
    return materials_path("scenes", f"{name}.json")


def _render(
    prep: PreparedScene,
    scene: Scene,
    simd: int,
    threads: int,
    spp: int | None = None,
    seed: int | None = None,
    sampler: str | None = None,
) -> np.ndarray:
    """One render of the prepared scene, start to resolved image; the linear RGB image. simd: 1, 4, 8 (0: default);
    seed, sampler: the scene's unless given."""
    options = _core.RenderOptions(
        spp=spp or scene.render.spp,
        max_depth=path_depth(scene),
        seed=scene.render.seed if seed is None else seed,
        threads=threads,
        width=simd,
        sampler=sampler or scene.render.sampler,
    )
    job = _core.RenderJob(prep.core, options)
    job.start()
    job.wait()
    return np.asarray(job.resolve().rgb, np.float64)


# --- SIMD width and threads on the preview scene ---------------------------------------------


def preview_scene(quick: bool) -> tuple[Scene, PreparedScene, str]:
    """The preview scene, path traced (the file's max_depth), at 256 x 192 and 32 spp (quick: 64 x 48, 4 spp)."""
    w, h, spp = (64, 48, 4) if quick else (256, 192, 32)
    scene = with_overrides(load_scene(_scene_path("preview-ball")), integrator="path", width=w, height=h, spp=spp)
    label = f"preview-ball {w}x{h}, {spp} spp, path (max_depth {scene.render.max_depth})"
    return scene, PreparedScene(scene), label


def _simd_records(scene: Scene, prep: PreparedScene, label: str, repeat: int) -> list[Record]:
    widths = simd_widths()  # 16 too where the CPU runs it (AVX-512)
    fns = [lambda w=w: _render(prep, scene, w, 1) for w in (1, *widths)]
    times, _ = median_times_and_values(fns, repeat)
    samples = scene.camera.width * scene.camera.height * scene.render.spp
    return [
        Record(
            f"render.preview.w{w}",
            f"{label}, SIMD width {w}, 1 thread",
            "the same render at width 1",
            times[0] / t,
            samples / t / 1e6,
            "Msamples/s",
        )
        for w, t in zip(widths, times[1:])
    ]


def _kdtree_only(scene: Scene) -> PreparedScene:
    """The scene prepared with every ray on the kd-tree (PATINA_TRACER=kdtree; docs/trace.md)."""
    before = os.environ.get("PATINA_TRACER")
    os.environ["PATINA_TRACER"] = "kdtree"
    try:
        return PreparedScene(scene)
    finally:
        if before is None:
            del os.environ["PATINA_TRACER"]
        else:
            os.environ["PATINA_TRACER"] = before


def _tracer_record(scene: Scene, prep: PreparedScene, label: str, repeat: int) -> Record:
    """`render.preview.bvh_vs_kdtree`: the render as it is (secondary and shadow rays through the
    BVH) against every ray on the kd-tree, at the widest width, one thread."""
    simd = _core.default_width()
    kd = _kdtree_only(scene)
    times, _ = median_times_and_values([lambda p=p: _render(p, scene, simd, 1) for p in (kd, prep)], repeat)
    samples = scene.camera.width * scene.camera.height * scene.render.spp
    return Record(
        "render.preview.bvh_vs_kdtree",
        f"{label}, SIMD width {simd}, 1 thread, secondary and shadow rays through the BVH",
        "the same render with every ray on the kd-tree",
        times[0] / times[1],
        samples / times[1] / 1e6,
        "Msamples/s",
    )


def _thread_record(scene: Scene, prep: PreparedScene, label: str, repeat: int) -> Record:
    cores = os.cpu_count() or 1
    simd = _core.default_width()
    one, all_cores = (lambda n=n: _render(prep, scene, simd, n) for n in (1, cores))
    times, _ = median_times_and_values([one, all_cores], repeat)
    speedup = times[0] / times[1]
    return Record(
        "render.threads",
        f"{label}, SIMD width {simd}, {cores} threads; value = speedup / threads",
        "the same render on 1 thread",
        speedup,
        speedup / cores,
        "per core",
    )


# --- low-discrepancy against independent numbers -------------------------------------------


LD_SEEDS = 3  # renders a level and sampler (different seeds); their MSEs are averaged


def _spp_to_target(mse_at: Callable[[int], float], target_mse: float, first: int, last: int) -> tuple[float, list]:
    """The spp at which the MSE falls to target_mse, and the levels measured: spp first,
    4 first, ... until the MSE is at or below the target (or spp `last`), then a power law
    through the last two levels. The exponent is measured, not assumed: low-discrepancy
    error falls faster than 1 / spp, and by how much depends on the scene and the spp."""
    measured = [(first, mse_at(first))]
    while measured[-1][1] > target_mse and measured[-1][0] < last:
        n = measured[-1][0] * 4
        measured.append((n, mse_at(n)))
    if len(measured) < 2:  # at the target from the first level
        return float(first), measured
    (n0, e0), (n1, e1) = measured[-2], measured[-1]
    slope = np.log(e1 / e0) / np.log(n1 / n0)  # d log MSE / d log spp, negative
    return (float(n0 * np.exp(np.log(target_mse / e0) / slope)) if slope < 0 else float("inf")), measured


def _own_reference(render_at: Callable[..., np.ndarray], spp: int) -> tuple[np.ndarray, float]:
    """A renderer's converged image of its own: two halves of `spp` with different seeds; their
    mean, and a quarter of their mean squared difference (the mean's own MSE)."""
    a, b = render_at(spp // 2, seed=1001), render_at(spp // 2, seed=1002)
    return (a + b) / 2, float(((a - b) ** 2).mean()) / 4


def _ld_vs_independent_record(quick: bool) -> Record:
    """Samples a pixel to the same RMSE on the preview ball, independent over Sobol.

    The preview scene path traced at 32 x 24 (quick: 16 x 12, RMSE target 0.05). Reference:
    a Sobol render at 4096 spp (quick: 1024) as two halves of different seeds, their mean
    the reference and a quarter of their mean squared difference its own MSE, subtracted
    from every measured MSE. Each sampler renders at 16, 64, 256, ... spp, LD_SEEDS seeds a
    level (the MSE their mean, relative to the reference's image mean squared), until it
    reaches a relative RMSE of TARGET_RMSE (or 4096 spp); the spp to the target is interpolated between
    the last two levels by a power law. ratio = independent's spp / Sobol's, value = Sobol's.
    """
    w, h, ref_spp, target = (16, 12, 1024, 0.05) if quick else (32, 24, 4096, TARGET_RMSE)
    scene = with_overrides(load_scene(_scene_path("preview-ball")), integrator="path", width=w, height=h)
    prep = PreparedScene(scene)
    threads = os.cpu_count() or 1
    reference, reference_mse = _own_reference(
        lambda n, seed: _render(prep, scene, 0, threads, n, seed=seed, sampler="sobol"), ref_spp
    )
    mean2 = float(reference.mean()) ** 2

    def mse_at(sampler: str, spp: int) -> float:
        errors = [
            float(((_render(prep, scene, 0, threads, spp, seed=s, sampler=sampler) - reference) ** 2).mean())
            for s in range(LD_SEEDS)
        ]
        return max(statistics.fmean(errors) - reference_mse, 1e-30) / mean2

    found = {s: _spp_to_target(lambda n, s=s: mse_at(s, n), target**2, 16, ref_spp) for s in ("sobol", "independent")}
    (ld, ld_levels), (iid, iid_levels) = found["sobol"], found["independent"]
    return Record(
        "render.preview.ld_vs_independent",
        f"Owen-scrambled Sobol, preview-ball {w}x{h}, path (max_depth {scene.render.max_depth}): {ld:.0f} spp for "
        f"RMSE {target:g} x mean (measured at {', '.join(str(n) for n, _ in ld_levels)} spp, {LD_SEEDS} seeds each)",
        f"independent numbers, same scene: {iid:.0f} spp (measured at {', '.join(str(n) for n, _ in iid_levels)})",
        iid / ld,
        ld,
        "spp",
    )


# --- against Mitsuba 3 -----------------------------------------------------------------------


def _error_curve(render_at: Callable[[int], np.ndarray], levels: list[int], reference: np.ndarray,
                 reference_mse: float, repeat: int) -> list[tuple[float, float]]:  # fmt: skip
    """(median render seconds, MSE relative to the reference's image mean and net of the
    reference's own MSE) at each spp level."""
    times, images = median_times_and_values([lambda n=n: render_at(n) for n in levels], repeat)
    mean = float(reference.mean())
    return [
        (t, max(float(((img - reference) ** 2).mean()) - reference_mse, 1e-30) / mean**2)
        for t, img in zip(times, images)
    ]


def _seconds_to_error(curve: list[tuple[float, float]], mse: float) -> float:
    """The render time at which a measured (seconds, MSE) curve reaches `mse`: the power law
    through the two measured points around it (through the last two, if it is below all of
    them; through the first two, if above). Measured, not assumed: a low-discrepancy
    sampler's error falls faster than 1 / spp, by how much depends on the scene."""
    points = sorted(curve)
    i = next((k for k in range(len(points) - 2) if points[k + 1][1] <= mse), len(points) - 2)
    (t0, e0), (t1, e1) = points[i], points[i + 1]
    slope = math.log(e1 / e0) / math.log(t1 / t0) if t1 > t0 else 0.0
    if not slope < 0:  # noise swamped the decrease: the later point's time
        return t1
    return t0 * (mse / e0) ** (1.0 / slope)


def _mitsuba_renderer(
    scene: Scene,
    variant: str,
    threads: int,
    stand_ins: bool = False,
    sampler: str | None = None,
    integrator: dict[str, Any] | None = None,
) -> Callable[..., np.ndarray]:
    """Renders of the scene by Mitsuba's `variant` on `threads` threads: spp (and seed) -> image.
    stand_ins: Patina's triangles for every shape and Mitsuba's nearest BSDFs for car paints
    (bench/mitsuba_scenes.py); else the exact conversion (analytic spheres and planes).
    sampler: a Mitsuba sampler plugin instead of the conversion's independent one; integrator: a
    Mitsuba integrator (a plugin's dict) instead of the conversion's."""
    import drjit as dr
    import mitsuba as mi

    dr.set_thread_count(threads)
    # both set the variant
    scene_dict = mitsuba_scene_dict(scene, variant) if stand_ins else to_mitsuba(scene, variant=variant)
    if sampler is not None:
        scene_dict["sensor"]["sampler"]["type"] = sampler
    if integrator is not None:
        scene_dict["integrator"] = integrator
    loaded = mi.load_dict(scene_dict)

    def render_at(spp: int, seed: int = 0) -> np.ndarray:
        mi.set_variant(variant)
        return np.asarray(mi.render(loaded, spp=spp, seed=seed), np.float64)

    return render_at


def llvm_variant_works(timeout: float = 300.0) -> bool:
    """Whether Mitsuba's llvm_ad_rgb renders here. Tried in a child process: with an LLVM that
    lacks what Dr.Jit needs (e.g. Debian 12's libLLVM 15), the JIT aborts the whole process."""
    code = (
        "import mitsuba as mi; mi.set_variant('llvm_ad_rgb'); "
        "import numpy as np; s = mi.load_dict(mi.cornell_box()); "
        "assert np.isfinite(np.asarray(mi.render(s, spp=2))).all()"
    )
    try:
        done = subprocess.run([sys.executable, "-c", code], capture_output=True, timeout=timeout, check=False)
    except (OSError, subprocess.TimeoutExpired):
        return False
    return done.returncode == 0


def _vs_mitsuba_records(repeat: int, quick: bool, llvm: bool) -> list[Record]:
    """Time to the same error, Patina against Mitsuba 3, same scene and thread count, each with
    its best sampler.

    Scene: the rough gold sphere under the studio map (`conductor-sphere.json`, direct
    lighting with MIS on both sides), 128 x 96 (quick: 32 x 24). Method:

    1. Reference: Mitsuba at a high spp (llvm_ad_rgb if it works here, it is faster; else
       scalar_rgb, both with the independent sampler: unbiased and uncorrelated), rendered
       as two halves with different seeds: their mean is the reference and a quarter of
       their mean squared difference its own MSE, subtracted from every measured MSE.
    2. Patina with its default sampler (Owen-scrambled Sobol) and Mitsuba with MITSUBA_SAMPLER
       (the one of its samplers with the least error at equal time here, docs/bench.md), each
       at three spp levels: median render time over `repeat` runs and the MSE against the
       reference (relative to the image mean).
    3. The error to reach is Patina's at its highest level, so Patina's time is measured;
       Mitsuba's time to that error comes from the power law through its two measured
       points around it (_seconds_to_error). No 1 / spp law is assumed: a low-discrepancy
       sampler converges faster, by an amount that depends on the scene.
       ratio = Mitsuba's time / Patina's time, value = Patina's time.
    The sphere is analytic on both sides (the scene's `"analytic": true`: Patina's exact sphere,
    Mitsuba's `sphere` plugin).
    4. `render.vs_mitsuba_llvm.triangles`: both renderers on Patina's own triangles of the
       sphere instead (the scene with `analytic` off; Mitsuba given those triangles,
       bench/mitsuba_scenes.py), Patina's error curve and target measured again on them; same
       reference.

    Patina's GGX uses the height-correlated Smith term and Mitsuba's the separable one
    (0.2 % brighter image mean on this scene, tests/python/render/test_against_mitsuba.py): that
    bias counts as Patina's error, but its square is under 1 % of the MSE at the levels
    measured.
    """
    import mitsuba  # noqa: F401  (ImportError: no records)

    threads = os.cpu_count() or 1
    w, h, levels, ref_spp = (32, 24, [4, 16, 64], 1024) if quick else (128, 96, [32, 128, 512], 8192)
    scene = with_overrides(load_scene(_scene_path("conductor-sphere")), width=w, height=h, seed=0)
    prep = PreparedScene(scene)

    ref_render = _mitsuba_renderer(scene, "llvm_ad_rgb" if llvm else "scalar_rgb", threads)
    reference, reference_mse = _own_reference(ref_render, ref_spp)

    def patina_curve(s: Scene) -> list[tuple[float, float]]:
        p = prep if s is scene else PreparedScene(s)
        return _error_curve(lambda n: _render(p, s, 0, threads, n), levels, reference, reference_mse, repeat)

    # (record name, variant, both on Patina's triangles of the sphere instead of the analytic one)
    runs = [("render.vs_mitsuba", "scalar_rgb", False)]
    if llvm:
        runs += [("render.vs_mitsuba_llvm", "llvm_ad_rgb", False)]
        runs += [("render.vs_mitsuba_llvm.triangles", "llvm_ad_rgb", True)]
    curves = {False: patina_curve(scene)}
    records = []
    for name, variant, triangles in runs:
        if triangles not in curves:
            curves[triangles] = patina_curve(triangle_spheres(scene))
        patina = curves[triangles]
        tp, target = patina[-1]
        shown = triangle_spheres(scene) if triangles else scene
        render_at = _mitsuba_renderer(shown, variant, threads, stand_ins=triangles, sampler=MITSUBA_SAMPLER)
        other = _error_curve(render_at, levels, reference, reference_mse, repeat)
        tm = _seconds_to_error(other, target)
        shape = "Patina's triangles of the sphere, as Patina" if triangles else "its analytic sphere, as Patina"
        records.append(
            Record(
                name,
                f"Patina (Owen-scrambled Sobol), conductor-sphere {w}x{h}, {threads} threads: {tp:.2f} s for "
                f"RMSE {math.sqrt(target):.3f} x mean at {levels[-1]} spp (MSE at {', '.join(map(str, levels))} spp: "
                f"{', '.join(f'{e:.2e}' for _, e in patina)})",
                f"Mitsuba 3 {variant} ({MITSUBA_SAMPLER} sampler, {shape}), same threads: {tm:.2f} s (MSE: "
                f"{', '.join(f'{e:.2e} in {t:.2f} s' for t, e in other)})",
                tm / tp,
                tp,
                "s",
            )
        )
    return records


def _preview_vs_mitsuba_record(repeat: int, quick: bool) -> Record:
    """Time to the same relative RMSE on the preview ball with materials Mitsuba also has
    (materials/scenes/preview-mitsuba.json), Patina against Mitsuba 3 llvm_ad_rgb, same threads,
    each with its best sampler (Patina's Owen-scrambled Sobol, Mitsuba's MITSUBA_SAMPLER).

    Path traced (5 segments), 128 x 96 (quick: 32 x 24), every shape the same triangles on both
    sides. Two of its materials are Mitsuba stand-ins, not exact equivalents (bench/mitsuba_scenes.py),
    so each renderer's error is measured against its own converged image (2048 spp as two halves,
    _own_reference; quick 256); otherwise the method is render.vs_mitsuba's: measured error
    curves at three spp levels, the error to reach Patina's at its highest level, Mitsuba's time
    to it from the power law through its own measured points (_seconds_to_error). The candidate
    string gives Patina's image mean over Mitsuba's, to show the scenes agree.
    """
    threads = os.cpu_count() or 1
    w, h, levels, ref_spp = (32, 24, [4, 16, 64], 256) if quick else (128, 96, [16, 64, 256], 2048)
    scene = preview_mitsuba_scene(w, h)
    prep = PreparedScene(scene)

    def patina_at(n: int, seed: int = 0) -> np.ndarray:
        return _render(prep, scene, 0, threads, n, seed)

    mitsuba_at = _mitsuba_renderer(scene, "llvm_ad_rgb", threads, stand_ins=True, sampler=MITSUBA_SAMPLER)
    own = {"patina": _own_reference(patina_at, ref_spp), "mitsuba": _own_reference(mitsuba_at, ref_spp)}
    patina = _error_curve(patina_at, levels, *own["patina"], repeat)
    other = _error_curve(mitsuba_at, levels, *own["mitsuba"], repeat)
    tp, target = patina[-1]
    tm = _seconds_to_error(other, target)
    means = float(own["patina"][0].mean()) / float(own["mitsuba"][0].mean())
    return Record(
        "render.preview.vs_mitsuba_llvm",
        f"Patina (Owen-scrambled Sobol), preview-mitsuba {w}x{h}, path, {threads} threads: {tp:.2f} s for "
        f"RMSE {math.sqrt(target):.3f} x mean at {levels[-1]} spp (MSE at {', '.join(map(str, levels))} spp: "
        f"{', '.join(f'{e:.2e}' for _, e in patina)}; image mean {means:.3f} x Mitsuba's)",
        f"Mitsuba 3 llvm_ad_rgb ({MITSUBA_SAMPLER} sampler), same scene (stand-in BSDFs for the coats) and "
        f"threads: {tm:.2f} s (MSE: {', '.join(f'{e:.2e} in {t:.2f} s' for t, e in other)})",
        tm / tp,
        tp,
        "s",
    )


def bench_render(repeat: int, quick: bool, mitsuba: bool = True) -> list[Record]:
    """The `render` group: SIMD width records, the thread record, Sobol against independent, then the Mitsuba comparison
    (skipped without Mitsuba, or with mitsuba=False; `_llvm` only where llvm_ad_rgb works)."""
    scene, prep, label = preview_scene(quick)
    records = _simd_records(scene, prep, label, repeat)
    records.append(_tracer_record(scene, prep, label, repeat))
    records.append(_thread_record(scene, prep, label, repeat))
    records.append(_ld_vs_independent_record(quick))
    if mitsuba:
        try:
            import mitsuba as _  # noqa: F401
        except ImportError:
            print("patina bench: Mitsuba 3 is not installed: no render.vs_mitsuba records", file=sys.stderr)
            return records
        llvm = llvm_variant_works()
        if not llvm:
            print("patina bench: Mitsuba's llvm_ad_rgb does not run here: no render.vs_mitsuba_llvm", file=sys.stderr)
        records += _vs_mitsuba_records(repeat, quick, llvm)
        if llvm:
            records.append(_preview_vs_mitsuba_record(repeat, quick))
    return records
