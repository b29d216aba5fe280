"""`patina plot`'s 3-D lobe view: a BRDF over the outgoing hemisphere as a surface, per incidence angle.

For each incidence angle the lobe is the surface r(wo) wo, r the luminance of f(wi, wo) (times
cos theta_o by default, on a log scale on request for high-dynamic-range lobes), normalised to
the measured peak at that incidence. Measured lobes make the top row; a fit, when given, the
row below on the same scale and colours.

The geometry is computed here; the scene is drawn by a child process running lobes_render.py
(numpy and pyvista only). Where no off-screen OpenGL context can be made, VTK may kill its
process outright (a segmentation fault, not an exception), so only the child can die, and every
failure (pyvista missing, no OpenGL, a crash, a timeout) comes back as a one-line reason.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from patina.colour_constants import LUMINANCE_WEIGHTS, luminance
from patina.fitting import FittedModel
from patina.table.angles import angles_to_directions
from patina.table.brdf import Brdf
from patina.table.spectral import xyz_weights

RENDERER = os.path.join(os.path.dirname(os.path.abspath(__file__)), "lobes_render.py")
Evaluate = Callable[[np.ndarray, np.ndarray], np.ndarray]  # (wi, wo) (n, 3) -> luminance (n,)


@dataclass(frozen=True)
class LobeOptions:
    """How lobes are shaped: cosine-weighted or not, linear or log radius (`decades` below the peak)."""

    cosine: bool = True
    log: bool = False
    decades: float = 3.0
    n_theta: int = 46
    n_phi: int = 121

    @property
    def quantity(self) -> str:
        return "Y f cos(theta_o) (1/sr)" if self.cosine else "Y f (1/sr)"


def luminance_of(brdf: Brdf) -> Evaluate:
    """Luminance of the table's value: Y for XYZ and spectral (D65), Rec. 709 Y for RGB, the value if mono."""
    kind = brdf.channel_kind
    if kind == "rgb":
        weights = LUMINANCE_WEIGHTS
    elif kind == "xyz":
        weights = np.array([0.0, 1.0, 0.0])
    elif kind == "spectral":
        weights = xyz_weights(brdf.wavelengths)[1]
    else:
        weights = np.full(brdf.channels, 1.0 / brdf.channels)
    return lambda wi, wo: brdf.eval(wi, wo).astype(np.float64) @ weights


def luminance_of_fit(fitted: FittedModel) -> Evaluate:
    """Fits are of linear sRGB (see fitting.table_samples), so Rec. 709 Y."""
    return lambda wi, wo: luminance(fitted.eval(wi, wo))


def incidence_direction(theta_i_deg: float) -> np.ndarray:
    """wi in the x-z plane (phi_i = 0), so the mirror direction lies at phi_o = 180 deg (-x)."""
    return angles_to_directions(np.radians(theta_i_deg), 0.0)


def hemisphere(n_theta: int, n_phi: int) -> np.ndarray:
    """(n_theta, n_phi, 3) outgoing directions from the normal to just above the horizon; the seam is closed."""
    theta = np.radians(np.linspace(0.0, 89.5, n_theta))
    phi = np.linspace(0.0, 2.0 * np.pi, n_phi)
    t, p = np.meshgrid(theta, phi, indexing="ij")
    return angles_to_directions(t, p)


def lobe_values(evaluate: Evaluate, theta_i_deg: float, wo: np.ndarray, cosine: bool) -> np.ndarray:
    """Luminance (times cos theta_o if `cosine`) at every direction of a hemisphere grid, shape wo.shape[:-1]."""
    flat = np.ascontiguousarray(wo.reshape(-1, 3), np.float32)
    wi = np.ascontiguousarray(np.broadcast_to(incidence_direction(theta_i_deg), flat.shape), np.float32)
    v = np.asarray(evaluate(wi, flat), dtype=np.float64)
    if cosine:
        v = v * flat[:, 2]
    v = np.where(np.isfinite(v), np.maximum(v, 0.0), 0.0)
    return v.reshape(wo.shape[:-1])


def radius(values: np.ndarray, peak: float, options: LobeOptions) -> np.ndarray:
    """Radius of the lobe surface: value / peak, or on a log scale, 1 at the peak and 0 `decades` below it."""
    if peak <= 0:
        return np.zeros_like(values)
    if not options.log:
        return values / peak
    with np.errstate(divide="ignore"):
        r = np.log10(np.maximum(values, 1e-300) / peak) / options.decades + 1.0
    return np.maximum(r, 0.0)


