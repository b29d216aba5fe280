"""The 3-D lobe view: its geometry, a real off-screen render, and `patina plot` when it cannot render."""

from __future__ import annotations

import os

import numpy as np
import pytest

from patina.cli import main
from patina.plot.lobes import (
    LobeOptions,
    build_scene,
    hemisphere,
    incidence_direction,
    luminance_of,
    radius,
    render_scene,
)

SMALL = LobeOptions(cosine=False, n_theta=30, n_phi=61)


def phong(wi: np.ndarray, wo: np.ndarray) -> np.ndarray:
    """A specular lobe around the mirror direction over a small constant floor."""
    mirror = wi * np.array([-1, -1, 1], np.float32)
    c = np.clip((wo * mirror).sum(axis=1), 0, 1).astype(np.float64)
    return 0.05 + 20.0 * c**30


class Grey:
    """Table-like: the same value in every channel, so its luminance is that value whatever the channels mean."""

    def __init__(self, kind: str, channels: int) -> None:
        self.channel_kind, self.channels = kind, channels
        self.wavelengths = np.linspace(380.0, 780.0, channels) if kind == "spectral" else None

    def eval(self, wi: np.ndarray, wo: np.ndarray) -> np.ndarray:
        return np.repeat(wo[:, 2:3] * 0.5, self.channels, axis=1)


@pytest.mark.parametrize("kind, channels", [("rgb", 3), ("xyz", 3), ("spectral", 16), ("mono", 1)])
def test_luminance_of_a_grey_value_is_the_value(kind, channels):
    wo = hemisphere(5, 7).reshape(-1, 3).astype(np.float32)
    lum = luminance_of(Grey(kind, channels))(wo, wo)  # type: ignore[arg-type]
    np.testing.assert_allclose(lum, 0.5 * wo[:, 2], rtol=1e-6, atol=1e-9)


def test_radius_is_one_at_the_peak_linear_and_log():
    v = np.array([0.0, 1e-4, 1e-3, 0.1, 1.0])
    np.testing.assert_allclose(radius(v, 1.0, LobeOptions()), v)
    np.testing.assert_allclose(radius(v, 1.0, LobeOptions(log=True, decades=3)), [0, 0, 0, 2 / 3, 1], atol=1e-12)
    assert not radius(v, 0.0, LobeOptions()).any()


@pytest.mark.parametrize("theta_i", [0.0, 30.0, 60.0])
def test_the_lobe_reaches_furthest_along_the_mirror_direction(theta_i):
    arrays, meta = build_scene(phong, None, (theta_i,), SMALL)
    points = arrays["points0_0"].reshape(-1, 3)
    r = np.linalg.norm(points, axis=1)
    assert r.max() == pytest.approx(1.0, abs=1e-6)  # normalised to the measured peak
    tip = points[np.argmax(r)] / r.max()
    mirror = incidence_direction(theta_i) * [-1, -1, 1]
    assert np.degrees(np.arccos(min(1.0, float(tip @ mirror)))) < 90.0 / (SMALL.n_theta - 1) + 1e-3
    assert meta["shape"] == [1, 1]


def test_a_fit_is_a_second_row_on_the_measured_scale():
    arrays, meta = build_scene(phong, lambda wi, wo: 2 * phong(wi, wo), (0, 45), SMALL)
    assert meta["shape"] == [2, 2]
    for col in range(2):
        fit_r = np.linalg.norm(arrays[f"points1_{col}"], axis=-1)
        assert fit_r.max() == pytest.approx(2.0, rel=1e-5)
        np.testing.assert_allclose(arrays[f"values1_{col}"], 2 * arrays[f"values0_{col}"], rtol=1e-6)
    assert arrays["points0_0"].shape == (*hemisphere(SMALL.n_theta, SMALL.n_phi).shape[:2], 3)


