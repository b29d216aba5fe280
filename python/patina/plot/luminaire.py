"""Polar intensity diagram of a luminaire (matplotlib): the C0-C180 and C90-C270 planes
(type B: the horizontal and vertical planes through the beam axis), plus the C45-C225 and
C135-C315 planes for files without quadrant symmetry. Nadir (type B: the beam axis) points down."""

from __future__ import annotations

import os
from typing import Any

import numpy as np

from patina.photometry.luminaire import Luminaire
from patina.plot.figures import save_figure


def _c_plane(lum: Luminaire, c0: float, s: np.ndarray) -> np.ndarray:
    phi = np.radians(np.where(s >= 0, c0, c0 + 180.0))
    return lum.intensity(np.radians(np.abs(s)), phi)


def plot_luminaire(lum: Luminaire, out_path: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.ticker

    s = np.linspace(-180.0, 180.0, 1441)
    curves: list[tuple[str, np.ndarray, Any]] = []
    p = lum.photometry
    if lum.kind == "C":
        planes = [("C0-C180", 0.0, "tab:red"), ("C90-C270", 90.0, "tab:blue")]
        if p.symmetry not in ("rotational", "quadrant"):
            planes += [("C45-C225", 45.0, "tab:green"), ("C135-C315", 135.0, "tab:orange")]
        curves = [(name, _c_plane(lum, c0, s), colour) for name, c0, colour in planes]
    else:
        _, horizontal = lum._plane("horizontal", step_deg=0.25)
        _, vertical = lum._plane("vertical", step_deg=0.25)
        curves = [("horizontal (V = 0)", horizontal, "tab:red"), ("vertical (H = 0)", vertical, "tab:blue")]
    fig = plt.figure(figsize=(6.0, 6.4))
    ax = fig.add_subplot(projection="polar")
    ax.set_theta_zero_location("S")
    for label, values, colour in curves:
        ax.plot(np.radians(s), values, color=colour, lw=1.4, label=label)
    ax.set_thetagrids(range(0, 360, 30), [f"{abs(a if a <= 180 else a - 360)}°" for a in range(0, 360, 30)])
    # Ring values in cd, along a steep ray between the 150° and 180° spokes: clear of the angle labels, in
    # the upper half where most luminaires send little light.
    ax.set_rlabel_position(165)
    ax.yaxis.set_major_formatter(matplotlib.ticker.FuncFormatter(lambda v, _: f"{v:g} cd" if v > 0 else ""))
    ax.tick_params(axis="y", labelsize=8)
    ax.legend(loc="lower left", bbox_to_anchor=(-0.12, -0.14), fontsize=8, ncols=2)
    axis = "gamma from nadir" if lum.kind == "C" else "angle from the beam axis"
    ax.set_title(f"{os.path.basename(p.path)}: candela ({axis})", fontsize=10, pad=28)
    fig.tight_layout()
    save_figure(fig, out_path)
