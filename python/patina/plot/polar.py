"""Polar plots of the plane of incidence (matplotlib): reflected f cos(theta_o), measured and
fitted, on a labelled log radius, for the report of `patina plot`."""

from __future__ import annotations

import math
import os
from collections.abc import Sequence

import numpy as np

from patina.fitting import FittedModel
from patina.plot.figures import save_figure
from patina.plot.slices import FIT_STYLES, fit_channels
from patina.table.brdf import Brdf, angles_to_directions

DECADES = 3  # the radius spans this many decades below the largest value drawn
FIT_COLOURS = ("tab:orange", "tab:blue", "tab:green", "tab:purple", "tab:brown", "tab:pink")


def _incidence_plane(theta_i_deg: float, n: int = 361) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Directions in the plane of incidence: signed theta_o in degrees (+ = forward), wi, wo."""
    signed = np.linspace(-89.5, 89.5, n)
    wo = angles_to_directions(np.radians(np.abs(signed)), np.where(signed >= 0, np.pi, 0.0))
    wi = np.broadcast_to(angles_to_directions(np.radians(theta_i_deg), 0.0), wo.shape)
    return signed, np.ascontiguousarray(wi, np.float32), np.ascontiguousarray(wo, np.float32)


def plot_incidence_polar(
    brdf: Brdf, path: str, incidence: Sequence[float], fits: Sequence[tuple[str, FittedModel]] = ()
) -> str:
    """One polar panel per incidence angle; returns the figure's caption.

    The radius is log10 of f cos(theta_o) (mean of the colour channels), shifted so that the centre is
    DECADES below the figure's peak: a linear radius shows a glossy peak and leaves the diffuse part
    a dot at the centre. The rings are labelled in 1/sr."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D

    # The colour channels' mean; a spectral table's mean over its wavelengths, with no fit beside it (a fit
    # is made on the table's colour, whose mean is not the spectrum's).
    channels = brdf.channels if brdf.channel_kind == "spectral" else min(3, brdf.channels)
    dropped = bool(fits) and fit_channels(brdf) is None
    if dropped:
        fits = ()
    curves = []
    for ti in incidence:
        signed, wi, wo = _incidence_plane(ti)
        measured = brdf.eval(wi, wo)[:, :channels].mean(axis=1) * wo[:, 2]
        fitted = [model.eval(wi, wo).mean(axis=1) * wo[:, 2] for _, model in fits]
        curves.append((ti, signed, measured, fitted))
    peak = max(float(np.nanmax(np.concatenate([m, *f]))) for _, _, m, f in curves)
    # The rim a little above the peak (not at the next decade, which can leave the curves a third of the
    # radius), the centre DECADES below it; rings at the whole decades in between, labelled.
    top = math.log10(peak) + 0.1 if peak > 0 and math.isfinite(peak) else 0.0
    bottom = top - DECADES
    rings = list(range(math.ceil(bottom + 0.05), math.floor(top) + 1))

    def radius(v: np.ndarray) -> np.ndarray:
        return np.clip(np.log10(np.maximum(v, 10.0**bottom)) - bottom, 0, None)

    # Two half-discs a row: four in one row leave each a strip too small to read on a page.
    cols = min(2, len(incidence))
    rows = -(-len(incidence) // cols)
    fig, axes = plt.subplots(
        rows, cols, figsize=(4.4 * cols, 2.9 * rows + 0.5), subplot_kw={"projection": "polar"}, squeeze=False
    )
    for ax in axes.flat[len(incidence) :]:
        ax.set_visible(False)
    for ax, (ti, signed, measured, fitted) in zip(axes.flat, curves):
        theta = np.radians(signed)
        ax.plot(theta, radius(measured), color="black", lw=1.3)
        for k, values in enumerate(fitted):
            ax.plot(theta, radius(values), color=FIT_COLOURS[k % len(FIT_COLOURS)], lw=1.1, ls=FIT_STYLES[k % 6])
        ax.plot([np.radians(ti)] * 2, [0, DECADES], color="0.45", lw=0.8, ls=(0, (2, 2)))  # the mirror direction
        ax.set_thetamin(-90)
        ax.set_thetamax(90)
        ax.set_theta_zero_location("N")
        ax.set_theta_direction(-1)  # forward (specular) side to the right
        ax.set_thetagrids([-90, -60, -30, 0, 30, 60, 90], [f"{a}°" for a in (-90, -60, -30, 0, 30, 60, 90)])
        ax.set_ylim(0, DECADES)
        ax.set_yticks([r - bottom for r in rings])
        ax.set_yticklabels([f"$10^{{{r}}}$" for r in rings])
        ax.set_rlabel_position(-90)  # along the backward horizon, as a radial scale read from the centre
        ax.tick_params(axis="x", labelsize=8, pad=1)
        ax.tick_params(axis="y", labelsize=8)
        ax.set_title(f"θi = {ti:g}°", fontsize=9, pad=4)
    names = ["measured", *[f"fit: {name}" for name, _ in fits], "mirror direction"]
    handles = [Line2D([], [], color="black", lw=1.3)]
    handles += [
        Line2D([], [], color=FIT_COLOURS[k % len(FIT_COLOURS)], lw=1.1, ls=FIT_STYLES[k % 6]) for k in range(len(fits))
    ]
    handles.append(Line2D([], [], color="0.45", lw=0.8, ls=(0, (2, 2))))
    fig.legend(handles, names, loc="lower center", ncols=len(names), fontsize=7, frameon=False)
    fig.suptitle(f"f cos θo in the plane of incidence (1/sr, log radius): {os.path.basename(brdf.source)}", fontsize=10)
    fig.tight_layout(rect=(0, 0.35 / fig.get_figheight(), 1, 1))
    save_figure(fig, path)
    averaged = "wavelengths" if brdf.channel_kind == "spectral" else "colour channels"
    return (
        f"Reflected f cos θo (1/sr, mean of the {averaged}) in the plane of incidence, one panel per "
        "incidence angle θi: the angle is θo (0° the normal, positive forward), the radius is logarithmic, "
        f"{DECADES} decades from the centre ({10**bottom:.2g} 1/sr and below) to the rim ({10**top:.2g} 1/sr), "
        "rings labelled along the backward horizon; the dashed ray is the mirror direction."
        + (" The fits are not drawn: they are made on the table's colour, not on its spectrum." if dropped else "")
    )
