"""Whether a fit is usable: its own errors against stated thresholds, and whether the model's
symmetry suits the table's.

A fit is usable when every threshold below holds and nothing else is wrong with it (a loss
that is not finite, a diffuse albedo at its upper bound, an isotropic model on an
anisotropic table or the reverse). The verdict keeps every number that decided it, each
beside its threshold, so `patina fit` and `batch` can say why. The defaults come from the
fits of the bundled tables (docs/fitting.md, "Why these thresholds"); `patina fit --accept` overrides
them.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, fields, replace
from typing import Any


@dataclass(frozen=True)
class Thresholds:
    """The largest error a usable fit may have, by metric (FitResult.metrics keys)."""

    relative_error_median: float = 0.20  # |fit - table| / table, median over every grid point
    ciede2000_mean: float = 3.0  # colour difference under D65, mean over measure-weighted samples
    ciede2000_p95: float = 8.0  # ... and its 95th percentile
    cosine_relative_rmse: float = 0.25  # RMS of cos_i cos_o (fit - table) over that of cos_i cos_o table


# how each metric is named in the text output
LABELS = {
    "relative_error_median": "relative error, median",
    "ciede2000_mean": "CIEDE2000, mean",
    "ciede2000_p95": "CIEDE2000, 95th percentile",
    "cosine_relative_rmse": "cosine-weighted relative RMSE",
}
KEYS = tuple(f.name for f in fields(Thresholds))
# the tables the variants of a lobe suit: isotropic lobes cannot represent an azimuth-dependent
# table, and an isotropic table cannot tell an anisotropic lobe's tangent (nor its anisotropy)
ANISOTROPIC_LOBES = ("ward-aniso", "ashikhmin-aniso", "lafortune-aniso")


def parse_accept(text: str, base: Thresholds | None = None) -> Thresholds:
    """`KEY=VALUE[,KEY=VALUE...]` -> Thresholds (the others from base, or the defaults).
    ValueError naming the pair and what is allowed."""
    out = base or Thresholds()
    for item in text.split(","):
        key, sep, value = (s.strip() for s in item.partition("="))
        if not sep or not key:
            raise ValueError(f"'{item.strip()}' is not KEY=VALUE (keys: {', '.join(KEYS)})")
        if key not in KEYS:
            raise ValueError(f"unknown key '{key}' (keys: {', '.join(KEYS)})")
        try:
            number = float(value)
        except ValueError:
            raise ValueError(f"{key}={value}: not a number") from None
        if not (math.isfinite(number) and number > 0):
            raise ValueError(f"{key}={value}: must be a positive finite number")
        out = replace(out, **{key: number})
    return out


@dataclass
class Check:
    """One metric against its threshold."""

    metric: str
    value: float
    threshold: float

    @property
    def passed(self) -> bool:
        return math.isfinite(self.value) and self.value <= self.threshold

    def as_json(self) -> dict[str, Any]:
        return {**asdict(self), "passed": self.passed}

    def describe(self) -> str:
        sign = "<=" if self.passed else ">"
        return f"{LABELS[self.metric]} {self.value:.3g} {sign} threshold {self.threshold:g}"


def checks(metrics: dict[str, float], thresholds: Thresholds) -> list[Check]:
    return [Check(k, float(metrics[k]), getattr(thresholds, k)) for k in KEYS]


def symmetry_problem(lobe: str, anisotropic_table: bool) -> str:
    """Why the lobe (a LOBES key) does not suit the table, or "": by whether the table's values
    depend on the azimuth (table/isotropy.py), not by its grid -- an isotropic material
    measured on a four-dimensional grid suits an isotropic lobe."""
    anisotropic_model = lobe in ANISOTROPIC_LOBES
    if anisotropic_table and not anisotropic_model:
        return "an isotropic model on an anisotropic table (it cannot follow the table's azimuth dependence)"
    if not anisotropic_table and anisotropic_model:
        return (
            "an anisotropic model on an isotropic table (the table cannot tell the tangent: "
            "the fitted anisotropy is not measured)"
        )
    return ""


def failed(found: list[Check]) -> list[str]:
    """The problems the failing checks make, one each."""
    return [c.describe() for c in found if not c.passed]
