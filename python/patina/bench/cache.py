"""`patina bench --only cache` (issue 13, item 6): the radiance-cache integrators against the
path tracer on the bundled scenes where secondary light matters (materials/scenes/cache-*.json).

Per scene, at a small size (64 pixels wide; `--quick` 16), all renders on every core:

1. A converged reference, rendered once by `path` as two halves with different seeds and
   kept on disk outside the repository (`reference_dir()`, keyed by a hash of the scene
   file, the settings and Patina's version): their mean is the reference, a quarter of
   their squared difference its own error, subtracted from every error measured.
2. The error of an image: relMSE, per pixel (x - r)^2 / (r^2 + 0.01) averaged over RGB with
   both images divided by the reference's mean, the top 0.1 % of pixel errors discarded
   (as path-guiding evaluations do, so a few fireflies do not decide a record).
3. `path` at a ladder of spp: the median time of each and its error give error-versus-time,
   interpolated piecewise linearly on log-log axes (extrapolated along the end segments).
4. Records (docs/bench.md): `cache.<scene>.biased_vs_path` (the time `path` needs for the
   error `cache` reaches, over the time `cache` takes), `cache.<scene>.guided_vs_path` (the
   same for `cache-guided`) and `cache.<scene>.guided_equal_time` (path's error at the time
   `cache-guided` takes, over `cache-guided`'s), `cache.<scene>.bias` (the relative bias of
   `cache`'s image mean), `cache.threads` (`cache` on every core against one thread).

A record whose integrator this build does not have is skipped with the reason on stderr;
`run_cache_bench(..., integrators=...)` runs the same measurements with other integrators
(the tests use `path` for both, which the harness then must find equal to itself).
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import statistics
import sys
import time
from dataclasses import dataclass, field

import numpy as np

from patina.atomic import atomic_output
from patina.bench.records import Record
from patina.bundled import materials_path
from patina.errors import FormatError
from patina.native import _core
from patina.render.run import PreparedScene, render
from patina.scene.reading import load_scene, with_overrides
from patina.scene.types import Scene
from patina.scene.writing import scene_to_json

SCENES = ("cache-room", "cache-studio", "cache-ies-interior")
RELMSE_EPSILON = 0.01  # added to the squared reference pixel (image mean 1): dark pixels do not explode
DISCARD_FRACTION = 0.001  # the largest pixel errors left out of relMSE
REFERENCE_SEEDS = (1001, 1002)  # the two halves of a reference
INTEGRATORS = {"biased": "cache", "guided": "cache-guided"}


@dataclass(frozen=True)
class Sizes:
    width: int  # pixels; the height keeps the scene's aspect
    reference_spp: int  # both halves together
    ladder: tuple[int, ...]  # path's spp levels
    candidate_spp: int  # the cache integrators' spp


FULL = Sizes(64, 2048, (8, 32, 128), 16)
QUICK = Sizes(16, 64, (2, 8), 2)


def reference_dir() -> str:
    """Where references are kept: $PATINA_BENCH_CACHE, else $XDG_CACHE_HOME/patina/bench
    (~/.cache/patina/bench). Delete it to render them again."""
    given = os.environ.get("PATINA_BENCH_CACHE")
    if given:
        return given
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return os.path.join(base, "patina", "bench")


# --- error measures ------------------------------------------------------------------------


def pixel_relmse(image: np.ndarray, reference: np.ndarray) -> np.ndarray:
    """Per pixel: (x - r)^2 / (r^2 + RELMSE_EPSILON), averaged over RGB, both images divided
    by the reference's mean (so the measure does not depend on the scene's brightness)."""
    scale = float(reference.mean())
    if not scale > 0:
        raise ValueError("the reference image is black")
    x, r = image / scale, reference / scale
    return ((x - r) ** 2 / (r**2 + RELMSE_EPSILON)).mean(axis=-1).ravel()


def relmse(image: np.ndarray, reference: np.ndarray, reference_error: float = 0.0) -> float:
    """relMSE with the top DISCARD_FRACTION of pixel errors discarded, less the reference's own
    error (`reference_error`, the same measure of the reference against the truth), at least
    a millionth of the raw value (a candidate cannot be better than perfect)."""
    per_pixel = np.sort(pixel_relmse(image, reference))
    keep = per_pixel.size - int(per_pixel.size * DISCARD_FRACTION)
    raw = float(per_pixel[:keep].mean())
    return max(raw - reference_error, raw * 1e-6)


def _log_interpolate(x: float, xs: list[float], ys: list[float]) -> float:
    """y at x, piecewise linear in (log x, log y) through the points (xs increasing), the end
    segments extended beyond them. A segment along which the error does not fall (noise on
    a short ladder) is taken with slope -1 instead, as Monte Carlo error falls with time."""
    lx, ly = [math.log(v) for v in xs], [math.log(v) for v in ys]
    t = math.log(x)
    i = 0
    while i < len(lx) - 2 and t > lx[i + 1]:
        i += 1
    slope = (ly[i + 1] - ly[i]) / (lx[i + 1] - lx[i]) if lx[i + 1] != lx[i] else -1.0
    if not slope < 0:
        slope = -1.0
    return math.exp(ly[i] + slope * (t - lx[i]))


@dataclass
class ErrorCurve:
    """A renderer's error against time: (seconds, relMSE) at each level, by increasing time."""

    seconds: list[float]
    errors: list[float]

    def __post_init__(self) -> None:
        order = sorted(range(len(self.seconds)), key=lambda i: self.seconds[i])
        self.seconds = [self.seconds[i] for i in order]
        self.errors = [self.errors[i] for i in order]
        if len(self.seconds) < 2:
            raise ValueError("an error curve needs at least two levels")

    def seconds_for(self, error: float) -> float:
        """The time at which the error is `error` (interpolated on log-log axes). The curve is
        monotone in each segment used, so it is inverted as error -> time."""
        # invert: time as a function of error, points by increasing error
        pairs = sorted(zip(self.errors, self.seconds))
        return _log_interpolate(error, [e for e, _ in pairs], [s for _, s in pairs])

    def error_at(self, seconds: float) -> float:
        return _log_interpolate(seconds, self.seconds, self.errors)


