"""The `math` and `brdf` groups: fast inverse trigonometry against the C library, and table
evaluation at widths 4 and 8 against width 1 on random and coherent direction pairs."""

from __future__ import annotations

import functools

import numpy as np

from patina.bench.records import Record, median_times, simd_widths
from patina.native import _core
from patina.synthetic.analytic import merl_table, plastic, sample_isotropic
from patina.table.formats import table_from_data


def random_pairs(n: int, seed: int = 1) -> tuple[np.ndarray, np.ndarray]:
    """Independent uniformly distributed upper-hemisphere direction pairs."""
    rng = np.random.default_rng(seed)

    def hemi(k: int) -> np.ndarray:
        z = rng.uniform(0.0, 1.0, k)
        phi = rng.uniform(0.0, 2 * np.pi, k)
        r = np.sqrt(1 - z * z)
        return np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=1).astype(np.float32)

    return hemi(n), hemi(n)


def coherent_pairs(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Pairs as neighbouring pixels produce them: a sphere seen from +z, lit from a fixed
    direction, scanned row by row; each pixel's light and view directions in its local frame."""
    side = int(np.ceil(np.sqrt(n / 0.7))) + 1
    u = (np.arange(side) + 0.5) / side * 2 - 1
    x, y = np.meshgrid(u, -u)
    inside = x * x + y * y < 0.999
    nrm = np.stack([x[inside], y[inside], np.sqrt(1 - x[inside] ** 2 - y[inside] ** 2)], axis=1)
    light = np.array([0.5, 0.6, 0.62])
    light /= np.linalg.norm(light)
    view = np.array([0.0, 0.0, 1.0])
    t = np.cross(nrm, [0.0, 1.0, 0.0])
    t /= np.linalg.norm(t, axis=1, keepdims=True)
    b = np.cross(nrm, t)

    def local(w: np.ndarray) -> np.ndarray:
        return np.stack([t @ w, b @ w, nrm @ w], axis=1)

    wi, wo = local(light), local(view)
    lit = wi[:, 2] > 0.01
    wi, wo = wi[lit], wo[lit]
    reps = int(np.ceil(n / len(wi)))
    return (np.tile(wi, (reps, 1))[:n].astype(np.float32), np.tile(wo, (reps, 1))[:n].astype(np.float32))


def merl_sized_table() -> _core.Table:

    return table_from_data(merl_table(plastic()))


def iso_table() -> _core.Table:
    """An irregular 30 x 30 x 60 isotropic table, denser near the specular direction."""

    theta = np.radians(89.0 * np.linspace(0, 1, 30) ** 1.2)
    u = np.linspace(0, 1, 60)
    phi = np.pi * (0.3 * u + 0.7 * np.sin(u * np.pi / 2))  # dense near phi_d = pi, where the peak lies
    return table_from_data(sample_isotropic(plastic(), theta, theta, phi, "bench"))


def bench_math(repeat: int, quick: bool) -> list[Record]:
    n = 1 << (14 if quick else 20)
    rng = np.random.default_rng(3)
    x = rng.uniform(-1, 1, n).astype(np.float32)
    y = rng.normal(size=n).astype(np.float32)
    records = []
    for op, libc, args in (("acos", "libc_acos", (x,)), ("atan2", "libc_atan2", (y, x))):
        out = np.empty(n, np.float32)
        for w in simd_widths():
            base = functools.partial(_core.math, libc, *args, width=1, out=out)
            cand = functools.partial(_core.math, op, *args, width=w, out=out)
            tb, tc = median_times([base, cand], repeat)
            records.append(
                Record(
                    f"math.{op}.w{w}",
                    f"fast_{op} width {w}",
                    f"C library {op}f, scalar",
                    tb / tc,
                    n / tc / 1e6,
                    "Mvalues/s",
                )
            )
    return records


def bench_brdf(repeat: int, quick: bool) -> list[Record]:
    n = 1 << (13 if quick else 18)
    records: list[Record] = []
    merl = merl_sized_table()
    iso = iso_table()
    rnd = random_pairs(n)
    coh = coherent_pairs(n)

    # coherent binary search alone, on the theta_h axis of the MERL table (90 irregular knots),
    # with the coordinates the two direction sets produce.
    knots = np.ascontiguousarray(merl.axes[0])
    for label, (wi, wo) in (("", coh), (".random", rnd)):
        h = wi + wo
        th = np.arccos(np.clip(h[:, 2] / np.linalg.norm(h, axis=1), -1, 1)).astype(np.float32)
        cells = np.empty(n, np.int32)
        for w in simd_widths():
            scalar = functools.partial(_core.search, knots, th, width=1, out=cells)
            masked = functools.partial(_core.search, knots, th, width=w, out=cells)
            thesis = functools.partial(_core.search, knots, th, width=w, out=cells, split="sequential")
            tb, tc, tt = median_times([scalar, masked, thesis], repeat)
            records.append(
                Record(
                    f"brdf.search{label}.w{w}",
                    f"coherent search width {w}",
                    "binary search width 1",
                    tb / tc,
                    n / tc / 1e6,
                    "Msearches/s",
                )
            )
            records.append(
                Record(
                    f"brdf.search{label}.thesis.w{w}",
                    f"coherent search width {w}, sequential split walk (thesis)",
                    "binary search width 1",
                    tb / tt,
                    n / tt / 1e6,
                    "Msearches/s",
                )
            )

    for tname, table in (("merl", merl), ("iso", iso)):
        for dname, (wi, wo) in (("random", rnd), ("coherent", coh)):
            t1 = None
            out = np.empty((n, table.channels), np.float32)
            for w in simd_widths():
                tb, tc = median_times(
                    [
                        functools.partial(table.eval, wi, wo, width=1, threads=1, out=out),
                        functools.partial(table.eval, wi, wo, width=w, threads=1, out=out),
                    ],
                    repeat,
                )
                t1 = tb if t1 is None else min(t1, tb)
                records.append(
                    Record(
                        f"brdf.eval.{tname}.{dname}.w{w}",
                        f"evaluator width {w}",
                        "evaluator width 1",
                        tb / tc,
                        n / tc / 1e6,
                        "Mevals/s",
                    )
                )
            if t1 is not None:
                records.append(
                    Record(
                        f"brdf.eval.{tname}.{dname}.w1",
                        "evaluator width 1",
                        "evaluator width 1",
                        1.0,
                        n / t1 / 1e6,
                        "Mevals/s",
                    )
                )
            # against a plain scalar evaluator using the C library's acosf / atan2f
            for w in simd_widths():
                tb, tc = median_times(
                    [
                        functools.partial(table.eval, wi, wo, width=1, threads=1, out=out, libm_trig=True),
                        functools.partial(table.eval, wi, wo, width=w, threads=1, out=out),
                    ],
                    repeat,
                )
                records.append(
                    Record(
                        f"brdf.eval.{tname}.{dname}.w{w}_vs_libm",
                        f"evaluator width {w}",
                        "scalar evaluator with C library acosf/atan2f",
                        tb / tc,
                        n / tc / 1e6,
                        "Mevals/s",
                    )
                )
    return records
