"""`patina bench --only cache` (issue 13, item 6): the radiance-cache integrators against the
path tracer on the bundled scenes where secondary light matters (materials/scenes/cache-*.json).

Per scene, at the scenes' own size (192 pixels wide, where users preview; `--large` 384,
records named with LARGE_SUFFIX; `--quick` 16), all renders on every core:

1. A converged reference, rendered once by `path` as two halves with different seeds and
   kept on disk outside the repository (bench/convergence.py, `reference_dir()`, keyed by
   a hash of the scene file, the settings and Patina's version): their mean is the
   reference, its own error (from the halves) subtracted from every error measured.
2. The error of an image: relMSE, per pixel (x - r)^2 / (r^2 + 0.01) averaged over RGB with
   both images divided by the reference's mean, the top 0.1 % of pixel errors discarded
   (as path-guiding evaluations do, so a few fireflies do not decide a record).
3. `path` at a ladder of spp: the median time of each and its error (the median over the
   renders' seeds: bench/convergence.py, timed_renders) give error-versus-time, interpolated
   piecewise linearly on log-log axes and extended beyond the ladder at Monte Carlo's rate
   (error x time constant). Every integrator's error is the median over the same seeds.
4. Records (docs/bench.md): `cache.<scene>.biased_vs_path` (the time `path` needs for the
   error `cache` reaches, over the time `cache` takes), `cache.<scene>.guided_vs_path` (the
   same for `cache-guided`) and `cache.<scene>.guided_equal_time` (path's error at the time
   `cache-guided` takes, over `cache-guided`'s), `cache.<scene>.bias` (the relative bias of
   `cache`'s image mean: the mean over BIAS_SEEDS seeds at BIAS_SIZES' width against a
   reference of that size, as one seed's swings with the rare bright texels a cache point
   shares) and `cache.<scene>.bias_se` (that mean's standard error), `cache.threads`
   (`cache` on every core against one thread),
   `cache.<scene>.block_steps` (the mosaic in `cache`'s error: bench/block_steps.py),
   `cache.<scene>.flip_vs_path` (the mean FLIP of `path` at the time `cache` takes over
   `cache`'s: how the images look, bench/flip.py),
   `cache.<scene>.vs_mitsuba_llvm` (bench/cache_mitsuba.py: Patina's fastest integrator
   against Mitsuba 3's llvm_ad_rgb path tracer on the scene's analytic counterpart),
   `cache.<scene>.aa_adaptive_vs_uniform` (bench/cache_aa.py: `cache` with the adaptive
   antialiasing against the uniform sampler, at the scene's own size).

A record whose integrator this build does not have is skipped with the reason on stderr;
`run_cache_bench(..., integrators=...)` runs the same measurements with other integrators
(the tests use `path` for both, which the harness then must find equal to itself).
"""

from __future__ import annotations

import dataclasses
import os
import statistics
import sys
import time
from dataclasses import dataclass, field

import numpy as np

from patina.bench.block_steps import block_step_ratios
from patina.bench.cache_aa import aa_adaptive_record
from patina.bench.cache_mitsuba import vs_mitsuba_record
from patina.bench.convergence import (
    ErrorCurve,
    Reference,
    Run,
    Sizes,
    integrator_missing,
    median_relmse,
    reference,
    sized,
    timed_renders,
)
from patina.bench.flip import mean_flip
from patina.bench.records import Record
from patina.bench.render import llvm_variant_works
from patina.bundled import materials_path
from patina.render.outputs import auto_exposure
from patina.render.run import PreparedScene, render
from patina.scene.reading import load_scene, with_overrides
from patina.scene.types import Scene

SCENES = ("cache-room", "cache-studio", "cache-ies-interior", "cache-car")
INTEGRATORS = {"biased": "cache", "guided": "cache-guided"}
# the scenes' own width: the cache's fixed work (its points' hemispheres) amortises over the
# pixels, so at 96 wide the bench measured it where it cannot pay (issue 31: cache-room's
# biased_vs_path 0.40 at 96 wide, 1.79 at 192, 2.76 at 384)
FULL = Sizes(192, 2048, (8, 32, 128), 16)
LARGE = Sizes(384, 2048, (8, 32, 128), 16)  # `--large`: twice the scenes' width, toward a user's final render
LARGE_SUFFIX = ".large"  # on every record name of a `--large` run: both sizes' records fit in one file
# the group's repeats at most (`patina bench --repeat`, default 7): 1 + 3 seeds give the
# medians, and the group's renders stay at minutes a scene
MAX_REPEAT = 3
QUICK = Sizes(16, 64, (2, 8), 2)
# the bias: `cache` at the candidates' spp on BIAS_SEEDS seeds at a small size (its image mean
# swings from seed to seed with the few bright texels a cache point shares, so one seed, or
# the four of the errors, says little: docs/radiance-cache.md, "Bias"), against a reference of
# that size with more samples than FULL's (its own noise is part of the bias measured)
BIAS_SEEDS = 16
BIAS_SIZES = Sizes(32, 8192, (), 16)
QUICK_BIAS_SIZES = Sizes(16, 64, (), 2)


