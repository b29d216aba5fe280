"""The in-plane slice plot (matplotlib, no display needed): the one slice plotter, used by
`patina slices` and by the report of `patina plot`, with fitted models overlaid."""

from __future__ import annotations

import os
from collections.abc import Sequence

import numpy as np

from patina.fitting import FittedModel
from patina.plot.figures import save_figure
from patina.table.brdf import Brdf, angles_to_directions

CHANNEL_COLOURS = {"rgb": ("tab:red", "tab:green", "tab:blue"), "xyz": ("tab:purple", "tab:olive", "tab:cyan")}
CHANNEL_NAMES = {"rgb": ("R", "G", "B"), "xyz": ("X", "Y", "Z")}
# The measurement is drawn solid; each fit gets its own line style (the colour stays the channel's),
# so that measured and fitted curves of one channel are compared by eye without a colour key per fit.
FIT_STYLES = ("--", ":", "-.", (0, (5, 1, 1, 1, 1, 1)), (0, (1, 3)), (0, (8, 2)))
FLOOR = 1e-6  # log axes cannot show zero; values below are drawn at the floor


def fit_channels(brdf: Brdf) -> list[int] | None:
    """Which of a fit's (r, g, b) outputs go with the table's plotted channels, or None where they do not
    correspond (a spectral table: a fit is made on its colour, not on single wavelengths)."""
    if brdf.channel_kind in CHANNEL_COLOURS and brdf.channels == 3:
        return [0, 1, 2]
    if brdf.channels == 1:
        return [1]  # a one-channel table is fitted as grey: its three outputs agree
    return None


def plot_inplane_slices(
    brdf: Brdf,
    out_path: str,
    incidence_deg: Sequence[float] = (0, 20, 40, 60, 75),
    fits: Sequence[tuple[str, FittedModel]] = (),
) -> str:
    """In-plane slices: f(theta_i, 0; theta_o, 0 or 180 deg) against signed theta_o, one panel per incidence,
    with each (name, model) of `fits` overlaid in its own line style; the mirror direction is marked.

    Negative theta_o is the backward half of the plane (phi_o = 0), positive the forward (specular) half.
    Written to a temporary file, then renamed into place. Returns a caption describing the figure.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D

    signed = np.linspace(-89.5, 89.5, 359)
    theta_o = np.radians(np.abs(signed))
    phi_o = np.where(signed >= 0, np.pi, 0.0)  # forward scattering lies opposite the incidence azimuth
    wo = np.ascontiguousarray(angles_to_directions(theta_o, phi_o), np.float32)
    n = len(incidence_deg)
    fig, axes = plt.subplots(1, n, figsize=(3.2 * n, 3.5), sharey=True, squeeze=False)
    colours = CHANNEL_COLOURS.get(brdf.channel_kind)
    if brdf.channel_kind == "spectral":
        picks = list(np.linspace(0, brdf.channels - 1, min(brdf.channels, 5)).astype(int))
        labels = [f"{brdf.wavelengths[i]:g} nm" for i in picks]
        cols: Sequence[str | None] = [f"C{k}" for k in range(len(picks))]
    else:
        picks = list(range(brdf.channels))
        labels = list(CHANNEL_NAMES.get(brdf.channel_kind, ("f",) * brdf.channels))[: brdf.channels]
        cols = colours or ["0.2"] * brdf.channels
    fitted = fit_channels(brdf)
    shown_fits = list(fits) if fitted is not None else []
    for ax, ti in zip(axes[0], incidence_deg):
        values = brdf.eval_angles(np.radians(ti), 0.0, theta_o, phi_o)
        for i, col in zip(picks, cols):
            ax.semilogy(signed, np.maximum(values[:, i], FLOOR), color=col, lw=1.3)
        if shown_fits:
            wi = np.ascontiguousarray(np.broadcast_to(angles_to_directions(np.radians(ti), 0.0), wo.shape), np.float32)
            for k, (_, model) in enumerate(shown_fits):
                predicted = model.eval(wi, wo)
                for c, col in zip(fitted or [], cols):
                    ax.semilogy(
                        signed,
                        np.maximum(predicted[:, c], FLOOR),
                        color=col,
                        lw=1.1,
                        ls=FIT_STYLES[k % len(FIT_STYLES)],
                    )
        ax.axvline(ti, color="0.35", lw=0.8, ls=(0, (2, 2)))
        # Labelled at the foot of the line, where the curves (at their peak near the mirror) leave room, and
        # to the left of a line near the right-hand edge.
        right = ti < 60
        ax.annotate(
            "mirror",
            (ti, 0.0),
            xycoords=("data", "axes fraction"),
            xytext=(3 if right else -3, 4),
            textcoords="offset points",
            ha="left" if right else "right",
            fontsize=7,
            color="0.35",
        )
        ax.set_title(f"θi = {ti:g}°", fontsize=9)
        ax.set_xlabel("θo (°): - back, + forward", fontsize=8)
        ax.set_xlim(-90, 90)
        ax.set_xticks([-90, -60, -30, 0, 30, 60, 90])
        ax.tick_params(labelsize=7)
        ax.grid(alpha=0.3)
    axes[0][0].set_ylabel(f"BRDF f ({brdf.info()['units']}, log scale)", fontsize=8)
    # One legend for the figure, below the panels, so that it covers no curve: the channel colours, then
    # what each line style is (measured, each fit by name), then the mirror-direction marker.
    handles = [Line2D([], [], color=col, lw=2) for col in cols]
    names = list(labels)
    handles.append(Line2D([], [], color="0.1", lw=1.3))
    names.append("measured")
    for k, (name, _) in enumerate(shown_fits):
        handles.append(Line2D([], [], color="0.1", lw=1.1, ls=FIT_STYLES[k % len(FIT_STYLES)]))
        names.append(f"fit: {name}")
    handles.append(Line2D([], [], color="0.35", lw=0.8, ls=(0, (2, 2))))
    names.append("mirror direction (θo = θi)")
    rows = 1 if len(names) <= 8 else 2
    fig.legend(handles, names, loc="lower center", ncols=-(-len(names) // rows), fontsize=7, frameon=False)
    fig.suptitle(f"In-plane slices: {os.path.basename(brdf.source)}", fontsize=10)
    fig.tight_layout(rect=(0, 0.07 * rows + 0.02, 1, 1))
    save_figure(fig, out_path)
    caption = (
        f"BRDF of {os.path.basename(brdf.source)} in the plane of incidence, one panel per incidence angle θi, "
        "against the signed outgoing angle θo (negative: back towards the light, positive: forward, "
        "where the mirror direction θo = θi is marked). Log scale; colour is the channel; "
        "the measurement is solid"
    )
    if shown_fits:
        caption += ", each fit has its own line style (legend)"
    elif fits:
        caption += "; the fits are not overlaid because a spectral table's channels are single wavelengths"
    return caption + "."
