"""Writes benchmark meshes for the kd-tree build comparison (run.sh) as raw binary files.

Each file: int64 vertex count V, int64 triangle count T, V x 3 float32, T x 3 int32.
"""

import sys
from pathlib import Path

import numpy as np

from patina.geometry import benchmark_geometry as bg

MESHES = {
    "sphere1m": lambda: bg.sphere_of(1_000_000),
    "sphere200k": lambda: bg.sphere_of(200_000),
    "boxes200k": lambda: bg.box_field(200_000),
    "icosphere80k": bg.icosphere,
}


def main() -> None:
    out = Path(sys.argv[1])
    out.mkdir(parents=True, exist_ok=True)
    for name, make in MESHES.items():
        mesh = make()
        v = np.ascontiguousarray(mesh.vertices, np.float32)
        i = np.ascontiguousarray(mesh.indices, np.int32)
        with open(out / f"{name}.bin", "wb") as f:
            np.array([len(v), len(i)], np.int64).tofile(f)
            v.tofile(f)
            i.tofile(f)
        print(name, len(i), "triangles")


if __name__ == "__main__":
    main()