def _yellow_centroid(panel: np.ndarray) -> tuple[float, float]:
    """Where the top of the viridis colour map (the lobe's peak) lies, as fractions of width and height."""
    r, g, b = panel[..., 0], panel[..., 1], panel[..., 2]
    yellow = (r > 0.75) & (g > 0.75) & (b < 0.4)
    yellow[int(0.75 * panel.shape[0]) :] = False  # the colour bar
    ys, xs = np.nonzero(yellow)
    assert xs.size > 10, "no peak-coloured pixels"
    return xs.mean() / panel.shape[1], ys.mean() / panel.shape[0]


def test_renders_a_lobe_png_with_the_peak_where_the_mirror_direction_is(tmp_path):
    import matplotlib.pyplot as plt

    arrays, meta = build_scene(phong, None, (0, 60), SMALL)
    path = str(tmp_path / "lobe3d.png")
    skipped = render_scene(arrays, meta, path, size=(260, 260))
    assert skipped is None, skipped
    assert open(path, "rb").read(8) == b"\x89PNG\r\n\x1a\n"
    image = plt.imread(path)[..., :3]
    assert image.shape == (260, 520, 3)
    assert (image.min(axis=-1) < 0.9).mean() > 0.05  # not a blank page
    assert len(np.unique((image * 255).astype(np.uint8).reshape(-1, 3), axis=0)) > 50
    x0, y0 = _yellow_centroid(image[:, :260])
    x60, y60 = _yellow_centroid(image[:, 260:])
    assert 0.35 < x0 < 0.6 and y0 < 0.5  # normal incidence: the peak straight up
    assert x60 < 0.35 and x60 < x0 - 0.12 and y60 > y0  # the camera looks along +y: the mirror side is left
    assert not [f for f in os.listdir(tmp_path) if "tmp" in f]


def _fake_pyvista(tmp_path, monkeypatch, body: str) -> None:
    """The renderer's child process imports this instead of pyvista."""
    package = tmp_path / "fake" / "pyvista"
    package.mkdir(parents=True)
    (package / "__init__.py").write_text(body)
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join([str(package.parent), os.environ.get("PYTHONPATH", "")]))


def test_plot_says_in_one_line_why_the_view_was_skipped(tmp_path, monkeypatch, capsys, bundled_ptab):
    _fake_pyvista(tmp_path, monkeypatch, 'raise ImportError("simulated: no pyvista here")')
    out = tmp_path / "report"
    out.mkdir()
    (out / "lobe3d.png").write_bytes(b"stale")
    assert main(["plot", bundled_ptab, "--out", str(out)]) == 0
    captured = capsys.readouterr()
    messages = [line for line in captured.err.strip().splitlines() if not line.startswith("report:")]  # progress
    assert messages == [
        "patina plot: 3-D lobe view skipped: pyvista cannot be imported (ImportError: simulated: no pyvista here)"
    ]
    assert "Traceback" not in captured.out + captured.err
    page = (out / "index.html").read_text()
    assert "3-D lobe view was skipped: pyvista cannot be imported" in page
    assert not (out / "lobe3d.png").exists()
    assert (out / "slices.png").exists() and (out / "polar.png").exists()


def test_a_crashing_or_hanging_renderer_is_a_reason_not_a_crash(tmp_path, monkeypatch):
    arrays, meta = build_scene(phong, None, (30,), SMALL)
    path = tmp_path / "lobe3d.png"
    _fake_pyvista(tmp_path, monkeypatch, "import os, signal\nos.kill(os.getpid(), signal.SIGSEGV)\n")
    why = render_scene(arrays, meta, str(path))
    assert why is not None and "died (signal 11)" in why and "libegl1" in why
    (tmp_path / "fake" / "pyvista" / "__init__.py").write_text("import time\ntime.sleep(60)\n")
    assert render_scene(arrays, meta, str(path), timeout=1.0) == "rendering took longer than 1 s"
    assert os.listdir(tmp_path) == ["fake"]


def test_no_3d_leaves_the_view_out(tmp_path, capsys, bundled_ptab):
    out = tmp_path / "report"
    assert main(["plot", bundled_ptab, "--out", str(out), "--no-3d"]) == 0
    assert "lobe3d.png" not in capsys.readouterr().out
    assert "skipped: not requested (--no-3d)" in (out / "index.html").read_text()
    assert not (out / "lobe3d.png").exists()
