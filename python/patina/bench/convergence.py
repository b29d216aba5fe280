"""Convergence measures for the renderer benchmarks (bench/cache.py, bench/cache_mitsuba.py):
relMSE against a converged reference with the top 0.1 % of pixel errors discarded, error
against time on log-log axes, references rendered once and kept on disk outside the
repository, and render times by the job's own clock."""

from __future__ import annotations

import hashlib
import json
import math
import os
import statistics
from dataclasses import dataclass

import numpy as np

from patina.atomic import atomic_output
from patina.errors import FormatError
from patina.native import _core
from patina.render.run import PreparedScene, render
from patina.scene.reading import with_overrides
from patina.scene.types import Scene
from patina.scene.writing import scene_to_json

RELMSE_EPSILON = 0.01  # added to the squared reference pixel (image mean 1): dark pixels do not explode
DISCARD_FRACTION = 0.001  # the largest pixel errors left out of relMSE
REFERENCE_SEEDS = (1001, 1002)  # the two halves of a reference


@dataclass(frozen=True)
class Sizes:
    width: int  # pixels; the height keeps the scene's aspect
    reference_spp: int  # both halves together
    ladder: tuple[int, ...]  # path's spp levels
    candidate_spp: int  # the cache integrators' spp


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
    """y at x, piecewise linear in (log x, log y) through the points (xs increasing). Beyond
    the points, and along a segment where the error does not fall (noise on a short ladder),
    the slope is -1, Monte Carlo's rate (error x time constant for an unbiased estimator):
    the end segments' own slopes are the noisiest of all (a firefly-carried error falls
    slower than it should between two levels and, extended, put a record at 190 one run
    and 350 the next)."""
    lx, ly = [math.log(v) for v in xs], [math.log(v) for v in ys]
    t = math.log(x)
    if t <= lx[0] or t >= lx[-1]:
        i = 0 if t <= lx[0] else len(lx) - 1
        return math.exp(ly[i] - (t - lx[i]))
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


# --- renders ----------------------------------------------------------------------------------


def sized(scene: Scene, width: int) -> Scene:
    aspect = scene.camera.width / scene.camera.height
    return with_overrides(scene, width=width, height=max(1, round(width / aspect)))


@dataclass
class Run:
    scene: Scene
    prep: PreparedScene
    threads: int


def timed_renders(runs: list[Run], repeat: int) -> tuple[list[float], list[list[np.ndarray]]]:
    """Each run rendered 1 + `repeat` times with seeds scene seed + 0, 1, ..., interleaved so
    a burst of load hits all alike: its median time over the last `repeat` renders (the
    first warms up) and all its images (for the median error over seeds: median_relmse).
    The time is the render job's own clock (RenderResult.seconds: from the workers' start
    to the last tile done), which counts all the integrator does in its tiles and not the
    50 ms progress polling of `render`."""
    images: list[list[np.ndarray]] = [[] for _ in runs]
    samples: list[list[float]] = [[] for _ in runs]
    for k in range(1 + max(repeat, 0)):
        for i, r in enumerate(runs):
            scene = with_overrides(r.scene, seed=r.scene.render.seed + k)
            result = render(scene, threads=r.threads, prepared=r.prep)
            images[i].append(np.asarray(result.rgb, np.float64))
            if k > 0 or repeat <= 0:
                samples[i].append(result.seconds)
    return [statistics.median(s) for s in samples], images


def median_relmse(images: list[np.ndarray], reference: np.ndarray, reference_error: float = 0.0) -> float:
    """The median over independent renders (seeds) of their relMSE: one render's error swings
    with the few pixels a firefly lands in, the median over seeds does not."""
    return statistics.median(relmse(img, reference, reference_error) for img in images)


def integrator_missing(scene: Scene, name: str) -> str | None:
    """Why this build cannot render `scene` with integrator `name` (None: it can)."""
    try:
        with_overrides(scene, integrator=name)
    except FormatError as e:
        return f"integrator '{name}' is not in this build ({e.problem})"
    return None
