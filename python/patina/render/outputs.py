"""A render's outputs: the float EXR (beauty, AOVs, metadata), the tone-mapped PNG, and the
exposure that tone-maps it; each file written to a temporary file and renamed."""

from __future__ import annotations

import json

import numpy as np

from patina.colour_constants import luminance
from patina.native import _core
from patina.render.images import write_exr, write_png
from patina.render.run import RenderResult
from patina.scene.types import Scene
from patina.scene.writing import scene_to_json


def auto_exposure(rgb: np.ndarray) -> float:
    """Stops that bring the image's log-average luminance to 0.18 (Reinhard's key value)."""
    y = luminance(rgb)
    y = y[np.isfinite(y) & (y > 0)]
    if y.size == 0:
        return 0.0
    return float(np.log2(0.18 / np.exp(np.mean(np.log(y)))))


def metadata(scene: Scene, result: RenderResult) -> dict[str, str | float | int]:
    """The EXR header attributes of a render. EXR ints are 32-bit: counts that can exceed
    that (rays: billions in a long render; the seed: up to 2^63 - 1) are decimal strings,
    always, so a reader sees one type whatever the value."""
    meta: dict[str, str | float | int] = {
        "patina:version": _core.__version__,
        "patina:scene": json.dumps(scene_to_json(scene), separators=(",", ":")),
        "patina:scene_file": scene.path,
        "patina:spp": int(result.spp),
        # rounded: the adaptive sampler's weights sum to 1 a pass only up to float rounding
        "patina:samples_min": round(float(result.samples.min())) if result.samples.size else 0,
        "patina:integrator": scene.render.integrator,
        "patina:seed": str(int(scene.render.seed)),
        "patina:seconds": float(result.seconds),
        "patina:rays": str(int(result.rays)),
        "patina:simd_width": int(result.simd_width),
        "patina:threads": int(result.threads),
        "patina:complete": int(result.complete),
        "patina:aa": result.aa,
        "patina:sampler": result.sampler,
    }
    if scene.render.integrator in ("cache", "cache-guided"):
        meta["patina:cache_points"] = str(int(result.cache_points))
        meta["patina:cache_queries"] = str(int(result.cache_queries))
        meta["patina:cache_texels_reprojected"] = str(int(result.cache_texels_reprojected))
        meta["patina:cache_texels_traced"] = str(int(result.cache_texels_traced))
    if result.aa_level is not None:
        # docs/antialiasing.md: camera rays a pixel a pass (the patterns traced: the weight sums)
        meta["patina:aa_threshold"] = float(result.aa_threshold)
        meta["patina:aa_rays_per_pixel"] = float(result.camera_rays / max(float(result.samples.sum()), 1.0))
        for level in (1, 2, 3):
            meta[f"patina:aa_level{level}_fraction"] = float(np.mean(result.aa_level == level))
    return meta


def write_outputs(
    scene: Scene,
    result: RenderResult,
    exr_path: str | None,
    png_path: str | None,
    exposure: float = 0.0,
    curve: str = "filmic",
) -> None:
    """The EXR (beauty and AOVs, metadata) and the tone-mapped image (PNG or JPEG, by its
    extension), each written atomically; None skips one."""
    if exr_path:
        depth = np.where(np.isfinite(result.depth), result.depth, 0.0).astype(np.float32)
        layers = {
            "beauty": result.rgb,
            "albedo": result.albedo,
            "normal": result.normal,
            "depth": depth,
            "illuminance": result.illuminance,
        }
        if result.aa_rays is not None:
            layers["aa_rays"] = result.aa_rays  # the adaptive sampler's rays a pixel a pass
        write_exr(exr_path, layers, metadata(scene, result))
    if png_path:
        write_png(png_path, result.rgb, exposure_stops=exposure, curve=curve)
