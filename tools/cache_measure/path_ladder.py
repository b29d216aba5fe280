"""The bench's setting for one bundled cache scene, shared by the studies in this folder: the
scene at the bench's size (bench/cache.py FULL: 192 pixels wide), its converged reference (kept
by the bench) and path's ladder of renders (8, 32, 128 spp, 2 threads), whose error curve a
candidate's time to its error is read against. The ladder is returned untimed so that a study
can time it interleaved with its candidates (timed_renders alternates them)."""

from patina.bench.cache import FULL
from patina.bench.convergence import Run, reference, sized
from patina.bundled import materials_path
from patina.render.run import PreparedScene
from patina.scene.reading import load_scene, with_overrides


def path_ladder(name: str):
    """(scene file, the scene at the bench's size, its reference, path's ladder of Runs)."""
    f = materials_path("scenes", f"{name}.json")
    scene = sized(load_scene(f), FULL.width)
    ref = reference(f, scene, FULL.reference_spp, 2)
    path_scene = with_overrides(scene, integrator="path")
    prep = PreparedScene(path_scene)
    return f, scene, ref, [Run(with_overrides(path_scene, spp=n), prep, 2) for n in FULL.ladder]
