"""Fitting analytic lobes to tables: the models and their parameter spaces (models), the
samples a fit runs on (samples), the nlopt search (search), how close a fit is (metrics),
and fit.json (fit_file). Named `fitting` so that `patina.fit` stays the function."""

from patina.fitting.fit_file import FittedModel, read_fit, write_fit, write_ranking
from patina.fitting.metrics import colour_differences
from patina.fitting.models import ALIASES, COAT_ETA, LOSSES, MODELS
from patina.fitting.samples import table_samples
from patina.fitting.search import FitResult, compare, fit

__all__ = [
    "ALIASES",
    "COAT_ETA",
    "LOSSES",
    "MODELS",
    "FitResult",
    "FittedModel",
    "colour_differences",
    "compare",
    "fit",
    "read_fit",
    "table_samples",
    "write_fit",
    "write_ranking",
]