def build_scene(
    measured: Evaluate,
    fitted: Evaluate | None,
    incidence: Sequence[float],
    options: LobeOptions,
    title: str = "",
) -> tuple[dict[str, np.ndarray], dict[str, object]]:
    """Arrays and a description for lobes_render.py: a column per incidence angle, a row for the fit.

    Arrays are named points{row}_{col} ((n_theta, n_phi, 3) surface) and values{row}_{col}
    ((n_theta, n_phi) colour); the fit's row shares the measured row's radius scale and colours.
    """
    arrays: dict[str, np.ndarray] = {}
    panels = []
    wo = hemisphere(options.n_theta, options.n_phi)
    rows = [("measured", measured)] + ([("fit", fitted)] if fitted is not None else [])
    for col, ti in enumerate(incidence):
        peak = 0.0
        for row, (name, evaluate) in enumerate(rows):
            values = lobe_values(evaluate, ti, wo, options.cosine)
            if row == 0:
                peak = float(values.max())
            arrays[f"points{row}_{col}"] = (radius(values, peak, options)[..., None] * wo).astype(np.float32)
            arrays[f"values{row}_{col}"] = values.astype(np.float32)
            panels.append(
                {
                    "row": row,
                    "col": col,
                    "title": f"{name}: theta_i {ti:g} deg, peak {values.max():.3g}/sr",
                    "wi": incidence_direction(ti).tolist(),
                    "clim": [peak * 10.0**-options.decades if options.log else 0.0, peak if peak > 0 else 1.0],
                }
            )
    scale = f"log radius, {options.decades:g} decades" if options.log else "linear radius"
    meta: dict[str, object] = {
        "shape": [len(rows), len(incidence)],
        "panels": panels,
        "quantity": options.quantity,
        "log": options.log,
        "legend": f"{scale}, 1 = measured peak",
        "caption": (
            f"{title}: luminance of the BRDF{' times cos theta_o' if options.cosine else ''} over the outgoing "
            f"hemisphere ({scale}, normalised to each incidence's measured peak)"
            + ("; bottom row: the fit, on the same scale and colours" if fitted is not None else "")
        ),
    }
    return arrays, meta


def render_scene(
    arrays: dict[str, np.ndarray],
    meta: dict[str, object],
    path: str,
    size: tuple[int, int] = (420, 440),
    timeout: float = 120.0,
) -> str | None:
    """Draws the scene to a PNG at `path` in a child process: None when written, else why it was not."""
    out_dir = os.path.dirname(os.path.abspath(path))
    with tempfile.TemporaryDirectory(prefix="patina-lobe3d-") as work:
        scene = os.path.join(work, "scene.npz")
        np.savez(scene, meta=np.array(json.dumps({**meta, "size": list(size)})), **arrays)
        tmp_png = os.path.join(out_dir, f".lobe3d.tmp{os.getpid()}.png")
        env = dict(os.environ)
        if not env.get("DISPLAY") and "VTK_DEFAULT_OPENGL_WINDOW" not in env:
            # No X server: go straight to EGL (VTK still falls back to OSMesa), sparing a failed X attempt.
            env["VTK_DEFAULT_OPENGL_WINDOW"] = "vtkEGLRenderWindow"
        try:
            done = subprocess.run(
                [sys.executable, RENDERER, scene, tmp_png],
                capture_output=True,
                text=True,
                timeout=timeout,
                env=env,
                cwd=work,  # where a core dump, should the child crash, is cleaned up with the rest
                check=False,
            )
        except subprocess.TimeoutExpired:
            _remove(tmp_png)
            return f"rendering took longer than {timeout:g} s"
        except OSError as e:
            return f"could not start the renderer: {e.strerror}"
        if done.returncode == 0 and os.path.exists(tmp_png):
            os.replace(tmp_png, path)
            return None
        _remove(tmp_png)
        return _reason(done.returncode, done.stderr)


def _reason(returncode: int, stderr: str) -> str:
    """One line on why the child failed: its own message, or the signal that killed it."""
    lines = [ln.strip() for ln in stderr.splitlines() if ln.strip()]
    mine = [ln.removeprefix("lobe3d: ") for ln in lines if ln.startswith("lobe3d: ")]
    if mine:
        return mine[-1]
    if returncode < 0:
        return (
            f"the renderer died (signal {-returncode}) opening an off-screen OpenGL context; it needs EGL "
            "(Debian: libegl1 libgl1-mesa-dri), OSMesa (libosmesa6) or an X display"
        )
    return f"the renderer failed (exit {returncode}): {lines[-1] if lines else 'no message'}"


def _remove(path: str) -> None:
    if os.path.exists(path):
        os.remove(path)


@dataclass(frozen=True)
class LobeView:
    """What render_lobes did: the PNG and its caption, or why it was skipped (then path is None)."""

    path: str | None
    caption: str
    skipped: str | None = None


def render_lobes(
    brdf: Brdf,
    fitted: FittedModel | None,
    path: str,
    incidence: Sequence[float] = (0, 30, 60),
    options: LobeOptions | None = None,
    timeout: float = 120.0,
) -> LobeView:
    """A PNG of the table's lobes (and its fit's) at `path`; never raises for want of pyvista or OpenGL."""
    options = options or LobeOptions()
    arrays, meta = build_scene(
        luminance_of(brdf),
        luminance_of_fit(fitted) if fitted is not None else None,
        incidence,
        options,
        title=os.path.basename(brdf.source),
    )
    why = render_scene(arrays, meta, path, timeout=timeout)
    return LobeView(None if why else path, str(meta["caption"]), why)
