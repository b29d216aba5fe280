"""Draws the 3-D lobe scene written by patina.plot.lobes to a PNG, off-screen, with pyvista.

Run by patina.plot.lobes as `python lobes_render.py SCENE.npz OUT.png`, in a process of its own
because VTK can crash where no OpenGL context can be made. It needs only numpy and pyvista (not
patina's compiled core); a failure it can catch is one stderr line starting "lobe3d: " and
exit status 3.
"""

from __future__ import annotations

import json
import sys
from typing import Any

import numpy as np

CAMERA = [(1.6, -6.0, 3.0), (0.15, 0.0, 0.5), (0.0, 0.0, 1.0)]  # from -y: the mirror side (-x) is on the left
CMAP = "viridis"
WI_ARROW = (1.0, 1.6)  # the incidence arrow runs along wi from 1.6 (its tail) to 1.0 (its head)
NORMAL_LABEL = np.array([0.0, 0.0, 1.3])  # above the normal's arrow (length 1.25)
NORMAL_LABEL_ASIDE = np.array([0.3, 0.0, 1.15])  # beside it, right of the camera's view (+x)
NEAR_NORMAL_DEG = 20.0  # wi closer than this to n: its arrow would run through the normal's label


def label_anchors(wi: np.ndarray) -> dict[str, np.ndarray]:
    """Where each label of a panel is drawn: "n (z)" moves aside when wi is near the normal
    (at theta_i = 0 the wi arrow covers the normal's arrow and its label), to the +x side,
    away from the mirror direction, which leans to -x."""
    near = wi[2] > np.cos(np.radians(NEAR_NORMAL_DEG))
    labels = {
        "n (z)": NORMAL_LABEL_ASIDE if near else NORMAL_LABEL,
        "x": np.array([1.2, 0.0, 0.0]),
        "y": np.array([0.0, 1.2, 0.0]),
        "wi": 1.7 * wi,
    }
    if wi[0] > 1e-6:
        labels["mirror"] = 1.25 * np.array([-wi[0], -wi[1], wi[2]])
    return labels


def _grid(pv: Any, points: np.ndarray, values: np.ndarray | None = None) -> Any:
    grid = pv.StructuredGrid(points[..., 0], points[..., 1], points[..., 2])
    if values is not None:
        grid.point_data["value"] = values.ravel(order="F")  # StructuredGrid orders points Fortran-style
    return grid


def _panel(pv: Any, plotter: Any, scene: Any, meta: dict[str, Any], panel: dict[str, Any], k: int) -> None:
    key = f"{panel['row']}_{panel['col']}"
    wi = np.asarray(panel["wi"], dtype=np.float64)
    plotter.add_mesh(pv.Disc(inner=0.0, outer=1.0, c_res=72), color="lightgrey", opacity=0.35)
    plotter.add_mesh(
        _grid(pv, scene[f"points{key}"], scene[f"values{key}"]),
        scalars="value",
        cmap=CMAP,
        clim=panel["clim"],
        log_scale=bool(meta["log"]),
        smooth_shading=True,
        specular=0.0,
        ambient=0.35,
        scalar_bar_args={
            "title": meta["quantity"] + " " * k,  # pyvista keys colour bars by title: one per panel
            "n_labels": 3,
            "fmt": "%.3g",
            "title_font_size": 12,
            "label_font_size": 11,
            "color": "black",
            "position_x": 0.2,
            "position_y": 0.08,
            "width": 0.6,
            "height": 0.06,
        },
    )
    plotter.add_mesh(
        pv.Arrow(start=(0, 0, 0), direction=(0, 0, 1), scale=1.25, tip_radius=0.04, shaft_radius=0.01), color="grey"
    )
    plotter.add_mesh(pv.Line((-1.15, 0, 0), (1.15, 0, 0)), color="grey", line_width=1)
    plotter.add_mesh(pv.Line((0, -1.15, 0), (0, 1.15, 0)), color="grey", line_width=1)
    head, tail = WI_ARROW
    plotter.add_mesh(
        pv.Arrow(start=tail * wi, direction=-wi, scale=tail - head, tip_radius=0.06, shaft_radius=0.02),
        color="darkorange",
    )
    labels = label_anchors(wi)
    if "mirror" in labels:
        plotter.add_mesh(pv.Line((0, 0, 0), 1.2 / 1.25 * labels["mirror"]), color="darkorange", line_width=1)
    plotter.add_point_labels(
        np.array(list(labels.values()), dtype=np.float64),
        list(labels),
        show_points=False,
        shape=None,
        font_size=12,
        text_color="black",
        always_visible=True,
    )
    plotter.add_text(panel["title"], position="upper_edge", font_size=7, color="black")
    plotter.add_text(meta["legend"], position="lower_left", font_size=6, color="dimgrey")
    plotter.camera_position = CAMERA


def render(scene_path: str, out_path: str) -> None:
    import pyvista as pv

    pv.OFF_SCREEN = True
    scene = np.load(scene_path)
    meta = json.loads(str(scene["meta"]))
    rows, cols = meta["shape"]
    width, height = meta["size"]
    plotter = pv.Plotter(off_screen=True, shape=(rows, cols), window_size=(width * cols, height * rows), border=False)
    plotter.set_background("white")
    try:
        for k, panel in enumerate(meta["panels"]):
            plotter.subplot(panel["row"], panel["col"])
            _panel(pv, plotter, scene, meta, panel, k)
        image = plotter.screenshot(out_path, return_img=True)
    finally:
        plotter.close()
    if image is None or np.ptp(image) == 0:
        raise RuntimeError("the rendered image is blank")


def _one_line(e: Exception) -> str:
    return f"{type(e).__name__}: {' '.join(str(e).split())}"


def main(argv: list[str]) -> int:
    if len(argv) != 2:
        print("lobe3d: usage: lobes_render.py SCENE.npz OUT.png", file=sys.stderr)
        return 3
    try:
        import pyvista  # noqa: F401
    except Exception as e:  # a broken install can raise more than ImportError
        print(f"lobe3d: pyvista cannot be imported ({_one_line(e)})", file=sys.stderr)
        return 3
    try:
        render(argv[0], argv[1])
    except Exception as e:
        print(f"lobe3d: rendering failed ({_one_line(e)})", file=sys.stderr)
        return 3
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
