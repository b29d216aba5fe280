"""A material as an RGL tensor file (`--to rgl`), and a measured table as Mitsuba 3's and
pbrt-v4's `measured` material reading the tensor file written beside the scene file.

The tensor file is written by patina.export.rgl (read back against the source before it is
written). The scene files name it by its base name: Mitsuba resolves it against the folder of
the XML, pbrt-v4 against the folder of the scene file. Where the `mitsuba` package is
installed, Mitsuba's own `measured` plugin evaluates the written file at direction pairs and
that is compared with the source (`target_error_against_source`): a spectral file in
`scalar_spectral` at four wavelengths against the source's RGB upsampled the same way, an RGB
file in `scalar_rgb`; Mitsuba's `eval` includes cos(theta_o), as the file's values do
(patina.export.rgl), and is divided by it here."""

from __future__ import annotations

import importlib.util
import os
import xml.etree.ElementTree as ET
from typing import Any

import numpy as np

from patina.atomic import write_text
from patina.export.rgb_upsampling import upsample
from patina.export.rgl import RglSource, check_pairs, table_source, write_rgl_file
from patina.export.source import Source
from patina.fitting.metrics import relative_errors

MEASURED_TARGETS = ("mitsuba", "pbrt")  # the targets holding a table as `measured`
MITSUBA_WAVELENGTHS = np.array([450.0, 520.0, 600.0, 680.0])  # nm: scalar_spectral's four at a time
TARGET_PAIRS = 1000


def tensor_path(target: str, out: str) -> str:
    """The .bsdf written: `out` itself for rgl, else beside `out` with its stem."""
    return out if target == "rgl" else os.path.splitext(out)[0] + ".bsdf"


def rgl_source(source: Source) -> RglSource:
    if source.table is not None:
        return table_source(source.table, source.path)
    return RglSource(source.path, lambda wi, wo: np.asarray(source.evaluate(wi, wo), np.float64))


def mitsuba_measured_xml(name: str, filename: str, source: str, two_sided: bool = False) -> str:
    """A Mitsuba 3 scene file with the `measured` BSDF (id = name), inside `twosided` for a
    two-sided material (`measured` reflects on its front side only)."""
    scene = ET.Element("scene", version="3.5.0")
    outer = ET.SubElement(scene, "bsdf", type="twosided" if two_sided else "measured", id=name)
    measured = ET.SubElement(outer, "bsdf", type="measured") if two_sided else outer
    ET.SubElement(measured, "string", name="filename", value=filename)
    ET.indent(scene)
    said = f"{name}: exported by patina export from {source}".replace("--", "- -")  # '--' ends no comment
    comment = f"<!-- {said} (a spectral file needs a spectral variant) -->\n"
    return comment + ET.tostring(scene, encoding="unicode") + "\n"


def pbrt_measured(name: str, filename: str, source: str) -> str:
    return (
        f"# {name}: exported by patina export from {source}\n"
        f'MakeNamedMaterial "{name}"\n    "string type" "measured"\n    "string filename" "{filename}"\n'
    )


def mitsuba_measured_eval(path: str, wi: np.ndarray, wo: np.ndarray, spectral: bool) -> np.ndarray:
    """Mitsuba 3's `measured` plugin's own evaluation of the file at (n, 3) local pairs, as a
    BRDF (its `eval` divided by cos(theta_o)): (n, 4) at MITSUBA_WAVELENGTHS (scalar_spectral)
    or (n, 3) RGB (scalar_rgb)."""
    import mitsuba as mi

    mi.set_variant("scalar_spectral" if spectral else "scalar_rgb")
    bsdf = mi.load_dict({"type": "measured", "filename": os.path.abspath(path)})
    ctx = mi.BSDFContext()
    si = mi.SurfaceInteraction3f()
    si.sh_frame = mi.Frame3f(mi.Vector3f(0, 0, 1))
    if spectral:
        si.wavelengths = mi.Spectrum(*MITSUBA_WAVELENGTHS)
    out = np.zeros((len(wi), 4 if spectral else 3))
    for j in range(len(wi)):
        si.wi = mi.Vector3f(*wi[j])
        out[j] = np.array(bsdf.eval(ctx, si, mi.Vector3f(*wo[j]))) / wo[j, 2]
    return out


def in_mitsuba(path: str, source: RglSource, spectral: bool) -> dict[str, Any] | None:
    """The written file as Mitsuba evaluates it against the source; None without the package."""
    if importlib.util.find_spec("mitsuba") is None:
        return None
    wi, wo = check_pairs(85.0)
    wi, wo = wi[:TARGET_PAIRS], wo[:TARGET_PAIRS]
    got = mitsuba_measured_eval(path, wi, wo, spectral)
    want = source.rgb(wi, wo)
    if spectral:
        want = upsample(want, MITSUBA_WAVELENGTHS)
        if source.spectral is not None:  # the table's own spectra, interpolated in wavelength
            values = source.spectral(wi, wo)
            want = np.stack([np.interp(MITSUBA_WAVELENGTHS, source.wavelengths, v) for v in values])
    rel = relative_errors(want, got).max(axis=1)
    return {
        "evaluator": f"mitsuba {'scalar_spectral' if spectral else 'scalar_rgb'} measured",
        "relative_error_median": float(np.median(rel)),
        "relative_error_p95": float(np.percentile(rel, 95)),
        "pairs": len(wi),
    }


def export_measured(source: Source, target: str, out: str, channels: str, progress: bool) -> dict[str, Any]:
    """Writes the tensor file (and for mitsuba / pbrt the scene file naming it); the sidecar's
    contents."""
    tensor = tensor_path(target, out)
    rgl = rgl_source(source)
    report = write_rgl_file(rgl, tensor, channels, progress=progress)
    filename = os.path.basename(tensor)
    if target == "mitsuba":
        write_text(out, mitsuba_measured_xml(source.name, filename, source.path, source.two_sided))
    elif target == "pbrt":
        write_text(out, pbrt_measured(source.name, filename, source.path))
    in_target = in_mitsuba(tensor, rgl, channels == "spectral") if target in ("mitsuba", "rgl") else None
    notes = []
    if target == "mitsuba" and channels == "spectral":
        notes.append("measured with a spectral file: load it in a spectral variant (scalar_spectral, llvm_ad_spectral)")
    return {
        "target": target,
        "out": os.fspath(out),
        "tensor_file": tensor,
        "source": source.path,
        "source_model": source.model,
        "material": {"type": "measured", "tensor_file": report},
        "refitted": False,
        "error_against_source": report["read_back_error"],
        "target_error_against_source": in_target,
        "notes": notes,
    }
