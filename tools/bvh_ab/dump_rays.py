"""Writes the trace bench's ray sets (bench/trace.py) and their meshes as raw files for driver.cpp.

Mesh files: int64 T, then T x 9 float32 corners. Ray files: int64 n, int64 any_hit (1 for
shadow rays), then n x 3 origins, n x 3 directions, n tmax (float32; inf for closest hits).
Run from the Patina checkout (the preview ball's recorded rays need its materials).
"""

import sys
from pathlib import Path

import numpy as np

from patina.bench import trace as bench
from patina.bench.ray_replay import recorded_preview
from patina.geometry import benchmark_geometry as scenes
from patina.geometry.accel import Accel
from patina.geometry.mesh import Mesh


def write_mesh(path: Path, mesh: Mesh) -> None:
    corners = np.ascontiguousarray(mesh.triangles(), np.float32).reshape(-1, 9)
    with open(path, "wb") as f:
        np.array([len(corners)], np.int64).tofile(f)
        corners.tofile(f)


def write_rays(path: Path, origins: np.ndarray, directions: np.ndarray, tmax: np.ndarray | None = None) -> None:
    n = len(origins)
    with open(path, "wb") as f:
        np.array([n, 0 if tmax is None else 1], np.int64).tofile(f)
        np.ascontiguousarray(origins, np.float32).tofile(f)
        np.ascontiguousarray(directions, np.float32).tofile(f)
        np.ascontiguousarray(np.full(n, np.inf) if tmax is None else tmax, np.float32).tofile(f)
    print(path.name, n, "rays")


def main() -> None:
    out = Path(sys.argv[1])
    out.mkdir(parents=True, exist_ok=True)
    for sc in bench._scenes(False)[:2]:  # icosphere, box field
        accel = Accel(sc.mesh)
        write_mesh(out / f"{sc.name}.mesh", sc.mesh)
        primary = scenes.pinhole_rays(sc.side, sc.side, sc.eye, sc.target, sc.fov_deg)
        if sc.name == "icosphere":
            write_rays(out / "primary.icosphere.rays", *primary)
        write_rays(out / f"random.{sc.name}.rays", *scenes.diffuse_bounce_rays(accel, primary, seed=4))
        if sc.name == "boxes":
            shadow, tmax = bench._shadow_rays(accel, primary, np.array([0.6, -0.4, 2.5]))
            write_rays(out / "shadow.boxes.rays", *shadow, tmax)
    rec = recorded_preview(False)
    write_mesh(out / "preview.mesh", rec.mesh)
    write_rays(out / "replay.path.rays", *rec.closest)
    write_rays(out / "replay.shadow.rays", *rec.shadow)
    write_mesh(out / "sphere1m.mesh", scenes.sphere_of(1_000_000))


if __name__ == "__main__":
    main()
