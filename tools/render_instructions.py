"""Instructions the render kernels execute, counted by valgrind's callgrind: the measure of "no
slower" for a change of structure that a loaded machine's timings cannot give (callgrind counts
the same for the same binary and inputs whatever else runs). Each case renders a bundled scene
small, one thread, at width 8 (valgrind has no AVX-512), and counts only inside the integrator's
entry points (trace_paths, build_cache_region).

    .venv/bin/python tools/render_instructions.py --out after.json
    PYTHONPATH=/path/to/other/python .venv/bin/python tools/render_instructions.py --out before.json
    .venv/bin/python tools/render_instructions.py --compare before.json after.json

(PYTHONPATH picks the package, and its compiled _core, a case runs; the numbers are comparable
only between runs on one machine.)"""

from __future__ import annotations

import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path

SCENES = Path(__file__).resolve().parent.parent / "materials" / "scenes"
CASES = (
    ("preview-ball", 4, "path"),
    ("area-box", 4, "path"),
    ("cache-studio", 4, "cache"),
    ("cache-studio", 2, "cache-guided"),
)
COLLECT = ("*render_detail::trace_paths*", "*render_detail::build_cache_region*")

ONE_RENDER = """
import sys
from patina.render.prepare import PreparedScene
from patina.render.run import render
from patina.scene.reading import load_scene, with_overrides
scene = with_overrides(load_scene(sys.argv[1]), spp=int(sys.argv[2]), width=64, height=48, integrator=sys.argv[3])
render(scene, threads=1, simd=8, prepared=PreparedScene(scene))
"""


def instructions(scene: str, spp: int, integrator: str) -> int:
    with tempfile.TemporaryDirectory() as tmp:
        script, out = os.path.join(tmp, "render.py"), os.path.join(tmp, "callgrind.out")
        Path(script).write_text(ONE_RENDER)
        toggles = [f"--toggle-collect={c}" for c in COLLECT]
        cmd = ["valgrind", "--tool=callgrind", *toggles, f"--callgrind-out-file={out}", sys.executable, script]
        subprocess.run([*cmd, str(SCENES / f"{scene}.json"), str(spp), integrator], check=True, capture_output=True)
        return int(re.search(r"^summary: (\d+)", Path(out).read_text(), re.M).group(1))


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path)
    ap.add_argument("--compare", nargs=2, type=Path)
    args = ap.parse_args(argv)
    if args.compare:
        a, b = (json.loads(p.read_text()) for p in args.compare)
        for key in sorted(a.keys() & b.keys()):
            print(f"{key:32} {a[key]:>14,} {b[key]:>14,} {b[key] / a[key] - 1:+.2%}")
        return 0
    counts = {f"{scene}/{integrator}": instructions(scene, spp, integrator) for scene, spp, integrator in CASES}
    text = json.dumps(counts, indent=1)
    if args.out:
        args.out.write_text(text)
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
