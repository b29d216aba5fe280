"""What every command shares: usage errors, JSON output, channel labels."""

from __future__ import annotations

import json
import sys
from typing import Any


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
