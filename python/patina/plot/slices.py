"""Static plots of tables (matplotlib, no display needed)."""

from __future__ import annotations

import os
from collections.abc import Sequence

import numpy as np

from patina.plot.figures import save_figure
from patina.table.brdf import Brdf

CHANNEL_COLOURS = {"rgb": ("tab:red", "tab:green", "tab:blue"), "xyz": ("tab:purple", "tab:olive", "tab:cyan")}


def plot_inplane_slices(brdf: Brdf, out_path: str, incidence_deg: Sequence[float] = (0, 20, 40, 60, 75)) -> None:
    """In-plane slices: f(theta_i, 0; theta_o, 0 or 180 deg) against signed theta_o, one panel per incidence.

    Negative theta_o is the backward half of the plane (phi_o = 180 deg), positive the forward
    (specular) half. Written to a temporary file, then renamed into place.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    signed = np.linspace(-89.5, 89.5, 359)
    theta_o = np.radians(np.abs(signed))
    phi_o = np.where(signed >= 0, np.pi, 0.0)  # forward scattering lies opposite the incidence azimuth
    n = len(incidence_deg)
    fig, axes = plt.subplots(1, n, figsize=(3.2 * n, 3.2), sharey=True, squeeze=False)
    colours = CHANNEL_COLOURS.get(brdf.channel_kind)
    for ax, ti in zip(axes[0], incidence_deg):
        values = brdf.eval_angles(np.radians(ti), 0.0, theta_o, phi_o)
        if brdf.channel_kind == "spectral":
            picks = np.linspace(0, brdf.channels - 1, min(brdf.channels, 5)).astype(int)
            labels = [f"{brdf.wavelengths[i]:g} nm" for i in picks]
            cols = [None] * len(picks)
        else:
            picks = range(brdf.channels)
            labels = (
                ["R", "G", "B"]
                if brdf.channel_kind == "rgb"
                else (["X", "Y", "Z"] if brdf.channel_kind == "xyz" else ["f"])
            )
            cols = colours or [None] * brdf.channels
        for i, label, col in zip(picks, labels, cols):
            ax.semilogy(signed, np.maximum(values[:, i], 1e-6), color=col, label=label, lw=1.2)
        ax.axvline(ti, color="0.6", lw=0.6, ls=":")
        ax.set_title(f"theta_i = {ti:g} deg", fontsize=9)
        ax.set_xlabel("theta_o (deg, + = forward)", fontsize=8)
        ax.set_xlim(-90, 90)
        ax.grid(alpha=0.3)
    axes[0][0].set_ylabel(f"BRDF ({brdf.info()['units']})")
    axes[0][0].legend(fontsize=7)
    fig.suptitle(f"In-plane slices: {os.path.basename(brdf.source)}", fontsize=10)
    fig.tight_layout()
    save_figure(fig, out_path)
