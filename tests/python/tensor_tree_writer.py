"""Radiance tensor-tree BSDF XML written from a known BRDF, from the format's definition
(Radiance's bsdf_t.c, bsdf.c: Shirley-Chiu squares, child n holding the halves named by
its bits, leaves in C order), independently of the reader: for the tests."""

from __future__ import annotations

import numpy as np

UNUSED = 99.0  # the upper half of a TensorTree3's first dimension: never to be read


def square_to_disk(sx: np.ndarray, sy: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Shirley and Chiu's concentric map (Radiance's SDsquare2disk)."""
    a, b = 2 * sx - 1, 2 * sy - 1
    with np.errstate(divide="ignore", invalid="ignore"):
        region = np.select([(a > -b) & (a > b), a > -b, a < b], [1, 2, 3], 4)
        r = np.choose(region - 1, [a, b, -a, -b])
        phi = np.choose(
            region - 1, [np.pi / 4 * (b / a), np.pi / 4 * (2 - a / b), np.pi / 4 * (4 + b / a), np.pi / 4 * (6 - a / b)]
        )
    phi = np.where(r == 0, 0.0, phi)
    return r * np.cos(phi), r * np.sin(phi)


def _direction(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    return np.stack([x, y, np.sqrt(np.clip(1 - x * x - y * y, 0, 1))], axis=1)


def cell_centres(dims: int, log2: int) -> np.ndarray:
    """The centres (N, dims) of a (2^log2)^dims grid, C order."""
    n = 1 << log2
    axes = [(np.arange(n) + 0.5) / n] * dims
    return np.stack([m.ravel() for m in np.meshgrid(*axes, indexing="ij")], axis=1)


def tree_directions(dims: int, g: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The direction pairs (wi, wo) at tree positions g (N, dims)."""
    if dims == 4:
        wi = _direction(*(-v for v in square_to_disk(g[:, 0], g[:, 1])))
        wo = _direction(*square_to_disk(g[:, 2], g[:, 3]))
    else:  # wi at azimuth 180 degrees, sin(theta_i) = 1 - 2 g0 on the used half
        s = np.clip(1 - 2 * g[:, 0], 0, 1)
        wi = _direction(-s, np.zeros_like(s))
        wo = _direction(*square_to_disk(g[:, 1], g[:, 2]))
    return wi, wo


def tree_grid(f, dims: int, log2: int, channel: int = 0) -> np.ndarray:
    """f (wi, wo) -> (N, channels) at the cell centres, as a (2^log2,)*dims array."""
    g = cell_centres(dims, log2)
    values = f(*tree_directions(dims, g))[:, channel]
    if dims == 3:
        values = np.where(g[:, 0] < 0.5, values, UNUSED)
    return values.reshape((1 << log2,) * dims)


def tree_text(grid: np.ndarray, branch_levels: int) -> str:
    """The grid as a tree: `branch_levels` levels of branches, then leaf grids (a uniform one
    written as its single value)."""
    dims = grid.ndim
    if branch_levels == 0:
        flat = grid.ravel()
        if np.all(flat == flat[0]):
            flat = flat[:1]
        return "{ " + " ".join(f"{v:.7g}" for v in flat) + " }"
    half = grid.shape[0] // 2
    parts = []
    for n in range(1 << dims):
        index = tuple(slice(half, None) if n >> i & 1 else slice(0, half) for i in range(dims))
        parts.append(tree_text(grid[index], branch_levels - 1))
    return "{\n" + ",\n".join(parts) + "\n}"


def tree_document(blocks: list[tuple[str, str, str]], rank: int, basis: str = "LBNL/Shirley-Chiu") -> str:
    """A WindowElement document; blocks: (direction, wavelength label, tree text)."""
    data = "".join(
        f"<WavelengthData><LayerNumber>System</LayerNumber><Wavelength unit='Integral'>{label}</Wavelength>"
        f"<SourceSpectrum>CIE Illuminant D65 1nm.ssp</SourceSpectrum><WavelengthDataBlock>"
        f"<WavelengthDataDirection>{direction}</WavelengthDataDirection><AngleBasis>{basis}</AngleBasis>"
        f"<ScatteringDataType>BRDF</ScatteringDataType><ScatteringData>{tree}</ScatteringData>"
        "</WavelengthDataBlock></WavelengthData>"
        for direction, label, tree in blocks
    )
    return (
        "<?xml version='1.0' encoding='UTF-8'?>\n<WindowElement xmlns='http://windows.lbl.gov'>"
        "<WindowElementType>System</WindowElementType><Optical><Layer><Material><Name>tree</Name></Material>"
        f"<DataDefinition><IncidentDataStructure>TensorTree{rank}</IncidentDataStructure></DataDefinition>"
        f"{data}</Layer></Optical></WindowElement>\n"
    )
