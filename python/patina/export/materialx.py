"""MaterialX: an OpenPBR Surface (or Autodesk Standard Surface) document, written with the
`materialx` package and checked with its validate() against the standard libraries."""

from __future__ import annotations

from patina.export.material import AnalyticMaterial
from patina.export.principled import Principled, principled

# OpenPBR input -> Standard Surface input, for the parameters Patina writes
STANDARD_SURFACE = {
    "base_weight": "base",
    "base_color": "base_color",
    "base_metalness": "metalness",
    "specular_weight": "specular",
    "specular_color": "specular_color",
    "specular_ior": "specular_IOR",
    "specular_roughness": "specular_roughness",
    "coat_weight": "coat",
    "coat_roughness": "coat_roughness",
    "coat_ior": "coat_IOR",
}


def _inputs(p: Principled) -> dict[str, object]:
    return {
        "base_weight": 1.0,
        "base_color": p.base_color,
        "base_metalness": p.metalness,
        "specular_weight": p.specular_weight,
        "specular_color": p.specular_color,
        "specular_ior": p.specular_ior,
        "specular_roughness": p.specular_roughness,
        "coat_weight": p.coat_weight,
        "coat_roughness": p.coat_roughness,
        "coat_ior": p.coat_ior,
    }


def _libraries():
    import MaterialX as mx

    libs = mx.createDocument()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), libs)
    return libs


def materialx_document(material: AnalyticMaterial, shading_model: str = "open_pbr_surface", notes=None):
    """The MaterialX document (mx.Document with the standard libraries imported)."""
    import MaterialX as mx

    p = principled(material)
    if notes is not None:
        notes.extend(p.notes)
    doc = mx.createDocument()
    doc.importLibrary(_libraries())
    shader = doc.addNode(shading_model, f"{material.name}_shader", "surfaceshader")
    for key, value in _inputs(p).items():
        name = STANDARD_SURFACE[key] if shading_model == "standard_surface" else key
        if isinstance(value, tuple):
            shader.setInputValue(name, mx.Color3(*[float(c) for c in value]), "color3")
        else:
            shader.setInputValue(name, float(value), "float")
    doc.addMaterialNode(material.name, shader)
    return doc


def to_materialx(material: AnalyticMaterial, shading_model: str = "open_pbr_surface", notes=None) -> str:
    """The .mtlx text (the libraries are referenced, not written); ValueError if validate() fails."""
    import MaterialX as mx

    doc = materialx_document(material, shading_model, notes)
    valid, message = doc.validate()
    if not valid:
        raise ValueError(f"MaterialX validate() refused the document: {message.strip()}")
    options = mx.XmlWriteOptions()
    options.writeXIncludeEnable = False
    options.elementPredicate = lambda element: not element.hasSourceUri()  # the document's own elements only
    return mx.writeToXmlString(doc, options)
