"""`patina plot`: figures and an index.html for a table, its validation and an optional fit.

In-plane slices (measured against fitted, log scale, per channel) and polar plots of the
incidence plane for several incidence angles, made with matplotlib, and a 3-D lobe view
(lobe3d.py, pyvista off-screen) that is skipped, with the reason on the page, where it
cannot be rendered; every file is written to a temporary name and renamed into place.
"""

from __future__ import annotations

import html
import json
import os
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from patina.atomic import write_text
from patina.fitting import FittedModel
from patina.plot.figures import save_figure
from patina.plot.lobes import LobeOptions, render_lobes
from patina.table.brdf import Brdf, angles_to_directions
from patina.table.validation import Report, validate

COLOURS = ("tab:red", "tab:green", "tab:blue")
DEFAULT_LOBES = LobeOptions()


def _incidence_plane(theta_i_deg: float, n: int = 361) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Directions in the plane of incidence: signed theta_o in degrees (+ = forward), wi, wo."""
    signed = np.linspace(-89.5, 89.5, n)
    wo = angles_to_directions(np.radians(np.abs(signed)), np.where(signed >= 0, np.pi, 0.0))
    wi = np.broadcast_to(angles_to_directions(np.radians(theta_i_deg), 0.0), wo.shape)
    return signed, np.ascontiguousarray(wi, np.float32), np.ascontiguousarray(wo, np.float32)


def plot_slices(brdf: Brdf, fitted: FittedModel | None, path: str, incidence: Sequence[float]) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(incidence), figsize=(3.3 * len(incidence), 3.3), sharey=True, squeeze=False)
    for ax, ti in zip(axes[0], incidence):
        signed, wi, wo = _incidence_plane(ti)
        measured = brdf.eval(wi, wo)
        for c in range(min(3, brdf.channels)):
            ax.semilogy(signed, np.maximum(measured[:, c], 1e-6), color=COLOURS[c], lw=1.3)
        if fitted is not None:
            model = fitted.eval(wi, wo)
            for c in range(3):
                ax.semilogy(signed, np.maximum(model[:, c], 1e-6), color=COLOURS[c], lw=1.0, ls="--")
        ax.set_title(f"theta_i = {ti:g} deg", fontsize=9)
        ax.set_xlabel("theta_o (deg, + = forward)", fontsize=8)
        ax.grid(alpha=0.3)
    axes[0][0].set_ylabel("BRDF (1/sr); dashed: fit" if fitted else "BRDF (1/sr)")
    fig.suptitle(f"In-plane slices: {os.path.basename(brdf.source)}", fontsize=10)
    fig.tight_layout()
    save_figure(fig, path)


def plot_polar(brdf: Brdf, fitted: FittedModel | None, path: str, incidence: Sequence[float]) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(
        1, len(incidence), figsize=(3.3 * len(incidence), 3.0), subplot_kw={"projection": "polar"}, squeeze=False
    )
    for ax, ti in zip(axes[0], incidence):
        signed, wi, wo = _incidence_plane(ti)
        lum = brdf.eval(wi, wo)[:, : min(3, brdf.channels)].mean(axis=1) * wo[:, 2]  # reflected, cosine-weighted
        ax.plot(np.radians(signed), lum, color="black", lw=1.2)
        if fitted is not None:
            ax.plot(np.radians(signed), fitted.eval(wi, wo).mean(axis=1) * wo[:, 2], color="tab:orange", ls="--")
        ax.set_thetamin(-90)
        ax.set_thetamax(90)
        ax.set_theta_zero_location("N")
        ax.set_theta_direction(-1)  # forward (specular) side to the right
        ax.set_yticklabels([])
        ax.set_title(f"theta_i = {ti:g} deg", fontsize=9)
    fig.suptitle("f cos(theta_o) in the plane of incidence (mean of channels)", fontsize=10)
    fig.tight_layout()
    save_figure(fig, path)


def _html_table(rows: list[tuple[str, str]]) -> str:
    cells = "".join(f"<tr><th>{html.escape(k)}</th><td>{html.escape(v)}</td></tr>" for k, v in rows)
    return f"<table>{cells}</table>"


def _lobe_view(
    brdf: Brdf,
    fitted: FittedModel | None,
    out_dir: str,
    lobes: LobeOptions | None,
    on_skip: Callable[[str], None] | None,
) -> str:
    """lobe3d.png and its section of index.html; a stale PNG from an earlier run is removed when none is made."""
    path = os.path.join(out_dir, "lobe3d.png")
    if lobes is None:
        why = "not requested (--no-3d)"
    else:
        view = render_lobes(brdf, fitted, path, options=lobes)
        if view.skipped is None:
            return f'<h2>3-D lobes</h2><img src="lobe3d.png"><p>{html.escape(view.caption)}</p>'
        why = view.skipped
        if on_skip is not None:
            on_skip(why)
    if os.path.exists(path):
        os.remove(path)
    return f"<h2>3-D lobes</h2><p>The 3-D lobe view was skipped: {html.escape(why)}.</p>"


def write_report(
    brdf: Brdf,
    out_dir: str,
    fitted: FittedModel | None = None,
    fit_doc: dict[str, Any] | None = None,
    incidence: Sequence[float] = (0, 30, 60, 75),
    lobes: LobeOptions | None = DEFAULT_LOBES,
    on_skip: Callable[[str], None] | None = None,
) -> Report:
    """Writes the report into out_dir. lobes=None leaves out the 3-D view; on_skip hears why it could not be made."""
    os.makedirs(out_dir, exist_ok=True)
    plot_slices(brdf, fitted, os.path.join(out_dir, "slices.png"), incidence)
    plot_polar(brdf, fitted, os.path.join(out_dir, "polar.png"), incidence)
    lobe_html = _lobe_view(brdf, fitted, out_dir, lobes, on_skip)
    report = validate(brdf)
    write_text(os.path.join(out_dir, "validate.json"), json.dumps(report.as_json(), indent=2))
    info = brdf.info()
    parts = [
        f"<h1>{html.escape(os.path.basename(brdf.source) or 'table')}</h1>",
        _html_table(
            [
                ("parametrization", info["parametrization"]),
                ("grid", " x ".join(str(a["knots"]) for a in info["axes"])),
                ("channels", f"{info['channels']} {info['channel_kind']}"),
                ("provenance", info["provenance"]),
            ]
        ),
        "<h2>Validation</h2>",
        f"<p>{'clean' if report.ok else 'problems found:'}</p>",
        "<ul>" + "".join(f"<li>{html.escape(p)}</li>" for p in report.problems) + "</ul>",
        '<p><a href="validate.json">validate.json</a></p>',
    ]
    if fit_doc is not None:
        params = [(k, f"{v:.6g}") for k, v in fit_doc.get("parameters", {}).items()]
        metrics = [(k, f"{v:.4g}") for k, v in fit_doc.get("metrics", {}).items() if isinstance(v, (int, float))]
        parts += [f"<h2>Fit: {html.escape(str(fit_doc.get('model')))}</h2>", _html_table(params + metrics)]
    parts += ['<h2>Slices</h2><img src="slices.png">', '<h2>Polar</h2><img src="polar.png">', lobe_html]
    page = "<!doctype html><meta charset=utf-8><title>Patina report</title>" + "\n".join(parts)
    write_text(os.path.join(out_dir, "index.html"), page)
    return report
