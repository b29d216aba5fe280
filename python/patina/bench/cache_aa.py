"""`cache.<scene>.aa_adaptive_vs_uniform` (issue 31, "The cache and AA together"): the radiance
cache (`cache`) with the adaptive antialiasing against `cache` with the uniform sampler, at the
scene's own size: the time the uniform sampler needs for the error the adaptive one reaches,
over the adaptive render's time (> 1: adaptive gets there sooner).

Both are measured as the cache group measures its integrators (bench/convergence.py): relMSE
against the converged `path` reference, the median over seeds, the render job's own time; the
uniform sampler at a ladder of spp gives error against time, interpolated on log-log axes.
The adaptive sampler at ADAPTIVE_PATTERNS patterns a pixel (each pattern its 1 to 28 rays)."""

from __future__ import annotations

from patina.bench.convergence import ErrorCurve, Run, median_relmse, reference, sized, timed_renders
from patina.bench.records import Record
from patina.bundled import materials_path
from patina.render.run import PreparedScene
from patina.scene.reading import load_scene, with_overrides

UNIFORM_LADDER = (1, 4, 16)  # the uniform sampler's spp
ADAPTIVE_PATTERNS = 2  # the adaptive sampler's patterns a pixel: within the ladder's rays on the room
QUICK_LADDER, QUICK_PATTERNS = (1, 4), 1
REFERENCE_SPP, QUICK_REFERENCE_SPP = 2048, 64  # the cache group's (bench/cache.py FULL, QUICK)
QUICK_WIDTH = 16


def aa_adaptive_record(name: str, repeat: int, threads: int, quick: bool) -> Record:
    """`cache.<name>.aa_adaptive_vs_uniform` for materials/scenes/<name>.json at its own width
    (`quick`: QUICK_WIDTH pixels wide, fewer samples)."""
    scene_file = materials_path("scenes", f"{name}.json")
    scene = with_overrides(load_scene(scene_file), integrator="cache")
    if quick:
        scene = sized(scene, QUICK_WIDTH)
    ladder, patterns = (QUICK_LADDER, QUICK_PATTERNS) if quick else (UNIFORM_LADDER, ADAPTIVE_PATTERNS)
    ref = reference(scene_file, scene, QUICK_REFERENCE_SPP if quick else REFERENCE_SPP, threads)
    uniform = with_overrides(scene, aa="uniform")
    adaptive = with_overrides(scene, aa="adaptive", spp=patterns)
    prepared = PreparedScene(uniform)  # the spp change nothing prepared
    runs = [Run(with_overrides(uniform, spp=n), prepared, threads) for n in ladder]
    runs.append(Run(adaptive, PreparedScene(adaptive), threads))
    times, images = timed_renders(runs, repeat)
    errors = [median_relmse(imgs, ref.image, ref.error) for imgs in images]
    curve = ErrorCurve(times[:-1], errors[:-1])
    t, e = times[-1], errors[-1]
    size = f"{scene.camera.width}x{scene.camera.height}"
    steps = ", ".join(f"{n} spp {s:.2f} s relMSE {x:.3g}" for n, s, x in zip(ladder, times, errors))
    what = f"cache, adaptive antialiasing, {name} {size}, {threads} threads, {patterns} patterns"
    what += f": {t:.2f} s, relMSE {e:.3g}"
    baseline = f"cache with the uniform sampler ({steps}); reference {ref.path}"
    return Record(f"cache.{name}.aa_adaptive_vs_uniform", what, baseline, curve.seconds_for(e) / t, t, "s")
