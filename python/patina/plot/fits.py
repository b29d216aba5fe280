"""The fits a report shows: fit.json files written by `patina fit --out`, and rankings: the file
`patina fit --compare --out` writes (the best fit at the top level and every model, best first,
under "ranking"), or a JSON list of fits as `patina fit --compare --json` prints; read into models."""

from __future__ import annotations

import json
import os
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from patina.errors import FormatError
from patina.fitting import FittedModel

RANKING_KEYS = ("ranking",)


@dataclass
class Fit:
    name: str  # what the legend and the tables call it: the model, with the file where two share a model
    model: FittedModel
    doc: dict[str, Any]  # the fit's JSON object (parameters, metrics, at_bounds, source, ...)
    path: str


def _entries(path: str, doc: Any) -> list[tuple[str, Any]]:
    """(place in the file, fit object) for each fit the document holds."""
    if isinstance(doc, list):
        return [(f"[{i}]", d) for i, d in enumerate(doc)]
    if isinstance(doc, dict):
        for key in RANKING_KEYS:
            # A ranking repeats its best fit at the top level (for readers of one fit): show the list only.
            if isinstance(doc.get(key), list):
                return [(f"{key}[{i}]", d) for i, d in enumerate(doc[key])]
        return [("", doc)]
    raise FormatError(path, "", "expected a fit (a JSON object as written by patina fit) or a list of them")


def read_fits(path: str) -> list[Fit]:
    """The fits in one file; FormatError naming the file and the entry and field for anything wrong."""
    try:
        with open(path, encoding="utf-8") as f:
            doc = json.load(f)
    except OSError as e:
        raise FormatError(path, "", f"cannot open: {e.strerror}") from None
    except (json.JSONDecodeError, UnicodeDecodeError) as e:
        raise FormatError(path, (getattr(e, "lineno", None) and f"line {e.lineno}") or "", f"not JSON: {e}") from None
    except RecursionError:
        raise FormatError(path, "", "not JSON that can be read: nested too deeply") from None
    except ValueError as e:  # e.g. an integer too long to convert
        raise FormatError(path, "", f"not JSON that can be read: {e}") from None
    entries = _entries(path, doc)
    if not entries:
        raise FormatError(path, "", "the ranking holds no fits")
    fits = []
    for place, entry in entries:
        where = lambda key, place=place: f"{place}.{key}" if place else key  # noqa: E731
        if not isinstance(entry, dict):
            raise FormatError(path, place, "expected a fit: a JSON object as written by patina fit")
        for key, kind in (("model", str), ("parameters", dict)):
            if not isinstance(entry.get(key), kind):
                raise FormatError(path, where(key), f"missing or not a {kind.__name__}")
        try:
            model = FittedModel(entry["model"], entry["parameters"])
        except (TypeError, ValueError, OverflowError) as e:
            raise FormatError(path, where("parameters"), str(e)) from None
        fits.append(Fit(entry["model"], model, entry, path))
    return fits


def read_all_fits(paths: Sequence[str]) -> list[Fit]:
    """The fits of several files, in order; a model that occurs twice is named with its file (and place)."""
    fits = [fit for path in paths for fit in read_fits(path)]

    def repeated() -> set[str]:
        names = [fit.name for fit in fits]
        return {n for n in names if names.count(n) > 1}

    twice = repeated()
    for fit in fits:
        if fit.name in twice:
            fit.name = f"{fit.name} ({os.path.basename(fit.path)})"
    seen: dict[str, int] = {}
    again = repeated()  # the same model twice in one file (or in files of one name): number them
    for fit in fits:
        if fit.name in again:
            seen[fit.name] = seen.get(fit.name, 0) + 1
            fit.name = f"{fit.name} #{seen[fit.name]}"
    return fits
