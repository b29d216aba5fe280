"""fit.json: a fit's result written out, and read back as a model evaluable like a table."""

from __future__ import annotations

import json
import math

import numpy as np

from patina.atomic import write_text
from patina.errors import FormatError
from patina.fitting.models import ALIASES, MODELS, ParameterSpace
from patina.fitting.search import FitResult
from patina.native import _core


class FittedModel:
    """A model read back from fit.json, evaluable like a table (`eval(wi, wo)` -> (n, 3)).

    The variant (shared or per-channel shapes, isotropic or anisotropic Lafortune lobes)
    follows from the parameter names; held parameters (Lafortune's cz, the coat's eta)
    are read like the fitted ones."""

    def __init__(self, model: str, parameters: dict[str, float]) -> None:
        coat = model.endswith("+coat")
        name, _, count = model.removesuffix("+coat").partition(" x")
        name = ALIASES.get(name, name)
        if name not in MODELS or (count and not (count.isdigit() and 1 <= int(count) <= 3)):
            raise ValueError(f"unknown model '{model}'")
        self.model = model
        lobe = MODELS[name]
        variants = [lobe, f"{lobe}-aniso"] if lobe == "lafortune" else [lobe]
        spaces = [
            ParameterSpace(v, int(count) if count else 1, coat, per_channel, None)
            for v in variants
            for per_channel in (False, True)
        ]
        complete = [sp for sp in spaces if all(n in parameters for n in sp.names)]
        if not complete:
            fewest = min(spaces, key=lambda sp: sum(n not in parameters for n in sp.names))
            missing = [n for n in fewest.names if n not in parameters]
            raise ValueError(f"parameters missing for {model}: {', '.join(missing)}")
        self.space = max(complete, key=lambda sp: len(sp.names))  # the most specific variant present
        self.values = [float(parameters[n]) for n in self.space.names]
        if not all(math.isfinite(v) for v in self.values):
            raise ValueError("parameters must be finite numbers")

    def eval(self, wi: np.ndarray, wo: np.ndarray) -> np.ndarray:
        as32 = lambda a: np.ascontiguousarray(a, dtype=np.float32)  # noqa: E731
        return _core.mixture_eval(self.space.kernel_name, self.values, as32(wi), as32(wo), 0, self.space.per_channel)


def read_fit(path: str) -> FittedModel:
    """fit.json -> FittedModel; FormatError naming the file and the field for anything wrong."""
    try:
        with open(path, encoding="utf-8") as f:
            doc = json.load(f)
    except OSError as e:
        raise FormatError(path, "", f"cannot open: {e.strerror}") from None
    except (json.JSONDecodeError, UnicodeDecodeError) as e:
        raise FormatError(path, (getattr(e, "lineno", None) and f"line {e.lineno}") or "", f"not JSON: {e}") from None
    if not isinstance(doc, dict):
        raise FormatError(path, "", "expected a JSON object as written by patina fit")
    for key, kind in (("model", str), ("parameters", dict)):
        if not isinstance(doc.get(key), kind):
            raise FormatError(path, key, f"missing or not a {kind.__name__}")
    try:
        return FittedModel(doc["model"], doc["parameters"])
    except (TypeError, ValueError) as e:
        raise FormatError(path, "parameters", str(e)) from None


def write_fit(result: FitResult, path: str) -> None:
    """fit.json, written to a temporary file and renamed."""
    write_text(path, json.dumps(result.as_json(), indent=2))


def write_ranking(results: list[FitResult], path: str) -> None:
    """`fit --compare --out`: the best fit's fields at the top level (so read_fit, and every
    command taking a fit.json, reads the best model) and under "ranking" every model's
    result, best first (parameters, metrics, at_bounds, usable and problems)."""
    if not results:
        raise ValueError("no fits to write")
    doc = {**results[0].as_json(), "ranking": [r.as_json() for r in results]}
    write_text(path, json.dumps(doc, indent=2))
