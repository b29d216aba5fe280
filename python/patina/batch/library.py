"""What a batch runs on: the tables of a library folder and the settings every task gets.

A file is a table when it is a regular file (FIFOs, devices and links to them are skipped
with a notice: reading one would wait or never end), `detect_format` (the one `load_brdf` uses) recognises it and its
extension is not one of the documents, images and scenes a library keeps beside its tables
(NOT_TABLES); the others are listed as skipped with the reason. A recognised file that then fails to load (a corrupt
.ptab) is a table whose tasks fail: it is in the report with its error, not skipped.
"""

from __future__ import annotations

import os
import re
from dataclasses import asdict, dataclass
from typing import Any

from patina.errors import FormatError
from patina.file_names import not_a_regular_file
from patina.fitting import ALIASES, LOSSES, MODELS
from patina.table.formats.loading import detect_format

STEPS = ("validate", "fit", "preview", "report")
DEFAULT_MODELS = ("ggx+lambert", "beckmann+lambert", "ward+lambert")
MAX_SIDE = 4096  # a preview is a thumbnail beside a report, not a final render
MAX_SPP = 1 << 16


@dataclass(frozen=True)
class Material:
    """One table of the library: `name` is its file name, unique in the folder, and names its
    output folder (materials/NAME/)."""

    name: str
    path: str  # absolute: tasks may run on another machine that shares the file system


@dataclass(frozen=True)
class Settings:
    """Everything a task's result depends on besides its input file (so, with the file's
    checksum, what a manifest records). Thread counts are not here: results do not depend
    on them (deterministic reductions and renders)."""

    steps: tuple[str, ...] = STEPS
    models: tuple[str, ...] = DEFAULT_MODELS
    loss: str = "l2cos"
    starts: int = 2
    seed: int = 0
    width: int = 160
    height: int = 120
    spp: int = 16
    shape: str = "ball"
    env: str = ""  # the environment map (absolute path); "" is the bundled studio
    lobes: bool = False  # the 3-D lobe view in each report (pyvista: seconds a material)

    def for_step(self, step: str) -> dict[str, Any]:
        """The settings one step's outputs depend on: a change elsewhere does not redo it."""
        d = asdict(self)
        keys = {
            "validate": (),
            "fit": ("models", "loss", "starts", "seed"),
            "preview": ("models", "loss", "starts", "seed", "width", "height", "spp", "shape", "env"),
            "report": ("models", "loss", "starts", "seed", "lobes"),
        }[step]
        return {k: list(d[k]) if isinstance(d[k], tuple) else d[k] for k in keys}


def parse_steps(text: str) -> tuple[str, ...]:
    """`validate,fit,preview` -> the steps in their run order; ValueError names an unknown one.
    preview needs fit (the best model is what it shows beside the table)."""
    names = [s.strip() for s in text.split(",") if s.strip()]
    if not names:
        raise ValueError("--steps: no step given (known: " + ", ".join(STEPS) + ")")
    for s in names:
        if s not in STEPS:
            raise ValueError(f"--steps: unknown step '{s}' (known: {', '.join(STEPS)})")
    if "preview" in names and "fit" not in names:
        raise ValueError("--steps: preview shows the table beside its best fit: it needs the fit step")
    return tuple(s for s in STEPS if s in names)


def check_settings(settings: Settings) -> None:
    """Every value checked before the first task starts (ValueError naming the option)."""
    for name in settings.models:
        model, _, k = name.partition(":")
        if k and not (k.isdigit() and 1 <= int(k) <= 3):
            raise ValueError(f"--models: '{name}': the lobe count after ':' must be 1, 2 or 3")
        if ALIASES.get(model, model) not in MODELS:
            raise ValueError(f"--models: unknown model '{model}' (known: {', '.join(MODELS)})")
    if not settings.models:
        raise ValueError("--models: at least one model")
    if settings.loss not in LOSSES:
        raise ValueError(f"--loss: unknown loss '{settings.loss}' (known: {', '.join(LOSSES)})")
    for option, value, lo, hi in (
        ("--starts", settings.starts, 1, 64),
        ("--seed", settings.seed, 0, 2**63 - 1),
        ("--width", settings.width, 1, MAX_SIDE),
        ("--height", settings.height, 1, MAX_SIDE),
        ("--spp", settings.spp, 1, MAX_SPP),
    ):
        if not lo <= value <= hi:
            raise ValueError(f"{option}: {value} is not in {lo} .. {hi}")
    if settings.shape not in ("ball", "sphere", "panel") and not os.path.isfile(settings.shape):
        raise ValueError(f"--shape: '{settings.shape}' is not one of ball, sphere, panel nor a mesh file")
    if settings.env and not os.path.isfile(settings.env):
        raise ValueError(f"--env: {settings.env}: no such file")


_HIDDEN = re.compile(r"^\.|~$")  # dot-files (our own temporaries among them) and editor backups
# Files a library keeps beside its tables (provenance notes, images, scenes, luminaires): never
# tables, though a note that mentions ASTM would pass detect_format's look at the content.
NOT_TABLES = frozenset(
    ".md .rst .html .htm .json .yaml .yml .toml .pdf .png .jpg .jpeg .exr .hdr .tif .tiff "
    ".ies .ldt .obj .ply .stl .py .sh .zip .gz".split()
)


def find_tables(folder: str) -> tuple[list[Material], list[tuple[str, str]]]:
    """(the tables, [(file, why skipped)]) in `folder`, by name; not recursive (an output
    folder inside the library is not read as input). ValueError if the folder is missing."""
    if not os.path.isdir(folder):
        what = "is not a folder" if os.path.exists(folder) else "no such folder"
        raise ValueError(f"{folder}: {what} (the library of tables to process)")
    tables, skipped = [], []
    for name in sorted(os.listdir(folder)):
        path = os.path.abspath(os.path.join(folder, name))
        if _HIDDEN.search(name):
            continue
        if os.path.isdir(path):
            skipped.append((name, "a folder (libraries are read one level deep)"))
            continue
        kind = not_a_regular_file(path)
        if kind:  # a FIFO's open waits for a writer forever, /dev/zero never ends: only files are read
            skipped.append((name, f"not a regular file ({kind})"))
            continue
        extension = os.path.splitext(name)[1].lower()
        if extension in NOT_TABLES:
            skipped.append((name, f"not a table (a {extension} file)"))
            continue
        try:
            detect_format(path, confirm=True)  # by content: a library's other .xml or .bin is no table
        except FormatError as e:
            skipped.append((name, e.problem))
            continue
        tables.append(Material(name, path))
    return tables, skipped
