"""fit.json: a fit's result written out, and read back as a model evaluable like a table."""

from __future__ import annotations

import json
import math

import numpy as np

from patina.atomic import write_text
from patina.errors import FormatError
from patina.fitting.models import ALIASES, MODELS, ParameterSpace
from patina.fitting.search import FitResult
from patina.kernel_arrays import as_float32
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
        return _core.mixture_eval(
            self.space.kernel_name, self.values, as_float32(wi), as_float32(wo), 0, self.space.per_channel
        )


MAX_FIT_BYTES = 1 << 20  # a fit.json is a few hundred bytes; more is not one
_FLOAT32_MAX = float(np.finfo(np.float32).max)  # the kernels evaluate parameters as float32


def _parameter(path: str, name: str, value: object) -> float:
    """One parameter as the float32 kernels can use it, or a FormatError naming it."""
    where = f"parameters.{name}"
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise FormatError(path, where, f"must be a number, got {type(value).__name__}")
    try:
        x = float(value)
    except OverflowError:  # an integer of hundreds of digits
        raise FormatError(path, where, "is too large to be a number") from None
    if not math.isfinite(x):
        raise FormatError(path, where, f"must be finite, got {x}")
    if abs(x) > _FLOAT32_MAX:
        raise FormatError(path, where, f"{x:g} is beyond the 32-bit float range the models are evaluated in")
    return x


def read_fit(path: str) -> FittedModel:
    """fit.json -> FittedModel; FormatError naming the file and the field for anything wrong."""
    try:
        with open(path, "rb") as f:
            data = f.read(MAX_FIT_BYTES + 1)
    except OSError as e:
        raise FormatError(path, "", f"cannot open: {e.strerror}") from None
    if len(data) > MAX_FIT_BYTES:
        raise FormatError(path, "", f"larger than {MAX_FIT_BYTES >> 20} MiB: not a fit.json")
    try:
        doc = json.loads(data.decode("utf-8-sig"))
    except UnicodeDecodeError as e:
        raise FormatError(path, f"byte {e.start}", "not UTF-8 text") from None
    except json.JSONDecodeError as e:
        raise FormatError(path, f"line {e.lineno}, column {e.colno}", f"not JSON: {e.msg}") from None
    except RecursionError:  # thousands of nested brackets
        raise FormatError(path, "", "JSON nested too deeply") from None
    except ValueError as e:  # an integer literal beyond Python's digit limit
        raise FormatError(path, "", f"JSON value not readable: {e}") from None
    if not isinstance(doc, dict):
        raise FormatError(path, "", "expected a JSON object as written by patina fit")
    for key, kind in (("model", str), ("parameters", dict)):
        if not isinstance(doc.get(key), kind):
            raise FormatError(path, key, f"missing or not a {kind.__name__}")
    parameters = {str(k): _parameter(path, str(k), v) for k, v in doc["parameters"].items()}
    try:
        return FittedModel(doc["model"], parameters)
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
