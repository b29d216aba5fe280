"""Fitting analytic lobes to tables: the models and their parameter spaces (models), the
samples a fit runs on (samples), the nlopt search (search), how close a fit is (metrics),
whether it is usable (verdict) and fit.json (fit_file). Named `fitting` so that `patina.fit`
stays the function."""

from patina.fitting.fit_file import FittedModel, read_fit, write_fit, write_ranking
from patina.fitting.metrics import colour_differences
from patina.fitting.models import ALIASES, COAT_ETA, LOSSES, MODELS
from patina.fitting.samples import table_samples
from patina.fitting.search import FitResult, compare, fit, recommended
from patina.fitting.verdict import Thresholds, parse_accept

__all__ = [
    "ALIASES",
    "COAT_ETA",
    "LOSSES",
    "MODELS",
    "FitResult",
    "FittedModel",
    "Thresholds",
    "colour_differences",
    "compare",
    "fit",
    "parse_accept",
    "read_fit",
    "recommended",
    "table_samples",
    "write_fit",
    "write_ranking",
]
