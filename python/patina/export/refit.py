"""Refitting a material to the model a target holds, and measuring an export against its source.

Targets hold Lambert + GGX (Mitsuba also Beckmann and several lobes) with one roughness for
the three channels. Other fits (Ward, Ashikhmin-Shirley, Blinn-Phong, Lafortune, per-channel
shapes, several lobes for a one-lobe target) are refitted to Lambert + one GGX lobe (the coat
kept, its index held) against the source evaluated densely (or the measured table, given): differences of log(1 + the
cosine-weighted value) (the `log` loss of `patina fit`; plain differences let grazing
pairs, where Ward and Lafortune lobes part from GGX most, outweigh the highlight) at
direction pairs spread over both hemispheres, plus pairs about the mirror direction where
the highlight is, minimised by scipy's bounded
least squares from a few roughness starts. The error of what is exported against the source
is reported as `patina fit` reports a fit's (relative error median and 95th percentile,
CIEDE2000 mean and 95th percentile by patina.fitting.metrics)."""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from patina.export.material import AnalyticMaterial, Coat, Lobe
from patina.export.source import Source, sample_pairs
from patina.fitting.metrics import colour_differences, relative_errors
from patina.fitting.samples import sample_measure, subset, table_samples
from patina.kernel_arrays import as_float32
from patina.native import _core
from patina.progress import Progress

REFIT_PAIRS = 20_000
METRIC_PAIRS = 50_000
ALPHA_RANGE = (0.005, 1.0)
# a refit whose CIEDE2000 mean is above this is refused: the target cannot hold the material
MAX_REFIT_DE = 10.0


class RefitError(ValueError):
    """The refit could not bring the material into the target's model."""


