"""Fitting analytic lobes to a measured table with nlopt (the models: patina.fitting.models).

The search is bounded, a global stage (nlopt's CRS2 with local mutation) on a random
subsample of the table, then several local starts (BOBYQA) on a larger one; the loss
runs on the SIMD kernels over all cores. The local stage's samples are drawn in
proportion to the solid-angle measure each grid point stands for (patina.fitting.samples),
so the loss it minimises is an integral over direction pairs rather than a sum over an
irregular grid's knots. The global stage keeps a plain subset of the knots: only a start
for the local stage, and measure-weighted draws led it into a wrong basin on a
retro-reflective Lafortune table (its exponent ending near 10^4).

Metrics: `loss` (the measure-weighted loss the search minimises, the ranking's key),
`loss_all_samples` (the plain mean over every grid point), rmse and relative errors over
every grid point, CIEDE2000 mean and 95th percentile over measure-weighted samples, and
`cosine_relative_rmse` (the RMS of cos_i cos_o (fit - table) over that of cos_i cos_o table,
measure-weighted: the l2cos loss as a fraction of the table's own size).

A fit is flagged `usable = False` (with `problems` saying why, and `verdict` holding every
metric beside its threshold) when one of its errors exceeds its threshold
(patina.fitting.verdict), its loss is not finite, a diffuse albedo ends at its upper bound
(a full-white diffuse term: the search traded the albedo for something the lobe could not
fit) or the model's symmetry does not suit the table's; `compare` adds fits whose mean
CIEDE2000 is far above the best one's, and ranks usable fits first.
"""

from __future__ import annotations

import math
import os
import time
import zlib
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np

from patina.fitting.metrics import colour_differences, relative_errors
from patina.fitting.models import ALIASES, COAT_ETA, LOSSES, MODELS, ParameterSpace
from patina.fitting.samples import sample_measure, subset, table_samples
from patina.fitting.verdict import Thresholds, checks, failed, symmetry_problem
from patina.native import _core
from patina.progress import Progress
from patina.table.brdf import Brdf
from patina.table.isotropy import is_anisotropic

# compare: a fit whose mean CIEDE2000 exceeds the best fit's by both of these is unusable
DE_FAR_RATIO = 2.0
DE_FAR_ABOVE = 5.0


@dataclass
class FitResult:
    model: str
    parameters: dict[str, float]
    loss: str
    loss_value: float
    metrics: dict[str, float]
    converged: bool
    message: str
    seconds: float
    samples: int
    source: str = ""
    table_checksum: str = ""
    at_bounds: list[str] = field(default_factory=list)
    usable: bool = True
    problems: list[str] = field(default_factory=list)  # why the fit is not usable
    verdict: list[dict[str, Any]] = field(default_factory=list)  # each metric, its threshold, passed

    def as_json(self) -> dict[str, Any]:
        return asdict(self)


def _polish(
    space: ParameterSpace,
    samples: tuple[np.ndarray, ...],
    loss: str,
    x0: np.ndarray,
    lower: np.ndarray,
    upper: np.ndarray,
) -> tuple[np.ndarray, bool]:
    """Levenberg-Marquardt (scipy's bounded trust-region reflective) from x0 on the loss's
    residuals, whose Jacobian follows the coat's narrow valley (a sharp coat highlight
    beside a dim, broad base) that BOBYQA's interpolated quadratic creeps along.
    Returns the point and whether it converged."""
    from scipy.optimize import least_squares

    wi, wo, measured, weight = samples
    w = weight.astype(np.float64)[:, None]
    target = measured.astype(np.float64) * w
    if loss == "log":
        target = np.log1p(target)
    scale = 1.0 / math.sqrt(target.size)  # so that the sum of squares is the mean loss

    def residuals(x: np.ndarray) -> np.ndarray:
        f = _core.mixture_eval(space.kernel_name, space.params(x), wi, wo, 0, space.per_channel) * w
        return ((np.log1p(f) if loss == "log" else f) - target).ravel() * scale

    try:
        r = least_squares(
            residuals,
            np.clip(x0, lower, upper),
            bounds=(lower, upper),
            x_scale="jac",
            diff_step=1e-4,  # float32 values: a step well above their rounding
            xtol=1e-10,
            ftol=1e-12,
            gtol=1e-12,
            max_nfev=100,
        )
    except ValueError:  # non-finite residuals at x0
        return x0, False
    return (r.x, r.status > 0) if np.all(np.isfinite(r.x)) else (x0, False)


def _checksum(path: str) -> str:
    if not path or not os.path.isfile(path):
        return ""
    crc = 0
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            crc = zlib.crc32(block, crc)
    return f"crc32:{crc:08x}"