@dataclass
class CacheBench:
    records: list[Record] = field(default_factory=list)
    skipped: list[tuple[str, str]] = field(default_factory=list)  # (record name, why)


def _scene_records(
    name: str, sizes: Sizes, repeat: int, threads: int, integrators: dict[str, str], out: CacheBench
) -> None:
    scene_file = materials_path("scenes", f"{name}.json")
    scene = sized(load_scene(scene_file), sizes.width)
    label = f"{name} {scene.camera.width}x{scene.camera.height}, {threads} threads"
    candidates: list[Run] = []
    roles: dict[str, int] = {}  # candidate role -> its index after the ladder
    for role, integrator in integrators.items():
        why = integrator_missing(scene, integrator)
        if why is not None:
            names = (
                ["biased_vs_path", "bias", "bias_se", "block_steps", "flip_vs_path"]
                if role == "biased"
                else ["guided_vs_path", "guided_equal_time"]
            )
            out.skipped += [(f"cache.{name}.{n}", why) for n in names]
            continue
        candidate = with_overrides(scene, integrator=integrator, spp=sizes.candidate_spp)
        roles[role] = len(sizes.ladder) + len(candidates)
        candidates.append(Run(candidate, PreparedScene(candidate), threads))
    if not candidates:
        return  # nothing to compare the path tracer with: no reference, no ladder
    ref = reference(scene_file, scene, sizes.reference_spp, threads)
    path_scene = with_overrides(scene, integrator="path")
    path_prep = PreparedScene(path_scene)
    ladder = [Run(with_overrides(path_scene, spp=n), path_prep, threads) for n in sizes.ladder]
    times, images = timed_renders(ladder + candidates, repeat)
    errors = [median_relmse(imgs, ref.image, ref.error) for imgs in images]
    n = len(sizes.ladder)
    curve = ErrorCurve(times[:n], errors[:n])
    steps = ", ".join(f"{s} spp {t:.2f} s relMSE {e:.3g}" for s, t, e in zip(sizes.ladder, times, errors))
    baseline = f"path on the same scene and threads ({steps}); reference {sizes.reference_spp} spp of path"
    for role, i in roles.items():
        integrator, t, e = integrators[role], times[i], errors[i]
        what = f"{integrator}, {label}, {sizes.candidate_spp} spp: {t:.2f} s, relMSE {e:.3g}"
        key = "biased_vs_path" if role == "biased" else "guided_vs_path"
        out.records.append(Record(f"cache.{name}.{key}", what, baseline, curve.seconds_for(e) / t, t, "s"))
        if role == "guided":
            equal_time = f"path's relMSE at {t:.2f} s: " + baseline
            out.records.append(
                Record(f"cache.{name}.guided_equal_time", what, equal_time, curve.error_at(t) / e, e, "relMSE")
            )
        else:
            bias_sizes = QUICK_BIAS_SIZES if sizes == QUICK else BIAS_SIZES
            out.records += bias_records(name, scene_file, scene, integrator, bias_sizes, threads)
            out.records.append(block_steps_record(name, what, images[i][0], ref))
            found = flip_vs_path_record(name, what, images[i], t, ladder[-1], times[n - 1], repeat, ref)
            if isinstance(found, Record):
                out.records.append(found)
            else:
                out.skipped.append((f"cache.{name}.flip_vs_path", found))


