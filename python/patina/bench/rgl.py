"""The `rgl` group: the native RGL .bsdf evaluator (brdf/rgl/) at widths 4, 8 and 16 against
width 1 on coherent and random direction pairs (`brdf.eval.rgl.coherent.wN`, `.random.wN`),
and against the double-precision reference evaluator in Python (`brdf.eval.rgl.vs_reference`,
value in Mevals/s), on an isotropic plastic written in the format's default layout; and the
renderer's RGL material sampled by the file's own warps against the cosine
(`render.rgl.sampling_vs_cosine`, rgl_sampling.py)."""

from __future__ import annotations

import functools

import numpy as np

from patina.bench.kernels import coherent_pairs, random_pairs
from patina.bench.records import Record, median_times, simd_widths
from patina.bench.rgl_sampling import sampling_vs_cosine_record
from patina.synthetic.analytic import plastic
from patina.table.formats.rgl_brdf import RglBrdf
from patina.table.formats.rgl_native import native_rgl
from patina.table.formats.rgl_writer import RglLayout, rgl_arrays
from patina.table.formats.tensor_file import parse_tensor_file, tensor_file_bytes

QUICK_LAYOUT = RglLayout(theta_i=4, ndf=(8, 16), sigma=(8, 16), vndf=(12, 16), values=(12, 12))


def bench_material(quick: bool) -> RglBrdf:
    model = plastic(diffuse=(0.5, 0.3, 0.1), specular=0.04, roughness=0.2)
    arrays = rgl_arrays(model, layout=QUICK_LAYOUT if quick else RglLayout())
    return RglBrdf(parse_tensor_file("bench.bsdf", tensor_file_bytes(arrays)))


def _width_records(native, pairs: dict[str, tuple[np.ndarray, np.ndarray]], repeat: int) -> list[Record]:
    records: list[Record] = []
    for kind, (wi, wo) in pairs.items():
        n = len(wi)
        fastest_scalar = None
        for w in simd_widths():
            scalar = functools.partial(native.eval, wi, wo, width=1, threads=1)
            wide = functools.partial(native.eval, wi, wo, width=w, threads=1)
            t1, tw = median_times([scalar, wide], repeat)
            fastest_scalar = t1 if fastest_scalar is None else min(fastest_scalar, t1)
            name = f"brdf.eval.rgl.{kind}.w{w}"
            records.append(
                Record(name, f"RGL evaluator width {w}", "RGL evaluator width 1", t1 / tw, n / tw / 1e6, "Mevals/s")
            )
        if fastest_scalar is not None:
            name = f"brdf.eval.rgl.{kind}.w1"
            records.append(
                Record(
                    name, "RGL evaluator width 1", "RGL evaluator width 1", 1.0, n / fastest_scalar / 1e6, "Mevals/s"
                )
            )
    return records


def bench_rgl(repeat: int, quick: bool) -> list[Record]:
    n = 1 << (12 if quick else 17)
    brdf = bench_material(quick)
    native = native_rgl(brdf)
    records = _width_records(native, {"coherent": coherent_pairs(n), "random": random_pairs(n)}, repeat)
    # the reference is ~100x slower: timed on fewer pairs, compared per evaluation
    wi, wo = random_pairs(n // 16, seed=2)
    wi64, wo64 = wi.astype(np.float64), wo.astype(np.float64)
    t_native, t_reference = median_times(
        [functools.partial(native.eval, wi, wo, width=0, threads=1), functools.partial(brdf.eval, wi64, wo64)], repeat
    )
    records.append(
        Record(
            "brdf.eval.rgl.vs_reference",
            "native RGL evaluator (default width, 1 thread)",
            "double-precision reference evaluator (numpy)",
            t_reference / t_native,
            len(wi) / t_native / 1e6,
            "Mevals/s",
        )
    )
    records.append(sampling_vs_cosine_record(quick))
    return records
