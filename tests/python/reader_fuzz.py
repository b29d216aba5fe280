"""What the readers' fuzz tests share: a file damaged at one byte (changed or cut there),
loaded, and either a FormatError naming it or a table that evaluates."""

from __future__ import annotations

import numpy as np

from conftest import load_or_format_error


def evaluates(brdf) -> None:
    with np.errstate(all="ignore"):
        brdf.eval(np.array([[0.0, 0.6, 0.8]]), np.array([[0.3, 0.0, 0.954]]))


def load_damaged(clean: bytes, at: int, value: int, cut: bool, filename: str, load, check=evaluates) -> None:
    """`clean` cut at byte `at`, or with that byte set to `value`, saved as `filename` and loaded."""
    raw = clean[:at] if cut else clean[:at] + bytes([value]) + clean[at + 1 :]
    load_or_format_error(raw, filename, load, check)
