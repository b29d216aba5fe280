"""What every command shares: usage errors, JSON output, channel labels, the help format and
the `--simd` option."""

from __future__ import annotations

import argparse
import contextlib
import json
import sys
import warnings
from collections.abc import Iterator
from typing import Any

from patina.cli.values import integer
from patina.widths import WIDTHS


class HelpFormat(argparse.ArgumentDefaultsHelpFormatter):
    """Every option's help shows its default ("(default: ...)") beside its text, except where
    there is none to show (None, a flag's False) or the text already says it."""

    def _get_help_string(self, action: argparse.Action) -> str | None:
        if action.default is None or action.default is False or "default" in (action.help or ""):
            return action.help
        return super()._get_help_string(action)


class UsageError(Exception):
    """A bad option value: reported like argparse does, exit status 2."""


def print_json(obj: Any) -> None:
    json.dump(obj, sys.stdout, indent=2)
    sys.stdout.write("\n")


def channel_labels(brdf: Any) -> list[str]:
    kind = brdf.channel_kind
    if kind == "rgb":
        return ["R", "G", "B"]
    if kind == "xyz":
        return ["X", "Y", "Z"]
    if kind == "spectral":
        return [f"{w:g}nm" for w in brdf.wavelengths]
    return ["value"]


def add_simd_option(s: argparse.ArgumentParser) -> None:
    """`--simd {1,4,8,16}`: the one name for the SIMD width on every command (`--width` is an image's width)."""
    s.add_argument(
        "--simd",
        type=integer(min(WIDTHS), max(WIDTHS)),
        choices=WIDTHS,
        default=None,
        help="force a SIMD width: 1 (scalar), 4 (SSE4.1), 8 (AVX2) or 16 (AVX-512); "
        "default: PATINA_SIMD, else the widest",
    )


@contextlib.contextmanager
def brief_warnings() -> Iterator[None]:
    """Python warnings raised under a command (numpy, matplotlib, Dask...) as one line each,
    `patina: warning: RuntimeWarning: overflow encountered in multiply`, instead of Python's
    two (the library's file and source line mean nothing to a user). Which are shown, and how
    often, stays Python's choice: once a place, none of those it ignores."""

    def show(message: Warning | str, category: type[Warning], *args: Any, **kwargs: Any) -> None:
        print(f"patina: warning: {category.__name__}: {' '.join(str(message).split())}", file=sys.stderr)

    with warnings.catch_warnings():
        warnings.showwarning = show
        yield
