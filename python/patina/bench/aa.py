"""The `aa` benchmark group (issue 12, docs/antialiasing.md): the adaptive antialiasing on
the bundled test scenes (materials/scenes/aa-*.json) against a reference of 1024 stratified
samples a pixel with the same box filter.

Stratified samples come from the uniform sampler on a k-times finer image (one jittered
sample a sub-pixel) box-averaged down: k x k strata a pixel, jittered within each; the
reference is 8 x 8 strata of 16 samples each (1024). Per scene:

- `aa.<scene>.rays_per_pixel`: the adaptive sampler's camera rays a pixel (value and ratio);
- `aa.<scene>.vs_random25`: RMSE of 25 random rays a pixel over the adaptive sampler's (> 1:
  adaptive is better), and `aa.<scene>.flip_vs_random25` the same with mean FLIP on the
  tone-mapped images (flip-evaluator from PyPI; the record is left out without it);
- `aa.<scene>.vs_stratified16`: the same against 16 stratified rays;
- `aa.<scene>.vs_equal_rays`: stratified sampling with k x k rays, k the rounded square root
  of the adaptive sampler's rays a pixel (at least 1), over adaptive;
- `aa.<scene>.time_vs_random25`: the 25-ray render's time over the adaptive render's, medians
  of `repeat` interleaved runs on the scene prepared once (the tree is built once, as a
  preview re-rendering a scene does), each the render job's own time.

The full run renders the scenes at twice their own size (512 x 384: the size users preview at,
`make demo`'s, where an edge crosses as few pixels as it does in the images the thesis
measured), `--quick` at their own size (256 x 192); $PATINA_BENCH_AA_SCALE multiplies both.
The reference costs 1024 rays a pixel (2 to 5 minutes a scene at 512 x 384 on a loaded
machine), so it is kept on disk outside the repository (`reference_dir()`), under a key of
the scene, the size and a checksum of a small uniform render of it: a change to the scene or
to what the renderer computes makes a new one."""

from __future__ import annotations

import dataclasses
import functools
import glob
import hashlib
import math
import os
import statistics
import sys

import numpy as np

from patina.bench.flip import mean_flip
from patina.bench.records import Record
from patina.bundled import materials_path
from patina.render.outputs import auto_exposure
from patina.render.prepare import PreparedScene
from patina.render.run import render
from patina.scene.reading import load_scene, with_overrides
from patina.scene.types import Scene

REFERENCE_STRATA = 8  # 8 x 8 strata ...
REFERENCE_PER_STRATUM = 16  # ... of 16 random samples: 1024 a pixel
# times the scenes' own size (256 x 192): the full run at a preview's 512 x 384 (issue 31), --quick at 256 x 192
FULL_FACTOR, QUICK_FACTOR = 2.0, 1.0
SCALE_VARIABLE = "PATINA_BENCH_AA_SCALE"  # multiplies both, for another size


def _scale() -> float:
    text = os.environ.get(SCALE_VARIABLE, "1")
    try:
        scale = float(text)
    except ValueError:
        scale = float("nan")
    if not (math.isfinite(scale) and scale > 0):
        print(f"patina bench: {SCALE_VARIABLE} must be a number > 0, got {text!r}", file=sys.stderr)
        sys.exit(2)
    return scale


def _scenes() -> list[str]:
    return sorted(glob.glob(os.path.join(materials_path("scenes"), "aa-*.json")))


def _stratified(scene: Scene, k: int, per_stratum: int = 1) -> np.ndarray:
    """k x k jittered strata a pixel: the uniform sampler on a k-times finer image, box-averaged."""
    w, h = scene.camera.width, scene.camera.height
    fine = with_overrides(scene, spp=per_stratum, width=k * w, height=k * h)
    rgb = render(fine, aa="uniform").rgb.astype(np.float64)
    return rgb.reshape(h, k, w, k, 3).mean(axis=(1, 3))


def reference_dir() -> str:
    """Where the references are kept: $PATINA_BENCH_CACHE, else $XDG_CACHE_HOME/patina/aa-reference
    (~/.cache/patina/aa-reference)."""
    root = os.environ.get("PATINA_BENCH_CACHE")
    if not root:
        root = os.path.join(os.environ.get("XDG_CACHE_HOME") or os.path.expanduser("~/.cache"), "patina")
    return os.path.join(root, "aa-reference")


