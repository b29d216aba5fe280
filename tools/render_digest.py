"""Digests of every number the renderer gives, for checking that a change of structure is
bit-identical: every bundled scene at every SIMD width this CPU runs, with every integrator
and both pixel samplers (and both number samplers on one scene), every AOV; the sensors'
direct and indirect illuminance; the radiance cache's probe. Small images, few samples: a
refactor that changes one bit anywhere changes a digest.

    .venv/bin/python tools/render_digest.py --out before.json      # on the old build
    .venv/bin/python tools/render_digest.py --out after.json       # on the new one
    .venv/bin/python tools/render_digest.py --compare before.json after.json

The widths are those this CPU runs (16 only on AVX-512 CPUs), so compare
digests made on one machine."""

from __future__ import annotations

import argparse
import hashlib
import json
import sys
import time
from pathlib import Path

import numpy as np

from patina.native import _core
from patina.render.illuminance import Grid
from patina.render.prepare import PreparedScene
from patina.render.run import render
from patina.scene.reading import load_scene, with_overrides

INTEGRATORS = ("direct", "path", "cache", "cache-guided")
IMAGE = (40, 30)
SPP = 2
AOVS = ("rgb", "albedo", "normal", "depth", "illuminance", "samples")


def digest(*arrays: np.ndarray) -> str:
    h = hashlib.sha256()
    for a in arrays:
        h.update(np.ascontiguousarray(a).tobytes())
    return h.hexdigest()[:24]


SCENES = Path(__file__).resolve().parent.parent / "materials" / "scenes"


def scene_files() -> list[Path]:
    return sorted(SCENES.glob("*.json"))


def render_digests(widths: list[int]) -> dict[str, str]:
    out: dict[str, str] = {}
    for path in scene_files():
        base = load_scene(path)
        for integrator in INTEGRATORS:
            for aa in ("uniform", "adaptive"):
                samplers = ("sobol", "independent") if path.stem == "area-box" else (None,)
                for sampler in samplers:
                    scene = with_overrides(
                        base, spp=SPP, integrator=integrator, width=IMAGE[0], height=IMAGE[1], aa=aa,
                        sampler=sampler, indirect_illuminance=integrator == "path" and aa == "uniform",
                    )  # fmt: skip
                    prepared = PreparedScene(scene)
                    for width in widths:
                        for threads in (1, 2) if width == widths[-1] else (2,):
                            r = render(scene, threads=threads, simd=width, prepared=prepared)
                            key = f"{path.stem}/{integrator}/{aa}/{sampler or 'scene'}/w{width}/t{threads}"
                            out[key] = digest(*(getattr(r, a) for a in AOVS))
                            out[key + "/counts"] = str(
                                (r.rays, r.camera_rays, r.cache_points, r.cache_queries,
                                 r.cache_texels_reprojected, r.cache_texels_traced)
                            )  # fmt: skip
    return out


def illuminance_digests(widths: list[int]) -> dict[str, str]:
    """The sensor kernels themselves (direct light sampling, and with sensor paths), as
    `patina illuminance` calls them for what it does not sum exactly."""
    out: dict[str, str] = {}
    grids = {
        "street-luminaire": Grid(-3.5, -15, 3.5, 15, 5, 9),
        "cache-ies-interior": Grid(-2, -1.5, 2, 1.5, 5, 4, 0.75),
    }
    for name, grid in grids.items():
        prepared = PreparedScene(load_scene(SCENES / f"{name}.json"))
        points = grid.points()[2]
        normals = np.ascontiguousarray(np.tile(np.float32([0, 1, 0]), (len(points), 1)))
        for width in widths:
            for depth in (0, 3):  # the sensor paths' vertices: max_depth 0 (none), 4 (3 vertices)
                max_depth = depth + 1 if depth else 0
                lux = _core.sensor_illuminance(prepared.core, points, normals, 8, 3, width, 2, max_depth)
                out[f"illuminance/{name}/w{width}/depth{depth}"] = digest(np.asarray(lux))
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path)
    ap.add_argument("--compare", nargs=2, type=Path)
    args = ap.parse_args(argv)
    if args.compare:
        a, b = (json.loads(p.read_text()) for p in args.compare)
        differ = sorted(k for k in a.keys() | b.keys() if a.get(k) != b.get(k))
        for k in differ:
            print(f"differs: {k}: {a.get(k)} -> {b.get(k)}")
        print(f"{len(a.keys() & b.keys()) - len([k for k in differ if k in a and k in b])} equal, {len(differ)} differ")
        return 1 if differ else 0
    widths = [w for w in (1, 4, 8, 16) if _core.width_supported(w)]
    t0 = time.time()
    digests = render_digests(widths) | illuminance_digests(widths)
    print(f"{len(digests)} digests at widths {widths} in {time.time() - t0:.0f} s", file=sys.stderr)
    text = json.dumps(digests, indent=1, sort_keys=True)
    if args.out:
        args.out.write_text(text)
    else:
        print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
