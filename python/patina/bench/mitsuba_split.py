"""Mitsuba 3's lead over Patina split by Mitsuba's own switches (docs/performance.md).

Mitsuba's llvm_ad_rgb variant renders the bench's gold sphere (render.vs_mitsuba_llvm) to
the same error faster than Patina. Its own documentation names three reasons: Dr.Jit
compiles the whole path tracer into one megakernel that keeps path state in registers,
its LLVM backend uses the CPU's widest vectors, and Embree's BVH traces its rays. Each
is a switch measured here, every configuration in a child process of its own (Dr.Jit's
target and flags are process-wide, and its vector width must be set before the first
kernel), rendering the same scene at the same spp, so a time ratio is a ratio at equal
error:

- vector width: 8 lanes (what Dr.Jit picks on this AVX2 machine) against 4, set through
  `jit_llvm_set_target` (a C entry point of libdrjit-core, through ctypes: Dr.Jit's Python
  API has no switch for it);
- megakernel against wavefront: `JitFlag.SymbolicLoops` and `JitFlag.SymbolicCalls` off,
  so every loop iteration (bounce) and BSDF call is evaluated into memory, kernel by kernel,
  as a wavefront renderer does;
- geometry: the analytic sphere (`to_mitsuba`'s default) against Patina's own triangles
  of it in Embree's BVH, the geometry Patina traces.

Embree's BVH against Patina's kd-tree on the same rays is the trace group's `*_vs_embree`
(docs/trace.md).
"""

from __future__ import annotations

import json
import statistics
import subprocess
import sys
import time
from typing import Any

import numpy as np

from patina.bench.mitsuba_scenes import mitsuba_scene_dict, preview_mitsuba_scene, triangle_spheres
from patina.bench.records import Record
from patina.bundled import materials_path
from patina.scene.mitsuba import to_mitsuba
from patina.scene.reading import load_scene, with_overrides

VARIANT = "llvm_ad_rgb"


def _set_vector_width(width: int) -> None:
    """Dr.Jit's LLVM backend at `width` lanes, same CPU and features (before any kernel)."""
    import ctypes
    import os

    import drjit as dr

    core = ctypes.CDLL(os.path.join(os.path.dirname(dr.__file__), "libdrjit-core.so"))
    cpu, features = core._Z19jit_llvm_target_cpuv, core._Z24jit_llvm_target_featuresv
    cpu.restype = features.restype = ctypes.c_char_p
    set_target = core._Z19jit_llvm_set_targetPKcS0_j
    set_target.argtypes = [ctypes.c_char_p, ctypes.c_char_p, ctypes.c_uint32]
    set_target(cpu(), features(), width)


def _vector_width() -> int:
    import ctypes
    import os

    import drjit as dr

    core = ctypes.CDLL(os.path.join(os.path.dirname(dr.__file__), "libdrjit-core.so"))
    get = core._Z21jit_llvm_vector_widthv
    get.restype = ctypes.c_uint32
    return int(get())


def _scene_dict(spec: dict[str, Any]) -> dict[str, Any]:
    w, h = spec["size"]
    if spec["scene"] == "preview-mitsuba":
        return mitsuba_scene_dict(preview_mitsuba_scene(w, h), VARIANT)
    scene = with_overrides(load_scene(materials_path("scenes", f"{spec['scene']}.json")), width=w, height=h, seed=0)
    if spec["mesh"]:  # Patina's triangles of the sphere, though the scene has Patina trace it analytically
        return mitsuba_scene_dict(triangle_spheres(scene), VARIANT)
    return to_mitsuba(scene, variant=VARIANT)


def child_main() -> None:
    """In a child process: the configuration from stdin (JSON), its render times on stdout (JSON)."""
    spec = json.loads(sys.stdin.read())
    import drjit as dr
    import mitsuba as mi

    mi.set_variant(VARIANT)
    if spec["vector_width"]:
        _set_vector_width(spec["vector_width"])
    if spec["wavefront"]:
        dr.set_flag(dr.JitFlag.SymbolicLoops, False)
        dr.set_flag(dr.JitFlag.SymbolicCalls, False)
    dr.set_thread_count(spec["threads"])  # (Dr.Jit 1.5 hangs rendering with 1 thread here: the bench uses all cores)
    scene = mi.load_dict(_scene_dict(spec))
    times = []
    for k in range(spec["repeat"] + 1):  # the first run compiles the kernels: not counted
        t0 = time.perf_counter()
        image = np.asarray(mi.render(scene, spp=spec["spp"], seed=k))
        times.append(time.perf_counter() - t0)
    print(json.dumps({"seconds": times[1:], "mean": float(image.mean()), "vector_width": _vector_width()}))


def run_child(spec: dict[str, Any], timeout: float = 900.0) -> dict[str, Any]:
    """Runs one configuration (child_main) in a fresh interpreter."""
    code = "from patina.bench.mitsuba_split import child_main; child_main()"
    done = subprocess.run(
        [sys.executable, "-c", code],
        input=json.dumps(spec),
        capture_output=True,
        text=True,
        timeout=timeout,
        check=False,
    )
    if done.returncode != 0:
        raise RuntimeError(f"Mitsuba child failed ({done.returncode}): {done.stderr.strip()[-400:]}")
    return json.loads(done.stdout.strip().splitlines()[-1])


# (record suffix, the candidate, the baseline, the baseline's configuration changes, the candidate's)
SWITCHES = [
    ("w8_vs_w4", "8 vector lanes", "4 lanes", {"vector_width": 4}, {"vector_width": 8}),
    ("megakernel_vs_wavefront", "one megakernel (symbolic loops and calls)", "wavefront (evaluated loops and calls)",
     {"wavefront": True}, {}),
    ("analytic_vs_mesh", "the analytic sphere", "Patina's triangles of it in Embree's BVH", {"mesh": True}, {}),
]  # fmt: skip


def mitsuba_split_records(repeat: int, quick: bool, threads: int) -> list[Record]:
    """One record per switch on the gold sphere (the preview for the megakernel switch too):
    ratio = the baseline configuration's median time / the candidate's; value = the candidate's
    seconds per render."""
    size, spp = ((32, 24), 16) if quick else ((128, 96), 128)
    base = {"size": size, "spp": spp, "threads": threads, "repeat": 2,
            "vector_width": 0, "wavefront": False, "mesh": False}  # fmt: skip
    cases = [("conductor-sphere", name, what, vs, b, c) for name, what, vs, b, c in SWITCHES]
    cases.append(("preview-mitsuba", *SWITCHES[1]))
    records = []
    for scene, name, what, vs, base_change, cand_change in cases:
        spec = {**base, "scene": scene, "spp": spp if scene == "conductor-sphere" else spp // 4}
        # children alternated, so a change in the machine's load hits both configurations
        runs: dict[str, list[dict[str, Any]]] = {"b": [], "c": []}
        for _ in range(max(repeat // 3, 1)):
            runs["b"].append(run_child({**spec, **base_change}))
            runs["c"].append(run_child({**spec, **cand_change}))
        b, c = runs["b"][0], runs["c"][0]
        tb = statistics.median(t for r in runs["b"] for t in r["seconds"])
        tc = statistics.median(t for r in runs["c"] for t in r["seconds"])
        records.append(
            Record(
                f"render.profile.mitsuba.{scene}.{name}",
                f"Mitsuba 3 {VARIANT}, {scene} {size[0]}x{size[1]}, {spec['spp']} spp, {threads} threads: {what} "
                f"({c['vector_width']} lanes)",
                f"the same with {vs} ({b['vector_width']} lanes)",
                tb / tc,
                tc,
                "s",
            )
        )
    return records
