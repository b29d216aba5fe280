"""`cache.<scene>.vs_mitsuba_llvm` (issue 13, item 6): Patina's best integrator against
Mitsuba 3's path tracer (llvm_ad_rgb) at equal relMSE and thread count, on the cache
scenes with their tabulated materials replaced, in both renderers, by fitted analytic
counterparts (Mitsuba reads no Patina table).

The counterpart (`analytic_counterpart`): each `table` or `fit` material becomes the
Lambert fit of its BRDF -- the albedo the renderer reports for it (directional, light
from 30 degrees, `render.materials.directional_albedo`) times its scale and tint, at most 1
-- and a car paint keeps its coat over the Lambert fit of its base (Mitsuba's `plastic`,
scene/mitsuba.py); a luminaire becomes Mitsuba's `spot` projecting its candela table as a
texture (scene/mitsuba.py). A scene with a light Mitsuba has no equivalent for (a luminaire lit
to its horizon, a type B one) is skipped with the reason.

Each renderer is measured against its own converged reference of the counterpart scene
(Patina's `path` and Mitsuba's `path`, each as two halves kept on disk as bench/cache.py
keeps its references), since the coat's two models need not agree to the last percent:
error is relMSE as in bench/cache.py, against time through a ladder of spp on log-log
axes. The target is the relMSE Patina's `path` reaches at the ladder's middle level; each
renderer's time for it is read off its own curve; the ratio is Mitsuba's time over the
fastest Patina integrator's (`path`, and `cache` / `cache-guided` where this build has
them, each through its error at a quarter of and at the cache integrators' spp).
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import os
import time

import numpy as np

from patina.atomic import atomic_output
from patina.bench.convergence import (
    REFERENCE_SEEDS,
    ErrorCurve,
    Run,
    Sizes,
    integrator_missing,
    median_relmse,
    reference,
    reference_dir,
    relmse,
    sized,
    timed_renders,
)
from patina.bench.records import Record
from patina.bundled import materials_path
from patina.fitting import read_fit
from patina.render.materials import directional_albedo
from patina.render.prepare import shape_mesh
from patina.render.run import PreparedScene
from patina.scene.mitsuba import MitsubaConversionError, to_mitsuba
from patina.scene.reading import load_scene, with_overrides
from patina.scene.types import (
    BallShape,
    CarpaintMaterial,
    FitMaterial,
    LambertMaterial,
    Material,
    MeshShape,
    PanelShape,
    Scene,
    TableMaterial,
)
from patina.scene.writing import scene_to_json
from patina.table.formats import load_brdf
from patina.table.spectral import as_linear_srgb

VARIANT = "llvm_ad_rgb"


def lambert_fit(m: TableMaterial | FitMaterial, two_sided: bool) -> LambertMaterial:
    """The Lambert fit of a table or fit material: its directional albedo times scale and tint."""
    evaluate = as_linear_srgb(load_brdf(m.file)).eval if isinstance(m, TableMaterial) else read_fit(m.file).eval
    albedo = np.asarray(directional_albedo(evaluate), np.float64) * m.scale * np.asarray(m.tint, np.float64)
    rgb = tuple(float(min(max(a, 0.0), 1.0)) for a in albedo)
    return LambertMaterial(rgb, two_sided)  # type: ignore[arg-type]


def _counterpart(m: Material) -> Material:
    if isinstance(m, (TableMaterial, FitMaterial)):
        return lambert_fit(m, m.two_sided)
    if isinstance(m, CarpaintMaterial) and isinstance(m.base, (TableMaterial, FitMaterial)):
        return dataclasses.replace(m, base=lambert_fit(m.base, False))
    return m


def analytic_counterpart(scene: Scene) -> Scene:
    """The scene with every tabulated or fitted BRDF replaced by its Lambert fit."""
    return dataclasses.replace(scene, materials={k: _counterpart(m) for k, m in scene.materials.items()})


def mitsuba_dict(scene: Scene, variant: str = VARIANT) -> dict:
    """The scene for Mitsuba (shapes without an analytic form as meshes of their arrays)."""
    meshes = {i: shape_mesh(s) for i, s in enumerate(scene.shapes) if isinstance(s, (BallShape, PanelShape, MeshShape))}
    return to_mitsuba(scene, meshes, variant=variant)


class _Mitsuba:
    """Mitsuba's renders of one scene on `threads` threads: (spp, seed) -> (image, seconds)."""

    def __init__(self, scene: Scene, threads: int) -> None:
        import drjit as dr
        import mitsuba as mi

        self.mi = mi
        dr.set_thread_count(threads)
        self.loaded = mi.load_dict(mitsuba_dict(scene))

    def render(self, spp: int, seed: int = 0) -> tuple[np.ndarray, float]:
        self.mi.set_variant(VARIANT)
        t0 = time.perf_counter()
        image = np.asarray(self.mi.render(self.loaded, spp=spp, seed=seed), np.float64)  # evaluated here
        return image, time.perf_counter() - t0


