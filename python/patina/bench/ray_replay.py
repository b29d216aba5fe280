"""The rays of a real render, recorded once and replayed by `patina bench --only trace`.

The recorder renders the preview scene (the preview ball, path traced) with the tracing
kernels' ray recorder on (`_core.start_ray_recording`), which keeps every ray the
integrator traces: camera and bounce rays (closest hit) and shadow rays (any hit), in the
batches and order the integrator traced them. They are saved under the cache directory
(`$PATINA_CACHE_DIR`, else `$XDG_CACHE_HOME/patina`, else `~/.cache/patina`), keyed by the
scene file's content and the render settings, so later runs replay the same rays without
rendering; they are never in git. The replay (bench/trace.py, `trace.replay.*`) traces them
against Patina's tracer and Embree.
"""

from __future__ import annotations

import hashlib
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from patina.atomic import atomic_output
from patina.bundled import materials_path
from patina.geometry.mesh import Mesh
from patina.native import _core
from patina.render.run import PreparedScene, path_depth
from patina.scene.reading import load_scene, with_overrides

RECORD_LIMIT = 4_000_000  # rays kept at most: a preview at the bench's size traces fewer


@dataclass
class RecordedRender:
    """A render's geometry and rays. Closest-hit rays: origins, directions (tmax inf). Shadow rays:
    origins, directions and tmax. tmin is 0 for both (what the integrator traces with)."""

    label: str
    mesh: Mesh
    closest: tuple[np.ndarray, np.ndarray]
    shadow: tuple[np.ndarray, np.ndarray, np.ndarray]


def cache_dir() -> Path:
    """Where recorded rays are kept: $PATINA_CACHE_DIR, else $XDG_CACHE_HOME/patina, else ~/.cache/patina."""
    if os.environ.get("PATINA_CACHE_DIR"):
        return Path(os.environ["PATINA_CACHE_DIR"])
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(Path.home(), ".cache")
    return Path(base) / "patina"


def _settings(quick: bool) -> tuple[int, int, int]:
    """Image width, height and spp of the recorded render."""
    return (64, 48, 2) if quick else (160, 120, 4)


def _record(scene_file: str, quick: bool) -> tuple[PreparedScene, dict[str, np.ndarray]]:
    w, h, spp = _settings(quick)
    scene = with_overrides(load_scene(scene_file), integrator="path", width=w, height=h, spp=spp)
    prep = PreparedScene(scene)
    options = _core.RenderOptions(spp=spp, max_depth=path_depth(scene), seed=scene.render.seed, threads=1)
    job = _core.RenderJob(prep.core, options)
    _core.start_ray_recording(RECORD_LIMIT)
    try:
        job.start()
        job.wait()
    finally:
        rays = _core.stop_ray_recording()
    return prep, rays


def recorded_preview(quick: bool) -> RecordedRender:
    """The preview ball's rays: from the cache, else recorded now (one small render) and cached."""
    scene_file = materials_path("scenes", "preview-ball.json")
    w, h, spp = _settings(quick)
    digest = hashlib.sha256(Path(scene_file).read_bytes()).hexdigest()[:16]
    path = cache_dir() / "bench" / f"rays-preview-ball-{w}x{h}-{spp}spp-{_core.__version__}-{digest}.npz"
    label = f"preview-ball {w}x{h}, {spp} spp, path"
    try:
        with np.load(path) as z:
            data = {k: z[k] for k in z.files}
    except (OSError, ValueError, KeyError):
        prep, rays = _record(scene_file, quick)
        tris = prep.accel.triangles
        data = {k: np.asarray(rays[k]) for k in ("origins", "directions", "tmin", "tmax", "any_hit")}
        data["triangles"] = tris
        path.parent.mkdir(parents=True, exist_ok=True)

        def save(tmp: str) -> None:
            with open(tmp, "wb") as f:
                np.savez(f, **data)

        atomic_output(path, save)
    tris = data["triangles"]
    mesh = Mesh(tris.reshape(-1, 3), np.arange(3 * len(tris), dtype=np.int32).reshape(-1, 3), "preview-ball")
    if np.any(data["tmin"] != 0):
        raise ValueError(f"{path}: recorded rays with tmin other than 0; delete the file to record again")
    shadow = data["any_hit"] != 0
    o, d = data["origins"], data["directions"]
    closest = (np.ascontiguousarray(o[~shadow]), np.ascontiguousarray(d[~shadow]))
    tmax = np.ascontiguousarray(data["tmax"][shadow])
    shadows = (np.ascontiguousarray(o[shadow]), np.ascontiguousarray(d[shadow]), tmax)
    return RecordedRender(label, mesh, closest, shadows)
