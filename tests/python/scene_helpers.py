"""Test helpers for scene files: the JSON blocks of docs/scene.md, and empty stand-ins for the
files a scene references (the parser only checks that they exist)."""

from __future__ import annotations

import os
import re
from typing import Any

from repo_paths import ROOT

DOC = os.path.join(ROOT, "docs", "scene.md")


def doc_blocks(language: str) -> list[str]:
    """The fenced code blocks of docs/scene.md whose info string is exactly `language`."""
    with open(DOC, encoding="utf-8") as f:
        text = f.read()
    return re.findall(rf"^```{re.escape(language)}\n(.*?)^```", text, re.S | re.M)


def referenced_files(obj: Any) -> list[str]:
    """Every string under a "file" key, anywhere in a decoded scene."""
    found: list[str] = []
    if isinstance(obj, dict):
        for k, v in obj.items():
            if k == "file" and isinstance(v, str):
                found.append(v)
            else:
                found.extend(referenced_files(v))
    elif isinstance(obj, list):
        for v in obj:
            found.extend(referenced_files(v))
    return found


def write_stand_ins(obj: Any, folder: str) -> None:
    """Creates an empty file for each file the scene names (relative to `folder`) that is missing."""
    for name in referenced_files(obj):
        path = os.path.join(folder, name)
        if not os.path.exists(path):
            os.makedirs(os.path.dirname(path), exist_ok=True)
            open(path, "wb").close()