def fit(
    brdf: Brdf,
    model: str = "ggx+lambert",
    loss: str = "l2cos",
    lobes: int = 1,
    coat: bool = False,
    per_channel: bool = False,
    coat_eta: float = COAT_ETA,
    fit_coat_eta: bool = False,
    anisotropic: bool | None = None,
    starts: int = 4,
    global_evals: int | None = None,
    local_evals: int | None = None,
    global_samples: int = 20_000,
    local_samples: int = 200_000,
    seed: int = 0,
    threads: int = 0,
    accept: Thresholds | None = None,
) -> FitResult:
    """Fits `model` to the table; see the module docstring. `accept`: the thresholds a
    usable fit passes (patina.fitting.verdict's defaults when None)."""
    import nlopt

    model = ALIASES.get(model, model)
    if model not in MODELS:
        raise ValueError(f"unknown model '{model}' (known: {', '.join(MODELS)})")
    if loss not in LOSSES:
        raise ValueError(f"unknown loss '{loss}' (known: {', '.join(LOSSES)})")
    if starts < 1:
        raise ValueError("starts must be at least 1")
    if not 1 <= lobes <= 3:
        raise ValueError("lobes must be 1, 2 or 3")
    if not (math.isfinite(coat_eta) and 1.0 < coat_eta <= 3.0):
        raise ValueError(f"coat_eta must be in (1, 3], not {coat_eta}")
    lobe = MODELS[model]
    if lobe == "lafortune" and (brdf.parametrization == "anisotropic" if anisotropic is None else anisotropic):
        lobe = "lafortune-aniso"
    space = ParameterSpace(lobe, lobes, coat, per_channel, None if fit_coat_eta else coat_eta)
    lower, upper = space.bounds()
    # evaluation budgets grow with the number of parameters (7 for one lobe, 4 more per lobe)
    global_evals = global_evals or 200 * len(lower)
    simple = lobes == 1 and not coat and not per_channel and len(lower) == 7
    local_evals = local_evals or (200 if simple else 600) * len(lower)
    started = time.perf_counter()
    rng = np.random.default_rng(seed)
    every = table_samples(brdf)
    if len(every[0]) < 20:
        raise ValueError(f"only {len(every[0])} usable samples in the table: too few to fit")
    measure = sample_measure(brdf)
    coarse = _core.FitSamples(*subset(every, global_samples, rng))
    fine_arrays = subset(every, local_samples, rng, measure)
    fine = _core.FitSamples(*fine_arrays)

    def loss_at(samples: Any, x: np.ndarray) -> float:
        return samples.mixture_loss(space.kernel_name, space.params(x), loss, 0, threads, space.per_channel)

    def objective(samples: Any) -> Any:
        def f(x: np.ndarray, grad: np.ndarray) -> float:
            value = loss_at(samples, x)
            return value if math.isfinite(value) else 1e300

        return f

    nlopt.srand(seed)
    glob = nlopt.opt(nlopt.GN_CRS2_LM, len(lower))
    glob.set_lower_bounds(lower.tolist())
    glob.set_upper_bounds(upper.tolist())
    glob.set_min_objective(objective(coarse))
    glob.set_maxeval(global_evals)
    x0 = (lower + upper) / 2
    best_global = np.asarray(glob.optimize(x0.tolist()))

    best_x, best_value, best_code = None, math.inf, 0
    guesses = [best_global] + [lower + rng.uniform(0, 1, len(lower)) * (upper - lower) for _ in range(starts - 1)]
    for guess in guesses:
        local = nlopt.opt(nlopt.LN_BOBYQA, len(lower))
        local.set_lower_bounds(lower.tolist())
        local.set_upper_bounds(upper.tolist())
        local.set_min_objective(objective(fine))
        local.set_maxeval(local_evals)
        local.set_xtol_rel(1e-7)
        local.set_ftol_rel(1e-12)
        try:
            x = np.asarray(local.optimize(np.clip(guess, lower, upper).tolist()))
            value, code = local.last_optimum_value(), local.last_optimize_result()
        except nlopt.RoundoffLimited:
            x, value, code = np.asarray(guess), loss_at(fine, np.asarray(guess)), 5
        if value < best_value:
            best_x, best_value, best_code = x, value, code
    assert best_x is not None

    converged = best_code in (nlopt.SUCCESS, nlopt.FTOL_REACHED, nlopt.XTOL_REACHED, nlopt.STOPVAL_REACHED)
    if coat or lobe.startswith("lafortune"):
        x, ok = _polish(space, fine_arrays, loss, best_x, lower, upper)
        value = loss_at(fine, x)
        if value < best_value:
            best_x, best_value = x, value
            if ok:  # the polish converged from where BOBYQA stopped
                converged, best_code = True, nlopt.SUCCESS
    messages = {
        nlopt.MAXEVAL_REACHED: "evaluation limit reached before convergence",
        nlopt.MAXTIME_REACHED: "time limit reached before convergence",
    }
    message = "converged" if converged else messages.get(best_code, f"nlopt stopped with code {best_code}")
    span = upper - lower
    at_bounds = [n for n, v, lo, s in zip(space.free_names, best_x, lower, span) if min(v - lo, lo + s - v) < 1e-6 * s]
    wi, wo, measured, _ = every
    best = space.params(best_x)
    predicted = _core.mixture_eval(space.kernel_name, best, wi, wo, 0, space.per_channel).astype(np.float64)
    diff = predicted - measured
    rel = relative_errors(measured, predicted)
    full = _core.FitSamples(*every)
    cosine = (measure * every[3].astype(np.float64) ** 2)[:, None]  # measure x (cos_i cos_o)^2
    cosine_relative_rmse = math.sqrt(float(np.sum(cosine * diff**2)) / max(float(np.sum(cosine * measured**2)), 1e-300))
    pick = np.sort(rng.choice(len(wi), min(len(wi), 100_000), replace=True, p=measure / measure.sum()))
    delta_e = colour_differences(measured[pick], predicted[pick], wi[pick, 2])
    metrics = {
        "loss": loss_at(fine, best_x),
        "loss_all_samples": loss_at(full, best_x),
        "rmse": float(np.sqrt(np.mean(diff**2))),
        "relative_error_median": float(np.median(rel)),
        "relative_error_p95": float(np.percentile(rel, 95)),
        "ciede2000_mean": float(np.mean(delta_e)),
        "ciede2000_p95": float(np.percentile(delta_e, 95)),
        "cosine_relative_rmse": cosine_relative_rmse,
    }
    verdict = checks(metrics, accept or Thresholds())
    problems = [] if math.isfinite(best_value) else ["the loss is not finite"]
    full_white = [n for n, v, hi in zip(space.free_names, best_x, upper) if n.startswith("rho_") and v >= hi - 1e-6]
    if full_white:
        problems.append(f"diffuse albedo at its upper bound ({', '.join(full_white)} = 1)")
    if mismatch := symmetry_problem(lobe, is_anisotropic(brdf)):
        problems.append(mismatch)
    problems += failed(verdict)
    return FitResult(
        model=(model if lobes == 1 else f"{model} x{lobes}") + ("+coat" if coat else ""),
        parameters={n: float(v) for n, v in zip(space.names, best)},
        loss=loss,
        loss_value=float(best_value),
        metrics=metrics,
        converged=bool(converged and math.isfinite(best_value)),
        message=message if math.isfinite(best_value) else "the loss is not finite",
        seconds=time.perf_counter() - started,
        samples=len(wi),
        source=brdf.source,
        table_checksum=_checksum(brdf.source),
        at_bounds=at_bounds,
        usable=not problems,
        problems=problems,
        verdict=[c.as_json() for c in verdict],
    )


