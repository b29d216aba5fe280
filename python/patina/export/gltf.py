"""glTF 2.0: a preview sphere carrying the material (metallic-roughness, with
KHR_materials_specular, _ior and _clearcoat where used), written with pygltflib as .gltf
(buffer embedded as a data URI) or .glb. glTF's clear coat has index 1.5 fixed."""

from __future__ import annotations

import numpy as np

from patina.export.material import AnalyticMaterial
from patina.export.principled import principled

SPHERE_RINGS, SPHERE_SEGMENTS = 32, 64


def sphere(rings: int = SPHERE_RINGS, segments: int = SPHERE_SEGMENTS) -> tuple[np.ndarray, np.ndarray]:
    """A unit UV sphere: (V, 3) float32 positions (also its normals), (T, 3) uint16 indices, counter-clockwise."""
    theta = np.linspace(0, np.pi, rings + 1)
    phi = np.linspace(0, 2 * np.pi, segments + 1)
    t, p = np.meshgrid(theta, phi, indexing="ij")
    positions = np.stack([np.sin(t) * np.cos(p), np.cos(t), -np.sin(t) * np.sin(p)], -1).reshape(-1, 3)
    faces = []
    for i in range(rings):
        for j in range(segments):
            a, b = i * (segments + 1) + j, (i + 1) * (segments + 1) + j
            if i > 0:
                faces.append((a, b, a + 1))
            if i < rings - 1:
                faces.append((a + 1, b, b + 1))
    return positions.astype(np.float32), np.asarray(faces, np.uint16)


def gltf_document(material: AnalyticMaterial, notes: list[str] | None = None):
    import pygltflib as g

    p = principled(material)
    notes = notes if notes is not None else []
    notes.extend(p.notes)
    positions, faces = sphere()
    normals = positions / np.linalg.norm(positions, axis=1, keepdims=True)
    blob = faces.tobytes() + positions.tobytes() + normals.astype(np.float32).tobytes()
    n_index, n_vertex = faces.nbytes, positions.nbytes
    extensions: dict[str, dict] = {}
    if p.specular_weight and not p.metalness:
        extensions["KHR_materials_ior"] = {"ior": p.specular_ior}
        extensions["KHR_materials_specular"] = {"specularFactor": 1.0, "specularColorFactor": list(p.specular_color)}
    if p.coat_weight:
        extensions["KHR_materials_clearcoat"] = {"clearcoatFactor": 1.0, "clearcoatRoughnessFactor": p.coat_roughness}
        if abs(p.coat_ior - 1.5) > 1e-3:
            notes.append(f"glTF's clear coat has index 1.5; the coat's {p.coat_ior:g} is not carried")
    mat = g.Material(
        name=material.name,
        pbrMetallicRoughness=g.PbrMetallicRoughness(
            baseColorFactor=[*p.base_color, 1.0], metallicFactor=p.metalness, roughnessFactor=p.specular_roughness
        ),
        doubleSided=material.two_sided,
        extensions=extensions,
    )
    doc = g.GLTF2(
        asset=g.Asset(version="2.0", generator="patina export"),
        scene=0,
        scenes=[g.Scene(nodes=[0])],
        nodes=[g.Node(mesh=0, name=f"{material.name}_sphere")],
        meshes=[
            g.Mesh(
                name="sphere",
                primitives=[g.Primitive(attributes=g.Attributes(POSITION=1, NORMAL=2), indices=0, material=0)],
            )
        ],
        materials=[mat],
        accessors=[
            g.Accessor(
                bufferView=0,
                componentType=g.UNSIGNED_SHORT,
                count=faces.size,
                type=g.SCALAR,
                max=[int(faces.max())],
                min=[int(faces.min())],
            ),
            g.Accessor(
                bufferView=1,
                componentType=g.FLOAT,
                count=len(positions),
                type=g.VEC3,
                max=positions.max(0).tolist(),
                min=positions.min(0).tolist(),
            ),
            g.Accessor(bufferView=2, componentType=g.FLOAT, count=len(normals), type=g.VEC3),
        ],
        bufferViews=[
            g.BufferView(buffer=0, byteOffset=0, byteLength=n_index, target=g.ELEMENT_ARRAY_BUFFER),
            g.BufferView(buffer=0, byteOffset=n_index, byteLength=n_vertex, target=g.ARRAY_BUFFER),
            g.BufferView(buffer=0, byteOffset=n_index + n_vertex, byteLength=n_vertex, target=g.ARRAY_BUFFER),
        ],
        buffers=[g.Buffer(byteLength=len(blob))],
        extensionsUsed=sorted(extensions),
    )
    doc.set_binary_blob(blob)
    return doc


def write_gltf(material: AnalyticMaterial, path: str, notes: list[str] | None = None) -> None:
    """Writes .glb (binary) or .gltf (JSON, the buffer as a data URI) to `path` as given
    (callers pass a temporary path: patina.atomic)."""
    doc = gltf_document(material, notes)
    if path.lower().endswith(".glb"):
        doc.save_binary(path)
    else:
        doc.convert_buffers(__import__("pygltflib").BufferFormat.DATAURI)
        doc.save_json(path)
