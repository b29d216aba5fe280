"""Manifests: what a finished task read and wrote, so that a rerun skips it.

Each task writes its outputs (atomically), then `STEP.manifest.json` beside them: the input
file's checksum, the checksums of the outputs of earlier steps it read, its settings, the
Patina version, the checksums of its outputs and its result. A task is up to date when its
manifest says exactly that about the files as they are now. The manifest is written last,
so a task killed half-way (a dead worker, Ctrl-C) has none and runs again.
"""

from __future__ import annotations

import hashlib
import json
import os
from typing import Any

from patina.atomic import write_text
from patina.native import _core

MANIFEST_VERSION = 1
MAX_MANIFEST_BYTES = 1 << 20


def checksum(path: str) -> str:
    """sha256 of the file's bytes ("" if it cannot be read: never equal to a recorded one)."""
    h = hashlib.sha256()
    try:
        with open(path, "rb") as f:
            for block in iter(lambda: f.read(1 << 20), b""):
                h.update(block)
    except OSError:
        return ""
    return "sha256:" + h.hexdigest()


def manifest_path(folder: str, step: str) -> str:
    return os.path.join(folder, f"{step}.manifest.json")


def _checksums(folder: str, names: list[str]) -> dict[str, str]:
    return {n: checksum(os.path.join(folder, n)) for n in names}


def write_manifest(
    folder: str,
    step: str,
    input_path: str,
    input_checksum: str,
    inputs: dict[str, str],
    settings: dict[str, Any],
    outputs: list[str],
    result: dict[str, Any],
) -> None:
    """`inputs`: {name in folder: checksum} of earlier steps' outputs the task read;
    `outputs`: the names (relative to folder) it wrote."""
    doc = {
        "version": MANIFEST_VERSION,
        "patina": _core.__version__,
        "step": step,
        "input": input_path,
        "input_checksum": input_checksum,
        "inputs": inputs,
        "settings": settings,
        "outputs": _checksums(folder, outputs),
        "result": result,
    }
    write_text(manifest_path(folder, step), json.dumps(doc, indent=2, sort_keys=True))


def up_to_date(
    folder: str, step: str, input_checksum: str, inputs: dict[str, str], settings: dict[str, Any]
) -> dict[str, Any] | None:
    """The recorded result if the step's manifest matches the input, the earlier outputs read,
    the settings and this Patina, and every output it lists is there unchanged; else None
    (a missing, unreadable or foreign manifest is simply out of date)."""
    path = manifest_path(folder, step)
    try:
        with open(path, "rb") as f:
            doc = json.loads(f.read(MAX_MANIFEST_BYTES))
    except (OSError, ValueError, RecursionError):
        return None
    if not isinstance(doc, dict) or not isinstance(doc.get("outputs"), dict) or not isinstance(doc.get("result"), dict):
        return None
    expected = {
        "version": MANIFEST_VERSION,
        "patina": _core.__version__,
        "step": step,
        "input_checksum": input_checksum,
        "inputs": inputs,
        "settings": json.loads(json.dumps(settings)),  # as JSON reads it back (tuples are lists)
    }
    if any(doc.get(k) != v for k, v in expected.items()):
        return None
    if _checksums(folder, list(doc["outputs"])) != doc["outputs"]:
        return None
    return doc["result"]