def flip_vs_path_record(
    name: str,
    what: str,
    images: list[np.ndarray],
    seconds: float,
    top_level: Run,
    top_seconds: float,
    repeat: int,
    ref: Reference,
) -> Record | str:
    """`cache.<name>.flip_vs_path`: the median over seeds of `path`'s mean FLIP at equal time
    over that of the candidate's `images` (> 1: the candidate looks closer to the reference);
    value: the candidate's mean FLIP. `path` at equal time is the ladder's `top_level` (which
    took `top_seconds`) at the spp that fit in `seconds` at its time a sample (the level whose
    fixed costs weigh least on a sample), rendered here on the same seeds as `images`. The
    reason instead where flip-evaluator is missing."""
    stops = auto_exposure(ref.image)
    flips = [mean_flip(img, ref.image, stops) for img in images]
    if None in flips:
        return "flip-evaluator is not installed"
    spp = max(1, round(seconds * top_level.scene.render.spp / top_seconds))
    equal_time = Run(with_overrides(top_level.scene, spp=spp), top_level.prep, top_level.threads)
    (path_seconds,), (path_images,) = timed_renders([equal_time], repeat)
    path_flip = statistics.median(mean_flip(img, ref.image, stops) for img in path_images)
    flip = statistics.median(flips)
    baseline = f"path at {spp} spp ({path_seconds:.2f} s: equal time), mean FLIP {path_flip:.4f}, median over seeds"
    candidate = f"{what}; mean FLIP {flip:.4f} (filmic at the reference's auto exposure)"
    return Record(f"cache.{name}.flip_vs_path", candidate, baseline, path_flip / flip, flip, "FLIP")


def block_steps_record(name: str, what: str, image: np.ndarray, ref: Reference) -> Record:
    """`cache.<name>.block_steps`: the largest, over k in BLOCK_SIZES, of the mean step of the
    image's error across a k x k grid over its mean step beside the grid's lines
    (bench/block_steps.py; 1: no mosaic; issue 31's bound 1.2)."""
    ratios = block_step_ratios(image, ref.image)
    steps = ", ".join(f"k = {k}: {r:.3f}" for k, r in ratios.items())
    worst = max(ratios.values())
    base = "the error's mean step beside the k x k grid lines (reference: the path tracer's)"
    return Record(f"cache.{name}.block_steps", f"{what}; {steps}", base, worst, worst, "ratio")


def bias_over_seeds(
    scene_file: str, scene: Scene, integrator: str, sizes: Sizes, threads: int, seeds: int = BIAS_SEEDS
) -> tuple[np.ndarray, Reference]:
    """`integrator`'s image mean over the reference's, one a seed (scene seed + 0, 1, ...), at
    `sizes`' width and candidate spp, against `path`'s reference of `sizes.reference_spp`."""
    small = sized(scene, sizes.width)
    ref = reference(scene_file, small, sizes.reference_spp, threads)
    candidate = with_overrides(small, integrator=integrator, spp=sizes.candidate_spp)
    prep = PreparedScene(candidate)
    means = [
        float(
            np.mean(
                render(with_overrides(candidate, seed=candidate.render.seed + k), threads=threads, prepared=prep).rgb
            )
        )
        for k in range(seeds)
    ]
    return np.asarray(means) / float(ref.image.mean()), ref


def bias_records(name: str, scene_file: str, scene: Scene, integrator: str, sizes: Sizes, threads: int) -> list[Record]:
    """`cache.<name>.bias` (the mean over seeds of the image mean over the reference's; value
    the relative bias in %) and `cache.<name>.bias_se` (its standard error over the seeds:
    ratio as a ratio, value in %)."""
    ratios, ref = bias_over_seeds(scene_file, scene, integrator, sizes, threads)
    mean, se = float(ratios.mean()), float(ratios.std(ddof=1) / np.sqrt(len(ratios)))
    h, w = ref.image.shape[:2]
    what = (
        f"{integrator}, {name} {w}x{h}, {threads} threads, {sizes.candidate_spp} spp, mean over {len(ratios)} seeds "
        f"(bias {100 * (mean - 1):+.2f} +- {100 * se:.2f} %)"
    )
    base = f"the reference's image mean ({sizes.reference_spp} spp of path, {w}x{h})"
    bias_what = f"{what}; value = (mean - reference mean) / reference mean"
    se_what = f"{what}; value = the bias's standard error over the seeds"
    return [
        Record(f"cache.{name}.bias", bias_what, base, mean, 100 * (mean - 1), "%"),
        Record(f"cache.{name}.bias_se", se_what, base, se, 100 * se, "%"),
    ]