def _highlight_pairs(count: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """wi over the hemisphere, wo within about 25 degrees of its mirror direction."""
    rng = np.random.default_rng(seed + 1)
    wi, _ = sample_pairs(count, seed + 2)
    mirror = wi * np.array([-1.0, -1.0, 1.0])
    wo = mirror + rng.normal(0.0, 0.25, (count, 3))
    wo[:, 2] = np.abs(wo[:, 2]) + 0.02
    return wi, wo / np.linalg.norm(wo, axis=1, keepdims=True)


def dense_pairs(count: int, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """Half the pairs uniform over the hemispheres, half near the mirror direction."""
    a = sample_pairs(count - count // 2, seed)
    b = _highlight_pairs(count // 2, seed)
    return np.concatenate([a[0], b[0]]), np.concatenate([a[1], b[1]])


def error_metrics(reference: np.ndarray, exported: np.ndarray, cos_i: np.ndarray) -> dict[str, float]:
    """Relative error and CIEDE2000 of `exported` against `reference` ((n, 3) BRDF values)."""
    diff = exported - reference
    rel = relative_errors(reference, exported)
    delta_e = colour_differences(reference, exported, cos_i)
    return {
        "rmse": float(np.sqrt(np.mean(diff**2))),
        "relative_error_median": float(np.median(rel)),
        "relative_error_p95": float(np.percentile(rel, 95)),
        "ciede2000_mean": float(np.mean(delta_e)),
        "ciede2000_p95": float(np.percentile(delta_e, 95)),
    }


# (count, seed) -> wi, wo (n, 3) and the reference's RGB values there (n, 3)
Reference = Callable[[int, int], tuple[np.ndarray, np.ndarray, np.ndarray]]


def fit_reference(evaluate: Callable) -> Reference:
    """The source fit evaluated at dense_pairs."""

    def draw(count: int, seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        wi, wo = dense_pairs(count, seed)
        return wi, wo, np.asarray(evaluate(wi, wo), np.float64)

    return draw


def table_reference(brdf: Any) -> Reference:
    """A measured table's own samples (no interpolation), drawn in proportion to the measure
    of direction pairs each stands for, as `patina fit` draws them."""
    every, weights = table_samples(brdf), sample_measure(brdf)

    def draw(count: int, seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        wi, wo, values, _ = subset(every, count, np.random.default_rng(seed), weights)
        return wi.astype(np.float64), wo.astype(np.float64), values.astype(np.float64)

    return draw


def measure(reference: Reference, material: AnalyticMaterial, pairs: int = METRIC_PAIRS) -> dict[str, float]:
    """The material's error against the reference, on pairs apart from the refit's."""
    wi, wo, values = reference(pairs, 7)
    return error_metrics(values, material.eval(wi, wo), wi[:, 2])


def refit(source: Source, name: str, reference: Reference, progress: bool = False) -> AnalyticMaterial:
    """The source refitted to Lambert + one GGX lobe (and its coat) against `reference` (the
    source's fit_reference, or the measured table's); RefitError if it fails.
    `progress`: one step per roughness start on stderr."""
    coat_eta = None
    if source.fitted is not None and source.fitted.space.coat:
        coat_eta = dict(zip(source.fitted.space.names, source.fitted.values))["coat_eta"]
    wi, wo, values = reference(REFIT_PAIRS, 3)
    weight = wi[:, 2:3]
    target = np.log1p(np.maximum(values, 0.0) * weight)
    if not np.all(np.isfinite(target)):
        raise RefitError("the source evaluates to non-finite values")
    wi32, wo32 = as_float32(wi), as_float32(wo)
    kind = "ggx+coat" if coat_eta else "ggx"
    log_alpha = (math.log10(ALPHA_RANGE[0]), math.log10(ALPHA_RANGE[1]))
    lower = [0.0] * 3 + [log_alpha[0]] + [0.0] * 3 + ([log_alpha[0]] if coat_eta else [])
    upper = [1.0] * 3 + [log_alpha[1]] + [1.0] * 3 + ([0.0] if coat_eta else [])

    def params(x: np.ndarray) -> list[float]:
        out = [float(v) for v in (*x[:3], 10 ** x[3], *x[4:7])]
        return out + ([float(10 ** x[7]), coat_eta] if coat_eta else [])

    def residuals(x: np.ndarray) -> np.ndarray:
        f = np.asarray(_core.mixture_eval(kind, params(x), wi32, wo32), np.float64) * weight
        return (np.log1p(f) - target).ravel()

    from scipy.optimize import least_squares

    best = None
    starts = (0.05, 0.2, 0.5)
    with Progress(len(starts), "refitting to GGX", unit="start", enabled=progress) as bar:
        for done, start_alpha in enumerate(starts):
            bar.update(done)
            x0 = [0.3] * 3 + [math.log10(start_alpha)] + [0.04] * 3 + ([math.log10(0.05)] if coat_eta else [])
            try:
                r = least_squares(residuals, x0, bounds=(lower, upper), x_scale="jac", diff_step=1e-4, max_nfev=200)
            except ValueError as e:
                raise RefitError(f"the refit failed: {e}") from None
            if np.all(np.isfinite(r.x)) and (best is None or r.cost < best.cost):
                best = r
        bar.update(len(starts))
    if best is None:
        raise RefitError("the refit found no finite solution")
    p = params(best.x)
    coat = Coat(p[7], coat_eta) if coat_eta else None
    material = AnalyticMaterial(
        name,
        tuple(p[:3]),
        (Lobe("ggx", p[3], tuple(p[4:7])),),
        coat,
        False,
        "ggx+lambert" + ("+coat" if coat else ""),
        source.path,
        [f"refitted from {source.model} to ggx+lambert{'+coat' if coat else ''}"],
    )
    return material


def needs_refit(source: Source, max_lobes: int | None, distributions: tuple[str, ...]) -> str:
    """Why the source must be refitted for a target ('' when it need not)."""
    m = source.exact
    if m is None:
        return f"{source.model} is not Lambert + GGX or Beckmann lobes with a shared roughness"
    if m.lobes and m.distribution not in distributions:
        return f"the target has no {m.distribution} lobe"
    if max_lobes is not None and len(m.lobes) > max_lobes:
        return f"the target holds {max_lobes} specular lobe(s), the fit has {len(m.lobes)}"
    return ""