def _mitsuba_reference(scene_file: str, scene: Scene, spp: int, renderer: _Mitsuba) -> tuple[np.ndarray, float]:
    """Mitsuba's converged image of the scene and its own relMSE, kept on disk like Patina's."""
    import mitsuba as mi

    h = hashlib.sha256()
    with open(scene_file, "rb") as f:
        h.update(f.read())
    key = {"scene": scene_to_json(scene), "spp": spp, "mitsuba": mi.__version__, "variant": VARIANT}
    h.update(json.dumps(key, sort_keys=True, default=str).encode())
    name = os.path.splitext(os.path.basename(scene_file))[0]
    path = os.path.join(reference_dir(), f"{name}-mitsuba-{spp}spp-{h.hexdigest()[:16]}.npz")
    shape = (scene.camera.height, scene.camera.width, 3)
    halves = None
    if os.path.isfile(path):
        try:
            with np.load(path) as z:
                halves = (z["a"], z["b"]) if z["a"].shape == shape == z["b"].shape else None
        except (OSError, KeyError, ValueError):
            halves = None
    if halves is None:
        halves = tuple(np.asarray(renderer.render(spp // 2, seed)[0], np.float32) for seed in REFERENCE_SEEDS)
        os.makedirs(reference_dir(), exist_ok=True)

        def write(tmp: str) -> None:
            with open(tmp, "wb") as f:
                np.savez(f, a=halves[0], b=halves[1])

        atomic_output(path, write)
    a, b = (np.asarray(x, np.float64) for x in halves)
    image = (a + b) / 2
    return image, relmse(a, image)


def _mitsuba_curve(renderer: _Mitsuba, levels: tuple[int, ...], repeat: int, ref: np.ndarray, ref_error: float):
    renderer.render(levels[0])  # the JIT compiles its kernels on the first render: not timed
    seconds, errors = [], []
    for n in levels:
        runs = [renderer.render(n, seed) for seed in range(max(repeat, 1))]
        seconds.append(float(np.median([t for _, t in runs])))
        errors.append(median_relmse([image for image, _ in runs], ref, ref_error))
    return ErrorCurve(seconds, errors)


def vs_mitsuba_record(name: str, sizes: Sizes, repeat: int, threads: int, integrators: list[str]) -> Record | str:
    """`cache.<name>.vs_mitsuba_llvm` with Patina's `path` and those of `integrators` this
    build has; or why it cannot be measured."""
    record = f"cache.{name}.vs_mitsuba_llvm"
    scene_file = materials_path("scenes", f"{name}.json")
    scene = analytic_counterpart(sized(load_scene(scene_file), sizes.width))
    try:
        mitsuba_dict(scene, "scalar_rgb")  # what does not convert is found before the JIT starts
    except MitsubaConversionError as e:
        return f"no Mitsuba 3 equivalent: {e}"
    renderer = _Mitsuba(scene, threads)
    ref = reference(scene_file, scene, sizes.reference_spp, threads)
    # the cache integrators at a quarter of and at their own spp: at path's top level (128)
    # one render of `cache` took minutes
    cache_levels = (max(1, sizes.candidate_spp // 4), sizes.candidate_spp)
    patina: dict[str, ErrorCurve] = {}
    for integrator in ["path", *(i for i in integrators if integrator_missing(scene, i) is None)]:
        if integrator in patina:
            continue
        s = with_overrides(scene, integrator=integrator)
        prep = PreparedScene(s)
        levels = sizes.ladder if integrator == "path" else cache_levels
        times, images = timed_renders([Run(with_overrides(s, spp=n), prep, threads) for n in levels], repeat)
        patina[integrator] = ErrorCurve(times, [median_relmse(imgs, ref.image, ref.error) for imgs in images])
    target = _error_at_spp(patina["path"], sizes.ladder, sizes.ladder[len(sizes.ladder) // 2])
    best, best_time = min(((k, c.seconds_for(target)) for k, c in patina.items()), key=lambda kv: kv[1])
    m_ref, m_error = _mitsuba_reference(scene_file, scene, sizes.reference_spp, renderer)
    mitsuba = _mitsuba_curve(renderer, sizes.ladder, repeat, m_ref, m_error)
    mitsuba_time = mitsuba.seconds_for(target)
    size = f"{scene.camera.width}x{scene.camera.height}"
    what = f"Patina {best}, {name} {size} (Lambert fits for its tables), {threads} threads: {best_time:.2f} s "
    what += f"to relMSE {target:.3g} (each against its own {sizes.reference_spp}-spp reference)"
    baseline = f"Mitsuba 3 {VARIANT} path, same scene and threads: {mitsuba_time:.2f} s"
    # the two converged images should be the same scene's: their means say how near
    baseline += f" (its reference's mean / Patina's: {float(m_ref.mean()) / float(ref.image.mean()):.3f})"
    return Record(record, what, baseline, mitsuba_time / best_time, best_time, "s")


def _error_at_spp(curve: ErrorCurve, ladder: tuple[int, ...], spp: int) -> float:
    """The error path reached at `spp` of its ladder (the curve keeps levels by time, and
    path's time grows with spp, so the order is the ladder's)."""
    return curve.errors[sorted(ladder).index(spp)]
