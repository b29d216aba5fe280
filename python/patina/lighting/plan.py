"""The plan a lighting engineer hands over: false colour of the grid with each cell centred
on its sensor, iso-lux contour lines with their values, the luminaires' positions and aiming
projected on the plan (x right, z up the page: the scenes' ground plane, docs/scene.md), and
a colour bar as tall as the plot."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from patina.plot.figures import save_figure

ISO_LEVELS = 7  # contour lines drawn at most (matplotlib picks round values)
LUMINAIRE_REACH = 5.0  # m beyond the grid within which luminaires are drawn (a road's row goes on)


@dataclass(frozen=True)
class PlanLuminaire:
    """A luminaire's foot on the plan (x, z), its mounting height and where its axis points."""

    x: float
    z: float
    height: float
    aim: tuple[float, float, float]


def cell_edges(centres: np.ndarray) -> np.ndarray:
    """Edges of cells centred on sorted sensor coordinates: half way between neighbours,
    half a spacing beyond the ends (a lone sensor gets a 1 m cell)."""
    c = np.asarray(centres, np.float64)
    if len(c) == 1:
        return np.array([c[0] - 0.5, c[0] + 0.5])
    mid = (c[1:] + c[:-1]) / 2
    return np.concatenate([[c[0] - (mid[0] - c[0])], mid, [c[-1] + (c[-1] - mid[-1])]])


def plan_figure(
    lux: np.ndarray,
    x: np.ndarray,
    z: np.ndarray,
    title: str = "",
    luminaires: list[PlanLuminaire] | None = None,
    label: str = "illuminance (lx)",
):
    """A matplotlib figure of lux (nz, nx) over sensor coordinates x (nx,), z (nz,)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from mpl_toolkits.axes_grid1 import make_axes_locatable

    xe, ze = cell_edges(x), cell_edges(z)
    near = LUMINAIRE_REACH
    luminaires = [
        lum
        for lum in luminaires or []
        if xe[0] - near <= lum.x <= xe[-1] + near and ze[0] - near <= lum.z <= ze[-1] + near
    ]
    horizontal, vertical = ("x", "z")
    if ze[-1] - ze[0] > 2 * (xe[-1] - xe[0]):
        # a long grid (a road's field) drawn lying down, z across the page: readable at page width
        lux, x, z, xe, ze = lux.T, z, x, ze, xe
        luminaires = [
            PlanLuminaire(lum.z, lum.x, lum.height, (lum.aim[2], lum.aim[1], lum.aim[0])) for lum in luminaires
        ]
        horizontal, vertical = vertical, horizontal
    span_x, span_z = xe[-1] - xe[0], ze[-1] - ze[0]
    aspect = span_z / span_x if span_x > 0 else 1.0
    fig, ax = plt.subplots(figsize=(7.0, float(np.clip(5.4 * aspect + 1.5, 3.0, 9.5))))
    mesh = ax.pcolormesh(xe, ze, lux, cmap="inferno", shading="flat")
    if lux.shape[0] > 1 and lux.shape[1] > 1 and np.ptp(lux) > 0:
        lines = ax.contour(x, z, lux, levels=ISO_LEVELS, colors="white", linewidths=0.8)
        # the values alone, their unit the colour bar's: with it on every label they crowded
        # round the luminaires of a road plan
        ax.clabel(lines, fmt="%g", fontsize=7, inline=True, inline_spacing=2)
    gx, gz = np.meshgrid(x, z)
    ax.plot(gx.ravel(), gz.ravel(), ".", color="0.75", markersize=1.5, label="sensors")
    for i, lum in enumerate(luminaires):
        ax.plot(lum.x, lum.z, "o", mfc="cyan", mec="black", ms=7, label="luminaires" if i == 0 else None)
        right_half = lum.x > 0.5 * (xe[0] + xe[-1])  # its height label inwards, never past the plot's edge
        ax.annotate(
            f"{lum.height:g} m", (lum.x, lum.z), xytext=(-4 if right_half else 4, 4), textcoords="offset points",
            fontsize=7, color="cyan", ha="right" if right_half else "left",
        )  # fmt: skip
        dx, dz = lum.aim[0], lum.aim[2]
        if abs(dx) + abs(dz) > 1e-6:  # aimed off the vertical: the axis' horizontal direction
            ax.annotate("", (lum.x + dx, lum.z + dz), (lum.x, lum.z), arrowprops={"arrowstyle": "->", "color": "cyan"})
    # the grid and every luminaire in view
    xs = [xe[0], xe[-1], *(lum.x for lum in luminaires)]
    zs = [ze[0], ze[-1], *(lum.z for lum in luminaires)]
    ax.set_xlim(min(xs) - 0.2, max(xs) + 0.2)
    ax.set_ylim(min(zs) - 0.2, max(zs) + 0.2)
    ax.set_aspect("equal")
    ax.set_xlabel(f"{horizontal} (m)", labelpad=1)
    ax.set_ylabel(f"{vertical} (m)")
    ax.set_title(title, fontsize=9)
    # below the plot, where it hides nothing
    handles, names = ax.get_legend_handles_labels()
    fig.legend(handles, names, loc="lower center", ncol=2, fontsize=7, frameon=False)
    # the bar in an axis cut from the plot's own: never taller than the plot
    bar_ax = make_axes_locatable(ax).append_axes("right", size="4%", pad=0.1)
    fig.colorbar(mesh, cax=bar_ax, label=label)
    fig.tight_layout(rect=(0, 0.05, 1, 1))
    return fig


def write_plan(path: str, *args, **kwargs) -> None:
    save_figure(plan_figure(*args, **kwargs), path)