# --- references ----------------------------------------------------------------------------


@dataclass
class Reference:
    image: np.ndarray  # (H, W, 3) float64, the mean of the halves
    error: float  # its own relMSE against the truth, estimated from the halves
    path: str  # the file it is kept in
    rendered: bool  # rendered by this call (not read from disk)


def reference_key(scene_file: str, scene: Scene, spp: int) -> str:
    """The reference's file name: a hash of the scene file's bytes, the scene as rendered
    (size, settings, every material and light: the canonical JSON), the spp, the halves'
    seeds and Patina's version."""
    h = hashlib.sha256()
    with open(scene_file, "rb") as f:
        h.update(f.read())
    settings = {"scene": scene_to_json(scene), "spp": spp, "seeds": REFERENCE_SEEDS, "version": _core.__version__}
    h.update(json.dumps(settings, sort_keys=True, default=str).encode())
    name = os.path.splitext(os.path.basename(scene_file))[0]
    return f"{name}-{scene.camera.width}x{scene.camera.height}-{spp}spp-{h.hexdigest()[:16]}.npz"


def reference(scene_file: str, scene: Scene, spp: int, threads: int = 0, folder: str | None = None) -> Reference:
    """The converged `path` reference of `scene` at `spp` samples a pixel, from `folder`
    (default `reference_dir()`) when an earlier run left it there, else rendered and kept."""
    folder = folder or reference_dir()
    path = os.path.join(folder, reference_key(scene_file, scene, spp))
    halves = _read_halves(path, (scene.camera.height, scene.camera.width, 3))
    rendered = halves is None
    if halves is None:
        base = with_overrides(scene, integrator="path", spp=max(spp // 2, 1))
        prep = PreparedScene(base)
        halves = tuple(
            render(with_overrides(base, seed=seed), threads=threads, prepared=prep).rgb for seed in REFERENCE_SEEDS
        )
        os.makedirs(folder, exist_ok=True)
        a, b = (np.asarray(x, np.float32) for x in halves)

        def write(tmp: str) -> None:
            with open(tmp, "wb") as f:  # a file object: np.savez would add .npz to a name
                np.savez(f, a=a, b=b)

        atomic_output(path, write)
    a, b = (np.asarray(x, np.float64) for x in halves)
    image = (a + b) / 2
    # the halves' errors are independent of variance s^2 each: (a - b)^2 / 4 estimates s^2 / 2,
    # the mean's error variance; and a - image is exactly (a - b) / 2
    return Reference(image, relmse(a, image), path, rendered)


def _read_halves(path: str, shape: tuple[int, int, int]) -> tuple[np.ndarray, np.ndarray] | None:
    if not os.path.isfile(path):
        return None
    try:
        with np.load(path) as z:
            a, b = z["a"], z["b"]
    except (OSError, KeyError, ValueError):
        return None  # damaged: rendered again and replaced
    if a.shape != shape or b.shape != shape or not (np.isfinite(a).all() and np.isfinite(b).all()):
        return None
    return a, b


# --- the measurements ----------------------------------------------------------------------


def integrator_missing(scene: Scene, name: str) -> str | None:
    """Why this build cannot render `scene` with integrator `name` (None: it can)."""
    try:
        with_overrides(scene, integrator=name)
    except FormatError as e:
        return f"integrator '{name}' is not in this build ({e.problem})"
    return None


@dataclass
class CacheBench:
    records: list[Record] = field(default_factory=list)
    skipped: list[tuple[str, str]] = field(default_factory=list)  # (record name, why)


def _sized(scene: Scene, width: int) -> Scene:
    aspect = scene.camera.width / scene.camera.height
    return with_overrides(scene, width=width, height=max(1, round(width / aspect)))


@dataclass
class _Run:
    scene: Scene
    prep: PreparedScene
    threads: int


def timed_renders(runs: list[_Run], repeat: int) -> tuple[list[float], list[np.ndarray]]:
    """Each run's image (from a first, untimed render) and its median time over `repeat`
    renders, interleaved so a burst of load hits all alike. The time is the render job's own
    clock (RenderResult.seconds: from the workers' start to the last tile done), which counts
    all the integrator does in its tiles and not the 50 ms progress polling of `render`."""
    images = [np.asarray(render(r.scene, threads=r.threads, prepared=r.prep).rgb, np.float64) for r in runs]
    samples: list[list[float]] = [[] for _ in runs]
    for _ in range(repeat):
        for i, r in enumerate(runs):
            samples[i].append(render(r.scene, threads=r.threads, prepared=r.prep).seconds)
    return [statistics.median(s) for s in samples], images


def _scene_records(
    name: str, sizes: Sizes, repeat: int, threads: int, integrators: dict[str, str], out: CacheBench
) -> None:
    scene_file = materials_path("scenes", f"{name}.json")
    scene = _sized(load_scene(scene_file), sizes.width)
    label = f"{name} {scene.camera.width}x{scene.camera.height}, {threads} threads"
    candidates: list[_Run] = []
    roles: dict[str, int] = {}  # candidate role -> its index after the ladder
    for role, integrator in integrators.items():
        why = integrator_missing(scene, integrator)
        if why is not None:
            names = ["biased_vs_path", "bias"] if role == "biased" else ["guided_vs_path", "guided_equal_time"]
            out.skipped += [(f"cache.{name}.{n}", why) for n in names]
            continue
        candidate = with_overrides(scene, integrator=integrator, spp=sizes.candidate_spp)
        roles[role] = len(sizes.ladder) + len(candidates)
        candidates.append(_Run(candidate, PreparedScene(candidate), threads))
    if not candidates:
        return  # nothing to compare the path tracer with: no reference, no ladder
    ref = reference(scene_file, scene, sizes.reference_spp, threads)
    path_scene = with_overrides(scene, integrator="path")
    path_prep = PreparedScene(path_scene)
    ladder = [_Run(with_overrides(path_scene, spp=n), path_prep, threads) for n in sizes.ladder]
    times, images = timed_renders(ladder + candidates, repeat)
    errors = [relmse(img, ref.image, ref.error) for img in images]
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
            ratio = float(images[i].mean()) / float(ref.image.mean())
            bias_what = f"{what}; value = (mean - reference mean) / reference mean"
            bias_base = f"the reference's image mean ({sizes.reference_spp} spp of path)"
            out.records.append(Record(f"cache.{name}.bias", bias_what, bias_base, ratio, 100 * (ratio - 1), "%"))


def _threads_record(sizes: Sizes, repeat: int, integrator: str, out: CacheBench) -> None:
    """`integrator` on the studio scene, on every core against one thread."""
    scene_file = materials_path("scenes", "cache-studio.json")
    scene = _sized(load_scene(scene_file), sizes.width)
    why = integrator_missing(scene, integrator)
    if why is not None:
        out.skipped.append(("cache.threads", why))
        return
    cores = os.cpu_count() or 1
    candidate = with_overrides(scene, integrator=integrator, spp=sizes.candidate_spp)
    prep = PreparedScene(candidate)
    times, _ = timed_renders([_Run(candidate, prep, n) for n in (1, cores)], repeat)
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
) -> CacheBench:
    """The group's measurements on `scenes` with the candidate `integrators` ({"biased": ...,
    "guided": ...}, default INTEGRATORS); records whose integrator is missing are listed in
    `skipped` with the reason."""
    integrators = dict(INTEGRATORS if integrators is None else integrators)
    threads = threads or os.cpu_count() or 1
    sizes = QUICK if quick else FULL
    out = CacheBench()
    for name in scenes:
        t0 = time.perf_counter()
        _scene_records(name, sizes, repeat, threads, integrators, out)
        print(f"patina bench: cache: {name} measured in {time.perf_counter() - t0:.0f} s", file=sys.stderr)
    if "biased" in integrators:
        _threads_record(sizes, repeat, integrators["biased"], out)
    return out


def bench_cache(repeat: int, quick: bool) -> list[Record]:
    """The `cache` group (GROUPS in bench/run.py): the records, each skipped one named on stderr."""
    result = run_cache_bench(repeat, quick)
    for name, why in result.skipped:
        print(f"patina bench: {name} skipped: {why}", file=sys.stderr)
    return result.records
