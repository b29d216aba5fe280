"""`patina bench --only trace`: the tracer's speed, as ratios measured in one run.

Primary rays: 4- and 8-ray packet traversal of the kd-tree against single-ray traversal of
the same tree, and against Embree 4 (through embreex) on the same rays. Diffuse-bounce
rays: the same packets against single rays where packets are incoherent. Shadow rays:
any-hit queries the same way. The 8-wide BVH (one ray at a time) against the kd-tree's
widest packets and against Embree on the same rays. Build: seconds to build trees of 10k
to 1M triangles, with the growth against N log N, and the BVH's build of 1M. Everything
on one thread; builds (Patina's and Embree's) are outside every traversal timing.
docs/trace.md describes the records.
"""

from __future__ import annotations

import functools
import math
import statistics
import time
from dataclasses import dataclass
from typing import Any

import numpy as np

from patina.bench.ray_replay import recorded_preview
from patina.bench.records import Record, median_times, simd_widths
from patina.geometry import benchmark_geometry as scenes
from patina.geometry.accel import Accel
from patina.geometry.mesh import Mesh
from patina.native import _core

EMBREE = "Embree 4 via embreex, rtcIntersect1 one ray at a time, 1 thread"
EMBREE_SHADOW = "Embree 4 via embreex, rtcOccluded1 one ray at a time, 1 thread"


@dataclass
class _Scene:
    """A benchmark scene: its mesh, the camera that frames it, and the image side in pixels."""

    name: str
    mesh: Mesh
    eye: tuple[float, float, float]
    target: tuple[float, float, float]
    fov_deg: float
    side: int


