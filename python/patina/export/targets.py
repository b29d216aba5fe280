"""The export targets: what model each holds and how each writes a file (an RGL tensor file,
and a measured table for Mitsuba and pbrt, by patina.export.measured)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from patina.atomic import atomic_output, write_text
from patina.export.blender import to_blender_script
from patina.export.gltf import write_gltf
from patina.export.material import AnalyticMaterial
from patina.export.materialx import to_materialx
from patina.export.mitsuba import to_mitsuba_xml
from patina.export.pbrt import to_pbrt
from patina.export.usd import write_usd


@dataclass(frozen=True)
class Target:
    name: str
    max_lobes: int | None  # None: any number
    distributions: tuple[str, ...]
    suffixes: tuple[str, ...]
    write: Callable[[AnalyticMaterial, str, list[str], dict], None]  # (material, path, notes, options)


def _text(make: Callable[..., str]) -> Callable[[AnalyticMaterial, str, list[str], dict], None]:
    def write(material: AnalyticMaterial, path: str, notes: list[str], options: dict) -> None:
        write_text(path, make(material, notes=notes, **options))

    return write


def _file(make: Callable[..., None]) -> Callable[[AnalyticMaterial, str, list[str], dict], None]:
    def write(material: AnalyticMaterial, path: str, notes: list[str], options: dict) -> None:
        atomic_output(path, lambda tmp: make(material, tmp, notes))

    return write


def _materialx(material: AnalyticMaterial, notes: list[str], standard_surface: bool = False) -> str:
    return to_materialx(material, "standard_surface" if standard_surface else "open_pbr_surface", notes)


def _tensor_file(material: AnalyticMaterial, path: str, notes: list[str], options: dict) -> None:
    raise ValueError("an RGL tensor file is written from what the material evaluates to: patina.export.measured")


ONE_GGX = (1, ("ggx",))
TARGETS = {
    "mitsuba": Target("mitsuba", None, ("ggx", "beckmann"), (".xml",), _text(to_mitsuba_xml)),
    "pbrt": Target("pbrt", *ONE_GGX, (".pbrt",), _text(to_pbrt)),
    "materialx": Target("materialx", *ONE_GGX, (".mtlx",), _text(_materialx)),
    "gltf": Target("gltf", *ONE_GGX, (".gltf", ".glb"), _file(write_gltf)),
    "usd": Target("usd", *ONE_GGX, (".usda", ".usd", ".usdc"), _file(write_usd)),
    "blender": Target("blender", *ONE_GGX, (".py",), _text(to_blender_script)),
    "rgl": Target("rgl", None, ("ggx", "beckmann"), (".bsdf",), _tensor_file),  # patina.export.measured
}
