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
# Where the axis labels may go, in order of preference: the first place clear of the wi arrow and
# of the labels placed before is taken (at theta_i = 0 the wi arrow covers the normal and its label).
LABEL_PLACES = {
    "n (z)": [(0.0, 0.0, 1.3), (-0.3, 0.0, 1.15), (0.3, 0.0, 1.15), (-0.35, 0.0, 0.75), (0.35, 0.0, 0.75)],
    "x": [(1.2, 0.0, 0.0), (1.25, 0.0, -0.2), (0.95, 0.0, -0.2)],
    "y": [(0.0, 1.2, 0.0), (0.15, 1.2, -0.15)],
}
LABEL_CLEARANCE = 0.05  # on the screen (see screen_position): about a 12-point label's size at the panel's


def screen_position(points: np.ndarray) -> np.ndarray:
    """(n, 3) scene points -> (n, 2) positions on the panels' camera's screen (perspective:
    offsets from the view axis divided by depth)."""
    eye, focus, up = (np.asarray(v, np.float64) for v in CAMERA)
    forward = (focus - eye) / np.linalg.norm(focus - eye)
    right = np.cross(forward, up)
    right /= np.linalg.norm(right)
    rel = np.atleast_2d(np.asarray(points, np.float64)) - eye
    return np.stack([rel @ right, rel @ np.cross(right, forward)], axis=-1) / (rel @ forward)[:, None]


def distance_to_segment(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> float:
    t = np.clip(np.dot(p - a, b - a) / max(float(np.dot(b - a, b - a)), 1e-12), 0.0, 1.0)
    return float(np.linalg.norm(p - (a + t * (b - a))))


def label_anchors(wi: np.ndarray) -> dict[str, np.ndarray]:
    """Where each label of a panel is drawn: "wi" beyond the arrow's tail, "mirror" beyond the
    mirror direction's line, the axes' labels each at its first place clear of those, of each
    other and of the wi arrow on the screen."""
    labels = {"wi": 1.7 * wi}
    if wi[0] > 1e-6:
        labels["mirror"] = 1.25 * np.array([-wi[0], -wi[1], wi[2]])
    head, tail = screen_position(np.array([WI_ARROW[0] * wi, WI_ARROW[1] * wi]))

    def clear(place: np.ndarray) -> bool:
        at = screen_position(place)[0]
        others = screen_position(np.array(list(labels.values())))
        return bool(
            np.linalg.norm(others - at, axis=1).min() > LABEL_CLEARANCE
            and distance_to_segment(at, head, tail) > LABEL_CLEARANCE / 2
        )

    for name, places in LABEL_PLACES.items():
        candidates = [np.array(p) for p in places]
        labels[name] = next((p for p in candidates if clear(p)), candidates[0])
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
