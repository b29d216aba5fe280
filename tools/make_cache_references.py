"""Renders the converged references of the radiance cache's artefact test
(tests/python/render/test_cache_artefacts.py; docs/radiance-cache.md, "The mosaic"): `path`
at 4096 samples a pixel, seed 7, of cache-studio and cache-ies-interior at their own size
(192 wide), written as RGB float EXRs (about 300 KB each) to materials/references/, the
provenance in materials/references/README.md.

    .venv/bin/python tools/make_cache_references.py [--spp 4096] [--threads 0] [--out DIR]

At 256 spp both scenes took about a minute on two threads of a busy machine; 4096 take 16 times that."""

from __future__ import annotations

import argparse
import os
import subprocess

from patina.bundled import materials_path
from patina.render.images import write_exr
from patina.render.run import render
from patina.scene.reading import load_scene, with_overrides

SCENES = ("cache-studio", "cache-ies-interior")
SEED = 7


def reference_name(scene: str, spp: int) -> str:
    return f"{scene}-path-{spp}spp.exr"


def source_revision() -> str:
    done = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True, check=False)
    return done.stdout.strip() or "unknown"


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--spp", type=int, default=4096, help="samples a pixel of the references (default 4096)")
    ap.add_argument("--threads", type=int, default=0, help="render threads (0: one a core)")
    ap.add_argument("--out", default=materials_path("references"), help="the folder (default: materials/references)")
    args = ap.parse_args()
    for name in SCENES:
        scene = with_overrides(
            load_scene(materials_path("scenes", f"{name}.json")), integrator="path", spp=args.spp, seed=SEED
        )
        rgb = render(scene, threads=args.threads).rgb
        out = os.path.join(args.out, reference_name(name, args.spp))
        metadata = {
            "patina:scene": name,
            "patina:integrator": "path",
            "patina:spp": args.spp,
            "patina:seed": SEED,
            "patina:revision": source_revision(),
        }
        write_exr(out, {"beauty": rgb}, metadata)
        print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
