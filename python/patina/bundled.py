"""Where the repository's bundled files (materials/: tables, maps, luminaires, scenes) are.

The package is usually built from a checkout and run from it: materials/ is beside the
package's source tree, or in the working directory. (The studio map `patina preview` needs
is also installed with the package: studio_environment.)
"""

from __future__ import annotations

import os

_SOURCE_TREE = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))


def materials_path(*parts: str) -> str:
    """The absolute path of materials/<parts...>: in the source tree, else the working directory."""
    for base in (_SOURCE_TREE, os.getcwd()):
        path = os.path.join(base, "materials", *parts)
        if os.path.exists(path):
            return os.path.abspath(path)
    raise FileNotFoundError(f"materials/{'/'.join(parts)} not found: run from the Patina checkout")


def studio_environment() -> str:
    """The bundled studio environment: installed with the package, else the repository's."""
    installed = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data", "studio.exr")
    if os.path.isfile(installed):
        return installed
    try:
        return materials_path("env", "studio.exr")
    except FileNotFoundError:
        raise FileNotFoundError("the bundled studio environment is missing; pass --env FILE") from None
