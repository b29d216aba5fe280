"""LBNL WINDOW / Radiance BSDF XML (the `WindowElement` schema of LBNL's WINDOW 6 and
Radiance's genBSDF), Klems-type bases: the reflection blocks of one side as a table.

The document is parsed with the standard library's XML parser (a stray line before
`<?xml`, as some tools write, is dropped, as Radiance does). The angle basis comes from
the file's own `AngleBasis` (Klems full, half, quarter: rings of theta bounds, each cut
into nPhis patches, the first centred on phi = 0). `ScatteringData` holds one value per
(outgoing, incident) patch pair, the incident index fastest for the default
`IncidentDataStructure` "Columns" (the other way round for "Rows"); values are the BSDF
in 1/sr, averaged over the patches, no cosine. Reflection is expressed in the mirrored
outgoing basis (a mirror's matrix is diagonal), so an outgoing direction (theta, phi) is
in the patch that holds (theta, phi + 180 deg).

Blocks of WavelengthDataDirection "Reflection Front" (or "Reflection Back": `side`) are
kept: X, Y and Z detector blocks together as an XYZ table, otherwise the visible (or the
first) one as a single channel; transmission blocks and the rest are listed in the
provenance as skipped. Tensor-tree documents (TensorTree3, TensorTree4: Radiance's
variable-resolution trees on Shirley-Chiu squares) are read by `tensor_tree.py` and
resampled by `tensor_tree_table.py`. The Klems patch function is evaluated onto an
anisotropic grid whose knots are the ring centres and every patch centre's azimuth, and
the resampling error is reported.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from dataclasses import dataclass

import numpy as np

from patina.errors import FormatError
from patina.file_names import printable
from patina.table.formats.resample import relative_error
from patina.table.formats.tabledata import TableData
from patina.table.formats.tensor_tree import parse_tree
from patina.table.formats.tensor_tree_table import tree_table
from patina.table.formats.whole_file import read_whole_file

MAX_FILE_BYTES = 256 << 20
MAX_PATCHES = 10000
TREE_RANKS = {"tensortree3": 3, "tensortree4": 4}
TREE_BASIS = "LBNL/Shirley-Chiu"
ERROR_PAIRS = 8192


@dataclass
class AngleBasis:
    name: str
    centres: np.ndarray  # ring centre theta, degrees
    lower: np.ndarray  # ring bounds, degrees
    upper: np.ndarray
    phis: np.ndarray  # patches per ring

    @property
    def size(self) -> int:
        return int(self.phis.sum())

    def index(self, theta_deg: np.ndarray, phi_deg: np.ndarray) -> np.ndarray:
        """The patch holding each direction (theta, phi in degrees)."""
        ring = np.clip(np.searchsorted(self.upper, theta_deg, side="left"), 0, self.centres.size - 1)
        n = self.phis[ring]
        width = 360.0 / n
        k = np.floor(np.mod(phi_deg + width / 2, 360.0) / width).astype(np.int64) % n
        offsets = np.concatenate([[0], np.cumsum(self.phis)[:-1]])
        return offsets[ring] + k


def _local(tag: str) -> str:
    return tag.rsplit("}", 1)[-1]


def _children(node: ET.Element, name: str) -> list[ET.Element]:
    return [c for c in node if _local(c.tag) == name]


def _child(node: ET.Element, name: str) -> ET.Element | None:
    found = _children(node, name)
    return found[0] if found else None


def _text(node: ET.Element | None) -> str:
    return "" if node is None or node.text is None else node.text.strip()


def _parse(path: str, raw: bytes) -> ET.Element:
    start = raw.find(b"<")
    if start < 0:
        raise FormatError(path, "line 1", "no XML element: not a BSDF XML document")
    skipped = raw[:start].count(b"\n")
    try:
        root = ET.fromstring(raw[start:])
    except ET.ParseError as e:
        line, column = e.position
        problem = str(e).split(":")[0]
        raise FormatError(
            path, f"line {line + skipped}, column {column + 1}", f"not well-formed XML ({problem})"
        ) from None
    except LookupError as e:  # the declaration names an encoding Python does not know
        raise FormatError(path, f"line {skipped + 1}", f"the XML declaration's {e}") from None
    if _local(root.tag) != "WindowElement":
        raise FormatError(path, "root element", f"<{_local(root.tag)}>: expected <WindowElement> (a BSDF XML document)")
    return root


def _number(path: str, node: ET.Element | None, name: str, where: str) -> float:
    try:
        value = float(_text(node))
    except ValueError:
        raise FormatError(path, where, f"<{name}> '{_text(node)[:40]}' is not a number") from None
    if not math.isfinite(value):
        raise FormatError(path, where, f"<{name}> is not finite")
    return value


def _bases(path: str, layer: ET.Element) -> tuple[dict[str, AngleBasis], str]:
    bases = {}
    definition = _child(layer, "DataDefinition")
    if definition is None:
        raise FormatError(path, "Layer", "no <DataDefinition>")
    structure = _text(_child(definition, "IncidentDataStructure")) or "Columns"
    if structure.lower() in TREE_RANKS:
        return bases, structure  # a tree's basis is named in each block
    if structure.lower().startswith("tensortree"):
        raise FormatError(path, "IncidentDataStructure", f"{structure}: expected TensorTree3 or TensorTree4")
    for basis in _children(definition, "AngleBasis"):
        name = _text(_child(basis, "AngleBasisName"))
        rows = []
        for b, block in enumerate(_children(basis, "AngleBasisBlock")):
            where = f"AngleBasis '{name}' block {b + 1}"
            bounds = _child(block, "ThetaBounds")
            if bounds is None:
                raise FormatError(path, where, "no <ThetaBounds>")
            rows.append(
                (
                    _number(path, _child(block, "Theta"), "Theta", where),
                    _number(path, _child(bounds, "LowerTheta"), "LowerTheta", where),
                    _number(path, _child(bounds, "UpperTheta"), "UpperTheta", where),
                    _number(path, _child(block, "nPhis"), "nPhis", where),
                )
            )
        a = np.array(rows, dtype=np.float64).reshape(-1, 4)
        if a.size == 0:
            raise FormatError(path, f"AngleBasis '{name}'", "no <AngleBasisBlock>")
        phis = a[:, 3]
        if np.any(phis < 1) or np.any(phis != np.round(phis)) or phis.sum() > MAX_PATCHES:
            raise FormatError(path, f"AngleBasis '{name}'", f"nPhis must be whole numbers >= 1, {MAX_PATCHES} at most")
        if np.any(np.diff(a[:, 2]) <= 0) or a[0, 1] < 0 or a[-1, 2] > 90.0 + 1e-6:
            raise FormatError(path, f"AngleBasis '{name}'", "theta bounds must increase within [0, 90] degrees")
        bases[name] = AngleBasis(name, a[:, 0], a[:, 1], a[:, 2], phis.astype(np.int64))
    return bases, structure


def _matrix(path: str, block: ET.Element, where: str, rows: AngleBasis, cols: AngleBasis, structure: str) -> np.ndarray:
    text = _text(_child(block, "ScatteringData"))
    try:
        values = np.array([float(v) for v in text.replace(",", " ").split()], dtype=np.float64)
    except ValueError as e:
        raise FormatError(path, f"{where} ScatteringData", f"not a list of numbers ({e})") from None
    expected = rows.size * cols.size
    if values.size != expected:
        raise FormatError(
            path, f"{where} ScatteringData", f"{values.size} values: expected {rows.size} x {cols.size} = {expected}"
        )
    bad = ~np.isfinite(values) | (values < 0)
    if bad.any():
        first = int(np.argmax(bad))
        raise FormatError(
            path, f"{where} ScatteringData value {first + 1}", f"{values[first]:g}: negative or not finite"
        )
    # [outgoing, incident]
    if structure.lower() == "rows":
        return values.reshape(cols.size, rows.size).T
    return values.reshape(rows.size, cols.size)


def _tree(path: str, block: ET.Element, where: str, dims: int):
    basis = _text(_child(block, "AngleBasis"))
    if basis.lower() != TREE_BASIS.lower():
        raise FormatError(path, f"{where} AngleBasis", f"'{basis[:40]}': a tensor tree needs {TREE_BASIS}")
    return parse_tree(_text(_child(block, "ScatteringData")), dims, path, f"{where} ScatteringData")


def _grid_axes(basis: AngleBasis) -> list[np.ndarray]:
    theta = np.radians(np.unique(np.concatenate([basis.centres, [basis.upper[-1] - 1e-3]])))
    centres = [k * 360.0 / n for n in np.unique(basis.phis) for k in range(int(n))]
    phi = np.radians(np.unique(np.round(np.concatenate([centres, [360.0]]), 9)))
    return [theta, phi, theta, phi]


def read_window_xml(path: str, side: str = "front") -> TableData:
    """The reflection blocks of `side` ("front" or "back") as a table (see the module's text)."""
    if side not in ("front", "back"):
        raise ValueError(f"side '{side}': expected front or back")
    root = _parse(path, read_whole_file(path, MAX_FILE_BYTES))
    layer = next((n for n in root.iter() if _local(n.tag) == "Layer"), None)
    if layer is None:
        raise FormatError(path, "Optical", "no <Layer>: not a BSDF document")
    bases, structure = _bases(path, layer)
    wanted = f"reflection {side}"
    kept: dict[str, np.ndarray] = {}
    skipped: list[str] = []
    basis = None
    for d, data in enumerate(n for n in layer.iter() if _local(n.tag) == "WavelengthData"):
        label = _text(_child(data, "Wavelength")) or "?"
        detector = _text(_child(data, "DetectorSpectrum"))
        for b, block in enumerate(_children(data, "WavelengthDataBlock")):
            direction = " ".join(_text(_child(block, "WavelengthDataDirection")).lower().split())
            name = f"{direction or '?'} ({label}{', ' + detector if detector else ''})"
            if direction != wanted:
                skipped.append(name)
                continue
            where = f"WavelengthData {d + 1} block {b + 1}"
            key = _channel_key(label, detector)
            if structure.lower() in TREE_RANKS:
                kept.setdefault(key, _tree(path, block, where, TREE_RANKS[structure.lower()]))
                continue
            row_name = _text(_child(block, "RowAngleBasis"))
            col_name = _text(_child(block, "ColumnAngleBasis"))
            for n in (row_name, col_name):
                if n not in bases:
                    raise FormatError(path, where, f"angle basis '{n}' is not defined in <DataDefinition>")
            if row_name != col_name:
                raise FormatError(path, where, "row and column bases differ: not read")
            basis = bases[row_name]
            kept.setdefault(key, _matrix(path, block, where, basis, basis, structure))
    if not kept:
        transmission = [s for s in skipped if s.startswith("transmission")]
        other = "back" if side == "front" else "front"
        has_other = (s.startswith(f"reflection {other}") for s in skipped)
        raise FormatError(
            path,
            "WavelengthData",
            f"no '{wanted.title()}' block"
            + (f" (only {', '.join(sorted(set(skipped)))[:200]})" if skipped else "")
            + (": Patina tables are reflection" if transmission and len(transmission) == len(skipped) else "")
            + (f"; name {printable(path)}#{other} for its {other} side" if any(has_other) else ""),
        )
    if all(k in kept for k in ("X", "Y", "Z")):
        channels, kind = [kept["X"], kept["Y"], kept["Z"]], "xyz"
        skipped += [f"{wanted} ({k})" for k in kept if k not in ("X", "Y", "Z")]
    else:
        key = "Y" if "Y" in kept else next(iter(kept))
        channels, kind = [kept[key]], "mono"
        skipped += [f"{wanted} ({k})" for k in kept if k != key]
    if structure.lower() in TREE_RANKS:
        description = f"BSDF XML ({structure}, {TREE_BASIS}, {wanted}, {kind})"
        data = tree_table(channels, kind, description)
        if skipped:
            data.provenance += f"; skipped: {', '.join(dict.fromkeys(skipped))}"[:400]
        return data
    matrix = np.stack(channels, axis=-1)  # (outgoing, incident, channels)
    axes = _grid_axes(basis)
    ti, pi, to, po = np.meshgrid(*[np.degrees(a) for a in axes], indexing="ij")
    values = matrix[basis.index(to.ravel(), po.ravel() + 180.0), basis.index(ti.ravel(), pi.ravel())]
    values = values.reshape(*ti.shape, len(channels))
    err = _resampling_error(basis, matrix, axes, values)
    notes = [
        f"BSDF XML ({basis.name}, {basis.size} patches, {wanted}, {kind})",
        f"patch values onto an anisotropic {' x '.join(str(a.size) for a in axes)} grid at the patch centres; "
        f"relative difference to the patch function at {ERROR_PAIRS} pairs: median {err[0]:.3g}, 95% {err[1]:.3g}",
    ]
    if skipped:
        notes.append(f"skipped: {', '.join(dict.fromkeys(skipped))}"[:400])
    return TableData(
        parametrization="anisotropic",
        axes=axes,
        values=values.astype(np.float32),
        channel_kind=kind,
        provenance="; ".join(notes),
    )


def _channel_key(label: str, detector: str) -> str:
    """X, Y or Z for the CIE detector blocks, Y for the photopic 'Visible', else the label."""
    d = detector.upper()
    for key in ("X", "Y", "Z"):
        if f"1931 {key}" in d or d.endswith(f"CIE-{key}") or label.upper() in (f"CIE-{key}", f"CIE {key}"):
            return key
    return "Y" if label.lower() == "visible" else label


def _resampling_error(basis: AngleBasis, matrix: np.ndarray, axes: list[np.ndarray], values: np.ndarray) -> tuple:
    """Median and 95th percentile of the table's linear interpolation against the patch function."""
    from scipy.interpolate import RegularGridInterpolator

    rng = np.random.default_rng(29)
    hi = math.degrees(axes[0][-1])
    ti, to = rng.uniform(0, hi, (2, ERROR_PAIRS))
    pi, po = rng.uniform(0, 360, (2, ERROR_PAIRS))
    want = matrix[basis.index(to, po + 180.0), basis.index(ti, pi)]
    got = RegularGridInterpolator(axes, values)(np.radians(np.stack([ti, pi, to, po], axis=1)))
    err = relative_error(got, want)
    return err["median"], err["p95"]