def _threads_record(sizes: Sizes, repeat: int, integrator: str, out: CacheBench) -> None:
    """`integrator` on the studio scene, on every core against one thread."""
    scene_file = materials_path("scenes", "cache-studio.json")
    scene = sized(load_scene(scene_file), sizes.width)
    why = integrator_missing(scene, integrator)
    if why is not None:
        out.skipped.append(("cache.threads", why))
        return
    cores = os.cpu_count() or 1
    # a quarter of the candidates' samples: the one-thread renders are the group's longest
    candidate = with_overrides(scene, integrator=integrator, spp=max(1, sizes.candidate_spp // 4))
    prep = PreparedScene(candidate)
    times, _ = timed_renders([Run(candidate, prep, n) for n in (1, cores)], repeat)
    speedup = times[0] / times[1]
    size = f"{scene.camera.width}x{scene.camera.height}"
    what = f"{integrator}, cache-studio {size}, {cores} threads; value = speedup / threads"
    record = Record("cache.threads", what, "the same render on 1 thread", speedup, speedup / cores, "per core")
    out.records.append(record)


def run_cache_bench(
    repeat: int,
    quick: bool,
    scenes: tuple[str, ...] = SCENES,
    integrators: dict[str, str] | None = None,
    threads: int = 0,
    mitsuba: bool = True,
    large: bool = False,
) -> CacheBench:
    """The group's measurements on `scenes` with the candidate `integrators` ({"biased": ...,
    "guided": ...}, default INTEGRATORS) and, with `mitsuba`, against Mitsuba 3
    (bench/cache_mitsuba.py), at QUICK's, LARGE's (`large`) or FULL's sizes; records that
    cannot be measured are listed in `skipped` with the reason."""
    integrators = dict(INTEGRATORS if integrators is None else integrators)
    threads = threads or os.cpu_count() or 1
    sizes = QUICK if quick else LARGE if large else FULL
    out = CacheBench()
    for name in scenes:
        t0, before = time.perf_counter(), len(out.records)
        _scene_records(name, sizes, repeat, threads, integrators, out)
        if len(out.records) > before:
            print(f"patina bench: cache: {name} measured in {time.perf_counter() - t0:.0f} s", file=sys.stderr)
    if "biased" in integrators:
        _threads_record(sizes, repeat, integrators["biased"], out)
    if mitsuba:
        why = mitsuba_missing()
        for name in scenes:
            t0 = time.perf_counter()
            found = why or vs_mitsuba_record(name, sizes, repeat, threads, list(integrators.values()))
            if isinstance(found, Record):
                out.records.append(found)
                seconds = time.perf_counter() - t0
                print(f"patina bench: cache: {name} against Mitsuba in {seconds:.0f} s", file=sys.stderr)
            else:
                out.skipped.append((f"cache.{name}.vs_mitsuba_llvm", found))
    return out


def mitsuba_missing() -> str | None:
    """Why Mitsuba 3's llvm_ad_rgb cannot render here (None: it can)."""
    try:
        import mitsuba as _  # noqa: F401
    except ImportError:
        return "Mitsuba 3 is not installed"
    if not llvm_variant_works():
        return "Mitsuba's llvm_ad_rgb does not run here (bench/render.py, llvm_variant_works)"
    return None


def bench_cache(repeat: int, quick: bool) -> list[Record]:
    """The `cache` group (GROUPS in bench/run.py), at most MAX_REPEAT repeats: the records, each
    skipped one named on stderr."""
    repeat = min(repeat, MAX_REPEAT)
    result = run_cache_bench(repeat, quick)
    threads = os.cpu_count() or 1
    result.records += [aa_adaptive_record(name, repeat, threads, quick) for name in SCENES]
    return _reported(result)


def bench_cache_large(repeat: int, quick: bool) -> list[Record]:
    """The `cache` group at LARGE's sizes (`patina bench --large`; with `quick`, QUICK's, for a
    smoke test of the names), every record named with LARGE_SUFFIX."""
    result = run_cache_bench(min(repeat, MAX_REPEAT), quick, large=True)
    result.records = [dataclasses.replace(r, name=r.name + LARGE_SUFFIX) for r in result.records]
    result.skipped = [(name + LARGE_SUFFIX, why) for name, why in result.skipped]
    return _reported(result)


def _reported(result: CacheBench) -> list[Record]:
    """The records; each skipped one named on stderr with the reason."""
    for name, why in result.skipped:
        print(f"patina bench: {name} skipped: {why}", file=sys.stderr)
    return result.records