def _scenes(quick: bool) -> list[_Scene]:
    """1024 x 1024 camera rays; 512 x 512 for the slivers, where Embree's default BVH is so
    slow (tens of times slower than elsewhere) that it would take most of the run.
    quick: 128 x 128 rays and about a tenth of the triangles."""
    k, side = (10, 128) if quick else (1, 1024)
    thin_side = side if quick else 512
    return [
        _Scene("icosphere", scenes.icosphere(5_000 if quick else 80_000), (0.3, -3.0, 0.8), (0, 0, 0), 45.0, side),
        _Scene("boxes", scenes.box_field(200_000 // k, seed=1), (0.2, -2.2, 1.2), (0, 0, 0), 50.0, side),
        _Scene("soup", scenes.triangle_soup(100_000 // k, seed=2), (0.5, -1.0, 0.6), (0.5, 0.5, 0.5), 55.0, side),
        _Scene("thin", scenes.thin_triangles(100_000 // k, seed=3), (0.5, -1.0, 0.6), (0.5, 0.5, 0.5), 55.0, thin_side),
    ]


def _packetsimd_widths() -> list[int]:
    return simd_widths()


def _embree_scene(mesh: Mesh) -> Any | None:
    """A committed Embree scene of the mesh, or None without embreex."""
    try:
        from embreex import rtcore_scene as rtcs
        from embreex.mesh_construction import TriangleMesh
    except ImportError:
        return None
    scene = rtcs.EmbreeScene()
    TriangleMesh(scene, np.ascontiguousarray(mesh.triangles()))
    probe = np.zeros((1, 3), np.float32)
    scene.run(probe, probe + np.float32(1.0))  # the first query commits (builds) the scene
    return scene


def _closest_records(
    prefix: str, accel: Accel, embree: Any | None, rays: scenes.Rays, repeat: int, scalar_suffix: str
) -> list[Record]:
    """Closest hits: packets (p4, p8) against single rays of the same tree, and against Embree.

    Names: `{prefix}.p{w}{scalar_suffix}` and `{prefix}.p{w}_vs_embree`. All runs interleaved.
    """
    o, d = rays
    widths = _packetsimd_widths()
    # Packets against single rays: both write into the same preallocated arrays, so the
    # ratio is the traversal's. Against Embree: ours allocates its results as embreex does.
    n = len(o)
    out = _hit_arrays(n)
    fns = [functools.partial(accel.core.intersect, o, d, width=w, threads=1, out=out) for w in (1, *widths)]
    fns += [functools.partial(accel.core.intersect, o, d, width=w, threads=1) for w in widths]
    if embree is not None:
        fns.append(functools.partial(embree.run, o, d, output=1))
    times = median_times(fns, repeat)
    k = len(widths)
    records = _packet_records(prefix, widths, times[: 1 + k], n, scalar_suffix, "kd-tree", None)
    if embree is not None:
        records += _embree_records(prefix, widths, times[1 + k : 1 + 2 * k], times[-1], n, "kd-tree", EMBREE)
    return records


def _hit_arrays(n: int) -> tuple[np.ndarray, ...]:
    """Preallocated results of `intersect(..., out=)` for n rays: t, triangle id, u, v, normal."""
    return (
        np.empty(n, np.float32),
        np.empty(n, np.int32),
        np.empty(n, np.float32),
        np.empty(n, np.float32),
        np.empty((n, 3), np.float32),
    )


def _shadow_records(
    prefix: str, accel: Accel, embree: Any | None, rays: scenes.Rays, tmax: np.ndarray, repeat: int
) -> list[Record]:
    """Any-hit (shadow) queries: packets against single rays, and against Embree's rtcOccluded1."""
    o, d = rays
    widths = _packetsimd_widths()
    fns = [functools.partial(accel.core.occluded, o, d, tmax=tmax, width=w, threads=1) for w in (1, *widths)]
    if embree is not None:
        fns.append(functools.partial(embree.run, o, d, dists=tmax.copy(), query="OCCLUDED"))
    times = median_times(fns, repeat)
    return _packet_records(prefix, widths, times, len(o), "", "kd-tree any-hit", EMBREE_SHADOW if embree else None)


def _packet_records(
    prefix: str, widths: list[int], times: list[float], n: int, scalar_suffix: str, what: str, embree: str | None
) -> list[Record]:
    """times: single rays, then each packet width, then (if `embree`) Embree."""
    records = []
    for w, t in zip(widths, times[1 : 1 + len(widths)]):
        cand = f"{what}, {w}-ray packets"
        mrays = n / t / 1e6
        records.append(
            Record(f"{prefix}.p{w}{scalar_suffix}", cand, f"{what}, single rays", times[0] / t, mrays, "Mrays/s")
        )
        if embree is not None:
            records.append(Record(f"{prefix}.p{w}_vs_embree", cand, embree, times[-1] / t, mrays, "Mrays/s"))
    return records


def _embree_records(
    prefix: str, widths: list[int], packet_times: list[float], embree_time: float, n: int, what: str, embree: str
) -> list[Record]:
    """`{prefix}.p{w}_vs_embree`: packets (allocating their results) against Embree."""
    return [
        Record(f"{prefix}.p{w}_vs_embree", f"{what}, {w}-ray packets", embree, embree_time / t, n / t / 1e6, "Mrays/s")
        for w, t in zip(widths, packet_times)
    ]


def _bvh_records(
    prefix: str, accel: Accel, embree: Any | None, rays: scenes.Rays, repeat: int, tmax: np.ndarray | None = None
) -> list[Record]:
    """The BVH at the widest width: `{prefix}.bvh_vs_p{w}` against the kd-tree's widest
    packets (both into preallocated arrays) and `{prefix}.bvh_vs_embree`; closest hit, or
    any hit when `tmax` is given. All runs interleaved."""
    o, d = rays
    n = len(o)
    w = max(_packetsimd_widths(), default=1)
    accel.core.build_bvh()  # not timed
    if tmax is None:
        out = _hit_arrays(n)
        fns = [functools.partial(accel.core.intersect, o, d, width=w, threads=1, out=out, bvh=b) for b in (False, True)]
        fns.append(functools.partial(accel.core.intersect, o, d, width=w, threads=1, bvh=True))
        what, embree_what = "BVH", EMBREE
        if embree is not None:
            fns.append(functools.partial(embree.run, o, d, output=1))
    else:
        occluded = functools.partial(accel.core.occluded, o, d, tmax=tmax, width=w, threads=1)
        fns = [functools.partial(occluded, bvh=b) for b in (False, True)]
        what, embree_what = "BVH any-hit", EMBREE_SHADOW
        if embree is not None:
            fns.append(functools.partial(embree.run, o, d, dists=tmax.copy(), query="OCCLUDED"))
    times = median_times(fns, repeat)
    cand = f"{what}, one ray at a time, {w} lanes over a node's children"
    mrays = n / times[1] / 1e6
    kd = f"kd-tree{' any-hit' if tmax is not None else ''}, {w}-ray packets"
    records = [Record(f"{prefix}.bvh_vs_p{w}", cand, kd, times[0] / times[1], mrays, "Mrays/s")]
    if embree is not None:
        mine = times[1] if tmax is not None else times[2]  # against Embree: both allocate their results
        ratio = times[-1] / mine
        records.append(Record(f"{prefix}.bvh_vs_embree", cand, embree_what, ratio, n / mine / 1e6, "Mrays/s"))
    return records


def _shadow_rays(accel: Accel, primary: scenes.Rays, light: np.ndarray) -> tuple[scenes.Rays, np.ndarray]:
    """From each primary hit (lifted off the surface) toward a point light; tmax stops short of it."""
    hits = accel.intersect(*primary)
    hit = hits.hit
    p = hits.points(*primary)[hit]
    nrm = hits.normal[hit].astype(np.float64)
    facing = np.where(np.sum(nrm * primary.directions[hit], axis=1, keepdims=True) > 0, -nrm, nrm)
    origin = p + 1e-4 * (1 + np.abs(p).max(axis=1, keepdims=True)) * facing
    to_light = light - origin
    dist = np.linalg.norm(to_light, axis=1)
    rays = scenes.Rays(
        np.ascontiguousarray(origin, dtype=np.float32), np.ascontiguousarray(to_light / dist[:, None], dtype=np.float32)
    )
    return rays, (dist * (1 - 1e-4)).astype(np.float32)


def _trace_records(repeat: int, quick: bool) -> list[Record]:
    records: list[Record] = []
    for sc in _scenes(quick):
        accel = Accel(sc.mesh)  # built once, all threads; only traversal is timed
        embree = _embree_scene(sc.mesh)
        primary = scenes.pinhole_rays(sc.side, sc.side, sc.eye, sc.target, sc.fov_deg)
        records += _closest_records(f"trace.primary.{sc.name}", accel, embree, primary, repeat, "")
        records += _bvh_records(f"trace.primary.{sc.name}", accel, embree, primary, repeat)
        if sc.name in ("icosphere", "boxes"):
            bounce = scenes.diffuse_bounce_rays(accel, primary, seed=4)
            records += _closest_records(f"trace.random.{sc.name}", accel, embree, bounce, repeat, "_vs_scalar")
            records += _bvh_records(f"trace.random.{sc.name}", accel, embree, bounce, repeat)
        if sc.name == "boxes":
            shadow, tmax = _shadow_rays(accel, primary, np.array([0.6, -0.4, 2.5]))
            records += _shadow_records("trace.shadow.boxes", accel, embree, shadow, tmax, repeat)
            records += _bvh_records("trace.shadow.boxes", accel, embree, shadow, repeat, tmax)
    return records


def _replay_records(repeat: int, quick: bool) -> list[Record]:
    """The preview ball's recorded rays (bench/ray_replay.py), closest hit and shadow, replayed."""
    rec = recorded_preview(quick)
    accel = Accel(rec.mesh)
    embree = _embree_scene(rec.mesh)
    o, d = rec.closest
    records = _closest_records("trace.replay.preview.path", accel, embree, scenes.Rays(o, d), repeat, "_vs_scalar")
    records += _bvh_records("trace.replay.preview.path", accel, embree, scenes.Rays(o, d), repeat)
    so, sd, tmax = rec.shadow
    shadow = scenes.Rays(so, sd)
    records += _shadow_records("trace.replay.preview.shadow", accel, embree, shadow, tmax, repeat)
    return records + _bvh_records("trace.replay.preview.shadow", accel, embree, shadow, repeat, tmax)


def _size_label(n: int) -> str:
    return f"{n // 1_000_000}m" if n >= 1_000_000 else f"{n // 1000}k"


def _build_records(repeat: int, quick: bool) -> list[Record]:
    """Build time over a series of sizes; ratio against the N log N growth from the smallest."""
    sizes = [10_000, 30_000, 100_000] if quick else [10_000, 30_000, 100_000, 300_000, 1_000_000]
    records: list[Record] = []
    first = _size_label(sizes[0])
    base: tuple[int, float] | None = None
    for size in sizes:
        mesh = scenes.sphere_of(size)
        n = mesh.triangle_count
        runs = min(repeat, 3) if size >= 300_000 else repeat  # a 1M build takes seconds
        seconds, cpu_seconds = _build_seconds(mesh, runs)
        n0, t0 = base = base or (n, seconds)
        predicted = t0 * (n * math.log(n)) / (n0 * math.log(n0))
        records.append(
            Record(
                f"trace.build.{_size_label(size)}",
                f"kd-tree build, 1 thread, {n} triangles, {cpu_seconds:.2f} s CPU; "
                f"time/(N log N) = {seconds / predicted:.2f} x {first}'s",
                f"the {first} build time scaled by N log N",
                predicted / seconds,
                seconds,
                "s",
            )
        )
        if size == sizes[-1] and (embree_seconds := _embree_build_seconds(mesh, runs)) is not None:
            records.append(
                Record(
                    f"trace.build.{_size_label(size)}_vs_embree",
                    f"kd-tree build, 1 thread, {n} triangles",
                    "Embree 4's BVH build via embreex (its default quality, all cores through TBB)",
                    embree_seconds / seconds,
                    seconds,
                    "s",
                )
            )
    return records


def _build_seconds(mesh: Mesh, runs: int) -> tuple[float, float]:
    """Median wall and CPU seconds of a one-thread kd-tree build of the mesh, after a warm-up
    build. The CPU time is what the target "1 s on one core" means: on a shared machine
    the wall time also holds the waits for a core."""
    build = functools.partial(_core.Accel, mesh.vertices, mesh.indices, threads=1)
    build()
    wall: list[float] = []
    cpu: list[float] = []
    for _ in range(runs):
        t0, c0 = time.perf_counter(), time.process_time()
        build()
        wall.append(time.perf_counter() - t0)
        cpu.append(time.process_time() - c0)
    return statistics.median(wall), statistics.median(cpu)


def _embree_build_seconds(mesh: Mesh, runs: int) -> float | None:
    """Median seconds to build and commit an Embree scene of the mesh, or None without embreex."""
    try:
        import embreex  # noqa: F401
    except ImportError:
        return None
    (seconds,) = median_times([functools.partial(_embree_scene, mesh)], runs)
    return seconds


def _bvh_build_records(repeat: int, quick: bool) -> list[Record]:
    """`trace.build.bvh.1m`: the BVH's build (one thread) of the 1M-triangle sphere against the
    kd-tree's (one thread), both from the same triangles; value: the BVH's seconds."""
    size = 100_000 if quick else 1_000_000
    mesh = scenes.sphere_of(size)
    runs = min(repeat, 3)
    kd_seconds, bvh_seconds = [], []
    for _ in range(runs):
        accel = _core.Accel(mesh.vertices, mesh.indices, threads=1)
        kd_seconds.append(accel.build_seconds)
        bvh_seconds.append(accel.build_bvh())
    kd, bvh = sorted(kd_seconds)[runs // 2], sorted(bvh_seconds)[runs // 2]
    n = mesh.triangle_count
    return [
        Record(
            f"trace.build.bvh.{_size_label(size)}",
            f"8-wide BVH build (binned SAH), 1 thread, {n} triangles",
            "kd-tree build, 1 thread, the same triangles",
            kd / bvh,
            bvh,
            "s",
        )
    ]


def bench_trace(repeat: int, quick: bool) -> list[Record]:
    """The `trace` group: traversal records, then build records."""
    records = _trace_records(repeat, quick) + _replay_records(repeat, quick)
    return records + _build_records(repeat, quick) + _bvh_build_records(repeat, quick)