def compare(brdf: Brdf, models: list[str], progress: bool = False, **options: Any) -> list[FitResult]:
    """Fits each model (names as for fit, `NAME:K` for K lobes) and ranks them: usable fits
    first, each group by its loss. `progress` shows one step per model on stderr."""
    names = []
    for name in models:
        model, _, k = name.partition(":")
        if k and not (k.isdigit() and 1 <= int(k) <= 3):
            raise ValueError(f"'{name}': the lobe count after ':' must be 1, 2 or 3")
        if ALIASES.get(model, model) not in MODELS:
            raise ValueError(f"unknown model '{model}' (known: {', '.join(MODELS)})")
        names.append((model, int(k or 1)))  # all checked before the first (long) fit
    results = []
    with Progress(len(names), "fitting", unit="model", enabled=progress) as bar:
        for done, (model, lobes) in enumerate(names):
            bar.update(done, postfix=model if lobes == 1 else f"{model}:{lobes}")
            results.append(fit(brdf, model=model, lobes=lobes, **options))
        bar.update(len(names))
    return rank(results)


def rank(results: list[FitResult]) -> list[FitResult]:
    """Flags the colour outliers (flag_outliers), then usable fits first, each group by loss."""
    flag_outliers(results)
    return sorted(results, key=lambda r: (not r.usable, r.metrics["loss"]))


def recommended(ranked: list[FitResult]) -> FitResult | None:
    """The fit to use from a ranking (rank's order): its first if that passes, else None
    (ranked[0] is then the least bad, shown with its numbers)."""
    return ranked[0] if ranked and ranked[0].usable else None


def flag_outliers(results: list[FitResult]) -> None:
    """Marks unusable the fits whose mean CIEDE2000 is far above the best usable one's
    (DE_FAR_RATIO times and DE_FAR_ABOVE more): beside a fit that reproduces the colour,
    one that does not is no candidate whatever its loss."""
    usable = [r.metrics["ciede2000_mean"] for r in results if r.usable and math.isfinite(r.metrics["ciede2000_mean"])]
    if not usable:
        return
    best = min(usable)
    for r in results:
        de = r.metrics["ciede2000_mean"]
        if not math.isfinite(de) or (de > DE_FAR_RATIO * best and de > best + DE_FAR_ABOVE):
            r.usable = False
            r.problems.append(f"mean CIEDE2000 {de:.1f}, far above the best fit's {best:.1f}")