def reference(scene: Scene) -> np.ndarray:
    """The 1024-sample reference, from the disk cache when its key matches."""
    w, h = scene.camera.width, scene.camera.height
    # what the renderer makes of this scene: a small uniform render, so a changed renderer
    # (or a changed mesh file, which the scene's repr does not show) makes a new reference
    probe = render(with_overrides(scene, spp=2, width=32, height=24), aa="uniform").rgb
    key = hashlib.sha256()
    key.update(repr(dataclasses.replace(scene, path=os.path.basename(scene.path))).encode())
    key.update(f"{REFERENCE_STRATA}x{REFERENCE_PER_STRATUM}".encode())
    key.update(np.ascontiguousarray(probe, np.float32).tobytes())
    path = os.path.join(reference_dir(), f"{os.path.basename(scene.path)}-{w}x{h}-{key.hexdigest()[:16]}.npy")
    try:
        return np.load(path)
    except (OSError, ValueError, EOFError):  # none yet (or unreadable): made anew
        pass
    ref = _stratified(scene, REFERENCE_STRATA, REFERENCE_PER_STRATUM)
    try:
        os.makedirs(os.path.dirname(path), exist_ok=True)
        tmp = f"{path}.{os.getpid()}.tmp"
        with open(tmp, "wb") as f:
            np.save(f, ref)
        os.replace(tmp, path)
    except OSError as e:
        print(f"patina bench: cannot keep the aa reference in {path}: {e}", file=sys.stderr)
    return ref


def _rmse(a: np.ndarray, ref: np.ndarray) -> float:
    return float(np.sqrt(np.mean((np.asarray(a, np.float64) - ref) ** 2)))


def bench_aa(repeat: int, quick: bool) -> list[Record]:
    """Every figure but the time ratio is an error of one render (the scenes render the
    same image every time); the time ratio is the median of `repeat` runs of each."""
    records: list[Record] = []
    files = _scenes()
    if not files:
        print("patina bench: no materials/scenes/aa-*.json: no aa records", file=sys.stderr)
        return records
    warned = False
    for path in files:
        name = os.path.splitext(os.path.basename(path))[0].removeprefix("aa-")
        scene = load_scene(path)
        factor = _scale() * (QUICK_FACTOR if quick else FULL_FACTOR)
        scene = with_overrides(
            scene,
            spp=1,
            width=max(8, round(scene.camera.width * factor)),
            height=max(8, round(scene.camera.height * factor)),
        )
        ref = reference(scene)
        prep = PreparedScene(scene)
        scene25 = with_overrides(scene, spp=25)
        runs = [functools.partial(render, scene, aa="adaptive", prepared=prep)]
        # random: independent numbers (the uniform sampler's default is Sobol, stratified)
        runs.append(functools.partial(render, scene25, aa="uniform", prepared=prep, sampler="independent"))
        adaptive, random25 = (f() for f in runs)  # also the warm-up
        # the renders' own time (RenderResult.seconds: from the start of the job, the adaptive
        # sampler's geometric pre-pass included, to its last tile), not the call's: the call
        # waits on a progress poll of 0.1 s, which would hide a render of 40 ms
        times: list[list[float]] = [[], []]
        for _ in range(max(1, repeat)):
            for t, f in zip(times, runs):
                t.append(f().seconds)
        t_adaptive, t_random25 = (statistics.median(t) for t in times)
        pixels = scene.camera.width * scene.camera.height
        rpp = adaptive.camera_rays / pixels
        k_equal = max(1, round(math.sqrt(rpp)))
        err = _rmse(adaptive.rgb, ref)
        err_random25 = _rmse(random25.rgb, ref)
        err_strat16 = _rmse(_stratified(scene, 4), ref)
        err_equal = (
            _rmse(_stratified(scene, k_equal), ref) if k_equal > 1 else _rmse(render(scene, aa="uniform").rgb, ref)
        )
        tiny = 1e-12  # a perfect adaptive image would divide by zero
        base = f"aa.{name}"
        records += [
            Record(f"{base}.rays_per_pixel", "adaptive", "-", rpp, rpp, "rays/pixel"),
            Record(f"{base}.vs_random25", "adaptive", "random 25", err_random25 / max(err, tiny), err, "RMSE"),
            Record(f"{base}.vs_stratified16", "adaptive", "stratified 16", err_strat16 / max(err, tiny), err, "RMSE"),
            Record(
                f"{base}.vs_equal_rays",
                "adaptive",
                f"stratified {k_equal * k_equal}",
                err_equal / max(err, tiny),
                err,
                "RMSE",
            ),
            Record(f"{base}.time_vs_random25", "adaptive", "random 25", t_random25 / t_adaptive, t_adaptive, "s"),
        ]
        stops = auto_exposure(ref)
        flip, flip_random25 = mean_flip(adaptive.rgb, ref, stops), mean_flip(random25.rgb, ref, stops)
        if flip is None or flip_random25 is None:
            if not warned:
                print("patina bench: flip-evaluator is not installed: no aa.*.flip_vs_random25", file=sys.stderr)
                warned = True
        else:
            records.append(
                Record(
                    f"{base}.flip_vs_random25", "adaptive", "random 25", flip_random25 / max(flip, tiny), flip, "FLIP"
                )
            )
    return records
